// test_supermesh.cpp -- mesh-mesh intersection: the pairs found against brute force with the
// exact reference, volumes against mesh volumes, on matching, offset, degenerate (coincident
// faces), far-from-origin, non-convex, holed and multi-component meshes; front against R-tree,
// one thread against two, with and without polyhedra.
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
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tetia/exact.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"
#include "tetia/tet_intersection.hpp"
#include "support/supermesh_checks.hpp"

namespace {

using tetia::CandidateSearch;
using tetia::Supermesh;
using tetia::SupermeshOptions;
using tetia::SupermeshPiece;
using tetia::Tet;
using tetia::TetMesh;
using tetia::Vec3;

TetMesh kuhn(std::array<int, 3> n, Vec3 origin = {0, 0, 0}, Vec3 h = {1, 1, 1}) {
  return tetia::make_kuhn_mesh(n, origin, h);
}

/// The mesh with every node mapped by f (refinalized).
TetMesh mapped(TetMesh m, const std::function<Vec3(Vec3)>& f) {
  for (Vec3& p : m.nodes) p = f(p);
  tetia::finalize(m, "mapped");
  return m;
}

/// A rotation by `angle` about the unit axis `a`, then a translation by `d`.
std::function<Vec3(Vec3)> rigid(Vec3 a, double angle, Vec3 d) {
  const double n = std::sqrt(tetia::dot(a, a));
  a = (1.0 / n) * a;
  const double c = std::cos(angle), s = std::sin(angle);
  return [=](Vec3 p) {
    const Vec3 r = c * p + s * tetia::cross(a, p) + ((1.0 - c) * tetia::dot(a, p)) * a;
    return r + d;
  };
}

/// The cells of a Kuhn mesh of n cubes whose cube (i, j, k) satisfies keep (nodes kept as is).
TetMesh kuhn_subset(std::array<int, 3> n, const std::function<bool(int, int, int)>& keep, Vec3 origin = {0, 0, 0},
                    Vec3 h = {1, 1, 1}) {
  const TetMesh full = kuhn(n, origin, h);
  TetMesh m;
  m.nodes = full.nodes;
  for (std::size_t c = 0; c < full.num_cells(); ++c) {
    const int cube = static_cast<int>(c / 6);
    const int i = cube % n[0], j = (cube / n[0]) % n[1], k = cube / (n[0] * n[1]);
    if (keep(i, j, k)) m.cells.push_back(full.cells[c]);
  }
  tetia::finalize(m, "kuhn subset");
  return m;
}


using tetia::testsupport::bitwise_equal;
using tetia::testsupport::check_against_brute_force;
using tetia::testsupport::joined;
using tetia::testsupport::describe;
using tetia::testsupport::kResolution;
using tetia::testsupport::PairList;
using tetia::testsupport::pairs_of;

Supermesh run(const TetMesh& src, const TetMesh& tgt, CandidateSearch search, int threads, bool keep = false) {
  return tetia::testsupport::run(src, tgt, search, threads, keep);
}

/// Per target cell, the sum of its pieces' volumes (pieces are sorted by target).
std::vector<double> covered(const Supermesh& sm) {
  std::vector<double> c(sm.target->num_cells(), 0.0);
  for (const auto& pc : sm.pieces) c[static_cast<std::size_t>(pc.target)] += pc.volume;
  return c;
}
std::vector<double> covered_source(const Supermesh& sm) {
  std::vector<double> c(sm.source->num_cells(), 0.0);
  for (const auto& pc : sm.pieces) c[static_cast<std::size_t>(pc.source)] += pc.volume;
  return c;
}

void expect_cells_covered(const std::vector<double>& cov, const TetMesh& m, double rel, const char* what) {
  std::size_t bad = 0;
  double worst = 0.0;
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const double e = std::abs(cov[c] - m.volumes[c]) / m.volumes[c];
    worst = std::max(worst, e);
    bad += e > rel;
  }
  EXPECT_EQ(bad, 0u) << what << ": worst relative error " << worst;
}

// ---------------------------------------------------------------------------------------------

