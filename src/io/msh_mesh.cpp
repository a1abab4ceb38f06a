// src/io/msh_mesh.cpp -- extract_msh, msh_dimension, msh_views (msh_mesh.hpp).
#include "msh_mesh.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tetia::detail {

template <class Mesh>
Extracted<Mesh> extract_msh(const MshFile& file, const std::string& name, bool corner_nodes) {
  using Dm = Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const MshCells& first_order = Dm::d == 3 ? file.tetrahedra : file.triangles;
  const MshCells& higher = Dm::d == 3 ? file.higher_tetrahedra : file.higher_triangles;
  MshCells merged;  // with corner_nodes: both, first order first
  if (corner_nodes && !higher.tags.empty()) {
    merged = first_order;
    merged.tags.insert(merged.tags.end(), higher.tags.begin(), higher.tags.end());
    merged.nodes.insert(merged.nodes.end(), higher.nodes.begin(), higher.nodes.end());
    merged.where.insert(merged.where.end(), higher.where.begin(), higher.where.end());
  }
  const MshCells& kept = corner_nodes && !higher.tags.empty() ? merged : first_order;
  const MshCells& other = Dm::d == 3 ? file.triangles : file.tetrahedra;
  Extracted<Mesh> ex;
  const auto lines = [&](const std::vector<std::size_t>& where) {
    return [&file, &where](std::size_t first, std::size_t later) {
      return " (" + file.location(where[first]) + " and " + file.location(where[later]) + ")";
    };
  };

  std::vector<std::size_t> order;
  ex.node_index.build(
      file.node_tags, order, name, "node",
      [&](std::size_t i, std::size_t j) { return std::equal(&file.xyz[3 * i], &file.xyz[3 * i + 3], &file.xyz[3 * j]); },
      lines(file.node_where));
  const std::vector<std::size_t> node_order = order;
  auto& nodes = ex.mesh.nodes;
  nodes.resize(order.size());
  std::vector<double> z;  // 2D: the dropped coordinate, checked below
  if constexpr (Dm::d == 2) z.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const double* p = &file.xyz[3 * order[k]];
    nodes[k] = Dm::point(p);
    if constexpr (Dm::d == 2) z[k] = p[2];
  }

  {
    TagIndex by_tag;  // only for the order; cell_index is built on the cells kept
    by_tag.build(
        kept.tags, order, name, "element",
        [&](std::size_t i, std::size_t j) {
          std::array<std::uint64_t, nv> a, b;
          std::copy_n(&kept.nodes[nv * i], nv, a.begin());
          std::copy_n(&kept.nodes[nv * j], nv, b.begin());
          std::sort(a.begin(), a.end());
          std::sort(b.begin(), b.end());
          return a == b;
        },
        lines(kept.where));
  }
  // Ignored: the elements of other types and the cells of the other dimension, each tag once (a
  // mesh given twice lists them twice; the same tag with the same nodes is one element).
  const auto distinct = [](const std::vector<std::uint64_t>& tags) {
    std::vector<std::uint64_t> t(tags);
    std::sort(t.begin(), t.end());
    return static_cast<std::size_t>(std::unique(t.begin(), t.end()) - t.begin());
  };
  const std::size_t higher_distinct = distinct(higher.tags);
  ex.ignored = file.other_elements + distinct(other.tags);
  ex.higher_order = higher_distinct;
  if (corner_nodes) {
    ex.ignored -= std::min(ex.ignored, higher_distinct);
    ex.straightened = higher_distinct;
    ex.higher_order = 0;
  }
  auto& cells = ex.mesh.cells;
  std::vector<std::size_t> cell_tags(order.size());
  cells.resize(order.size());
  for (std::size_t c = 0; c < order.size(); ++c) {
    cell_tags[c] = kept.tags[order[c]];
    const std::uint64_t* en = &kept.nodes[nv * order[c]];
    for (std::size_t j = 0; j < nv; ++j) {
      const std::int32_t idx = ex.node_index.find(en[j]);
      if (idx < 0)
        io_fail(name, file.location(kept.where[order[c]]) + ": element " + std::to_string(cell_tags[c]) +
                          ": unknown node tag " + std::to_string(en[j]));
      cells[c][j] = idx;
    }
  }
  ex.ignored += drop_repeated_cells(cells, cell_tags);
  ex.cell_index.build(cell_tags, order, name, "element", [](std::size_t, std::size_t) { return false; });
  // The file's tags, in the mesh's order (nodes by tag; cells by tag, repeats dropped).
  ex.mesh.node_tags.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k)
    ex.mesh.node_tags[k] = static_cast<std::int64_t>(file.node_tags[node_order[k]]);
  ex.mesh.cell_tags.assign(cell_tags.begin(), cell_tags.end());
  if constexpr (Dm::d == 2) check_planar(name, nodes, z, cells);
  return ex;
}

template Extracted<TetMesh> extract_msh<TetMesh>(const MshFile&, const std::string&, bool);
template Extracted<TriMesh> extract_msh<TriMesh>(const MshFile&, const std::string&, bool);

int msh_dimension(const MshFile& file) {
  if (!file.tetrahedra.tags.empty() || file.higher_order_tetrahedra > 0) return 3;
  if (!file.triangles.tags.empty() || file.higher_order_triangles > 0) return 2;
  return 0;
}

std::vector<ViewData> msh_views(const MshFile& file, bool with_values) {
  std::vector<ViewData> out;
  for (const MshData& d : file.data) {
    ViewData v{d.name, d.on_elements ? "ElementData" : "NodeData", d.components, d.step, {}, {}};
    if (with_values) {
      v.tags.assign(d.tags.begin(), d.tags.end());
      v.values = d.values;
    } else if (!d.tags.empty()) {
      v.tags.push_back(d.tags.front());  // marks the block as having values
    }
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace tetia::detail
