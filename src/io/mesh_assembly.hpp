// src/io/mesh_assembly.hpp -- from the tags of a file to a mesh: what both readers (the strict
// .msh reader, msh_mesh.cpp, and the Gmsh model of a generated mesh, io.cpp) share: tag indices,
// cells listed twice, the plane check of 2D meshes, field values matched by tag (internal to the
// library).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "../mesh/mesh_dim.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace tetia::detail {

[[noreturn]] inline void io_fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("tetia: " + name + ": " + what);
}

// Ranks positive tags: find(tag) is the number of smaller (kept) tags. A vector when the tags
// are dense (the usual case: 1..N), a hash map otherwise.
class TagIndex {
 public:
  // `tags` in any order; `order` receives the input positions of the kept tags, by increasing
  // tag. A tag given twice is kept once if `same(first, later)` (positions) says both are the
  // same entity (Gmsh holds a mesh twice when a file has it twice), and is an error otherwise,
  // whose message ends with `where(first, later)` (the strict reader: the two lines).
  template <class Same, class Where>
  void build(const std::vector<std::size_t>& tags, std::vector<std::size_t>& order, const std::string& name,
             const char* kind, Same&& same, Where&& where) {
    const std::size_t n = tags.size();
    if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
      io_fail(name, std::string("too many ") + kind + "s for 32-bit indices");
    const auto duplicate = [&](std::size_t first, std::size_t later) {
      io_fail(name, std::string(kind) + " tag " + std::to_string(tags[later]) + " given twice, differently" +
                        where(first, later));
    };
    order.clear();
    order.reserve(n);
    dense_.clear();
    sparse_.clear();
    const std::size_t max_tag = n == 0 ? 0 : *std::max_element(tags.begin(), tags.end());
    if (max_tag / 4 <= n) {
      dense_.assign(max_tag + 1, -1);
      for (std::size_t i = 0; i < n; ++i) {
        auto& slot = dense_[tags[i]];
        if (slot == -1)
          slot = static_cast<std::int32_t>(i);
        else if (!same(static_cast<std::size_t>(slot), i))
          duplicate(static_cast<std::size_t>(slot), i);
      }
      std::int32_t rank = 0;
      for (auto& slot : dense_)
        if (slot >= 0) {
          order.push_back(static_cast<std::size_t>(slot));
          slot = rank++;
        }
    } else {
      order.resize(n);
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tags[a] < tags[b]; });
      std::size_t kept = 0;
      for (std::size_t k = 0; k < n; ++k) {
        if (kept > 0 && tags[order[k]] == tags[order[kept - 1]]) {
          if (!same(order[kept - 1], order[k])) duplicate(order[kept - 1], order[k]);
          continue;
        }
        order[kept++] = order[k];
      }
      order.resize(kept);
      // Sorted tags, searched by bisection: no hash whose collisions a file could choose (the
      // standard hash of an integer is the integer; tags that are all multiples of the bucket
      // count made a hash map quadratic).
      sparse_.resize(kept);
      for (std::size_t k = 0; k < kept; ++k) sparse_[k] = tags[order[k]];
    }
  }
  template <class Same>
  void build(const std::vector<std::size_t>& tags, std::vector<std::size_t>& order, const std::string& name,
             const char* kind, Same&& same) {
    build(tags, order, name, kind, same, [](std::size_t, std::size_t) { return std::string(); });
  }

  // -1 if the tag is not indexed.
  std::int32_t find(std::size_t tag) const {
    if (!sparse_.empty()) {
      const auto it = std::lower_bound(sparse_.begin(), sparse_.end(), tag);
      return it == sparse_.end() || *it != tag ? -1 : static_cast<std::int32_t>(it - sparse_.begin());
    }
    return tag < dense_.size() ? dense_[tag] : -1;
  }

 private:
  std::vector<std::int32_t> dense_;
  std::vector<std::size_t> sparse_;  // the kept tags, ascending (when they are not dense)
};

template <class Mesh>
struct Extracted {
  Mesh mesh;                        // not finalized
  TagIndex node_index, cell_index;  // Gmsh tag -> index in mesh.nodes / mesh.cells
  std::size_t ignored = 0;          // elements of other types, and repeated cells
  std::size_t higher_order = 0;     // elements of other types that are cells of order > 1
  std::size_t straightened = 0;     // cells of order > 1 kept by their corner nodes
  // Where cells of order > 1 were kept by their corners (straightened > 0): each file cell's
  // number of nodes in the file, in cell_index's order (the mesh's cells, or its file cells
  // where cells are split), which $ElementNodeData entries must give. Empty otherwise: each
  // has its first-order type's. (The strict reader only; the Gmsh model path leaves it empty.)
  std::vector<std::uint8_t> element_nodes;
};

