// app/netcdf_library.hpp -- the netCDF C library, loaded with dlopen the first time an ESMF
// weight file (*.nc, app/operator_esmf.cpp) is written or read.
//
// Why not linked: libnetcdf brings HDF5, curl, GnuTLS, Kerberos, LDAP and ICU with it, and
// loading them cost every start of the executable about 19 ms (an empty program linked with
// -lnetcdf: 20.6 ms against 1.6 ms, this VM), while only `--save-operator W.nc` and
// `tetia apply W.nc` use it. The library is the one the executable was built against, by its
// soname (TETIA_NETCDF_SONAME, set by CMake: libnetcdf.so.19 on Debian 12), found where the
// dynamic loader looks, or the one the environment variable TETIA_NETCDF_LIBRARY names; its
// functions are the ones netcdf.h declares, with those types.
#pragma once

#include <netcdf.h>

#include <string>

namespace tetia::app {

struct NetcdfLibrary {
  decltype(&::nc_strerror) nc_strerror;
  decltype(&::nc_create) nc_create;
  decltype(&::nc_open) nc_open;
  decltype(&::nc_close) nc_close;
  decltype(&::nc_enddef) nc_enddef;
  decltype(&::nc_def_dim) nc_def_dim;
  decltype(&::nc_def_var) nc_def_var;
  decltype(&::nc_put_att_text) nc_put_att_text;
  decltype(&::nc_put_att_int) nc_put_att_int;
  decltype(&::nc_put_var_int) nc_put_var_int;
  decltype(&::nc_put_var_double) nc_put_var_double;
  decltype(&::nc_inq_dimid) nc_inq_dimid;
  decltype(&::nc_inq_dimlen) nc_inq_dimlen;
  decltype(&::nc_inq_varid) nc_inq_varid;
  decltype(&::nc_inq_varndims) nc_inq_varndims;
  decltype(&::nc_inq_vartype) nc_inq_vartype;
  decltype(&::nc_inq_vardimid) nc_inq_vardimid;
  decltype(&::nc_get_var_int) nc_get_var_int;
  decltype(&::nc_get_var_double) nc_get_var_double;
  decltype(&::nc_inq_attlen) nc_inq_attlen;
  decltype(&::nc_get_att_text) nc_get_att_text;
  decltype(&::nc_get_att_int) nc_get_att_int;
};

/// The loaded library (once, thread-safe). Throws std::runtime_error "tetia: FILE: ESMF weight
/// files need the netCDF library (NAME): REASON" where it cannot be loaded or lacks a function
/// (the CLI's exit status 2, nothing written).
const NetcdfLibrary& netcdf_library(const std::string& file);

}  // namespace tetia::app
