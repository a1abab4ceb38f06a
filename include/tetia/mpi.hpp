// tetia/mpi.hpp -- the supermesh, P0 and P1 remap of two tetrahedral meshes distributed over the
// ranks of an MPI communicator, partitioned in any way (library tetia_mpi, CMake target
// tetia::mpi; built where MPI is found).
//
// Contract. Every rank of `comm` calls with its own part of the source and of the target mesh
// (a MeshPart: any subset of each mesh's cells, possibly none, each cell with its global id;
// the parts of one mesh are disjoint and together the whole mesh). The call is collective.
// - supermesh: every piece (source cell, target cell, volume, first moments) whose target cell
//   the rank holds, sorted by (target id, source id). As a set over the ranks, these are the
//   pieces one process computes for the whole meshes (tetia::supermesh): each piece is computed
//   once, by the same kernel on the same coordinates in the same vertex order, so it is equal
//   bit for bit, whatever the partitions and the number of ranks.
// - remap_p0: for each target cell of the rank, in the rank's order, the P0 remap of a source
//   field (`components` values per source cell, given by each rank for its own source cells):
//   sum over pieces of volume * u_S, in source id order, divided by the target cell's volume
//   (cell_volume) or by its covered volume (covered_volume; 0 where nothing covers it). Where
//   the ids are the serial mesh's cell indices this is tetia::remap_p0's arithmetic, bit for bit.
// - remap_p1: for each target node of the rank, the Galerkin projection over the whole meshes,
//   solved over the ranks (see its declaration).
// Communication (src/mpi/distributed_supermesh.cpp has the argument that it misses no piece):
// each rank sends every other rank a few bounding boxes of its target cells (at most
// DistributedOptions::boxes_per_rank, each over cells consecutive along a Morton curve), then
// each source cell (its id, its four vertices, its node ids where given, and for the remaps its
// field values) only to the ranks one of whose boxes meets the cell's bounding box.
// Errors (a MeshPart whose arrays do not agree in size, a node index out of range, non-finite
// coordinates, a field of the wrong size) throw std::invalid_argument on the rank that has
// them; a collective call then stops on every rank together: every rank throws, the others
// with std::runtime_error("tetia: mpi: rank R: <its message>") for the lowest failing rank R.
#pragma once

#include <mpi.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tetia/geometry.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"

