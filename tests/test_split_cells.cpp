// test_split_cells.cpp -- src/mesh/split_cells.hpp: hexahedra, prisms, pyramids and
// quadrilaterals as simplices. For every order of the node tags: the pieces are positively
// oriented, their volumes add up to the cell's exactly (dyadic coordinates, planar faces: every
// determinant is exact), and two cells that share a face split it into the same triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "../src/mesh/split_cells.hpp"
#include "tetia/geometry.hpp"

namespace {

using tetia::Vec3;
using tetia::detail::SplitShape;
using tetia::detail::split_cell;
using tetia::detail::kMaxSplitSimplices;

double det6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return tetia::dot(b - a, tetia::cross(c - a, d - a));
}

// Corner coordinates in Gmsh's order, with an affine map (dyadic, so planar faces and exact
// volumes stay so) applied: x -> A x + t.
std::vector<Vec3> shape_points(SplitShape s) {
  std::vector<Vec3> p;
  switch (s) {
    case SplitShape::hexahedron:
      p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
      break;
    case SplitShape::prism:
      p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
      break;
    case SplitShape::pyramid:
      p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
      break;
    case SplitShape::quadrangle:
      p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
      break;
  }
  for (Vec3& q : p) q = {2 * q.x + 0.5 * q.y + 0.25 * q.z + 3, 0.25 * q.x + 1.5 * q.y - 0.5 * q.z - 1, 0.125 * q.x + 0.5 * q.y + 1.75 * q.z};
  return p;
}

double cell_volume6(SplitShape s) {  // six times the volume of the mapped shape
  const double det_a = 2 * (1.5 * 1.75 - (-0.5) * 0.5) - 0.5 * (0.25 * 1.75 - (-0.5) * 0.125) + 0.25 * (0.25 * 0.5 - 1.5 * 0.125);
  const double unit6 = s == SplitShape::hexahedron ? 6.0 : s == SplitShape::prism ? 3.0 : 2.0;  // cube, half, third
  return unit6 * det_a;
}

void check_all_orders(SplitShape shape, int expected_min, int expected_max) {
  const std::vector<Vec3> p = shape_points(shape);
  const int nv = static_cast<int>(p.size());
  std::vector<std::uint64_t> tags(static_cast<std::size_t>(nv));
  std::iota(tags.begin(), tags.end(), std::uint64_t{10});
  std::vector<int> nodes(static_cast<std::size_t>(nv));
  std::iota(nodes.begin(), nodes.end(), 0);
  int orders = 0;
  do {
    std::array<int, 4> out[kMaxSplitSimplices];
    const int n = split_cell(shape, nodes.data(), tags.data(), out);
    ASSERT_GE(n, expected_min);
    ASSERT_LE(n, expected_max);
    double sum6 = 0.0;
    for (int k = 0; k < n; ++k) {
      const auto& t = out[k];
      const double v = det6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
      ASSERT_GT(v, 0.0) << "simplex " << k << " of order " << orders;
      sum6 += v;
    }
    EXPECT_EQ(sum6, cell_volume6(shape)) << "order " << orders;
    ++orders;
  } while (std::next_permutation(tags.begin(), tags.end()));
  EXPECT_GT(orders, 100);
}

TEST(SplitCells, HexahedronEveryOrder) { check_all_orders(SplitShape::hexahedron, 6, 6); }
TEST(SplitCells, PrismEveryOrder) { check_all_orders(SplitShape::prism, 3, 3); }
TEST(SplitCells, PyramidEveryOrder) { check_all_orders(SplitShape::pyramid, 2, 2); }

