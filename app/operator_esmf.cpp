// app/operator_esmf.cpp -- remap operators as ESMF offline weight files (netCDF, classic 64-bit
// offset format; app/operator_file.hpp), through the netCDF C library (loaded on first use:
// netcdf_library.hpp). The reader checks every dimension against the file's size (each entry,
// source and target value takes bytes there) and against what the meshes justify before it
// allocates.
#include <filesystem>
#include <stdexcept>
#include <type_traits>

#include "netcdf_library.hpp"
#include "operator_file.hpp"

namespace tetia::app {

namespace {

void nc_check(const NetcdfLibrary& lib, int status, const std::string& file, const char* what) {
  if (status != NC_NOERR)
    throw std::runtime_error("tetia: " + file + ": netCDF: " + what + ": " + lib.nc_strerror(status));
}

}  // namespace

void write_esmf(const std::string& file, const OperatorFile& op) {
  const NetcdfLibrary& lib = netcdf_library(file);
  const auto n_a = static_cast<std::size_t>(op.weights.cols()), n_b = static_cast<std::size_t>(op.weights.rows());
  const auto n_s = static_cast<std::size_t>(op.weights.nonZeros());
  if (op.area_a.size() != n_a || op.frac_a.size() != n_a || op.area_b.size() != n_b || op.frac_b.size() != n_b)
    throw std::logic_error("tetia: ESMF weight file: areas and fractions do not match the operator's size");
  int nc = -1;
  nc_check(lib, lib.nc_create(file.c_str(), NC_CLOBBER | NC_64BIT_OFFSET, &nc), file, "create");
  struct Closer {
    const NetcdfLibrary& lib;
    int id;
    ~Closer() {
      if (id >= 0) lib.nc_close(id);
    }
  } closer{lib, nc};
  int dim_a, dim_b, dim_s;
  nc_check(lib, lib.nc_def_dim(nc, "n_a", n_a, &dim_a), file, "n_a");
  nc_check(lib, lib.nc_def_dim(nc, "n_b", n_b, &dim_b), file, "n_b");
  nc_check(lib, lib.nc_def_dim(nc, "n_s", n_s, &dim_s), file, "n_s");
  int row, col, S, area_a, area_b, frac_a, frac_b;
  nc_check(lib, lib.nc_def_var(nc, "row", NC_INT, 1, &dim_s, &row), file, "row");
  nc_check(lib, lib.nc_def_var(nc, "col", NC_INT, 1, &dim_s, &col), file, "col");
  nc_check(lib, lib.nc_def_var(nc, "S", NC_DOUBLE, 1, &dim_s, &S), file, "S");
  nc_check(lib, lib.nc_def_var(nc, "area_a", NC_DOUBLE, 1, &dim_a, &area_a), file, "area_a");
  nc_check(lib, lib.nc_def_var(nc, "area_b", NC_DOUBLE, 1, &dim_b, &area_b), file, "area_b");
  nc_check(lib, lib.nc_def_var(nc, "frac_a", NC_DOUBLE, 1, &dim_a, &frac_a), file, "frac_a");
  nc_check(lib, lib.nc_def_var(nc, "frac_b", NC_DOUBLE, 1, &dim_b, &frac_b), file, "frac_b");
  const auto text = [&](int var, const char* name, const std::string& value) {
    nc_check(lib, lib.nc_put_att_text(nc, var, name, value.size(), value.c_str()), file, name);
  };
  text(row, "long_name", "destination (target) value, 1-based");
  text(col, "long_name", "source value, 1-based");
  text(S, "long_name", "weight: destination value i = sum of S times source value col over the entries of row i");
  text(area_a, "long_name", "measure of each source value");
  text(area_b, "long_name", "measure of each destination value");
  text(frac_a, "long_name", "fraction of each source value's measure that the destination covers");
  text(frac_b, "long_name", "fraction of each destination value's measure that the source covers");
  text(NC_GLOBAL, "title", "tetia remap operator");
  text(NC_GLOBAL, "map_method", "Conservative remapping");
  text(NC_GLOBAL, "conventions", "NCAR-CSM");
  text(NC_GLOBAL, "normalization", op.normalize == "full" ? "destarea" : "fracarea");
  text(NC_GLOBAL, "tetia_method", op.method);
  text(NC_GLOBAL, "tetia_rows", location_name(op.rows));
  text(NC_GLOBAL, "tetia_columns", location_name(op.columns));
  const int dimension = op.dimension;
  nc_check(lib, lib.nc_put_att_int(nc, NC_GLOBAL, "tetia_dimension", NC_INT, 1, &dimension), file, "tetia_dimension");
  nc_check(lib, lib.nc_enddef(nc), file, "enddef");
  std::vector<int> rows(n_s), cols(n_s);
  std::vector<double> values(n_s);
  std::size_t k = 0;
  for (Eigen::Index r = 0; r < op.weights.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(op.weights, r); it; ++it, ++k) {
      rows[k] = static_cast<int>(r + 1);
      cols[k] = static_cast<int>(it.col() + 1);
      values[k] = it.value();
    }
  if (n_s > 0) {
    nc_check(lib, lib.nc_put_var_int(nc, row, rows.data()), file, "row");
    nc_check(lib, lib.nc_put_var_int(nc, col, cols.data()), file, "col");
    nc_check(lib, lib.nc_put_var_double(nc, S, values.data()), file, "S");
  }
  if (n_a > 0) {
    nc_check(lib, lib.nc_put_var_double(nc, area_a, op.area_a.data()), file, "area_a");
    nc_check(lib, lib.nc_put_var_double(nc, frac_a, op.frac_a.data()), file, "frac_a");
  }
  if (n_b > 0) {
    nc_check(lib, lib.nc_put_var_double(nc, area_b, op.area_b.data()), file, "area_b");
    nc_check(lib, lib.nc_put_var_double(nc, frac_b, op.frac_b.data()), file, "frac_b");
  }
  closer.id = -1;
  nc_check(lib, lib.nc_close(nc), file, "close");
}

OperatorFile read_esmf(const std::string& file, std::size_t max_values, bool description_only) {
  const NetcdfLibrary& lib = netcdf_library(file);
  int nc = -1;
  const int opened = lib.nc_open(file.c_str(), NC_NOWRITE, &nc);
  if (opened != NC_NOERR) throw std::invalid_argument("tetia: " + file + ": not a netCDF file: " + lib.nc_strerror(opened));
  struct Closer {
    const NetcdfLibrary& lib;
    int id;
    ~Closer() { lib.nc_close(id); }
  } closer{lib, nc};
  const auto bad = [&](const std::string& what) { return std::invalid_argument("tetia: " + file + ": " + what); };
  const auto dim = [&](const char* name) {
    int id = -1;
    std::size_t n = 0;
    if (lib.nc_inq_dimid(nc, name, &id) != NC_NOERR || lib.nc_inq_dimlen(nc, id, &n) != NC_NOERR)
      throw bad(std::string("no dimension ") + name + ": not an ESMF weight file");
    return n;
  };
  const auto var = [&](const char* name, std::size_t n, auto* out) {
    int id = -1, dims = 0;
    nc_type type;
    if (lib.nc_inq_varid(nc, name, &id) != NC_NOERR) throw bad(std::string("no variable ") + name);
    nc_check(lib, lib.nc_inq_varndims(nc, id, &dims), file, name);
    nc_check(lib, lib.nc_inq_vartype(nc, id, &type), file, name);
    if (dims != 1) throw bad(std::string("variable ") + name + " is not one-dimensional");
    int dimid = -1;
    nc_check(lib, lib.nc_inq_vardimid(nc, id, &dimid), file, name);
    std::size_t len = 0;
    nc_check(lib, lib.nc_inq_dimlen(nc, dimid, &len), file, name);
    if (len != n) throw bad(std::string("variable ") + name + " has " + std::to_string(len) + " values, not " + std::to_string(n));
    if (n == 0) return;
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(*out)>, int>) nc_check(lib, lib.nc_get_var_int(nc, id, out), file, name);
    else nc_check(lib, lib.nc_get_var_double(nc, id, out), file, name);
  };
  const auto attribute = [&](const char* name) {
    std::size_t n = 0;
    if (lib.nc_inq_attlen(nc, NC_GLOBAL, name, &n) != NC_NOERR)
      throw bad(std::string("no attribute ") + name + ": not an operator that 'tetia remap --save-operator' wrote");
    std::string s(n, '\0');
    nc_check(lib, lib.nc_get_att_text(nc, NC_GLOBAL, name, s.data()), file, name);
    while (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
  };
  OperatorFile op;
  op.method = attribute("tetia_method");
  op.rows = parse_location(attribute("tetia_rows"), "tetia: " + file);
  op.columns = parse_location(attribute("tetia_columns"), "tetia: " + file);
  const std::string normalization = attribute("normalization");
  op.normalize = normalization == "fracarea" ? "covered" : "full";
  int dimension = 0;
  if (lib.nc_get_att_int(nc, NC_GLOBAL, "tetia_dimension", &dimension) != NC_NOERR) throw bad("no attribute tetia_dimension");
  op.dimension = dimension;
  check_description(op, "tetia: " + file);
  if (description_only) return op;
  const std::size_t n_a = dim("n_a"), n_b = dim("n_b"), n_s = dim("n_s");
  // Nothing is allocated for more than the file or the meshes justify: every entry (row, col, S)
  // and every value (area, frac) takes bytes in the file, and the values are the meshes'.
  std::error_code ec;
  const auto bytes = static_cast<std::size_t>(std::filesystem::file_size(file, ec));
  if (ec || n_s > bytes / 16 || n_a > bytes / 16 || n_b > bytes / 16)
    throw bad("its dimensions (n_s " + std::to_string(n_s) + ", n_a " + std::to_string(n_a) + ", n_b " +
              std::to_string(n_b) + ") are more than the file holds");
  if (n_a > max_values || n_b > max_values)
    throw bad("an n_b x n_a = " + std::to_string(n_b) + " x " + std::to_string(n_a) +
              " operator is larger than the meshes have values (" + std::to_string(max_values) + ")");
  std::vector<int> rows(n_s), cols(n_s);
  std::vector<double> values(n_s);
  var("row", n_s, rows.data());
  var("col", n_s, cols.data());
  var("S", n_s, values.data());
  op.area_a.resize(n_a), op.frac_a.resize(n_a), op.area_b.resize(n_b), op.frac_b.resize(n_b);
  var("area_a", n_a, op.area_a.data());
  var("frac_a", n_a, op.frac_a.data());
  var("area_b", n_b, op.area_b.data());
  var("frac_b", n_b, op.frac_b.data());
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(n_s);
  for (std::size_t k = 0; k < n_s; ++k) {
    if (rows[k] < 1 || static_cast<std::size_t>(rows[k]) > n_b || cols[k] < 1 || static_cast<std::size_t>(cols[k]) > n_a)
      throw bad("entry " + std::to_string(k + 1) + ": (row, col) = (" + std::to_string(rows[k]) + ", " +
                std::to_string(cols[k]) + ") outside n_b x n_a = " + std::to_string(n_b) + " x " + std::to_string(n_a));
    if (!std::isfinite(values[k])) throw bad("entry " + std::to_string(k + 1) + ": S is not finite");
    t.emplace_back(rows[k] - 1, cols[k] - 1, values[k]);
  }
  op.weights = from_entries(n_b, n_a, t, "tetia: " + file);
  return op;
}

}  // namespace tetia::app
