// tetia/mesh_from_arrays.hpp -- a mesh from arrays of coordinates and of cells of any of the
// types the file layer reads (what the Python package's tetia.Mesh(points, cells) calls).
//
// Contract. `coordinates` holds num_nodes x coordinate_dim values, row by row (3 for a
// tetrahedral mesh; 2 or 3 for a triangular one, whose z must then be one value for all the
// nodes its cells use, within 1e-12 of the mesh's size, as read_tri_mesh requires; z is
// dropped). Each CellBlock gives cells of one Gmsh element type (mesh.hpp's file_cell_nodes:
// 4 tetrahedron, 5 hexahedron, 6 prism, 7 pyramid in 3D; 2 triangle, 3 quadrilateral in 2D),
// file_cell_nodes(type) node indices (0-based) per cell, cell after cell, in Gmsh's node order.
// The file cells are the blocks' cells in the order given (block after block), and every result
// per file cell (tetia/file_cells.hpp) is in that order; nodes keep their order. Cells other than
// simplices are split as the reader splits them (src/mesh/split_cells.hpp, node index + 1
// taking the place of the file's node tag), collapsed ones (a node twice) by their pieces with
// volume. The mesh is finalized (inverted cells reoriented). Errors throw std::invalid_argument
// "tetia: NAME: ..." naming the cell (its index among the file cells) or the array: a type of
// the other dimension or unknown, a node index out of range, a block whose size is not a
// multiple of its type's node count, no cells, a cell whose repeated nodes leave it no volume,
// non-finite coordinates; and, as std::runtime_error, what finalize checks and the plane check
// of read_tri_mesh (the same code, src/io/mesh_assembly.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "tetia/mesh.hpp"

namespace tetia {

struct CellBlock {
  int type = 4;                         ///< Gmsh element type
  std::span<const std::int64_t> nodes;  ///< file_cell_nodes(type) indices per cell
};

TetMesh make_tet_mesh(std::span<const double> coordinates, std::span<const CellBlock> blocks,
                      const std::string& name = "mesh");
TriMesh make_tri_mesh(std::span<const double> coordinates, int coordinate_dim, std::span<const CellBlock> blocks,
                      const std::string& name = "mesh");

}  // namespace tetia