// Collapsed cells (a node twice), as generators write prisms, pyramids and tetrahedra as
// degenerate hexahedra and prisms: for every order of the distinct nodes' tags, the pieces have
// no repeated node, are positive and fill the collapsed cell exactly.
TEST(SplitCells, CollapsedCellsEveryOrder) {
  struct Collapsed {
    SplitShape shape;
    std::vector<Vec3> points;  // the distinct corners
    std::vector<int> corners;  // the cell's corners (Gmsh's order) as indices into points
    double unit6;              // six times the volume before the affine map
  };
  const std::vector<Vec3> prism = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  const std::vector<Vec3> pyramid = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
  const std::vector<Vec3> tet = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Collapsed> cases = {
      {SplitShape::hexahedron, prism, {0, 1, 2, 2, 3, 4, 5, 5}, 3.0},    // a prism
      {SplitShape::hexahedron, pyramid, {0, 1, 2, 3, 4, 4, 4, 4}, 2.0},  // a pyramid
      {SplitShape::prism, tet, {0, 1, 2, 3, 3, 3}, 1.0},                 // a tetrahedron
      {SplitShape::pyramid, tet, {0, 1, 2, 2, 3}, 1.0},                  // a tetrahedron
  };
  const double det_a = cell_volume6(SplitShape::hexahedron) / 6.0;
  for (const Collapsed& c : cases) {
    std::vector<Vec3> p = c.points;
    for (Vec3& q : p) q = {2 * q.x + 0.5 * q.y + 0.25 * q.z + 3, 0.25 * q.x + 1.5 * q.y - 0.5 * q.z - 1, 0.125 * q.x + 0.5 * q.y + 1.75 * q.z};
    std::vector<std::uint64_t> distinct_tags(p.size());
    std::iota(distinct_tags.begin(), distinct_tags.end(), std::uint64_t{5});
    int orders = 0;
    do {
      std::vector<std::uint64_t> tags;
      for (const int k : c.corners) tags.push_back(distinct_tags[static_cast<std::size_t>(k)]);
      std::array<int, 4> out[kMaxSplitSimplices];
      const int n = split_cell(c.shape, c.corners.data(), tags.data(), out);
      double sum6 = 0.0;
      for (int k = 0; k < n; ++k) {
        const auto& t = out[k];
        ASSERT_FALSE(tetia::detail::repeats_a_node(t));
        const double v = det6(p[static_cast<std::size_t>(t[0])], p[static_cast<std::size_t>(t[1])],
                              p[static_cast<std::size_t>(t[2])], p[static_cast<std::size_t>(t[3])]);
        ASSERT_GT(v, 0.0) << "simplex " << k << " of order " << orders;
        sum6 += v;
      }
      EXPECT_EQ(sum6, c.unit6 * det_a) << "order " << orders;
      ++orders;
    } while (std::next_permutation(distinct_tags.begin(), distinct_tags.end()));
    EXPECT_GE(orders, 24);
  }
  // A quadrilateral with a node twice is its triangle; with two pairs, nothing.
  const int q[4] = {0, 1, 1, 2};
  const std::uint64_t tq[4] = {7, 3, 3, 5};
  std::array<int, 3> out[2];
  ASSERT_EQ(tetia::detail::split_quadrangle(q, tq, out), 1);
  std::array<int, 3> t = out[0];
  std::sort(t.begin(), t.end());
  EXPECT_EQ(t, (std::array<int, 3>{0, 1, 2}));
  const int flat[4] = {0, 1, 0, 1};
  const std::uint64_t tf[4] = {4, 9, 4, 9};
  EXPECT_EQ(tetia::detail::split_quadrangle(flat, tf, out), 0);
}

TEST(SplitCells, QuadrangleEveryOrder) {
  const std::vector<Vec3> p = shape_points(SplitShape::quadrangle);
  std::vector<std::uint64_t> tags = {1, 2, 3, 4};
  const int nodes[4] = {0, 1, 2, 3};
  const auto area2 = [&](int a, int b, int c) {
    const Vec3 u = p[static_cast<std::size_t>(b)] - p[static_cast<std::size_t>(a)], v = p[static_cast<std::size_t>(c)] - p[static_cast<std::size_t>(a)];
    return u.x * v.y - u.y * v.x;
  };
  do {
    std::array<int, 3> out[2];
    ASSERT_EQ(tetia::detail::split_quadrangle(nodes, tags.data(), out), 2);
    const double a0 = area2(out[0][0], out[0][1], out[0][2]), a1 = area2(out[1][0], out[1][1], out[1][2]);
    EXPECT_GT(a0, 0.0);
    EXPECT_GT(a1, 0.0);
    EXPECT_EQ(a0 + a1, area2(0, 1, 2) + area2(0, 2, 3));
    // The diagonal passes through the node of smallest tag.
    const int smallest = static_cast<int>(std::min_element(tags.begin(), tags.end()) - tags.begin());
    EXPECT_TRUE(std::count(out[0].begin(), out[0].end(), smallest) == 1 && std::count(out[1].begin(), out[1].end(), smallest) == 1);
  } while (std::next_permutation(tags.begin(), tags.end()));
}

