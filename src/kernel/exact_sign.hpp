// src/kernel/exact_sign.hpp -- the exact sign of orient2d for double input, in double arithmetic
// (error-free transformations and an expansion, after Shewchuk's "Adaptive precision
// floating-point arithmetic and fast robust geometric predicates", 1997). For the rare decisions
// that must be exact and would otherwise need GMP: whether two triangles whose computed
// intersection has no area really only touch (tri_intersection.cpp).
//
// Contract: orient2d_sign(a, b, c) is the sign (-1, 0, +1) of det[b - a, c - a] for the exact
// values of the doubles, provided the differences stay below 2^496 in magnitude (Dekker's split
// then cannot overflow) and, where products of their parts underflow, the determinant is above
// 2^-958; 2 (not a sign) otherwise or for input that is not finite, so that the caller can take
// another way. No fused
// multiply-add is assumed or needed (the project builds with -ffp-contract=off).
#pragma once

#include <cmath>

namespace tetia::detail {

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

}  // namespace exact_sign_impl

// The expansion of det[b - a, c - a] (up to 32 components, increasing magnitude); returns its
// length, or -1 where a difference is 2^496 or more (or not finite). A product of two parts
// below 2^-969 in magnitude may lose its error term to underflow: `tiny` is then set, and the
// expansion's sum is exact only to 2^-960 (sixteen such terms, each off by less than 2^-965),
// which matters only for a determinant of that order.
inline int orient2d_expansion(double ax, double ay, double bx, double by, double cx, double cy, double (&e)[32],
                              bool& tiny) {
  using namespace exact_sign_impl;
  double h[4], l[4];  // exact differences: bx - ax, cy - ay, by - ay, cx - ax
  two_diff(bx, ax, h[0], l[0]);
  two_diff(cy, ay, h[1], l[1]);
  two_diff(by, ay, h[2], l[2]);
  two_diff(cx, ax, h[3], l[3]);
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
      // room for the split's halves).
      tiny |= (p != 0.0 && std::abs(p) < 0x1p-969) || (q != 0.0 && std::abs(q) < 0x1p-969);
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

// det[b - a, c - a] to within a few units in the last place, whatever the cancellation (the
// expansion's components summed from the smallest: they do not overlap, so the sum's rounding
// errors stay below the last component's ulp); false where orient2d_sign would return 2.
inline bool orient2d_rounded(double ax, double ay, double bx, double by, double cx, double cy, double& value) {
  double e[32];
  bool tiny = false;
  const int n = orient2d_expansion(ax, ay, bx, by, cx, cy, e, tiny);
  if (n < 0) return false;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += e[i];
  if (tiny && !(std::abs(sum) > 0x1p-900)) return false;  // not resolved relative to the lost terms
  value = sum;
  return true;
}

}  // namespace tetia::detail
