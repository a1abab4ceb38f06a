// src/kernel/frame.hpp -- Section 2 of McCoid & Gander, line 1 of Algorithm 2: the change of
// coordinates. The conditioning of U and V (shape_qualities), the choice of the reference V
// (the better-conditioned one), and X, U's barycentric coordinates in it by eq. (1)
// (BarycentricMap, barycentric_map.hpp).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "barycentric_map.hpp"  // BarycentricMap, TETIA_KERNEL_SSE2 (SSE2 or scalar loops)
#include "one_to_many.hpp"      // Conditioning
#include "tetia/geometry.hpp"

namespace tetia::detail {

namespace {

// --- change of coordinates (Section 2) ------------------------------------------------------

// Conditioning of a tetrahedron as a reference: |det| / (sum of squared edge lengths)^(3/2),
// scale invariant, largest for the regular tetrahedron, zero when flat. The mapping to Y
// amplifies rounding by about the inverse of this ratio.
#if !TETIA_KERNEL_SSE2
Conditioning shape_quality(const Tet& t) {
  const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], e3 = t[3] - t[0];
  const Vec3 e4 = t[2] - t[1], e5 = t[3] - t[1], e6 = t[3] - t[2];
  Conditioning c;
  c.det6 = dot(e1, cross(e2, e3));
  const double s = dot(e1, e1) + dot(e2, e2) + dot(e3, e3) + dot(e4, e4) + dot(e5, e5) + dot(e6, e6);
  c.quality = std::abs(c.det6) / (s * std::sqrt(s));
  c.inv_det6 = 1.0 / c.det6;
  c.det6_sq = c.det6 * c.det6;
  c.s_cubed = s * s * s;
  c.s = s;
  return c;
}
#endif

// shape_quality of U and V at once: the same operations in the same order, U in the low lane
// and V in the high one; with 1 / det6 of each, which the barycentric map of the one chosen as
// the reference needs (the same division, done here in parallel with the quality's instead of
// after the choice).
void shape_qualities(const Tet& U, const Tet& V, Conditioning& cu, Conditioning& cv) {
#if TETIA_KERNEL_SSE2
  __m128d x[4], y[4], z[4];
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && offsetof(Vec3, y) == sizeof(double));
  for (int k = 0; k < 4; ++k) {  // (x, y) of each point as one load, then unpacked
    const __m128d u = _mm_loadu_pd(&U[k].x), v = _mm_loadu_pd(&V[k].x);
    x[k] = _mm_unpacklo_pd(u, v);
    y[k] = _mm_unpackhi_pd(u, v);
    z[k] = _mm_loadh_pd(_mm_load_sd(&U[k].z), &V[k].z);
  }
  struct V2 {
    __m128d x, y, z;
  };
  const auto sub = [&](int i, int j) {  // t[i] - t[j]
    return V2{_mm_sub_pd(x[i], x[j]), _mm_sub_pd(y[i], y[j]), _mm_sub_pd(z[i], z[j])};
  };
  const auto dot2 = [](const V2& a, const V2& b) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(a.x, b.x), _mm_mul_pd(a.y, b.y)), _mm_mul_pd(a.z, b.z));
  };
  const V2 e1 = sub(1, 0), e2 = sub(2, 0), e3 = sub(3, 0), e4 = sub(2, 1), e5 = sub(3, 1), e6 = sub(3, 2);
  const V2 c{_mm_sub_pd(_mm_mul_pd(e2.y, e3.z), _mm_mul_pd(e2.z, e3.y)),
             _mm_sub_pd(_mm_mul_pd(e2.z, e3.x), _mm_mul_pd(e2.x, e3.z)),
             _mm_sub_pd(_mm_mul_pd(e2.x, e3.y), _mm_mul_pd(e2.y, e3.x))};
  const __m128d det6 = dot2(e1, c);
  __m128d s = _mm_add_pd(dot2(e1, e1), dot2(e2, e2));
  s = _mm_add_pd(s, dot2(e3, e3));
  s = _mm_add_pd(s, dot2(e4, e4));
  s = _mm_add_pd(s, dot2(e5, e5));
  s = _mm_add_pd(s, dot2(e6, e6));
  const __m128d q = _mm_div_pd(_mm_andnot_pd(_mm_set1_pd(-0.0), det6), _mm_mul_pd(s, _mm_sqrt_pd(s)));
  const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), det6);
  const __m128d d2 = _mm_mul_pd(det6, det6), s3 = _mm_mul_pd(_mm_mul_pd(s, s), s);
  double qq[2], dd[2], ii[2], d2d[2], s3d[2];
  _mm_storeu_pd(qq, q);
  _mm_storeu_pd(dd, det6);
  _mm_storeu_pd(ii, inv);
  _mm_storeu_pd(d2d, d2);
  _mm_storeu_pd(s3d, s3);
  cu.quality = qq[0], cv.quality = qq[1], cu.det6 = dd[0], cv.det6 = dd[1], cu.inv_det6 = ii[0], cv.inv_det6 = ii[1];
  cu.det6_sq = d2d[0], cv.det6_sq = d2d[1], cu.s_cubed = s3d[0], cv.s_cubed = s3d[1];
  double sd[2];
  _mm_storeu_pd(sd, s);
  cu.s = sd[0], cv.s = sd[1];