// Gmsh's element types of the cells read: the 4-node tetrahedron and the 3-node triangle, and
// the prefix of Gmsh's names of their higher-order variants (counted for the error message).
template <class Mesh>
struct GmshCell;
template <>
struct GmshCell<TetMesh> {
  static constexpr int type = 4;
  static constexpr const char* family = "Tetrahedron";
};
template <>
struct GmshCell<TriMesh> {
  static constexpr int type = 2;
  static constexpr const char* family = "Triangle";
};

// Drops the cells whose node set is that of an earlier one, and returns how many. A .msh
// 2.2 file lists a cell once per physical group it belongs to, under different tags;
// kept twice, it would make its facets look shared by three or four cells.
template <std::size_t N>
std::size_t drop_repeated_cells(std::vector<std::array<std::int32_t, N>>& cells, std::vector<std::size_t>& tags) {
  struct Key {
    std::array<std::int32_t, N> nodes;  // sorted
    std::size_t cell;
  };
  // Keys bucketed by their smallest node (a counting sort, linear), each bucket (a few cells)
  // sorted by its nodes and then by cell: equal node sets are then neighbours, earliest first.
  std::size_t max_node = 0;
  for (const auto& c : cells)
    for (const auto v : c) max_node = std::max(max_node, static_cast<std::size_t>(v));
  std::vector<std::size_t> start(cells.empty() ? 1 : max_node + 2, 0);
  std::vector<Key> unsorted(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    unsorted[c] = {cells[c], c};
    std::sort(unsorted[c].nodes.begin(), unsorted[c].nodes.end());
    ++start[static_cast<std::size_t>(unsorted[c].nodes[0]) + 1];
  }
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<Key> keys(cells.size());
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (const Key& k : unsorted) keys[fill[static_cast<std::size_t>(k.nodes[0])]++] = k;  // cells ascending
  }
  for (std::size_t b = 0; b + 1 < start.size(); ++b)
    std::sort(keys.begin() + static_cast<std::ptrdiff_t>(start[b]), keys.begin() + static_cast<std::ptrdiff_t>(start[b + 1]),
              [](const Key& a, const Key& k) { return a.nodes != k.nodes ? a.nodes < k.nodes : a.cell < k.cell; });
  std::vector<char> drop(cells.size(), 0);
  std::size_t dropped = 0;
  for (std::size_t k = 1; k < keys.size(); ++k)
    if (keys[k].nodes == keys[k - 1].nodes) {
      drop[keys[k].cell] = 1;  // the later of equal keys: the first cell is kept
      ++dropped;
    }
  if (dropped == 0) return 0;
  std::size_t kept = 0;
  for (std::size_t c = 0; c < cells.size(); ++c)
    if (!drop[c]) {
      cells[kept] = cells[c];
      tags[kept++] = tags[c];
    }
  cells.resize(kept);
  tags.resize(kept);
  return dropped;
}

// A 2D mesh must lie in a plane z = const (Gmsh writes 2D meshes with z = 0): the z of every
// node of a triangle must agree with the first to 1e-12 of the size of the mesh (its x, y
// extent and |z|), which leaves room for coordinates written with 16 digits and nothing else.
inline void check_planar(const std::string& name, const std::vector<Vec2>& nodes, const std::vector<double>& z,
                  const std::vector<std::array<std::int32_t, 3>>& cells) {
  if (cells.empty()) return;
  const double z0 = z[static_cast<std::size_t>(cells[0][0])];
  double zlo = z0, zhi = z0, size = std::abs(z0);
  Vec2 lo = nodes[static_cast<std::size_t>(cells[0][0])], hi = lo;
  for (const auto& c : cells)
    for (const auto v : c) {
      const auto i = static_cast<std::size_t>(v);
      zlo = std::min(zlo, z[i]);
      zhi = std::max(zhi, z[i]);
      lo = {std::min(lo.x, nodes[i].x), std::min(lo.y, nodes[i].y)};
      hi = {std::max(hi.x, nodes[i].x), std::max(hi.y, nodes[i].y)};
    }
  size = std::max({size, std::abs(zlo), std::abs(zhi), hi.x - lo.x, hi.y - lo.y});
  if (zhi - zlo > 1e-12 * size) {
    char range[96];
    std::snprintf(range, sizeof range, "z from %.17g to %.17g", zlo, zhi);
    io_fail(name, std::string("the triangles do not lie in a plane z = const (") + range +
                   "); 2D meshes must be in the xy plane");
  }
}

