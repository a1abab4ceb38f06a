// app/operator_file.hpp -- remap operators in files: `tetia remap --save-operator W` writes one,
// `tetia apply W ...` reads it and applies it without the meshes' supermesh. Two formats, by
// the file's name:
// - *.mtx: Matrix Market (coordinate real general, 1-based, 17 significant digits: every double
//   comes back exactly), for SciPy (scipy.io.mmread), Eigen and MATLAB. The line
//   "% tetia-operator dimension=D method=M normalize=N rows=R columns=C" says what the rows and
//   columns are (R, C: cells, nodes or cell_nodes: the target's and source's file cells, nodes,
//   or cells' vertices in the order of the cells' nodes).
// - *.nc: an ESMF offline weight file (netCDF, classic 64-bit offset format) as ESMF's
//   regridding tools and the couplers that read them expect: dimensions n_a (source values),
//   n_b (target values), n_s (entries); variables row, col (1-based int), S (double), area_a,
//   area_b (the measure each value stands for: a cell's, a node's lumped mass, a cell vertex's
//   share |T| / (d + 1)), frac_a, frac_b (the fraction of that measure the other mesh covers);
//   global attributes title, map_method, normalization (ESMF's "destarea" for --normalize
//   full, "fracarea" for covered) and tetia_dimension, tetia_method, tetia_rows, tetia_columns.
// In both, entry (i, j) is W_ij with (W u)_i the remap of u at target value i. The entries are
// kept in (row, column) order, and tetia::apply_operator sums each row in that order: a saved
// operator applied gives what `tetia remap` computed with it, bit for bit.
// Errors (a file that cannot be read or written, a malformed or inconsistent one) throw
// std::invalid_argument or std::runtime_error naming the file (and the line, for Matrix Market).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "remap_method.hpp"
#include "tetia/remap.hpp"

namespace tetia::app {

struct OperatorFile {
  int dimension = 3;
  std::string method = "p0";     // method_name()
  std::string normalize = "full";
  Location rows = Location::cells, columns = Location::cells;
  SparseMatrix weights;  // rows x columns
  // ESMF's per-value measures and covered fractions (written to .nc files only; read back from
  // them, empty from .mtx files).
  std::vector<double> area_a, area_b, frac_a, frac_b;
};

const char* location_name(Location l);

bool is_esmf_path(const std::string& file);  // *.nc
bool is_operator_path(const std::string& file);  // *.mtx or *.nc

void write_operator(const std::string& file, const OperatorFile& op);
/// max_values: the most rows or columns the meshes it is for can have (nothing larger is
/// allocated: a file's sizes are checked against it and against the file's own size first).
/// description_only: the dimension, method, normalization, rows and columns without the
/// weights (what the reader of the meshes needs to know first).
OperatorFile read_operator(const std::string& file, std::size_t max_values = static_cast<std::size_t>(-1),
                           bool description_only = false);

// The formats (app/operator_mtx.cpp, app/operator_esmf.cpp); parse_mtx is the Matrix Market
// reader on the file's text (`file` names it in errors), which fuzz/fuzz_operator_mtx.cpp fuzzes.
void write_mtx(const std::string& file, const OperatorFile& op);
OperatorFile read_mtx(const std::string& file, std::size_t max_values, bool description_only);
OperatorFile parse_mtx(std::string_view text, const std::string& file, std::size_t max_values,
                       bool description_only = false);
void write_esmf(const std::string& file, const OperatorFile& op);
OperatorFile read_esmf(const std::string& file, std::size_t max_values, bool description_only);

// What both formats share: a location's name back to it, the description's checks, and the
// entries into a matrix (an entry given twice is an error). Errors name `where`.
Location parse_location(const std::string& s, const std::string& where);
void check_description(const OperatorFile& op, const std::string& where);
SparseMatrix from_entries(std::size_t rows, std::size_t cols, const std::vector<Eigen::Triplet<double>>& t,
                          const std::string& where);

}  // namespace tetia::app
