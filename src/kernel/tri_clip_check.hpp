// src/kernel/tri_clip_check.hpp -- a derived error bound for the 2D kernel's result, where the
// certified formula (tri_certified_moments.hpp) left the pair to the kernel: touching and shared
// vertices or edges, size ratios beyond about 2^6, small overlaps, near-identical pairs. The
// kernel's own accuracy there is measured, not bounded; this check turns it into a bound, or
// sends the pair to the exact last resort.
//
// Contract: clip_enclosure(S, L, det_s, det_s_error, det_l, out), given det(S) within
// det_s_error and det(L)'s sign (det_of, certain), encloses the exact area of S n L: it returns
// true and sets out.area and out.error with |out.area - exact| <= out.error, or returns false
// (a line of L whose values at S's vertices leave no certain gradient across its slab, or a
// vertex of L whose coordinates' sum its bound does not keep from 0, in both tries; never seen
// on the test families; or a bound that is not finite). S and L are triangles in any vertex
// order, neither flat, with edges in the kernel's range (after its rescaling); outside it the
// bounds only grow (underflow is covered by absolute terms) or are not finite. The result is
// a function of the two triangles and of the order of each one's vertices; the kernel passes
// them in its canonical order, so that it depends on the pair as point sets only.
// kernel_area_stands(A, B, area) is whether a result `area` for the pair (A, B) is certainly
// within kCheckAccepted of the smaller triangle's area of the exact one. Nothing allocates,
// nothing throws.
//
// Method. Everything is measured in S's barycentric coordinates lambda (lambda_0 + lambda_1 +
// lambda_2 = 1), where S is the unit simplex Delta whatever its size or shape, drawn in the
// plane of (lambda_1, lambda_2) with area 1/2. L's edge line j enters only through its three
// values at S's vertices, D[j][k] = orient2d(L_j, L_j+1, s_k) (signed so that L's inside is
// positive): on Delta, line j is the zero set of g_j(lambda) = sum_k lambda_k D[j][k], exactly,
// since orient2d is affine in its last point. So S n L, in the frame, is
//   R = {lambda in Delta : g_j(lambda) >= 0, j = 0, 1, 2}.
// With the computed values Dh (each within delta[j][k] of D), the polygon
//   Rh = {lambda in Delta : gh_j(lambda) >= 0}, gh_j = sum_k lambda_k Dh[j][k],
// is defined by doubles, and its area is computed with a bound of its own:
//  (1) Its combinatorial structure is exact: Delta is clipped by gh_0, gh_1, gh_2 in turn
//      (Sutherland and Hodgman), every vertex kept symbolic as the two lines it lies on (S's edge
//      lines lambda_p = 0 and L's), every sign of gh_j at a vertex decided exactly on the doubles
//      Dh (an entry at a vertex of S; a 2x2 determinant at a crossing of S's edge; a 3x3 at a
//      vertex of L), with a double filter first and an expansion (exact_sign.hpp) where it does
//      not decide. The clipped polygon is then exactly Rh, convex, counter-clockwise.
//  (2) Each vertex's coordinates are computed from its two lines, not from the clipping's
//      earlier vertices, so errors do not accumulate: a vertex of S is exact; a crossing of S's
//      edge p with line i is lambda_q = |Dh_ir| / (|Dh_iq| + |Dh_ir|) (opposite signs at the edge's
//      ends q, r), within 2.01 u of it; a vertex of L, lines i and k, is c / sum(c) for the
//      cross product c = Dh_i x Dh_k, whose components (2x2 determinants, evaluated with exact
//      products: within 2 u of themselves plus 2 u^2 of their products) have one sign inside
//      Delta, so that their sum does not cancel.
//  (3) Moving the computed vertices V_i of a closed polygon by e_i (to the exact ones) changes
//      twice its area by sum_i e_i x (V_i+1 - V_i-1) + sum_i e_i x e_i+1, so with |e_i|_inf <=
//      d_i by at most sum_i d_i |V_i+1 - V_i-1|_1 + 2 sum_i d_i d_i+1 (the differences of
//      computed vertices, enlarged for their rounding); the shoelace sum's own rounding adds at
//      most (n + 3) u times the sum of its products' magnitudes.
//  (4) Between R and Rh: every lambda in Delta has |g_j - gh_j| <= delta_j = max_k delta[j][k],
//      so both lie between I = {gh_j >= delta_j for all j} and G = {gh_j >= -delta_j for all j},
//      and their areas differ by at most area(G \ I), which lies in the union of the slabs
//      {-delta_j <= gh_j < delta_j} n Delta. Each slab is at most 2 delta_j / |grad gh_j| wide and
//      Delta at most sqrt(2) long across it: 4 sqrt(2) delta_j / |grad gh_j| of Delta's area. A
//      line with gh_j > delta_j on all of Delta (its smallest Dh above delta_j) has no slab
//      there; one with all Dh below -delta_j leaves R and Rh both empty, exactly. For a line
//      through Delta the gradient is at least half the range of its Dh, so with correctly
//      rounded Dh (delta = u |Dh|) each slab is below 12 u of Delta, whatever the size ratio.
// The area of S n L is the fraction f = 2 area(R) of S's, times |det(S)| / 2, det(S) within its
// own bound (Shewchuk's, else correctly rounded). Rows of Dh are scaled by powers of two to a
// largest entry in [1, 2) (the half-planes do not change) and entries below 2^-250 then set to 0
// (delta grows by 2^-250), so that every product the exact signs form stays normal.
// Tries: Dh first in doubles with Shewchuk's bound (3 + 16 u) u of the products; where the slabs
// do not accept (planes far from S for S's size: a ratio of sizes), again with Dh correctly
// rounded (orient2d_nearest).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "exact_sign.hpp"  // two_product, grow, orient2d_nearest
#include "tetia/geometry.hpp"

