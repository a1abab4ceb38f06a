// tests/support/gmsh_write.hpp -- a mesh written by the Gmsh library itself (the tests of the
// readers, bench/bench_read.cpp), in any .msh version, ASCII or binary, optionally with one node
// and one element field appended as views: tetrahedral meshes as a discrete volume, triangular
// ones as a discrete surface at height z.
#pragma once

#include <gmsh.h>

#include <cstddef>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <vector>

#include "tetia/mesh.hpp"

namespace tetia::testsupport {

/// Nodes `xyz` (three per node) and cells `cells` (Gmsh element type `type`, node indices from
/// 0) on one discrete entity of dimension `dim`, written by Gmsh as .msh of the given version,
/// ASCII or binary, so the readers are checked on Gmsh's own output (node and element tags:
/// index + 1). With `node_field` / `cell_field` (non-empty), also views "gmsh nodes" / "gmsh
/// cells" of that data appended by gmsh::view::write. Gmsh is global state: this runs on the
/// caller's thread only, never alongside a tetia I/O call; initializing Gmsh a second time
/// (tetia's module does it too) is harmless in Gmsh 4.8.
template <class Cells>
void gmsh_write_entity(int dim, int type, const std::vector<double>& xyz, const Cells& cells,
                       const std::filesystem::path& file, double version, bool binary,
                       const std::vector<double>& node_field, const std::vector<double>& cell_field) {
  static std::once_flag once;
  std::call_once(once, [] { gmsh::initialize(0, nullptr, false); });
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.AbortOnError", 0);
  gmsh::clear();
  gmsh::model::add("test");
  const int entity = gmsh::model::addDiscreteEntity(dim);
  std::vector<std::size_t> node_tags(xyz.size() / 3), elem_tags(cells.size()), elem_nodes;
  std::iota(node_tags.begin(), node_tags.end(), std::size_t{1});
  std::iota(elem_tags.begin(), elem_tags.end(), std::size_t{1});
  for (const auto& c : cells)
    for (const auto v : c) elem_nodes.push_back(static_cast<std::size_t>(v) + 1);
  gmsh::model::mesh::addNodes(dim, entity, node_tags, xyz);
  gmsh::model::mesh::addElementsByType(entity, type, elem_tags, elem_nodes);
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

/// A tetrahedral mesh (a discrete volume of 4-node tetrahedra).
inline void gmsh_write(const TetMesh& m, const std::filesystem::path& file, double version, bool binary,
                       const std::vector<double>& node_field = {}, const std::vector<double>& cell_field = {}) {
  std::vector<double> xyz;
  for (const auto& p : m.nodes) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  gmsh_write_entity(3, 4, xyz, m.cells, file, version, binary, node_field, cell_field);
}

/// A triangular mesh (a discrete surface of 3-node triangles at height z).
inline void gmsh_write(const TriMesh& m, const std::filesystem::path& file, double version, bool binary,
                       double z = 0.0, const std::vector<double>& node_field = {},
                       const std::vector<double>& cell_field = {}) {
  std::vector<double> xyz;
  for (const auto& p : m.nodes) xyz.insert(xyz.end(), {p.x, p.y, z});
  gmsh_write_entity(2, 2, xyz, m.cells, file, version, binary, node_field, cell_field);
}

// Gmsh is one process-wide state: initialized once (tetia's own sessions initialize it too,
// which Gmsh 4.8 only warns about), quiet, and cleared before and after each use here, with the
// options the tests change put back to their defaults.
class GmshScope {
 public:
  GmshScope() {
    static std::once_flag once;
    std::call_once(once, [] { gmsh::initialize(0, nullptr, false); });
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::clear();
  }
  GmshScope(const GmshScope&) = delete;
  GmshScope& operator=(const GmshScope&) = delete;
  ~GmshScope() {
    try {
      gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
      gmsh::option::setNumber("Mesh.Binary", 0);
      gmsh::option::setNumber("Mesh.SaveAll", 0);
      gmsh::option::setNumber("Mesh.SaveParametric", 0);
      gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
      gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
      gmsh::clear();
    } catch (...) {  // Gmsh 4.8 throws std::string; nothing to do about it in a destructor
    }
  }
};

}  // namespace tetia::testsupport
