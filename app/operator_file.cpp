// app/operator_file.cpp -- the remap operator's files (app/operator_file.hpp): Matrix Market
// written and parsed here (a strict reader: every line checked, the line named in errors), the
// ESMF weight file through the netCDF C library.
#include "operator_file.hpp"

#include <netcdf.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tetia::app {
namespace {

bool ends_with(const std::string& s, const char* tail) {
  const std::size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

Location parse_location(const std::string& s, const std::string& where) {
  if (s == "cells") return Location::cells;
  if (s == "nodes") return Location::nodes;
  if (s == "cell_nodes") return Location::cell_nodes;
  throw std::invalid_argument(where + ": rows and columns must be cells, nodes or cell_nodes, not '" + s + "'");
}

// The operator's description, as the Matrix Market comment and the netCDF attributes hold it.
void check_description(const OperatorFile& op, const std::string& where) {
  if (op.dimension != 2 && op.dimension != 3) throw std::invalid_argument(where + ": dimension must be 2 or 3");
  if (op.method.empty()) throw std::invalid_argument(where + ": no method");
  if (op.normalize != "full" && op.normalize != "covered")
    throw std::invalid_argument(where + ": normalize must be full or covered, not '" + op.normalize + "'");
}

SparseMatrix from_entries(std::size_t rows, std::size_t cols, const std::vector<Eigen::Triplet<double>>& t,
                          const std::string& where) {
  SparseMatrix w(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  w.setFromTriplets(t.begin(), t.end(), [&](const double&, const double&) -> double {
    throw std::invalid_argument(where + ": an entry (row, column) is given twice");
  });
  w.makeCompressed();
  return w;
}

// ---------------------------------------------------------------------------------------------
// Matrix Market

void write_mtx(const std::string& file, const OperatorFile& op) {
  std::FILE* out = std::fopen(file.c_str(), "wb");
  if (out == nullptr) throw std::runtime_error("tetia: " + file + ": cannot write: " + std::strerror(errno));
  std::fprintf(out, "%%%%MatrixMarket matrix coordinate real general\n");
  std::fprintf(out, "%% tetia remap operator: (W u)_i is the remap of u at target value i (tetia apply)\n");
  std::fprintf(out, "%% tetia-operator dimension=%d method=%s normalize=%s rows=%s columns=%s\n", op.dimension,
               op.method.c_str(), op.normalize.c_str(), location_name(op.rows), location_name(op.columns));
  std::fprintf(out, "%lld %lld %lld\n", static_cast<long long>(op.weights.rows()),
               static_cast<long long>(op.weights.cols()), static_cast<long long>(op.weights.nonZeros()));
  for (Eigen::Index r = 0; r < op.weights.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(op.weights, r); it; ++it)
      std::fprintf(out, "%lld %lld %.17g\n", static_cast<long long>(r + 1), static_cast<long long>(it.col() + 1),
                   it.value());
  const bool failed = std::ferror(out) != 0;
  if (std::fclose(out) != 0 || failed) throw std::runtime_error("tetia: " + file + ": write failed");
}

// A whole non-negative integer below 2^31 (indices and sizes), or a finite double.
bool parse_count(const std::string& word, long long& v) {
  if (word.empty() || word.size() > 10) return false;
  for (const char c : word)
    if (c < '0' || c > '9') return false;
  v = std::atoll(word.c_str());
  return v < (1LL << 31);
}
bool parse_value(const std::string& word, double& v) {
  char* end = nullptr;
  errno = 0;
  v = std::strtod(word.c_str(), &end);
  return !word.empty() && end == word.c_str() + word.size() && std::isfinite(v);
}

OperatorFile read_mtx(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("tetia: " + file + ": cannot open: " + std::strerror(errno));
  OperatorFile op;
  std::string line;
  std::size_t number = 0;
  const auto where = [&] { return "tetia: " + file + ":" + std::to_string(number); };
  if (!std::getline(in, line) || (++number, line.rfind("%%MatrixMarket matrix coordinate real general", 0) != 0))
    throw std::invalid_argument("tetia: " + file + ":1: not a Matrix Market file of a real sparse matrix "
                                "('%%MatrixMarket matrix coordinate real general')");
  bool described = false;
  long long rows = -1, cols = -1, entries = -1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("%", 0) == 0) {
      if (line.rfind("% tetia-operator ", 0) == 0) {
        std::istringstream words(line.substr(17));
        std::string w;
        std::string rows_word, cols_word;
        while (words >> w) {
          const auto eq = w.find('=');
          if (eq == std::string::npos) throw std::invalid_argument(where() + ": '" + w + "' is not key=value");
          const std::string key = w.substr(0, eq), value = w.substr(eq + 1);
          if (key == "dimension") op.dimension = value == "2" ? 2 : value == "3" ? 3 : 0;
          else if (key == "method") op.method = value;
          else if (key == "normalize") op.normalize = value;
          else if (key == "rows") rows_word = value;
          else if (key == "columns") cols_word = value;
        }
        op.rows = parse_location(rows_word, where());
        op.columns = parse_location(cols_word, where());
        check_description(op, where());
        described = true;
      }
      continue;
    }
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream words(line);
    std::string a, b, c, extra;
    words >> a >> b >> c;
    if (words >> extra) throw std::invalid_argument(where() + ": more than three numbers");
    if (rows < 0) {
      if (!parse_count(a, rows) || !parse_count(b, cols) || !parse_count(c, entries))
        throw std::invalid_argument(where() + ": the size line must be three counts: rows, columns, entries");
      break;
    }
  }
  if (!described)
    throw std::invalid_argument("tetia: " + file + ": no '% tetia-operator ...' line: not an operator that "
                                "'tetia remap --save-operator' wrote (it says what the rows and columns are)");
  if (rows < 0) throw std::invalid_argument("tetia: " + file + ": no size line");
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(std::min<long long>(entries, 1LL << 26)));
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '%') continue;
    std::istringstream words(line);
    std::string a, b, c, extra;
    words >> a >> b >> c;
    long long i = 0, j = 0;
    double v = 0.0;
    if (!parse_count(a, i) || !parse_count(b, j) || !parse_value(c, v) || (words >> extra))
      throw std::invalid_argument(where() + ": an entry must be: row column value (a finite number)");
    if (i < 1 || i > rows || j < 1 || j > cols)
      throw std::invalid_argument(where() + ": entry (" + a + ", " + b + ") outside the " + std::to_string(rows) +
                                  " x " + std::to_string(cols) + " matrix");
    if (static_cast<long long>(t.size()) == entries)
      throw std::invalid_argument(where() + ": more entries than the size line's " + std::to_string(entries));
    t.emplace_back(static_cast<int>(i - 1), static_cast<int>(j - 1), v);
  }
  if (static_cast<long long>(t.size()) != entries)
    throw std::invalid_argument("tetia: " + file + ": " + std::to_string(t.size()) + " entries, the size line says " +
                                std::to_string(entries));
  op.weights = from_entries(static_cast<std::size_t>(rows), static_cast<std::size_t>(cols), t, "tetia: " + file);
  return op;
}