namespace tetia {
namespace detail2 {
namespace {

// The largest error accepted, relative to the smaller triangle's area: 2.3e-13, a factor 4.4
// below the contract's 1e-12, as for the 3D refinement's clipping (refined_clip.hpp).
constexpr double kCheckAccepted = 0x1p-42;

namespace clip_check {

using detail::exact_sign_impl::grow;
using detail::exact_sign_impl::two_product;

constexpr double u = 0x1p-53;
constexpr double kShewchuk = (3.0 + 16.0 * u) * u;  // orient2d's ccwerrboundA
constexpr double kTiny = 0x1p-250;                   // entries below this (row max in [1, 2)) are 0

// floor(log2 |x|) for x finite and non-zero (std::ilogb without the call, for normal x).
inline int exponent_of(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const int e = int((bits >> 52) & 0x7ff);
  return e != 0 ? e - 1023 : std::ilogb(x);
}

// 2^e for e in [-1022, 1023], exactly; 0 otherwise.
inline double power_of_two(int e) {
  return e >= -1022 && e <= 1023 ? std::bit_cast<double>(std::uint64_t(e + 1023) << 52) : 0.0;
}

// The exact sign of a d - b c, for doubles of magnitude below 2 whose non-zero values are at
// least 2^-250 (so that every product keeps its error term: above 2^-969).
inline int det2_sign(double a, double b, double c, double d) {
  const double l = a * d, r = b * c;
  const double v = l - r;
  // Each product within u of itself, the difference within u of itself: 2.01 u (|l| + |r|).
  const double bound = 0x1p-51 * (std::abs(l) + std::abs(r));
  if (v > bound) return 1;
  if (-v > bound) return -1;
  // A product is 0 only where a factor is (non-zero ones are at least 2^-500): exactly 0
  // (lines through a shared vertex or along a shared edge).
  if (l == 0.0 && r == 0.0) return 0;
  double p, pe, q, qe, e[4];
  two_product(a, d, p, pe);
  two_product(b, c, q, qe);
  int n = grow(e, 0, pe);
  n = grow(e, n, -qe);
  n = grow(e, n, p);
  n = grow(e, n, -q);
  return n == 0 ? 0 : (e[n - 1] > 0.0 ? 1 : -1);
}

// The exact sign of det[r0; r1; r2], entries as for det2_sign.
inline int det3_sign(const double (&r0)[3], const double (&r1)[3], const double (&r2)[3]) {
  const double m0 = r1[1] * r2[2] - r1[2] * r2[1];
  const double m1 = r1[2] * r2[0] - r1[0] * r2[2];
  const double m2 = r1[0] * r2[1] - r1[1] * r2[0];
  const double v = (r0[0] * m0 + r0[1] * m1) + r0[2] * m2;
  const double perm = std::abs(r0[0]) * (std::abs(r1[1] * r2[2]) + std::abs(r1[2] * r2[1])) +
                      std::abs(r0[1]) * (std::abs(r1[2] * r2[0]) + std::abs(r1[0] * r2[2])) +
                      std::abs(r0[2]) * (std::abs(r1[0] * r2[1]) + std::abs(r1[1] * r2[0]));
  // Minors within 2.01 u of their permanents, the products one more u, the sum two: 5.1 u of
  // the permanent (itself rounded by less than 4 u) to first order; 8 u allows for the rest.
  const double bound = 0x1p-50 * perm;
  if (v > bound) return 1;
  if (-v > bound) return -1;
  // Exactly: each of the six triple products a b c as four doubles (a b = h + l, then h c and
  // l c by two_product: the smallest, l c, is at least 2^-854 where non-zero).
  static constexpr int kTerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  double e[32];
  int n = 0;
  for (int t = 0; t < 6; ++t) {
    const double sign = t < 3 ? 1.0 : -1.0;
    double h, l, p1, e1, p2, e2;
    two_product(r0[kTerm[t][0]], r1[kTerm[t][1]], h, l);
    two_product(h, r2[kTerm[t][2]], p1, e1);
    two_product(l, r2[kTerm[t][2]], p2, e2);
    n = grow(e, n, sign * e2);
    n = grow(e, n, sign * p2);
    n = grow(e, n, sign * e1);
    n = grow(e, n, sign * p1);
  }
  return n == 0 ? 0 : (e[n - 1] > 0.0 ? 1 : -1);
}

// a d - b c with exact products: within kMinorRel of itself plus kMinorAbs of |a d| + |b c|
// (the difference of the leading products and of their error terms, each rounded once, and the
// sum of the two: 2 u of the result and 2 u^2 of the products, to first order), plus 2^-1070.
constexpr double kMinorRel = 0x1p-51;
constexpr double kMinorAbs = 0x1p-103;
inline double minor(double a, double b, double c, double d, double& error) {
  double p, pe, q, qe;
  two_product(a, d, p, pe);
  two_product(b, c, q, qe);
  const double v = (p - q) + (pe - qe);
  error = kMinorRel * std::abs(v) + kMinorAbs * (std::abs(p) + std::abs(q)) + 0x1p-1070;
  return v;
}

// A vertex of the clipped polygon: the two lines it lies on (0-2: S's edge lines lambda_p = 0;
// 3-5: L's lines 0-2), first < second.
struct Vertex {
  int first, second;
};

// Lines 3-5, their rows scaled (largest entry in [1, 2), entries below 2^-250 zero) and each
// row's error bound delta in the same units.
struct Rows {
  double D[3][3];
  double delta[3];
};

// The sign of gh_j at v, exactly (method (1)).
inline int sign_at(const Rows& R, const Vertex& v, int j) {
  const double(&Dj)[3] = R.D[j];
  if (v.first == 3 + j || v.second == 3 + j) return 0;
  if (v.second < 3) return Dj[3 - v.first - v.second] > 0.0 ? 1 : (Dj[3 - v.first - v.second] < 0.0 ? -1 : 0);
  if (v.first < 3) {
    // On S's edge p, between its vertices q and r, and on line i: homogeneous coordinates
    // c = e_p x Dh_i (c_q = -Dh_iq, c_r = Dh_ir; their sum Dh_iq - Dh_ir has the sign of Dh_iq,
    // Dh_iq and Dh_ir being of opposite signs, one possibly 0), and gh_j . c = Dh_iq Dh_jr -
    // Dh_ir Dh_jq.
    const int p = v.first, i = v.second - 3, q = (p + 1) % 3, r = (p + 2) % 3;
    const double(&Di)[3] = R.D[i];
    const int s = det2_sign(Di[q], Di[r], Dj[q], Dj[r]);
    const int sum_sign = Di[q] != 0.0 ? (Di[q] > 0.0 ? 1 : -1) : (Di[r] > 0.0 ? -1 : 1);
    return s * sum_sign;
  }
  // A vertex of L: c = Dh_i x Dh_k, gh_j . c = det[Dh_j; Dh_i; Dh_k], and sum(c) has the sign of
  // every non-zero component of c (the vertex lies in Delta).
  const double(&Di)[3] = R.D[v.first - 3];
  const double(&Dk)[3] = R.D[v.second - 3];
  int sum_sign = det2_sign(Di[1], Di[2], Dk[1], Dk[2]);
  if (sum_sign == 0) sum_sign = det2_sign(Di[2], Di[0], Dk[2], Dk[0]);
  if (sum_sign == 0) sum_sign = det2_sign(Di[0], Di[1], Dk[0], Dk[1]);
  return det3_sign(Dj, Di, Dk) * sum_sign;
}

// (lambda_1, lambda_2) of v and a bound on their error (method (2)); false where a vertex of L
// has coordinates whose sum its error bound does not keep away from 0 (never seen).
inline bool position(const Rows& R, const Vertex& v, double& x, double& y, double& d) {
  double l[3] = {0.0, 0.0, 0.0};
  if (v.second < 3) {
    l[3 - v.first - v.second] = 1.0;
    d = 0.0;
  } else if (v.first < 3) {
    const int p = v.first, q = (p + 1) % 3, r = (p + 2) % 3;
    const double(&Di)[3] = R.D[v.second - 3];
    const double aq = std::abs(Di[q]), ar = std::abs(Di[r]);
    const double sum = aq + ar;
    if (!(sum > 0.0)) return false;
    l[q] = ar / sum;
    l[r] = aq / sum;
    d = 0x1.01p-52;  // the sum and the quotient rounded once each (no underflow: both >= 2^-250)
  } else {
    const double(&Di)[3] = R.D[v.first - 3];
    const double(&Dk)[3] = R.D[v.second - 3];
    double c[3], e[3];
    c[0] = minor(Di[1], Di[2], Dk[1], Dk[2], e[0]);
    c[1] = minor(Di[2], Di[0], Dk[2], Dk[0], e[1]);
    c[2] = minor(Di[0], Di[1], Dk[0], Dk[1], e[2]);
    const double sum = (c[0] + c[1]) + c[2];
    // |sum - exact sum| <= F: the components' errors and the sum's two roundings.
    const double F = ((e[0] + e[1]) + e[2]) * (1.0 + 0x1p-50) +
                     0x1.01p-52 * ((std::abs(c[0]) + std::abs(c[1])) + std::abs(c[2]));
    if (!(std::abs(sum) > 2.0 * F)) return false;
    for (int m = 1; m < 3; ++m) l[m] = c[m] / sum;
    // |c_m / sum - exact| <= (e_m + |exact lambda_m| F) / |exact sum| with |exact lambda_m| <= 1
    // (inside Delta) and |exact sum| >= |sum| - F, plus the quotient's rounding.
    const double em = std::max(e[1], e[2]);
    d = (em + F) / ((std::abs(sum) - F) * (1.0 - 0x1p-50)) * (1.0 + 0x1p-50) + u;
  }
  x = l[1];
  y = l[2];
  return true;
}

// Rh's doubled area (the fraction f of S) and its error bound, methods (1)-(3); false where
// position() is.
inline bool clipped_fraction(const Rows& R, double& f, double& error) {
  Vertex poly[8] = {{1, 2}, {0, 2}, {0, 1}};  // S's vertices 0, 1, 2: (0, 0), (1, 0), (0, 1)
  int line[8] = {2, 0, 1};                   // the line of the edge from vertex i to i + 1
  int n = 3;
  for (int j = 0; j < 3 && n >= 3; ++j) {
    int s[8];
    bool any_out = false;
    for (int i = 0; i < n; ++i) {
      s[i] = sign_at(R, poly[i], j);
      any_out |= s[i] < 0;
    }
    if (!any_out) continue;
    Vertex out[8];
    int out_line[8];
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const int i1 = i + 1 == n ? 0 : i + 1;
      if (s[i] >= 0) {
        out[m] = poly[i];
        // The edge from a kept vertex goes on along its own line unless it leaves the
        // half-plane at this very vertex (on line j, the next one outside).
        out_line[m++] = (s[i] > 0 || s[i1] >= 0) ? line[i] : 3 + j;
      }
      if (s[i] * s[i1] < 0) {
        const int a = line[i], b = 3 + j;
        out[m] = {std::min(a, b), std::max(a, b)};
        // Leaving: the boundary goes on along line j; entering: along the edge's line.
        out_line[m++] = s[i] > 0 ? 3 + j : line[i];
      }
    }
    n = m;
    for (int i = 0; i < n; ++i) {
      poly[i] = out[i];
      line[i] = out_line[i];
    }
  }
  if (n < 3) {  // a point, a segment or nothing: area exactly 0
    f = 0.0;
    error = 0.0;
    return true;
  }
  double x[8], y[8], d[8];
  for (int i = 0; i < n; ++i)
    if (!position(R, poly[i], x[i], y[i], d[i])) return false;
  double twice = 0.0, magnitude = 0.0, moved = 0.0;
  for (int i = 0; i < n; ++i) {
    const int i1 = i + 1 == n ? 0 : i + 1, i0 = i == 0 ? n - 1 : i - 1;
    const double l = x[i] * y[i1], r = x[i1] * y[i];
    twice += l - r;
    magnitude += std::abs(l) + std::abs(r);
    const double w = std::abs(x[i1] - x[i0]) + std::abs(y[i1] - y[i0]);
    moved += d[i] * w * (1.0 + 0x1p-50) + 2.0 * d[i] * d[i1];
  }
  f = twice;
  error = (moved + double(n + 3) * u * magnitude) * (1.0 + 0x1p-48);
  return true;
}

// D[j][k] = orient2d(L_j, L_j+1, s_k) times the sign of det(L), Shewchuk's evaluation order,
// each within delta[j][k]; `nearest`: correctly rounded instead, where orient2d_nearest takes
// it (not where a determinant below 2^-900 comes from products that underflow: there the
// plain value's bound, 2^-1060 with underflow, is tiny anyway).
inline void plane_values(const Triangle& S, const Triangle& L, double sign_l, bool nearest, double (&D)[3][3],
                         double (&delta)[3][3]) {
  for (int j = 0; j < 3; ++j) {
    const Vec2 a = L[j], b = L[(j + 1) % 3];
    for (int k = 0; k < 3; ++k) {
      const Vec2 c = S[k];
      const double acx = a.x - c.x, bcx = b.x - c.x, acy = a.y - c.y, bcy = b.y - c.y;
      const double l = acx * bcy, r = acy * bcx;
      D[j][k] = sign_l * (l - r);
      delta[j][k] = kShewchuk * (std::abs(l) + std::abs(r)) + 0x1p-1060;
      double v;
      if (nearest && delta[j][k] > u * std::abs(D[j][k]) && detail::orient2d_nearest(a.x, a.y, b.x, b.y, c.x, c.y, v)) {
        D[j][k] = sign_l * v;
        delta[j][k] = u * std::abs(v) + 0x1p-1074;
      }
    }
  }
}

// The rows scaled (see Rows) and the slabs' share of Delta (method (4)); `empty`: some line has
// all of Delta certainly outside (R and Rh both empty). False where a line has no certain
// gradient across its slab.
inline bool scaled_rows(const double (&D)[3][3], const double (&delta)[3][3], Rows& R, double& slabs, bool& empty) {
  slabs = 0.0;
  empty = false;
  for (int j = 0; j < 3; ++j) {
    const double big = std::max({std::abs(D[j][0]), std::abs(D[j][1]), std::abs(D[j][2])});
    double dj = std::max({delta[j][0], delta[j][1], delta[j][2]});
    if (!(big > 0.0)) return false;  // S on line j: S flat, which the caller excludes
    const int shift = -exponent_of(big);
    const double factor = power_of_two(shift);  // 0 where out of range: ldexp then
    bool zeroed = false;
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      double v = factor != 0.0 ? D[j][k] * factor : std::ldexp(D[j][k], shift);
      if (std::abs(v) < kTiny) {
        zeroed |= D[j][k] != 0.0;
        v = 0.0;
      }
      R.D[j][k] = v;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    // The scaled bound, rounded up (the scaling is exact unless it underflows: 2^-1074 covers
    // that).
    dj = (factor != 0.0 ? dj * factor : std::ldexp(dj, shift)) + 0x1p-1074 + (zeroed ? kTiny : 0.0);
    R.delta[j] = dj;
    if (lo > dj) continue;  // gh_j > delta_j on Delta: no slab
    if (hi < -dj) {
      empty = true;
      continue;
    }
    // |grad gh_j|_2 >= the larger of |Dh_j1 - Dh_j0| and |Dh_j2 - Dh_j0| (each rounded once).
    const double g = std::max(std::abs(R.D[j][1] - R.D[j][0]), std::abs(R.D[j][2] - R.D[j][0])) * (1.0 - 0x1p-52);
    if (!(g > 0.0)) return false;
    slabs += 4.0 * 1.4142135623730951 * dj / g * (1.0 + 0x1p-49);
  }
  return true;
}

// det(t) = orient2d(t0, t1, t2) and its error bound: Shewchuk's where it is at most 2^-50 of the
// value, else correctly rounded. False where orient2d_nearest fails.
inline bool det_of(const Triangle& t, double& det, double& error) {
  const double acx = t[0].x - t[2].x, bcx = t[1].x - t[2].x, acy = t[0].y - t[2].y, bcy = t[1].y - t[2].y;
  const double l = acx * bcy, r = acy * bcx;
  det = l - r;
  error = kShewchuk * (std::abs(l) + std::abs(r)) + 0x1p-1060;
  if (error <= 0x1p-50 * std::abs(det)) return true;
  if (!detail::orient2d_nearest(t[0].x, t[0].y, t[1].x, t[1].y, t[2].x, t[2].y, det)) return false;
  error = u * std::abs(det) + 0x1p-1074;
  return true;
}

}  // namespace clip_check

// What clip_enclosure finds: the area of S n L in S's frame as a fraction of S (fraction, with
// its bound fraction_error), |det(S)| with its bound, and the enclosure of the area itself.
struct ClipEnclosure {
  bool found = false;  // clip_enclosure returned true
  double fraction = 0.0, fraction_error = 0.0;
  double det = 0.0, det_error = 0.0;
  double area = 0.0, error = 0.0;
};

// det_s, det_l: det_of's values for S and L, with their bounds (certain signs).
inline bool clip_enclosure(const Triangle& S, const Triangle& L, double det_s, double det_s_error, double det_l,
                           ClipEnclosure& out) {
  using namespace clip_check;
  out.det = std::abs(det_s);
  out.det_error = det_s_error;
  const double sign_l = det_l > 0.0 ? 1.0 : -1.0;
  bool done = false;
  for (int attempt = 0; attempt < 2 && !done; ++attempt) {
    double D[3][3], delta[3][3];
    plane_values(S, L, sign_l, attempt == 1, D, delta);
    Rows R;
    double slabs, f = 0.0, f_error = 0.0;
    bool empty;
    if (!scaled_rows(D, delta, R, slabs, empty)) continue;
    if (!empty && !clipped_fraction(R, f, f_error)) continue;
    out.fraction = f;
    out.fraction_error = empty ? 0.0 : f_error + slabs;
    // The first attempt stands where its bound leaves room under the check's threshold.
    done = attempt == 1 || out.fraction_error <= 0.25 * kCheckAccepted;
  }
  if (!done) return false;
  // area = f |det(S)| / 2: |f^ d^ - f d| <= e_f d^ + (f^ + e_f) e_d, and the products' rounding.
  out.area = 0.5 * (out.fraction * out.det);
  out.error = 0.5 * (out.fraction_error * out.det + (std::abs(out.fraction) + out.fraction_error) * out.det_error) *
                  (1.0 + 0x1p-50) +
              0x1p-53 * std::abs(out.area) + 0x1p-1074;
  return out.error < INFINITY;  // not NaN either (values out of range)
}

// Whether `area` is certainly within kCheckAccepted of the smaller triangle's area of the exact
// area of A n B (A and B in a canonical vertex order, neither flat). S is the triangle of
// smaller |det| (det_of; the coordinates break a tie, so that the choice does not depend on the
// argument order); its area stands for the smaller one's, which it exceeds by at most their
// bounds (2^-49 of them). Equal triangles (in the same canonical vertex order: the same point
// set) need no clipping. `trace`: where not null, what clip_enclosure found.
inline bool kernel_area_stands(const Triangle& A, const Triangle& B, double area, ClipEnclosure* trace = nullptr) {
  using namespace clip_check;
  double da, ea, db, eb;
  if (!det_of(A, da, ea) || !det_of(B, db, eb) || !(std::abs(da) > ea) || !(std::abs(db) > eb)) return false;
  bool a_smaller = std::abs(da) < std::abs(db);
  if (std::abs(da) == std::abs(db)) {
    const double* pa = &A[0].x;
    const double* pb = &B[0].x;
    a_smaller = std::lexicographical_compare(pa, pa + 6, pb, pb + 6);
  }
  ClipEnclosure e;
  if (A == B) {  // one triangle twice (identical cells of two meshes): the exact area is its own
    e.found = true;
    e.fraction = 1.0;
    e.det = std::abs(da);
    e.det_error = ea;
    e.area = 0.5 * e.det;
    e.error = 0.5 * ea;
  } else {
    e.found = a_smaller ? clip_enclosure(A, B, da, ea, db, e) : clip_enclosure(B, A, db, eb, da, e);
  }
  if (trace) *trace = e;
  if (!e.found) return false;
  const double off = std::abs(area - e.area) * (1.0 + 0x1p-52);
  return off + e.error <= kCheckAccepted * 0.5 * (e.det - e.det_error) * (1.0 - 0x1p-50);
}

}  // namespace
}  // namespace detail2
}  // namespace tetia
