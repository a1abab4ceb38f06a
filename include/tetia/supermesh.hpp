// tetia/supermesh.hpp -- the intersection of two tetrahedral meshes, or of two triangular ones.
//
// Contract: supermesh(source, target) returns every pair (source cell, target cell) whose
// intersection has positive volume (area, in 2D), with its volume (area) and first moments,
// sorted by (target, source); on request also the polyhedra (polygons), or each piece's local
// mixed mass matrix (keep_mixed_mass: A[i * (d+1) + j] = integral over the piece of target cell
// basis i times source cell basis j, d the dimension; exact for products of linear functions on
// the piece's simplices; bit for bit what the remap computes from kept polyhedra; 128 B per
// piece in 3D, 72 B in 2D, against 2,216 B (608 B) for a kept polyhedron (polygon): all that P1
// remap and the mixed mass matrix need, for large meshes). "Positive" is above the
// resolution of double arithmetic: pieces of volume (area) at most 1e-14 times the smaller
// cell's volume (area) are dropped (there the kernel cannot tell a sliver from a touching
// contact; such pieces are in practice 1e-30 of a cell or less). Candidates are found by an
// advancing front over facet adjacency (faces of tetrahedra, edges of triangles), seeded per
// connected region by an R-tree query, with an R-tree query for the cells the front cannot
// vouch for (near the target boundary; linear complexity, robust to non-convex domains, holes,
// several components, identical and facet-sharing cells, non-conforming interfaces), or by a
// plain R-tree search; both give the same pieces provided the target cells do not overlap one
// another, as in any mesh (the front walks the target's facet adjacency: several overlapping
// meshes given as one target are searched completely only by the R-tree). Results are
// identical for any number of threads. Out of memory while the threads work (the pieces, and
// what is kept with them, grow as they are found) is std::bad_alloc from supermesh(), as
// elsewhere, not the end of the process. Both dimensions run the same code
// (src/supermesh/supermesh.cpp, a template over the dimension) with their own kernel.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "tetia/mesh.hpp"
#include "tetia/polygon.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia {

enum class CandidateSearch { front, rtree };

