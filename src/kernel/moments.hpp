// src/kernel/moments.hpp -- the volume and first moments of X ∩ Y: in the reference frame, by
// fans over the facets (fan_moments, reference_moments), and back in the caller's coordinates
// by the inverse change of coordinates, eq. (3) (original_moments).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <cmath>

#include "fan.hpp"
#include "frame.hpp"
#include "kernel_result.hpp"
#include "tetia/geometry.hpp"

namespace tetia::detail {

namespace {

// --- volume and moments in the reference frame --------------------------------------------

// Volume and first moments in the reference frame, where the corners' barycentric coordinates
// are the data the kernel decided. Each facet is fanned into triangles and joined to the mean
// of the corners, a point inside the polytope: every such pyramid has non-negative volume for
// a convex polytope, so its absolute value is taken and the facets' walking directions do not
// matter. Returns six times the signed volume as the facets are stored (for orientation).
template <bool kMoments>
double fan_moments(KernelResult& r, double& vol6, double (&m)[3]) {
  vol6 = 0.0;
  m[0] = m[1] = m[2] = 0.0;
  if (r.num_facets == 0) return 0.0;
  double o[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < r.num_corners; ++c)
    for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
  const double inv = 1.0 / r.num_corners;  // as in build_facets: the same rounding
  for (double& x : o) x *= inv;
  double signed6 = 0.0;
  for (int f = 0; f < r.num_facets; ++f) {
    const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
    double fv = 0.0, fm[3] = {0.0, 0.0, 0.0};
    fan_pyramids<kMoments>(o, e - b, [&](int k) { return r.corners[r.facet_index[b + k]].bary; }, fv, fm);
    signed6 += fv;
    r.facet_volume6[f] = fv;
    const double s = fv < 0.0 ? -1.0 : 1.0;
    vol6 += s * fv;
    if constexpr (kMoments)
      for (int c = 0; c < 3; ++c) m[c] += s * fm[c];
  }
  return signed6;
}

template <bool kMoments>
void reference_moments(KernelResult& r) {
  double vol6, m[3];
  fan_moments<kMoments>(r, vol6, m);
  r.ref_volume = vol6 / 6.0;
  for (int c = 0; c < 3; ++c) r.ref_first[c] = m[c] / 24.0;
}

// The volume in original units: the reference frame's volume scaled by |det6|, except where X
// lies inside Y, whose intersection is X itself: its own |det6| / 6 then, accurate relative to X
// however much smaller X is (its corners, X's vertices, have coordinates in Y's frame that
// resolve X only to eps times Y's size); or the refined result where the kernel's was not
// certified (solve_with). Every entry point takes the volume from here.
double original_volume(const Frame& fr, const KernelResult& res) {
  if (res.refined) [[unlikely]] return res.refined_moments.volume;
  return res.x_inside ? std::abs(fr.det6_sub) * (1.0 / 6.0) : res.ref_volume * std::abs(fr.det6);
}

Moments original_moments(const Frame& fr, const KernelResult& res) {
  if (res.refined) [[unlikely]] return res.refined_moments;
  Moments m;
  if (res.x_inside) {  // X itself: volume and centroid from its vertices (original_volume)
    const Tet& s = *fr.sub;
    m.volume = original_volume(fr, res);
    m.first = m.volume * (0.25 * (((s[0] + s[1]) + s[2]) + s[3]));
    return m;
  }
  const double scale = std::abs(fr.det6);
  m.volume = res.ref_volume * scale;
  const Tet& r = *fr.ref;
  const Vec3 a1 = r[1] - r[0], a2 = r[2] - r[0], a3 = r[3] - r[0];
  const Vec3 lin = res.ref_first[0] * a1 + res.ref_first[1] * a2 + res.ref_first[2] * a3;
  m.first = m.volume * r[0] + scale * lin;
  return m;
}

}  // namespace

}  // namespace tetia::detail
