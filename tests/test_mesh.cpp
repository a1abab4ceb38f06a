// test_mesh.cpp -- TetMesh::finalize (validation messages, reorientation, flat cells, face
// adjacency) and make_kuhn_mesh (counts, exact volume, adjacency invariants).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "tetia/mesh.hpp"

namespace {

using tetia::TetMesh;
using tetia::Vec3;

// The unit tetrahedron (volume 1/6), positively oriented, plus its mirror across the face 123.
TetMesh two_tets() {
  TetMesh m;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.cells = {{0, 1, 2, 3}, {4, 2, 1, 3}};
  return m;
}

// The message finalize throws, or "" if it does not throw.
template <class Mesh>
std::string finalize_error(Mesh m, const std::string& name) {
  try {
    tetia::finalize(m, name);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Finalize, ErrorMessagesNameTheMeshAndTheCell) {
  TetMesh m = two_tets();
  m.cells[1][2] = 9;
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: cell 1: node index 9 out of range");
  m = two_tets();
  m.cells[0][0] = -1;
  EXPECT_EQ(finalize_error(m, "a.msh"), "tetia: a.msh: cell 0: node index -1 out of range");
  m = two_tets();
  m.nodes[3].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: node 3: non-finite coordinate");
  m = two_tets();
  m.nodes[4].z = std::numeric_limits<double>::infinity();
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: node 4: non-finite coordinate");
  m = two_tets();
  m.cells.clear();
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: no tetrahedra");
  m = two_tets();
  m.cells[1] = {4, 2, 4, 3};
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: cell 1: repeated node");
  m = two_tets();
  m.cells.push_back({0, 1, 2, 3});  // cell 0 again: face 123 (its first) is now in three cells
  EXPECT_EQ(finalize_error(m, "NAME"), "tetia: NAME: cell 2: a face shared by more than two cells");
  EXPECT_EQ(finalize_error(two_tets(), "NAME"), "");
}

TEST(Finalize, VolumesAndAdjacency) {
  TetMesh m = two_tets();
  tetia::finalize(m);
  ASSERT_EQ(m.volumes.size(), 2u);
  EXPECT_DOUBLE_EQ(m.volumes[0], 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(m.volumes[1], 1.0 / 3.0);  // |det[(-1,0,-1),(0,-1,-1),(-1,-1,0)]| / 6 = 2/6
  EXPECT_DOUBLE_EQ(m.total_volume(), 0.5);
  EXPECT_EQ(m.reoriented_cells, 0u);
  EXPECT_EQ(m.flat_cells, 0u);
  // They share face {1,2,3}: opposite node 0 in cell 0, opposite node 4 in cell 1.
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t k = 0; k < 4; ++k) {
      const bool shared = (c == 0 && m.cells[0][k] == 0) || (c == 1 && m.cells[1][k] == 4);
      EXPECT_EQ(m.neighbors[c][k], shared ? static_cast<std::int32_t>(1 - c) : -1) << "cell " << c << " face " << k;
    }
}

TEST(Finalize, ReorientsInvertedCellsAndCountsThem) {
  TetMesh m = two_tets();
  std::swap(m.cells[0][0], m.cells[0][1]);  // inverted
  std::swap(m.cells[1][2], m.cells[1][3]);  // was positive: now inverted
  tetia::finalize(m, "x");
  EXPECT_EQ(m.reoriented_cells, 2u);
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_GT(tetia::signed_volume(m.cell(c)), 0.0) << "cell " << c;
    EXPECT_GT(m.volumes[c], 0.0);
  }
  EXPECT_DOUBLE_EQ(m.total_volume(), 0.5);
  // Finalizing again changes nothing.
  const auto cells = m.cells;
  tetia::finalize(m, "x");
  EXPECT_EQ(m.reoriented_cells, 0u);
  EXPECT_EQ(m.cells, cells);
}

TEST(Finalize, FlatCellIsCountedAndKept) {
  TetMesh m = two_tets();
  m.nodes.push_back({0.5, 0.5, 0.0});        // node 5: in the plane z = 0 of nodes 0, 1, 2
  m.cells.push_back({0, 1, 2, 5});           // zero volume, exactly
  tetia::finalize(m, "flat");
  EXPECT_EQ(m.flat_cells, 1u);
  ASSERT_EQ(m.num_cells(), 3u);
  EXPECT_EQ(m.volumes[2], 0.0);
  EXPECT_DOUBLE_EQ(m.total_volume(), 0.5);
  // It is a cell like another: face 012 of cell 0 now has cell 2 across it.
  EXPECT_NE(std::find(m.neighbors[0].begin(), m.neighbors[0].end(), 2), m.neighbors[0].end());
}

// finalize's neighbours against every pair of cells compared: the cell across facet k of c is
// the other cell holding the facet's nodes, -1 if none.
template <class Mesh>
void expect_brute_force_adjacency(const Mesh& m) {
  constexpr std::size_t nv = std::tuple_size_v<typename decltype(Mesh::cells)::value_type>;
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    for (std::size_t k = 0; k < nv; ++k) {
      std::int32_t across = -1;
      for (std::size_t d = 0; d < m.num_cells(); ++d) {
        if (d == c) continue;
        bool all = true;
        for (std::size_t q = 0; q < nv; ++q)
          if (q != k) all &= std::find(m.cells[d].begin(), m.cells[d].end(), m.cells[c][q]) != m.cells[d].end();
        if (all) across = static_cast<std::int32_t>(d);
      }
      ASSERT_EQ(m.neighbors[c][k], across) << "cell " << c << " facet " << k;
    }
}

// Node 0 in every cell (a fan: 3 n faces in its bucket in 3D, 2 n edges in 2D), the other
// nodes numbered in a scrambled order; then one cell given twice, whose facets the fan's bucket
// must find in three cells. n = 50: the bucket is matched through finalize's hash table (up to
// 256 facets); n = 150: it is sorted.
TEST(Finalize, AdjacencyOfAFanAroundOneNode) {
  for (const int n : {50, 150}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const auto scrambled = [n](int i) { return 1 + (i * 97) % n; };  // 97 is prime to 50 and 150: a permutation of 1..n
    TetMesh t;
    t.nodes.resize(static_cast<std::size_t>(n) + 2);
    t.nodes[0] = {0, 0, 0};
    t.nodes[static_cast<std::size_t>(n) + 1] = {0, 0, 1};  // the apex
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      t.nodes[static_cast<std::size_t>(scrambled(i))] = {std::cos(a), std::sin(a), 0.5};
    }
    for (int i = 0; i < n; ++i) t.cells.push_back({0, scrambled(i), scrambled((i + 1) % n), n + 1});
    tetia::finalize(t, "fan");
    expect_brute_force_adjacency(t);
    tetia::TriMesh f;
    f.nodes.resize(static_cast<std::size_t>(n) + 1);
    f.nodes[0] = {0, 0};
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      f.nodes[static_cast<std::size_t>(scrambled(i))] = {std::cos(a), std::sin(a)};
    }
    for (int i = 0; i < n; ++i) f.cells.push_back({0, scrambled(i), scrambled((i + 1) % n)});
    tetia::finalize(f, "fan");
    expect_brute_force_adjacency(f);
    t.cells.push_back(t.cells[7]);
    EXPECT_EQ(finalize_error(t, "fan"), "tetia: fan: cell " + std::to_string(n) + ": a face shared by more than two cells");
    f.cells.push_back(f.cells[7]);
    EXPECT_EQ(finalize_error(f, "fan"), "tetia: fan: cell " + std::to_string(n) + ": an edge shared by more than two cells");
  }
}

