// src/kernel/corner_coordinates.hpp -- the corners of X ∩ Y and their coordinates, computed only
// once the signs have placed a corner on Y: edge corners by eq. (2), face corners by eq. (5)
// where it is well conditioned and by the recursive eq. (4) otherwise, and the guardrail of
// Section 4.1.1 (Table 4) that keeps a corner inside Y.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "kernel.hpp"

namespace tetia::detail {

namespace {

// --- corners ------------------------------------------------------------------------------

// Appends a corner with its labels and returns it, for the caller to write its coordinates
// (and, with kWeights, its weights) in place.
// The count and the planes' masks are kept in `cl`, a local of run() (see there), and copied
// to `out` when the kernel is done.
template <bool kWeights, bool kStats>
inline RawCorner& Kernel<kWeights, kStats>::add_corner(KernelResult& out, CornerList& cl, int l0, int l1, int l2,
                                                        u8 kind, int index) {
  if (cl.num_corners >= KernelResult::kMaxCorners) {  // impossible for a simple polytope
    note_inconsistency();
    return overflow_;
  }
  const int c = cl.num_corners++;
  RawCorner& rc = out.corners[c];
  // Callers pass the labels ascending (faces of X first, then planes of Y, each ascending).
  rc.labels[0] = static_cast<u8>(l0);
  rc.labels[1] = static_cast<u8>(l1);
  rc.labels[2] = static_cast<u8>(l2);
  rc.kind = kind;
  rc.moved = false;
  rc.index = static_cast<u8>(index);
  const std::uint32_t b = 1u << c;
  cl.on_plane[l0] |= b;
  cl.on_plane[l1] |= b;
  cl.on_plane[l2] |= b;
  return rc;
}

// Guardrails (Section 4.1.1): a corner found on Y by its signs has all coordinates in [0, 1]
// summing to 1. Computed coordinates that disagree (rounding when an edge of X lies in a
// plane of Y) are clamped to 0 and the rest renormalized; the coordinates of the planes it
// lies on stay exactly 0. If nothing is left, the midpoint of the admissible coordinates
// (one choice in the spirit of Table 4).
// nonneg: bit p set if b[p] >= 0 (nonneg_lanes of the values just stored in b).
// Returns whether the point was moved.
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::guardrail(double (&b)[4], unsigned zero_mask, unsigned nonneg) {
  // The usual case, nothing to clamp, without a call (and the rare one out of the way).
  if (nonneg != 0xF) [[unlikely]] {
    if (clamp_to_simplex(b, zero_mask)) {
      if (stats()) ++stats()->guardrail_clamps;
      return true;
    }
  }
  return false;
}

// The clamping of guardrail; returns whether a coordinate was clamped.
// [[gnu::noinline]] and inline as declared in kernel.hpp (g++ does not accept the attribute
// again on a definition that follows an inline declaration).
template <bool kWeights, bool kStats>
bool Kernel<kWeights, kStats>::clamp_to_simplex(double (&b)[4], unsigned zero_mask) {
  bool clamped = false;
  for (int p = 0; p < 4; ++p)
    if (!(b[p] >= 0.0)) {  // also catches NaN; the zero coordinates are exact zeros already
      b[p] = 0.0;
      clamped = true;
    }
  if (!clamped) return false;  // computed coordinates sum to 1 up to rounding: left as they are
  const double sum = b[0] + b[1] + b[2] + b[3];
  if (sum > 0.0 && sum < INFINITY) {
    const double inv = 1.0 / sum;
    for (double& x : b) x *= inv;
    return true;
  }
  const int free = 4 - std::popcount(zero_mask & 0xFu);
  for (int p = 0; p < 4; ++p) b[p] = bit(zero_mask, p) ? 0.0 : 1.0 / free;
  return true;
}

// The point where edge (s, o) of X meets P_p, s the vertex with p >= 0 and o the one with
// p < 0: eq. (2) written as s + t (o - s), t = p_s / (p_s - p_o). The denominator is at least
// |p_o| > 0 and t lies in [0, 1), so the point stays on the edge whatever the rounding; when
// p_s is exactly 0 (a vertex on the plane, as on shared faces) it is the vertex exactly.
// Also returns the point's barycentric weights on X's vertices in w (exact zeros off the
// edge): they give the corner's coordinates in U when U is the caller's V (see fill()).
template <bool kWeights, bool kStats>
inline Quad Kernel<kWeights, kStats>::edge_point(int i, int j, int p, double (&w)[4]) const {
  const int s = j ^ ((i ^ j) & -int(bit(sm_[i], p))), o = i ^ j ^ s;  // without a branch
  const double t = C_[s][p] / (C_[s][p] - C_[o][p]);
  const Quad b = clear_lanes(lerp(load4(C_[s]), load4(C_[o]), t), 1u << p);
  if constexpr (kWeights) {
    w[0] = w[1] = w[2] = w[3] = 0.0;
    w[s] = 1.0 - t;
    w[o] = t;
  }
  return b;
}

// Coordinates of the corner where edge e meets P_p.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::edge_corner_coords(int e, int p, RawCorner& rc) {
  const Quad q = edge_point(tet_edges[e][0], tet_edges[e][1], p, rc.weights);
  store4(rc.bary, q);
  if (stats()) stats()->corner_coordinates += 3;
  rc.moved = guardrail(rc.bary, 1u << p, nonneg_lanes(q));
}

// Eq. (5) for the corner where face f = (i, j, k) of X meets P_a ∩ P_b, where it is well
// conditioned (the usual case; 98 % of the face corners of the benchmark pairs). By Cramer's
// rule for the two conditions a = b = 0, the point is l_i x_i + l_j x_j + l_k x_k with weights
// proportional to the 2x2 minors of columns (a, b), m_jk, m_ki and m_ij, whose sum is the
// denominator det[1 a b] of eq. (5). It is used only when
// - the three minors have the sign of their sum (tested by products, so that exact zeros
//   pass): the weights are then non-negative, the point a convex combination of the face's
//   vertices, and the sum free of cancellation;
// - the sum is at least 2^-4 of the sum of the six products' magnitudes: each minor's
//   rounding error is at most about 2 eps times its products, so the weights are then
//   accurate to a few dozen ulps;
// - the sum and the products are far from underflow and overflow: the bounds above hold,
//   1 / sum is finite, and the sign test's products (minor times sum) cannot underflow to
//   zero with a minor of the wrong sign unless that minor is below 2^-74 of the sum.
// Leaves the point in res (the coordinates a and b not yet cleared) and, with kWeights, the
// weights in w. Otherwise it returns false, and eq. (4) decides (face_corner_coords). Where a
// face contains the line, eq. (5) is 0/0; its minors then cancel to rounding noise and fail
// the second test.
// The tests are combined without short-circuits: the sum's sign is data, and a branch on it
// was mispredicted often enough to cost 5 % of intersection_volume.
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::face_corner_by_eq5(int f, int a, int b, Quad& res, double (&w)[4]) const {
  const int i = kFaceVerts[f][0], j = kFaceVerts[f][1], k = kFaceVerts[f][2];
  const double* ci = C_[i];
  const double* cj = C_[j];
  const double* ck = C_[k];
  const double p_jk = cj[a] * ck[b], q_jk = cj[b] * ck[a];
  const double p_ki = ck[a] * ci[b], q_ki = ck[b] * ci[a];
  const double p_ij = ci[a] * cj[b], q_ij = ci[b] * cj[a];
  const double m_jk = p_jk - q_jk, m_ki = p_ki - q_ki, m_ij = p_ij - q_ij;
  const double den = (m_jk + m_ki) + m_ij;
  const double mag = ((std::abs(p_jk) + std::abs(q_jk)) + (std::abs(p_ki) + std::abs(q_ki))) +
                     (std::abs(p_ij) + std::abs(q_ij));
  const double size = std::abs(den);
  const bool same_sign = (m_jk * den >= 0.0) & (m_ki * den >= 0.0) & (m_ij * den >= 0.0);
  if (!(same_sign & (size >= 0x1p-4 * mag) & (size >= 0x1p-500) & (mag < 0x1p960))) return false;
  const double inv = 1.0 / den;
  const double li = m_jk * inv, lj = m_ki * inv, lk = m_ij * inv;
  const Quad qi = load4(ci), qj = load4(cj), qk = load4(ck);
#if TETIA_KERNEL_AVX
  res = Quad{_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(li), qi.v), _mm256_mul_pd(_mm256_set1_pd(lj), qj.v)),
                           _mm256_mul_pd(_mm256_set1_pd(lk), qk.v))};
