// src/kernel/error_estimate.hpp -- whether the kernel's volume is accurate to 1e-12 of the
// smaller tetrahedron: an a priori estimate of its error from the frame alone, on every pair,
// and for a result with corners that it does not certify, an a posteriori one from the polytope
// found (docs/architecture.md, "Accuracy relative to the smaller tetrahedron"). What neither
// certifies is computed again in the smaller tetrahedron's frame (refined_clip.hpp).
// Part of the kernel's one translation unit: included by src/kernel/solve.hpp only (what it
// defines in the anonymous namespace is that file's own).
//
// The premise, common to both: the kernel's corners are convex combinations of X's vertices
// or of points on X's faces in the reference frame, each resolved to about eps M (eps = 2^-53),
// M the largest of 1 and X's coordinates' permanents over |det6| (barycentric_map.hpp: at least
// the largest |coordinate|, the magnitude the kernel's sums and differences work with, and the
// scale of the map's own rounding error, which a flattened reference amplifies). In original
// units that is d = eps M sqrt(s_ref) (s: the sum of squared edge lengths, so sqrt(s_ref) bounds
// the map's stretch). This premise is calibrated, not derived (below).
//
// The a priori estimate. Moving the corners of a convex polytope by d changes its volume by at
// most about d times its surface, and the polytope's surface is at most min(s_ref, s_sub) /
// (2 sqrt 3) (it lies in both tetrahedra, surface is monotone on convex sets, and a triangle's
// area is at most the sum of its squared edges over 4 sqrt 3, each edge in two faces).
// Relative to the smaller volume |det6| / 6:
//   a priori = sqrt(3) eps M sqrt(s_ref) min(s_ref, s_sub) / min(|det6_ref|, |det6_sub|).
//
// The a posteriori estimate measures the computed polytope K' instead, and adds the error the a
// priori one leaves to its slack: the rounding of the volume's own evaluation.
//  - Corners: the volume of a triangulated surface is a polynomial in its corners; moving each
//    by at most d changes it by at most S' d to first order (S' the surface: each triangle's
//    volume term moves by d times its area over 3, for each of its 3 corners), plus d^2 times
//    the sum over the fan's tetrahedra of their three edge vectors' lengths, plus d^3 per
//    tetrahedron: at most 4.72 L' d^2 + 29.4 d^3 with L' = (3/2 n) times the diagonal of K''s
//    bounding box (n corners, 2n - 4 triangles).
//  - Evaluation: the kernel sums, in the reference frame, triple products of corners relative
//    to corner 0 (build_facets' fans). Each is within 8 eps of its permanent (the rounding of
//    the differences, 3 eps; of the products and sums, 5 eps), the sum adds at most eps per
//    term: (16 + 2n) eps times the sum of the permanents, times |det6_ref| / 6 in original
//    units. A needle cut near its tip has a volume of width^2 times length and triple products
//    of length^3: its error is eps (length / width)^2 of its volume, far beyond S' d. (Without
//    this term the estimate was off by 35 times on such a pair: "vs-random" of the slivers.)
//   a posteriori = 4 (S' d + 4.72 L' d^2 + 29.4 d^3 + evaluation) / (min(|det6_ref|, |det6_sub|) / 6).
// The factor 4 is its calibration (below). S' and the permanents are measured on the fans the
// volume was computed on, by a second walk of build_facets (kMeasure) over the kernel's result.
//
// Calibration. Against GMP on every test family and on unit-cube pairs (KernelVsExact.
// ErrorEstimate), and under a directed search that climbs towards the largest error over the
// estimate (KernelVsExact.EstimateUnderDirectedSearch; docs/architecture.md has the figures),
// the error was at most 0.215 of the a priori estimate (before the a posteriori one existed),
// and of the smaller of the two at most 0.182 with the a posteriori one's factor 4 over six
// searches (0.52 with a factor 2, 0.60 without), 0.251 over sixty-three (2026-12-06). A result is
// accepted when 0.5 of either estimate is at most 1e-12.
//
// (Until 2026-12-03 M was the largest |coordinate| and the factor 0.25, 0.08 for pairs without
// a zero coordinate, from random families alone; the directed search found errors of up to 3.3
// times that estimate, and pairs off by 1.11e-12 and 1.97e-12 of the smaller tetrahedron:
// fuzz/regressions/fuzz_tet_kernel/found-2026-12-03.txt.)
//
// Every number here is computed alike by every entry point (the frame, and the kernel's corners
// and labels, which do not depend on what the entry point returns), so all take the same way;
// both tests are symmetric in U and V (the reference is), so (U, V) and (V, U) take the same
// way too.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "facets.hpp"  // FacetMeasures
#include "frame.hpp"
#include "kernel_result.hpp"

