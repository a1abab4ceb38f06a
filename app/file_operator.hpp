// app/file_operator.hpp -- what `tetia remap --save-operator` and `tetia apply` need around the
// library's operators (tetia/remap_operator.hpp's matrix(): rows and columns on the files'
// cells, nodes, or cells' vertices): which methods have one, how many values a field has where
// it lives, a field as the columns take it, and the measures and covered fractions an ESMF
// weight file holds beside the weights.
#pragma once

#include <Eigen/SparseCore>
#include <cstddef>
#include <span>
#include <vector>

#include "mesh_kind.hpp"
#include "operator_file.hpp"
#include "remap_method.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/remap_methods.hpp"

namespace tetia::app {

// Cell averages (from cells or from a discontinuous source), lumped and discontinuous P1 are
// linear in the field; the Galerkin P1 operator M_t^-1 M_ts is dense, and the bounded P1 and
// the limited reconstruction depend on the field.
inline bool has_operator(Method m) {
  return m == Method::p0 || m == Method::p0_from_discontinuous || m == Method::p1_lumped ||
         m == Method::p1_discontinuous;
}

// How many values a field has where it lives: file cells, nodes, or simplices' vertices.
template <class Mesh>
std::size_t value_count(const Mesh& m, Location where) {
  switch (where) {
    case Location::cells: return m.num_file_cells();
    case Location::nodes: return m.num_nodes();
    case Location::cell_nodes: return m.num_cells() * (Kind<Mesh>::dim + 1);
  }
  return 0;
}

// A field as the operator's columns take it: per file cell (the value of its first simplex: a
// file cell's value is on each of its simplices), else as it is.
template <class Mesh>
std::vector<double> operator_columns(const Mesh& m, Location where, std::span<const double> values) {
  if (where != Location::cells || m.cell_origin.empty()) return {values.begin(), values.end()};
  std::vector<double> out(m.num_file_cells(), 0.0);
  for (std::size_t c = m.num_cells(); c-- > 0;) out[m.file_cell(c)] = values[c];
  return out;
}

// What an ESMF weight file holds beside the weights: per value, the measure it stands for
// (a file cell's, a node's lumped mass, a cell vertex's |T| / (d + 1)) and the fraction of it
// that the other mesh covers. For the target: file_coverage (per file cell), node_coverage (per
// node), cell_coverage (per simplex); for the source they are computed here from the pieces
// (and, for nodes, the mixed mass matrix's column sums).
template <class Mesh>
void add_esmf_measures(OperatorFile& op, const typename Kind<Mesh>::Result& s, const std::vector<double>& file_coverage, const std::vector<double>& node_coverage,
                       const std::vector<double>& cell_coverage) {
  using K = Kind<Mesh>;
  constexpr std::size_t nv = K::dim + 1;
  const Mesh& tgt = *s.target;
  const Mesh& src = *s.source;
  const auto per_vertex = [&](const Mesh& m, const std::vector<double>& per_cell, bool measure) {
    std::vector<double> out(m.num_cells() * nv);
    for (std::size_t c = 0; c < m.num_cells(); ++c)
      for (std::size_t k = 0; k < nv; ++k) out[c * nv + k] = measure ? per_cell[c] * (1.0 / nv) : per_cell[c];
    return out;
  };
  const auto area = [&](const Mesh& m, Location where) {
    if (where == Location::cells) return file_cell_measures(m);
    if (where == Location::nodes) return lumped_mass(m);
    return per_vertex(m, K::measures(m), true);
  };
  op.area_b = area(tgt, op.rows);
  op.area_a = area(src, op.columns);
  op.frac_b = op.rows == Location::cells ? file_coverage
              : op.rows == Location::nodes ? node_coverage
                                           : per_vertex(tgt, cell_coverage, false);
  if (op.columns == Location::nodes) {
    const SparseMatrix m = mixed_mass_matrix(s);
    std::vector<double> covered(src.num_nodes(), 0.0);
    for (Eigen::Index r = 0; r < m.outerSize(); ++r)
      for (SparseMatrix::InnerIterator it(m, r); it; ++it) covered[static_cast<std::size_t>(it.col())] += it.value();
    op.frac_a = lumped_mass(src);
    for (std::size_t i = 0; i < covered.size(); ++i) op.frac_a[i] = op.frac_a[i] > 0.0 ? covered[i] / op.frac_a[i] : 0.0;
    return;
  }
  // Cells: each source simplex's covered measure, over its measure (per file cell: summed).
  std::vector<double> covered(src.num_cells(), 0.0);
  for (const auto& p : s.pieces) covered[static_cast<std::size_t>(p.source)] += K::measure_of(p);
  if (op.columns == Location::cells) {
    std::vector<double> per_file(src.num_file_cells(), 0.0);
    for (std::size_t c = 0; c < src.num_cells(); ++c) per_file[src.file_cell(c)] += covered[c];
    const std::vector<double> measure = file_cell_measures(src);
    for (std::size_t f = 0; f < per_file.size(); ++f) per_file[f] = measure[f] > 0.0 ? per_file[f] / measure[f] : 0.0;
    op.frac_a = std::move(per_file);
    return;
  }
  const auto& measures = K::measures(src);
  for (std::size_t c = 0; c < covered.size(); ++c) covered[c] = measures[c] > 0.0 ? covered[c] / measures[c] : 0.0;
  op.frac_a = per_vertex(src, covered, false);
}

}  // namespace tetia::app
