// tetia/remap.hpp -- conservative transfer of fields between meshes on a supermesh, for
// tetrahedral (Supermesh of TetMesh) and triangular (Supermesh2 of TriMesh) meshes alike.
//
// Contract: P0 (cell averages) is the L2 projection onto piecewise constants: target value =
// sum over pieces of (source value * piece volume) / target cell volume; it conserves the
// integral over the overlap and reproduces constants exactly where the target is covered.
// Target cells only partly covered by the source domain: by default (cell_volume) the source
// field counts as zero outside its domain, so the value is the covered fraction times the
// covered average, and sum(u_t |t|) equals the source integral over the overlap to rounding.
// P0Normalization::covered_volume divides by the covered volume (sum of the cell's piece
// volumes) instead: constants are reproduced on every cell the source touches, and the
// integral over the overlap, sum(u_t covered_t), is conserved; cells not covered at all get 0.
// P1 (continuous, nodal) is the Galerkin L2 projection: M_t u_t = M_ts u_s with M_t the target
// mass matrix and M_ts the mixed mass matrix assembled exactly on the supermesh (products of
// linear functions integrated exactly on a tetrahedralization of each piece), solved by
// conjugate gradients. It needs the supermesh built with keep_mixed_mass (the pieces' local
// mixed mass matrices, used when present) or keep_polyhedra (the matrices computed here from
// the polyhedra); both give the same results bit for bit. M_t is the full
// (consistent) target mass matrix, so the source field again counts as zero outside its domain:
// the integral over the target equals the source integral over the overlap (to the solver
// tolerance) whatever the coverage, and where the domains coincide linear fields are reproduced;
// near the edge of a partial overlap the projection falls off towards zero.
// In 2D read area for volume and polygon (triangulated by a fan) for polyhedron; the two
// dimensions share one implementation (src/remap.cpp, templates over the dimension).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <filesystem>
#include <functional>
#include <span>
#include <vector>

#include "tetia/supermesh.hpp"

namespace tetia {

/// Sparse matrices handed out in memory: Eigen's, compressed by rows (CSR, as SciPy's
/// csr_matrix; outerIndexPtr / innerIndexPtr / valuePtr give the three arrays).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

enum class P0Normalization { cell_volume, covered_volume };

std::vector<double> remap_p0(const Supermesh& s, std::span<const double> source_cell_values,
                             P0Normalization normalization = P0Normalization::cell_volume);

/// Per target cell, the volume the source mesh covers (the sum of its pieces' volumes).
std::vector<double> covered_volumes(const Supermesh& s);

struct P1RemapReport {
  int iterations = 0;
  double residual = 0.0;
};

std::vector<double> remap_p1(const Supermesh& s, std::span<const double> source_node_values,
                             P1RemapReport* report = nullptr);

/// P1 remap without keeping the supermesh, for large meshes: the loads M_ts u_s of several
/// source fields summed by a PieceConsumer (supermesh(source, target, loads, options)). Each
/// piece's local mixed mass matrix (the one keep_mixed_mass keeps) is applied to every field's
/// values at its source cell's nodes while the piece is found, and only those d + 1 numbers per
/// field wait for the sums, which are formed in (target, source) order: bit for bit the loads
/// remap_p1 sums from a kept supermesh, in (d + 1) * 8 B per piece and field instead of the
/// matrix's (d + 1)^2 * 8 B and the kept pieces. The meshes and the fields' values must outlive
/// it; every field has one value per source node (std::invalid_argument otherwise).
template <class Mesh, class Piece, class Shape>
class BasicP1Loads : public BasicPieceConsumer<Piece, Shape> {
 public:
  BasicP1Loads(const Mesh& source, const Mesh& target, std::vector<std::span<const double>> fields);
  std::size_t values_per_piece() const override;
  void compute(const Piece& piece, const Shape& shape, double* values) const override;
  void consume(const Piece& piece, const double* values) override;
  /// Per field, M_ts u_s: one value per target node.
  const std::vector<Eigen::VectorXd>& loads() const { return loads_; }

