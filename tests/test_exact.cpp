// test_exact.cpp -- the exact reference (tetia::exact) against volumes (3D) and areas (2D) known
// in closed form, and against exact identities (symmetry, scaling, additivity over a
// decomposition) on random and on deliberately degenerate input.
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
#include "support/generators2d.hpp"

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

// =============================================================================================
// 2D: exact::area, exact::intersection_area.
// =============================================================================================

using tetia::Triangle;
using tetia::Vec2;
namespace gen2 = tetia::testgen2d;

const Triangle kRefTri{{{0, 0}, {1, 0}, {0, 1}}};

TEST(ExactArea, ReferenceTriangleInBothOrientations) {
  EXPECT_EQ(exact::area(kRefTri), mpq_class(1, 2));
  EXPECT_EQ(exact::area(Triangle{Vec2{0, 0}, Vec2{0, 1}, Vec2{1, 0}}), mpq_class(1, 2));
  EXPECT_EQ(exact::area(Triangle{Vec2{0, 0}, Vec2{1, 1}, Vec2{0.25, 0.25}}), 0);
  // 0.1 is not 1/10: the area is that of the doubles.
  const Triangle t{Vec2{0, 0}, Vec2{0.1, 0}, Vec2{0, 0.1}};
  EXPECT_EQ(exact::area(t), mpq_class(0.1) * mpq_class(0.1) / 2);
}

TEST(ExactIntersectionArea, IdenticalInEveryVertexOrder) {
  std::mt19937_64 rng(7);
  for (const Triangle& base : {kRefTri, gen2::unit_random_tri(rng)}) {
    const mpq_class a = exact::area(base);
    for (const auto& p : gen2::kPerms3)
      for (const auto& q : gen2::kPerms3)
        ASSERT_EQ(exact::intersection_area(gen2::permute(base, p), gen2::permute(base, q)), a);
  }
}

TEST(ExactIntersectionArea, Disjoint) {
  EXPECT_EQ(exact::intersection_area(kRefTri, gen2::translate(kRefTri, {2, 0})), 0);
  // Separated only by the slanted line x + y = 1.1, with overlapping bounding boxes.
  const Triangle far{Vec2{1, 1}, Vec2{1.1, 0}, Vec2{0, 1.1}};
  EXPECT_EQ(exact::intersection_area(kRefTri, far), 0);
  EXPECT_EQ(exact::intersection_area(far, kRefTri), 0);
}

TEST(ExactIntersectionArea, TouchingIsExactlyZero) {
  // Edge to edge across the hypotenuse x + y = 1, and across x = 0 (mirror image).
  const Triangle across{Vec2{1, 0}, Vec2{0, 1}, Vec2{1, 1}};
  const Triangle mirror{Vec2{0, 0}, Vec2{-1, 0}, Vec2{0, 1}};
  // A longer collinear edge: B's edge on x = 0 contains A's.
  const Triangle longer{Vec2{0, -1}, Vec2{0, 3}, Vec2{-1, 0}};
  // A shorter collinear edge inside A's, and a common vertex only.
  const Triangle shorter{Vec2{0, 0.25}, Vec2{0, 0.5}, Vec2{-1, 0}};
  const Triangle vertex = gen2::scale(kRefTri, -1.0);
  for (const Triangle& t : {across, mirror, longer, shorter, vertex}) {
    EXPECT_EQ(exact::intersection_area(kRefTri, t), 0);
    EXPECT_EQ(exact::intersection_area(t, kRefTri), 0);
  }
}

TEST(ExactIntersectionArea, HalfOverlapNestedAndTranslated) {
  // The two halves of the unit square's lower-left triangle cut by x = y: (0,0),(1,0),(1/2,1/2).
  const Triangle other_half{Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}};
  EXPECT_EQ(exact::intersection_area(kRefTri, other_half), mpq_class(1, 4));
  EXPECT_EQ(exact::intersection_area(other_half, kRefTri), mpq_class(1, 4));
  // Nested: the small one strictly inside, and a half-scaled copy sharing a corner.
  const Triangle big{Vec2{0, 0}, Vec2{4, 0}, Vec2{0, 4}};
  const Triangle small{Vec2{1, 1}, Vec2{2, 1}, Vec2{1, 2}};
  EXPECT_EQ(exact::intersection_area(big, small), mpq_class(1, 2));
  EXPECT_EQ(exact::intersection_area(small, big), mpq_class(1, 2));
  EXPECT_EQ(exact::intersection_area(kRefTri, gen2::scale(kRefTri, 0.5)), mpq_class(1, 8));
  // Translating by (t, 0) leaves a copy scaled by 1 - |t|.
  for (double t : {0.0, 1.0 / 1024, 0.125, 0.5, 0.75, 1.0, 1.25, -0.25, -0.5, -1.0, -3.0}) {
    const mpq_class s = 1 - abs(mpq_class(t));
    const mpq_class expected = s > 0 ? mpq_class(s * s / 2) : mpq_class(0);
    EXPECT_EQ(exact::intersection_area(kRefTri, gen2::translate(kRefTri, {t, 0})), expected) << t;
    EXPECT_EQ(exact::intersection_area(gen2::translate(kRefTri, {0, t}), kRefTri), expected) << t;
  }
}

