// app/operator_file.cpp -- the remap operator's files (app/operator_file.hpp): what both formats
// share (the description's checks, the entries into a matrix) and the choice of the format by
// the file's name. Matrix Market: app/operator_mtx.cpp; ESMF (netCDF): app/operator_esmf.cpp.
#include "operator_file.hpp"

#include <cstring>
#include <stdexcept>

namespace tetia::app {

namespace {

bool ends_with(const std::string& s, const char* tail) {
  const std::size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

}  // namespace

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
  if (is_esmf_path(file)) write_esmf(file, op);
  else write_mtx(file, op);
}

OperatorFile read_operator(const std::string& file, std::size_t max_values, bool description_only) {
  if (!is_operator_path(file))
    throw std::invalid_argument("tetia: " + file + ": an operator file ends in .mtx (Matrix Market) or .nc (ESMF)");
  return is_esmf_path(file) ? read_esmf(file, max_values, description_only)
                            : read_mtx(file, max_values, description_only);
}

}  // namespace tetia::app
