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
//   covered measure sum_S |S cap T| (covered_volume; 0 where nothing covers it). apply() is
//   matrix() times the field, each row summed by apply_operator (tetia/remap_methods.hpp); it
//   equals remap_p0 to rounding (which sums the pieces' |P| u_S and then divides).
// - order 1 (P1): one value per node, in and out: the Galerkin projection M_t u_t = M_ts u_s,
//   bit for bit what remap_p1 returns (the same assembly and solver, src/remap/assembly.hpp).
// Fields with k components are given and returned as rows of k values (row-major, n x k); each
// component is remapped on its own. The matrices, in memory (Eigen sparse, row-major CSR):
// - matrix(): the operator of order 0 itself, diag(1 / d_T) M (M below): apply(u) is
//   apply_operator(matrix(), u), bit for bit. Order 1 has no sparse operator (M_t^-1 M_ts is
//   dense): it throws std::logic_error, saying so; use mixed_mass() and target_mass().
// - mixed_mass(): M, rows target, columns source: the file-cell pair measures |S cap T| for
//   order 0, the mixed mass matrix M_ts (mixed_mass_matrix) for order 1.
// - target_mass(): diagonal d_T for order 0; the consistent mass matrix M_t (mass_matrix) for
//   order 1.
// coverage(): per target file cell, the fraction of its measure that the source covers (sum of
// its pairs' measures over its own measure; 0 for a cell of zero measure); node_coverage(): per
// target node, that of its basis function (p1_node_coverage; order 1 with a continuous result).
// Errors (sizes that do not match, an order other than 0 or 1, a method the order does not
// have, null meshes) throw std::invalid_argument.
//
// Methods (RemapOptions::method; tetia/remap_methods.hpp says what each computes):
// - standard: P0 or Galerkin P1, as above.
// - lumped (order 1), discontinuous (order 1: discontinuous P1 on the target, rows() = target
//   simplices x (d + 1), the values per simplex and vertex; order 0: cell averages from a
//   discontinuous source, cols() = source simplices x (d + 1)): linear, so apply() is matrix()
//   times the field, summed by apply_operator (each row in the order of its entries), which is
//   what `tetia remap` computes and `tetia apply` gives back from a saved operator, bit for bit.
//   matrix() is W with the rows and columns above; where the result is per cell (order 0), a
//   target file cell's row is the measure-weighted average of its simplices' rows. The
//   normalization applies to order 0 and to lumped (a row divided by the covered fraction).
// - bounded (order 1): remap_p1_bounded per component; linear_reconstruction (order 0):
//   remap_p0_linear per component, reconstructed per source file cell, its averages taken to
//   the target's file cells and renormalized as P0. Both depend on the field: no matrix().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include "tetia/remap.hpp"
#include "tetia/remap_methods.hpp"
#include "tetia/supermesh.hpp"

namespace tetia {

enum class RemapMethod { standard, lumped, bounded, discontinuous, linear_reconstruction };

struct RemapOptions {
  int order = 0;  ///< 0: cell averages (P0), 1: nodal values (P1)
  RemapMethod method = RemapMethod::standard;
  P0Normalization normalization = P0Normalization::cell_volume;  ///< order 0, and lumped
  /// The supermesh's search, threads and progress; what it keeps is set by the operator (the
  /// local mixed mass matrices for order 1 and the discontinuous methods, nothing else).
  SupermeshOptions supermesh;
};

template <class Mesh>
class BasicRemap {
 public:
  using Result = std::conditional_t<std::is_same_v<Mesh, TetMesh>, Supermesh, Supermesh2>;

  BasicRemap(std::shared_ptr<const Mesh> source, std::shared_ptr<const Mesh> target, const RemapOptions& options = {});
  /// From a supermesh already built (for order 1 and the discontinuous methods it must have
  /// kept the local mixed mass matrices or the shapes, as remap_p1 needs).
  BasicRemap(Result supermesh, int order, P0Normalization normalization = P0Normalization::cell_volume,
             RemapMethod method = RemapMethod::standard);

  int order() const { return order_; }
  RemapMethod method() const { return method_; }
  /// Values a field has per component: target (rows) and source (columns) file cells, nodes,
  /// or simplices' vertices (the discontinuous methods).
  std::size_t rows() const;
  std::size_t cols() const;

  /// The field remapped: `field` holds cols() x components values (row-major), the result
  /// rows() x components. For order 1, `report` (if given) receives the last component's solve.
  std::vector<double> apply(std::span<const double> field, int components = 1, P1RemapReport* report = nullptr) const;

  SparseMatrix matrix() const;
  SparseMatrix mixed_mass() const;
  SparseMatrix target_mass() const;
  std::vector<double> coverage() const;
  std::vector<double> node_coverage() const;

  const Result& supermesh() const { return supermesh_; }
  const std::shared_ptr<const Mesh>& source() const { return supermesh_.source; }
  const std::shared_ptr<const Mesh>& target() const { return supermesh_.target; }

 private:
  void prepare(P0Normalization normalization);
  std::vector<double> apply_component(std::span<const double> column, P1RemapReport* report) const;

  Result supermesh_;
  int order_ = 0;
  RemapMethod method_ = RemapMethod::standard;
  P0Normalization normalization_ = P0Normalization::cell_volume;
  // The linear methods' W on file cells (lumped, discontinuous).
  SparseMatrix operator_;
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
