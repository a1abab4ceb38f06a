// src/kernel/separation.hpp -- whether two tetrahedra certainly meet in zero volume: a plane
// with one on each side (closed half-spaces), found among the separating-axis candidates (the
// face normals of each, the cross products of an edge of each), with every rounding of the test
// bounded.
// Part of the kernel's one translation unit: included by src/kernel/refined_clip.hpp.
//
// Why: an empty result that the a priori estimate does not certify (a sliver near the other
// tetrahedron, a size ratio far from 1) needs a certificate that the exact intersection is empty
// or below 1e-12 of the smaller tetrahedron. Among the benchmark's random pairs (the first
// 2 x 10^5, 2026-12-06), every such result had a separating plane with a margin far above
// rounding: a face of the bigger tetrahedron in 64 % of them, a face of the smaller in 16 %, an
// edge of each in 20 %. Where such a plane exists the intersection has no volume, whatever the
// sizes.
//
// Contract: certainly_separated(A, B) returns true only if A and B lie in the two closed
// half-spaces of some plane (A n B then lies in the plane: its volume is 0); false says nothing
// (overlapping tetrahedra, or a separation within rounding). Finite input; an overflow answers
// false. Allocation-free, no exceptions.
//
// The bound. Each axis n is whatever the rounded cross products give (any vector will do: only
// the test needs to be exact). For a vertex p, q = p - o (o: a vertex the two share exactly if
// there is one, else A's vertex 0; translation keeps the products small where both are far from
// the origin) is rounded to q(1 + delta), |delta| <= u (u = 2^-53), and n . q is evaluated as
// (n.x q.x + n.y q.y) + n.z q.z, within gamma_3 of sum |n_i q_i| (Higham, eq. 3.5): n . (p - o)
// is within (gamma_3 + u / (1 - u)) sum |n_i q_i| < 4.0001 u sum |n_i q_i| of the computed
// value. Bounding each projection by value -+ 7 u sum |n_i q_i| leaves room for the rounding of
// the sum of magnitudes (3 u) and of value -+ bound (u |value| <= 1.0001 u sum); 2^-1070 covers
// what underflow takes (four operations, each at most 2^-1075 absolute). Where every term has
// n_i = 0 or q_i = 0 (q_i = 0 only for p_i = o_i exactly: a difference of doubles does not
// underflow to 0), the value is exactly 0 and so is its bound: a shared vertex projects to
// exactly 0 for both, which lets two tetrahedra that touch at it be certified.
#pragma once

#include <algorithm>
#include <cmath>

#include "tetia/geometry.hpp"

namespace tetia::detail {

namespace {

namespace separation_impl {

// [lo, hi] containing n . (p - o) exactly for the four vertices p of t (see the top); false
// where a bound is not finite (an overflow: nothing is certain then).
inline bool projection_bounds(const Vec3& n, const Tet& t, const Vec3& o, double& lo, double& hi) {
  lo = INFINITY;
  hi = -INFINITY;
  double largest = 0.0;
  for (const Vec3& p : t) {
    const Vec3 q = p - o;
    const double value = (n.x * q.x + n.y * q.y) + n.z * q.z;
    const bool exact_zero = (n.x == 0.0 || q.x == 0.0) && (n.y == 0.0 || q.y == 0.0) && (n.z == 0.0 || q.z == 0.0);
    const double bound =
        exact_zero ? 0.0
                   : 0x1.cp-51 * ((std::abs(n.x * q.x) + std::abs(n.y * q.y)) + std::abs(n.z * q.z)) + 0x1p-1070;  // 7 u
    largest = std::max(largest, bound);
    lo = std::min(lo, value - bound);
    hi = std::max(hi, value + bound);
  }
  return largest < INFINITY;  // NaN compares false too
}

// Whether axis n certainly separates a and b (closed half-spaces), projections relative to o.
inline bool separates(const Vec3& n, const Tet& a, const Tet& b, const Vec3& o) {
  double a_lo, a_hi, b_lo, b_hi;
  if (!projection_bounds(n, a, o, a_lo, a_hi) || !projection_bounds(n, b, o, b_lo, b_hi)) return false;
  return a_hi <= b_lo || b_hi <= a_lo;
}

// A vertex of a equal to a vertex of b, or a's vertex 0.
inline Vec3 shared_or_first(const Tet& a, const Tet& b) {
  for (const Vec3& p : a)
    for (const Vec3& q : b)
      if (p.x == q.x && p.y == q.y && p.z == q.z) return p;
  return a[0];
}

inline constexpr int kFaceVertices[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
inline constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

// Whether a face plane of t separates t and other.
inline bool face_separates(const Tet& t, const Tet& other, const Vec3& o) {
  for (const auto& f : kFaceVertices) {
    const Vec3 n = cross(t[f[1]] - t[f[0]], t[f[2]] - t[f[0]]);
    if (separates(n, t, other, o)) return true;
  }
  return false;
}

}  // namespace separation_impl

// A and B certainly meet in zero volume (see the top). The faces of `first` are tried first (the caller's
// guess of the likelier one), then those of the other (unless second_faces is false: a caller
// that has tested them already), then the 36 edge pairs.
inline bool certainly_separated(const Tet& first, const Tet& second, bool second_faces = true) {
  using namespace separation_impl;
  const Vec3 o = shared_or_first(first, second);
  if (face_separates(first, second, o) || (second_faces && face_separates(second, first, o))) return true;
  for (const auto& e : kEdges) {
    const Vec3 u = first[e[1]] - first[e[0]];
    for (const auto& f : kEdges) {
      const Vec3 n = cross(u, second[f[1]] - second[f[0]]);
      if (separates(n, first, second, o)) return true;
    }
  }
  return false;
}

}  // namespace

}  // namespace tetia::detail
