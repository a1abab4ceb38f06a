// Tests of src/kernel/exact_sign.hpp, the kernels' exact predicates in double arithmetic: orient2d_sign (the exact sign) and orient2d_nearest (the
// correctly rounded value) against GMP, on random, near-collinear, far-from-origin, tiny,
// mixed-magnitude and exactly tied input.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include "../src/kernel/exact_sign.hpp"
#include "support/generators.hpp"  // nudge

namespace {

using tetia::detail::orient2d_nearest;
using tetia::detail::orient2d_sign;
using tetia::testgen::nudge;

mpq_class exact_orient(double ax, double ay, double bx, double by, double cx, double cy) {
  const mpq_class Ax(ax), Ay(ay), Bx(bx), By(by), Cx(cx), Cy(cy);
  return (Bx - Ax) * (Cy - Ay) - (By - Ay) * (Cx - Ax);
}

// x rounded to the nearest double, ties to even (x in the normal range or 0).
double nearest_double(const mpq_class& x) {
  const double t = x.get_d();  // truncated toward zero
  const double away = std::nextafter(t, x > 0 ? INFINITY : -INFINITY);
  if (x == mpq_class(t)) return t;
  const mpq_class dt = abs(x - mpq_class(t)), da = abs(mpq_class(away) - x);
  if (dt < da) return t;
  if (da < dt) return away;
  return (std::bit_cast<std::uint64_t>(t) & 1u) == 0 ? t : away;
}

struct Counts {
  int checked = 0, ties_to_even = 0, exact_zero = 0;
};

void check(double ax, double ay, double bx, double by, double cx, double cy, Counts& counts) {
  const mpq_class x = exact_orient(ax, ay, bx, by, cx, cy);
  const int s = sgn(x);
  ASSERT_EQ(orient2d_sign(ax, ay, bx, by, cx, cy), s) << ax << " " << ay << " " << bx << " " << by << " " << cx << " " << cy;
  double v = 0.0;
  ASSERT_TRUE(orient2d_nearest(ax, ay, bx, by, cx, cy, v));
  const double want = nearest_double(x);
  ASSERT_EQ(std::bit_cast<std::uint64_t>(v), std::bit_cast<std::uint64_t>(want))
      << std::hexfloat << v << " != " << want << " for " << ax << " " << ay << " " << bx << " " << by << " " << cx << " " << cy;
  ++counts.checked;
  counts.exact_zero += s == 0;
}

TEST(ExactSign, RandomAndNearCollinear) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), t(-0.5, 1.5);
  std::uniform_int_distribution<int> ulps(-4, 4), octave(-40, 40);
  Counts counts;
  for (int n = 0; n < 100000; ++n) {
    const double scale = std::ldexp(1.0, octave(rng));
    const double offset = (n % 3 == 0) ? std::ldexp(1.0, octave(rng) + 20) : 0.0;  // far from the origin
    const double ax = offset + scale * uni(rng), ay = offset + scale * uni(rng);
    const double bx = offset + scale * uni(rng), by = offset + scale * uni(rng);
    double cx, cy;
    if (n % 2 == 0) {  // c near the line ab, nudged by a few ulps
      const double s = t(rng);
      cx = nudge(ax + s * (bx - ax), ulps(rng));
      cy = nudge(ay + s * (by - ay), ulps(rng));
    } else {
      cx = offset + scale * uni(rng);
      cy = offset + scale * uni(rng);
    }
    check(ax, ay, bx, by, cx, cy, counts);
    check(bx, by, cx, cy, ax, ay, counts);  // the same determinant, cyclically
    check(ax, ay, cx, cy, bx, by, counts);  // its negative
  }
  EXPECT_GT(counts.exact_zero, 0);
}

TEST(ExactSign, MixedMagnitudesAndTinyScales) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> uni(0.5, 1.0);
  std::uniform_int_distribution<int> e(-470, 470), sign(0, 1);
  Counts counts;
  for (int n = 0; n < 50000; ++n) {
    double c[6];
    for (double& x : c) x = (sign(rng) ? 1.0 : -1.0) * std::ldexp(uni(rng), e(rng) / (1 + n % 4));
    check(c[0], c[1], c[2], c[3], c[4], c[5], counts);
  }
}

TEST(ExactSign, ExactTiesRoundToEven) {
  // Integer coordinates whose determinant is an odd multiple of 2^k just above 2^53: exactly
  // halfway between two doubles, so the rounding is to the even one; and exact zeros.
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::int64_t> small(1, 1 << 20);
  Counts counts;
  int ties = 0;
  for (int n = 0; n < 20000; ++n) {
    // det[b - a, c - a] = p q - r s with b - a = (p, r), c - a = (s, q): an integer near 2^54.
    const std::int64_t p = (std::int64_t{1} << 33) + small(rng), q = (std::int64_t{1} << 21) + small(rng);
    const std::int64_t s = small(rng), r = small(rng);
    const double ax = 0.0, ay = 0.0, bx = double(p), by = double(r), cx = double(s), cy = double(q);
    const mpz_class x = exact_orient(ax, ay, bx, by, cx, cy).get_num();  // an integer
    ties += x > mpz_class(1) << 54 && x % 4 == 2;  // doubles 4 apart there: halfway
    check(ax, ay, bx, by, cx, cy, counts);
    // Collinear: c the midpoint of a and b, exactly 0.
    check(1.0, 2.0, 1.0 + 2.0 * double(p), 2.0 + 2.0 * double(r), 1.0 + double(p), 2.0 + double(r), counts);
  }
  EXPECT_GT(ties, 1000);
  EXPECT_GE(counts.exact_zero, 20000);
}

TEST(ExactSign, OutOfRangeIsRefused) {
  double v = 0.0;
  EXPECT_FALSE(orient2d_nearest(0, 0, 0x1p500, 0, 0, 0x1p500, v));
  EXPECT_FALSE(orient2d_nearest(0, 0, NAN, 0, 0, 1, v));
  EXPECT_EQ(orient2d_sign(0, 0, INFINITY, 0, 0, 1), 2);
}

}  // namespace
