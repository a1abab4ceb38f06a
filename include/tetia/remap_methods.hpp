// tetia/remap_methods.hpp -- conservative remap methods beyond Galerkin P0 and P1
// (tetia/remap.hpp): lumped and bounded P1, discontinuous P1, and second-order cell averages by
// a limited linear reconstruction. All of them on the exact supermesh, for tetrahedral
// (Supermesh) and triangular (Supermesh2) meshes alike; read area for volume in 2D.
//
// Conventions shared with tetia/remap.hpp: the source field counts as zero outside the source
// domain (the target integral equals the source integral over the overlap, whatever the
// coverage); results are per target node (continuous P1), per target cell (P0), or per target
// cell and vertex, in the order of the cell's nodes (discontinuous P1: nv = d + 1 values a cell,
// row-major). Every function needs the supermesh's local mixed mass matrices
// (SupermeshOptions::keep_mixed_mass, or keep_polyhedra) except remap_p0_linear, which uses only
// the pieces' volumes and first moments. Sizes that do not match throw std::invalid_argument.
//
// - remap_p1_lumped: u_i = (M_ts u_s)_i / m_i, m_i = sum_j (M_t)_ij the lumped target mass (the
//   integral of basis function i). First order. Each u_i is an average of the source field over
//   the support of basis function i weighted by that function (zero where the source does not
//   cover it), so it lies within the local bounds below: exactly, the quotient being clamped to
//   them (which moves it by its rounding only); sum_i m_i u_i = sum_i (M_ts u_s)_i, the source
//   integral over the overlap, to rounding.
// - p1_local_bounds: per target node i, the least and largest source nodal value on the source
//   cells that overlap the support of basis function i (the target cells around node i); 0 is
//   included where that support is not fully covered (the field is zero outside the source), and
//   both bounds are 0 where nothing covers it.
// - remap_p1_bounded: the Galerkin solution (remap_p1) corrected by clip-and-assured-sum (CAAS,
//   Bradley, Bosler and Guba 2019): each nodal value clipped to its local bounds, then the mass
//   the clipping moved, Q - sum_i m_i c_i with Q = sum_i (M_ts u_s)_i, given back to the nodes in
//   proportion to m_i times their room to the bound on the side that receives it. Why CAAS: it
//   is one pass with no iteration, is always feasible here (the lumped solution is within the
//   bounds and carries Q to rounding), and where no value leaves its bounds it moves the
//   Galerkin solution only by the solve's residual mass, so that linear fields (within their
//   bounds up to the solver's rounding) are reproduced where the domains coincide. Where values
//   are clipped, the mass goes to every node with room, in bounds or not.
//   Every value is within its local bounds exactly (not to rounding: a step stays in [0, 1]).
//   Conservation is exact to rounding, better than the Galerkin solve's tolerance, since Q itself
//   is the target.
// - remap_p1_discontinuous: the L2 projection onto discontinuous P1 on the target, per cell: the
//   cell's consistent mass matrix |T| / ((d + 1)(d + 2)) (I + J) has the closed-form inverse
//   (d + 1)(d + 2) / |T| (I - J / (d + 2)), so u_T = (d + 1)(d + 2) / |T| (b_T - sum(b_T) / (d + 2))
//   with b_T the cell's loads; no global solve. Exact for linear fields on fully covered cells;
//   conserves per target cell. The source is continuous P1 (one value per source node) or
//   discontinuous P1 (nv values per source cell: P1Source::discontinuous).
// - remap_p0_from_discontinuous: cell averages (P0) on the target from a discontinuous P1 source:
//   u_T = sum over pieces of the integral of the source's linear function on the piece, / |T|
//   (or / the covered volume, as remap_p0's normalization).
// - remap_p0_linear: second-order conservative remap of cell averages. Per source cell, a
//   gradient by least squares over its face neighbours' averages (centroid differences as the
//   directions), limited by Barth and Jespersen: scaled by the largest factor in [0, 1] for which
//   the reconstruction at the cell's vertices stays within the least and largest average of the
//   cell and its vertex neighbours (the cells sharing a vertex with it: an interior vertex lies
//   among their centroids, so linear fields are not clipped there; they are also the gradient's
//   stencil where the face neighbours do not span the space). Each piece then carries the
//   integral of the reconstruction, u_S |P| + g_S . (first moments of P - c_S |P|), exactly (c_S the source cell's centroid), so
//   the source cell's own integral is unchanged (conservative) and the target averages are
//   weighted averages of bounded linear functions (bounded by the neighbourhoods' averages).
//   A cell whose neighbours do not span the space (an isolated cell), or whose gradient is not
//   finite (coordinates near the overflow threshold), keeps a zero gradient: first order there.
//   `groups`, if given, names each simplex's group (for instance its file cell,
//   TetMesh::cell_origin): the reconstruction is then per group (one average, one gradient, the
//   group's centroid; neighbours are groups sharing a face), and the values are given per
//   simplex, equal within a group.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace tetia {

