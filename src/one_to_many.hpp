// src/one_to_many.hpp -- the moments of the intersection of one tetrahedron with many
// (internal to the library; the supermesh uses it for each source cell).
//
// Contract: OneToMany(S).moments(T, conditioning(T)) is intersection_moments(S, T), bit for bit.
// What depends on S alone (its conditioning, and its barycentric map, used whenever S is the
// better-conditioned of the pair and so the reference) is computed once, by the constructor;
// what depends on T alone, by conditioning(T), which the caller may compute once per T. The
// kernel then only maps the other tetrahedron (and builds T's map when T is the reference).
// Allocation-free, like the kernel.
#pragma once

#include "barycentric_map.hpp"
#include "tetia/geometry.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia::detail {

/// What the kernel uses to choose the reference tetrahedron (src/tet_intersection.cpp,
/// make_frame): the shape quality |det| / (sum of squared edge lengths)^(3/2), and det6, six
/// times the signed volume.
struct Conditioning {
  double quality = 0.0;
  double det6 = 0.0;
};

/// The conditioning of t, computed as the kernel computes it for each pair.
Conditioning conditioning(const Tet& t);

/// Above this quality the sign of a tetrahedron's det6, and so the signs of its barycentric
/// map's coordinates, are certain: det6's rounding error is below about 1e-14 s^(3/2) (s the sum
/// of squared edge lengths), and the quality is |det6| / s^(3/2).
inline constexpr double kSignCertainQuality = 1e-12;

/// Bit k set unless all four points (rows of c, barycentric coordinates in some tetrahedron)
/// have coordinate k > 0: the faces whose plane does not have all four strictly on the
/// tetrahedron's side.
inline unsigned faces_not_strictly_inside(const double (&c)[4][4]) {
  unsigned inside = 0xFu;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) inside &= ~(unsigned(!(c[i][k] > 0.0)) << k);
  return ~inside & 0xFu;
}

class OneToMany {
 public:
  explicit OneToMany(const Tet& s);
  /// intersection_moments(s, t), given ct == conditioning(t).
  ///
  /// With t_faces: which faces of t s may meet, from the signs of the barycentric coordinates
  /// the kernel computed (certified: BarycentricMap's signs are exact where not zero). Bit k is
  /// cleared when s certainly does not meet t's face k (the triangle): if t was the reference
  /// (s's vertices in t's coordinates), when every vertex of s has coordinate k > 0 (s strictly
  /// on t's side of the face's plane); if s was, when the face's three vertices all have some
  /// coordinate p < 0 (strictly outside s's face p). kPlanesTested is set in the first case,
  /// where the plane test is complete; in the second the caller may add its own plane test.
  /// t_faces is 0xF (nothing known) for flat or non-finite input, and when the reference's
  /// quality is too low for the sign of its determinant, and so of its map, to be certain.
  static constexpr unsigned kPlanesTested = 0x10;
  Moments moments(const Tet& t, const Conditioning& ct, unsigned* t_faces = nullptr) const;

 private:
  Tet s_;
  Conditioning cs_;
  BarycentricMap map_;  // s's map (a flat or non-finite s is never a reference: not used then)
};

}  // namespace tetia::detail
