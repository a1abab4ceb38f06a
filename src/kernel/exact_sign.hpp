// src/kernel/exact_sign.hpp -- the exact sign of orient2d for double input, and its correctly
// rounded value, in double arithmetic (error-free transformations and an expansion, after
// Shewchuk's "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates", 1997). For the decisions that must be exact and would otherwise need GMP: whether
// two triangles whose computed intersection has no area really only touch; and for the 2D
// kernel's accurate determinants (orient2d_accurate in tri_kernel.hpp: needles, points
// near a line, triangles of very different sizes).
//
// Contract: orient2d_sign(a, b, c) is the sign (-1, 0, +1) of det[b - a, c - a] for the exact
// values of the doubles, provided the differences stay below 2^496 in magnitude (Dekker's split
// then cannot overflow) and, where products of their parts underflow, the determinant is above
// 2^-958; 2 (not a sign) otherwise or for input that is not finite, so that the caller can take
// another way. orient2d_nearest(a, b, c, value) sets value to det[b - a, c - a] rounded to
// nearest (ties to even) under the same provisos (with 2^-900 for the underflow one), and
// returns false where they fail. No fused multiply-add is assumed or needed (the project builds
// with -ffp-contract=off).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace tetia::detail {

// Internal linkage: each kernel variant compiles its own copy for its instruction set, which
// no other object file can bind to (src/kernel/entry_points.hpp, "Linkage").
namespace {

namespace exact_sign_impl {

inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bv = s - a;
  e = (a - (s - bv)) + (b - bv);
}

inline void two_diff(double a, double b, double& d, double& e) {
  d = a - b;
  const double bv = a - d;
  e = (a - (d + bv)) + (bv - b);
}

inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  hi = c - (c - a);
  lo = a - hi;
}

inline void two_product(double a, double b, double& p, double& e) {
  p = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  e = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
}

// Adds x to the expansion e[0..n) (non-overlapping, increasing magnitude, zeros eliminated),
// Shewchuk's GROW-EXPANSION with zero elimination. e has room for the result.
inline int grow(double* e, int n, double x) {
  int k = 0;
  double q = x;
  for (int i = 0; i < n; ++i) {
    double s, h;
    two_sum(q, e[i], s, h);
    if (h != 0.0) e[k++] = h;
    q = s;
  }
  if (q != 0.0) e[k++] = q;
  return k;
}

// The differences of orient2d's determinant det[b - a, c - a] exactly, as h + l (two_diff):
// bx - ax, cy - ay, by - ay, cx - ax, so that det = (h0 + l0)(h1 + l1) - (h2 + l2)(h3 + l3).
inline void exact_differences(double ax, double ay, double bx, double by, double cx, double cy, double (&h)[4],
                              double (&l)[4]) {
  two_diff(bx, ax, h[0], l[0]);
  two_diff(cy, ay, h[1], l[1]);
  two_diff(by, ay, h[2], l[2]);
  two_diff(cx, ax, h[3], l[3]);
}

}  // namespace exact_sign_impl

// The expansion of det[b - a, c - a] (up to 32 components, increasing magnitude); returns its
// length, or -1 where a difference is 2^496 or more (or not finite). A product of two non-zero
// parts below 2^-969 in magnitude (0 included) may lose its error term, or itself, to
// underflow: `tiny` is then set, and the
// expansion's sum is exact only to 2^-960 (sixteen such terms, each off by less than 2^-965),
// which matters only for a determinant of that order.
inline int orient2d_expansion(double ax, double ay, double bx, double by, double cx, double cy, double (&e)[32],
                              bool& tiny) {
  using namespace exact_sign_impl;
  double h[4], l[4];
  exact_differences(ax, ay, bx, by, cx, cy, h, l);
  for (int k = 0; k < 4; ++k)
    if (!(std::abs(h[k]) < 0x1p496)) return -1;  // overflow ahead (or not finite)
  // det = (h0 + l0)(h1 + l1) - (h2 + l2)(h3 + l3): eight exact products of two doubles each.
  int n = 0;
  const double u[2] = {h[0], l[0]}, v[2] = {h[1], l[1]}, w[2] = {h[2], l[2]}, z[2] = {h[3], l[3]};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      double p, err, q, qerr;
      two_product(u[i], v[j], p, err);
      two_product(w[i], z[j], q, qerr);
      // Dekker's error term is exact only while the product stays normal (above 2^-969 leaves
      // room for the split's halves); a product of two non-zero parts that underflows to 0 is
      // lost whole (counted since 2026-12-06: two points 1e-150 apart came out exactly on a line
      // they are not on, fuzz/regressions/fuzz_tri_kernel/found-2026-12-06.txt).
      tiny |= (std::abs(p) < 0x1p-969 && u[i] != 0.0 && v[j] != 0.0) ||
              (std::abs(q) < 0x1p-969 && w[i] != 0.0 && z[j] != 0.0);
      n = grow(e, n, err);
      n = grow(e, n, p);
      n = grow(e, n, -qerr);
      n = grow(e, n, -q);
    }
  return n;
}

