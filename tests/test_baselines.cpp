// test_baselines.cpp -- the floating-point baselines (Sutherland-Hodgman clipping and PANG-style
// hull) against closed-form volumes and against the exact reference.
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

}  // namespace
