// tetia/polygon.hpp -- the intersection of two triangles as a convex polygon.
//
// Contract: a Polygon is what `tetia::intersect(A, B)` (two triangles) returns. Each corner lies
// on exactly two of the six bounding lines (its label): edges 0-2 of A, lines 3-5 of B, where
// edge k of a triangle is the edge opposite its vertex k (so label 3 + p is the line {p = 0} of
// B's barycentric coordinate p). The corners are in counter-clockwise order (in the original
// coordinates, whatever the orientation of the input), an order found from the labels alone:
// two consecutive corners share a label. Coincident corners (a degenerate intersection) are kept
// as separate corners, so the combinatorics stay those of the six half-planes; the geometry then
// has zero-length edges.
//
// An empty polygon (no corners) means the intersection has no interior in the arithmetic used:
// disjoint, touching, or a flat input triangle. area() is never negative or NaN. Nothing here
// allocates except triangles() and triangle_corners().
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "tetia/geometry.hpp"

namespace tetia {

/// Area and first moments (integral of the position) of a planar region.
struct Moments2 {
  double area = 0.0;
  Vec2 first{};  ///< integral of (x, y) over the region; centroid = first / area

  /// Divided coordinate by coordinate: finite for every positive area, subnormal ones included
  /// (1 / area would overflow there).
  Vec2 centroid() const { return area > 0.0 ? Vec2{first.x / area, first.y / area} : Vec2{}; }
};

/// One corner of a triangle-triangle intersection.
struct PolygonCorner {
  Vec2 point;                          ///< position in the original coordinates
  std::array<double, 3> bary;          ///< barycentric coordinates in B, (w, x, y) = vertex 0..2
  std::array<std::uint8_t, 2> labels;  ///< the two lines it lies on, ascending: 0-2 A, 3-5 B
};

class Polygon {
 public:
  /// Six half-planes bound at most six corners (each of the six lines carries at most one side,
  /// each side has two ends, each corner ends two sides); the margin guards a logic error.
  static constexpr int max_corners = 12;

  bool empty() const { return num_corners_ == 0; }
  int num_corners() const { return num_corners_; }
  const PolygonCorner& corner(int i) const { return corners_[static_cast<std::size_t>(i)]; }
  /// The corners, counter-clockwise.
  std::span<const PolygonCorner> corners() const {
    return {corners_.data(), static_cast<std::size_t>(num_corners_)};
  }

  /// Area, computed in the reference frame of the reference triangle and scaled by its
  /// determinant. Never negative.
  double area() const { return moments_.area; }
  /// Area and first moments in the original coordinates.
  const Moments2& moments() const { return moments_; }
  Vec2 centroid() const { return moments_.centroid(); }

  /// Edges of B that the intersection lies on with a side (bit k: edge opposite B's vertex k):
  /// a side labelled 3 + k, or a side on an edge of A whose two corners have barycentric
  /// coordinate k exactly zero (a shared or collinear edge). Needed by advancing fronts.
  unsigned touched_edges_of_b() const { return touched_b_; }

  /// A triangulation: a fan from corner 0, counter-clockwise triangles whose areas add up to
  /// area() up to rounding (zero-area fan triangles of coincident corners are left out).
  std::vector<Triangle> triangles() const;
  /// The same triangles as corner indices (for output that shares the corners).
  std::vector<std::array<std::uint8_t, 3>> triangle_corners() const;

 private:
  template <class>
  friend struct PolygonBuilder;  // the 2D kernel's (src/kernel/tri_kernel.hpp)

  int num_corners_ = 0;
  unsigned touched_b_ = 0;
  Moments2 moments_{};
  std::array<PolygonCorner, max_corners> corners_;  // only the first num_corners_ are set
};

}  // namespace tetia
