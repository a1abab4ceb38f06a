// test_supermesh2d.cpp -- the 2D supermesh (triangular meshes): the pairs found against brute
// force with the exact reference (GMP), areas against mesh areas, on matching, offset,
// degenerate (coincident edges), far-from-origin, non-convex, holed and multi-component meshes
// and Gmsh meshes of different domains (disk, annulus, rectangle); front against R-tree, one
// thread against two, with and without polygons. The 2D counterpart of test_supermesh.cpp.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "tetia/exact.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/supermesh.hpp"
#include "tetia/tri_intersection.hpp"
#include "support/supermesh_checks.hpp"

namespace {

using tetia::CandidateSearch;
using tetia::Supermesh2;
using tetia::SupermeshOptions;
using tetia::SupermeshPiece2;
using tetia::Triangle;
using tetia::TriMesh;
using tetia::Vec2;

TriMesh grid(std::array<int, 2> n, Vec2 origin = {0, 0}, Vec2 h = {1, 1}) {
  return tetia::make_structured_tri_mesh(n, origin, h);
}

/// The mesh with every node mapped by f (refinalized).
TriMesh mapped(TriMesh m, const std::function<Vec2(Vec2)>& f) {
  for (Vec2& p : m.nodes) p = f(p);
  tetia::finalize(m, "mapped");
  return m;
}

/// A rotation by `angle` about the origin, then a translation by `d`.
std::function<Vec2(Vec2)> rigid(double angle, Vec2 d) {
  const double c = std::cos(angle), s = std::sin(angle);
  return [=](Vec2 p) { return Vec2{c * p.x - s * p.y + d.x, s * p.x + c * p.y + d.y}; };
}

/// The cells of a structured mesh of n rectangles whose rectangle (i, j) satisfies keep.
TriMesh grid_subset(std::array<int, 2> n, const std::function<bool(int, int)>& keep, Vec2 origin = {0, 0},
                    Vec2 h = {1, 1}) {
  const TriMesh full = grid(n, origin, h);
  TriMesh m;
  m.nodes = full.nodes;
  for (std::size_t c = 0; c < full.num_cells(); ++c) {
    const int rect = static_cast<int>(c / 2);
    if (keep(rect % n[0], rect / n[0])) m.cells.push_back(full.cells[c]);
  }
  tetia::finalize(m, "grid subset");
  return m;
}

using tetia::testsupport::bitwise_equal;
using tetia::testsupport::check_against_brute_force;
using tetia::testsupport::joined;
using tetia::testsupport::describe;
using tetia::testsupport::kResolution;
using tetia::testsupport::PairList;
using tetia::testsupport::pairs_of;

Supermesh2 run(const TriMesh& src, const TriMesh& tgt, CandidateSearch search, int threads, bool keep = false) {
  return tetia::testsupport::run(src, tgt, search, threads, keep);
}

/// Per cell of the target (source), the sum of its pieces' areas.
std::vector<double> covered(const Supermesh2& sm) {
  std::vector<double> c(sm.target->num_cells(), 0.0);
  for (const auto& pc : sm.pieces) c[static_cast<std::size_t>(pc.target)] += pc.area;
  return c;
}
std::vector<double> covered_source(const Supermesh2& sm) {
  std::vector<double> c(sm.source->num_cells(), 0.0);
  for (const auto& pc : sm.pieces) c[static_cast<std::size_t>(pc.source)] += pc.area;
  return c;
}

void expect_cells_covered(const std::vector<double>& cov, const TriMesh& m, double rel, const char* what) {
  std::size_t bad = 0;
  double worst = 0.0;
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const double e = std::abs(cov[c] - m.areas[c]) / m.areas[c];
    worst = std::max(worst, e);
    bad += e > rel;
  }
  EXPECT_EQ(bad, 0u) << what << ": worst relative error " << worst;
}

// ---------------------------------------------------------------------------------------------

TEST(Supermesh2D, GridVsRotatedShiftedGridMatchesExactBruteForce) {
  const TriMesh src = grid({5, 5});
  const TriMesh tgt = mapped(grid({5, 5}), rigid(0.37, {0.31, -0.17}));
  check_against_brute_force(src, tgt, "grid 5^2 vs rotated+shifted");
}