TEST(ExactIntersectionArea, OrientationDoesNotMatter) {
  const Triangle big{Vec2{0, 0}, Vec2{4, 0}, Vec2{0, 4}};
  const Triangle cut{Vec2{-10, 11}, Vec2{11, -10}, Vec2{20, 20}};  // keeps x + y >= 1 of big
  for (const auto& p : gen2::kPerms3)
    for (const auto& q : gen2::kPerms3)
      ASSERT_EQ(exact::intersection_area(gen2::permute(big, p), gen2::permute(cut, q)),
                mpq_class(15, 2));
}

TEST(ExactIntersectionArea, StarOfDavid) {
  // A triangle and its point reflection through the centroid: a hexagon of 2/3 the area. An
  // affine image of the equilateral star, with exact coordinates.
  const Triangle a{Vec2{0, 0}, Vec2{3, 0}, Vec2{0, 3}};
  const Triangle b{Vec2{2, 2}, Vec2{-1, 2}, Vec2{2, -1}};
  EXPECT_EQ(exact::intersection_area(a, b), 3);
  EXPECT_EQ(exact::intersection_area(b, a), 3);
}

TEST(ExactIntersectionArea, CoordinatesOfVeryDifferentMagnitude) {
  // B = (t,0), (1,0), (t,1): for y >= 0 its slanted edge x + (1-t) y <= 1 is implied by
  // x + y <= 1, so A ∩ B = {x >= t} ∩ A, of area (1-t)^2 / 2. 1 + t is not a double, which is
  // why B is not a translated copy.
  for (double t : {0x1p-60, 0x1p-1000, 0x1p-1070}) {
    const Triangle b{Vec2{t, 0}, Vec2{1, 0}, Vec2{t, 1}};
    const mpq_class s = 1 - mpq_class(t);
    EXPECT_EQ(exact::intersection_area(kRefTri, b), s * s / 2) << t;
    EXPECT_EQ(exact::intersection_area(b, kRefTri), s * s / 2) << t;
  }
}

TEST(ExactIntersectionArea, FlatInputIsZero) {
  const Triangle flat{Vec2{0, 0}, Vec2{1, 1}, Vec2{0.25, 0.25}};
  const Triangle flat_inside{Vec2{0.125, 0.125}, Vec2{0.375, 0.25}, Vec2{0.625, 0.375}};
  const Triangle point{Vec2{0.1, 0.1}, Vec2{0.1, 0.1}, Vec2{0.1, 0.1}};
  for (const Triangle& f : {flat, flat_inside, point}) {
    EXPECT_EQ(exact::intersection_area(kRefTri, f), 0);
    EXPECT_EQ(exact::intersection_area(f, kRefTri), 0);
    EXPECT_EQ(exact::intersection_area(f, f), 0);
  }
}

TEST(ExactIntersectionArea, NonFiniteInputThrows) {
  Triangle bad = kRefTri;
  bad[2].y = std::nan("");
  EXPECT_THROW(exact::intersection_area(kRefTri, bad), std::domain_error);
  bad[2].y = INFINITY;
  EXPECT_THROW(exact::intersection_area(bad, kRefTri), std::domain_error);
  EXPECT_THROW(exact::area(bad), std::domain_error);
}

TEST(ExactIntersectionArea, LatticePartitionOfRandomTrianglesInTheSquare) {
  // Either diagonal cuts the unit square into two right triangles that tile it, so for W inside
  // the square the two pieces add up to |W|: edges shared by the two with opposite sides.
  const auto lat = gen2::lattice_tris();
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 300; ++trial) {
    Triangle w = gen2::unit_random_tri(rng);
    if (trial % 2 == 1)
      for (Vec2& p : w) p = {gen2::irand(rng, 0, 4) / 4.0, gen2::irand(rng, 0, 4) / 4.0};
    ASSERT_EQ(exact::intersection_area(lat[0], w) + exact::intersection_area(lat[1], w),
              exact::area(w)) << trial;
    ASSERT_EQ(exact::intersection_area(w, lat[2]) + exact::intersection_area(w, lat[3]),
              exact::area(w)) << trial;
  }
}