namespace tetia::detail {

namespace {

constexpr double kAcceptanceFactor = 0.5;  // a result is accepted where 0.5 x estimate <= 1e-12
constexpr double kPosteriorSafety = 4.0;   // the a posteriori estimate's calibration (see above)
constexpr double kSqrt3 = 1.7320508075688772;

// The a priori estimate's constant with the acceptance factor.
constexpr double kEstimateConstant = kAcceptanceFactor * kSqrt3 * 0x1p-53 / 1e-12;

// Whether the kernel's volume is certified to 1e-12 of the smaller tetrahedron by the estimate
// above; a NaN or infinite estimate does not certify.
bool accuracy_certified(const Frame& fr) {
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub));
  return kEstimateConstant * fr.coordinate_max * std::sqrt(fr.s_ref) * std::min(fr.s_ref, fr.s_sub) <= smaller;
}

// The estimate without its acceptance factor (kernel_estimate, for the tests; maybe_unused:
// a kernel variant's translation unit has only the entry points).
[[maybe_unused]] double a_priori_estimate(const Frame& fr) {
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub));
  return kSqrt3 * 0x1p-53 * fr.coordinate_max * std::sqrt(fr.s_ref) * std::min(fr.s_ref, fr.s_sub) /
         smaller;
}

// --- the a posteriori estimate (for results with corners that the a priori one sends on) ------

// The corners of the kernel's polytope in original units (relative to the reference's vertex
// 0) and their bounding box, with the extents of the corners' reference coordinates from corner
// 0's; and the measures a walk over the facets takes with them (FacetMeasures: the surface and
// the fans' permanents, on the fans the volume was computed on), or bounds on them without it.
struct PolytopeGeometry {
  Vec3 p[KernelResult::kMaxCorners];
  Vec3 lo, hi;
  double extent_ref[3];  // largest |bary[k + 1] - corner 0's bary[k + 1]| over the corners
  FacetMeasures walked;

  // p, lo, hi and extent_ref from the kernel's corners.
  void place(const Tet& ref, const KernelResult& res) {
    const Vec3 e1 = ref[1] - ref[0], e2 = ref[2] - ref[0], e3 = ref[3] - ref[0];
    lo = {INFINITY, INFINITY, INFINITY};
    hi = {-INFINITY, -INFINITY, -INFINITY};
    extent_ref[0] = extent_ref[1] = extent_ref[2] = 0.0;
    const double* o = res.corners[0].bary;
    for (int c = 0; c < res.num_corners; ++c) {
      const double* b = res.corners[c].bary;
      p[c] = (b[1] * e1 + b[2] * e2) + b[3] * e3;
      lo = {std::min(lo.x, p[c].x), std::min(lo.y, p[c].y), std::min(lo.z, p[c].z)};
      hi = {std::max(hi.x, p[c].x), std::max(hi.y, p[c].y), std::max(hi.z, p[c].z)};
      for (int k = 0; k < 3; ++k) extent_ref[k] = std::max(extent_ref[k], std::abs(b[k + 1] - o[k + 1]));
    }
  }

  // `walked` (build_facets with kMeasure), after place(). False where the walk cannot be made
  // (labels the fast walk does not take: not certified then).
  bool walk(KernelResult& res) { return build_facets<kFacetsVolume, true, false, true>(res, p, &walked); }

  // The same measures bounded from place()'s numbers alone, for n corners:
  //  - twice the surface of the corners' bounding box: the exact polytope is convex and lies in
  //    the bounding box of its corners, within d of the computed ones, and a convex body's
  //    surface is at most that of any convex set containing it (to first order in d, as the
  //    estimate's corner term is);
  //  - the fans' permanents: each fan triangle's triple product has rows that are differences
  //    of corners from corner 0 (the same roundings as extent_ref's), column k at most
  //    extent_ref[k], so each of its six products at most the product of the three extents;
  //    a simple polytope with n corners has 2n - 4 fan triangles (fewer from corner 0), so
  //    12 n times that product bounds them with room.
  FacetMeasures bounded(int n) const {
    const Vec3 e = hi - lo;
    FacetMeasures m;
    m.surface2 = 4.0 * ((e.x * e.y + e.y * e.z) + e.z * e.x);
    m.permanents = 12.0 * n * (extent_ref[0] * extent_ref[1] * extent_ref[2]);
    return m;
  }
};

