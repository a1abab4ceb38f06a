// tests/support/gmsh_write.hpp -- a tetrahedral mesh written by the Gmsh library itself (the
// tests of the readers, bench/bench_read.cpp), in any .msh version, ASCII or binary, optionally
// with one node and one element field appended as views.
#pragma once

#include <gmsh.h>

#include <cstddef>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <vector>

#include "tetia/mesh.hpp"

namespace tetia::testsupport {

/// `m` written by Gmsh itself (a model built from it, then gmsh::write) as .msh of the
/// given version, ASCII or binary, so read_mesh is checked on Gmsh's own output. Gmsh is global
/// state: this runs on the test's thread only, never alongside a tetia I/O call; initializing
/// Gmsh a second time (tetia does it too) is harmless in Gmsh 4.8.
/// With `node_field` / `cell_field` (non-empty), also views "gmsh nodes" / "gmsh cells" of that
/// data appended by gmsh::view::write (node and element tags: index + 1).
inline void gmsh_write(const TetMesh& m, const std::filesystem::path& file, double version, bool binary,
                       const std::vector<double>& node_field = {}, const std::vector<double>& cell_field = {}) {
  static std::once_flag once;
  std::call_once(once, [] { gmsh::initialize(0, nullptr, false); });
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.AbortOnError", 0);
  gmsh::clear();
  gmsh::model::add("test");
  const int vol = gmsh::model::addDiscreteEntity(3);
  std::vector<std::size_t> node_tags(m.num_nodes()), elem_tags(m.num_cells()), elem_nodes;
  std::iota(node_tags.begin(), node_tags.end(), std::size_t{1});
  std::iota(elem_tags.begin(), elem_tags.end(), std::size_t{1});
  std::vector<double> xyz;
  for (const auto& p : m.nodes) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  for (const auto& c : m.cells)
    for (const auto v : c) elem_nodes.push_back(static_cast<std::size_t>(v) + 1);
  gmsh::model::mesh::addNodes(3, vol, node_tags, xyz);
  gmsh::model::mesh::addElementsByType(vol, 4, elem_tags, elem_nodes);
  gmsh::option::setNumber("Mesh.MshFileVersion", version);
  gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
  gmsh::write(file.string());
  if (!node_field.empty()) {
    const int view = gmsh::view::add("gmsh nodes");
    gmsh::view::addHomogeneousModelData(view, 0, "test", "NodeData", node_tags, node_field);
    gmsh::view::write(view, file.string(), true);
  }
  if (!cell_field.empty()) {
    const int view = gmsh::view::add("gmsh cells");
    gmsh::view::addHomogeneousModelData(view, 0, "test", "ElementData", elem_tags, cell_field);
    gmsh::view::write(view, file.string(), true);
  }
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::clear();
}

}  // namespace tetia::testsupport