TEST(ExactIntersectionArea, RandomPairsSymmetricScaledAndBounded) {
  std::mt19937_64 rng(2024);
  for (int trial = 0; trial < 500; ++trial) {
    const Triangle a = gen2::unit_random_tri(rng), b = gen2::unit_random_tri(rng);
    const mpq_class ar = exact::intersection_area(a, b);
    ASSERT_GE(ar, 0);
    ASSERT_LE(ar, exact::area(a));
    ASSERT_LE(ar, exact::area(b));
    ASSERT_EQ(exact::intersection_area(b, a), ar) << trial;
    ASSERT_EQ(exact::intersection_area(gen2::permute(a, {0, 2, 1}), gen2::permute(b, {1, 2, 0})), ar)
        << trial;
    // Scaling by a power of two is exact in doubles and multiplies the area by its square.
    ASSERT_EQ(exact::intersection_area(gen2::scale(a, 0x1p-300), gen2::scale(b, 0x1p-300)),
              ar / (mpq_class(1) << 600)) << trial;
    ASSERT_EQ(exact::intersection_area(gen2::scale(a, 0x1p+200), gen2::scale(b, 0x1p+200)),
              ar * (mpq_class(1) << 400)) << trial;
  }
}

TEST(ExactIntersectionArea, AdditiveOverASplitOfB) {
  // Splitting B at an interior point p into three triangles splits A ∩ B into three pieces
  // whose areas must add up exactly; grid input adds collinear edges and vertices on edges.
  std::mt19937_64 rng(99);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Triangle a = gen2::unit_random_tri(rng), b = gen2::unit_random_tri(rng);
    if (trial % 2 == 1) {
      for (Triangle* t : {&a, &b})
        for (Vec2& p : *t) p = {gen2::irand(rng, 0, 4) / 4.0, gen2::irand(rng, 0, 4) / 4.0};
    }
    // (b0 + b1 + 2 b2) / 4: exact on the grid; used only if the pieces' exact areas add up.
    const Vec2 p = 0.25 * (b[0] + b[1] + 2.0 * b[2]);
    mpq_class pieces = 0, sum = 0;
    for (int k = 0; k < 3; ++k) {
      Triangle piece = b;
      piece[static_cast<std::size_t>(k)] = p;
      pieces += exact::area(piece);
      sum += exact::intersection_area(a, piece);
    }
    if (pieces != exact::area(b) || sgn(pieces) == 0) continue;
    ++checked;
    ASSERT_EQ(sum, exact::intersection_area(a, b)) << "trial " << trial;
  }
  EXPECT_GT(checked, 300);
}

TEST(ExactIntersectionArea, DoubleIsCorrectlyRounded) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    // Include scales where the area is subnormal or vanishes (2^-1060 and below).
    const double s = std::ldexp(1.0, trial % 4 == 0 ? -525 - trial % 16 : 0);
    const Triangle a = gen2::scale(gen2::unit_random_tri(rng), s);
    const Triangle b = gen2::scale(gen2::unit_random_tri(rng), s);
    const mpq_class q = exact::intersection_area(a, b);
    const double r = exact::intersection_area_double(a, b);
    ASSERT_GE(r, 0.0);
    expect_nearest(r, q);
  }
  EXPECT_EQ(exact::intersection_area_double(kRefTri, kRefTri), 0.5);
  // A quadrilateral of area 2/3, which is not a double: x/2 + y <= 1 against x + y/2 <= 1, the
  // corners (0,0), (1,0), (2/3,2/3), (0,1). IEEE division rounds to nearest as well.
  const Triangle wide{Vec2{0, 0}, Vec2{2, 0}, Vec2{0, 1}};
  const Triangle tall{Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 2}};
  EXPECT_EQ(exact::intersection_area(wide, tall), mpq_class(2, 3));
  EXPECT_EQ(exact::intersection_area_double(wide, tall), 2.0 / 3.0);
}

TEST(ExactIntersectionArea, TimingOfRandomPairs) {
  std::mt19937_64 rng(1);
  constexpr int kPairs = 5000;
  std::vector<std::pair<Triangle, Triangle>> pairs;
  for (int i = 0; i < kPairs; ++i) pairs.emplace_back(gen2::unit_random_tri(rng), gen2::unit_random_tri(rng));
  int nonzero = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& [a, b] : pairs) nonzero += sgn(exact::intersection_area(a, b)) != 0;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("exact::intersection_area: %.1f us per random pair (%d of %d nonzero)\n",
              1e6 * s / kPairs, nonzero, kPairs);
  RecordProperty("us_per_pair_2d", std::to_string(1e6 * s / kPairs));
  EXPECT_GT(nonzero, 0);
}

}  // namespace