inline int orient2d_sign(double ax, double ay, double bx, double by, double cx, double cy) {
  double e[32];
  bool tiny = false;
  const int n = orient2d_expansion(ax, ay, bx, by, cx, cy, e, tiny);
  if (n < 0) return 2;
  if (tiny && !(n > 0 && std::abs(e[n - 1]) > 0x1p-958)) return 2;  // at the level of the lost terms
  // The expansion's components do not overlap and grow in magnitude: the last one's sign is
  // the sum's.
  return n == 0 ? 0 : (e[n - 1] > 0.0 ? 1 : -1);
}

// The correctly rounded value (to nearest, ties to even) of an expansion e[0..n) (increasing
// magnitude, non-overlapping, as orient2d_expansion makes it). The sum from the smallest
// component is within a few units in the last place; the exact residual of a candidate, an
// expansion again, then decides against the midpoints to its neighbours, exactly. `scratch`
// has room for n + 2 components.
inline double nearest_of_expansion(const double* e, int n, double (&scratch)[34]) {
  using namespace exact_sign_impl;
  double v = 0.0;
  for (int i = 0; i < n; ++i) v += e[i];
  // The sign of e - v - offset, offset a double that is exact as given.
  const auto side = [&](double offset) {
    for (int i = 0; i < n; ++i) scratch[i] = e[i];
    int m = grow(scratch, n, -v);
    m = grow(scratch, m, -offset);
    return m == 0 ? 0 : (scratch[m - 1] > 0.0 ? 1 : -1);
  };
  for (int step = 0; step < 64 && std::isfinite(v); ++step) {
    if (side(0.0) == 0) return v;  // exactly representable
    const double up = std::nextafter(v, INFINITY), down = std::nextafter(v, -INFINITY);
    // Half the gaps, exact: the gap between neighbours is a power of two times the ulp, and
    // halving it is exact above the subnormal range (below it, the expansion is already the
    // value: the components are then multiples of the smallest subnormal).
    const double half_up = 0.5 * (up - v), half_down = 0.5 * (v - down);
    const bool even = (std::bit_cast<unsigned long long>(v) & 1u) == 0;
    const int above = side(half_up);
    if (above > 0 || (above == 0 && !even)) {
      v = up;
      continue;
    }
    const int below = side(-half_down);
    if (below < 0 || (below == 0 && !even)) {
      v = down;
      continue;
    }
    return v;
  }
  return v;
}

// Whether v is the double nearest to v + w + delta for every |delta| <= bound (v normal, above
// 2^-960): |w| + bound is below the half-gap to v's neighbour on w's side (half an ulp, a
// quarter toward zero from a power of two), with a margin for the sum's own rounding.
inline bool rounds_to(double v, double w, double bound) {
  if (!(std::abs(v) >= 0x1p-960 && std::abs(v) < 0x1p1000)) return false;
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(std::abs(v));
  const double half_ulp = std::bit_cast<double>(bits & 0x7FF0000000000000ull) * 0x1p-53;
  const bool toward_zero = (w < 0.0) != (v < 0.0);
  const double room = toward_zero && (bits & 0x000FFFFFFFFFFFFFull) == 0 ? 0.5 * half_ulp : half_ulp;
  return std::abs(w) + bound < (1.0 - 0x1p-50) * room;
}

