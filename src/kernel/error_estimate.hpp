// src/kernel/error_estimate.hpp -- whether the kernel's volume is accurate to 1e-12 of the
// smaller tetrahedron, by an a priori estimate of its error from the frame alone
// (docs/architecture.md, "Accuracy relative to the smaller tetrahedron"). What it does not
// certify is computed again in the smaller tetrahedron's frame (refined_clip.hpp).
// Part of the kernel's one translation unit: included by src/kernel/solve.hpp only (what it
// defines in the anonymous namespace is that file's own).
//
// The kernel's corners are convex combinations of X's vertices or of points on X's faces in the
// reference frame, each resolved to about eps M (eps = 2^-53), M the largest of 1 and X's
// coordinates' permanents over |det6| (barycentric_map.hpp: at least the largest |coordinate|,
// the magnitude the kernel's sums and differences work with, and the scale of the map's own
// rounding error, which a flattened reference amplifies); moving the corners of a convex
// polytope by d changes its volume by at most about d times its surface. In original units a
// reference error of eps M is at most d = eps M sqrt(s_ref) (s: the sum of squared edge
// lengths, so sqrt(s_ref) bounds the map's stretch), and the polytope's surface at most
// min(s_ref, s_sub) / (2 sqrt 3) (it lies in both tetrahedra, surface is monotone on convex
// sets, and a triangle's area is at most the sum of its squared edges over 4 sqrt 3, each edge
// in two faces). Relative to the smaller volume |det6| / 6:
//   estimate = sqrt(3) eps M sqrt(s_ref) min(s_ref, s_sub) / min(|det6_ref|, |det6_sub|).
// The constant is first order only, and calibrated, not derived: against GMP on every test
// family and on unit-cube pairs (KernelVsExact.ErrorEstimate), and by a directed search that
// climbs towards the largest error (KernelVsExact.EstimateUnderDirectedSearch;
// docs/architecture.md has the figures), the error was at most 0.22 of the estimate. A result
// is accepted when 0.5 of the estimate is at most 1e-12 (a factor 2.3 to spare).
//
// Why the bound on the surface and not the computed polytope's own surface (which certifies 97 %
// of the random pairs this estimate sends on, 2026-12-04): the premise that the computed
// polytope lies within d of the exact one fails where facets meet at small angles. A needle
// whose tip is cut off by two faces of a fat tetrahedron (test family "vs-random" of the
// slivers) was off by 35 times that estimate, and the directed search found pairs where it
// let intersection_volume be off by 1.13e-12 of the smaller tetrahedron; the slack of the
// bound above is what covers those.
//
// (Until 2026-12-03 M was the largest |coordinate| and the factor 0.25, 0.08 for pairs without
// a zero coordinate, from random families alone; the directed search found errors of up to 3.3
// times that estimate, and pairs off by 1.11e-12 and 1.97e-12 of the smaller tetrahedron:
// fuzz/regressions/fuzz_tet_kernel/found-2026-12-03.txt.)
//
// Every number here is computed alike by every entry point (the frame), so all take the same
// way; the test is symmetric in U and V (the reference is), so (U, V) and (V, U) take the same
// way too.
#pragma once

#include <algorithm>
#include <cmath>

#include "frame.hpp"

namespace tetia::detail {

namespace {

// The estimate's constant with the acceptance factor: accepted where 0.5 x estimate <= 1e-12.
constexpr double kEstimateConstant = 0.5 * 1.7320508075688772 * 0x1p-53 / 1e-12;

// Whether the kernel's volume is certified to 1e-12 of the smaller tetrahedron by the estimate
// above; a NaN or infinite estimate does not certify.
bool accuracy_certified(const Frame& fr) {
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub));
  return kEstimateConstant * fr.coordinate_max * std::sqrt(fr.s_ref) * std::min(fr.s_ref, fr.s_sub) <= smaller;
}

// The estimate without its acceptance factor (kernel_estimate, for the tests).
double a_priori_estimate(const Frame& fr) {
  const double smaller = std::min(std::abs(fr.det6), std::abs(fr.det6_sub));
  return 1.7320508075688772 * 0x1p-53 * fr.coordinate_max * std::sqrt(fr.s_ref) * std::min(fr.s_ref, fr.s_sub) /
         smaller;
}

// Whether some coordinate of X is exactly 0: a vertex on a plane of Y, exactly or within the
// rounding of its orientation (snapped, barycentric_map.hpp).
bool has_zero_coordinate(const double (&C)[4][4]) {
  bool zero = false;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) zero |= C[i][p] == 0.0;
  return zero;
}

}  // namespace

}  // namespace tetia::detail