TEST(Supermesh2D, IdenticalMeshes) {
  const TriMesh m = grid({6, 6});
  const Supermesh2 sm = check_against_brute_force(m, m, "identical grid 6^2");
  ASSERT_EQ(sm.pieces.size(), m.num_cells());
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_EQ(sm.pieces[c].source, static_cast<std::int32_t>(c));
    EXPECT_EQ(sm.pieces[c].target, static_cast<std::int32_t>(c));
    EXPECT_EQ(sm.pieces[c].area, m.areas[c]);
  }
  EXPECT_EQ(sm.intersection_area(), 36.0);
  // An unstructured mesh against itself.
  const TriMesh disk = tetia::generate_disk({0.2, 0.1}, 1.0, 0.2);
  const Supermesh2 d = check_against_brute_force(disk, disk, "identical Gmsh disks");
  EXPECT_EQ(d.pieces.size(), disk.num_cells());
  expect_cells_covered(covered(d), disk, 1e-13, "target");
}

TEST(Supermesh2D, SameDomainDifferentResolution) {
  const TriMesh src = grid({6, 6}, {0, 0}, {1.0 / 6, 1.0 / 6});
  const TriMesh tgt = grid({7, 7}, {0, 0}, {1.0 / 7, 1.0 / 7});
  const Supermesh2 sm = check_against_brute_force(src, tgt, "grid 6^2 vs 7^2, unit square");
  expect_cells_covered(covered(sm), tgt, 1e-13, "target");
  expect_cells_covered(covered_source(sm), src, 1e-13, "source");
  EXPECT_NEAR(sm.intersection_area(), 1.0, 1e-13);
  // Two Gmsh meshes of one rectangle.
  const TriMesh a = tetia::generate_rectangle({0, 0}, {2, 1}, 0.2);
  const TriMesh b = tetia::generate_rectangle({0, 0}, {2, 1}, 0.15);
  const Supermesh2 g = check_against_brute_force(a, b, "Gmsh rectangles h 0.2 vs 0.15");
  expect_cells_covered(covered(g), b, 1e-13, "target");
  expect_cells_covered(covered_source(g), a, 1e-13, "source");
  EXPECT_NEAR(g.intersection_area(), 2.0, 2e-13);
}

TEST(Supermesh2D, HalfCellOffsetCoincidentEdges) {
  // Offsets by half a cell along one and two axes: edges of the two meshes coincide exactly.
  for (const Vec2& d : {Vec2{0.5, 0}, Vec2{0, 0.5}, Vec2{0.5, 0.5}}) {
    const TriMesh src = grid({4, 4});
    const TriMesh tgt = grid({5, 5}, Vec2{-1, -1} + d);
    const Supermesh2 sm = check_against_brute_force(
        src, tgt, "half offset (" + std::to_string(d.x) + "," + std::to_string(d.y) + ")");
    expect_cells_covered(covered_source(sm), src, 1e-13, "source");
    EXPECT_NEAR(sm.intersection_area(), 16.0, 16.0 * 1e-13);
  }
  // The same-sized meshes offset by half a cell: a partial overlap with coincident edges.
  const Supermesh2 sm = check_against_brute_force(grid({4, 4}), grid({4, 4}, {0.5, 0.5}), "grid 4^2 vs itself + (0.5,0.5)");
  EXPECT_NEAR(sm.intersection_area(), 3.5 * 3.5, 1e-12);
  // Diagonals crossing diagonals: the target split along the other diagonal (mirrored grid).
  const TriMesh mirrored = mapped(grid({4, 4}), [](Vec2 p) { return Vec2{4.0 - p.x, p.y}; });
  const Supermesh2 mx = check_against_brute_force(grid({4, 4}), mirrored, "grid vs mirrored grid");
  EXPECT_EQ(mx.intersection_area(), 16.0);
}

TEST(Supermesh2D, TinyOffsets) {
  const TriMesh src = grid({4, 4});
  for (const Vec2& d : {Vec2{1e-12, 0}, Vec2{1e-12, -1e-12}, Vec2{0, -3e-13}}) {
    const TriMesh tgt = grid({4, 4}, d);
    const Supermesh2 sm = check_against_brute_force(src, tgt, "tiny offset");
    EXPECT_NEAR(sm.intersection_area(), (4 - std::abs(d.x)) * (4 - std::abs(d.y)), 1e-12);
  }
  // And a rotation by 1e-12 rad about the centre.
  const TriMesh rot = mapped(grid({4, 4}, {-2, -2}), rigid(1e-12, {2, 2}));
  check_against_brute_force(src, rot, "rotated by 1e-12");
}

