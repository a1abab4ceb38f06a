#include "tetia/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "compensated_sum.hpp"
#include "mesh/mesh_dim.hpp"
#include "mesh/check_file_cells.hpp"

namespace tetia {

// Compensated (compensated_sum.hpp): exact to about eps, whatever the number of cells.
double TetMesh::total_volume() const {
  detail::CompensatedSum s;
  for (const double v : volumes) s.add(v);
  return s.value();
}

double TriMesh::total_area() const {
  detail::CompensatedSum s;
  for (const double a : areas) s.add(a);
  return s.value();
}

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("tetia: " + name + ": " + what);
}

// A cell's signed volume (area) for any finite coordinates: where the determinant's products
// overflow (coordinates near the top of double's range), the same determinant of the cell scaled
// by a power of two (exact), scaled back. Infinite only when the measure itself is beyond
// double's range.
template <class D>
double signed_measure_of(const typename D::Cell& cell) {
  const double sv = D::signed_measure(cell);
  if (std::isfinite(sv)) return sv;
  double big = 0.0;
  for (const auto& p : cell)
    for (int k = 0; k < D::d; ++k) big = std::max(big, std::abs(D::coord(p, k)));
  int e = 0;
  std::frexp(big, &e);
  typename D::Cell scaled = cell;
  for (auto& p : scaled) p = std::ldexp(1.0, -e) * p;
  return std::ldexp(D::signed_measure(scaled), D::d * e);
}