// Two hexahedra sharing the face x = 1 of a 2 x 1 x 1 box, a pyramid on the second one's face
// x = 2 and a prism on the first one's face y = 1, with random global tags: every cell's pieces
// are positive and fill it, and the triangles two cells put on their shared face are the same.
TEST(SplitCells, NeighboursSplitSharedFacesAlike) {
  std::vector<Vec3> X;
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 2; ++i) X.push_back({double(i), double(j), double(k)});
  const auto id = [](int i, int j, int k) { return k * 6 + j * 3 + i; };
  X.push_back({3, 0.5, 0.5});  // 12: the pyramid's apex
  X.push_back({0, 2, 0});      // 13, 14: the prism's far edge
  X.push_back({0, 2, 1});
  struct Cell {
    SplitShape shape;
    std::vector<int> nodes;
    double volume6;
  };
  const std::vector<Cell> cells = {
      {SplitShape::hexahedron, {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0), id(0, 0, 1), id(1, 0, 1), id(1, 1, 1), id(0, 1, 1)}, 6.0},
      {SplitShape::hexahedron, {id(1, 0, 0), id(2, 0, 0), id(2, 1, 0), id(1, 1, 0), id(1, 0, 1), id(2, 0, 1), id(2, 1, 1), id(1, 1, 1)}, 6.0},
      // Base counter-clockwise seen from the apex (a positive pyramid), on the face x = 2.
      {SplitShape::pyramid, {id(2, 0, 0), id(2, 1, 0), id(2, 1, 1), id(2, 0, 1), 12}, 2.0},
      // Bottom triangle counter-clockwise seen from the top, on the face y = 1.
      {SplitShape::prism, {id(0, 1, 0), id(1, 1, 0), 13, id(0, 1, 1), id(1, 1, 1), 14}, 3.0},
  };
  // Shared faces: (cell, cell, the face's four nodes).
  const std::vector<std::array<int, 6>> shared = {
      {0, 1, id(1, 0, 0), id(1, 1, 0), id(1, 1, 1), id(1, 0, 1)},
      {1, 2, id(2, 0, 0), id(2, 1, 0), id(2, 1, 1), id(2, 0, 1)},
      {0, 3, id(0, 1, 0), id(1, 1, 0), id(1, 1, 1), id(0, 1, 1)},
  };
  std::mt19937_64 rng(7);
  for (int round = 0; round < 2000; ++round) {
    std::vector<std::uint64_t> tag(X.size());
    std::iota(tag.begin(), tag.end(), std::uint64_t{1});
    std::shuffle(tag.begin(), tag.end(), rng);
    std::vector<std::vector<std::array<int, 4>>> pieces;
    for (const Cell& c : cells) {
      std::vector<std::uint64_t> t;
      for (int n : c.nodes) t.push_back(tag[static_cast<std::size_t>(n)]);
      std::array<int, 4> out[kMaxSplitSimplices];
      const int n = split_cell(c.shape, c.nodes.data(), t.data(), out);
      double sum = 0.0;
      for (int k = 0; k < n; ++k) {
        const double v = det6(X[out[k][0]], X[out[k][1]], X[out[k][2]], X[out[k][3]]);
        EXPECT_GT(v, 0.0);
        sum += v;
      }
      EXPECT_EQ(sum, c.volume6);
      pieces.emplace_back(out, out + n);
    }
    for (const auto& sh : shared) {
      const std::set<int> face = {sh[2], sh[3], sh[4], sh[5]};
      std::set<std::array<int, 3>> tris[2];
      for (int side = 0; side < 2; ++side)
        for (const auto& q : pieces[static_cast<std::size_t>(sh[static_cast<std::size_t>(side)])])
          for (int skip = 0; skip < 4; ++skip) {
            std::array<int, 3> f;
            for (int m = 0, w = 0; m < 4; ++m)
              if (m != skip) f[static_cast<std::size_t>(w++)] = q[static_cast<std::size_t>(m)];
            if (face.count(f[0]) && face.count(f[1]) && face.count(f[2])) {
              std::sort(f.begin(), f.end());
              tris[side].insert(f);
            }
          }
      EXPECT_EQ(tris[0].size(), 2u);
      EXPECT_EQ(tris[0], tris[1]) << "cells " << sh[0] << " and " << sh[1] << ", round " << round;
    }
  }
}

}  // namespace