// The a posteriori estimate (see the top of this file) from its measures of the polytope:
// surface2 twice the surface (original units), permanents the sum of the fan's triple
// products' permanents (reference frame).
double a_posteriori_from(const Frame& fr, int n, const PolytopeGeometry& g, double surface2, double permanents) {
  const Vec3 extent = g.hi - g.lo;
  const double edges = 1.5 * n * std::sqrt(dot(extent, extent));
  const double d = 0x1p-53 * fr.coordinate_max * std::sqrt(fr.s_ref);
  const double corners = (0.5 * surface2 * d + 4.72 * edges * d * d) + 29.4 * d * d * d;
  const double evaluation = (16.0 + 2.0 * n) * 0x1p-53 * permanents * std::abs(fr.det6) * (1.0 / 6.0);
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub)) * (1.0 / 6.0);
  return kPosteriorSafety * (corners + evaluation) / smaller;
}

// The a posteriori estimate without its acceptance factor, for a result with corners whose
// labels closed. First from PolytopeGeometry::bounded (the corners' bounding box, and the
// extents of their reference coordinates), which needs no walk; where that does not certify,
// the smaller of it and the estimate from the walk's measures: the surface as the sum of the
// fans' triangle areas (an upper bound on each planar facet's area whatever the rounding), the
// permanents over the fans from corner 0 (the facets through it contribute exactly 0). The walk
// is made after the kernel's own, and only for the results that need it, so that the rest pay
// nothing for it (measuring on the kernel's walk, for every pair the a priori estimate does not
// certify, cost the near-identical pairs 3 %). The bounds certified 13,660 of the 31,388 results
// the walk certified among the 10^6 benchmark pairs (37,664 computed), and none it did not
// (2026-12-06): most of what they miss is the box's surface against the polytope's.
[[gnu::noinline]] double a_posteriori_estimate(const Frame& fr, KernelResult& res) {
  PolytopeGeometry g;
  g.place(*fr.ref, res);
  const int n = res.num_corners;
  const FacetMeasures b = g.bounded(n);
  const double bounded = a_posteriori_from(fr, n, g, b.surface2, b.permanents);
  if (kAcceptanceFactor * bounded <= 1e-12) return bounded;
  if (!g.walk(res)) return bounded;
  return std::min(bounded, a_posteriori_from(fr, n, g, g.walked.surface2, g.walked.permanents));
}

// Whether the a posteriori estimate is worth computing for this result: only where the polytope
// fills less than half of the smaller tetrahedron. It gains on the a priori estimate where the
// polytope is a small part of the smaller tetrahedron (its surface and its fans' triple products
// then small); where it fills most of it, its surface is that of the smaller tetrahedron and the
// a posteriori estimate, with its evaluation term and its factor 4, is the larger of the two.
// Measured before this test existed: of the results the a priori estimate left to it that fill
// at least half of the smaller tetrahedron, it certified 2 of 73 among 2 10^5 of the benchmark's
// random pairs, and 10 of 12,439 among 10^5 of the peers' near-degenerate pairs (V = U moved by
// 1e-12 and turned by 1e-10), where computing it cost 6 % of the time. The results not tried are
// refined (more accurate, not less). The volume is the kernel's, computed alike by every entry
// point, so all of them decide alike.
constexpr double kPosteriorFill = 0.5;

bool a_posteriori_worthwhile(const Frame& fr, const KernelResult& res) {
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub));
  return res.ref_volume * std::abs(fr.det6) < kPosteriorFill * (1.0 / 6.0) * smaller;
}

// Whether the a posteriori estimate certifies the kernel's volume (NaN or infinite: not), where
// it is worth computing (a_posteriori_worthwhile).
bool accuracy_certified_a_posteriori(const Frame& fr, KernelResult& res) {
  return a_posteriori_worthwhile(fr, res) && kAcceptanceFactor * a_posteriori_estimate(fr, res) <= 1e-12;
}

// Whether some coordinate of X is exactly 0: a vertex on a plane of Y, exactly or within the
// rounding of its orientation (snapped, barycentric_map.hpp). For X inside Y (solve.hpp) and
// kernel_estimate.
inline bool has_zero_coordinate(const double (&C)[4][4]) {
  bool zero = false;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) zero |= C[i][p] == 0.0;
  return zero;
}

}  // namespace

}  // namespace tetia::detail