// ---------------------------------------------------------------------------------------------
// ESMF (netCDF)

void nc_check(int status, const std::string& file, const char* what) {
  if (status != NC_NOERR)
    throw std::runtime_error("tetia: " + file + ": netCDF: " + what + ": " + nc_strerror(status));
}

void write_nc(const std::string& file, const OperatorFile& op) {
  const auto n_a = static_cast<std::size_t>(op.weights.cols()), n_b = static_cast<std::size_t>(op.weights.rows());
  const auto n_s = static_cast<std::size_t>(op.weights.nonZeros());
  if (op.area_a.size() != n_a || op.frac_a.size() != n_a || op.area_b.size() != n_b || op.frac_b.size() != n_b)
    throw std::logic_error("tetia: ESMF weight file: areas and fractions do not match the operator's size");
  int nc = -1;
  nc_check(nc_create(file.c_str(), NC_CLOBBER | NC_64BIT_OFFSET, &nc), file, "create");
  struct Closer {
    int id;
    ~Closer() {
      if (id >= 0) nc_close(id);
    }
  } closer{nc};
  int dim_a, dim_b, dim_s;
  nc_check(nc_def_dim(nc, "n_a", n_a, &dim_a), file, "n_a");
  nc_check(nc_def_dim(nc, "n_b", n_b, &dim_b), file, "n_b");
  nc_check(nc_def_dim(nc, "n_s", n_s, &dim_s), file, "n_s");
  int row, col, S, area_a, area_b, frac_a, frac_b;
  nc_check(nc_def_var(nc, "row", NC_INT, 1, &dim_s, &row), file, "row");
  nc_check(nc_def_var(nc, "col", NC_INT, 1, &dim_s, &col), file, "col");
  nc_check(nc_def_var(nc, "S", NC_DOUBLE, 1, &dim_s, &S), file, "S");
  nc_check(nc_def_var(nc, "area_a", NC_DOUBLE, 1, &dim_a, &area_a), file, "area_a");
  nc_check(nc_def_var(nc, "area_b", NC_DOUBLE, 1, &dim_b, &area_b), file, "area_b");
  nc_check(nc_def_var(nc, "frac_a", NC_DOUBLE, 1, &dim_a, &frac_a), file, "frac_a");
  nc_check(nc_def_var(nc, "frac_b", NC_DOUBLE, 1, &dim_b, &frac_b), file, "frac_b");
  const auto text = [&](int var, const char* name, const std::string& value) {
    nc_check(nc_put_att_text(nc, var, name, value.size(), value.c_str()), file, name);
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
  nc_check(nc_put_att_int(nc, NC_GLOBAL, "tetia_dimension", NC_INT, 1, &dimension), file, "tetia_dimension");
  nc_check(nc_enddef(nc), file, "enddef");
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
    nc_check(nc_put_var_int(nc, row, rows.data()), file, "row");
    nc_check(nc_put_var_int(nc, col, cols.data()), file, "col");
    nc_check(nc_put_var_double(nc, S, values.data()), file, "S");
  }
  if (n_a > 0) {
    nc_check(nc_put_var_double(nc, area_a, op.area_a.data()), file, "area_a");
    nc_check(nc_put_var_double(nc, frac_a, op.frac_a.data()), file, "frac_a");
  }
  if (n_b > 0) {
    nc_check(nc_put_var_double(nc, area_b, op.area_b.data()), file, "area_b");
    nc_check(nc_put_var_double(nc, frac_b, op.frac_b.data()), file, "frac_b");
  }
  closer.id = -1;
  nc_check(nc_close(nc), file, "close");
}

