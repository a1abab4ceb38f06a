// src/kernel/tri_certified_moments.hpp -- the area and first moments of the intersection of two
// triangles in general position, with an error bound derived below, without the kernel's
// labels: the 2D kernel's first step (tri_kernel.hpp), which answers most pairs.
//
// Contract: certified_moments(A, B, m) returns
//  - kSeparated when an edge line of one triangle has the three vertices of the other strictly
//    on its outer side, every orientation involved being certain (Shewchuk's bound); or, for
//    two triangles with a vertex in common (neighbours in a mesh), on its closed outer side,
//    the signs the bounds leave open decided exactly (closed_separation): the exact area is 0.
//  - kCertified when |m.area - exact area| <= kAcceptedError times the smaller triangle's area
//    (a bound, rounding included, not an estimate) and m.area is at least kSmallestFraction of
//    it; m.first: the first moments of the same polygon (not bounded).
//  - kUncertain otherwise: an orientation within its error bound (a vertex on or near an edge
//    line of the other triangle: overlapping triangles with a vertex in common, collinear
//    edges), a triangle whose own orientation is not certain, two crossings on one edge too
//    close to order, a bound above the threshold, a small overlap, a coordinate outside
//    [-2^300, 2^300] or not finite. The kernel decides those.
// The outcome and the bits of m depend on A and B as two sets of three points only: not on the
// order of the triangles nor of their vertices. Nothing allocates, nothing throws.
//
// Method. Each triangle is put in a canonical order: its lexicographically smallest vertex
// first (smallest abscissa, then ordinate), then counter-clockwise. S is the one with the
// smaller determinant (equal determinants: the lexicographically smaller canonical triangle),
// L the other. Everything is measured in S's own frame, where S is the unit
// triangle: o = S0 -> (0, 0), S1 -> (1, 0), S2 -> (0, 1), lambda = (l1, l2) the barycentric
// coordinates of S1 and S2, as the kernel measures areas (tri_kernel.hpp, step 5). Every corner
// of S n L is
//  - a vertex of S: exact in the frame;
//  - a crossing of S's edge f with L's edge line k: the weight t = g_p / (g_p - g_q) along f,
//    g_p, g_q the orientations of f's ends against line k (a point (t, 0), (1 - t, t) or
//    (0, 1 - t) on edge 0, 1 or 2);
//  - a vertex of L inside S: lambda = (g_2, g_0) / det(S), g_k its orientation against S's edge k.
// Which corners, and how they connect, follows from signs: S's edge f is clipped by L's three
// lines to its part inside L, [t0, t1], which starts where f enters L across line k0 and ends
// where it leaves across k1. L's edge e then runs inside S from the crossing where S's part on f
// ends on line e (k1 = e: the boundary turns from S's edge onto L's), or from L's vertex e if
// that is inside S, to the crossing where a part of S starts on line e, or L's vertex e + 1.
// Twice the area is the fan from o over the boundary: S's parts on edges 0 and 2 lie on lines
// through o and add exactly 0 (one coordinate is exactly 0 in the frame); S's part on edge 1
// adds t1 - t0; L's part from P to Q adds P x Q. Each crossing is computed once and shared by
// the two parts it ends, so the computed polygon is closed. Area = det(S) / 2 times that;
// first moments likewise (the fan's triangles' centroids), mapped back as the kernel does.
//
// Error bound, eps = 2^-53, for twice the area in the frame; then times det(S).
//  (1) Each orientation g = (b - a) x (x - a) is computed as Shewchuk's orient2d computes it:
//      |g_computed - g| <= E = (3 + 16 eps) eps (|l| + |r|) for its two computed products l, r,
//      plus 2^-1000 for roundings in the subnormal range (the bound assumes none). All 18 must
//      have |g| > E (certain signs), and det(S), det(L) likewise. (In the third try below, each
//      from exact differences and products instead: E = eps |g| + 2^-49 of its small terms +
//      2^-1060, accurate_orientations.)
//  (2) A crossing t = g_p * (1 / (g_p - g_q)) is within dt of the exact one:
//      dt = Q' (1 + 2 Q)(1 + 16 eps) + 4 eps, Q = (E_p + E_q) / D <= 1/2, D = |g_p - g_q|,
//      Q' = (E_p |g_q| + E_q |g_p|) / D^2 <= Q. (On the box of radii E_p, E_q around the
//      computed (g_p, g_q), which holds the exact pair, the signs are opposite, so t = a / (a + b)
//      with a = |x|, b = |y|, increasing in a and decreasing in b: its extremes are at two
//      corners, (a0 + E_p, b0 - E_q) and (a0 - E_p, b0 + E_q), where it differs from the
//      quotient of the computed g's by (E_p b0 + E_q a0) / (D (D +- (E_p - E_q))), at most
//      Q' / (1 - Q) <= Q' (1 + 2 Q). A crossing near a vertex of S, t or 1 - t small, has
//      Q' far below Q. The three roundings of t and Q's own add the rest, and 2^-1000 for
//      underflow: Q' is evaluated as (E_p / D)(|g_q| / D) + (E_q / D)(|g_p| / D), factors of
//      at most 1/2 and 1, so an underflowing product loses no more than that.) t0 = max(0,
//      lower ones) and t1 = min(1, upper ones) are within the dt of the one chosen, provided
//      the choice is certain: two crossings on one side of an edge must differ by more than
//      their dt's, and a part is certainly non-empty (t1 - t0 > dt0 + dt1 + eps) or certainly
//      empty. Then the computed corners are the exact ones, moved, in the same combinatorial
//      order.
//  (3) Moving the corners V_i of a closed polygon by d_i changes twice its area by
//      sum_i d_i x (V_{i+1} - V_{i-1}) + sum_i d_i x d_{i+1}. A crossing moves along S's edge f
//      by dt (d_f = (1, 0), (-1, 1), (0, -1) in the frame): one of its neighbours lies along f,
//      which cancels, the other along L's edge, w = the exact side on L's edge, so its term is at
//      most dt |d_f x w| <= dt (|d_f x w_computed| + |d_f|_1 m), m the max-norm bound of the
//      ends' other moves (the crossing's own move along f is parallel to d_f: it does not count).
//      (This is why a shallow crossing, whose t is ill-conditioned, costs little: the side it
//      slides along is nearly parallel to f.) S's side on edge 1 adds t1 - t0, linear in the
//      ends' weights: no second order there. Everything else (the rounding of 1 - t, the
//      coordinates of a vertex of L: (E_k + 2.01 eps |g_k|) / det + |lambda| rel(det), rel(det)
//      = det's error bound over det less it) moves a corner by at most a in the max norm, and
//      |V_{i+1} - V_{i-1}|_1 <= 2 in the unit triangle: 2 a. For a vertex of L, whose
//      neighbours (the start of L's part before it, the end of its own part) are often close to
//      it, the computed neighbours instead: |V_{i+1} - V_{i-1}|_1 <= |V'_{i+1} - V'_{i-1}|_1 +
//      2 (m_{i+1} + m_{i-1}), m the neighbours' max-norm moves (a + dt for a crossing), so
//      a min(2, that). Second order: 2 |d_0|_inf |d_1|_inf per side.
//  (4) Evaluation: P x Q rounds to within 2.01 eps (|P_x Q_y| + |P_y Q_x|); t1 - t0 within eps
//      of itself; the sum of at most four terms within 3.01 eps of the sum of their magnitudes.
//  (5) In original units: det times that, plus |twice the area in the frame| times det's error
//      bound, plus the last product's rounding; the bound evaluated with a factor 1 + 64 eps for
//      its own roundings. det(S) is computed from exact differences and products
//      (accurate_det, bounded_det): its bound is eps of itself, where the plain one, 3 eps of
//      its products, is eps times S's condition number (the largest term for most needles).
// Tries. The bound is first evaluated with the plain det(S) and Shewchuk's bounds; where it does
// not accept, again with det(S) accurate (5) and the vertices' neighbours in (3); where that
// does not, again from accurate orientations, reclipped. Each try is a computation with its own
// bound, accepted on it alone; which one accepts depends on the two triangles as point sets
// only, so every entry point and order still gets the same bits. Of the random pairs accepted,
// 96 % are accepted by the first try, 3.5 % by the second, 0.2 % by the third; of near-identical
// pairs (B = A moved by 1e-12, turned by 1e-10), 80 %, 8 % and 12 %.
// Coordinates within [-2^300, 2^300] keep every product below 2^1000 and every first moment
// below 2^910; det(S) >= 2^-600 keeps the products the frame divides by normal.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "exact_sign.hpp"  // two_diff, two_product, orient2d_sign
#include "tetia/geometry.hpp"
#include "tetia/polygon.hpp"  // Moments2

