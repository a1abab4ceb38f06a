// tetia/remap_operator.hpp -- a conservative remap built once and applied to many fields:
// tetia::Remap (tetrahedral meshes) and tetia::Remap2 (triangular ones).
//
// Contract. Building one computes the supermesh of the two meshes (shared with it, so the
// operator keeps them alive) and what every application needs; apply() then costs a pass over
// the pieces (P0) or that and one conjugate gradient solve per component (P1), and is const and
// safe to call from several threads at once.
// - order 0 (P0): one value per file cell (tetia/file_cells.hpp: a hexahedron, prism, pyramid or
//   quadrilateral of the mesh's file is one cell, as are its simplices), in and out. The result
//   is the L2 projection onto constants per target file cell: u_T = sum over overlapping source
//   file cells S of |S cap T| u_S / d_T, with d_T the target file cell's measure
//   (P0Normalization::cell_volume: the source field counts as zero outside its domain) or its
//   covered measure sum_S |S cap T| (covered_volume; 0 where nothing covers it). Where no cell
//   is split, the pairs are the supermesh's pieces and apply() returns what remap_p0 returns,
//   bit for bit.
// - order 1 (P1): one value per node, in and out: the Galerkin projection M_t u_t = M_ts u_s,
//   bit for bit what remap_p1 returns (the same assembly and solver, src/remap/assembly.hpp).
// Fields with k components are given and returned as rows of k values (row-major, n x k); each
// component is remapped on its own. The matrices, in memory (Eigen sparse, row-major CSR):
// - matrix(): the operator of order 0 itself, diag(1 / d_T) M (M below), so matrix() * u equals
//   apply(u) to rounding. Order 1 has no sparse operator (M_t^-1 M_ts is dense): it throws
//   std::logic_error, saying so; use mixed_mass() and target_mass().
// - mixed_mass(): M, rows target, columns source: the file-cell pair measures |S cap T| for
//   order 0, the mixed mass matrix M_ts (mixed_mass_matrix) for order 1.
// - target_mass(): diagonal d_T for order 0; the consistent mass matrix M_t (mass_matrix) for
//   order 1.
// coverage(): per target file cell, the fraction of its measure that the source covers (sum of
// its pairs' measures over its own measure; 0 for a cell of zero measure). Errors (sizes that
// do not match, an order other than 0 or 1, null meshes) throw std::invalid_argument.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace tetia {

struct RemapOptions {
  int order = 0;  ///< 0: cell averages (P0), 1: nodal values (P1)
  P0Normalization normalization = P0Normalization::cell_volume;  ///< order 0 only
  /// The supermesh's search, threads and progress; what it keeps is set by the operator (the
  /// local mixed mass matrices for order 1, nothing for order 0).
  SupermeshOptions supermesh;
};

template <class Mesh>
class BasicRemap {
 public:
  using Result = std::conditional_t<std::is_same_v<Mesh, TetMesh>, Supermesh, Supermesh2>;

  BasicRemap(std::shared_ptr<const Mesh> source, std::shared_ptr<const Mesh> target, const RemapOptions& options = {});
  /// From a supermesh already built (for order 1 it must have kept the local mixed mass
  /// matrices or the shapes, as remap_p1 needs).
  BasicRemap(Result supermesh, int order, P0Normalization normalization = P0Normalization::cell_volume);

  int order() const { return order_; }
  /// Values a field has per component: target (rows) and source (columns) file cells or nodes.
  std::size_t rows() const;
  std::size_t cols() const;

  /// The field remapped: `field` holds cols() x components values (row-major), the result
  /// rows() x components. For order 1, `report` (if given) receives the last component's solve.
  std::vector<double> apply(std::span<const double> field, int components = 1, P1RemapReport* report = nullptr) const;

  SparseMatrix matrix() const;
  SparseMatrix mixed_mass() const;
  SparseMatrix target_mass() const;
  std::vector<double> coverage() const;

  const Result& supermesh() const { return supermesh_; }
  const std::shared_ptr<const Mesh>& source() const { return supermesh_.source; }
  const std::shared_ptr<const Mesh>& target() const { return supermesh_.target; }

 private:
  void prepare(P0Normalization normalization);

  Result supermesh_;
  int order_ = 0;
  // Order 0: the pairs of file cells (target, source, measure), sorted by target, and each
  // target file cell's denominator d_T.
  std::vector<std::int32_t> pair_target_, pair_source_;
  std::vector<double> pair_measure_, denominator_;
  // Order 1: the target's mass matrix as the solver takes it (column-major, unit diagonal for a
  // node in no cell: src/remap/assembly.hpp).
  Eigen::SparseMatrix<double> solver_mass_;
};

using Remap = BasicRemap<TetMesh>;
using Remap2 = BasicRemap<TriMesh>;

extern template class BasicRemap<TetMesh>;
extern template class BasicRemap<TriMesh>;

}  // namespace tetia
