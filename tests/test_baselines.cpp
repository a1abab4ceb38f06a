// test_baselines.cpp -- the floating-point baselines (Sutherland-Hodgman clipping and PANG-style
// hull), 3D and 2D, against closed-form volumes and areas and against the exact reference.
//
// Tolerances: a method that computes intersection points in doubles has an absolute error of a
// few ulps of the coordinates, i.e. a volume error of about 1e-16 times the volume of the input
// tetrahedra, however small the intersection. So agreement is asserted relative to
// max(vol U, vol V); agreement relative to the intersection volume itself is counted and printed
// (slivers of volume 1e-9 cannot be had to 1e-12 of themselves from rounded points).
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tetia/baselines.hpp"
#include "tetia/exact.hpp"
#include "tetia/geometry.hpp"
#include "support/generators.hpp"
#include "support/generators2d.hpp"

namespace {

using tetia::Tet;
using tetia::Vec3;
namespace baselines = tetia::baselines;
namespace exact = tetia::exact;

const Tet& kRef = tetia::testgen::kRefTet;
using tetia::testgen::kuhn_tets;






double scale_of(const Tet& u, const Tet& v) { return std::max(tetia::volume(u), tetia::volume(v)); }

struct Method {
  const char* name;
  double (*fn)(const Tet&, const Tet&);
};
const Method kMethods[] = {{"clip", &baselines::clip_volume}, {"pang", &baselines::pang_volume}};

class Baseline : public ::testing::TestWithParam<Method> {
 protected:
  double operator()(const Tet& u, const Tet& v) const { return GetParam().fn(u, v); }
};

INSTANTIATE_TEST_SUITE_P(Methods, Baseline, ::testing::ValuesIn(kMethods),
                         [](const ::testing::TestParamInfo<Method>& info) {
                           return std::string(info.param.name);
                         });

constexpr double kTol = 1e-14;  // closed-form cases: volumes of order 0.1

TEST_P(Baseline, IdenticalTetrahedra) {
  const auto& f = *this;
  EXPECT_NEAR(f(kRef, kRef), 1.0 / 6, kTol);
  Tet permuted = {kRef[3], kRef[1], kRef[0], kRef[2]};
  EXPECT_NEAR(f(kRef, permuted), 1.0 / 6, kTol);
  EXPECT_NEAR(f(permuted, kRef), 1.0 / 6, kTol);
  std::mt19937_64 rng(7);
  const Tet r = tetia::testgen::unit_random_tet(rng);
  const Tet r2 = {r[2], r[0], r[3], r[1]};
  EXPECT_NEAR(f(r, r2), tetia::volume(r), kTol);
}

TEST_P(Baseline, DisjointAndTouchingAreZero) {
  const auto& f = *this;
  EXPECT_EQ(f(kRef, tetia::testgen::translate(kRef, {2, 0, 0})), 0.0);
  const Tet face = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 1, 1}};
  EXPECT_EQ(f(kRef, face), 0.0);
  EXPECT_EQ(f(face, kRef), 0.0);
  const Tet mirror = {Vec3{0, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  EXPECT_EQ(f(kRef, mirror), 0.0);
  EXPECT_EQ(f(mirror, kRef), 0.0);
  const Tet edge = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, -1, 0}, Vec3{0, 0, -1}};
  EXPECT_EQ(f(kRef, edge), 0.0);
  EXPECT_EQ(f(kRef, tetia::testgen::scale(kRef, -1.0)), 0.0);  // a common vertex
}

TEST_P(Baseline, KuhnTetrahedra) {
  const auto& f = *this;
  const auto kuhn = kuhn_tets();
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      EXPECT_NEAR(f(kuhn[i], kuhn[j]), i == j ? 1.0 / 6 : 0.0, kTol) << i << " " << j;
    }
    EXPECT_NEAR(f(kuhn[i], kRef), 1.0 / 36, kTol) << i;
    EXPECT_NEAR(f(kRef, kuhn[i]), 1.0 / 36, kTol) << i;
  }
}

TEST_P(Baseline, ScaledAndTranslatedCopies) {
  const auto& f = *this;
  EXPECT_NEAR(f(kRef, tetia::testgen::scale(kRef, 0.5)), 1.0 / 48, kTol);
  EXPECT_NEAR(f(tetia::testgen::scale(kRef, 0.5), kRef), 1.0 / 48, kTol);
  for (double t : {1.0 / 1024, 0.125, 0.25, 0.5, 0.75, -0.25, -0.5}) {
    const double s = 1 - std::abs(t);
    EXPECT_NEAR(f(kRef, tetia::testgen::translate(kRef, {t, 0, 0})), s * s * s / 6, kTol) << t;
    EXPECT_NEAR(f(tetia::testgen::translate(kRef, {0, t, 0}), kRef), s * s * s / 6, kTol) << t;
  }
  EXPECT_EQ(f(kRef, tetia::testgen::translate(kRef, {1.5, 0, 0})), 0.0);
}

