// A mesh from arrays (tetia/mesh_from_arrays.hpp): the file cells given by type blocks, split
// into simplices by the reader's rule (src/mesh/split_cells.hpp), then finalize.
#include "tetia/mesh_from_arrays.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh_dim.hpp"
#include "../io/mesh_assembly.hpp"
#include "split_cells.hpp"

namespace tetia {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::invalid_argument("tetia: " + name + ": " + what);
}

const char* type_name(int type) {
  switch (type) {
    case 2: return "triangle";
    case 3: return "quadrilateral";
    case 4: return "tetrahedron";
    case 5: return "hexahedron";
    case 6: return "prism";
    case 7: return "pyramid";
    default: return "unknown type";
  }
}

template <class Mesh>
Mesh assemble(std::vector<typename detail::MeshDim<Mesh>::Point> nodes, std::span<const CellBlock> blocks,
              const std::string& name) {
  using Dm = detail::MeshDim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const int simplex_type = Dm::d == 3 ? 4 : 2;
  if (nodes.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail(name, "too many nodes for 32-bit indices");
  std::size_t file_cells = 0;
  bool split = false;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const int t = blocks[b].type;
    const bool ok = Dm::d == 3 ? (t >= 4 && t <= 7) : (t == 2 || t == 3);
    if (!ok)
      fail(name, "cell block " + std::to_string(b) + ": element type " + std::to_string(t) + " (" + type_name(t) +
                     ") is not a cell of a " + std::to_string(Dm::d) + "D mesh");
    const auto n = static_cast<std::size_t>(file_cell_nodes(t));
    if (blocks[b].nodes.size() % n != 0)
      fail(name, "cell block " + std::to_string(b) + " (" + type_name(t) + "): " +
                     std::to_string(blocks[b].nodes.size()) + " node indices, not a multiple of " + std::to_string(n));
    file_cells += blocks[b].nodes.size() / n;
    split |= t != simplex_type && !blocks[b].nodes.empty();
  }
  if (file_cells == 0) fail(name, std::string("no cells"));
  if (file_cells > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail(name, "too many cells for 32-bit indices");
  Mesh m;
  m.nodes = std::move(nodes);
  const auto num_nodes = static_cast<std::int64_t>(m.nodes.size());
  m.cells.reserve(file_cells);
  if (split) {
    m.cell_origin.reserve(file_cells);
    m.origin_tags.reserve(file_cells);
    m.origin_types.reserve(file_cells);
  }
  std::size_t f = 0;  // file cell index
  for (const CellBlock& block : blocks) {
    const auto n = static_cast<std::size_t>(file_cell_nodes(block.type));
    for (std::size_t at = 0; at < block.nodes.size(); at += n, ++f) {
      std::int32_t idx[8];
      std::uint64_t tags[8];
      for (std::size_t j = 0; j < n; ++j) {
        const std::int64_t v = block.nodes[at + j];
        if (v < 0 || v >= num_nodes)
          fail(name, "cell " + std::to_string(f) + " (" + type_name(block.type) + "): node index " + std::to_string(v) +
                         " out of range (" + std::to_string(num_nodes) + " nodes)");
        idx[j] = static_cast<std::int32_t>(v);
        tags[j] = static_cast<std::uint64_t>(v) + 1;  // what the split's diagonals are chosen by
      }
      const std::size_t before = m.cells.size();
      if (n == nv) {
        std::array<std::int32_t, nv> c;
        for (std::size_t j = 0; j < nv; ++j) c[j] = idx[j];
        m.cells.push_back(c);
      } else if constexpr (Dm::d == 3) {
        std::array<std::int32_t, 4> out[detail::kMaxSplitSimplices];
        const int k = detail::split_cell(static_cast<detail::SplitShape>(block.type), idx, tags, out);
        for (int t = 0; t < k; ++t) m.cells.push_back(out[t]);
      } else {
        std::array<std::int32_t, 3> out[2];
        const int k = detail::split_quadrangle(idx, tags, out);
        for (int t = 0; t < k; ++t) m.cells.push_back(out[t]);
      }
      if (m.cells.size() == before)
        fail(name, "cell " + std::to_string(f) + " (" + type_name(block.type) +
                       "): its repeated nodes leave it no volume");
      if (split) {
        m.cell_origin.resize(m.cells.size(), static_cast<std::int32_t>(f));
        m.origin_tags.push_back(static_cast<std::int64_t>(f) + 1);
        m.origin_types.push_back(static_cast<std::uint8_t>(block.type));
        m.origin_nodes.insert(m.origin_nodes.end(), idx, idx + n);
      }
    }
  }
  finalize(m, name);
  return m;
}

void check_coordinates(std::span<const double> coordinates, int dim, const std::string& name) {
  if (coordinates.size() % static_cast<std::size_t>(dim) != 0)
    fail(name, std::to_string(coordinates.size()) + " coordinates, not a multiple of " + std::to_string(dim));
  for (std::size_t i = 0; i < coordinates.size(); ++i)
    if (!std::isfinite(coordinates[i]))
      fail(name, "node " + std::to_string(i / static_cast<std::size_t>(dim)) + ": coordinate " +
                     std::to_string(i % static_cast<std::size_t>(dim)) + " is not finite");
}

}  // namespace

TetMesh make_tet_mesh(std::span<const double> coordinates, std::span<const CellBlock> blocks, const std::string& name) {
  check_coordinates(coordinates, 3, name);
  std::vector<Vec3> nodes(coordinates.size() / 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = {coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]};
  return assemble<TetMesh>(std::move(nodes), blocks, name);
}

TriMesh make_tri_mesh(std::span<const double> coordinates, int coordinate_dim, std::span<const CellBlock> blocks,
                      const std::string& name) {
  if (coordinate_dim != 2 && coordinate_dim != 3)
    fail(name, "points must have 2 or 3 coordinates, not " + std::to_string(coordinate_dim));
  check_coordinates(coordinates, coordinate_dim, name);
  const auto d = static_cast<std::size_t>(coordinate_dim);
  std::vector<Vec2> nodes(coordinates.size() / d);
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = {coordinates[d * i], coordinates[d * i + 1]};
  TriMesh m = assemble<TriMesh>(std::move(nodes), blocks, name);
  if (coordinate_dim == 3) {  // the plane z = const, as read_tri_mesh checks it
    std::vector<double> z(m.nodes.size());
    for (std::size_t i = 0; i < z.size(); ++i) z[i] = coordinates[3 * i + 2];
    detail::check_planar(name, m.nodes, z, m.cells);
  }
  return m;
}

}  // namespace tetia