#else
  cu = shape_quality(U);
  cv = shape_quality(V);
#endif
}

// Below this shape quality (|det6| / s^(3/2)) the computed det6 of a tetrahedron is not certain
// to be nonzero or to have the right sign: 2^-40, about 1e-12, a thousand times det6's error
// bound relative to s^(3/2).
constexpr double kFlatQuality = 0x1p-40;

// The frame of the reference tetrahedron and X's barycentric coordinates in it.
struct Frame {
  const Tet* sub;  // U's role in the paper (mapped to X)
  const Tet* ref;  // V's role (mapped to Y)
  bool swapped;    // the caller's U is the reference
  double det6;     // det[r1 - r0, r2 - r0, r3 - r0]
  double det6_sub;  // the same for the other tetrahedron (solve_with's test of the result)
  double size_squared_max;  // the larger sum of squared edge lengths (the rescaling's choice)
  double s_ref, s_sub;      // the sums of squared edge lengths of each (the error estimate)
  double coordinate_max;    // the largest of 1 and X's coordinates' permanents / |det6| (the same)
  bool flat_to_rounding;    // U or V has a quality below kFlatQuality (frame_from)
  double C[4][4];
};

// frame_from's outcome. `rescale`: an edge length of U or V is outside [2^-250, 2^250] (the sum
// of squared edge lengths outside [2^-500, 2^500]), or the two sizes are more than 2^250 apart,
// where the map's products of three differences and their error bounds, or the kernel's
// products of coordinates, would leave the normal range (or are not finite): the caller scales
// the input by a power of two (rescale.hpp) and makes the frame again; sizes too far apart for
// any scale then go to the exact last resort.
enum class FrameStatus { ok, flat_or_not_finite, rescale };