TEST_P(Baseline, CoplanarFaces) {
  const auto& f = *this;
  const Tet inner = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 0.5}};
  EXPECT_NEAR(f(kRef, inner), 1.0 / 12, kTol);
  EXPECT_NEAR(f(inner, kRef), 1.0 / 12, kTol);
  const Tet wide = {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}, Vec3{0, 0, 0.5}};
  EXPECT_NEAR(f(kRef, wide), 7.0 / 54, kTol);
  EXPECT_NEAR(f(wide, kRef), 7.0 / 54, kTol);
}

TEST_P(Baseline, FlatInputIsZero) {
  const auto& f = *this;
  const Tet flat = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.25, 0.25, 0}};
  const Tet flat_inside = {Vec3{0.1, 0.1, 0.1}, Vec3{0.5, 0.1, 0.1}, Vec3{0.1, 0.5, 0.1},
                           Vec3{0.3, 0.3, 0.1}};
  for (const Tet& t : {flat, flat_inside}) {
    EXPECT_EQ(f(kRef, t), 0.0);
    EXPECT_EQ(f(t, kRef), 0.0);
  }
}

TEST_P(Baseline, BadInputGivesAFiniteNonNegativeValue) {
  const auto& f = *this;
  Tet nan = kRef;
  nan[1].x = std::nan("");
  Tet inf = kRef;
  inf[2].z = INFINITY;
  EXPECT_EQ(f(kRef, nan), 0.0);
  EXPECT_EQ(f(inf, kRef), 0.0);
  // Products of coordinates overflow (1e200^2) or underflow (1e-200^3): no promise on the value,
  // but no NaN, no negative, no crash.
  std::mt19937_64 rng(3);
  for (double s : {1e200, 1e-200, 1e100, 1e-110}) {
    for (int i = 0; i < 50; ++i) {
      const double r = f(tetia::testgen::scale(tetia::testgen::unit_random_tet(rng), s), tetia::testgen::scale(tetia::testgen::unit_random_tet(rng), s));
      EXPECT_TRUE(std::isfinite(r) && r >= 0.0) << s << " " << r;
    }
  }
}

// The comparison the paper makes: 2000 random pairs, four uniform points in [0,1]^3 each.
TEST_P(Baseline, AgreesWithExactOnRandomPairs) {
  const auto& f = *this;
  std::mt19937_64 rng(20240611);
  int failures = 0, strict_failures = 0, nonzero = 0;
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Tet u = tetia::testgen::unit_random_tet(rng), v = tetia::testgen::unit_random_tet(rng);
    const double e = exact::intersection_volume_double(u, v);
    const double r = f(u, v);
    ASSERT_TRUE(std::isfinite(r) && r >= 0.0);
    const double err = std::abs(r - e);
    worst = std::max(worst, err / scale_of(u, v));
    if (err > 1e-12 * scale_of(u, v)) ++failures;
    if (err > 1e-12 * e) ++strict_failures;
    nonzero += e > 0.0;
  }
  std::printf("%s: %d of 2000 random pairs off by more than 1e-12 max(vol U, vol V) (worst %.2e);"
              " %d off by more than 1e-12 of the exact intersection volume (%d nonzero)\n",
              GetParam().name, failures, worst, strict_failures, nonzero);
  EXPECT_EQ(failures, 0);
}

// Coordinates on a coarse grid: coplanar faces, shared vertices and edges, vertices on planes.
// Neither method promises anything here; these are the results they give, kept from regressing.
TEST_P(Baseline, AgreesWithExactOnGridPairs) {
  const auto& f = *this;
  std::mt19937_64 rng(4);
  int failures = 0;
  for (int i = 0; i < 2000; ++i) {
    const Tet u = tetia::testgen::quarter_grid_tet(rng), v = tetia::testgen::quarter_grid_tet(rng);
    const double e = exact::intersection_volume_double(u, v);
    const double r = f(u, v);
    ASSERT_TRUE(std::isfinite(r) && r >= 0.0);
    if (std::abs(r - e) > 1e-12 * std::max(scale_of(u, v), 1e-300)) ++failures;
  }
  std::printf("%s: %d of 2000 grid pairs off by more than 1e-12 max(vol U, vol V)\n",
              GetParam().name, failures);
  EXPECT_EQ(failures, 0);
}

