// tetia/exact.hpp -- exact intersection volume (3D) and area (2D) with GMP rationals, for tests
// and comparisons.
//
// Contract: the input doubles are taken as exact rationals; the result is the exact volume
// (area) of the intersection of the two closed tetrahedra (triangles): zero when they only
// touch, are disjoint, or one is flat. Any vertex orientation. Non-finite coordinates throw
// std::domain_error. Independent of the kernels' logic:
//  - 3D: every point defined by three of the eight planes is solved exactly, the feasible ones
//    are kept, and the volume is that of their convex hull, facet by facet;
//  - 2D: Sutherland-Hodgman clipping of A by B's three closed half-planes in rationals, then
//    the shoelace formula.
// Slow (tens of microseconds to a millisecond); never on a hot path.
#pragma once

#include <gmpxx.h>

#include "tetia/geometry.hpp"

namespace tetia::exact {

/// Exact volume of a tetrahedron (unsigned).
mpq_class volume(const Tet& t);

/// Exact volume of U intersected with V.
mpq_class intersection_volume(const Tet& U, const Tet& V);

/// The same, rounded to the nearest double.
double intersection_volume_double(const Tet& U, const Tet& V);

/// Exact area of a triangle (unsigned).
mpq_class area(const Triangle& t);

/// Exact area of A intersected with B.
mpq_class intersection_area(const Triangle& A, const Triangle& B);

/// The same, rounded to the nearest double (ties to even).
double intersection_area_double(const Triangle& A, const Triangle& B);

}  // namespace tetia::exact