OperatorFile read_nc(const std::string& file) {
  int nc = -1;
  const int opened = nc_open(file.c_str(), NC_NOWRITE, &nc);
  if (opened != NC_NOERR) throw std::invalid_argument("tetia: " + file + ": not a netCDF file: " + nc_strerror(opened));
  struct Closer {
    int id;
    ~Closer() { nc_close(id); }
  } closer{nc};
  const auto bad = [&](const std::string& what) { return std::invalid_argument("tetia: " + file + ": " + what); };
  const auto dim = [&](const char* name) {
    int id = -1;
    std::size_t n = 0;
    if (nc_inq_dimid(nc, name, &id) != NC_NOERR || nc_inq_dimlen(nc, id, &n) != NC_NOERR)
      throw bad(std::string("no dimension ") + name + ": not an ESMF weight file");
    return n;
  };
  const auto var = [&](const char* name, std::size_t n, auto* out) {
    int id = -1, dims = 0;
    nc_type type;
    if (nc_inq_varid(nc, name, &id) != NC_NOERR) throw bad(std::string("no variable ") + name);
    nc_check(nc_inq_varndims(nc, id, &dims), file, name);
    nc_check(nc_inq_vartype(nc, id, &type), file, name);
    if (dims != 1) throw bad(std::string("variable ") + name + " is not one-dimensional");
    int dimid = -1;
    nc_check(nc_inq_vardimid(nc, id, &dimid), file, name);
    std::size_t len = 0;
    nc_check(nc_inq_dimlen(nc, dimid, &len), file, name);
    if (len != n) throw bad(std::string("variable ") + name + " has " + std::to_string(len) + " values, not " + std::to_string(n));
    if (n == 0) return;
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(*out)>, int>) nc_check(nc_get_var_int(nc, id, out), file, name);
    else nc_check(nc_get_var_double(nc, id, out), file, name);
  };
  const auto attribute = [&](const char* name) {
    std::size_t n = 0;
    if (nc_inq_attlen(nc, NC_GLOBAL, name, &n) != NC_NOERR)
      throw bad(std::string("no attribute ") + name + ": not an operator that 'tetia remap --save-operator' wrote");
    std::string s(n, '\0');
    nc_check(nc_get_att_text(nc, NC_GLOBAL, name, s.data()), file, name);
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
  if (nc_get_att_int(nc, NC_GLOBAL, "tetia_dimension", &dimension) != NC_NOERR) throw bad("no attribute tetia_dimension");
  op.dimension = dimension;
  check_description(op, "tetia: " + file);
  const std::size_t n_a = dim("n_a"), n_b = dim("n_b"), n_s = dim("n_s");
  if (n_a >= (1u << 31) || n_b >= (1u << 31)) throw bad("n_a or n_b is 2^31 or more");
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

}  // namespace

const char* location_name(Location l) {
  switch (l) {
    case Location::cells: return "cells";
    case Location::nodes: return "nodes";
    case Location::cell_nodes: return "cell_nodes";
  }
  return "?";
}

bool is_esmf_path(const std::string& file) { return ends_with(file, ".nc"); }
bool is_operator_path(const std::string& file) { return ends_with(file, ".mtx") || ends_with(file, ".nc"); }

void write_operator(const std::string& file, const OperatorFile& op) {
  if (is_esmf_path(file)) write_nc(file, op);
  else write_mtx(file, op);
}

OperatorFile read_operator(const std::string& file) {
  if (!is_operator_path(file))
    throw std::invalid_argument("tetia: " + file + ": an operator file ends in .mtx (Matrix Market) or .nc (ESMF)");
  return is_esmf_path(file) ? read_nc(file) : read_mtx(file);
}

}  // namespace tetia::app
