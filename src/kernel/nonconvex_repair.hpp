// src/kernel/nonconvex_repair.hpp -- the non-convex case of the proof of Theorem 6 (Fig. 6 of
// McCoid & Gander): a cross-section X ∩ P_a whose four vertices alternate in b-sign, so that
// the line P_a ∩ P_b meets four faces of X. The paper's rule keeps the two extreme
// intersections on such a line. Here the cause is removed instead: the edge signs are decided
// again with the exact sign of every minor of C (crosses_before with exact_minors_), and signs
// decided so never alternate around a quadrilateral (docs/architecture.md, step 8, has the
// proof). The configuration needs the computed minors to be rounding ties, so this runs on no
// ordinary input; tests/test_tet_intersection.cpp makes it on purpose.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <bit>

#include "kernel.hpp"

namespace tetia::detail {

namespace {

// Bit 4a + b: the line P_a ∩ P_b meets all four faces of X, seen from P_a (the ends of every
// face's segment f ∩ P_a differ in b-sign). Nonzero exactly where some cross-section is
// twisted (Fig. 6); needs build_segments.
template <bool kWeights, bool kStats>
inline unsigned Kernel<kWeights, kStats>::twisted_views() const {
  return unsigned(seg1_[0] ^ seg2_[0]) & unsigned(seg1_[1] ^ seg2_[1]) & unsigned(seg1_[2] ^ seg2_[2]) &
         unsigned(seg1_[3] ^ seg2_[3]);
}

// The repair: every edge ordered again by insertion sort with exact minors (their comparisons
// are then transitive, so the sort's order is each pair's own comparison), and the segments
// rebuilt from the new signs. Counted with statistics: the twisted lines found
// (nonconvex_lines), and, as an inconsistency, any left after the repair (the proof says none).
template <bool kWeights, bool kStats>
[[gnu::noinline]] void Kernel<kWeights, kStats>::untwist(unsigned views) {
  if (stats()) {
    for (int L = 0; L < 6; ++L) {
      const int a = kLines[L][0], b = kLines[L][1];
      stats()->nonconvex_lines += (bit(views, 4 * a + b) || bit(views, 4 * b + a)) ? 1 : 0;
    }
  }
  exact_minors_ = true;
  edge_corners_ = 0;
  for (int e = 0; e < 6; ++e) {
    em_[e] = 0;
    order_edge_sorted(e, tet_edges[e][0], tet_edges[e][1], cross_[e]);
  }
  build_segments();
  if (stats() && twisted_views() != 0) note_inconsistency();
}

}  // namespace

}  // namespace tetia::detail