#elif TETIA_KERNEL_SSE2
  const __m128d Li = _mm_set1_pd(li), Lj = _mm_set1_pd(lj), Lk = _mm_set1_pd(lk);
  res = Quad{_mm_add_pd(_mm_add_pd(_mm_mul_pd(Li, qi.lo), _mm_mul_pd(Lj, qj.lo)), _mm_mul_pd(Lk, qk.lo)),
           _mm_add_pd(_mm_add_pd(_mm_mul_pd(Li, qi.hi), _mm_mul_pd(Lj, qj.hi)), _mm_mul_pd(Lk, qk.hi))};
#else
  for (int q = 0; q < 4; ++q) res.v[q] = (li * qi.v[q] + lj * qj.v[q]) + lk * qk.v[q];
#endif
  if constexpr (kWeights) {
    w[f] = 0.0;
    w[i] = li;
    w[j] = lj;
    w[k] = lk;
  }
  return true;
}

// Coordinates of the corner where face f meets P_a ∩ P_b: eq. (5) where it is well
// conditioned (face_corner_by_eq5), else eq. (4). Eq. (5) is 0/0 when the face contains the
// line (an edge of V lying in a face of U), and then places the point anywhere on the line,
// outside X too. The recursive form, eq. (4), interpolates between the two ends
// E1, E2 of the segment (f ∩ P_a) instead: whatever the rounding, the point stays on that
// segment, that is on the face of X. Of the two segments through the point (in P_a and in
// P_b) the one in P_a is used unless it is nearly parallel to the line; then the steeper. The point's value is computed once
// per corner, so the choice cannot make two parts of the algorithm disagree; the decisions
// were all taken on signs.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::face_corner_coords(int f, int a, int b, RawCorner& rc) {
  Quad res;
  if (!face_corner_by_eq5(f, a, b, res, rc.weights)) face_corner_by_eq4(f, a, b, res, rc.weights);
  res = clear_lanes(res, (1u << a) | (1u << b));
  store4(rc.bary, res);
  if (stats()) stats()->corner_coordinates += 2;
  rc.moved = guardrail(rc.bary, (1u << a) | (1u << b), nonneg_lanes(res));
}

