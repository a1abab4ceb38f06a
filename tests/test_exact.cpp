// test_exact.cpp -- the exact reference (tetia::exact) against volumes known in closed form, and
// against exact identities (symmetry, scaling, additivity over a decomposition) on random and on
// deliberately degenerate input.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tetia/exact.hpp"
#include "tetia/geometry.hpp"
#include "support/generators.hpp"

namespace {

using tetia::Tet;
using tetia::Vec3;
namespace exact = tetia::exact;

const Tet& kRef = tetia::testgen::kRefTet;
using tetia::testgen::kuhn_tets;






// All 24 vertex orders of t.
std::array<Tet, 24> permutations(const Tet& t) {
  std::array<Tet, 24> out;
  std::array<int, 4> p = {0, 1, 2, 3};
  int i = 0;
  do {
    out[i++] = {t[p[0]], t[p[1]], t[p[2]], t[p[3]]};
  } while (std::next_permutation(p.begin(), p.end()));
  return out;
}

TEST(ExactVolume, ReferenceTetInBothOrientations) {
  EXPECT_EQ(exact::volume(kRef), mpq_class(1, 6));
  Tet flipped = kRef;
  std::swap(flipped[0], flipped[1]);
  EXPECT_EQ(exact::volume(flipped), mpq_class(1, 6));
  EXPECT_EQ(exact::volume({Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0}}), 0);
}

TEST(ExactIntersection, IdenticalInEveryVertexOrder) {
  std::mt19937_64 rng(7);
  for (const Tet& base : {kRef, tetia::testgen::unit_random_tet(rng)}) {
    const mpq_class vol = exact::volume(base);
    const auto perms = permutations(base);
    for (const Tet& a : perms) {
      for (const Tet& b : perms) {
        ASSERT_EQ(exact::intersection_volume(a, b), vol);
      }
    }
  }
}

TEST(ExactIntersection, Disjoint) {
  EXPECT_EQ(exact::intersection_volume(kRef, tetia::testgen::translate(kRef, {2, 0, 0})), 0);
  // Separated only by the slanted plane x + y + z = 1.1, with overlapping bounding boxes.
  const Tet far = {Vec3{1, 1, 1}, Vec3{0.6, 0.6, 0}, Vec3{0, 0.6, 0.6}, Vec3{0.6, 0, 0.6}};
  EXPECT_EQ(exact::intersection_volume(kRef, far), 0);
  EXPECT_EQ(exact::intersection_volume(far, kRef), 0);
}

TEST(ExactIntersection, TouchingIsExactlyZero) {
  // Face to face: the other side of the face x + y + z = 1.
  const Tet face = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 1, 1}};
  EXPECT_EQ(exact::intersection_volume(kRef, face), 0);
  EXPECT_EQ(exact::intersection_volume(face, kRef), 0);
  // Mirror image through x = 0: shares the face x = 0.
  const Tet mirror = {Vec3{0, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  EXPECT_EQ(exact::intersection_volume(kRef, mirror), 0);
  // A larger face partly overlapping: the face of `big` on x = 0 contains U's.
  const Tet big = {Vec3{0, -1, -1}, Vec3{0, 3, -1}, Vec3{0, -1, 3}, Vec3{-1, 0, 0}};
  EXPECT_EQ(exact::intersection_volume(kRef, big), 0);
  // Along an edge and at a vertex.
  const Tet edge = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, -1, 0}, Vec3{0, 0, -1}};
  EXPECT_EQ(exact::intersection_volume(kRef, edge), 0);
  const Tet vertex = tetia::testgen::translate(tetia::testgen::scale(kRef, -1.0), {0, 0, 0});
  EXPECT_EQ(exact::intersection_volume(kRef, vertex), 0);
}

TEST(ExactIntersection, KuhnTetrahedra) {
  const auto kuhn = kuhn_tets();
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(exact::volume(kuhn[i]), mpq_class(1, 6));
    for (int j = 0; j < 6; ++j) {
      EXPECT_EQ(exact::intersection_volume(kuhn[i], kuhn[j]), i == j ? mpq_class(1, 6) : 0)
          << i << " " << j;
    }
    // The reference tetrahedron is cut into six congruent pieces by the planes x = y, y = z, x = z.
    EXPECT_EQ(exact::intersection_volume(kuhn[i], kRef), mpq_class(1, 36)) << i;
  }
}

TEST(ExactIntersection, KuhnPartitionOfRandomTetsInTheCube) {
  // The Kuhn tetrahedra tile the cube, so for W inside the cube the pieces add up to vol(W).
  // Exercises facets on planes shared by two Kuhn tetrahedra (coplanar with opposite sides).
  const auto kuhn = kuhn_tets();
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 150; ++trial) {
    const Tet w = trial % 2 == 0 ? tetia::testgen::unit_random_tet(rng) : tetia::testgen::quarter_grid_tet(rng);
    mpq_class sum = 0;
    for (const Tet& k : kuhn) sum += exact::intersection_volume(k, w);
    ASSERT_EQ(sum, exact::volume(w)) << "trial " << trial;
  }
}

