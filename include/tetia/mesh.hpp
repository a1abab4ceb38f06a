// tetia/mesh.hpp -- unstructured simplicial meshes: tetrahedral (TetMesh) and triangular
// (TriMesh, in the plane): nodes, cells, facet adjacency, cell measures.
//
// Contract: a mesh is plain data (nodes and cells as node-index tuples, optionally the tags they
// had in a file) plus what `finalize` derives from it. `finalize` validates (node indices in
// range, no repeated node in a cell, finite coordinates, at least one cell, no facet in more
// than two cells, tags either absent or one per node / cell, positive and distinct; split
// file cells' origins in range and in order, their types and node lists consistent), reorients
// inverted cells (counted), reports zero-measure cells (counted and kept: they intersect nothing),
// computes cell volumes (areas) and the facet adjacency (faces of tetrahedra, edges of
// triangles) in linear time. Errors throw std::runtime_error with a message naming the mesh and
// the cell: "tetia: FILE: cell 17: node index 900 out of range". Both dimensions share one
// implementation and the same messages, except for the names of cells and facets ("no
// tetrahedra" / "no triangles", "a face" / "an edge shared by more than two cells").
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
  /// The file's node and element tags (read_mesh fills them), one per node / cell; empty means
  /// 1, 2, ... by position. Written back by write_msh and as the VTU's node_id / cell_id.
  std::vector<std::int64_t> node_tags, cell_tags;
  /// Where the file has hexahedra, prisms or pyramids, read_mesh splits them into tetrahedra
  /// (conforming across shared faces, no new nodes: src/mesh/split_cells.hpp): then
  /// cell_origin[c] is the index of cell c's file cell, whose tag is origin_tags[i] and Gmsh
  /// element type origin_types[i] (4, 5, 6 or 7), cell_tags is empty (the tags are the file
  /// cells'), and the file cells are in tag order. origin_nodes holds each file cell's node
  /// indices in Gmsh's order (8, 6, 5 or 4 of them by type, one cell after the other), for
  /// writing the file cells back (write_vtu, write_msh). Empty: every cell is a file cell.
  std::vector<std::int32_t> cell_origin;
  std::vector<std::int64_t> origin_tags;
  std::vector<std::uint8_t> origin_types;
  std::vector<std::int32_t> origin_nodes;

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
  /// The cells of the file: the split ones' origins, else the cells themselves.
  std::size_t num_file_cells() const { return cell_origin.empty() ? cells.size() : origin_tags.size(); }
  std::size_t file_cell(std::size_t c) const { return cell_origin.empty() ? c : static_cast<std::size_t>(cell_origin[c]); }
};

/// A triangular mesh of a planar domain.
struct TriMesh {
  std::vector<Vec2> nodes;
  std::vector<std::array<std::int32_t, 3>> cells;  ///< node indices, counter-clockwise after finalize
  /// As TetMesh's: the file's tags, empty for 1, 2, ...
  std::vector<std::int64_t> node_tags, cell_tags;
  /// As TetMesh's, for quadrilaterals split into two triangles (types 2 and 3).
  std::vector<std::int32_t> cell_origin;
  std::vector<std::int64_t> origin_tags;
  std::vector<std::uint8_t> origin_types;
  std::vector<std::int32_t> origin_nodes;

  // Derived by finalize():
  std::vector<std::array<std::int32_t, 3>> neighbors;  ///< cell across edge k (opposite vertex k), -1 on the boundary
  std::vector<double> areas;                           ///< cell areas (>= 0)
  std::size_t reoriented_cells = 0;                    ///< clockwise cells that were flipped
  std::size_t flat_cells = 0;                          ///< zero-area cells (kept)

  std::size_t num_nodes() const { return nodes.size(); }
  std::size_t num_cells() const { return cells.size(); }
  Triangle cell(std::size_t c) const {
    const auto& v = cells[c];
    return {nodes[static_cast<std::size_t>(v[0])], nodes[static_cast<std::size_t>(v[1])],
            nodes[static_cast<std::size_t>(v[2])]};
  }
  double total_area() const;
  std::size_t num_file_cells() const { return cell_origin.empty() ? cells.size() : origin_tags.size(); }
  std::size_t file_cell(std::size_t c) const { return cell_origin.empty() ? c : static_cast<std::size_t>(cell_origin[c]); }
};

/// Validates and derives adjacency and volumes; `name` is used in error messages (a file name).
void finalize(TetMesh& mesh, const std::string& name = "mesh");
/// The same for triangles: areas, edge adjacency, clockwise cells made counter-clockwise.
void finalize(TriMesh& mesh, const std::string& name = "mesh");

/// Gmsh's number of corner nodes of its element types 2-7 (triangle, quadrilateral,
/// tetrahedron, hexahedron, prism, pyramid); 0 for any other type.
constexpr int file_cell_nodes(int gmsh_type) {
  constexpr int n[8] = {0, 0, 3, 4, 4, 8, 6, 5};
  return gmsh_type >= 2 && gmsh_type <= 7 ? n[gmsh_type] : 0;
}

/// A structured mesh of n[0] x n[1] x n[2] cubes, each split into the six Kuhn tetrahedra
/// (all sharing the cube's main diagonal), so faces match across cubes. Finalized.
TetMesh make_kuhn_mesh(std::array<int, 3> n, Vec3 origin, Vec3 cube_size);

/// A structured mesh of n[0] x n[1] rectangles, each split into two triangles along its
/// diagonal from (0, 0) to (1, 1) (the 2D Kuhn split), so edges match across rectangles.
/// Counter-clockwise, finalized.
TriMesh make_structured_tri_mesh(std::array<int, 2> n, Vec2 origin, Vec2 cell_size);

}  // namespace tetia
