// tetia/baselines.hpp -- the methods the paper compares against (Section 5.2), in doubles.
// For tests and comparisons only; they make no robustness promise.
//
//  - clip: Sutherland-Hodgman. U, as a closed polyhedron (a list of polygons), is clipped by the
//    four planes of V one after the other (plane offsets from V's own vertices); each clip
//    closes the cut with a new polygon. Volume by the divergence theorem.
//  - pang: PANG-style, as in PANG-3D (Gander & Japhet): collect vertices of U inside V, vertices
//    of V inside U, and every edge-face intersection computed independently for both pairs of
//    roles, then the volume of their convex hull. No consistency between the pieces.
#pragma once

#include "tetia/geometry.hpp"

namespace tetia::baselines {

/// Intersection volume by Sutherland-Hodgman clipping of U by V's faces.
double clip_volume(const Tet& U, const Tet& V);

/// Intersection volume by the PANG-style method (independent points + convex hull).
double pang_volume(const Tet& U, const Tet& V);

}  // namespace tetia::baselines
