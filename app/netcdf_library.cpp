// app/netcdf_library.cpp -- see netcdf_library.hpp.
#include "netcdf_library.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>
#include <type_traits>

#ifndef TETIA_NETCDF_SONAME
#error "TETIA_NETCDF_SONAME (the netCDF library's soname) is set by CMake"
#endif

namespace tetia::app {

namespace {

// The table, or the reason it could not be filled.
struct Loaded {
  NetcdfLibrary lib{};
  std::string error;
};

// The library's name or path: TETIA_NETCDF_LIBRARY where set (another build of it, or a test
// of the error), else the soname the executable was built against.
std::string library_name() {
  const char* env = std::getenv("TETIA_NETCDF_LIBRARY");
  return env != nullptr && *env != '\0' ? env : TETIA_NETCDF_SONAME;
}

Loaded load() {
  Loaded out;
  void* handle = ::dlopen(library_name().c_str(), RTLD_NOW | RTLD_LOCAL);  // never closed: used until exit
  if (!handle) {
    const char* why = ::dlerror();
    out.error = why ? why : "dlopen failed";
    return out;
  }
  const auto get = [&](auto& fn, const char* name) {
    if (!out.error.empty()) return;
    void* symbol = ::dlsym(handle, name);
    if (!symbol) out.error = std::string("no function ") + name;
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(symbol);
  };
  NetcdfLibrary& l = out.lib;
  get(l.nc_strerror, "nc_strerror");
  get(l.nc_create, "nc_create");
  get(l.nc_open, "nc_open");
  get(l.nc_close, "nc_close");
  get(l.nc_enddef, "nc_enddef");
  get(l.nc_def_dim, "nc_def_dim");
  get(l.nc_def_var, "nc_def_var");
  get(l.nc_put_att_text, "nc_put_att_text");
  get(l.nc_put_att_int, "nc_put_att_int");
  get(l.nc_put_var_int, "nc_put_var_int");
  get(l.nc_put_var_double, "nc_put_var_double");
  get(l.nc_inq_dimid, "nc_inq_dimid");
  get(l.nc_inq_dimlen, "nc_inq_dimlen");
  get(l.nc_inq_varid, "nc_inq_varid");
  get(l.nc_inq_varndims, "nc_inq_varndims");
  get(l.nc_inq_vartype, "nc_inq_vartype");
  get(l.nc_inq_vardimid, "nc_inq_vardimid");
  get(l.nc_get_var_int, "nc_get_var_int");
  get(l.nc_get_var_double, "nc_get_var_double");
  get(l.nc_inq_attlen, "nc_inq_attlen");
  get(l.nc_get_att_text, "nc_get_att_text");
  get(l.nc_get_att_int, "nc_get_att_int");
  return out;
}

}  // namespace

const NetcdfLibrary& netcdf_library(const std::string& file) {
  static const Loaded loaded = load();
  if (!loaded.error.empty())
    throw std::runtime_error("tetia: " + file + ": ESMF weight files need the netCDF library (" + library_name() +
                             "): " + loaded.error);
  return loaded.lib;
}

}  // namespace tetia::app
