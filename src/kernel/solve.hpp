// src/kernel/solve.hpp -- one pair from start to end: the quick exits (disjoint bounding boxes,
// lines 2-6's empty cases), the frame (frame.hpp), the kernel (Kernel::run, algorithm2.hpp),
// the facets (facets.hpp), the repair by the other tetrahedron as the reference, the tests
// that certify the result, and the rescaling of extreme sizes; what is not certified goes to
// the exact last resort (the entry points, tet_intersection.cpp).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <algorithm>
#include <cmath>

#include "algorithm2.hpp"
#include "barycentric_map.hpp"  // TETIA_KERNEL_SSE2
#include "error_estimate.hpp"
#include "facets.hpp"
#include "frame.hpp"
#include "kernel.hpp"
#include "kernel_result.hpp"
#include "moments.hpp"
#include "refined_clip.hpp"
#include "rescale.hpp"
#include "tetia/tet_intersection.hpp"

namespace tetia::detail {

namespace {

double coordinate_magnitude(const double (&C)[4][4]) {  // the largest of 1 and the |coordinates|
#if TETIA_KERNEL_SSE2
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d m = _mm_set1_pd(1.0);
  for (int i = 0; i < 4; ++i)
    m = _mm_max_pd(m, _mm_max_pd(_mm_andnot_pd(sign, _mm_loadu_pd(C[i])), _mm_andnot_pd(sign, _mm_loadu_pd(C[i] + 2))));
  return _mm_cvtsd_f64(_mm_max_sd(m, _mm_unpackhi_pd(m, m)));
#else
  double scale = 1.0;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) scale = std::max(scale, std::abs(C[i][p]));
  return scale;
#endif
}

// Bit p: some vertex of X has coordinate p > 0 (kStrict) or >= 0.
template <bool kStrict>
unsigned column_mask(const double (&C)[4][4]) {
#if TETIA_KERNEL_SSE2
  const __m128d z = _mm_setzero_pd();
  const auto cmp = [&z](__m128d v) { return kStrict ? _mm_cmpgt_pd(v, z) : _mm_cmpge_pd(v, z); };
  __m128d lo = cmp(_mm_loadu_pd(C[0])), hi = cmp(_mm_loadu_pd(C[0] + 2));
  for (int i = 1; i < 4; ++i) {
    lo = _mm_or_pd(lo, cmp(_mm_loadu_pd(C[i])));
    hi = _mm_or_pd(hi, cmp(_mm_loadu_pd(C[i] + 2)));
  }
  return unsigned(_mm_movemask_pd(lo)) | unsigned(_mm_movemask_pd(hi)) << 2;
#else
  unsigned mask = 0;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) mask |= unsigned(kStrict ? C[i][p] > 0.0 : C[i][p] >= 0.0) << p;
  return mask;
#endif
}

// Runs the kernel on a prepared frame. Returns false if the labels do not close up into a
// simple polytope (see Kernel::run and build_facets); the result is then empty.
// kFull: the result becomes a Polyhedron (weights, and the coordinate scale orient_facets uses).
template <bool kMoments, bool kFull>
bool run_kernel(const double (&C)[4][4], KernelResult& res, IntersectionStats* stats) {
  // Kernel::run's first test (lines 2-6) ahead of the kernel: some plane of Y has no vertex of
  // X strictly on its positive side (which covers X on its negative side: C >= 0 implies
  // C > 0 fails only for zeros). The result is then empty, as run and build_facets leave it.
  const unsigned positive = column_mask<true>(C);
  if (positive != 0xFu) {
    res.set_empty();
    res.contradiction = false;
    // Certain where X lies strictly on the negative side of a plane of Y (coordinates that
    // are not snapped to 0 have certain signs, barycentric_map.hpp); where a coordinate is 0
    // (on the plane, or within rounding of it) solve_with checks the accuracy.
    res.certainly_empty = column_mask<false>(C) != 0xFu;
    return true;
  }
  if (stats) {
    Kernel<kFull, true> k(C, stats);
    k.run(res);
    res.contradiction = !k.consistent();  // looked for only with statistics
  } else {
    Kernel<kFull, false> k(C, nullptr);
    k.run(res);
    res.contradiction = !k.consistent();
  }
  if constexpr (kFull) res.coordinate_scale = coordinate_magnitude(C);  // finite here: make_frame
  // X inside Y: its four vertices are the corners (algorithm2.hpp adds the vertices of X first
  // and returns right after them when all four are inside, so a fourth corner that is a
  // vertex of X means all four are).
  res.x_inside = res.num_corners == 4 && res.corners[3].kind == kVertexOfX;
  // Only a Polyhedron reads the facets and their fan volumes.
  const bool ok = build_facets<kMoments ? kFacetsMoments : kFacetsVolume, true, kFull>(res);
  if (!ok) {
    res.set_empty();
    return false;
  }
  return true;
}