namespace tetia {
namespace detail2 {
namespace {

enum class Certified : std::uint8_t { kUncertain, kSeparated, kCertified };

// The largest bound accepted, relative to the smaller triangle's area.
constexpr double kAcceptedError = 0x1p-47;
// A certified area is at least this fraction of the smaller triangle's, far above any error:
// the polygon intersect() builds for it is never empty, and smaller overlaps (an edge grazing a
// vertex) go to the kernel.
constexpr double kSmallestFraction = 0x1p-30;

namespace certified {

constexpr double kEps = 0x1p-53;
constexpr double kOrientBound = (3.0 + 16.0 * kEps) * kEps;  // Shewchuk's ccwerrboundA
constexpr double kUnderflow = 0x1p-1000;                     // slack for subnormal roundings
constexpr double kRange = 0x1p300;
constexpr double kSmallestDet = 0x1p-600;

// A triangle with its lexicographically smallest vertex first, then counter-clockwise.
// det = (p1 - p0) x (p2 - p0) > det_error (its error bound) when `certain`.
struct Canonical {
  Vec2 p[3];
  int index[3];  // the caller's index of vertex p[k]
  double det;
  double det_error;
  bool certain;
};

[[gnu::always_inline]] inline Canonical canonical(const Triangle& t) {
  static constexpr int kNext[3] = {1, 2, 0}, kPrev[3] = {2, 0, 1};
  // Without branches where the abscissas differ: the order is random. Where two tie (a
  // structured mesh's right triangles), the ordinates decide: lexicographic order, out of the
  // way (distinct points of a triangle that is certainly not flat).
  int m01 = t[1].x < t[0].x ? 1 : 0;
  int m = t[2].x < t[m01].x ? 2 : m01;
  if (int(t[0].x == t[1].x) | int(t[1].x == t[2].x) | int(t[0].x == t[2].x)) [[unlikely]] {
    const auto before = [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); };
    m01 = before(t[1], t[0]) ? 1 : 0;
    m = before(t[2], t[m01]) ? 2 : m01;
  }
  Canonical c;
  c.p[0] = t[m];
  c.p[1] = t[kNext[m]];
  c.p[2] = t[kPrev[m]];
  c.index[0] = m;
  const Vec2 e1 = c.p[1] - c.p[0], e2 = c.p[2] - c.p[0];
  const double l = e1.x * e2.y, r = e1.y * e2.x;
  const double det = l - r;
  // The reversed order computes exactly -det (the same products, swapped): one value either way.
  const bool flip = det < 0.0;
  const Vec2 p1 = c.p[1];
  c.p[1] = flip ? c.p[2] : p1;
  c.p[2] = flip ? p1 : c.p[2];
  c.index[1] = flip ? kPrev[m] : kNext[m];
  c.index[2] = flip ? kNext[m] : kPrev[m];
  c.det = std::abs(det);
  c.det_error = kOrientBound * (std::abs(l) + std::abs(r)) + kUnderflow;
  // det > 0 also means three distinct points, so that the first vertex is one of them whatever
  // the input's order.
  c.certain = c.det > c.det_error;
  return c;
}

// Whether a's canonical vertices come before b's, compared coordinate by coordinate.
inline bool lexicographically_less(const Canonical& a, const Canonical& b) {
  const double* pa = &a.p[0].x;
  const double* pb = &b.p[0].x;
  return std::lexicographical_compare(pa, pa + 6, pb, pb + 6);
}

// Four lanes of doubles: lanes 0-2 a triangle's three vertices (or edges), lane 3 a copy of lane
// 0, so that "all lanes" means all three. GCC's and Clang's vector extensions, one AVX register
// where the variant has AVX (x86-64-v3), else two SSE2 halves (a 32-byte vector without AVX
// would change the ABI and compile to scalar code). Every lane is an IEEE operation, so both
// give the same bits.
#if defined(__AVX__)
using v4d = double __attribute__((vector_size(32)));
using v4i = std::int64_t __attribute__((vector_size(32)));
[[gnu::always_inline]] inline v4d lanes(double a, double b, double c, double d) { return (v4d){a, b, c, d}; }
[[gnu::always_inline]] inline v4i mask_of(bool m) { return m ? (v4i){-1, -1, -1, -1} : (v4i){0, 0, 0, 0}; }
[[gnu::always_inline]] inline v4d vabs(const v4d& x) {
  return (v4d)((v4i)x & (v4i){INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX});
}
[[gnu::always_inline]] inline v4d select(const v4i& m, const v4d& a, const v4d& b) { return m ? a : b; }
// Lane f -> lane f + 1 (mod 3): the other end of edge f.
[[gnu::always_inline]] inline v4d next(const v4d& x) { return __builtin_shufflevector(x, x, 1, 2, 0, 1); }
#else
using v2d = double __attribute__((vector_size(16)));
using v2i = std::int64_t __attribute__((vector_size(16)));
struct v4i {
  v2i lo, hi;
  std::int64_t operator[](int k) const { return k < 2 ? lo[k] : hi[k - 2]; }
};
struct v4d {
  v2d lo, hi;
  double operator[](int k) const { return k < 2 ? lo[k] : hi[k - 2]; }
};
[[gnu::always_inline]] inline v4d lanes(double a, double b, double c, double d) { return {(v2d){a, b}, (v2d){c, d}}; }
[[gnu::always_inline]] inline v4i mask_of(bool m) {
  const v2i h = m ? (v2i){-1, -1} : (v2i){0, 0};
  return {h, h};
}
#define TETIA_LANES_OP(R, T, op) \
  [[gnu::always_inline]] inline R operator op(const T& a, const T& b) { return {a.lo op b.lo, a.hi op b.hi}; }
TETIA_LANES_OP(v4d, v4d, +)
TETIA_LANES_OP(v4d, v4d, -)
TETIA_LANES_OP(v4d, v4d, *)
TETIA_LANES_OP(v4d, v4d, /)
TETIA_LANES_OP(v4i, v4d, <)
TETIA_LANES_OP(v4i, v4d, >)
TETIA_LANES_OP(v4i, v4d, <=)
TETIA_LANES_OP(v4i, v4d, ==)
TETIA_LANES_OP(v4i, v4i, &)
TETIA_LANES_OP(v4i, v4i, |)
#undef TETIA_LANES_OP
[[gnu::always_inline]] inline v4d operator-(const v4d& a) { return {-a.lo, -a.hi}; }
[[gnu::always_inline]] inline v4i operator~(const v4i& a) { return {~a.lo, ~a.hi}; }
[[gnu::always_inline]] inline v4i& operator|=(v4i& a, const v4i& b) { return a = a | b; }
[[gnu::always_inline]] inline v4d vabs(const v4d& x) {
  const v2i m = {INT64_MAX, INT64_MAX};
  return {(v2d)((v2i)x.lo & m), (v2d)((v2i)x.hi & m)};
}
[[gnu::always_inline]] inline v4d select(const v4i& m, const v4d& a, const v4d& b) {
  return {m.lo ? a.lo : b.lo, m.hi ? a.hi : b.hi};
}
[[gnu::always_inline]] inline v4d next(const v4d& x) { return {__builtin_shufflevector(x.lo, x.hi, 1, 2), x.lo}; }
#endif
[[gnu::always_inline]] inline v4d splat(double x) { return lanes(x, x, x, x); }
// Bit k: lane k of a mask (lanes are all ones or all zeros).
[[gnu::always_inline]] inline unsigned bits(const v4i& m) {
#if defined(__AVX__)
  return unsigned(_mm256_movemask_pd(__m256d(m)));
#elif defined(__SSE2__)
  return unsigned(_mm_movemask_pd(__m128d(m.lo))) | unsigned(_mm_movemask_pd(__m128d(m.hi))) << 2;
#else
  return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1 | unsigned(m[2] & 1) << 2 | unsigned(m[3] & 1) << 3;
#endif
}
[[gnu::always_inline]] inline bool all(const v4i& m) { return bits(m) == 15u; }
[[gnu::always_inline]] inline bool any(const v4i& m) { return bits(m) != 0u; }

// Knuth's and Dekker's error-free difference and product, for doubles (exact_sign.hpp) and lane
// by lane: d + e = a - b and p + e = a b exactly, no overflow (|a|, |b| < 2^996).
using detail::exact_sign_impl::two_diff;
using detail::exact_sign_impl::two_product;
[[gnu::always_inline]] inline void two_diff(const v4d& a, const v4d& b, v4d& d, v4d& e) {
  d = a - b;
  const v4d bv = a - d;
  e = (a - (d + bv)) + (bv - b);
}
[[gnu::always_inline]] inline void two_product(const v4d& a, const v4d& b, v4d& p, v4d& e) {
  p = a * b;
  const v4d split = splat(134217729.0);  // 2^27 + 1, Dekker's split
  const v4d ca = split * a, cb = split * b;
  const v4d ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
  e = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
}
[[gnu::always_inline]] inline double abs_of(double x) { return std::abs(x); }
[[gnu::always_inline]] inline v4d abs_of(const v4d& x) { return vabs(x); }
template <class T>
T filled(double x);
template <>
[[gnu::always_inline]] inline double filled<double>(double x) {
  return x;
}
template <>
[[gnu::always_inline]] inline v4d filled<v4d>(double x) {
  return splat(x);
}

// det[b - a, c - a] with an error bound, from its differences b - a = (h0 + l0, h2 + l2) and
// c - a = (h3 + l3, h1 + l1), exact (two_diff): with h0 h1 = p + ep, h2 h3 = q + eq, p - q =
// d + ed exactly (two_product, two_diff),
//   det = d + (ed + ep - eq) + (h0 l1 + l0 h1 - h2 l3 - l2 h3) + (l0 l1 - l2 l3);
// the small terms summed in doubles are within 2^-49 of the sum of their magnitudes plus
// 2^-1060 (exact_sign.hpp, orient2d_nearest's stage 1: coordinates within 2^300 keep Dekker's
// split from overflowing; underflowing products lose at most 2^-1075 each), and the value adds
// its own rounding. Against Shewchuk's bound on the plain determinant, 3 eps of its products,
// this is eps of the determinant itself. T: double, or v4d for four at once.
template <class T>
struct Bounded {
  T value, error;
};

template <class T>
[[gnu::always_inline]] inline Bounded<T> bounded_det(const T (&h)[4], const T (&l)[4]) {
  T p, ep, q, eq, d, ed;
  two_product(h[0], h[1], p, ep);
  two_product(h[2], h[3], q, eq);
  two_diff(p, q, d, ed);
  const T c1 = h[0] * l[1], c2 = l[0] * h[1], c3 = h[2] * l[3], c4 = l[2] * h[3];
  const T c5 = l[0] * l[1], c6 = l[2] * l[3];
  const T rest = ((ed + (ep - eq)) + ((c1 + c2) - (c3 + c4))) + (c5 - c6);
  const T magnitude = ((abs_of(ed) + (abs_of(ep) + abs_of(eq))) + ((abs_of(c1) + abs_of(c2)) + (abs_of(c3) + abs_of(c4)))) +
                      (abs_of(c5) + abs_of(c6));
  const T value = d + rest;
  return {value, (filled<T>(kEps) * abs_of(value) + filled<T>(0x1p-49) * magnitude) + filled<T>(0x1p-1060)};
}

// det(S) = (p1 - p0) x (p2 - p0) of a canonical triangle, with its bound (5): a needle's frame
// no longer costs its condition number.
[[gnu::always_inline]] inline Bounded<double> accurate_det(const Canonical& t) {
  double h[4], l[4];
  detail::exact_sign_impl::exact_differences(t.p[0].x, t.p[0].y, t.p[1].x, t.p[1].y, t.p[2].x, t.p[2].y, h, l);
  return bounded_det(h, l);
}

// Orientations of x's three vertices (lanes) against t's edge line k (from t.p[k] to
// t.p[k + 1]), positive inside, with their error bounds: g[k], e[k].
[[gnu::always_inline]] inline void orientations(const Canonical& t, const Canonical& x, v4d (&g)[3], v4d (&e)[3]) {
  const v4d px = lanes(x.p[0].x, x.p[1].x, x.p[2].x, x.p[0].x);
  const v4d py = lanes(x.p[0].y, x.p[1].y, x.p[2].y, x.p[0].y);
  for (int k = 0; k < 3; ++k) {
    const Vec2 a = t.p[k], d = t.p[k == 2 ? 0 : k + 1] - t.p[k];
    const v4d l = splat(d.x) * (py - splat(a.y)), r = splat(d.y) * (px - splat(a.x));
    g[k] = l - r;
    e[k] = splat(kOrientBound) * (vabs(l) + vabs(r)) + splat(kUnderflow);
  }
}

// Whether an edge line of one triangle has the other's three vertices on its closed outer side,
// each sign certain by its bound (orientations) or else exact (exact_sign.hpp): the exact area
// is then 0, the triangles at most touch (a vertex or a part of an edge in common). Both
// triangles' lines are looked at, so the answer is a property of the pair, whatever the order.
// A line with a vertex of the other certainly inside is passed over without an exact sign.
inline bool closed_separation(const Canonical& ca, const Canonical& cb) {
  v4d g[3], e[3];
  for (int way = 0; way < 2; ++way) {
    const Canonical& t = way == 0 ? ca : cb;
    const Canonical& x = way == 0 ? cb : ca;
    orientations(t, x, g, e);
    for (int k = 0; k < 3; ++k) {
      if (any(g[k] - e[k] > splat(0.0))) continue;  // a vertex certainly inside
      const v4i beyond = g[k] + e[k] < splat(0.0);
      bool outside = true;
      for (int i = 0; i < 3 && outside; ++i) {
        if (beyond[i]) continue;
        const Vec2 a = t.p[k], b = t.p[k == 2 ? 0 : k + 1], p = x.p[i];
        const int side = detail::orient2d_sign(a.x, a.y, b.x, b.y, p.x, p.y);  // 2: unknown
        outside = side == 0 || side == -1;
      }
      if (outside) return true;
    }
  }
  return false;
}

// S's three edges (lanes f: from S.p[f] to S.p[f + 1]) clipped by L's three lines: the
// crossing weights and the part inside L, (2). g, err: L's lines at S's vertices.
struct EdgeParts {
  v4d t0, t1, dt0, dt1;
  v4d k0, k1;     // the line the part starts on (enters L) and ends on (leaves L); -1: a vertex
  v4i nonempty;   // certainly a part of positive length
  bool certain;   // every decision is certain
};

[[gnu::always_inline]] inline EdgeParts clip_edges(const v4d (&g)[3], const v4d (&err)[3]) {
  EdgeParts p;
  p.t0 = splat(0.0);
  p.t1 = splat(1.0);
  p.dt0 = p.dt1 = splat(0.0);
  p.k0 = p.k1 = splat(-1.0);
  v4i outside = mask_of(false), upper[3], lower[3];
  v4d t[3], dt[3];
  for (int k = 0; k < 3; ++k) {
    const v4d gp = g[k], gq = next(g[k]);
    const v4d zero = splat(0.0);
    outside |= (gp < zero) & (gq < zero);
    upper[k] = (gp > zero) & (gq < zero);  // leaves L across line k
    lower[k] = (gp < zero) & (gq > zero);  // enters L across line k
    const v4d inv = splat(1.0) / (gp - gq), inv_abs = vabs(inv);
    const v4d ep = err[k] * inv_abs, eq = next(err[k]) * inv_abs;  // E_p / D, E_q / D
    const v4d q = ep + eq;
    const v4d q_sharp = ep * (vabs(gq) * inv_abs) + eq * (vabs(gp) * inv_abs);  // Q' of (2)
    t[k] = gp * inv;
    dt[k] = select(q <= splat(0.5),
                   q_sharp * (splat(1.0) + splat(2.0) * q) * splat(1.0 + 16.0 * kEps) + splat(4.0 * kEps + kUnderflow),
                   splat(INFINITY));
    const v4i up_smaller = upper[k] & (t[k] < p.t1);
    p.t1 = select(up_smaller, t[k], p.t1);
    p.dt1 = select(up_smaller, dt[k], p.dt1);
    p.k1 = select(up_smaller, splat(double(k)), p.k1);
    const v4i lo_larger = lower[k] & (t[k] > p.t0);
    p.t0 = select(lo_larger, t[k], p.t0);
    p.dt0 = select(lo_larger, dt[k], p.dt0);
    p.k0 = select(lo_larger, splat(double(k)), p.k0);
  }
  // Two crossings on one side of an edge must be ordered certainly.
  v4i uncertain = mask_of(false);
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      uncertain |= ((upper[a] & upper[b]) | (lower[a] & lower[b])) & (vabs(t[a] - t[b]) <= dt[a] + dt[b]);
  const v4d span = p.t1 - p.t0, slack = p.dt0 + p.dt1 + splat(kEps);
  p.nonempty = ~outside & (span > slack);
  const v4i decided = outside | p.nonempty | (-span > slack);
  p.certain = int(!any(uncertain)) & int(all(decided));
  return p;
}

// One of S's edges clipped, as scalars: the part [t0, t1] inside L (within dt0, dt1), the lines of
// L it starts and ends on (-1: S's vertex), whether it is certainly of positive length.
struct EdgePart {
  double t0, t1, dt0, dt1;
  int k0, k1;
  bool nonempty;
};

constexpr Vec2 kEdgeDirection[3] = {{1.0, 0.0}, {-1.0, 1.0}, {0.0, -1.0}};

}  // namespace certified

// What a Polygon is built from where the formula certified (tri_kernel.hpp, PolygonBuilder):
// the two canonical triangles, the orientations, and how the parts connect.
struct CertifiedShape {
  bool s_is_a;  // S is the caller's A
  certified::Canonical S, L;
  double gs[3][3];  // S's edge line k at L's vertex i: gs[k][i]
  double gl[3][3];  // L's edge line k at S's vertex f: gl[k][f]
  certified::EdgePart part[3];
  int start_f[3], end_f[3];  // L's part on edge e starts where S's part start_f[e] ends (-1: L's vertex e), ...
  bool l_inside[3];          // L's vertex i is inside S
};

namespace certified {

// The orientations of x's three vertices (lanes) against t's edge lines, as orientations(), each
// with bounded_det's bound instead of Shewchuk's (3 eps of its products). For the third try.
inline void accurate_orientations(const Canonical& t, const Canonical& x, v4d (&g)[3], v4d (&e)[3]) {
  const v4d px = lanes(x.p[0].x, x.p[1].x, x.p[2].x, x.p[0].x);
  const v4d py = lanes(x.p[0].y, x.p[1].y, x.p[2].y, x.p[0].y);
  for (int k = 0; k < 3; ++k) {
    const Vec2 a = t.p[k], b = t.p[k == 2 ? 0 : k + 1];
    double dxh, dxl, dyh, dyl;
    two_diff(b.x, a.x, dxh, dxl);
    two_diff(b.y, a.y, dyh, dyl);
    v4d h[4], l[4];  // b - a and x - a, as bounded_det takes them
    two_diff(py, splat(a.y), h[1], l[1]);
    two_diff(px, splat(a.x), h[3], l[3]);
    h[0] = splat(dxh), l[0] = splat(dxl), h[2] = splat(dyh), l[2] = splat(dyl);
    const Bounded<v4d> o = bounded_det(h, l);
    g[k] = o.value;
    e[k] = o.error;
  }
}

// How the parts connect: S's edges clipped (their ends' weights in lanes, and as scalars), which
// part of S ends (starts) on L's line e (slot 3: the parts that end (start) at a vertex of S),
// which of L's vertices lie inside S.
struct Connection {
  v4d t0, t1;
  EdgePart part[3];
  int start_f[4], end_f[4];
  unsigned l_inside;
};

// The connection from the orientations (L's lines at S's vertices: gl, el; S's lines at L's
// vertices: gs); false where a decision is not certain.
[[gnu::always_inline]] inline bool connect(const v4d (&gs)[3], const v4d (&gl)[3], const v4d (&el)[3], Connection& c) {
  const EdgeParts parts = clip_edges(gl, el);
  if (!parts.certain) return false;
  c.t0 = parts.t0;
  c.t1 = parts.t1;
  // The parts' lanes as scalars for the assembly (through memory: one store a vector).
  {
    double t0[4], t1[4], dt0[4], dt1[4], k0[4], k1[4];
    std::memcpy(t0, &parts.t0, sizeof t0);
    std::memcpy(t1, &parts.t1, sizeof t1);
    std::memcpy(dt0, &parts.dt0, sizeof dt0);
    std::memcpy(dt1, &parts.dt1, sizeof dt1);
    std::memcpy(k0, &parts.k0, sizeof k0);
    std::memcpy(k1, &parts.k1, sizeof k1);
    const unsigned nonempty = bits(parts.nonempty);
    for (int f = 0; f < 3; ++f) c.part[f] = {t0[f], t1[f], dt0[f], dt1[f], int(k0[f]), int(k1[f]), ((nonempty >> f) & 1u) != 0};
  }
  const v4d zero = splat(0.0);
  c.l_inside = bits((gs[0] > zero) & (gs[1] > zero) & (gs[2] > zero));
  for (int k = 0; k < 4; ++k) c.start_f[k] = c.end_f[k] = -1;
  for (int f = 0; f < 3; ++f) {
    c.start_f[(c.part[f].nonempty & (c.part[f].k1 >= 0)) ? c.part[f].k1 : 3] = f;
    c.end_f[(c.part[f].nonempty & (c.part[f].k0 >= 0)) ? c.part[f].k0 : 3] = f;
  }
  // L's part on edge e exists where it starts (a crossing, or L's vertex e inside S); with
  // certain decisions it then ends too.
  bool consistent = true;
  for (int e = 0; e < 3; ++e) {
    const int j = e == 2 ? 0 : e + 1;
    consistent &= ((c.start_f[e] >= 0) | (((c.l_inside >> e) & 1u) != 0)) == ((c.end_f[e] >= 0) | (((c.l_inside >> j) & 1u) != 0));
  }
  return consistent;
}

// The area, its moments and its bound from a connection, with det(S) and det's error bound;
// kSecond: with the vertices' neighbours in (3) (the tries after the first). Returns 1 where
// accepted (m set), 0 where only the bound failed, -1 where the area is too small.
template <bool kFirst, bool kSecond>
[[gnu::always_inline]] inline int assemble(const Canonical& S, const v4d (&gs)[3], const v4d (&es)[3], const Connection& c,
                                           double det, double det_error, Moments2& m) {
  // The ends of S's parts in the frame (lanes f): base_f + t dir_f, (t, 0), (1 - t, t), (0, 1 - t).
  const v4d base_x = lanes(0.0, 1.0, 0.0, 0.0), base_y = lanes(0.0, 0.0, 1.0, 0.0);
  const v4d dir_x = lanes(1.0, -1.0, 0.0, 1.0), dir_y = lanes(0.0, 1.0, -1.0, 0.0);
  const v4d sx0 = base_x + c.t0 * dir_x, sy0 = base_y + c.t0 * dir_y;
  const v4d sx1 = base_x + c.t1 * dir_x, sy1 = base_y + c.t1 * dir_y;
  const double det_low = (det - det_error) * (1.0 - kEps);  // a lower bound on |det(S)|
  const double inv_det = 1.0 / det, inv_det_low = (1.0 / det_low) * (1.0 + 2.0 * kEps);
  const double det_rel = det_error * inv_det_low * (1.0 + 2.0 * kEps);
  // Candidate corners, all computed and then selected (branches here would follow random data).
  // L's vertices in the frame (lanes), used where inside S, with their bounds a of (3): the
  // weights of S1 and S2 are the orientations against S's edges 2 and 0 over det(S).
  const v4d vx = gs[2] * splat(inv_det), vy = gs[0] * splat(inv_det);
  const v4d va = (select(es[2] > es[0], es[2], es[0]) +
                  splat(2.01 * kEps) * select(vabs(gs[2]) > vabs(gs[0]), vabs(gs[2]), vabs(gs[0]))) *
                     splat(inv_det_low) +
                 select(vabs(vx) > vabs(vy), vabs(vx), vabs(vy)) * splat(det_rel);

  double area2 = 0.0, bound = 0.0, magnitude = 0.0;
  Vec2 first6{0.0, 0.0};
  // S's part on edge 1 (edges 0 and 2 lie on lines through o: exactly 0): t1 - t0.
  {
    const EdgePart& p = c.part[1];
    const double term = p.nonempty ? p.t1 - p.t0 : 0.0;
    area2 += term;
    if constexpr (kFirst) first6 = first6 + term * Vec2{(1.0 - p.t0) + (1.0 - p.t1), p.t0 + p.t1};
    magnitude += std::abs(term);
    // (4); no second order: the term is linear in t0 and t1 (both ends move along edge 1).
    bound += p.nonempty ? 1.01 * kEps * std::abs(term) : 0.0;
  }
  // L's parts: their ends first (a vertex of L needs its neighbours for (3)), then the terms.
  Vec2 end0[3], end1[3];        // L's part on edge e runs from end0[e] to end1[e]
  double a_end0[3], a_end1[3];  // the ends' moves in the max norm but along S's edges, (3)
  double dt_end0[3], dt_end1[3];
  for (int e = 0; e < 3; ++e) {
    const int i = e, j = e == 2 ? 0 : e + 1;
    const int fs = c.start_f[e], fe = c.end_f[e];
    const bool cross0 = fs >= 0, cross1 = fe >= 0;
    const int f0 = cross0 ? fs : 0, f1 = cross1 ? fe : 0;
    // Start: where S's part on f0 ends (t1), or L's vertex i; end: where S's part on f1 starts
    // (t0), or L's vertex j.
    end0[e] = {cross0 ? sx1[f0] : vx[i], cross0 ? sy1[f0] : vy[i]};
    end1[e] = {cross1 ? sx0[f1] : vx[j], cross1 ? sy0[f1] : vy[j]};
    a_end0[e] = cross0 ? 1.01 * kEps : va[i];
    a_end1[e] = cross1 ? 1.01 * kEps : va[j];
    dt_end0[e] = cross0 ? c.part[f0].dt1 : 0.0;
    dt_end1[e] = cross1 ? c.part[f1].dt0 : 0.0;
  }
  for (int e = 0; e < 3; ++e) {
    const int fs = c.start_f[e], fe = c.end_f[e];
    const bool cross0 = fs >= 0, cross1 = fe >= 0;
    const int f0 = cross0 ? fs : 0, f1 = cross1 ? fe : 0;
    const bool has0 = cross0 | (((c.l_inside >> e) & 1u) != 0);
    const Vec2 p0 = end0[e], p1 = end1[e];
    const double a0 = a_end0[e], a1 = a_end1[e], dt0 = dt_end0[e], dt1 = dt_end1[e];
    const double l = p0.x * p1.y, r = p0.y * p1.x;
    const double term = has0 ? l - r : 0.0;
    area2 += term;
    if constexpr (kFirst) first6 = first6 + term * (p0 + p1);
    magnitude += std::abs(term);
    // (3), each corner once: a crossing ends exactly one part of S and one of L (its move
    // along f here, where its side along L's edge is), a vertex of L starts one part of L.
    // The side w = p1 - p0 is the computed one: the exact one differs by the ends' moves, but
    // an end's own move along its edge f does not count in d_f x w.
    const Vec2 w = p1 - p0;
    const auto along = [&](double dt, int f, double moves) {
      const Vec2 d = kEdgeDirection[f];
      return dt * (std::abs(d.x * w.y - d.y * w.x) + (std::abs(d.x) + std::abs(d.y)) * moves);
    };
    double vertex_term = 2.0 * a0;
    if constexpr (kSecond) {
      // A vertex of L at the start: its neighbours are the start of L's part on the edge
      // before (which ends at this vertex) and the end of this part.
      const int before = e == 0 ? 2 : e - 1;
      const Vec2 across = p1 - end0[before];
      const double moves = (a_end0[before] + dt_end0[before]) + (a1 + dt1);
      vertex_term = a0 * std::min(2.0, (std::abs(across.x) + std::abs(across.y)) + 2.0 * moves);
    }
    const double b = 2.01 * kEps * (std::abs(l) + std::abs(r)) +  // (4)
                     along(dt0, f0, a0 + a1 + dt1) + along(dt1, f1, a0 + dt0 + a1) +
                     (cross0 ? 2.0 * a0 : vertex_term) + (cross1 ? 2.0 * a1 : 0.0) +
                     2.0 * (a0 + dt0) * (a1 + dt1);  // second order
    bound += has0 ? b : 0.0;
  }
  bound = (bound + 3.01 * kEps * magnitude) * (1.0 + 16.0 * kEps);
  // (5), relative to the smaller triangle's doubled area (at least det_low).
  const double bound_world = (bound * det + std::abs(area2) * det_error) * (1.0 + 64.0 * kEps) + kEps * std::abs(area2) * det;
  if (!(area2 * det >= kSmallestFraction * det_low)) return -1;
  if (!(bound_world <= kAcceptedError * det_low)) return 0;
  m.area = 0.5 * (area2 * det);
  if constexpr (kFirst) {
    const Vec2 e1 = S.p[1] - S.p[0], e2 = S.p[2] - S.p[0];
    m.first = m.area * S.p[0] + (det * (1.0 / 6.0)) * (first6.x * e1 + first6.y * e2);
  }
  return 1;
}

// The tries after the first (see "Tries" at the top), out of line: they take 3 % of random
// pairs and a fifth of near-identical ones, and inlined beside the first they slowed it down.
// On entry, the first try's orientations and connection; where the third try accepts, its own.
struct LaterTries {
  Canonical ca, cb;
  bool a_smaller;
  v4d gs[3], es[3], gl[3], el[3];
  Connection c;
};

template <bool kFirst>
[[gnu::noinline]] int later_tries(LaterTries& t, Moments2& m) {
  const Canonical& S = t.a_smaller ? t.ca : t.cb;
  const Bounded<double> accurate = accurate_det(S);
  const int second = assemble<kFirst, true>(S, t.gs, t.es, t.c, accurate.value, accurate.error, m);
  if (second != 0) return second;
  v4d gab[3], eab[3], gba[3], eba[3];
  accurate_orientations(t.ca, t.cb, gab, eab);
  accurate_orientations(t.cb, t.ca, gba, eba);
  const v4i certain = (vabs(gab[0]) > eab[0]) & (vabs(gab[1]) > eab[1]) & (vabs(gab[2]) > eab[2]) &
                      (vabs(gba[0]) > eba[0]) & (vabs(gba[1]) > eba[1]) & (vabs(gba[2]) > eba[2]);
  if (!all(certain)) return -1;
  const v4i sel = mask_of(t.a_smaller);
  for (int k = 0; k < 3; ++k) {
    t.gs[k] = select(sel, gab[k], gba[k]);
    t.es[k] = select(sel, eab[k], eba[k]);
    t.gl[k] = select(sel, gba[k], gab[k]);
    t.el[k] = select(sel, eba[k], eab[k]);
  }
  if (!connect(t.gs, t.gl, t.el, t.c)) return -1;
  return assemble<kFirst, true>(S, t.gs, t.es, t.c, accurate.value, accurate.error, m);
}

}  // namespace certified

// kFirst: the first moments too (else m.first is left alone; the area's bits do not depend on it).
// shape: where not null and the result is certified, what intersect() builds its polygon from.
template <bool kFirst>
Certified certified_moments(const Triangle& A, const Triangle& B, Moments2& m, CertifiedShape* shape = nullptr) {
  using namespace certified;
  bool shared;
  {
    const v4d ax = lanes(A[0].x, A[1].x, A[2].x, A[0].x), ay = lanes(A[0].y, A[1].y, A[2].y, A[0].y);
    const v4d bx = lanes(B[0].x, B[1].x, B[2].x, B[0].x), by = lanes(B[0].y, B[1].y, B[2].y, B[0].y);
    const v4d range = splat(kRange);
    const bool in_range = all((vabs(ax) <= range) & (vabs(ay) <= range) & (vabs(bx) <= range) & (vabs(by) <= range));
    // A shared vertex has orientation exactly 0 against two of the other's lines: uncertain, and
    // common in meshes (neighbours, identical cells), so decided before anything else. B's
    // vertices against A's, in B's three rotations.
    const v4d bx1 = next(bx), by1 = next(by), bx2 = next(bx1), by2 = next(by1);
    shared = any(((ax == bx) & (ay == by)) | ((ax == bx1) & (ay == by1)) | ((ax == bx2) & (ay == by2)));
    if (!in_range) return Certified::kUncertain;
  }
  const Canonical ca = canonical(A), cb = canonical(B);
  if (!(ca.certain & cb.certain)) return Certified::kUncertain;
  // Neighbours that share a vertex or an edge only touch, most of the time: decided here, with
  // exact signs where the bounds leave them open; the rest goes to the kernel.
  if (shared) [[unlikely]]
    return closed_separation(ca, cb) ? Certified::kSeparated : Certified::kUncertain;
  // Equal determinants (two cells of one size: a structured mesh against itself moved): the
  // lexicographically smaller canonical triangle, so that the choice depends on the two point
  // sets only. Equal point sets share vertices and were sent on above. (A branch on the tie
  // alone, which is rare, not on which determinant is smaller, which is random.)
  bool a_smaller = ca.det < cb.det;
  if (ca.det == cb.det) [[unlikely]]
    a_smaller = lexicographically_less(ca, cb);
  const Canonical& S = a_smaller ? ca : cb;
  if (!(S.det >= kSmallestDet)) return Certified::kUncertain;
  // Both ways, then selected: a branch on which triangle is smaller mispredicts half the time.
  // One way first: near-identical triangles, and neighbours in a mesh, stop there.
  v4d gab[3], eab[3], gba[3], eba[3];
  orientations(ca, cb, gab, eab);  // B's vertices against A's lines
  const v4d zero = splat(0.0);
  // Whether the three vertices are certainly beyond one of the lines (each orientation below
  // minus its bound): apart, whatever the other orientations.
  const auto beyond = [&](const v4d (&g)[3], const v4d (&e)[3]) {
    return int(all(g[0] + e[0] < zero)) | int(all(g[1] + e[1] < zero)) | int(all(g[2] + e[2] < zero));
  };
  // B beyond one of A's lines: apart, without the other way's orientations (about half of the
  // pairs that are apart; the result, exactly 0, is the same whichever way finds it).
  if (beyond(gab, eab)) return Certified::kSeparated;
  if (!all((vabs(gab[0]) > eab[0]) & (vabs(gab[1]) > eab[1]) & (vabs(gab[2]) > eab[2]))) [[unlikely]] {
    // Uncertain one way; A may still be beyond one of B's lines, and the outcome must not depend
    // on which way was looked at first (the argument order).
    orientations(cb, ca, gba, eba);
    return beyond(gba, eba) ? Certified::kSeparated : Certified::kUncertain;
  }
  orientations(cb, ca, gba, eba);  // A's vertices against B's lines
  v4d gs[3], es[3], gl[3], el[3];
  {
    const v4i m = mask_of(a_smaller);
    for (int k = 0; k < 3; ++k) {
      gs[k] = select(m, gab[k], gba[k]);
      es[k] = select(m, eab[k], eba[k]);
      gl[k] = select(m, gba[k], gab[k]);
      el[k] = select(m, eba[k], eab[k]);
    }
  }
  // A beyond one of B's lines (B beyond one of A's was tested above), whether or not every
  // other orientation is certain.
  if (beyond(gba, eba)) return Certified::kSeparated;
  if (!all((vabs(gba[0]) > eba[0]) & (vabs(gba[1]) > eba[1]) & (vabs(gba[2]) > eba[2]))) return Certified::kUncertain;

  // The first try, with the plain determinant and Shewchuk's bounds on the orientations; where
  // its bound does not accept, the later ones (see "Tries" at the top).
  Connection c;
  if (!connect(gs, gl, el, c)) return Certified::kUncertain;
  const int outcome = assemble<kFirst, false>(S, gs, es, c, S.det, S.det_error, m);
  if (outcome < 0) return Certified::kUncertain;
  if (outcome == 0) [[unlikely]] {
    // Copies, made only here: what the later tries read by reference must not be the first
    // try's locals (their addresses taken, they were kept in memory on every path).
    LaterTries later{ca, cb, a_smaller, {gs[0], gs[1], gs[2]}, {es[0], es[1], es[2]}, {gl[0], gl[1], gl[2]},
                     {el[0], el[1], el[2]}, c};
    if (later_tries<kFirst>(later, m) <= 0) return Certified::kUncertain;
    for (int k = 0; k < 3; ++k) {
      gs[k] = later.gs[k];
      gl[k] = later.gl[k];
    }
    c = later.c;
  }
  if (shape) {
    shape->s_is_a = a_smaller;
    shape->S = S;
    shape->L = a_smaller ? cb : ca;
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) {
        shape->gs[k][i] = gs[k][i];
        shape->gl[k][i] = gl[k][i];
      }
      shape->part[k] = c.part[k];
      shape->start_f[k] = c.start_f[k];
      shape->end_f[k] = c.end_f[k];
      shape->l_inside[k] = ((c.l_inside >> k) & 1u) != 0;
    }
  }
  return Certified::kCertified;
}

}  // namespace
}  // namespace detail2
}  // namespace tetia