TEST(KuhnMesh, CountsVolumeAndAdjacency) {
  for (const std::array<int, 3> n : {std::array<int, 3>{1, 1, 1}, {2, 3, 4}, {5, 1, 2}}) {
    const Vec3 h{0.5, 0.25, 2.0};  // dyadic: every cell volume and their sum are exact
    const TetMesh m = tetia::make_kuhn_mesh(n, {1.0, -2.0, 3.0}, h);
    const std::size_t cubes = static_cast<std::size_t>(n[0]) * n[1] * n[2];
    SCOPED_TRACE(std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]));
    EXPECT_EQ(m.num_cells(), 6 * cubes);
    EXPECT_EQ(m.num_nodes(), static_cast<std::size_t>(n[0] + 1) * (n[1] + 1) * (n[2] + 1));
    // Each cell volume is exact (h.x h.y h.z / 6, correctly rounded); the sum to rounding.
    EXPECT_NEAR(m.total_volume(), static_cast<double>(cubes) * h.x * h.y * h.z, 1e-14 * m.total_volume());
    EXPECT_EQ(m.reoriented_cells, 0u);  // built positively oriented
    EXPECT_EQ(m.flat_cells, 0u);
    std::size_t boundary = 0;
    for (std::size_t c = 0; c < m.num_cells(); ++c) {
      EXPECT_EQ(m.volumes[c], h.x * h.y * h.z / 6.0);
      for (std::size_t k = 0; k < 4; ++k) {
        const std::int32_t nb = m.neighbors[c][k];
        if (nb < 0) {
          ++boundary;
          continue;
        }
        ASSERT_LT(static_cast<std::size_t>(nb), m.num_cells());
        ASSERT_NE(static_cast<std::size_t>(nb), c);
        const auto& back = m.neighbors[static_cast<std::size_t>(nb)];
        EXPECT_NE(std::find(back.begin(), back.end(), static_cast<std::int32_t>(c)), back.end())
            << "cell " << c << " -> " << nb << " is not symmetric";
        // The neighbour holds the face: all three nodes other than node k of c.
        const auto& w = m.cells[static_cast<std::size_t>(nb)];
        for (std::size_t q = 0; q < 4; ++q)
          if (q != k) {
            EXPECT_NE(std::find(w.begin(), w.end(), m.cells[c][q]), w.end());
          }
      }
    }
    // Two triangles per boundary square.
    EXPECT_EQ(boundary, 2u * 2u * static_cast<std::size_t>(n[0] * n[1] + n[1] * n[2] + n[0] * n[2]));
  }
  EXPECT_THROW(tetia::make_kuhn_mesh({0, 1, 1}, {}, {1, 1, 1}), std::invalid_argument);
}

}  // namespace