// --- accuracy relative to the smaller tetrahedron (error_estimate.hpp) ----------------------

// The refined result (refined_clip.hpp) in the smaller tetrahedron's frame (the reference on a
// tie, so that the choice is symmetric too). False where it is not certified either.
template <bool kMoments>
[[gnu::noinline]] bool refine(const Frame& fr, KernelResult& res) {
  const bool sub_smaller = std::abs(fr.det6_sub) < std::abs(fr.det6);
  Moments m;
  const Tet& smaller = sub_smaller ? *fr.sub : *fr.ref;
  const Tet& other = sub_smaller ? *fr.ref : *fr.sub;
  if (!refined_moments<kMoments>(smaller, other, sub_smaller ? fr.det6 : fr.det6_sub, m)) return false;
  res.refined = true;
  res.refined_moments = m;
  return true;
}

// X inside Y, X thin: X's volume from its det6 in double-double, its centroid as computed.
constexpr double kInsideQuality = 1.2e-3;

[[gnu::noinline]] bool refine_inside(const Frame& fr, KernelResult& res) {
  double det6;
  if (!refined_det6(*fr.sub, det6)) return false;
  const Tet& s = *fr.sub;
  res.refined = true;
  res.refined_moments.volume = std::abs(det6) * (1.0 / 6.0);
  res.refined_moments.first = res.refined_moments.volume * (0.25 * (((s[0] + s[1]) + s[2]) + s[3]));
  return true;
}

// How a pair's result was obtained (solve_with, solve).
enum class Outcome {
  empty,    // no intersection (disjoint, touching, flat; or non-finite input)
  kernel,   // the double kernel's result, in the frame of the (possibly scaled) input
  exact,    // not certified: the exact last resort decides (exact_fallback.hpp), for the
            // caller's input as given (non-finite input: empty)
  rescale,  // sizes outside the kernel's range (FrameStatus::rescale): scale and solve again
};

