// tetia/polyhedron.hpp -- the intersection of two tetrahedra as a polyhedron.
//
// Contract: a Polyhedron is what `tetia::intersect(U, V)` returns. Each corner lies on exactly
// three of the eight bounding planes (its label): faces 0-3 of U, faces 4-7 of V, where face k
// of a tetrahedron is the face opposite its vertex k (so label 4 + p is the plane {p = 0} of V's
// barycentric coordinate p). The facets are cycles of corners, outward oriented (counter-clockwise
// seen from outside), built from the labels alone: two consecutive corners of a facet share two
// labels. Coincident corners (a degenerate intersection) are kept as separate corners so that the
// combinatorics stay those of a simple polytope; the geometry then has zero-length edges.
//
// An empty polyhedron (no corners) means the intersection has no interior in the arithmetic
// used: disjoint, touching, or a flat input tetrahedron. volume() is never negative or NaN.
// Nothing here allocates except tetrahedra().
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "tetia/geometry.hpp"

namespace tetia {

/// Volume and first moments (integral of the position) of a region.
struct Moments {
  double volume = 0.0;
  Vec3 first{};  ///< integral of (x, y, z) over the region; centroid = first / volume

  /// Divided coordinate by coordinate: finite for every positive volume, subnormal ones
  /// included (1 / volume would overflow there).
  Vec3 centroid() const {
    return volume > 0.0 ? Vec3{first.x / volume, first.y / volume, first.z / volume} : Vec3{};
  }
};

/// One corner of the intersection.
struct Corner {
  Vec3 point;                        ///< position in the original coordinates
  std::array<double, 4> bary;        ///< barycentric coordinates in V, (w, x, y, z) = vertex 0..3
  std::array<std::uint8_t, 3> labels;///< the three planes it lies on, ascending: 0-3 U, 4-7 V
};

class Polyhedron {
 public:
  /// A simple polytope with at most 8 facets has at most 2*8 - 4 = 12 corners; the algorithm
  /// produces no more than that, the margin guards against a logic error (checked).
  static constexpr int max_corners = 32;
  static constexpr int max_facets = 8;
  static constexpr int max_facet_indices = 3 * max_corners;

  bool empty() const { return num_corners_ == 0; }
  int num_corners() const { return num_corners_; }
  const Corner& corner(int i) const { return corners_[static_cast<std::size_t>(i)]; }
  std::span<const Corner> corners() const {
    return {corners_.data(), static_cast<std::size_t>(num_corners_)};
  }

  int num_facets() const { return num_facets_; }
  /// The label (0-7) of the plane facet f lies in.
  int facet_label(int f) const { return facet_label_[static_cast<std::size_t>(f)]; }
  /// Corner indices of facet f, counter-clockwise seen from outside.
  std::span<const std::uint8_t> facet(int f) const {
    const auto b = facet_begin_[static_cast<std::size_t>(f)];
    const auto e = facet_begin_[static_cast<std::size_t>(f) + 1];
    return {facet_index_.data() + b, static_cast<std::size_t>(e - b)};
  }

  /// Volume, computed in the reference frame and scaled by its determinant. Never negative.
  double volume() const { return moments_.volume; }
  /// Volume and first moments in the original coordinates.
  const Moments& moments() const { return moments_; }
  Vec3 centroid() const { return moments_.centroid(); }

  /// Faces of V that the intersection lies on with a facet (bit k: face opposite V's vertex k):
  /// a facet labelled 4 + k, or a facet of U whose corners all have barycentric coordinate
  /// k exactly zero (a shared or coplanar face). Needed by advancing fronts over matching meshes.
  unsigned touched_faces_of_v() const { return touched_v_; }

  /// A tetrahedralization: a fan from corner 0 over every facet that does not contain it.
  /// Tetrahedra are positively oriented; their volumes add up to volume() up to rounding.
  std::vector<Tet> tetrahedra() const;
  /// The same tetrahedra as corner indices (for output that shares the corners).
  std::vector<std::array<std::uint8_t, 4>> tetrahedra_corners() const;

 private:
  template <class>
  friend struct PolyhedronBuilder;  // the kernel's (src/kernel/polyhedron_builder.hpp)

  int num_corners_ = 0;
  int num_facets_ = 0;
  unsigned touched_v_ = 0;
  Moments moments_{};
  // Only the first num_corners_ are ever set or read, so the storage is left uninitialized on
  // construction (a result is built in place for every pair of tetrahedra).
  struct CornerStorage {
    CornerStorage() {}
    union {
      Corner v[max_corners];
    };
    Corner& operator[](std::size_t i) { return v[i]; }
    const Corner& operator[](std::size_t i) const { return v[i]; }
    const Corner* data() const { return v; }
  };
  CornerStorage corners_;
  // Like the corners, only the first num_facets_ labels and the indices they delimit are set.
  std::array<std::uint8_t, max_facets> facet_label_;
  std::array<std::uint8_t, max_facets + 1> facet_begin_{};
  std::array<std::uint8_t, max_facet_indices> facet_index_;
};

}  // namespace tetia