TEST_P(Baseline, Timing) {
  const auto& f = *this;
  std::mt19937_64 rng(1);
  const int pairs = GetParam().fn == &baselines::clip_volume ? 200000 : 20000;
  std::vector<std::pair<Tet, Tet>> input;
  input.reserve(pairs);
  for (int i = 0; i < pairs; ++i) input.emplace_back(tetia::testgen::unit_random_tet(rng), tetia::testgen::unit_random_tet(rng));
  double sum = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& [u, v] : input) sum += f(u, v);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %.0f ns per random pair, %.2f million pairs/s (sum %.6f)\n", GetParam().name,
              1e9 * s / pairs, pairs / s / 1e6, sum);
  RecordProperty("ns_per_pair", std::to_string(1e9 * s / pairs));
  EXPECT_GT(sum, 0.0);
}

// =============================================================================================
// 2D: clip_area and pang_area. The same tolerance reasoning: absolute errors of a few ulps of the
// coordinates, so agreement is asserted relative to max(area A, area B).
// =============================================================================================

using tetia::Triangle;
using tetia::Vec2;
namespace gen2 = tetia::testgen2d;

const Triangle kRefTri{{{0, 0}, {1, 0}, {0, 1}}};

struct Method2D {
  const char* name;
  double (*fn)(const Triangle&, const Triangle&);
};
const Method2D kMethods2D[] = {{"clip", &baselines::clip_area}, {"pang", &baselines::pang_area}};

class Baseline2D : public ::testing::TestWithParam<Method2D> {
 protected:
  double operator()(const Triangle& a, const Triangle& b) const { return GetParam().fn(a, b); }
};

INSTANTIATE_TEST_SUITE_P(Methods, Baseline2D, ::testing::ValuesIn(kMethods2D),
                         [](const ::testing::TestParamInfo<Method2D>& info) {
                           return std::string(info.param.name);
                         });

double scale_of(const Triangle& a, const Triangle& b) {
  return std::max(tetia::area(a), tetia::area(b));
}

TEST_P(Baseline2D, IdenticalTrianglesInEveryOrder) {
  const auto& f = *this;
  std::mt19937_64 rng(7);
  for (const Triangle& t : {kRefTri, gen2::unit_random_tri(rng)}) {
    for (const auto& p : gen2::kPerms3)
      for (const auto& q : gen2::kPerms3)
        EXPECT_NEAR(f(gen2::permute(t, p), gen2::permute(t, q)), tetia::area(t), kTol);
  }
}

TEST_P(Baseline2D, DisjointAndTouchingAreZero) {
  const auto& f = *this;
  EXPECT_EQ(f(kRefTri, gen2::translate(kRefTri, {2, 0})), 0.0);
  const Triangle far{Vec2{1, 1}, Vec2{1.1, 0}, Vec2{0, 1.1}};
  const Triangle across{Vec2{1, 0}, Vec2{0, 1}, Vec2{1, 1}};
  const Triangle mirror{Vec2{0, 0}, Vec2{-1, 0}, Vec2{0, 1}};
  const Triangle longer{Vec2{0, -1}, Vec2{0, 3}, Vec2{-1, 0}};
  const Triangle vertex = gen2::scale(kRefTri, -1.0);
  for (const Triangle& t : {far, across, mirror, longer, vertex}) {
    EXPECT_EQ(f(kRefTri, t), 0.0);
    EXPECT_EQ(f(t, kRefTri), 0.0);
  }
}

TEST_P(Baseline2D, ClosedForms) {
  const auto& f = *this;
  const Triangle other_half{Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}};
  EXPECT_NEAR(f(kRefTri, other_half), 0.25, kTol);
  EXPECT_NEAR(f(other_half, kRefTri), 0.25, kTol);
  const Triangle big{Vec2{0, 0}, Vec2{4, 0}, Vec2{0, 4}};
  const Triangle small{Vec2{1, 1}, Vec2{2, 1}, Vec2{1, 2}};
  EXPECT_NEAR(f(big, small), 0.5, kTol);
  EXPECT_NEAR(f(small, big), 0.5, kTol);
  const Triangle cut{Vec2{-10, 11}, Vec2{11, -10}, Vec2{20, 20}};
  EXPECT_NEAR(f(big, cut), 7.5, 1e-13);
  EXPECT_NEAR(f(cut, big), 7.5, 1e-13);
  // Star of David (affine image): a hexagon of 2/3 the area.
  const Triangle a{Vec2{0, 0}, Vec2{3, 0}, Vec2{0, 3}};
  const Triangle b{Vec2{2, 2}, Vec2{-1, 2}, Vec2{2, -1}};
  EXPECT_NEAR(f(a, b), 3.0, 1e-14);
  EXPECT_NEAR(f(b, a), 3.0, 1e-14);
  for (double t : {1.0 / 1024, 0.125, 0.5, 0.75, -0.25, -0.5}) {
    const double s = 1 - std::abs(t);
    EXPECT_NEAR(f(kRefTri, gen2::translate(kRefTri, {t, 0})), s * s / 2, kTol) << t;
    EXPECT_NEAR(f(gen2::translate(kRefTri, {0, t}), kRefTri), s * s / 2, kTol) << t;
  }
}

