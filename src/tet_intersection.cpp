// Placeholder: replaced by the kernel author. Returns empty results.
#include "tetia/tet_intersection.hpp"
namespace tetia {
IntersectionStats& IntersectionStats::operator+=(const IntersectionStats&) { return *this; }
Polyhedron intersect(const Tet&, const Tet&, IntersectionStats*) { return {}; }
double intersection_volume(const Tet&, const Tet&) { return 0.0; }
Moments intersection_moments(const Tet&, const Tet&) { return {}; }
}  // namespace tetia