// One implementation for both dimensions: the checks, the orientation and the adjacency do not
// depend on it (facet k of a cell is the one without its vertex k in either).
template <class Mesh>
void finalize_mesh(Mesh& m, const std::string& name) {
  using D = detail::MeshDim<Mesh>;
  constexpr std::size_t nv = D::nv;
  if (m.cells.empty()) fail(name, std::string("no ") + D::cells_word);
  const auto n = static_cast<std::int64_t>(m.nodes.size());
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    for (int k = 0; k < D::d; ++k)
      if (!std::isfinite(D::coord(m.nodes[i], k))) fail(name, "node " + std::to_string(i) + ": non-finite coordinate");
  const auto check_tags = [&](const std::vector<std::int64_t>& tags, std::size_t count, const char* what) {
    if (tags.empty()) return;
    if (tags.size() != count)
      fail(name, std::string(what) + " tags: " + std::to_string(tags.size()) + " for " + std::to_string(count) + " " +
                     what + "s");
    std::vector<std::int64_t> sorted(tags);
    std::sort(sorted.begin(), sorted.end());
    if (sorted.front() < 1) fail(name, std::string(what) + " tag " + std::to_string(sorted.front()) + " is not positive");
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end()) fail(name, std::string(what) + " tag " + std::to_string(*twice) + " given twice");
  };
  check_tags(m.node_tags, m.nodes.size(), "node");
  check_tags(m.cell_tags, m.cells.size(), "cell");
  if (const std::string problem = detail::file_cells_problem(m); !problem.empty()) fail(name, problem);
  check_tags(m.origin_tags, m.origin_types.size(), "file cell");
  auto& measures = D::measures(m);
  measures.assign(m.cells.size(), 0.0);
  m.reoriented_cells = m.flat_cells = 0;
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    auto& v = m.cells[c];
    for (const auto idx : v)
      if (idx < 0 || idx >= n)
        fail(name, "cell " + std::to_string(c) + ": node index " + std::to_string(idx) + " out of range");
    for (std::size_t a = 0; a < nv; ++a)
      for (std::size_t b = a + 1; b < nv; ++b)
        if (v[a] == v[b]) fail(name, "cell " + std::to_string(c) + ": repeated node");
    const double sv = signed_measure_of<D>(m.cell(c));
    if (!std::isfinite(sv))
      fail(name, "cell " + std::to_string(c) + ": its " + (D::d == 3 ? "volume" : "area") +
                     " is beyond the range of double precision (coordinates too large)");
    if (sv < 0.0) {
      std::swap(v[nv - 2], v[nv - 1]);  // an odd permutation: the orientation flips
      ++m.reoriented_cells;
    } else if (sv == 0.0) {
      ++m.flat_cells;
    }
    measures[c] = std::abs(sv);
  }
  // Facet adjacency in linear time: every facet (its nodes sorted) goes to the bucket of its
  // smallest node (a counting sort over the nodes), carrying its other one or two nodes packed
  // into 64 bits (node indices are non-negative int32) and its index, so that a bucket is read
  // from contiguous memory; within a bucket (up to 150 facets in the peers' meshes, half of all
  // facets in buckets of more than 32), equal facets are matched through a small open-addressing
  // table on the packed nodes, in the fill's order (facet ascending; a bucket of more than 256,
  // by sorting it). The first two occurrences of a facet are linked, a third is an error
  // (reported at the cell of the third, in cell order within its bucket). The keys are formed
  // twice (to count, then to fill) rather than stored: three compare-exchanges cost less than
  // 12 B a facet written and read again. (Sorting each bucket by the packed nodes instead was
  // half of finalize's time on those meshes.)
  constexpr std::size_t nf = nv;  // facets per cell
  using Key = std::array<std::int32_t, nv - 1>;
  const auto facet_key = [](const auto& v, std::size_t k) {
    Key key;
    std::size_t j = 0;
    for (std::size_t q = 0; q < nv; ++q)
      if (q != k) key[j++] = v[q];
    // Two or three nodes: sorted by compare-exchanges (std::sort's calls cost more than this).
    const auto order = [&](std::size_t a, std::size_t b) {
      if (key[b] < key[a]) std::swap(key[a], key[b]);
    };
    order(0, 1);
    if constexpr (nv - 1 == 3) {
      order(1, 2);
      order(0, 1);
    }
    return key;
  };
  const auto others_of = [](const Key& key) {
    std::uint64_t packed = static_cast<std::uint32_t>(key[1]);
    if constexpr (nv - 1 == 3) packed = packed << 32 | static_cast<std::uint32_t>(key[2]);
    return packed;
  };
  std::array<std::int32_t, nv> none;
  none.fill(-1);
  m.neighbors.assign(m.cells.size(), none);
  const std::size_t facets = m.cells.size() * nf;
  std::vector<std::size_t> start(m.nodes.size() + 1, 0);
  for (std::size_t c = 0; c < m.cells.size(); ++c)
    for (std::size_t k = 0; k < nf; ++k) ++start[static_cast<std::size_t>(facet_key(m.cells[c], k)[0]) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  struct Entry {
    std::uint64_t others;  // the facet's other nodes, packed
    std::size_t facet;     // cell * nf + k
  };
  std::vector<Entry> bucket(facets);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t c = 0; c < m.cells.size(); ++c)
      for (std::size_t k = 0; k < nf; ++k) {
        const Key key = facet_key(m.cells[c], k);
        bucket[fill[static_cast<std::size_t>(key[0])]++] = Entry{others_of(key), c * nf + k};  // facet ascending
      }
  }
  // The table: a slot holds the bucket it was written for (node + 1: a stale slot reads as
  // empty, so the table is never cleared), the position in the bucket of the first occurrence
  // of its facet, and whether the second has come. At least twice the largest bucket's slots.
  // A bucket of more than kHashedBucket facets (a node in very many cells, a fan) is sorted
  // instead, as Entry pairs by the packed nodes and then by facet (the fill's order within a
  // facet): linear probing among keys that an input could choose to collide costs up to the
  // square of the bucket's size, a sort n log n.
  constexpr std::size_t kHashedBucket = 256;
  std::size_t largest = 0;
  for (std::size_t node = 0; node < m.nodes.size(); ++node)
    largest = std::max(largest, std::min(start[node + 1] - start[node], kHashedBucket));
  unsigned bits = 3;
  while ((std::size_t{1} << bits) < 2 * largest) ++bits;
  struct Slot {
    std::size_t bucket = 0;  // node + 1
    std::size_t position = 0;
    bool paired = false;
  };
  std::vector<Slot> table(std::size_t{1} << bits);
  const std::size_t mask = table.size() - 1;
  const auto link = [&](const Entry& a, const Entry& b) {
    const std::size_t c0 = a.facet / nf, k0 = a.facet % nf, c1 = b.facet / nf, k1 = b.facet % nf;
    m.neighbors[c1][k1] = static_cast<std::int32_t>(c0);
    m.neighbors[c0][k0] = static_cast<std::int32_t>(c1);
  };
  const auto shared_by_three = [&](const Entry& third) {
    fail(name, "cell " + std::to_string(third.facet / nf) + ": " + D::facet_word + " shared by more than two cells");
  };
  for (std::size_t node = 0; node < m.nodes.size(); ++node) {
    Entry* const first = bucket.data() + start[node];
    const std::size_t count = start[node + 1] - start[node];
    if (count > kHashedBucket) {
      std::sort(first, first + count, [](const Entry& a, const Entry& b) {
        return a.others < b.others || (a.others == b.others && a.facet < b.facet);
      });
      for (std::size_t i = 0; i < count;) {
        std::size_t run = i + 1;
        while (run < count && first[run].others == first[i].others) ++run;
        if (run - i > 2) shared_by_three(first[i + 2]);
        if (run - i == 2) link(first[i], first[i + 1]);
        i = run;
      }
      continue;
    }
    for (std::size_t i = 0; i < count; ++i) {
      const Entry& e = first[i];
      // Fibonacci hashing: the top bits of the packed nodes times 2^64 / golden ratio.
      std::size_t h = static_cast<std::size_t>((e.others * 0x9E3779B97F4A7C15ull) >> (64 - bits));
      for (;; h = (h + 1) & mask) {
        Slot& slot = table[h];
        if (slot.bucket != node + 1) {  // empty: the facet's first occurrence
          slot = Slot{node + 1, i, false};
          break;
        }
        const Entry& seen = first[slot.position];
        if (seen.others != e.others) continue;
        if (slot.paired) shared_by_three(e);
        slot.paired = true;
        link(seen, e);
        break;
      }
    }
  }
}

}  // namespace

void finalize(TetMesh& m, const std::string& name) { finalize_mesh(m, name); }
void finalize(TriMesh& m, const std::string& name) { finalize_mesh(m, name); }

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

namespace tetia {

TriMesh make_structured_tri_mesh(std::array<int, 2> n, Vec2 origin, Vec2 h) {
  if (n[0] < 1 || n[1] < 1) throw std::invalid_argument("tetia: make_structured_tri_mesh: empty grid");
  TriMesh m;
  const auto id = [&](int i, int j) { return static_cast<std::int32_t>(j * (n[0] + 1) + i); };
  for (int j = 0; j <= n[1]; ++j)
    for (int i = 0; i <= n[0]; ++i) m.nodes.push_back({origin.x + i * h.x, origin.y + j * h.y});
  // The two triangles of a rectangle around its diagonal (0,0)-(1,1), as the Kuhn split does:
  // one per order of the axes along which a monotone path climbs from one corner to the other.
  for (int j = 0; j < n[1]; ++j)
    for (int i = 0; i < n[0]; ++i) {
      m.cells.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});  // x first: counter-clockwise
      m.cells.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});  // y first, reordered to be so
    }
  finalize(m, "structured triangle mesh");
  return m;
}

}  // namespace tetia
