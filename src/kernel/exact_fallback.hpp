// src/kernel/exact_fallback.hpp -- the kernels' last resort: the intersection computed exactly
// (GMP rationals, src/exact.cpp) and rounded once. Used only for the inputs the double kernels
// do not certify (docs/architecture.md, "Every finite input"): a frame that is flat or not
// finite in doubles although the input is finite, labels that do not close with either
// reference, a result that is not finite, negative-or-zero with corners, or larger than the
// smaller cell. Slow (tens of microseconds to a millisecond) and allocating; never the usual
// path.
//
// Contract: the polygon (polyhedron) is A ∩ B (U ∩ V) of the input doubles taken as exact
// rationals; every number reported is the exact value rounded to the nearest double (the
// measure and the first moments once each; corners' points and barycentric coordinates
// coordinate by coordinate). Empty exactly when the exact measure is 0.
#pragma once

#include <cstdint>

#include "tetia/geometry.hpp"
#include "tetia/polygon.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia::detail {

/// A ∩ B with the labels of tetia::Polygon: corners counter-clockwise, each on the two lines of
/// its labels (ascending; 0-2 edges of A, 3-5 lines of B, edge k opposite vertex k), consecutive
/// corners sharing a label; barycentric coordinates in B, exactly 0 on B's lines of the labels.
struct ExactPolygon {
  int num_corners = 0;
  Vec2 point[Polygon::max_corners];
  double bary[Polygon::max_corners][3];
  std::uint8_t labels[Polygon::max_corners][2];
  Moments2 moments;
};

/// Finite input only (checked by the caller).
void exact_polygon(const Triangle& A, const Triangle& B, ExactPolygon& out);

/// U ∩ V with the labels of tetia::Polyhedron: every vertex of the exact polytope is a corner
/// labelled with the planes it lies on (0-3 faces of U, 4-7 faces of V, face k opposite vertex
/// k), each facet a cycle counter-clockwise seen from outside, barycentric coordinates in V
/// exactly 0 on V's planes of the labels. A face of U and a face of V in one plane with one
/// orientation make one facet, labelled with the lower plane. `simple`: every corner lies on
/// exactly three of the (remaining) planes, as for a polyhedron of the double kernel; where a
/// degenerate intersection has a corner on more (the exact polytope is not simple), it carries
/// its three lowest labels and the facets are still the exact ones.
struct ExactPolyhedron {
  int num_corners = 0;
  int num_facets = 0;
  bool simple = true;
  Vec3 point[Polyhedron::max_corners];
  double bary[Polyhedron::max_corners][4];
  std::uint8_t labels[Polyhedron::max_corners][3];
  std::uint8_t facet_label[Polyhedron::max_facets];
  std::uint8_t facet_begin[Polyhedron::max_facets + 1];
  std::uint8_t facet_index[Polyhedron::max_facet_indices];
  Moments moments;
};

/// Finite input only (checked by the caller).
void exact_polyhedron(const Tet& U, const Tet& V, ExactPolyhedron& out);

}  // namespace tetia::detail
