// tetia/baselines.hpp -- the methods the paper compares against (Section 5.2), in doubles.
// For tests and comparisons only; they make no robustness promise.
//
//  - clip: Sutherland-Hodgman. U, as a closed polyhedron (a list of polygons), is clipped by the
//    four planes of V one after the other (plane offsets from V's own vertices); each clip
//    closes the cut with a new polygon. Volume by the divergence theorem.
//  - pang: PANG-style, as in PANG-3D (Gander & Japhet): collect vertices of U inside V, vertices
//    of V inside U, and every edge-face intersection computed independently for both pairs of
//    roles, then the volume of their convex hull. No consistency between the pieces.
//
// And their 2D counterparts for triangles (any orientation; 0 for flat or non-finite input):
//
//  - clip_area: Sutherland-Hodgman. A, as a polygon, is clipped by the three lines of B one
//    after the other (each line's side computed from B's own vertices); shoelace area. Fixed-size
//    arrays, no heap: the speed baseline for the 2D kernel.
//  - pang_area: PANG-style (Gander & Japhet's PANG2): vertices of A inside B, vertices of B
//    inside A and every edge-edge intersection, each computed independently, then the area of
//    their convex hull.
#pragma once

#include "tetia/geometry.hpp"

namespace tetia::baselines {

/// Intersection volume by Sutherland-Hodgman clipping of U by V's faces.
double clip_volume(const Tet& U, const Tet& V);

/// Intersection volume by the PANG-style method (independent points + convex hull).
double pang_volume(const Tet& U, const Tet& V);

/// Intersection area by Sutherland-Hodgman clipping of A by B's three lines.
double clip_area(const Triangle& A, const Triangle& B);

/// Intersection area by the PANG-style method (independent points + convex hull).
double pang_area(const Triangle& A, const Triangle& B);

}  // namespace tetia::baselines
