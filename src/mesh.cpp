#include "tetia/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace tetia {

double TetMesh::total_volume() const {
  double s = 0.0;
  for (const double v : volumes) s += v;
  return s;
}

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("tetia: " + name + ": " + what);
}

// A face as its three node indices, sorted, packed for hashing.
struct FaceKey {
  std::int32_t a, b, c;
  bool operator==(const FaceKey&) const = default;
};
struct FaceHash {
  std::size_t operator()(const FaceKey& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k.a);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.b);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(k.c);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

}  // namespace

void finalize(TetMesh& m, const std::string& name) {
  if (m.cells.empty()) fail(name, "no tetrahedra");
  const auto n = static_cast<std::int64_t>(m.nodes.size());
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const Vec3& p = m.nodes[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(name, "node " + std::to_string(i) + ": non-finite coordinate");
  }
  m.volumes.assign(m.cells.size(), 0.0);
  m.reoriented_cells = m.flat_cells = 0;
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    auto& v = m.cells[c];
    for (const auto idx : v)
      if (idx < 0 || idx >= n)
        fail(name, "cell " + std::to_string(c) + ": node index " + std::to_string(idx) + " out of range");
    if (v[0] == v[1] || v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3] || v[2] == v[3])
      fail(name, "cell " + std::to_string(c) + ": repeated node");
    const double sv = signed_volume(m.cell(c));
    if (sv < 0.0) {
      std::swap(v[2], v[3]);
      ++m.reoriented_cells;
    } else if (sv == 0.0) {
      ++m.flat_cells;
    }
    m.volumes[c] = std::abs(sv);
  }
  // Face adjacency in linear (expected) time: each face is entered once in a hash map; its
  // second occurrence links the two cells.
  m.neighbors.assign(m.cells.size(), {-1, -1, -1, -1});
  std::unordered_map<FaceKey, std::int64_t, FaceHash> open;
  open.reserve(m.cells.size() * 2);
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const auto& v = m.cells[c];
    for (int k = 0; k < 4; ++k) {
      std::int32_t f[3], j = 0;
      for (int q = 0; q < 4; ++q)
        if (q != k) f[j++] = v[static_cast<std::size_t>(q)];
      std::sort(f, f + 3);
      const FaceKey key{f[0], f[1], f[2]};
      const std::int64_t here = static_cast<std::int64_t>(c) * 4 + k;
      auto [it, inserted] = open.try_emplace(key, here);
      if (inserted) continue;
      const std::int64_t other = it->second;
      if (other < 0) fail(name, "cell " + std::to_string(c) + ": a face shared by more than two cells");
      m.neighbors[c][static_cast<std::size_t>(k)] = static_cast<std::int32_t>(other / 4);
      m.neighbors[static_cast<std::size_t>(other / 4)][static_cast<std::size_t>(other % 4)] = static_cast<std::int32_t>(c);
      it->second = -1;  // closed
    }
  }
}

TetMesh make_kuhn_mesh(std::array<int, 3> n, Vec3 origin, Vec3 h) {
  if (n[0] < 1 || n[1] < 1 || n[2] < 1) throw std::invalid_argument("tetia: make_kuhn_mesh: empty grid");
  TetMesh m;
  const auto id = [&](int i, int j, int k) {
    return static_cast<std::int32_t>((k * (n[1] + 1) + j) * (n[0] + 1) + i);
  };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i)
        m.nodes.push_back({origin.x + i * h.x, origin.y + j * h.y, origin.z + k * h.z});
  // The six tetrahedra of a cube around its main diagonal (0,0,0)-(1,1,1): one per ordering
  // of the axes along which a monotone path climbs from one corner to the other.
  static constexpr int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        for (const auto& path : kPaths) {
          int p[3] = {i, j, k};
          std::array<std::int32_t, 4> cell{};
          cell[0] = id(p[0], p[1], p[2]);
          for (int s = 0; s < 3; ++s) {
            ++p[path[s]];
            cell[static_cast<std::size_t>(s) + 1] = id(p[0], p[1], p[2]);
          }
          // Odd axis orders give left-handed tetrahedra: store every cell positively oriented.
          m.cells.push_back(cell);
          if (signed_volume(m.cell(m.cells.size() - 1)) < 0.0) std::swap(m.cells.back()[2], m.cells.back()[3]);
        }
  finalize(m, "kuhn mesh");
  return m;
}

}  // namespace tetia
