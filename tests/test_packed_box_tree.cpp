// tests/test_packed_box_tree.cpp -- the supermesh's packed R-tree (src/supermesh/packed_box_tree.hpp)
// against a scan of every box: each query returns exactly the boxes whose closed box meets the
// query's, once each, in increasing position, for tree sizes around every multiple of the
// fanout and its powers, boxes in Morton-like and in random order, touching and degenerate
// (point and flat) boxes, and boxes with a NaN bound (which meet nothing, and hide no other).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "../src/supermesh/packed_box_tree.hpp"

namespace {

using tetia::detail::Box;
using tetia::detail::PackedBoxTree;

template <int D>
std::vector<std::size_t> scan(const std::vector<Box<D>>& boxes, const Box<D>& q) {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    bool meet = true;
    for (std::size_t k = 0; k < D; ++k) meet = meet && boxes[i].lo[k] <= q.hi[k] && q.lo[k] <= boxes[i].hi[k];
    if (meet) hits.push_back(i);
  }
  return hits;
}

// Boxes on a grid of cells of width 1 (neighbours touch), in the order of the grid's rows when
// `sorted`, shuffled otherwise, with some shrunk to a point or flattened along an axis, and
// (`with_nan`) some with a NaN bound.
template <int D>
std::vector<Box<D>> grid_boxes(std::size_t n, bool sorted, bool with_nan, std::mt19937_64& rng) {
  std::vector<Box<D>> boxes(n);
  const auto side = static_cast<std::size_t>(std::ceil(std::pow(static_cast<double>(n), 1.0 / D)));
  std::uniform_int_distribution<int> pick(0, 9);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t rest = i;
    for (std::size_t k = 0; k < D; ++k) {
      const auto x = static_cast<double>(rest % side);
      rest /= side;
      boxes[i].lo[k] = x;
      boxes[i].hi[k] = x + 1.0;
    }
    const int kind = pick(rng);
    if (kind == 0) boxes[i].hi = boxes[i].lo;  // a point
    if (kind == 1) boxes[i].hi[0] = boxes[i].lo[0];  // flat
    if (kind == 2 && with_nan) boxes[i].lo[D - 1] = std::nan("");  // meets nothing
  }
  if (!sorted) std::shuffle(boxes.begin(), boxes.end(), rng);
  return boxes;
}

template <int D>
void check_sizes() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coord(-2.0, 14.0), width(0.0, 4.0);
  for (const std::size_t n : {0u, 1u, 2u, 7u, 8u, 9u, 63u, 64u, 65u, 511u, 512u, 513u, 1000u, 4097u}) {
    for (const int variant : {0, 1, 2}) {
      const bool sorted = variant != 1, with_nan = variant == 2;
      const std::vector<Box<D>> boxes = grid_boxes<D>(n, sorted, with_nan, rng);
      const PackedBoxTree<D> tree(boxes);
      ASSERT_EQ(tree.size(), n);
      for (int trial = 0; trial < 200; ++trial) {
        Box<D> q;
        for (std::size_t k = 0; k < D; ++k) {
          // Integer corners touch the grid's boxes exactly; others cut them.
          const double lo = trial % 2 ? std::floor(coord(rng)) : coord(rng);
          q.lo[k] = lo;
          q.hi[k] = trial % 3 == 0 ? lo : lo + (trial % 2 ? std::floor(width(rng)) : width(rng));
        }
        std::vector<std::size_t> hits;
        tree.query(q, [&](std::size_t i) { hits.push_back(i); });
        ASSERT_EQ(hits, scan(boxes, q)) << "n " << n << " variant " << variant << " trial " << trial;
      }
      {  // an unbounded query meets every box, and nothing else (no slot past the last box)
        Box<D> everything;
        everything.lo.fill(-INFINITY);
        everything.hi.fill(INFINITY);
        std::vector<std::size_t> all;
        tree.query(everything, [&](std::size_t i) { all.push_back(i); });
        ASSERT_EQ(all, scan(boxes, everything)) << "n " << n;
        if (!with_nan) {
          ASSERT_EQ(all.size(), n);
        }
      }
      if (n > 0 && !with_nan) {  // the bounds, and a query with them, which meets every box
        std::vector<std::size_t> all;
        tree.query(tree.bounds(), [&](std::size_t i) { all.push_back(i); });
        ASSERT_EQ(all.size(), n);
        for (std::size_t k = 0; k < D; ++k) {
          double lo = boxes[0].lo[k], hi = boxes[0].hi[k];
          for (const auto& b : boxes) lo = std::min(lo, b.lo[k]), hi = std::max(hi, b.hi[k]);
          EXPECT_EQ(tree.bounds().lo[k], lo);
          EXPECT_EQ(tree.bounds().hi[k], hi);
        }
      }
    }
  }
}

TEST(PackedBoxTree, QueriesMatchAScanIn3D) { check_sizes<3>(); }
TEST(PackedBoxTree, QueriesMatchAScanIn2D) { check_sizes<2>(); }

}  // namespace