// A field of a file at one time step: NodeData, ElementData or ElementNodeData (Gmsh: a
// model-based view). A file may hold several (one per field and step, or more, a step split in
// blocks).
struct ViewData {
  std::string name, type;  // type: "NodeData", "ElementData" or "ElementNodeData"
  int components = 0;
  std::int64_t step = 0;
  std::vector<std::size_t> tags;
  std::vector<double> values;  // `components` per tag; ElementNodeData: nodes[i] * components for tag i
  std::vector<std::uint32_t> nodes;  // ElementNodeData: each tag's number of nodes (empty otherwise)
};

using tetia::kOnlyStep;  // field_values' default step (tetia/io.hpp)

template <class Mesh>
std::string no_cells_message(const Extracted<Mesh>& ex) {
  const std::string cells = detail::MeshDim<Mesh>::cells_word;
  std::string m = "no " + cells;
  if (ex.higher_order > 0)
    m += " of first order (" + std::to_string(ex.higher_order) + " higher-order cells"
         " are not supported; convert with Gmsh: -order 1, or read their corner nodes only: --corner-nodes)";
  else
    m += " (" + std::to_string(ex.ignored) + " other elements ignored)";
  return m;
}

// The extracted mesh finalized (finalize(mesh, FILE)), or "no cells" with what was ignored.
template <class Mesh>
void finalize_extracted(Extracted<Mesh>& ex, const std::string& name) {
  if (ex.mesh.cells.empty()) io_fail(name, no_cells_message(ex));
  finalize(ex.mesh, name);
}

// What a read returns, from either reader: the mesh finalized (finalize_extracted, unless the
// caller did it already: `finalized`, to read element-node data on the final cells first) and,
// with `info`, what was ignored or made straight and the fields with values, each name once
// per kind in file order.
template <class Mesh>
Mesh finish_read(Extracted<Mesh>&& ex, const std::string& name, const std::vector<ViewData>& views, MeshReadInfo* info,
                 bool finalized = false) {
  if (!finalized) finalize_extracted(ex, name);
  if (info != nullptr) {
    *info = MeshReadInfo{};
    info->ignored_elements = ex.ignored;
    info->straightened_cells = ex.straightened;
    std::unordered_set<std::string> seen[3];
    std::vector<std::string>* lists[3] = {&info->node_fields, &info->cell_fields, &info->cell_node_fields};
    for (const auto& v : views) {
      const int kind = v.type == "NodeData" ? 0 : v.type == "ElementData" ? 1 : v.type == "ElementNodeData" ? 2 : -1;
      if (kind >= 0 && !v.tags.empty() && seen[kind].insert(v.name).second) lists[kind]->push_back(v.name);
    }
  }
  return std::move(ex.mesh);
}

// The time step of the named field of one kind (`type`: "NodeData", "ElementData",
// "ElementNodeData"; `kind` names it in messages: "node", "cell", "cell-node") that a read
// takes, and its number of components: `step`, or with kOnlyStep the field's only step with
// values. Errors: no such field with values (naming the fields of that kind there are), several
// steps and none chosen, no such step, blocks of the step with different numbers of
// components, and more than one component where only scalar fields are read (`scalar_only`).
struct FieldStep {
  std::int64_t step = 0;
  int components = 0;
};
inline FieldStep field_step(const std::string& name, const std::vector<ViewData>& views, const std::string& type,
                            const char* kind, const std::string& field_name, std::int64_t step, bool scalar_only) {
  std::vector<std::int64_t> steps;
  bool found = false;
  for (const auto& v : views) {
    if (v.type != type || v.name != field_name) continue;
    found = true;
    if (!v.tags.empty() && std::find(steps.begin(), steps.end(), v.step) == steps.end()) steps.push_back(v.step);
  }
  if (!found || steps.empty()) {
    // The fields of that kind with values, each name once, in file order (built only here).
    std::vector<std::string> names;
    std::unordered_set<std::string> seen;
    for (const auto& v : views)
      if (v.type == type && !v.tags.empty() && seen.insert(v.name).second) names.push_back(v.name);
    std::string available;
    for (std::size_t i = 0; i < names.size() && i < 20; ++i) available += (i ? ", " : "") + names[i];
    if (names.size() > 20) available += ", and " + std::to_string(names.size() - 20) + " more";
    io_fail(name, std::string("no ") + kind + " field named " + field_name + " (" + kind +
                      " fields: " + (available.empty() ? "none" : available) + ")");
  }
  std::sort(steps.begin(), steps.end());
  std::string step_list;
  for (const auto t : steps) step_list += (step_list.empty() ? "" : ", ") + std::to_string(t);
  if (step == kOnlyStep && steps.size() > 1)
    io_fail(name, "field " + field_name + " has " + std::to_string(steps.size()) + " time steps (" + step_list +
                      "); choose one (--step)");
  const std::int64_t chosen = step == kOnlyStep ? steps.front() : step;
  if (std::find(steps.begin(), steps.end(), chosen) == steps.end())
    io_fail(name, "field " + field_name + " has no time step " + std::to_string(chosen) + " (steps: " + step_list + ")");
  int comps = 0;
  for (const auto& v : views)
    if (v.type == type && v.name == field_name && v.step == chosen && !v.tags.empty()) {
      if (comps != 0 && v.components != comps)
        io_fail(name, "field " + field_name + ": blocks of step " + std::to_string(chosen) +
                          " with different numbers of components");
      comps = v.components;
    }
  if (scalar_only && comps != 1)
    io_fail(name, "field " + field_name + " has " + std::to_string(comps) + " components; only scalar fields are read here");
  return {chosen, comps};
}