// The kernel with its repair by the other reference and the tests that certify its result.
// Rounding in a degenerate configuration (an edge of one tetrahedron lying in a face of the
// other, say) can leave sign decisions that Theorem 6's relations accept but that no polytope
// realizes; the labels then do not close up. The other tetrahedron is then taken as the reference, which
// rounds differently. If that fails too, the exact last resort decides: a real intersection
// never vanishes. It also decides where the frame cannot be made in doubles for finite input
// (a flat frame, or coordinates that are not finite), where a tetrahedron is flat to the
// rounding of its own coordinates (Frame::flat_to_rounding), and where the volume is not finite or
// exceeds the smaller tetrahedron's by more than 1e-12 of it (|det6| / 6 of each, as computed
// for the choice of the reference): the kernel's error is about eps times the size ratio, and
// where that shows it is not accepted. Every test is on numbers all entry points compute alike
// (the bitwise contract). Counted with statistics: every attempt whose labels did not close or
// whose signs contradicted each other as an inconsistency, every second attempt as a retry.
// make_frame(fr, other_reference) prepares the frame (see make_frame).
template <bool kMoments, bool kFull, class MakeFrame>
Outcome solve_with(const MakeFrame& make_frame, Frame& fr, KernelResult& res, IntersectionStats* stats) {
  const FrameStatus status = make_frame(fr, false);
  if (status != FrameStatus::ok) [[unlikely]] {
    res.set_empty();
    return status == FrameStatus::rescale ? Outcome::rescale : Outcome::exact;
  }
  if (stats && fr.swapped) ++stats->reference_swaps;
  bool ok = run_kernel<kMoments, kFull>(fr.C, res, stats);
  if (!ok) [[unlikely]] {
    if (stats) {
      ++stats->inconsistencies;
      ++stats->retries;
    }
    ok = make_frame(fr, true) == FrameStatus::ok && run_kernel<kMoments, kFull>(fr.C, res, stats);
    if (!ok) {
      if (stats) ++stats->inconsistencies;
      res.set_empty();
      return Outcome::exact;
    }
  }
  if (stats && res.contradiction) ++stats->inconsistencies;
  if (fr.flat_to_rounding) [[unlikely]] return Outcome::exact;  // the kernel's polytope kept in res
  // Accuracy relative to the smaller tetrahedron: X certainly inside Y is exact (X's own
  // volume), and so is an empty result with X strictly beyond a plane of Y; otherwise the
  // estimate decides whether the double result stands. An empty result whose refined volume
  // exceeds 2^-44 of the smaller tetrahedron (X across a face of a much bigger Y, within its
  // rounding) has no corners to show for it: exact then; below that, empty is within the
  // accuracy promised with room for the refinement's own error. (The threshold was 1e-12 until
  // 2026-12-06, which left no room: a needle 1e3 times smaller across a vertex of Y came out
  // empty, 7.1e-13 of it off.)
  if (res.num_corners == 0) {
    if (res.certainly_empty || accuracy_certified(fr)) return Outcome::empty;
    if (stats) ++stats->refined;
    // A plane that certainly separates them (separation.hpp): exactly empty, without the
    // refinement. Y's faces are not tried: the column test above is theirs (X beyond one of
    // them, every coordinate certain), and what it left has a vertex of X on the plane or
    // within its rounding; X's faces, then the edge pairs.
    if (certainly_separated(*fr.sub, *fr.ref, false)) return Outcome::empty;
    const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub)) * (1.0 / 6.0);
    if (!refine<false>(fr, res) || !(res.refined_moments.volume <= 0x1p-44 * smaller)) return Outcome::exact;
    res.set_empty();
    return Outcome::empty;
  }
  if (res.x_inside) {
    // X inside Y is certain where no coordinate of X was snapped to 0: every sign is then beyond
    // its rounding bound (barycentric_map.hpp). A snapped one puts a vertex of X on a plane of Y
    // that it may cross by up to the map's rounding, far more than 1e-12 of a much smaller X
    // (a small X just across a face of a big Y): then the a priori estimate decides, and what
    // it does not certify is refined.
    // Otherwise X's own volume |det6| / 6: its rounding is below 2^-49 of det6's permanent, at
    // most (2/3) s^(3/2) (the product of three edges whose squares sum to at most s is at most
    // (s/3)^(3/2), and the permanent has 2 sqrt(3) such products at most), so below 1e-13 of
    // det6 where the quality |det6| / s^(3/2) is at least 2^-49 (2/3) / 1e-13 = 1.2e-3; a
    // thinner X gets its det6 in double-double.
    if (has_zero_coordinate(fr.C) && !accuracy_certified(fr)) [[unlikely]] {
      if (stats) ++stats->refined;
      if (!refine<kMoments>(fr, res)) return Outcome::exact;
    } else if (!(std::abs(fr.det6_sub) >= kInsideQuality * fr.s_sub * std::sqrt(fr.s_sub))) [[unlikely]] {
      if (stats) ++stats->refined;
      if (!refine_inside(fr, res)) return Outcome::exact;
    }
  } else if (!accuracy_certified(fr) && !accuracy_certified_a_posteriori(fr, res)) [[unlikely]] {
    if (stats) ++stats->refined;
    if (!refine<kMoments>(fr, res)) return Outcome::exact;
  }
  const double volume = original_volume(fr, res);
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub)) * (1.0 / 6.0);
  if (!(volume <= smaller * (1.0 + 1e-12)) || !(volume < INFINITY)) [[unlikely]] return Outcome::exact;
  return Outcome::kernel;
}