TEST(ExactIntersection, HalfScaledCopy) {
  EXPECT_EQ(exact::intersection_volume(kRef, tetia::testgen::scale(kRef, 0.5)), mpq_class(1, 48));
  EXPECT_EQ(exact::intersection_volume(tetia::testgen::scale(kRef, 0.5), kRef), mpq_class(1, 48));
}

TEST(ExactIntersection, CornerCutByTranslation) {
  // Translating by (t, 0, 0) leaves the corner {x >= max(t, 0), x + y + z <= 1 + min(t, 0)}, a
  // copy scaled by 1 - |t|. Negative t exercises coplanar faces y = 0, z = 0 on the same side.
  for (double t : {0.0, 1.0 / 1024, 0.125, 0.25, 0.5, 0.75, 1.0 - 1.0 / 1024, 1.0, 1.25, -0.25,
                   -0.5, -0.75, -1.0, -3.0}) {
    const mpq_class s = 1 - abs(mpq_class(t));
    const mpq_class expected = s > 0 ? mpq_class(s * s * s / 6) : mpq_class(0);
    EXPECT_EQ(exact::intersection_volume(kRef, tetia::testgen::translate(kRef, {t, 0, 0})), expected) << t;
    EXPECT_EQ(exact::intersection_volume(tetia::testgen::translate(kRef, {0, 0, t}), kRef), expected) << t;
  }
}

TEST(ExactIntersection, CoordinatesOfVeryDifferentMagnitude) {
  // 1 + t is not a double for tiny t, so instead of a translated copy V has the vertices
  // (t,0,0), (1,0,0), (t,1,0), (t,0,1): V = {x >= t, y >= 0, z >= 0, x + (1-t)(y+z) <= 1}. For
  // y + z >= 0 the last constraint is implied by U's x + y + z <= 1, so U ∩ V is U's corner
  // {x >= t}, of volume (1-t)^3/6. 2^-1000 and the subnormal 2^-1070 need integers of over a
  // thousand bits after scaling to a common power of two.
  for (double t : {0x1p-60, 0x1p-1000, 0x1p-1070}) {
    const Tet v = {Vec3{t, 0, 0}, Vec3{1, 0, 0}, Vec3{t, 1, 0}, Vec3{t, 0, 1}};
    const mpq_class s = 1 - mpq_class(t);
    EXPECT_EQ(exact::intersection_volume(kRef, v), s * s * s / 6) << t;
    EXPECT_EQ(exact::intersection_volume(v, kRef), s * s * s / 6) << t;
  }
}

TEST(ExactIntersection, CoplanarFacesWithKnownVolume) {
  // V inside U, sharing the three coordinate faces: the intersection is V.
  const Tet inner = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 0.5}};
  EXPECT_EQ(exact::intersection_volume(kRef, inner), mpq_class(1, 12));
  // Shares the faces z = 0, y = 0, x = 0 and cuts off the corner at e3, a tetrahedron of volume
  // 1/27 (the plane x + y + 4z = 2 meets U's edges at (0,0,1/2), (2/3,0,1/3), (0,2/3,1/3)).
  const Tet wide = {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}, Vec3{0, 0, 0.5}};
  EXPECT_EQ(exact::intersection_volume(kRef, wide), mpq_class(7, 54));
  EXPECT_EQ(exact::intersection_volume(wide, kRef), mpq_class(7, 54));
  EXPECT_EQ(exact::intersection_volume_double(kRef, wide), 7.0 / 54.0);  // division is rounded
  EXPECT_EQ(exact::intersection_volume_double(kRef, kRef), 1.0 / 6.0);
}

TEST(ExactIntersection, FlatInputIsZero) {
  const Tet flat = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.25, 0.25, 0}};
  const Tet flat_inside = {Vec3{0.1, 0.1, 0.1}, Vec3{0.5, 0.1, 0.1}, Vec3{0.1, 0.5, 0.1},
                           Vec3{0.3, 0.3, 0.1}};
  const Tet collinear = {Vec3{0, 0, 0}, Vec3{1, 1, 1}, Vec3{0.5, 0.5, 0.5}, Vec3{0.25, 0.25, 0.25}};
  const Tet point = {Vec3{0.1, 0.1, 0.1}, Vec3{0.1, 0.1, 0.1}, Vec3{0.1, 0.1, 0.1},
                     Vec3{0.1, 0.1, 0.1}};
  for (const Tet& f : {flat, flat_inside, collinear, point}) {
    EXPECT_EQ(exact::intersection_volume(kRef, f), 0);
    EXPECT_EQ(exact::intersection_volume(f, kRef), 0);
    EXPECT_EQ(exact::intersection_volume(f, f), 0);
  }
}

TEST(ExactIntersection, NonFiniteInputThrows) {
  Tet bad = kRef;
  bad[2].y = std::nan("");
  EXPECT_THROW(exact::intersection_volume(kRef, bad), std::domain_error);
  bad[2].y = INFINITY;
  EXPECT_THROW(exact::intersection_volume(bad, kRef), std::domain_error);
  EXPECT_THROW(exact::volume(bad), std::domain_error);
}

