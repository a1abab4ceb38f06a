// tetia/tet_intersection.hpp -- Algorithm 2 of McCoid & Gander, "A provably robust algorithm
// for tetrahedron-tetrahedron intersections in floating-point arithmetic".
//
// Contract:
//  - Any vertex orientation of U and V is accepted. Non-finite input gives an empty result;
//    check input at the boundary (the CLI and the mesh readers do).
//  - Any finite input, from subnormal to 1e308 coordinates, gives a finite result: the volume is
//    >= 0 and at most min(|U|, |V|) (1 + 1e-12), and it is 0 (or infinite) only when the exact
//    volume is within the accuracy below of 0 (or rounds to infinity). An exactly flat
//    tetrahedron gives an empty result. Extreme sizes are rescaled by an exact power of two; what the double computation does not certify (a
//    frame that is flat or not finite in doubles for finite input, a tetrahedron flat to the
//    rounding of its own coordinates, labels that close with neither reference, a volume that is
//    not finite or exceeds the smaller tetrahedron) is computed exactly (GMP) and rounded once;
//    the statistics count it. A tetrahedron certainly inside the other (every vertex beyond
//    the rounding of its orientations) is returned exactly.
//  - Accuracy: within 1e-12 of the exact volume relative to the smaller tetrahedron, at any
//    size ratio, sliver height, scale or distance from the origin, wherever the smaller one is
//    not flat to the rounding of its own coordinates (shape quality above 2^-40, below which the
//    exact last resort decides). Every double result carries an error estimate; what it does
//    not certify is computed again in the smaller tetrahedron's own frame, in double-double
//    where needed (IntersectionStats::refined; beyond a size ratio of about 2^50, exactly).
//    The estimate's constant is calibrated against GMP on the test families and under a
//    directed search for its worst case, not proven (docs/architecture.md, "Accuracy relative
//    to the smaller tetrahedron"). What the refinement returns carries a derived bound: the
//    near-cover formula's where the smaller tetrahedron is nearly inside the other, the
//    clipping's (from the computed polytope: its faces' residuals, its triangles' certain
//    orientations, one ray crossing it once) otherwise, and an empty result a separating plane
//    or one plane keeping at most 2^-42 of the smaller; what none certifies is computed exactly.
//  - The result is consistent: its corners and facets form a closed polytope whose facets are
//    built from labels alone, so a real intersection cannot vanish through rounding
//    (Theorem 6 and Corollary 2 of the paper).
//  - Symmetric: intersect(U, V) and intersect(V, U) compute the same polytope bit for bit
//    (the better-conditioned tetrahedron is always the reference, see docs/architecture.md);
//    only the labels and barycentric coordinates are reported relative to the argument order.
//  - Every entry point (intersect with or without statistics, intersection_volume,
//    intersection_moments, either argument order, and the supermesh's internal one-to-many
//    path) gives the same volume bit for bit.
//  - No heap allocation and no exceptions on the double path; the exact last resort allocates
//    (GMP) and is taken only for the inputs listed above.
#pragma once

#include <cstdint>

#include "tetia/geometry.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia {

/// How each sign and coordinate was obtained (the paper's parsimony claim, Sections 4.1, 5.1).
/// Counts are added to, so one object can accumulate over many calls.
struct IntersectionStats {
  // Section 3.2: signs of coordinates of edge-of-X / plane-of-Y intersections.
  std::int64_t edge_inherited = 0;      ///< Lemma 3
  std::int64_t edge_paired = 0;         ///< Lemma 2
  std::int64_t edge_straight_line = 0;  ///< Section 3.2.1
  std::int64_t edge_computed = 0;       ///< eq. (2), direct
  // Section 3.3: signs of coordinates of face-of-X / line-of-Y intersections.
  std::int64_t face_inherited = 0;      ///< from either parent pair
  std::int64_t face_paired = 0;         ///< Corollary 1
  std::int64_t face_computed = 0;       ///< eq. (5), direct
  std::int64_t nonconvex_lines = 0;     ///< lines of Y that four faces of X meet, seen from
                                        ///< either of the line's planes (Fig. 6, the non-convex
                                        ///< case of Theorem 6's proof), from edge signs that
                                        ///< rounding ties twisted; each such pair's edge signs
                                        ///< are decided again with exact minors, which cannot
                                        ///< twist (docs/architecture.md, step 8)
  // Coordinates actually evaluated for corners that lie on Y (eq. 2 / eq. 5), and clamps.
  std::int64_t corner_coordinates = 0;
  std::int64_t guardrail_clamps = 0;    ///< Section 4.1.1
  std::int64_t reference_swaps = 0;     ///< U was better conditioned and became the reference
  std::int64_t inconsistencies = 0;     ///< kernel runs whose signs contradicted each other
                                        ///< or whose labels did not close up (each attempt)
  std::int64_t retries = 0;             ///< first attempts whose labels did not close up,
                                        ///< redone with the other reference (see solve_with)
  std::int64_t rescaled = 0;            ///< inputs scaled by a power of two (extreme sizes)
  std::int64_t refined = 0;             ///< results whose error estimate exceeded 1e-12 of the
                                        ///< smaller tetrahedron: certified empty by a separating
                                        ///< plane, or computed again in its own frame with
                                        ///< double-double orientations (see solve_with)
  std::int64_t exact_fallbacks = 0;     ///< results computed exactly (the last resort)
  std::int64_t calls = 0;

  IntersectionStats& operator+=(const IntersectionStats& o);
};

/// The intersection polyhedron of U and V.
Polyhedron intersect(const Tet& U, const Tet& V, IntersectionStats* stats = nullptr);

/// The volume of the intersection (the fast path: no original coordinates, no allocation).
double intersection_volume(const Tet& U, const Tet& V);

/// Volume and first moments of the intersection, in original coordinates.
Moments intersection_moments(const Tet& U, const Tet& V);

}  // namespace tetia