// Eq. (4) as described above: the point in res (a and b not yet cleared), the weights in w.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::face_corner_by_eq4(int f, int a, int b, Quad& res, double (&w)[4]) const {
  res = zero4();  // set by the first view below
  if constexpr (kWeights)
    for (int q = 0; q < 4; ++q) w[q] = 0.0;
  double best = -1.0;
  for (const int view : {a, b}) {
    // A segment crossing the line at a clear angle is good enough; the second view is only
    // looked at when the first is nearly parallel to the line.
    if (best > 0x1p-10) break;
    const int cut = view == a ? b : a;  // the coordinate that vanishes along the segment
    const u8* v = seg_verts(f, view);
    const int i = v[0], j = v[1], k = v[2];
    double e[2][4], we[2][4];
    store4(e[0], edge_point(i, j, view, we[0]));
    store4(e[1], edge_point(i, k, view, we[1]));
    // Interpolate from the end with cut >= 0 to the one with cut < 0, as decided by signs.
    const int second = int(!bit(seg_m1(f, view), cut));
    const double* s = e[second];
    const double* o = e[second ^ 1];
    const double* ws = we[second];
    const double* wo = we[second ^ 1];
    const double cs = std::max(s[cut], 0.0), co = std::min(o[cut], 0.0);
    const double den = cs - co;
    if (!(den > best)) continue;
    best = den;
    const double t = den > 0.0 ? cs / den : 0.5;
    res = lerp(load4(s), load4(o), t);
    if constexpr (kWeights)
      for (int q = 0; q < 4; ++q) w[q] = ws[q] + t * (wo[q] - ws[q]);
  }
}

}  // namespace

}  // namespace tetia::detail