namespace tetia::mpi {

/// One rank's part of a distributed tetrahedral mesh, as plain arrays (no copy is kept).
struct MeshPart {
  std::span<const double> coordinates;      ///< 3 per local node, x y z
  std::span<const std::int32_t> cells;      ///< 4 local node indices per local cell
  std::span<const std::int64_t> cell_ids;   ///< the global id of each local cell (unique, >= 0)
  /// The global id of each local node (>= 0; a node in several parts has the same id, and the
  /// same coordinates, in each): needed by remap_p1, which assembles and solves by global node;
  /// optional elsewhere, where they make the receiving ranks faster (where every rank with
  /// source cells gives them, the source cells travel with them and the receiving rank rebuilds
  /// their adjacency: the advancing front search instead of an R-tree over a soup of cells).
  std::span<const std::int64_t> node_ids = {};
};

/// A MeshPart with its own storage: a part cut from a whole mesh (part_of, parts_of).
struct OwnedMeshPart {
  std::vector<double> coordinates;
  std::vector<std::int32_t> cells;
  std::vector<std::int64_t> cell_ids, node_ids;
  MeshPart view() const { return {coordinates, cells, cell_ids, node_ids}; }
};

/// For a rank that holds a whole mesh: part q has the cells c with owner[c] == q (ids: c), with
/// the nodes they use renumbered in order of first use (ids: their indices in the mesh); one
/// pass for all the parts. Throws std::invalid_argument if owner's size is not the number of
/// cells or an owner is not in [0, parts).
std::vector<OwnedMeshPart> parts_of(const TetMesh& mesh, std::span<const int> owner, int parts);

/// A partition into `parts` runs of equal size (to one cell) along a Morton curve through the
/// cell centroids (in the mesh's bounding box): compact regions, as partitioners give.
std::vector<int> morton_partition(const TetMesh& mesh, int parts);

struct DistributedOptions {
  /// Boxes each rank publishes for its target cells (cells cut into this many runs along a
  /// Morton curve through their centroids, one box each): more boxes send fewer donor cells
  /// to ranks whose region is not convex, at P * boxes_per_rank boxes kept on every rank.
  int boxes_per_rank = 64;
  int threads = 0;  ///< OpenMP threads of the local supermesh (0: OpenMP's default)
  /// supermesh(): also return each piece's local mixed mass matrix (DistributedSupermesh::
  /// local_mass), as SupermeshOptions::keep_mixed_mass does.
  bool keep_mixed_mass = false;
};

struct DistributedPiece {
  std::int64_t source = -1, target = -1;  ///< global cell ids
  double volume = 0.0;
  Vec3 first{};  ///< first moments (integral of the position)
};

struct DistributedSupermesh {
  std::vector<DistributedPiece> pieces;  ///< this rank's target cells' pieces, by (target, source)
  /// pieces[k]'s local mixed mass matrix (as Supermesh::local_mass), if keep_mixed_mass
  std::vector<std::array<double, 16>> local_mass;
  std::size_t candidates = 0;            ///< pairs this rank handed to the kernel
  // What this rank exchanged, for the benchmarks (bytes of payload, not MPI's own).
  std::size_t boxes_received = 0;        ///< target boxes of all the ranks (its own included)
  std::size_t cells_sent = 0;            ///< source cells sent (to other ranks; copies counted)
  std::size_t cells_received = 0;        ///< source cells received (its own included)
  std::size_t bytes_sent = 0;            ///< boxes and cells sent to other ranks
  double seconds = 0.0;                  ///< the whole call on this rank
};

DistributedSupermesh supermesh(const MeshPart& source, const MeshPart& target, MPI_Comm comm,
                               const DistributedOptions& options = {});

/// P0 remap for this rank's target cells: `source_values` holds components values per local
/// source cell (row by row), the result components values per local target cell.
std::vector<double> remap_p0(const MeshPart& source, std::span<const double> source_values, const MeshPart& target,
                             MPI_Comm comm, int components = 1,
                             P0Normalization normalization = P0Normalization::cell_volume,
                             const DistributedOptions& options = {}, DistributedSupermesh* pieces = nullptr);

/// Rows of a distributed sparse matrix held by one rank, CSR by global ids: row row_ids[r] has
/// columns column_ids[row_begin[r] .. row_begin[r + 1]) (ascending) with those values.
struct DistributedMatrix {
  std::vector<std::int64_t> row_ids;
  std::vector<std::int64_t> row_begin;
  std::vector<std::int64_t> column_ids;
  std::vector<double> values;
};

/// P1 (Galerkin) remap for this rank's target nodes: M_t u_t = M_ts u_s over the whole meshes.
/// Needs MeshPart::node_ids for both parts. `source_node_values` holds components values per
/// local source node (a node in several parts must have the same values in each), the result
/// components values per local target node. Each target node is owned by the lowest rank whose
/// target part has it; `mixed_mass` (if given) receives M_ts's rows of the nodes this rank owns
/// (columns: source node ids), and `report` the last component's conjugate gradient. The solve
/// is tetia::remap_p1's (Jacobi-preconditioned CG from the lumped solution to a residual of
/// 1e-14), over MPI: src/mpi/distributed_p1.cpp.
std::vector<double> remap_p1(const MeshPart& source, std::span<const double> source_node_values,
                             const MeshPart& target, MPI_Comm comm, int components = 1,
                             const DistributedOptions& options = {}, P1RemapReport* report = nullptr,
                             DistributedMatrix* mixed_mass = nullptr);

}  // namespace tetia::mpi
