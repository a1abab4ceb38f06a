// tetia/tri_intersection.hpp -- Algorithm 1 (PANG2) of McCoid & Gander, "A provably robust
// algorithm for triangle-triangle intersections in floating-point arithmetic" (ACM TOMS 48,
// 2022), as summarized in Algorithm 1 of their tetrahedron paper.
//
// Contract (the 2D counterpart of tet_intersection.hpp):
//  - Any vertex orientation of A and B is accepted. Non-finite input gives an empty result;
//    check input at the boundary (the CLI and the mesh readers do).
//  - Any finite input, from subnormal to 1e308 coordinates, gives a finite result: the area is
//    >= 0 and at most min(|A|, |B|) (1 + 1e-12), and it is 0 (or infinite) only when the exact
//    area rounds to that. A flat triangle (exactly collinear vertices) or a tangent contact
//    gives an empty polygon. Extreme magnitudes are rescaled by an exact power of two; what
//    the double computation does not certify (a frame that is flat in doubles although the input
//    is not, labels that do not close with either reference, an area that is not finite, is not
//    positive although corners were found, or exceeds the smaller triangle, and a result the
//    check below does not accept) is computed exactly (GMP rationals,
//    src/kernel/exact_fallback.hpp) and rounded once; the statistics count it.
//  - The result is consistent: its corners form a closed convex polygon ordered from their labels
//    alone, so a real intersection cannot vanish through rounding.
//  - Symmetric: intersect(A, B) and intersect(B, A) compute the same polygon bit for bit (the
//    better-conditioned triangle is the reference), and so does any reordering of either
//    triangle's vertices (they are put in a canonical order first); labels and barycentric
//    coordinates are reported relative to the caller's argument and vertex order.
//  - Accuracy: within 1e-12 of the exact area relative to the smaller triangle, at any size
//    ratio (to 1e16 tested), sliver height (to 1e-12), scale (2^-500 to 2^500) and distance from
//    the origin (2^50) (tests/test_tri_vs_exact.cpp, the Adversarial family); tangent contacts
//    give an empty polygon. Pairs in general position (every orientation of a vertex against
//    the other triangle's edge lines certain: all but 8 of the 810,282 random benchmark pairs
//    whose boxes overlap) get their area, first moments and polygon from a formula with a
//    derived error bound, within 2^-47 of the smaller triangle
//    (src/kernel/tri_certified_moments.hpp, tests/test_tri_certified.cpp). The kernel's area
//    for the other pairs stands only where a clipping with a derived error bound puts it within
//    2^-42 of the smaller triangle of the exact area (src/kernel/tri_clip_check.hpp,
//    tests/test_tri_clip_check.cpp); so every area is within a derived bound of the exact one,
//    or exact. The first moments carry no bound of their own.
//  - Every entry point (intersect with or without statistics, intersection_area,
//    intersection_moments, either argument order) gives the same area bit for bit.
//  - No heap allocation and no exceptions on the double path; the exact last resort allocates
//    (GMP) and is taken only for the inputs listed above.
#pragma once

#include <cstdint>

#include "tetia/geometry.hpp"
#include "tetia/polygon.hpp"

namespace tetia {

/// How each sign and coordinate was obtained (Algorithm 1, lines 8-13). Counts add up over calls.
struct TriIntersectionStats {
  std::int64_t edge_inherited = 0;      ///< sign shared by both ends of the edge
  std::int64_t edge_paired = 0;         ///< line 10: the sign of the partner intersection
  std::int64_t edge_straight_line = 0;  ///< forced by the order of the other two crossings
  std::int64_t edge_computed = 0;       ///< line 9: a direct calculation
  std::int64_t corner_coordinates = 0;  ///< coordinates evaluated for corners that lie on Y
  std::int64_t guardrail_clamps = 0;    ///< a computed coordinate clamped to its decided sign
  std::int64_t reference_swaps = 0;     ///< A was better conditioned and became the reference
  std::int64_t inconsistencies = 0;     ///< kernel runs whose signs contradicted each other or
                                        ///< whose label walk did not close (each attempt, as in 3D)
  std::int64_t retries = 0;             ///< label walks that did not close, redone with the
                                        ///< other reference
  std::int64_t refined = 0;             ///< corner coordinates recomputed in extended precision
                                        ///< (the plain ones were not accurate to 2^-44)
  std::int64_t rescaled = 0;            ///< inputs scaled by a power of two (extreme magnitudes)
  std::int64_t exact_fallbacks = 0;     ///< results computed exactly (the last resort)
  std::int64_t certified = 0;           ///< area and first moments from the certified formula
                                        ///< (kernel/tri_certified_moments.hpp): a bound of
                                        ///< 2^-47 of the smaller triangle, or certainly apart
  std::int64_t checked = 0;             ///< kernel results put to the check
                                        ///< (kernel/tri_clip_check.hpp)
  std::int64_t check_rejected = 0;      ///< of those, not accepted: computed exactly (also
                                        ///< counted in exact_fallbacks)
  std::int64_t calls = 0;

  TriIntersectionStats& operator+=(const TriIntersectionStats& o);
};

/// The intersection polygon of A and B.
Polygon intersect(const Triangle& A, const Triangle& B, TriIntersectionStats* stats = nullptr);

/// The area of the intersection.
double intersection_area(const Triangle& A, const Triangle& B);

/// Area and first moments of the intersection, in original coordinates.
Moments2 intersection_moments(const Triangle& A, const Triangle& B);

}  // namespace tetia
