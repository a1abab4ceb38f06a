// tetia/kernel_trace.hpp -- a window into the kernel's sign decisions, for tests and for the
// parsimony study. Not needed to use the library.
//
// Contract: trace_kernel runs Algorithm 2 on the barycentric coordinates C[i][p] of X (vertex i,
// coordinate p = w, x, y, z) directly, without the change of coordinates, and reports what it
// decided: the flags of line 9, the signs of every edge-plane and face-line intersection, the
// corners with their labels (0-3 faces of X, 4-7 planes P_w..P_z) and the reference volume.
#pragma once

#include <array>
#include <cstdint>

#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::detail {

struct KernelTrace {
  /// crossings[e] bit p: edge e (tet_edges order) crosses P_p (line 9 of Algorithm 2).
  std::array<std::uint8_t, 6> crossings{};
  /// edge_sign[e][p][q]: binary sign of coordinate q at edge e ∩ P_p; -1 where there is no
  /// such intersection or q == p.
  std::int8_t edge_sign[6][4][4];
  /// face_sign[f][L][c]: sign of coordinate c at face f (opposite vertex f) ∩ line L, lines in
  /// the order {w,x},{w,y},{w,z},{x,y},{x,z},{y,z}; -1 where there is none or c is on the line.
  std::int8_t face_sign[4][6][4];
  int num_corners = 0;
  std::array<std::array<std::uint8_t, 3>, 32> labels{};
  std::array<std::array<double, 4>, 32> bary{};
  int num_facets = 0;
  double volume = 0.0;  ///< in the reference frame (Y has volume 1/6)
  bool consistent = false;
};

/// Runs the kernel on X given by its barycentric coordinates in Y.
void trace_kernel(const double (&C)[4][4], KernelTrace& trace, IntersectionStats* stats = nullptr);

/// The double kernel's own result for (U, V) and its error estimate relative to the smaller
/// tetrahedron (src/kernel/error_estimate.hpp), without the refinement or the exact last resort it
/// decides on: for the test that checks the estimate against GMP.
struct KernelEstimate {
  bool ran = false;       ///< the frame was made and the labels closed (first reference), not flat
  bool x_inside = false;  ///< all of the reference's other tetrahedron inside (its own volume)
  bool empty = false;     ///< no corners
  double volume = 0.0;    ///< the kernel's volume before any refinement
  /// The error estimate that decides (src/kernel/error_estimate.hpp; accepted where 0.5 of it is
  /// at most 1e-12): the smaller of the a priori one and, for a result with corners that is not
  /// X itself and fills less than half of the smaller tetrahedron, the a posteriori one.
  double estimate = 0.0;
  double a_priori = 0.0;  ///< the a priori estimate alone
  bool snapped = false;   ///< some coordinate of X is exactly 0 (on a plane of Y, or snapped to it)
};
KernelEstimate kernel_estimate(const Tet& U, const Tet& V);

/// The refinement in S's frame (src/kernel/refined_clip.hpp) for S (the smaller tetrahedron) and
/// B, both ways: as the kernel takes it, where the near-cover formula decides when all four of
/// B's planes cut at most a thin part off S, and by clipping alone.
struct NearCoverTrace {
  bool certified = false;       ///< the refinement's result stands (else the exact last resort)
  bool tried = false;           ///< the near-cover formula was evaluated
  bool decided = false;         ///< and accepted: `moments` are its
  double bound = 0.0;           ///< its error bound, relative to S's exact volume (where tried)
  Moments moments;              ///< the refinement's result
  bool clip_certified = false;  ///< the clipping's result stands
  Moments clipped;              ///< the clipping's result
  /// The clipping's derived error bound relative to S's exact volume (src/kernel/refined_clip.hpp,
  /// clip_bound; accepted where at most 2^-42), -1 where it did not clip to a positive volume.
  double clip_bound = -1.0;
  bool clip_separated = false;  ///< an empty clipping certified by a separating plane
};
NearCoverTrace near_cover_trace(const Tet& S, const Tet& B);

/// The check of the 2D kernel's result (src/kernel/tri_clip_check.hpp) run alone on (A, B), as
/// the kernel runs it: on the input scaled by the kernel's power of two where its sizes need it,
/// the vertices in the kernel's canonical order.
struct TriClipTrace {
  bool enclosed = false;  ///< an enclosure was found (else the pair would go exact)
  double area = 0.0;      ///< its centre, the area of A n B (in the caller's units)
  double error = 0.0;     ///< its radius, |area - exact| <= error (in the caller's units)
  double relative = 0.0;  ///< error over the smaller triangle's area (accepted at most 2^-42)
  double fraction = 0.0;  ///< the area as a fraction of the smaller triangle's
};
TriClipTrace tri_clip_trace(const Triangle& A, const Triangle& B);

/// The combinatorial example of Section 5.1: (x, y, z) of X's vertices with the signs of
/// Table 5 (w, x, y, z of vertices 0..3: ++++, ++++, +++-, +---); these dyadic values reproduce
/// Tables 6 and 7 of the paper (found by search). w = 1 - x - y - z.
inline constexpr double kSection51Example[4][3] = {
    {0.5, 0.125, 0.25}, {0.125, 0.375, 0.125}, {0.875, 0.375, -0.75}, {-0.625, -0.75, -0.125}};

/// Runs the kernel on the Section 5.1 example.
inline void trace_section51_example(KernelTrace& trace, IntersectionStats* stats = nullptr) {
  double C[4][4];
  for (int i = 0; i < 4; ++i) {
    const auto& p = kSection51Example[i];
    C[i][1] = p[0];
    C[i][2] = p[1];
    C[i][3] = p[2];
    C[i][0] = 1.0 - p[0] - p[1] - p[2];
  }
  trace_kernel(C, trace, stats);
}

}  // namespace tetia::detail