TEST(ExactIntersection, RandomPairsSymmetricScaledAndBounded) {
  std::mt19937_64 rng(2024);
  for (int trial = 0; trial < 300; ++trial) {
    const bool grid = trial % 3 == 2;
    const Tet u = grid ? tetia::testgen::quarter_grid_tet(rng) : tetia::testgen::unit_random_tet(rng);
    const Tet v = grid ? tetia::testgen::quarter_grid_tet(rng) : tetia::testgen::unit_random_tet(rng);
    const mpq_class vol = exact::intersection_volume(u, v);
    ASSERT_GE(vol, 0);
    ASSERT_LE(vol, exact::volume(u));
    ASSERT_LE(vol, exact::volume(v));
    ASSERT_EQ(exact::intersection_volume(v, u), vol) << trial;
    Tet u2 = u, v2 = v;
    std::swap(u2[1], u2[3]);  // orientation reversed
    std::rotate(v2.begin(), v2.begin() + 1, v2.end());
    ASSERT_EQ(exact::intersection_volume(u2, v2), vol) << trial;
    // Scaling by a power of two is exact in doubles and multiplies the volume by its cube.
    ASSERT_EQ(exact::intersection_volume(tetia::testgen::scale(u, 0x1p-300), tetia::testgen::scale(v, 0x1p-300)),
              vol / (mpq_class(1) << 900))
        << trial;
    ASSERT_EQ(exact::intersection_volume(tetia::testgen::scale(u, 0x1p+200), tetia::testgen::scale(v, 0x1p+200)),
              vol * (mpq_class(1) << 600))
        << trial;
  }
}

TEST(ExactIntersection, AdditiveOverASplitOfV) {
  // Splitting V at an interior point p into four tetrahedra (p with each face) splits U ∩ V into
  // four pieces whose volumes must add up exactly; the pieces share faces through p and
  // p's faces meet U's facets in every configuration. Grid input adds coplanar faces.
  std::mt19937_64 rng(99);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool grid = trial % 2 == 1;
    const Tet u = grid ? tetia::testgen::quarter_grid_tet(rng) : tetia::testgen::unit_random_tet(rng);
    const Tet v = grid ? tetia::testgen::quarter_grid_tet(rng) : tetia::testgen::unit_random_tet(rng);
    // The rounded centroid (exact on the grid); used only if it is inside V, which the volumes
    // of the four pieces verify exactly.
    const Vec3 p = 0.25 * (v[0] + v[1] + v[2] + v[3]);
    mpq_class pieces_volume = 0;
    mpq_class sum = 0;
    for (int k = 0; k < 4; ++k) {
      Tet piece = v;
      piece[k] = p;
      pieces_volume += exact::volume(piece);
      sum += exact::intersection_volume(u, piece);
    }
    if (pieces_volume != exact::volume(v)) continue;
    ++checked;
    ASSERT_EQ(sum, exact::intersection_volume(u, v)) << "trial " << trial;
  }
  EXPECT_GT(checked, 200);
}

// |r - q| is no larger than for either neighbouring double: r is a nearest double to q.
void expect_nearest(double r, const mpq_class& q) {
  const mpq_class err = abs(mpq_class(r) - q);
  EXPECT_LE(err, abs(mpq_class(std::nextafter(r, INFINITY)) - q));
  EXPECT_LE(err, abs(mpq_class(std::nextafter(r, -INFINITY)) - q));
}

TEST(ExactIntersection, DoubleIsCorrectlyRounded) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    // Include scales where the volume is subnormal (2^-1050 / 6 and so on) or vanishes.
    const double scale = std::ldexp(1.0, trial % 4 == 0 ? -348 - trial % 16 : 0);
    const Tet u = tetia::testgen::scale(tetia::testgen::unit_random_tet(rng), scale), v = tetia::testgen::scale(tetia::testgen::unit_random_tet(rng), scale);
    const mpq_class q = exact::intersection_volume(u, v);
    const double r = exact::intersection_volume_double(u, v);
    ASSERT_GE(r, 0.0);
    expect_nearest(r, q);
  }
  const Tet tiny = tetia::testgen::scale(kRef, 0x1p-350);  // volume 2^-1050 / 6: 21 significant bits left
  expect_nearest(exact::intersection_volume_double(tiny, tiny), exact::volume(tiny));
}

TEST(ExactIntersection, TimingOfRandomPairs) {
  std::mt19937_64 rng(1);
  constexpr int kPairs = 2000;
  std::vector<std::pair<Tet, Tet>> pairs;
  for (int i = 0; i < kPairs; ++i) pairs.emplace_back(tetia::testgen::unit_random_tet(rng), tetia::testgen::unit_random_tet(rng));
  int nonzero = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& [u, v] : pairs) nonzero += sgn(exact::intersection_volume(u, v)) != 0;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("exact::intersection_volume: %.1f us per random pair (%d of %d nonzero)\n",
              1e6 * s / kPairs, nonzero, kPairs);
  RecordProperty("us_per_pair", std::to_string(1e6 * s / kPairs));
  EXPECT_GT(nonzero, 0);
}

}  // namespace
