// tetia/mesh.hpp -- unstructured tetrahedral meshes: nodes, cells, face adjacency, volumes.
//
// Contract: a TetMesh is plain data (nodes and cells as node-index quadruples) plus what
// `finalize` derives from it. `finalize` validates (node indices in range, finite
// coordinates, at least one cell), reorients inverted cells (counted), reports zero-volume
// cells (counted and kept: they intersect nothing), computes cell volumes and the face
// adjacency in linear time. Errors throw std::runtime_error with a message naming the mesh
// and the cell: "tetia: FILE: cell 17: node index 900 out of range".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tetia/geometry.hpp"

namespace tetia {

struct TetMesh {
  std::vector<Vec3> nodes;
  std::vector<std::array<std::int32_t, 4>> cells;  ///< node indices, positively oriented after finalize

  // Derived by finalize():
  std::vector<std::array<std::int32_t, 4>> neighbors;  ///< cell across face k (opposite vertex k), -1 on the boundary
  std::vector<double> volumes;                         ///< cell volumes (>= 0)
  std::size_t reoriented_cells = 0;                    ///< inverted cells that were flipped
  std::size_t flat_cells = 0;                          ///< zero-volume cells (kept)

  std::size_t num_nodes() const { return nodes.size(); }
  std::size_t num_cells() const { return cells.size(); }
  Tet cell(std::size_t c) const {
    const auto& v = cells[c];
    return {nodes[static_cast<std::size_t>(v[0])], nodes[static_cast<std::size_t>(v[1])],
            nodes[static_cast<std::size_t>(v[2])], nodes[static_cast<std::size_t>(v[3])]};
  }
  double total_volume() const;
};

/// Validates and derives adjacency and volumes; `name` is used in error messages (a file name).
void finalize(TetMesh& mesh, const std::string& name = "mesh");

/// A structured mesh of n[0] x n[1] x n[2] cubes, each split into the six Kuhn tetrahedra
/// (all sharing the cube's main diagonal), so faces match across cubes. Finalized.
TetMesh make_kuhn_mesh(std::array<int, 3> n, Vec3 origin, Vec3 cube_size);

}  // namespace tetia