// Whether the bounding boxes of U and V are disjoint: some axis has max U < min V or
// max V < min U, compared exactly on the input. A plane x = c (or y, z) then separates the two
// strictly, and the intersection is empty: no map, no kernel. Boxes that touch are not disjoint;
// the kernel decides those. NaN compares false; non-finite input is empty either way (if no
// axis separates it here, make_frame rejects it).
bool boxes_disjoint(const Tet& U, const Tet& V) {
#if TETIA_KERNEL_SSE2
  __m128d u_lo = _mm_loadu_pd(&U[0].x), u_hi = u_lo, v_lo = _mm_loadu_pd(&V[0].x), v_hi = v_lo;  // (x, y)
  __m128d uz_lo = _mm_load_sd(&U[0].z), uz_hi = uz_lo, vz_lo = _mm_load_sd(&V[0].z), vz_hi = vz_lo;
  for (int k = 1; k < 4; ++k) {
    const __m128d u = _mm_loadu_pd(&U[k].x), v = _mm_loadu_pd(&V[k].x);
    const __m128d uz = _mm_load_sd(&U[k].z), vz = _mm_load_sd(&V[k].z);
    u_lo = _mm_min_pd(u_lo, u), u_hi = _mm_max_pd(u_hi, u), v_lo = _mm_min_pd(v_lo, v), v_hi = _mm_max_pd(v_hi, v);
    uz_lo = _mm_min_sd(uz_lo, uz), uz_hi = _mm_max_sd(uz_hi, uz);
    vz_lo = _mm_min_sd(vz_lo, vz), vz_hi = _mm_max_sd(vz_hi, vz);
  }
  const __m128d apart = _mm_or_pd(_mm_cmplt_pd(u_hi, v_lo), _mm_cmplt_pd(v_hi, u_lo));
  const __m128d apart_z = _mm_or_pd(_mm_cmplt_sd(uz_hi, vz_lo), _mm_cmplt_sd(vz_hi, uz_lo));
  return (_mm_movemask_pd(apart) | (_mm_movemask_pd(apart_z) & 1)) != 0;
#else
  bool apart = false;
  for (int axis = 0; axis < 3; ++axis) {
    const auto coord = [axis](const Vec3& p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
    double u_lo = coord(U[0]), u_hi = u_lo, v_lo = coord(V[0]), v_hi = v_lo;
    for (int k = 1; k < 4; ++k) {
      u_lo = std::min(u_lo, coord(U[k])), u_hi = std::max(u_hi, coord(U[k]));
      v_lo = std::min(v_lo, coord(V[k])), v_hi = std::max(v_hi, coord(V[k]));
    }
    apart |= u_hi < v_lo || v_hi < u_lo;
  }
  return apart;
#endif
}

bool finite(const Tet& t) {
  for (const Vec3& p : t)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

// solve() for the input scaled by a power of two (rescale.hpp): the larger tetrahedron's size
// brought to about 1, into `scaled`, which the frame then points into; `scale` receives the
// exponent k (volumes scale back by 2^(-3k), first moments by 2^(-4k), points by 2^(-k)). The
// exact last resort where the scaling is not exact, the sizes are still out of range (more
// than 2^500 apart), or the volume scaled back would be rounded a second time (subnormal, or
// beyond the largest double). Out of line: the usual input never comes here.
template <bool kMoments, bool kFull>
[[gnu::noinline]] Outcome solve_rescaled(const Tet& U, const Tet& V, Frame& fr, KernelResult& res, Tet (&scaled)[2],
                                         int& scale, IntersectionStats* stats) {
  if (!finite(U) || !finite(V)) return Outcome::empty;
  if (stats) ++stats->rescaled;
  scale = -(std::ilogb(fr.size_squared_max) / 2);
  static_assert(sizeof(Tet) == 12 * sizeof(double));
  if (!scaled_exactly(&U[0].x, 12, scale, &scaled[0][0].x) || !scaled_exactly(&V[0].x, 12, scale, &scaled[1][0].x))
    return Outcome::exact;
  const Tet& Us = scaled[0];
  const Tet& Vs = scaled[1];
  const Outcome o =
      solve_with<kMoments, kFull>([&](Frame& f, bool other) { return make_frame(Us, Vs, f, other); }, fr, res, stats);
  if (o == Outcome::rescale) return Outcome::exact;
  if (o == Outcome::kernel) {
    const double back = std::ldexp(original_volume(fr, res), -3 * scale);
    if (!(back >= 0x1p-1022) || !(back < INFINITY)) return Outcome::exact;
  }
  return o;
}

// The pairwise entry points' kernel call: a quick exit for disjoint bounding boxes, then
// solve_with, and solve_rescaled where the sizes ask for it (`scaled`, `scale`: see there;
// scale is 0 otherwise).
template <bool kMoments, bool kFull>
Outcome solve(const Tet& U, const Tet& V, Frame& fr, KernelResult& res, Tet (&scaled)[2], int& scale,
              IntersectionStats* stats) {
  scale = 0;
  if (boxes_disjoint(U, V)) {
    res.set_empty();
    return Outcome::empty;
  }
  const Outcome o =
      solve_with<kMoments, kFull>([&](Frame& f, bool other) { return make_frame(U, V, f, other); }, fr, res, stats);
  if (o != Outcome::rescale) [[likely]] return o;
  return solve_rescaled<kMoments, kFull>(U, V, fr, res, scaled, scale, stats);
}

}  // namespace

}  // namespace tetia::detail