enum class P1Source { continuous, discontinuous };

struct P1Bounds {
  std::vector<double> lower, upper;  ///< per target node
};

std::vector<double> remap_p1_lumped(const Supermesh& s, std::span<const double> source_node_values);
P1Bounds p1_local_bounds(const Supermesh& s, std::span<const double> source_node_values);
std::vector<double> remap_p1_bounded(const Supermesh& s, std::span<const double> source_node_values,
                                     P1RemapReport* report = nullptr);
std::vector<double> remap_p1_discontinuous(const Supermesh& s, std::span<const double> source_values,
                                           P1Source source = P1Source::continuous);
std::vector<double> remap_p0_from_discontinuous(const Supermesh& s, std::span<const double> source_cell_node_values,
                                                P0Normalization normalization = P0Normalization::cell_volume);
std::vector<double> remap_p0_linear(const Supermesh& s, std::span<const double> source_cell_values,
                                    P0Normalization normalization = P0Normalization::cell_volume,
                                    std::span<const std::int32_t> groups = {});

std::vector<double> remap_p1_lumped(const Supermesh2& s, std::span<const double> source_node_values);
P1Bounds p1_local_bounds(const Supermesh2& s, std::span<const double> source_node_values);
std::vector<double> remap_p1_bounded(const Supermesh2& s, std::span<const double> source_node_values,
                                     P1RemapReport* report = nullptr);
std::vector<double> remap_p1_discontinuous(const Supermesh2& s, std::span<const double> source_values,
                                           P1Source source = P1Source::continuous);
std::vector<double> remap_p0_from_discontinuous(const Supermesh2& s, std::span<const double> source_cell_node_values,
                                                P0Normalization normalization = P0Normalization::cell_volume);
std::vector<double> remap_p0_linear(const Supermesh2& s, std::span<const double> source_cell_values,
                                    P0Normalization normalization = P0Normalization::cell_volume,
                                    std::span<const std::int32_t> groups = {});

/// The linear methods as sparse operators W (Eigen row-major CSR; rows: the result's values,
/// columns: the field's), so that W u is the remap of u, and W can be kept, saved and applied
/// without the supermesh. Each is its function above in exact arithmetic and to rounding in
/// floating point (the products are summed in another order; the lumped operator's values are
/// not clamped to the bounds, so they hold to rounding). Assembled in the pieces' (target,
/// source) order: the same for any number of threads. Rows of target cells that have nothing
/// to divide by (zero measure, or zero covered measure) are empty.
/// - p0_operator: rows target cells, columns source cells: |S cap T| / d_T (remap_p0); needs only
///   the pieces.
/// - p0_from_discontinuous_operator: rows target cells, columns source cell-vertices (cell c's
///   vertex k at c (d + 1) + k): each piece's integral of the source cell's barycentric
///   coordinate k, / d_T (remap_p0_from_discontinuous).
/// - p1_lumped_operator: rows target nodes, columns source nodes: (M_ts)_ij / m_i (remap_p1_lumped).
/// - p1_discontinuous_operator: rows target cell-vertices, columns source nodes (or source
///   cell-vertices: P1Source::discontinuous): the cell's inverse mass matrix times its rows of
///   the mixed mass matrix (remap_p1_discontinuous).
/// The Galerkin and bounded P1 and the limited reconstruction have none: M_t^-1 M_ts is dense,
/// and the limiters depend on the field.
SparseMatrix p0_operator(const Supermesh& s, P0Normalization normalization = P0Normalization::cell_volume);
SparseMatrix p0_operator(const Supermesh2& s, P0Normalization normalization = P0Normalization::cell_volume);
SparseMatrix p0_from_discontinuous_operator(const Supermesh& s,
                                            P0Normalization normalization = P0Normalization::cell_volume);