 private:
  const Mesh& source_;
  const Mesh& target_;
  std::vector<std::span<const double>> fields_;
  std::vector<Eigen::VectorXd> loads_;
};
using P1Loads = BasicP1Loads<TetMesh, SupermeshPiece, Polyhedron>;
using P1Loads2 = BasicP1Loads<TriMesh, SupermeshPiece2, Polygon>;

/// The end of P1 remap: solves M_t u_t = load (one value per target node) as remap_p1 does.
std::vector<double> solve_p1(const TetMesh& target, const Eigen::VectorXd& load, P1RemapReport* report = nullptr);
std::vector<double> solve_p1(const TriMesh& target, const Eigen::VectorXd& load, P1RemapReport* report = nullptr);

/// Both: P1 remap of each field (one value per source node) straight from the meshes, bit for
/// bit remap_p1(supermesh(source, target, {keep_mixed_mass}), field) for each. options as for
/// supermesh() (keep_polyhedra and keep_mixed_mass false); reports, if given, one per field.
std::vector<std::vector<double>> remap_p1(const TetMesh& source, const TetMesh& target,
                                          std::span<const std::vector<double>> fields, const SupermeshOptions& options = {},
                                          std::vector<P1RemapReport>* reports = nullptr);
std::vector<std::vector<double>> remap_p1(const TriMesh& source, const TriMesh& target,
                                          std::span<const std::vector<double>> fields, const SupermeshOptions& options = {},
                                          std::vector<P1RemapReport>* reports = nullptr);

/// The mixed mass (coupling) matrix M_ts (rows: target nodes, columns: source nodes) in Matrix
/// Market coordinate format. Needs keep_mixed_mass or keep_polyhedra, as remap_p1.
void write_mixed_mass_matrix(const Supermesh& s, const std::filesystem::path& file);

/// The same M_ts in memory (what remap_p1 applies and write_mixed_mass_matrix writes: the same
/// sums in the same order), and a mesh's consistent P1 mass matrix M_t (entry (i, j): the
/// integral of basis function i times basis function j; the row of a node in no cell is empty).
/// remap_p1 solves M_t u_t = M_ts u_s; each row sum of M_ts is the target basis function's
/// integral over the overlap, so it equals M_t's row sum (the lumped mass) where the source
/// covers that basis function's support.
SparseMatrix mixed_mass_matrix(const Supermesh& s);
SparseMatrix mass_matrix(const TetMesh& mesh);

/// Integrals of a piecewise constant (per cell) and a continuous piecewise linear (per node) field.
double integral_p0(const TetMesh& mesh, std::span<const double> cell_values);
double integral_p1(const TetMesh& mesh, std::span<const double> node_values);

/// Cell averages of f, by a 64-point conical product Gauss rule per cell (exact for degree 5).
std::vector<double> average_over_cells(const TetMesh& mesh, const std::function<double(Vec3)>& f);

/// L2 norm of (field - f) over the mesh, by the same rule.
double l2_error_p0(const TetMesh& mesh, std::span<const double> cell_values,
                   const std::function<double(Vec3)>& f);
double l2_error_p1(const TetMesh& mesh, std::span<const double> node_values,
                   const std::function<double(Vec3)>& f);

// ---------------------------------------------------------------------------------------------
// The same for triangular meshes (2D): areas instead of volumes, a 16-point conical product
// Gauss rule per triangle (exact for degree 6) instead of the 64-point one.

std::vector<double> remap_p0(const Supermesh2& s, std::span<const double> source_cell_values,
                             P0Normalization normalization = P0Normalization::cell_volume);

/// Per target cell, the area the source mesh covers (the sum of its pieces' areas).
std::vector<double> covered_areas(const Supermesh2& s);

/// Needs the supermesh built with keep_mixed_mass or keep_polyhedra (the polygons).
std::vector<double> remap_p1(const Supermesh2& s, std::span<const double> source_node_values,
                             P1RemapReport* report = nullptr);

void write_mixed_mass_matrix(const Supermesh2& s, const std::filesystem::path& file);

SparseMatrix mixed_mass_matrix(const Supermesh2& s);
SparseMatrix mass_matrix(const TriMesh& mesh);

double integral_p0(const TriMesh& mesh, std::span<const double> cell_values);
double integral_p1(const TriMesh& mesh, std::span<const double> node_values);

std::vector<double> average_over_cells(const TriMesh& mesh, const std::function<double(Vec2)>& f);

double l2_error_p0(const TriMesh& mesh, std::span<const double> cell_values, const std::function<double(Vec2)>& f);
double l2_error_p1(const TriMesh& mesh, std::span<const double> node_values, const std::function<double(Vec2)>& f);

}  // namespace tetia