TEST_P(Baseline2D, FlatInputIsZero) {
  const auto& f = *this;
  const Triangle flat{Vec2{0, 0}, Vec2{1, 1}, Vec2{0.25, 0.25}};
  const Triangle flat_inside{Vec2{0.125, 0.125}, Vec2{0.375, 0.25}, Vec2{0.625, 0.375}};
  for (const Triangle& t : {flat, flat_inside}) {
    EXPECT_EQ(f(kRefTri, t), 0.0);
    EXPECT_EQ(f(t, kRefTri), 0.0);
  }
}

TEST_P(Baseline2D, BadInputGivesAFiniteNonNegativeValue) {
  const auto& f = *this;
  Triangle nan = kRefTri;
  nan[1].x = std::nan("");
  Triangle inf = kRefTri;
  inf[2].y = INFINITY;
  EXPECT_EQ(f(kRefTri, nan), 0.0);
  EXPECT_EQ(f(inf, kRefTri), 0.0);
  std::mt19937_64 rng(3);
  for (double s : {1e300, 1e200, 1e-200, 1e-320}) {
    for (int i = 0; i < 50; ++i) {
      const double r = f(gen2::scale(gen2::unit_random_tri(rng), s), gen2::scale(gen2::unit_random_tri(rng), s));
      EXPECT_TRUE(std::isfinite(r) && r >= 0.0) << s << " " << r;
    }
  }
}

TEST_P(Baseline2D, AgreesWithExactOnRandomPairs) {
  const auto& f = *this;
  std::mt19937_64 rng(20240611);
  int failures = 0, strict_failures = 0, nonzero = 0;
  double worst = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const Triangle a = gen2::unit_random_tri(rng), b = gen2::unit_random_tri(rng);
    const double e = exact::intersection_area_double(a, b);
    const double r = f(a, b);
    ASSERT_TRUE(std::isfinite(r) && r >= 0.0);
    const double err = std::abs(r - e);
    worst = std::max(worst, err / scale_of(a, b));
    if (err > 1e-12 * scale_of(a, b)) ++failures;
    if (err > 1e-12 * e) ++strict_failures;
    nonzero += e > 0.0;
  }
  std::printf("%s: %d of 5000 random pairs off by more than 1e-12 max(area A, area B) (worst "
              "%.2e); %d off by more than 1e-12 of the exact intersection area (%d nonzero)\n",
              GetParam().name, failures, worst, strict_failures, nonzero);
  EXPECT_EQ(failures, 0);
}

// Coordinates on the quarter grid: shared and collinear edges, vertices on edges and vertices.
// Neither method promises anything here; these are the results they give, kept from regressing.
TEST_P(Baseline2D, AgreesWithExactOnGridPairs) {
  const auto& f = *this;
  std::mt19937_64 rng(4);
  int failures = 0;
  for (int i = 0; i < 5000; ++i) {
    Triangle a, b;
    for (Triangle* t : {&a, &b})
      for (Vec2& p : *t) p = {gen2::irand(rng, 0, 4) / 4.0, gen2::irand(rng, 0, 4) / 4.0};
    const double e = exact::intersection_area_double(a, b);
    const double r = f(a, b);
    ASSERT_TRUE(std::isfinite(r) && r >= 0.0);
    if (std::abs(r - e) > 1e-12 * std::max(scale_of(a, b), 1e-300)) ++failures;
  }
  std::printf("%s: %d of 5000 grid pairs off by more than 1e-12 max(area A, area B)\n",
              GetParam().name, failures);
  EXPECT_EQ(failures, 0);
}

TEST_P(Baseline2D, Timing) {
  const auto& f = *this;
  std::mt19937_64 rng(1);
  const int pairs = 200000;
  std::vector<std::pair<Triangle, Triangle>> input;
  input.reserve(pairs);
  for (int i = 0; i < pairs; ++i) input.emplace_back(gen2::unit_random_tri(rng), gen2::unit_random_tri(rng));
  double sum = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& [a, b] : input) sum += f(a, b);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s (2D): %.0f ns per random pair, %.2f million pairs/s (sum %.6f)\n",
              GetParam().name, 1e9 * s / pairs, pairs / s / 1e6, sum);
  RecordProperty("ns_per_pair", std::to_string(1e9 * s / pairs));
  EXPECT_GT(sum, 0.0);
}

}  // namespace