// The named NodeData / ElementData at time step `step` (kOnlyStep: its only step with values),
// in the reader's order of nodes / cells (matched by tag, so any tag numbering works), each
// entity's `components` values in a row. `components` receives their number; without it only
// scalar fields are accepted. Every node / cell must have a value; values on elements other
// than the kept cells are ignored; a tag given twice at the step is an error.
template <class Mesh>
std::vector<double> field_values(const std::string& name, const Extracted<Mesh>& ex,
                                 const std::vector<ViewData>& views, const std::string& field_name, bool on_cells,
                                 std::int64_t step = kOnlyStep, int* components = nullptr) {
  const char* kind = on_cells ? "cell" : "node";
  const std::string type = on_cells ? "ElementData" : "NodeData";
  const auto [chosen, comps] = field_step(name, views, type, kind, field_name, step, components == nullptr);
  const auto nc = static_cast<std::size_t>(comps);
  const TagIndex& index = on_cells ? ex.cell_index : ex.node_index;
  // Split file cells (mesh.cell_origin): the values are the file cells', given to their simplices.
  const auto& origin = ex.mesh.cell_origin;
  const bool by_origin = on_cells && !origin.empty();
  const std::size_t n = by_origin ? ex.mesh.origin_tags.size() : on_cells ? ex.mesh.cells.size() : ex.mesh.nodes.size();
  std::vector<double> values(n * nc, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> set(n, 0);
  for (const auto& v : views) {
    if (v.type != type || v.name != field_name || v.step != chosen) continue;
    for (std::size_t i = 0; i < v.tags.size(); ++i) {
      const std::int32_t k = index.find(v.tags[i]);
      if (k < 0) continue;  // data on elements other than the cells
      const auto at = static_cast<std::size_t>(k);
      if (set[at])
        io_fail(name, "field " + field_name + ": " + (on_cells ? "element" : "node") + " tag " +
                          std::to_string(v.tags[i]) + " has two values");
      std::copy_n(&v.values[i * nc], nc, &values[at * nc]);
      set[at] = 1;
    }
  }
  if (by_origin) {
    std::vector<double> per_cell(origin.size() * nc);
    for (std::size_t c = 0; c < origin.size(); ++c) {
      const auto f = static_cast<std::size_t>(origin[c]);
      if (!set[f])
        io_fail(name, "field " + field_name + " has no value for element " + std::to_string(ex.mesh.origin_tags[f]));
      std::copy_n(&values[f * nc], nc, &per_cell[c * nc]);
    }
    if (components != nullptr) *components = comps;
    return per_cell;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (!set[k]) io_fail(name, "field " + field_name + " has no value for " + kind + " " + std::to_string(k));
  if (components != nullptr) *components = comps;
  return values;
}

// The named ElementNodeData at time step `step` (kOnlyStep: its only step with values) on the
// simplices of the finalized mesh `ex.mesh` (finalize_extracted): per simplex c, per vertex k
// (mesh.cells[c][k]), the `components` values at index (c * (d + 1) + k) * components + j:
// the value its element (its file cell, for split cells) has at that node. The node is looked
// up in the element's node list, so splitting and reorientation (which only permute a
// simplex's vertices, or take them from the file cell) change nothing; a collapsed file cell
// (a node twice) gives a node its first position's value; cells of order > 1 read by their
// corners take their corners' values. `file_cells`: where the mesh has no split cells, its
// cells as extracted, before finalize (the nodes in the file's order); ignored otherwise
// (mesh.origin_nodes has them). `components` receives their number; without it only scalar
// fields are accepted. Errors name the field and the element tag: an element whose entry has
// another number of nodes than its type (in the file: more than its corners for order > 1), a
// kept cell without a value, an element tag given twice at the step; entries on elements other
// than the kept cells are ignored (as field_values does).
template <class Mesh>
std::vector<double> cell_node_values(const std::string& name, const Extracted<Mesh>& ex,
                                     const std::vector<std::array<std::int32_t, MeshDim<Mesh>::nv>>& file_cells,
                                     const std::vector<ViewData>& views, const std::string& field_name,
                                     std::int64_t step = kOnlyStep, int* components = nullptr) {
  constexpr std::size_t nv = MeshDim<Mesh>::nv;
  const std::string type = "ElementNodeData";
  const auto [chosen, comps] = field_step(name, views, type, "cell-node", field_name, step, components == nullptr);
  const auto nc = static_cast<std::size_t>(comps);
  const Mesh& mesh = ex.mesh;
  const bool split = !mesh.cell_origin.empty();
  if (!split && file_cells.size() != mesh.cells.size())
    throw std::logic_error("cell_node_values: file_cells must be the cells before finalize");
  // Per file cell (cell_index's order): its first node in origin_nodes (split cells only), its
  // corners, and the first of its values in the chosen view (null: none yet).
  const std::size_t files = split ? mesh.origin_tags.size() : mesh.cells.size();
  std::vector<std::size_t> first_node;
  if (split) {
    first_node.resize(files + 1, 0);
    for (std::size_t f = 0; f < files; ++f)
      first_node[f + 1] = first_node[f] + static_cast<std::size_t>(file_cell_nodes(mesh.origin_types[f]));
  }
  const auto corners = [&](std::size_t f) {
    return split ? static_cast<std::size_t>(file_cell_nodes(mesh.origin_types[f])) : nv;
  };
  const auto tag_of = [&](std::size_t f) {
    return split ? mesh.origin_tags[f] : mesh.cell_tags.empty() ? static_cast<std::int64_t>(f + 1) : mesh.cell_tags[f];
  };
  std::vector<const double*> first_value(files, nullptr);
  for (const auto& v : views) {
    if (v.type != type || v.name != field_name || v.step != chosen) continue;
    if (v.nodes.size() != v.tags.size()) throw std::logic_error("cell_node_values: views read without their values");
    std::size_t at = 0;  // v's values of entry i start at at (each entry: v.nodes[i] * nc values)
    for (std::size_t i = 0; i < v.tags.size(); at += static_cast<std::size_t>(v.nodes[i]) * nc, ++i) {
      const std::int32_t k = ex.cell_index.find(v.tags[i]);
      if (k < 0) continue;  // data on elements other than the cells
      const auto f = static_cast<std::size_t>(k);
      const std::size_t want = ex.element_nodes.empty() ? corners(f) : ex.element_nodes[f];
      if (v.nodes[i] != want)
        io_fail(name, "field " + field_name + ": element " + std::to_string(v.tags[i]) + " has " +
                          std::to_string(want) + " nodes, its data gives " + std::to_string(v.nodes[i]));
      if (first_value[f] != nullptr)
        io_fail(name, "field " + field_name + ": element tag " + std::to_string(v.tags[i]) + " has two values");
      first_value[f] = &v.values[at];
    }
  }
  std::vector<double> values(mesh.cells.size() * nv * nc);
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    const std::size_t f = split ? static_cast<std::size_t>(mesh.cell_origin[c]) : c;
    const double* given = first_value[f];
    if (given == nullptr) io_fail(name, "field " + field_name + " has no value for element " + std::to_string(tag_of(f)));
    const std::int32_t* nodes = split ? &mesh.origin_nodes[first_node[f]] : file_cells[c].data();
    const std::size_t n = corners(f);
    for (std::size_t k = 0; k < nv; ++k) {
      const std::size_t p = static_cast<std::size_t>(std::find(nodes, nodes + n, mesh.cells[c][k]) - nodes);
      if (p == n) throw std::logic_error("cell_node_values: a simplex vertex that is no node of its file cell");
      std::copy_n(given + p * nc, nc, &values[(c * nv + k) * nc]);
    }
  }
  if (components != nullptr) *components = comps;
  return values;
}

}  // namespace tetia::detail