// make_frame once the conditioning of U and V is known; map_u: U's barycentric map if the
// caller has it (OneToMany), used when U is the reference instead of building it again (the
// same map: the same constructor on the same data).
FrameStatus frame_from(const Tet& U, const Conditioning& cu, const BarycentricMap* map_u, const Tet& V,
                       const Conditioning& cv, Frame& fr, bool other_reference) {
  const double qU = cu.quality, qV = cv.quality;
  const double s_lo = std::min(cu.s, cv.s), s_hi = std::max(cu.s, cv.s);
  if (!(s_lo >= 0x1p-500 && s_hi <= 0x1p500 && s_hi <= 0x1p500 * s_lo)) [[unlikely]] {
    fr.size_squared_max = s_hi;
    return FrameStatus::rescale;
  }
  // Non-finite coordinates make a quality NaN or infinite; flat ones make it zero. Below
  // kFlatQuality a tetrahedron is flat to the rounding of its own coordinates (det6's error
  // bound is about 1e-15 s^(3/2)): a zero or wrongly signed det6 is possible. The kernel still
  // runs (its polytope's labels are what a Polyhedron needs), but solve_with lets the exact last
  // resort decide the numbers (exactly flat: empty).
  if (!(qU > 0.0) || !(qV > 0.0) || !(qU < INFINITY) || !(qV < INFINITY)) return FrameStatus::flat_or_not_finite;
  fr.flat_to_rounding = !(qU > kFlatQuality && qV > kFlatQuality);
  // With q^2 = det6^2 / s^3, qU > qV is det6U^2 sV^3 > det6V^2 sU^3: products only, so the
  // choice, and the map that waits for it, need not wait for the square roots and divisions of
  // the qualities. Where the products leave the normal range (edges beyond about 1e25 or below
  // 1e-25) the qualities themselves are compared. The two sides are swapped with U and V, so
  // (U, V) and (V, U) still choose the same reference.
  const double lhs = cu.det6_sq * cv.s_cubed, rhs = cv.det6_sq * cu.s_cubed;
  const bool products_fit = lhs >= 0x1p-1000 && rhs >= 0x1p-1000 && lhs < 0x1p1000 && rhs < 0x1p1000;
  bool use_u = products_fit ? lhs > rhs : qU > qV;
  if (products_fit ? lhs == rhs : qU == qV) {
    const double* pu = &U[0].x;
    const double* pv = &V[0].x;
    use_u = std::lexicographical_compare(pu, pu + 12, pv, pv + 12);
  }
  use_u = use_u != other_reference;
  fr.swapped = use_u;
  // Selected, not branched on: the choice is data (conditional moves, not a table on the stack,
  // whose store and load would lengthen the path to the map).
  fr.sub = use_u ? &V : &U;
  fr.ref = use_u ? &U : &V;
  fr.det6 = use_u ? cu.det6 : cv.det6;
  fr.det6_sub = use_u ? cv.det6 : cu.det6;
  fr.s_ref = use_u ? cu.s : cv.s;
  fr.s_sub = use_u ? cv.s : cu.s;
  BarycentricMap::LargestDet largest_det{};
  const double inv_det6 = use_u ? cu.inv_det6 : cv.inv_det6;
  if (use_u && map_u) {
    for (int i = 0; i < 4; ++i) map_u->map<true>((*fr.sub)[i], fr.C[i], largest_det);
  } else {
    const BarycentricMap bary(*fr.ref, inv_det6);
    for (int i = 0; i < 4; ++i) bary.map<true>((*fr.sub)[i], fr.C[i], largest_det);
  }
  fr.coordinate_max = std::max(1.0, BarycentricMap::largest(largest_det) * std::abs(inv_det6));
  // The sum of 0 * coordinate stays 0 unless a coordinate is infinite or NaN (in any order).
#if TETIA_KERNEL_SSE2
  const __m128d z = _mm_setzero_pd();
  __m128d probe = z;
  for (int i = 0; i < 4; ++i)
    probe = _mm_add_pd(probe, _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(fr.C[i]), z), _mm_mul_pd(_mm_loadu_pd(fr.C[i] + 2), z)));
  return _mm_movemask_pd(_mm_cmpeq_pd(probe, z)) == 3 ? FrameStatus::ok : FrameStatus::flat_or_not_finite;
#else
  double probe = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) probe += fr.C[i][p] * 0.0;
  return probe == 0.0 ? FrameStatus::ok : FrameStatus::flat_or_not_finite;
#endif
}

// Picks the reference (the better-conditioned tetrahedron; ties broken by comparing the
// coordinates, so that (U, V) and (V, U) always choose the same one) and computes X.
// See FrameStatus for what it returns.
FrameStatus make_frame(const Tet& U, const Tet& V, Frame& fr, bool other_reference = false) {
  Conditioning cu, cv;
  shape_qualities(U, V, cu, cv);
  return frame_from(U, cu, nullptr, V, cv, fr, other_reference);
}

}  // namespace

}  // namespace tetia::detail