// det[b - a, c - a] correctly rounded (to nearest, ties to even); false where orient2d_sign
// would return 2 (then nothing is certain). The differences are exact (two_diff: h + l), the
// determinant is
//   (h0 + l0)(h1 + l1) - (h2 + l2)(h3 + l3) = d + ed + ep - eq + (h0 l1 + l0 h1 - h2 l3 - l2 h3)
//                                              + (l0 l1 - l2 l3),
// with h0 h1 = p + ep, h2 h3 = q + eq, p - q = d + ed exactly (two_product, two_diff). Three
// stages, each taken only where the one before cannot decide:
//  1. The small terms summed in doubles, with the bound 2^-49 times the sum of their magnitudes
//     plus 2^-1060 (nine terms in a tree four deep and six rounded products: at most
//     5 2^-53 (1 + 2^-49) of it; an underflowing product at most 2^-1075 each). Decides where
//     the determinant is well above the products' rounding (2^-47 of them, about).
//  2. The cross terms h l exact too (two_product), all fourteen terms summed by cascaded
//     two_sum with their errors summed apart (Ogita, Rump and Oishi's Sum2), with the bound
//     2^-96 times the sum of their magnitudes (gamma_13^2 < 2^-98.5 of it) plus the rounding of
//     the two products of low parts and of underflows. Decides unless the determinant is within
//     about 2^-96 of the products of a midpoint or of 0.
//  3. The exact expansion (orient2d_expansion) rounded exactly (nearest_of_expansion).
// Stages 1 and 2 need the parts in [2^-480, 2^480] (or 0), so that the main products keep
// their error terms exactly; outside, stage 3.
inline bool orient2d_nearest(double ax, double ay, double bx, double by, double cx, double cy, double& value) {
  using namespace exact_sign_impl;
  double h[4], l[4];
  exact_differences(ax, ay, bx, by, cx, cy, h, l);
  unsigned in_range = 1;  // without branches: this test is on the path of every call
  for (int k = 0; k < 4; ++k) {
    const double m = std::abs(h[k]);
    in_range &= unsigned(m == 0.0) | (unsigned(m >= 0x1p-480) & unsigned(m < 0x1p480));
  }
  if (in_range) {
    double p, ep, q, eq, d, ed;
    two_product(h[0], h[1], p, ep);
    two_product(h[2], h[3], q, eq);
    two_diff(p, q, d, ed);
    const bool low_parts_zero = l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0 && l[3] == 0.0;
    if (low_parts_zero && ed == 0.0 && ep == 0.0 && eq == 0.0) {
      value = d + 0.0;  // the determinant is p - q = d exactly (+0 for a zero, as an expansion sums it)
      return true;
    }
    // Stage 1.
    const double c5 = l[0] * l[1], c6 = l[2] * l[3];
    {
      const double c1 = h[0] * l[1], c2 = l[0] * h[1], c3 = h[2] * l[3], c4 = l[2] * h[3];
      const double rest = ((ed + (ep - eq)) + ((c1 + c2) - (c3 + c4))) + (c5 - c6);
      const double magnitude = ((std::abs(ed) + (std::abs(ep) + std::abs(eq))) +
                                ((std::abs(c1) + std::abs(c2)) + (std::abs(c3) + std::abs(c4)))) +
                               (std::abs(c5) + std::abs(c6));
      double v, w;
      two_sum(d, rest, v, w);  // v + w = d + rest exactly
      if (rounds_to(v, w, 0x1p-49 * magnitude + 0x1p-1060)) {
        value = v;
        return true;
      }
    }
    // Stage 2.
    double t[14];
    t[0] = d, t[1] = ed, t[2] = ep, t[3] = -eq;
    two_product(h[0], l[1], t[4], t[5]);
    two_product(l[0], h[1], t[6], t[7]);
    two_product(h[2], l[3], t[8], t[9]);
    two_product(l[2], h[3], t[10], t[11]);
    for (int k = 8; k < 12; ++k) t[k] = -t[k];
    t[12] = c5, t[13] = -c6;
    double sigma = t[0], tau = 0.0, magnitude = std::abs(t[0]);
    for (int k = 1; k < 14; ++k) {
      double err;
      two_sum(sigma, t[k], sigma, err);
      tau += err;
      magnitude += std::abs(t[k]);
    }
    double v, w;
    two_sum(sigma, tau, v, w);
    if (rounds_to(v, w, 0x1p-96 * magnitude + 0x1p-52 * (std::abs(c5) + std::abs(c6)) + 0x1p-1060)) {
      value = v;
      return true;
    }
  }
  // Stage 3.
  double e[32], scratch[34];
  bool tiny = false;
  const int n = orient2d_expansion(ax, ay, bx, by, cx, cy, e, tiny);
  if (n < 0) return false;
  if (tiny && !(n > 0 && std::abs(e[n - 1]) > 0x1p-900)) return false;  // not resolved relative to the lost terms
  value = nearest_of_expansion(e, n, scratch);
  return true;
}

}  // namespace

}  // namespace tetia::detail