TEST(Supermesh2D, FarFromOrigin) {
  const Vec2 far{1e6, -2e6};
  const TriMesh src = grid({4, 4}, far);
  const TriMesh tgt = grid({4, 4}, far + Vec2{0.3, 0.2});
  const Supermesh2 sm = check_against_brute_force(src, tgt, "far from origin (1e6), offset");
  EXPECT_NEAR(sm.intersection_area(), 3.7 * 3.8, 1e-8);
  const Supermesh2 same = check_against_brute_force(src, src, "far from origin, identical");
  EXPECT_EQ(same.pieces.size(), src.num_cells());
  check_against_brute_force(src, grid({4, 4}, far + Vec2{0.5, 0.5}), "far from origin, half offset");
}

TEST(Supermesh2D, SmallerInsideBigger) {
  const TriMesh big = grid({5, 5});
  const TriMesh small = mapped(grid({4, 4}, {0, 0}, {0.5, 0.5}), rigid(0.2, {1.3, 1.1}));
  const Supermesh2 a = check_against_brute_force(big, small, "big -> small rotated");
  expect_cells_covered(covered(a), small, 1e-13, "target");
  const Supermesh2 b = check_against_brute_force(small, big, "small rotated -> big");
  expect_cells_covered(covered_source(b), small, 1e-13, "source");
  EXPECT_NEAR(b.intersection_area(), 4.0, 1e-13);
}

TEST(Supermesh2D, DifferentDomainsFromGmsh) {
  // A disk cutting a rectangle, an annulus (a hole: non-convex, not simply connected) against a
  // rectangle, both ways; the annulus against a disk that fills its hole.
  const TriMesh rect = tetia::generate_rectangle({0, 0}, {1, 1}, 0.12);
  const TriMesh disk = tetia::generate_disk({0.6, 0.5}, 0.55, 0.14);
  const TriMesh ring = tetia::generate_annulus({0.5, 0.45}, 0.2, 0.6, 0.13);
  check_against_brute_force(disk, rect, "disk -> rectangle");
  check_against_brute_force(rect, disk, "rectangle -> disk");
  check_against_brute_force(ring, rect, "annulus -> rectangle");
  check_against_brute_force(rect, ring, "rectangle -> annulus");
  const TriMesh plug = tetia::generate_disk({0.5, 0.45}, 0.3, 0.1);
  check_against_brute_force(plug, ring, "disk in the hole -> annulus");
}

TEST(Supermesh2D, NonConvexHolesAndComponents) {
  const TriMesh lshape = grid_subset({5, 5}, [](int i, int j) { return i < 2 || j < 2; });
  const TriMesh holed = grid_subset({5, 5}, [](int i, int j) { return !(i >= 1 && i <= 3 && j >= 1 && j <= 3 && !(i == 2 && j == 2)); });
  const TriMesh two = grid_subset({6, 2}, [](int i, int) { return i != 2 && i != 3; });
  const TriMesh rotated = mapped(grid({4, 4}, {0, 0}, {1.3, 1.3}), rigid(0.2, {0.1, 0.15}));
  check_against_brute_force(lshape, rotated, "L-shape -> rotated");
  check_against_brute_force(rotated, lshape, "rotated -> L-shape");
  check_against_brute_force(holed, rotated, "holed (with an island) -> rotated");
  check_against_brute_force(rotated, holed, "rotated -> holed (with an island)");
  check_against_brute_force(two, mapped(grid({2, 1}, {0, 0}, {3.1, 1.9}), rigid(0.1, {0.1, 0.05})),
                            "two components -> box");
  check_against_brute_force(lshape, mapped(holed, [](Vec2 p) { return p + Vec2{0.5, 0}; }),
                            "L-shape -> holed, half offset");
  // Big source cells spanning the hole and the gap: the targets meeting a cell are not
  // edge-connected.
  const TriMesh coarse = grid({1, 1}, {-0.2, -0.3}, {6.5, 6.4});
  const Supermesh2 h = check_against_brute_force(coarse, holed, "one big square -> holed");
  EXPECT_NEAR(h.intersection_area(), holed.total_area(), 1e-13 * holed.total_area());
  const Supermesh2 t = check_against_brute_force(coarse, two, "one big square -> two components");
  EXPECT_NEAR(t.intersection_area(), two.total_area(), 1e-13 * two.total_area());
}

