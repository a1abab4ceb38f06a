// src/mesh/check_file_cells.hpp -- whether a mesh's split file cells (TetMesh::cell_origin,
// origin_types, origin_nodes) are consistent: what finalize requires and what the writers need
// before they write the file cells back. Internal to the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "mesh_dim.hpp"
#include "tetia/mesh.hpp"

namespace tetia::detail {

/// Empty if the mesh has no split cells or they are consistent: one origin per cell, in range
/// and in order (the cells of a file cell follow one another), one type per file cell tag, each
/// type a cell of the mesh's dimension, and as many node indices, in range, as the types say.
/// Otherwise what is wrong, for an error message. Tags themselves are finalize's to check.
template <class Mesh>
std::string file_cells_problem(const Mesh& m) {
  if (m.cell_origin.empty() && m.origin_tags.empty() && m.origin_types.empty()) return "";
  if (m.cell_origin.size() != m.cells.size() || m.origin_types.size() != m.origin_tags.size() || !m.cell_tags.empty())
    return "cell origins: " + std::to_string(m.cell_origin.size()) + " for " + std::to_string(m.cells.size()) +
           " cells, " + std::to_string(m.origin_tags.size()) + " file cell tags and " +
           std::to_string(m.origin_types.size()) + " types (cell tags must be empty then)";
  for (std::size_t c = 0; c < m.cells.size(); ++c)
    if (m.cell_origin[c] < 0 || static_cast<std::size_t>(m.cell_origin[c]) >= m.origin_tags.size() ||
        (c > 0 && m.cell_origin[c] < m.cell_origin[c - 1]))
      return "cell " + std::to_string(c) + ": file cell " + std::to_string(m.cell_origin[c]) +
             " out of range or out of order (the cells of a file cell follow one another, in file cell order)";
  // The file cells' nodes, for writing them back: Gmsh's corner count for each type.
  std::size_t expected = 0;
  for (std::size_t f = 0; f < m.origin_types.size(); ++f) {
    const int t = m.origin_types[f];
    const bool ok = MeshDim<Mesh>::d == 3 ? (t >= 4 && t <= 7) : (t == 2 || t == 3);
    if (!ok)
      return "file cell " + std::to_string(m.origin_tags[f]) + ": element type " + std::to_string(t) +
             " is not a cell of this dimension";
    expected += static_cast<std::size_t>(file_cell_nodes(t));
  }
  if (m.origin_nodes.size() != expected)
    return "file cell nodes: " + std::to_string(m.origin_nodes.size()) + ", expected " + std::to_string(expected);
  const auto n = static_cast<std::int64_t>(m.nodes.size());
  for (const auto idx : m.origin_nodes)
    if (idx < 0 || idx >= n) return "file cell node index " + std::to_string(idx) + " out of range";
  return "";
}

}  // namespace tetia::detail
