// src/kernel/one_to_many.hpp -- the moments, or the polyhedron, of the intersection of one
// tetrahedron with many (internal to the library; the supermesh uses it for each source cell).
//
// Contract: OneToMany(S).moments(T, conditioning(T)) is intersection_moments(S, T), and
// OneToMany(S).intersect(T, conditioning(T), P) makes P intersect(S, T), bit for bit.
// What depends on S alone (its conditioning, and its barycentric map, used whenever S is the
// better-conditioned of the pair and so the reference) is computed once, by the constructor;
// what depends on T alone, by conditioning(T), which the caller may compute once per T. The
// kernel then only maps the other tetrahedron (and builds T's map when T is the reference).
// Allocation-free, like the kernel.
#pragma once

#include "barycentric_map.hpp"
#include "kernel_variant.hpp"
#include "tetia/geometry.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia::detail {

/// What the kernel uses to choose the reference tetrahedron (src/kernel/frame.hpp,
/// make_frame): the shape quality |det| / (sum of squared edge lengths)^(3/2), and det6, six
/// times the signed volume, with its inverse (computed alongside the quality, off the path from
/// the choice of the reference to its map).
struct Conditioning {
  double quality = 0.0;
  double det6 = 0.0;
  double inv_det6 = 0.0;  // 1 / det6, the scale of the barycentric map (BarycentricMap)
  // det6^2 and s^3, s the sum of squared edge lengths: quality^2 is their quotient, so that two
  // qualities compare by products, without waiting for the square root and the division.
  double det6_sq = 0.0;
  double s_cubed = 0.0;
  double s = 0.0;  // the sum of squared edge lengths (frame_from's range test)
};

/// The conditioning of t, computed as the kernel computes it for each pair.
Conditioning conditioning(const Tet& t);
/// The conditioning of a and of b, the same numbers as one at a time (one per SIMD lane).
void conditioning(const Tet& a, const Tet& b, Conditioning& ca, Conditioning& cb);

/// Above this quality the sign of a tetrahedron's det6, and so the signs of its barycentric
/// map's coordinates, are certain: det6's rounding error is below about 1e-14 s^(3/2) (s the sum
/// of squared edge lengths), and the quality is |det6| / s^(3/2).
inline constexpr double kSignCertainQuality = 1e-12;

class OneToMany {
 public:
  explicit OneToMany(const Tet& s);
  /// intersection_moments(s, t), given ct == conditioning(t).
  ///
  /// With t_faces: which faces of t s may cross, from the intersection's own facets. Bit k is
  /// cleared when the polytope s n t has no facet on t's face k: int(s) does not meet the
  /// interior of that triangle (where it does, s n t has a facet there), so no path inside s
  /// crosses it. kPlanesTested is then set: the mask is complete, no plane test is needed.
  /// t_faces is 0xF (nothing known) when the intersection is empty, for flat or non-finite
  /// input, and when the reference's quality is too low for the sign of its determinant, and so
  /// of its map and of the kernel's labels, to be certain.
  static constexpr unsigned kPlanesTested = 0x10;
  Moments moments(const Tet& t, const Conditioning& ct, unsigned* t_faces = nullptr) const {
    return variant_->one_to_many_moments(*this, t, ct, t_faces);
  }
  /// out = intersect(s, t) bit for bit, with t_faces as for moments(); returns out's moments
  /// (those of moments()). Where the intersection is empty, returns zero moments and leaves
  /// `out` as it was (no 2 KB to clear for each empty candidate).
  Moments intersect(const Tet& t, const Conditioning& ct, Polyhedron& out, unsigned* t_faces = nullptr) const {
    return variant_->one_to_many_intersect(*this, t, ct, out, t_faces);
  }

  /// s's barycentric map, and whether the signs of its coordinates are certain (the sign of s's
  /// det6 is: quality above kSignCertainQuality).
  const BarycentricMap& map() const { return map_; }
  const Tet& source() const { return s_; }
  const Conditioning& source_conditioning() const { return cs_; }
  bool signs_certain() const { return cs_.quality > kSignCertainQuality; }

 private:
  Tet s_;
  Conditioning cs_;
  BarycentricMap map_;  // s's map (a flat or non-finite s is never a reference: not used then)
  // The kernel's variant (kernel_variant.hpp), called directly: the supermesh calls it for every
  // candidate.
  const KernelVariant* variant_;
};

}  // namespace tetia::detail