struct SupermeshOptions {
  CandidateSearch search = CandidateSearch::front;
  int threads = 0;              ///< 0: OpenMP's default
  bool keep_polyhedra = false;  ///< fill Supermesh::polyhedra (3D) or Supermesh2::polygons (2D)
  bool keep_mixed_mass = false; ///< fill Supermesh::local_mass (3D) or Supermesh2::local_mass (2D)
  /// If set, called with (source cells done, source cells in all) as the work advances: after
  /// each chunk of about 4096 source cells that the calling thread's team finishes, always from
  /// the thread that called supermesh() (OpenMP's master), never concurrently.
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct SupermeshPiece {
  std::int32_t source = -1, target = -1;
  double volume = 0.0;
  Vec3 first{};  ///< first moments (integral of the position)
};

struct Supermesh {
  /// The meshes it was built from, shared: a supermesh keeps them alive (supermesh() given
  /// references copies them; given shared pointers it shares them).
  std::shared_ptr<const TetMesh> source, target;
  std::vector<SupermeshPiece> pieces;  ///< sorted by (target, source)
  std::vector<Polyhedron> polyhedra;   ///< pieces[k]'s polyhedron (U = source cell, V = target cell), if kept
  /// pieces[k]'s local mixed mass matrix, row-major: [4 * i + j] = integral over the piece of
  /// (target cell's basis function i) x (source cell's basis function j), if kept
  std::vector<std::array<double, 16>> local_mass;
  std::size_t candidates = 0;          ///< pairs handed to the kernel (the same for any number of threads)
  double seconds = 0.0;
  double intersection_volume() const;
};

/// The supermesh shares the meshes (no copy): they live as long as it does, and must not be
/// changed meanwhile (they are const through these pointers; whoever holds a non-const one is
/// trusted). Null pointers throw std::invalid_argument.
Supermesh supermesh(std::shared_ptr<const TetMesh> source, std::shared_ptr<const TetMesh> target,
                    const SupermeshOptions& options = {});
/// The same for meshes given by reference: they are copied into the supermesh (about 48 B a
/// cell and 32 B a node in 3D, with tags), so that it cannot outlive them; pass shared pointers
/// to avoid the copy.
Supermesh supermesh(const TetMesh& source, const TetMesh& target, const SupermeshOptions& options = {});

/// One piece of a 2D supermesh: a (source, target) pair of triangles whose intersection has
/// positive area.
struct SupermeshPiece2 {
  std::int32_t source = -1, target = -1;
  double area = 0.0;
  Vec2 first{};  ///< first moments (integral of the position)
};

/// The supermesh of two triangular meshes.
struct Supermesh2 {
  std::shared_ptr<const TriMesh> source, target;  ///< as Supermesh's
  std::vector<SupermeshPiece2> pieces;  ///< sorted by (target, source)
  std::vector<Polygon> polygons;        ///< pieces[k]'s polygon (A = source cell, B = target cell), if kept
  /// pieces[k]'s local mixed mass matrix, row-major: [3 * i + j] = integral over the piece of
  /// (target cell's basis function i) x (source cell's basis function j), if kept
  std::vector<std::array<double, 9>> local_mass;
  std::size_t candidates = 0;           ///< pairs handed to the kernel (the same for any number of threads)
  double seconds = 0.0;
  double intersection_area() const;
};

Supermesh2 supermesh(std::shared_ptr<const TriMesh> source, std::shared_ptr<const TriMesh> target,
                     const SupermeshOptions& options = {});
Supermesh2 supermesh(const TriMesh& source, const TriMesh& target, const SupermeshOptions& options = {});

/// What a supermesh that is not kept does with its pieces: the caller's choice (sum them into a
/// remap's right-hand side, count them, write them), handed each piece as it is computed, so
/// that nothing is stored that the caller does not need. Two phases, so that what the caller
/// sums does not depend on the number of threads:
///  - compute(): while the pieces are found, concurrently on every thread, turns a piece and its
///    polyhedron (polygon; U / A = source cell, V / B = target cell) into values_per_piece()
///    numbers. It must not change shared state. Not called when values_per_piece() is 0, and the
///    polyhedra are then not built. If it throws, the threads stop computing, and supermesh()
///    rethrows the exception of the first thread (in thread order) that had one.
///  - consume(): then every piece with its numbers (null when values_per_piece() is 0), in
///    (target, source) order (the order of Supermesh::pieces, with the same cell indices, volumes
///    and moments bit for bit), on the thread that called supermesh().
/// Held meanwhile: each piece's record (SupermeshPiece: 40 B in 3D, 32 B in 2D), its numbers,
/// and 8 B to order them; never the polyhedra.
template <class Piece, class Shape>
class BasicPieceConsumer {
 public:
  virtual ~BasicPieceConsumer() = default;
  virtual std::size_t values_per_piece() const { return 0; }
  virtual void compute(const Piece& piece, const Shape& shape, double* values) const {
    (void)piece, (void)shape, (void)values;
  }
  virtual void consume(const Piece& piece, const double* values) = 0;
};
using PieceConsumer = BasicPieceConsumer<SupermeshPiece, Polyhedron>;
using PieceConsumer2 = BasicPieceConsumer<SupermeshPiece2, Polygon>;

/// What a supermesh handed to a consumer reports (as Supermesh's members of the same names).
struct SupermeshSummary {
  std::size_t pieces = 0;
  std::size_t candidates = 0;
  double seconds = 0.0;
};

/// The supermesh handed to a consumer instead of kept: the same pieces as supermesh(source,
/// target, options), in its order. options.keep_polyhedra and keep_mixed_mass must be false
/// (std::invalid_argument otherwise): the consumer computes what it keeps.
SupermeshSummary supermesh(const TetMesh& source, const TetMesh& target, PieceConsumer& consumer,
                           const SupermeshOptions& options = {});
SupermeshSummary supermesh(const TriMesh& source, const TriMesh& target, PieceConsumer2& consumer,
                           const SupermeshOptions& options = {});

/// The supermesh per pair of file cells (the cells of the files the meshes came from: a split
/// hexahedron's tetrahedra together, tetia/file_cells.hpp). pairs[i].source and .target are
/// file cell indices (TetMesh::file_cell), .volume and .first the compensated sums over the
/// pieces of that pair, sorted by (target, source); piece_pair[k] is the index in `pairs` of
/// pieces[k]'s pair. Without split cells, pairs are the pieces (summed exactly: one each).
struct FileCellPairs {
  std::vector<SupermeshPiece> pairs;
  std::vector<std::int32_t> piece_pair;
};
FileCellPairs file_cell_pairs(const Supermesh& s);

struct FileCellPairs2 {
  std::vector<SupermeshPiece2> pairs;
  std::vector<std::int32_t> piece_pair;
};
FileCellPairs2 file_cell_pairs(const Supermesh2& s);

}  // namespace tetia
