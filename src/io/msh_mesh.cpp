// src/io/msh_mesh.cpp -- extract_msh, msh_dimension, msh_views (msh_mesh.hpp).
#include "msh_mesh.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "../mesh/split_cells.hpp"

namespace tetia::detail {

template <class Mesh>
Extracted<Mesh> extract_msh(const MshFile& file, const std::string& name, bool corner_nodes) {
  using Dm = MeshDim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  // Each kept type, and with corner_nodes its higher orders by their corners (first order first).
  // A merged list has the type of each element (MshCells::types), the first-order ones' too.
  std::array<MshCells, 5> merged;
  const auto with_higher = [&](const MshCells& first, const MshCells& higher, int slot, int type) -> const MshCells& {
    if (!corner_nodes || higher.tags.empty()) return first;
    MshCells& m = merged[static_cast<std::size_t>(slot)];
    m = first;
    m.tags.insert(m.tags.end(), higher.tags.begin(), higher.tags.end());
    m.nodes.insert(m.nodes.end(), higher.nodes.begin(), higher.nodes.end());
    m.where.insert(m.where.end(), higher.where.begin(), higher.where.end());
    m.types.assign(first.tags.size(), static_cast<std::uint8_t>(type));
    m.types.insert(m.types.end(), higher.types.begin(), higher.types.end());
    return m;
  };
  const MshCells& kept = Dm::d == 3 ? with_higher(file.tetrahedra, file.higher_tetrahedra, 0, 4)
                                    : with_higher(file.triangles, file.higher_triangles, 0, 2);
  // (Only this dimension's: a 3D file's boundary quadrilaterals are not copied.)
  const bool volume = Dm::d == 3;
  const MshCells& hexahedra = volume ? with_higher(file.hexahedra, file.higher_hexahedra, 1, 5) : file.hexahedra;
  const MshCells& prisms = volume ? with_higher(file.prisms, file.higher_prisms, 2, 6) : file.prisms;
  const MshCells& pyramids = volume ? with_higher(file.pyramids, file.higher_pyramids, 3, 7) : file.pyramids;
  const MshCells& quadrangles = volume ? file.quadrangles : with_higher(file.quadrangles, file.higher_quadrangles, 4, 3);
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

  // The file cells: the simplices kept, and (3D) hexahedra, prisms, pyramids or (2D)
  // quadrilaterals, which are split into simplices below. Each cell's node tags are pointed to
  // in the reader's lists, not copied.
  struct FileCells {
    std::vector<std::uint64_t> tags;
    std::vector<const std::uint64_t*> nodes;
    std::vector<std::uint8_t> types;
    std::vector<std::uint8_t> file_nodes;  // the number of nodes in the file (more than the corners: order > 1)
    std::vector<std::size_t> where;
  } fc;
  const auto add_cells = [&](const MshCells& c, int type, std::size_t n) {
    for (std::size_t i = 0; i < c.tags.size(); ++i) {
      fc.tags.push_back(c.tags[i]);
      fc.nodes.push_back(&c.nodes[n * i]);
      fc.types.push_back(static_cast<std::uint8_t>(type));
      fc.file_nodes.push_back(
          static_cast<std::uint8_t>(c.types.empty() ? n : static_cast<std::size_t>(msh_nodes_per_element(c.types[i]))));
      fc.where.push_back(c.where[i]);
    }
  };
  const std::size_t total = kept.tags.size() + (Dm::d == 3 ? hexahedra.tags.size() + prisms.tags.size() +
                                                               pyramids.tags.size()
                                                             : quadrangles.tags.size());
  fc.tags.reserve(total);
  fc.nodes.reserve(total);
  fc.types.reserve(total);
  fc.file_nodes.reserve(total);
  fc.where.reserve(total);
  add_cells(kept, Dm::d == 3 ? 4 : 2, nv);
  if constexpr (Dm::d == 3) {
    add_cells(hexahedra, 5, 8);
    add_cells(prisms, 6, 6);
    add_cells(pyramids, 7, 5);
  } else {
    add_cells(quadrangles, 3, 4);
  }
  const auto nodes_of_type = [](int type) { return static_cast<std::size_t>(file_cell_nodes(type)); };
  {
    TagIndex by_tag;  // only for the order; cell_index is built on the cells kept
    by_tag.build(
        fc.tags, order, name, "element",
        [&](std::size_t i, std::size_t j) {
          if (fc.types[i] != fc.types[j]) return false;
          const std::size_t n = nodes_of_type(fc.types[i]);
          std::array<std::uint64_t, 8> a{}, b{};
          std::copy_n(fc.nodes[i], n, a.begin());
          std::copy_n(fc.nodes[j], n, b.begin());
          std::sort(a.begin(), a.end());
          std::sort(b.begin(), b.end());
          return a == b;
        },
        lines(fc.where));
  }
  // Ignored: the elements of other types and the cells of the other dimension, each tag once (a
  // mesh given twice lists them twice; the same tag with the same nodes is one element).
  const auto distinct = [](const std::vector<std::uint64_t>& tags) {
    std::vector<std::uint64_t> t(tags);
    std::sort(t.begin(), t.end());
    return static_cast<std::size_t>(std::unique(t.begin(), t.end()) - t.begin());
  };
  std::vector<std::uint64_t> higher_tags;  // this dimension's cells of order > 1
  for (const MshCells* h : Dm::d == 3 ? std::array<const MshCells*, 4>{&file.higher_tetrahedra, &file.higher_hexahedra,
                                                                       &file.higher_prisms, &file.higher_pyramids}
                                      : std::array<const MshCells*, 4>{&file.higher_triangles, &file.higher_quadrangles,
                                                                       nullptr, nullptr})
    if (h != nullptr) higher_tags.insert(higher_tags.end(), h->tags.begin(), h->tags.end());
  const std::size_t higher_distinct = distinct(higher_tags);
  ex.ignored = file.other_elements + distinct(other.tags);
  if constexpr (Dm::d == 3) ex.ignored += distinct(file.quadrangles.tags);
  else ex.ignored += distinct(file.hexahedra.tags) + distinct(file.prisms.tags) + distinct(file.pyramids.tags);
  ex.higher_order = higher_distinct;
  if (corner_nodes) {
    ex.ignored -= std::min(ex.ignored, higher_distinct);
    ex.straightened = higher_distinct;
    ex.higher_order = 0;
  }
  auto& cells = ex.mesh.cells;
  std::vector<std::size_t> origin;  // the file cell (its position in `order`) of each cell
  // Every file cell's node indices, one after the other: kept only where some cell is split.
  const bool any_split = fc.types.size() > kept.tags.size();  // cells other than simplices were added
  std::vector<std::int32_t> file_nodes;
  cells.reserve(order.size());
  origin.reserve(order.size());
  if (any_split) file_nodes.reserve(nv * order.size());
  bool split = false;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t f = order[k];
    const std::size_t n = nodes_of_type(fc.types[f]);
    std::int32_t idx[8];
    for (std::size_t j = 0; j < n; ++j) {
      idx[j] = ex.node_index.find(fc.nodes[f][j]);
      if (idx[j] < 0)
        io_fail(name, file.location(fc.where[f]) + ": element " + std::to_string(fc.tags[f]) + ": unknown node tag " +
                          std::to_string(fc.nodes[f][j]));
    }
    if (any_split) file_nodes.insert(file_nodes.end(), idx, idx + n);
    if (n == nv) {  // a simplex
      std::array<std::int32_t, nv> c;
      std::copy_n(idx, nv, c.begin());
      cells.push_back(c);
      origin.push_back(k);
      continue;
    }
    split = true;
    // A collapsed cell (a node twice) gives only its pieces with volume (split_cell).
    if constexpr (Dm::d == 3) {
      std::array<std::int32_t, 4> out[kMaxSplitSimplices];
      const int m = split_cell(static_cast<SplitShape>(fc.types[f]), idx, fc.nodes[f], out);
      for (int t = 0; t < m; ++t) cells.push_back(out[t]), origin.push_back(k);
    } else {
      std::array<std::int32_t, 3> out[2];
      const int m = split_quadrangle(idx, fc.nodes[f], out);
      for (int t = 0; t < m; ++t) cells.push_back(out[t]), origin.push_back(k);
    }
  }
  const std::size_t cells_before = cells.size();
  drop_repeated_cells(cells, origin);
  // The file cells of the tags kept, in tag order; a file cell whose simplices all repeat an
  // earlier one's (a 2.2 file lists a cell once per physical group) is ignored.
  std::vector<std::size_t> file_tags(order.size());
  std::vector<std::uint8_t> file_types(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) file_tags[k] = fc.tags[order[k]], file_types[k] = fc.types[order[k]];
  // Only where cells of order > 1 were kept by their corners do node counts differ from types'.
  std::vector<std::uint8_t> file_counts;
  if (ex.straightened > 0) {
    file_counts.resize(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) file_counts[k] = fc.file_nodes[order[k]];
  }
  if (!split) {
    ex.ignored += cells_before - cells.size();
    std::vector<std::size_t> cell_tags(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) cell_tags[c] = file_tags[origin[c]];
    if (!file_counts.empty()) {
      ex.element_nodes.resize(cells.size());
      for (std::size_t c = 0; c < cells.size(); ++c) ex.element_nodes[c] = file_counts[origin[c]];
    }
    ex.cell_index.build(cell_tags, order, name, "element", [](std::size_t, std::size_t) { return false; });
    ex.mesh.cell_tags.assign(cell_tags.begin(), cell_tags.end());
  } else {
    // File cells left without simplices are dropped (and counted as ignored), the others
    // renumbered in order, with their nodes.
    std::vector<std::int64_t> renumber(order.size(), -1);
    for (const std::size_t k : origin) renumber[k] = 0;
    std::size_t kept_cells = 0, at = 0;
    std::vector<std::int32_t>& kept_nodes = ex.mesh.origin_nodes;
    kept_nodes.reserve(file_nodes.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::size_t n = nodes_of_type(file_types[k]);
      if (renumber[k] < 0) {
        ++ex.ignored;
      } else {
        renumber[k] = static_cast<std::int64_t>(kept_cells);
        file_tags[kept_cells] = file_tags[k];
        file_types[kept_cells] = file_types[k];
        if (!file_counts.empty()) file_counts[kept_cells] = file_counts[k];
        ++kept_cells;
        kept_nodes.insert(kept_nodes.end(), file_nodes.begin() + static_cast<std::ptrdiff_t>(at),
                          file_nodes.begin() + static_cast<std::ptrdiff_t>(at + n));
      }
      at += n;
    }
    file_tags.resize(kept_cells);
    file_types.resize(kept_cells);
    if (!file_counts.empty()) {
      file_counts.resize(kept_cells);
      ex.element_nodes = std::move(file_counts);
    }
    for (std::size_t& k : origin) k = static_cast<std::size_t>(renumber[k]);
    ex.cell_index.build(file_tags, order, name, "element", [](std::size_t, std::size_t) { return false; });
    ex.mesh.cell_origin.assign(origin.begin(), origin.end());
    ex.mesh.origin_tags.assign(file_tags.begin(), file_tags.end());
    ex.mesh.origin_types = file_types;
  }
  // The file's tags, in the mesh's order (nodes by tag; cells by tag, repeats dropped).
  ex.mesh.node_tags.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k)
    ex.mesh.node_tags[k] = static_cast<std::int64_t>(file.node_tags[node_order[k]]);
  if constexpr (Dm::d == 2) check_planar(name, nodes, z, cells);
  return ex;
}

template Extracted<TetMesh> extract_msh<TetMesh>(const MshFile&, const std::string&, bool);
template Extracted<TriMesh> extract_msh<TriMesh>(const MshFile&, const std::string&, bool);

int msh_dimension(const MshFile& file) {
  if (!file.tetrahedra.tags.empty() || !file.hexahedra.tags.empty() || !file.prisms.tags.empty() ||
      !file.pyramids.tags.empty() || file.higher_order_3d > 0)
    return 3;
  if (!file.triangles.tags.empty() || !file.quadrangles.tags.empty() || file.higher_order_2d > 0) return 2;
  return 0;
}

std::vector<ViewData> msh_views(const MshFile& file, bool with_values) {
  std::vector<ViewData> out;
  for (const MshData& d : file.data) {
    ViewData v{d.name, d.on_element_nodes ? "ElementNodeData" : d.on_elements ? "ElementData" : "NodeData",
               d.components, d.step, {}, {}, {}};
    if (with_values) {
      v.tags.assign(d.tags.begin(), d.tags.end());
      v.values = d.values;
      v.nodes = d.nodes;
    } else if (!d.tags.empty()) {
      v.tags.push_back(d.tags.front());  // marks the block as having values
    }
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace tetia::detail