SparseMatrix p0_from_discontinuous_operator(const Supermesh2& s,
                                            P0Normalization normalization = P0Normalization::cell_volume);
SparseMatrix p1_lumped_operator(const Supermesh& s);
SparseMatrix p1_lumped_operator(const Supermesh2& s);
SparseMatrix p1_discontinuous_operator(const Supermesh& s, P1Source source = P1Source::continuous);
SparseMatrix p1_discontinuous_operator(const Supermesh2& s, P1Source source = P1Source::continuous);

/// W u, each row summed from 0 in the order of its entries (columns ascending): how
/// BasicRemap applies its operators and `tetia apply` a saved one, which therefore agree bit for
/// bit. u has W.cols() values (std::invalid_argument otherwise).
std::vector<double> apply_operator(const SparseMatrix& w, std::span<const double> u);

/// Coverage. cell_coverage: per target cell, the fraction of its measure that the source covers
/// (sum of its pieces' measures over its own; 0 for a cell of zero measure; needs only the
/// pieces). p1_node_coverage: per target node, the fraction of its basis function's integral
/// that the source covers, (M_ts 1)_i / m_i with m_i the lumped mass (0 for a node in no cell);
/// from a supermesh that kept the local mixed mass matrices, or from the covered integrals
/// M_ts 1 themselves (the loads of a field of ones, tetia::P1Loads, give them bit for bit).
/// Both are 1 to rounding where the source covers the cell or the support, and may exceed 1
/// only by rounding (or where source cells overlap each other).
std::vector<double> cell_coverage(const Supermesh& s);
std::vector<double> cell_coverage(const Supermesh2& s);
std::vector<double> p1_node_coverage(const Supermesh& s);
std::vector<double> p1_node_coverage(const Supermesh2& s);
std::vector<double> p1_node_coverage(const TetMesh& target, std::span<const double> covered_integrals);
std::vector<double> p1_node_coverage(const TriMesh& target, std::span<const double> covered_integrals);
/// The same per target cell from each cell's covered measure (the sum of its pieces' measures,
/// in piece order, as a PieceConsumer sees them: bit for bit cell_coverage of a kept supermesh).
std::vector<double> cell_coverage(const TetMesh& target, std::span<const double> covered_measures);
std::vector<double> cell_coverage(const TriMesh& target, std::span<const double> covered_measures);
/// Per node, the integral of its basis function: sum over its cells of |T| / (d + 1) (the lumped
/// mass; p1_node_coverage's denominator).
std::vector<double> lumped_mass(const TetMesh& mesh);
std::vector<double> lumped_mass(const TriMesh& mesh);

/// Helpers for discontinuous P1 fields: the values of a continuous one per cell and vertex, and
/// the integral of a discontinuous one (sum over cells of |T| / nv times its nv values).
std::vector<double> discontinuous_from_nodes(const TetMesh& mesh, std::span<const double> node_values);
std::vector<double> discontinuous_from_nodes(const TriMesh& mesh, std::span<const double> node_values);
double integral_discontinuous(const TetMesh& mesh, std::span<const double> cell_node_values);
double integral_discontinuous(const TriMesh& mesh, std::span<const double> cell_node_values);
/// L2 norm of (field - f) for a discontinuous P1 field, by l2_error_p1's quadrature rule.
double l2_error_discontinuous(const TetMesh& mesh, std::span<const double> cell_node_values,
                              const std::function<double(Vec3)>& f);
double l2_error_discontinuous(const TriMesh& mesh, std::span<const double> cell_node_values,
                              const std::function<double(Vec2)>& f);

}  // namespace tetia