TEST(Supermesh2D, ComponentInsideOneSourceCell) {
  // Small target meshes strictly inside one source triangle, and one far away.
  const TriMesh src = grid({2, 2});
  const TriMesh tgt = joined(grid({1, 1}, {0.55, 0.1}, {0.1, 0.1}), grid({1, 1}, {1.5, 1.7}, {0.2, 0.2}));
  const Supermesh2 sm = check_against_brute_force(src, tgt, "components inside source cells");
  EXPECT_NEAR(sm.intersection_area(), 0.01 + 0.04, 1e-15);
}

TEST(Supermesh2D, NonConformingInterface) {
  // The 3D test's counterpart: two blocks of 2^2 and 3^2 squares glued at x = 1 without matching
  // edges (risky cells along the interface), and source cells tilted a little across it.
  const TriMesh tgt = joined(grid({2, 2}, {0, 0}, {0.5, 0.5}), grid({3, 3}, {1, 0}, {1.0 / 3, 1.0 / 3}),
                             "two blocks, non-conforming interface");
  ASSERT_NEAR(tgt.total_area(), 2.0, 1e-14);
  check_against_brute_force(mapped(grid({3, 2}, {0, 0}, {0.6, 0.45}), rigid(0.1, {0.1, 0.05})), tgt,
                            "rotated box -> two blocks");
  for (const double angle : {1e-3, 1e-5, 1e-6, 5e-7, 3e-7, 2e-7, 1e-7}) {
    const auto tilt = rigid(angle, {0, 0});
    const TriMesh near = mapped(grid({6, 6}, {0.25, 0.125}, {0.125, 0.125}), [&](Vec2 p) {
      return tilt(p - Vec2{1, 0.5}) + Vec2{1, 0.5};
    });
    char name[64];
    std::snprintf(name, sizeof name, "tilted by %.0e -> two blocks", angle);
    check_against_brute_force(near, tgt, name);
  }
}

TEST(Supermesh2D, PolygonsKeptMatchPieces) {
  const TriMesh src = grid({3, 3});
  const TriMesh tgt = mapped(grid({3, 3}), rigid(0.3, {0.2, 0.1}));
  const Supermesh2 a = run(src, tgt, CandidateSearch::front, 2, true);
  const Supermesh2 b = run(src, tgt, CandidateSearch::front, 1, false);
  ASSERT_EQ(a.polygons.size(), a.pieces.size());
  EXPECT_TRUE(b.polygons.empty());
  EXPECT_EQ(pairs_of(a), pairs_of(b));
  for (std::size_t k = 0; k < a.pieces.size(); ++k) {
    EXPECT_EQ(a.polygons[k].area(), a.pieces[k].area);
    EXPECT_EQ(a.pieces[k].area, b.pieces[k].area);
    const Triangle A = src.cell(static_cast<std::size_t>(a.pieces[k].source));
    const Triangle B = tgt.cell(static_cast<std::size_t>(a.pieces[k].target));
    // The polygon is the kernel's for (A = source, B = target).
    EXPECT_EQ(tetia::intersect(A, B).area(), a.polygons[k].area());
  }
  EXPECT_TRUE(bitwise_equal(a.pieces, run(src, tgt, CandidateSearch::rtree, 1, true).pieces));
}

TEST(Supermesh2D, EmptyDisjointAndTouching) {
  const TriMesh a = grid({2, 2});
  const TriMesh b = grid({2, 2}, {5, 0});
  for (const auto search : {CandidateSearch::front, CandidateSearch::rtree}) {
    const Supermesh2 sm = run(a, b, search, 2);
    EXPECT_TRUE(sm.pieces.empty());
    EXPECT_EQ(sm.intersection_area(), 0.0);
    ASSERT_TRUE(sm.source && sm.target);  // copies of a and b (the supermesh keeps its meshes)
    EXPECT_EQ(sm.source->nodes, a.nodes);
    EXPECT_EQ(sm.target->nodes, b.nodes);
  }
  // Touching along an edge line, and at a corner only.
  EXPECT_TRUE(run(a, grid({2, 2}, {2, 0}), CandidateSearch::front, 1).pieces.empty());
  EXPECT_TRUE(run(a, grid({2, 2}, {2, 2}), CandidateSearch::front, 1).pieces.empty());
}