TEST(Supermesh, KuhnVsRotatedShiftedKuhnMatchesExactBruteForce) {
  const TetMesh src = kuhn({3, 3, 3});
  const TetMesh tgt = mapped(kuhn({3, 3, 3}), rigid({1, 2, 3}, 0.37, {0.31, -0.17, 0.23}));
  check_against_brute_force(src, tgt, "Kuhn 3^3 vs rotated+shifted");
}

TEST(Supermesh, IdenticalMeshes) {
  const TetMesh m = kuhn({3, 3, 3});
  const Supermesh sm = check_against_brute_force(m, m, "identical Kuhn 3^3");
  ASSERT_EQ(sm.pieces.size(), m.num_cells());
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_EQ(sm.pieces[c].source, static_cast<std::int32_t>(c));
    EXPECT_EQ(sm.pieces[c].target, static_cast<std::int32_t>(c));
  }
  expect_cells_covered(covered(sm), m, 1e-13, "target");
  EXPECT_NEAR(sm.intersection_volume(), 27.0, 27.0 * 1e-13);
}

TEST(Supermesh, SameDomainDifferentResolution) {
  const TetMesh src = kuhn({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  const TetMesh tgt = kuhn({4, 4, 4}, {0, 0, 0}, {0.25, 0.25, 0.25});
  const Supermesh sm = check_against_brute_force(src, tgt, "Kuhn 3^3 vs 4^3, unit cube");
  expect_cells_covered(covered(sm), tgt, 1e-13, "target");
  expect_cells_covered(covered_source(sm), src, 1e-13, "source");
  EXPECT_NEAR(sm.intersection_volume(), 1.0, 1e-13);
}

TEST(Supermesh, HalfCellOffsetCoincidentFaces) {
  // Offsets by half a cell along one, two and three axes: faces of the two meshes coincide
  // exactly (the hardest degenerate case for a front). The target covers the source.
  const std::array<Vec3, 3> offsets = {Vec3{0.5, 0, 0}, Vec3{0.5, 0.5, 0}, Vec3{0.5, 0.5, 0.5}};
  for (const Vec3& d : offsets) {
    const TetMesh src = kuhn({3, 3, 3});
    const TetMesh tgt = kuhn({4, 4, 4}, Vec3{-1, -1, -1} + d);
    const Supermesh sm = check_against_brute_force(
        src, tgt, "half offset (" + std::to_string(d.x) + "," + std::to_string(d.y) + "," + std::to_string(d.z) + ")");
    expect_cells_covered(covered_source(sm), src, 1e-13, "source");
    EXPECT_NEAR(sm.intersection_volume(), 27.0, 27.0 * 1e-13);
  }
  // And the same-sized meshes offset by half a cell: a partial overlap with coincident faces.
  const TetMesh a = kuhn({3, 3, 3});
  const TetMesh b = kuhn({3, 3, 3}, {0.5, 0.5, 0});
  const Supermesh sm = check_against_brute_force(a, b, "Kuhn 3^3 vs itself + (0.5,0.5,0)");
  EXPECT_NEAR(sm.intersection_volume(), 2.5 * 2.5 * 3, 1e-12);
}

TEST(Supermesh, TinyOffsets) {
  const TetMesh src = kuhn({3, 3, 3});
  for (const Vec3& d : {Vec3{1e-12, 0, 0}, Vec3{1e-12, -1e-12, 1e-12}, Vec3{0, 0, -3e-13}}) {
    const TetMesh tgt = kuhn({3, 3, 3}, d);
    const Supermesh sm = check_against_brute_force(src, tgt, "tiny offset");
    const double want = (3 - std::abs(d.x)) * (3 - std::abs(d.y)) * (3 - std::abs(d.z));
    EXPECT_NEAR(sm.intersection_volume(), want, 1e-12);
  }
}

TEST(Supermesh, FarFromOrigin) {
  const Vec3 far{1e6, -2e6, 3e6};
  const TetMesh src = kuhn({3, 3, 3}, far);
  const TetMesh tgt = kuhn({3, 3, 3}, far + Vec3{0.3, 0.2, 0.1});
  const Supermesh sm = check_against_brute_force(src, tgt, "far from origin (1e6), offset");
  EXPECT_NEAR(sm.intersection_volume(), 2.7 * 2.8 * 2.9, 1e-8);
  const Supermesh same = check_against_brute_force(src, src, "far from origin, identical");
  EXPECT_EQ(same.pieces.size(), src.num_cells());
  const TetMesh half = kuhn({3, 3, 3}, far + Vec3{0.5, 0, 0.5});
  check_against_brute_force(src, half, "far from origin, half offset");
}

TEST(Supermesh, SmallerBoxInsideBiggerBox) {
  const TetMesh big = kuhn({4, 4, 4});
  const TetMesh small = mapped(kuhn({3, 3, 3}, {0, 0, 0}, {0.5, 0.5, 0.5}), rigid({0, 0, 1}, 0.2, {1.3, 1.1, 1.2}));
  const Supermesh a = check_against_brute_force(big, small, "big box -> small rotated box");
  expect_cells_covered(covered(a), small, 1e-13, "target");
  const Supermesh b = check_against_brute_force(small, big, "small rotated box -> big box");
  expect_cells_covered(covered_source(b), small, 1e-13, "source");
  EXPECT_NEAR(b.intersection_volume(), 27 * 0.125, 1e-13);
}

TEST(Supermesh, PyramidOfCubes) {
  // Cubes (i, j, k) with max(|i - 1.5|, |j - 1.5|) < 2 - k: a stepped pyramid.
  const TetMesh pyramid = kuhn_subset({4, 4, 3}, [](int i, int j, int k) {
    return std::max(std::abs(i - 1.5), std::abs(j - 1.5)) < 2.0 - k;
  });
  const TetMesh box = mapped(kuhn({3, 3, 3}, {0, 0, 0}, {1.3, 1.3, 1.0}), rigid({1, 1, 0}, 0.1, {0.05, 0.1, 0.1}));
  check_against_brute_force(pyramid, box, "pyramid -> rotated box");
  check_against_brute_force(box, pyramid, "rotated box -> pyramid");
}

TEST(Supermesh, TwoComponents) {
  // A slab of cubes removed: two components; against a box that spans the gap, both ways.
  const TetMesh two = kuhn_subset({5, 2, 2}, [](int i, int, int) { return i != 2; });
  const TetMesh box = mapped(kuhn({2, 2, 2}, {0, 0, 0}, {2.1, 0.9, 0.9}), rigid({0, 1, 1}, 0.15, {0.4, 0.2, 0.1}));
  check_against_brute_force(two, box, "two components -> box");
  check_against_brute_force(box, two, "box -> two components");
  // A source cell big enough to cover parts of both components (and the gap between them).
  const TetMesh coarse = kuhn({1, 1, 1}, {-0.1, -0.2, -0.1}, {5.3, 2.4, 2.3});
  const Supermesh sm = check_against_brute_force(coarse, two, "one big cube -> two components");
  EXPECT_NEAR(sm.intersection_volume(), two.total_volume(), 1e-13 * two.total_volume());
}

TEST(Supermesh, LShapeAndHoles) {
  const TetMesh lshape = kuhn_subset({4, 4, 2}, [](int i, int j, int) { return i < 2 || j < 2; });
  // A column through the middle (a torus-like hole) and a closed cavity.
  const TetMesh column = kuhn_subset({4, 4, 2}, [](int i, int j, int) { return !(i == 1 || i == 2) || !(j == 1 || j == 2); });
  const TetMesh cavity = kuhn_subset({3, 3, 3}, [](int i, int j, int k) { return !(i == 1 && j == 1 && k == 1); });
  const TetMesh rotated = mapped(kuhn({3, 3, 2}, {0, 0, 0}, {1.3, 1.3, 1.0}), rigid({1, 2, 3}, 0.2, {0.1, 0.15, 0.05}));
  check_against_brute_force(lshape, rotated, "L-shape -> rotated box");
  check_against_brute_force(rotated, lshape, "rotated box -> L-shape");
  check_against_brute_force(column, rotated, "holed (column) -> rotated box");
  check_against_brute_force(rotated, column, "rotated box -> holed (column)");
  check_against_brute_force(cavity, kuhn({3, 3, 3}, {0.5, 0.5, 0.5}), "cavity -> half offset Kuhn");
  check_against_brute_force(kuhn({3, 3, 3}, {0.5, 0.5, 0.5}), cavity, "half offset Kuhn -> cavity");
  // Non-convex against non-convex, with coincident faces.
  check_against_brute_force(lshape, mapped(column, [](Vec3 p) { return p + Vec3{0.5, 0, 0}; }),
                            "L-shape -> holed, half offset");
  // Big source cells spanning the hole: the targets meeting a cell are not face-connected.
  const TetMesh coarse = kuhn({1, 1, 1}, {-0.2, -0.3, -0.1}, {4.5, 4.4, 2.3});
  check_against_brute_force(coarse, column, "one big cube -> holed");
  check_against_brute_force(coarse, lshape, "one big cube -> L-shape");
}

TEST(Supermesh, ComponentInsideOneSourceCell) {
  // A small target mesh strictly inside one source tetrahedron, plus one far away.
  const TetMesh src = kuhn({2, 2, 2});
  const TetMesh tgt = joined(kuhn({1, 1, 1}, {0.55, 0.3, 0.1}, {0.1, 0.1, 0.1}),
                            kuhn({1, 1, 1}, {1.5, 1.5, 1.6}, {0.2, 0.2, 0.2}), "two small components");
  const Supermesh sm = check_against_brute_force(src, tgt, "components inside source cells");
  EXPECT_NEAR(sm.intersection_volume(), 0.001 + 0.008, 1e-15);
}

TEST(Supermesh, NonConformingInterface) {
  // Two blocks glued at x = 1 without matching faces (2^3 and 3^3 cubes): the interface faces
  // have no neighbour, so the cells along it are risky. Source cells nearly inside one block,
  // with a vertex a little across the interface (rotations by 1e-3 to 1e-6), are covered by
  // that block up to the coverage tolerance and still have a piece in the other: the risky
  // targets seed the search for it.
  const TetMesh tgt = joined(kuhn({2, 2, 2}, {0, 0, 0}, {0.5, 0.5, 0.5}),
                            kuhn({3, 3, 3}, {1, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3}), "two blocks, non-conforming interface");
  ASSERT_NEAR(tgt.total_volume(), 2.0, 1e-14);
  const TetMesh rotated = mapped(kuhn({3, 2, 2}, {0, 0, 0}, {0.6, 0.45, 0.45}), rigid({1, 2, 3}, 0.1, {0.1, 0.05, 0.05}));
  check_against_brute_force(rotated, tgt, "rotated box -> two blocks");
  check_against_brute_force(tgt, rotated, "two blocks -> rotated box");
  for (const double angle : {1e-3, 1e-4, 5e-5, 3e-5, 2e-5, 1e-5, 1e-6}) {
    // Cells up to the interface, away from the other boundaries, tilted about an axis through
    // (1, 0.5, 0.5).
    const auto tilt = rigid({0, 1, 1}, angle, {0, 0, 0});
    const TetMesh near = mapped(kuhn({2, 2, 2}, {0.5, 0.25, 0.25}, {0.25, 0.25, 0.25}), [&](Vec3 p) {
      return tilt(p - Vec3{1, 0.5, 0.5}) + Vec3{1, 0.5, 0.5};
    });
    char name[64];
    std::snprintf(name, sizeof name, "tilted by %.0e -> two blocks", angle);
    check_against_brute_force(near, tgt, name);
  }
}

TEST(Supermesh, PolyhedraKeptMatchPieces) {
  const TetMesh src = kuhn({2, 2, 2});
  const TetMesh tgt = mapped(kuhn({2, 2, 2}), rigid({3, 1, 2}, 0.3, {0.2, 0.1, -0.1}));
  const Supermesh a = run(src, tgt, CandidateSearch::front, 2, true);
  const Supermesh b = run(src, tgt, CandidateSearch::front, 1, false);
  ASSERT_EQ(a.polyhedra.size(), a.pieces.size());
  EXPECT_TRUE(b.polyhedra.empty());
  EXPECT_EQ(pairs_of(a), pairs_of(b));
  for (std::size_t k = 0; k < a.pieces.size(); ++k) {
    EXPECT_EQ(a.polyhedra[k].volume(), a.pieces[k].volume);
    EXPECT_EQ(a.pieces[k].volume, b.pieces[k].volume);
    const Tet U = src.cell(static_cast<std::size_t>(a.pieces[k].source));
    const Tet V = tgt.cell(static_cast<std::size_t>(a.pieces[k].target));
    // The polyhedron is the kernel's for (U = source, V = target).
    EXPECT_EQ(tetia::intersect(U, V).volume(), a.polyhedra[k].volume());
  }
  const Supermesh c = run(src, tgt, CandidateSearch::rtree, 1, true);
  EXPECT_TRUE(bitwise_equal(a.pieces, c.pieces));
}

// A supermesh cannot outlive its meshes: given shared pointers it shares them, given references
// it copies them; either way its meshes are alive and unchanged after the caller's are gone.
TEST(Supermesh, KeepsItsMeshes) {
  Supermesh shared, copied;
  double volume = 0.0;
  {
    auto a = std::make_shared<const TetMesh>(kuhn({2, 2, 2}));
    auto b = std::make_shared<const TetMesh>(kuhn({3, 3, 3}, {0.1, 0.2, 0.3}, {0.6, 0.6, 0.6}));
    shared = tetia::supermesh(a, b);
    EXPECT_EQ(shared.source.get(), a.get());  // the same mesh, not a copy
    EXPECT_EQ(a.use_count(), 2);
    const TetMesh c = *a, d = *b;
    copied = tetia::supermesh(c, d);
    EXPECT_NE(copied.source.get(), &c);
    volume = shared.intersection_volume();
  }
  ASSERT_TRUE(shared.source && shared.target && copied.source && copied.target);
  EXPECT_EQ(shared.source.use_count(), 1);  // the caller's pointers are gone; the meshes are not
  EXPECT_EQ(shared.target->num_cells(), 6u * 27u);
  EXPECT_EQ(copied.source->nodes, shared.source->nodes);
  EXPECT_EQ(copied.target->cells, shared.target->cells);
  EXPECT_GT(volume, 0.0);
  EXPECT_EQ(tetia::remap_p0(shared, std::vector<double>(shared.source->num_cells(), 1.0)),
            tetia::remap_p0(copied, std::vector<double>(copied.source->num_cells(), 1.0)));
  EXPECT_THROW(tetia::supermesh(std::shared_ptr<const TetMesh>(), shared.target), std::invalid_argument);
}

TEST(Supermesh, EmptyAndDisjoint) {
  const TetMesh a = kuhn({2, 2, 2});
  const TetMesh b = kuhn({2, 2, 2}, {5, 0, 0});
  for (const auto search : {CandidateSearch::front, CandidateSearch::rtree}) {
    const Supermesh sm = run(a, b, search, 2);
    EXPECT_TRUE(sm.pieces.empty());
    EXPECT_EQ(sm.intersection_volume(), 0.0);
    ASSERT_TRUE(sm.source && sm.target);  // copies of a and b (the supermesh keeps its meshes)
    EXPECT_EQ(sm.source->nodes, a.nodes);
    EXPECT_EQ(sm.target->nodes, b.nodes);
  }
  // Touching along a face plane only.
  const TetMesh c = kuhn({2, 2, 2}, {2, 0, 0});
  EXPECT_TRUE(run(a, c, CandidateSearch::front, 1).pieces.empty());
}

TEST(Supermesh, FrontEqualsRtreeOnMeshesWithManyInteriorCells) {
  // Most source cells are interior: the front proper (not the R-tree fallback near the target
  // boundary) decides. The R-tree search tests every pair whose boxes overlap, so it is complete.
  const int n = 6;
  const TetMesh src = kuhn({n, n, n});
  const std::vector<std::pair<std::string, TetMesh>> targets = {
      {"identical", kuhn({n, n, n})},
      {"half offset x", kuhn({n + 1, n, n}, {-0.5, 0, 0})},
      {"half offset xyz", kuhn({n + 1, n + 1, n + 1}, {-0.5, -0.5, -0.5})},
      {"tiny offset", kuhn({n, n, n}, {1e-12, -1e-12, 1e-12})},
      {"finer, same domain", kuhn({n + 1, n + 1, n + 1}, {0, 0, 0}, {n / (n + 1.0), n / (n + 1.0), n / (n + 1.0)})},
      {"rotated", mapped(kuhn({n + 2, n + 2, n + 2}, {-1, -1, -1}), rigid({1, 1, 2}, 0.3, {0.5 * n, -0.2 * n, 0.1}))},
  };
  for (const auto& [name, tgt] : targets) {
    SCOPED_TRACE(name);
    const Supermesh f = run(src, tgt, CandidateSearch::front, 2);
    const Supermesh r = run(src, tgt, CandidateSearch::rtree, 1);
    EXPECT_TRUE(bitwise_equal(f.pieces, r.pieces));
    std::printf("  %-20s %zu pairs, candidates: front %zu, rtree %zu\n", name.c_str(), f.pieces.size(), f.candidates,
                r.candidates);
  }
}

TEST(Supermesh, ThreadsGiveIdenticalResultsOnALargerMesh) {
  // Several chunks (more than 4096 source cells), offset by a generic fraction of a cell.
  const int n = 12;
  const double h = 1.0 / n;
  const TetMesh src = kuhn({n, n, n}, {0, 0, 0}, {h, h, h});
  const TetMesh tgt = kuhn({n, n, n}, {0.3 * h, 0.2 * h, 0.1 * h}, {h, h, h});
  const Supermesh f1 = run(src, tgt, CandidateSearch::front, 1);
  const Supermesh f2 = run(src, tgt, CandidateSearch::front, 2);
  const Supermesh r1 = run(src, tgt, CandidateSearch::rtree, 1);
  const Supermesh r2 = run(src, tgt, CandidateSearch::rtree, 2);
  EXPECT_TRUE(bitwise_equal(f1.pieces, f2.pieces));
  EXPECT_TRUE(bitwise_equal(f1.pieces, r1.pieces));
  EXPECT_TRUE(bitwise_equal(r1.pieces, r2.pieces));
  EXPECT_EQ(f1.candidates, f2.candidates);
  // Three threads, and OpenMP's default.
  const Supermesh f3 = run(src, tgt, CandidateSearch::front, 3);
  const Supermesh f0 = run(src, tgt, CandidateSearch::front, 0);
  EXPECT_TRUE(bitwise_equal(f1.pieces, f3.pieces));
  EXPECT_TRUE(bitwise_equal(f1.pieces, f0.pieces));
  EXPECT_EQ(f1.candidates, f3.candidates);
  EXPECT_LT(f1.candidates, r1.candidates);
  // Sorted by (target, source), one piece per pair of cells.
  for (std::size_t k = 1; k < f1.pieces.size(); ++k) {
    const auto& a = f1.pieces[k - 1];
    const auto& b = f1.pieces[k];
    ASSERT_TRUE(a.target < b.target || (a.target == b.target && a.source < b.source)) << "pieces " << k - 1 << ", " << k;
  }
  const double want = (1 - 0.3 * h) * (1 - 0.2 * h) * (1 - 0.1 * h);
  EXPECT_NEAR(f1.intersection_volume(), want, 1e-13);
  // Every source cell inside the overlap is covered exactly.
  const auto cov = covered_source(f1);
  std::size_t checked = 0;
  for (std::size_t c = 0; c < src.num_cells(); ++c) {
    const Tet t = src.cell(c);
    bool inside = true;
    for (const Vec3& p : t) inside &= p.x >= 0.3 * h && p.y >= 0.2 * h && p.z >= 0.1 * h;
    if (!inside) continue;
    ++checked;
    EXPECT_NEAR(cov[c], src.volumes[c], 1e-13 * src.volumes[c]);
  }
  EXPECT_GT(checked, 0u);
  std::printf("  Kuhn %d^3 (%zu cells) vs offset: %zu pairs; front %zu candidates (%.3f s, 1 thread; %.3f s, 2), "
              "rtree %zu (%.3f s, 1 thread; %.3f s, 2)\n",
              n, src.num_cells(), f1.pieces.size(), f1.candidates, f1.seconds, f2.seconds, r1.candidates, r1.seconds,
              r2.seconds);
}

}  // namespace
