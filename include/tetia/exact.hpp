// tetia/exact.hpp -- exact intersection volume with GMP rationals, for tests and comparisons.
//
// Contract: the input doubles are taken as exact rationals; the result is the exact volume of
// the intersection of the two closed tetrahedra (zero when they only touch or one is flat).
// Independent of the kernel's logic: every point defined by three of the eight planes is solved
// exactly, the feasible ones are kept, and the volume is that of their convex hull, facet by
// facet. Slow (about a millisecond); never on a hot path.
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

}  // namespace tetia::exact