TEST(Supermesh2D, FrontEqualsRtreeOnMeshesWithManyInteriorCells) {
  const int n = 12;
  const TriMesh src = grid({n, n});
  const std::vector<std::pair<std::string, TriMesh>> targets = {
      {"identical", grid({n, n})},
      {"half offset x", grid({n + 1, n}, {-0.5, 0})},
      {"half offset xy", grid({n + 1, n + 1}, {-0.5, -0.5})},
      {"tiny offset", grid({n, n}, {1e-12, -1e-12})},
      {"finer, same domain", grid({n + 1, n + 1}, {0, 0}, {n / (n + 1.0), n / (n + 1.0)})},
      {"rotated", mapped(grid({n + 2, n + 2}, {-1, -1}), rigid(0.3, {0.5 * n, -0.2 * n}))},
      {"Gmsh disk", tetia::generate_disk({0.5 * n, 0.5 * n}, 0.45 * n, 0.7)},
  };
  for (const auto& [name, tgt] : targets) {
    SCOPED_TRACE(name);
    const Supermesh2 f = run(src, tgt, CandidateSearch::front, 2);
    const Supermesh2 r = run(src, tgt, CandidateSearch::rtree, 1);
    EXPECT_TRUE(bitwise_equal(f.pieces, r.pieces));
    std::printf("  %-20s %zu pairs, candidates: front %zu, rtree %zu\n", name.c_str(), f.pieces.size(), f.candidates,
                r.candidates);
  }
}

TEST(Supermesh2D, ThreadsGiveIdenticalResultsOnALargerMesh) {
  // Several chunks (more than 4096 source cells), offset by a generic fraction of a cell.
  const int n = 60;
  const double h = 1.0 / n;
  const TriMesh src = grid({n, n}, {0, 0}, {h, h});
  const TriMesh tgt = grid({n, n}, {0.3 * h, 0.2 * h}, {h, h});
  const Supermesh2 f1 = run(src, tgt, CandidateSearch::front, 1);
  const Supermesh2 f2 = run(src, tgt, CandidateSearch::front, 2);
  const Supermesh2 r1 = run(src, tgt, CandidateSearch::rtree, 1);
  const Supermesh2 r2 = run(src, tgt, CandidateSearch::rtree, 2);
  EXPECT_TRUE(bitwise_equal(f1.pieces, f2.pieces));
  EXPECT_TRUE(bitwise_equal(f1.pieces, r1.pieces));
  EXPECT_TRUE(bitwise_equal(r1.pieces, r2.pieces));
  EXPECT_EQ(f1.candidates, f2.candidates);
  const Supermesh2 f3 = run(src, tgt, CandidateSearch::front, 3);
  const Supermesh2 f0 = run(src, tgt, CandidateSearch::front, 0);
  EXPECT_TRUE(bitwise_equal(f1.pieces, f3.pieces));
  EXPECT_TRUE(bitwise_equal(f1.pieces, f0.pieces));
  EXPECT_EQ(f1.candidates, f3.candidates);
  EXPECT_LT(f1.candidates, r1.candidates);
  EXPECT_NEAR(f1.intersection_area(), (1 - 0.3 * h) * (1 - 0.2 * h), 1e-13);
  // Every source cell inside the overlap is covered exactly.
  const auto cov = covered_source(f1);
  std::size_t checked = 0;
  for (std::size_t c = 0; c < src.num_cells(); ++c) {
    bool inside = true;
    for (const Vec2& p : src.cell(c)) inside &= p.x >= 0.3 * h && p.y >= 0.2 * h;
    if (!inside) continue;
    ++checked;
    EXPECT_NEAR(cov[c], src.areas[c], 1e-13 * src.areas[c]);
  }
  EXPECT_GT(checked, 0u);
  std::printf("  grid %d^2 (%zu cells) vs offset: %zu pairs; front %zu candidates (%.4f s, 1 thread; %.4f s, 2), "
              "rtree %zu (%.4f s, 1 thread; %.4f s, 2)\n",
              n, src.num_cells(), f1.pieces.size(), f1.candidates, f1.seconds, f2.seconds, r1.candidates, r1.seconds,
              r2.seconds);
}

}  // namespace
