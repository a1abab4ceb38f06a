// src/kernel/algorithm2.hpp -- Kernel::run_steps, Algorithm 2 of McCoid & Gander in the order of
// its lines: the early exit, the vertices of X inside Y (lines 2-6, Section 3.1), the edges of
// X against the planes of Y (lines 7-17, edge_signs.hpp), the faces of X against the lines of Y
// (line 18, face_signs.hpp), and the vertices of Y inside X (lines 19-23, Section 3.4).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <bit>
#include <cstdint>

#include "kernel.hpp"
// The steps' members, in the order of the paper and of their declarations in class Kernel: with
// g++, the order in which the definitions come is the order the optimizer meets them in, and
// this one makes the same code as the members defined in the class.
#include "edge_signs.hpp"
#include "face_signs.hpp"
#include "nonconvex_repair.hpp"
#include "corner_coordinates.hpp"

namespace tetia::detail {

namespace {

template <bool kWeights, bool kStats>
bool Kernel<kWeights, kStats>::run_steps(KernelResult& out, CornerList& cl) {
  // Lines 2-6 (Snippet 2): an empty intersection if X lies on the negative side of a plane.
  // The same holds, for the volume, when no vertex is strictly on the positive side: X ∩ Y
  // then lies in the plane. That is the case of two tetrahedra sharing a face from opposite
  // sides, whose shared vertices have coordinate exactly 0 (BarycentricMap); the answer is
  // then exactly zero instead of a flat sliver of rounding-sized volume.
  // (Without statistics the kernel runs only from run_kernel, which has made this test on C
  // already: pm_ covering every plane implies sm_ does.)
  if (kStats && ((sm_[0] | sm_[1] | sm_[2] | sm_[3]) != 0xF || (pm_[0] | pm_[1] | pm_[2] | pm_[3]) != 0xF)) return true;

  // Vertices of X inside Y: all four binary signs are 1 (Section 3.1). A vertex lies on the
  // three faces of X that contain it.
  for (int i = 0; i < 4; ++i)
    if (sm_[i] == 0xF) {
      RawCorner& rc = add_corner(out, cl, kFaceVerts[i][0], kFaceVerts[i][1], kFaceVerts[i][2], kVertexOfX, i);
      const Quad q = load4(C_[i]);
      store4(rc.bary, q);
      guardrail(rc.bary, 0, nonneg_lanes(q));
      if constexpr (kWeights) {
        for (int p = 0; p < 4; ++p) rc.weights[p] = 0.0;
        rc.weights[i] = 1.0;
      }
    }
  if ((sm_[0] & sm_[1] & sm_[2] & sm_[3]) == 0xF) return true;  // X inside Y

  // Lines 7-17: edges of X against planes of Y; corners where all signs are 1. A line of Y
  // meets the boundary of X in zero or two points while every X ∩ P_a is convex in its signs;
  // four would mean rounding twisted a quadrilateral (Fig. 6), which untwist repairs
  // (nonconvex_repair.hpp).
  for (int e = 0; e < 6; ++e) order_edge(e);
  build_segments();
  if (const unsigned views = twisted_views()) [[unlikely]]
    untwist(views);
  for (std::uint32_t rest = edge_corners_; rest; rest &= rest - 1) {
    const int bitpos = std::countr_zero(rest);
    const int e = bitpos >> 2, p = bitpos & 3;
    // Edge ij lies on the two faces of X opposite the vertices it does not contain, which are
    // the vertices of the opposite edge 5 - e.
    RawCorner& rc = add_corner(out, cl, tet_edges[5 - e][0], tet_edges[5 - e][1], 4 + p, kEdgeOfX, e * 4 + p);
    edge_corner_coords(e, p, rc);
  }

  // Line 18: faces of X against lines of Y (the segments f ∩ P_a are built above).
  face_line_flags();
  unsigned faces = 0;  // the faces of X that meet a line of Y
  for (int f = 0; f < 4; ++f) faces |= unsigned(fexist_[f] != 0) << f;
  for (; faces; faces &= faces - 1) {
    const int f = std::countr_zero(faces);
    decide_face(f);
    const unsigned fs = fsign_[f];
    const unsigned full = fs & (fs >> 1) & (fs >> 2) & (fs >> 3) & 0x111111u;  // nibble == 0xF
    for (unsigned rest = full & kLineNibbles[fexist_[f]]; rest; rest &= rest - 1) {  // bit 4L
      const int L = std::countr_zero(rest) >> 2;
      const int a = kLines[L][0], b = kLines[L][1];
      RawCorner& rc = add_corner(out, cl, f, 4 + a, 4 + b, kFaceOfX, f * 8 + L);
      face_corner_coords(f, a, b, rc);
    }
  }

  // Lines 19-23 (Section 3.4): vertex t of Y lies in X iff, on a line of Y through it, the two
  // intersections with faces of X differ in the sign of the coordinate that is neither the
  // line's nor t's. One line suffices; with statistics on, the other two are checked to agree
  // (end of the proof of Theorem 6).
  if constexpr (!kStats) {  // the same test on the first line, for the four vertices at once
    // The first lines through the vertices t = 0..3 are (2,3), (2,3), (1,3), (1,2) (lines 5, 5,
    // 4, 3) with the coordinates 1, 0, 0, 0: per face, the line's existence and that sign go to
    // nibble 3 - t of two counters; t is inside when two faces meet its line and exactly one of
    // them has the sign 1 (the two-point test below, in counts). In that nibble order the bits
    // needed, ex bits 3, 4, 5, 5 and fs bits 4L + r = 12, 16, 20, 21, come in a few operations.
    static_assert(kVertexLines[0][0][0] == 5 && kVertexLines[0][0][1] == 1 && kVertexLines[1][0][0] == 5 &&
                  kVertexLines[1][0][1] == 0 && kVertexLines[2][0][0] == 4 && kVertexLines[2][0][1] == 0 &&
                  kVertexLines[3][0][0] == 3 && kVertexLines[3][0][1] == 0);
    unsigned met = 0, positive = 0;
    for (int f = 0; f < 4; ++f) {
      const unsigned ex = fexist_[f], fs = fsign_[f];
      const unsigned e = ((ex >> 3) * 0x49u & 0x111u) | (ex & 0x20u) << 7;  // bits 3, 4, 5, 5 -> 0, 4, 8, 12
      const unsigned sg = ((fs >> 12) & 0x111u) | ((fs >> 9) & 0x1000u);    // bits 12, 16, 20, 21 -> 0, 4, 8, 12
      met += e;
      positive += e & sg;
    }
    const unsigned two = met ^ 0x2222u, one = positive ^ 0x1111u;  // zero nibbles where met == 2, positive == 1
    const unsigned nz = two | one;
    const unsigned zero_nibbles = ~(nz | (nz >> 1) | (nz >> 2) | (nz >> 3)) & 0x1111u;
    // Bit 4k -> bit 3 - k = t: the four products land on bits 15, 14, 13, 12, and the others
    // on distinct bits below 12 (no carry) or above 15.
    unsigned inside = ((zero_nibbles * 0x8421u) >> 12) & 0xFu;
    for (; inside; inside &= inside - 1) {
      const int t = std::countr_zero(inside);
      const int l0 = t == 0 ? 5 : 4, l1 = t <= 1 ? 6 : 5, l2 = t == 3 ? 6 : 7;
      RawCorner& rc = add_corner(out, cl, l0, l1, l2, kVertexOfY, t);
      for (int p = 0; p < 4; ++p) rc.bary[p] = rc.weights[p] = p == t ? 1.0 : 0.0;  // weights unknown here (see fill())
    }
    return consistent_;
  }
  const unsigned any_line = fexist_[0] | fexist_[1] | fexist_[2] | fexist_[3];
  for (int t = 0; t < 4 && any_line; ++t) {
    int inside = -1;
    for (int k = 0; k < 3 && (inside < 0 || stats()); ++k) {
      const int L = kVertexLines[t][k][0], r = kVertexLines[t][k][1];
      unsigned s = 0;
      int n = 0;
      for (int f = 0; f < 4; ++f) {  // the r-signs of the faces meeting the line, in order
        const unsigned e = bit(fexist_[f], L);
        s |= (e & unsigned(bit(fsign_[f], 4 * L + r))) << n;
        n += int(e);
      }
      const int here = n == 2 && (s == 1 || s == 2);
      if (inside >= 0 && here != inside) note_inconsistency();
      inside = here;
    }
    if (inside == 1) {
      const int l0 = t == 0 ? 5 : 4, l1 = t <= 1 ? 6 : 5, l2 = t == 3 ? 6 : 7;
      RawCorner& rc = add_corner(out, cl, l0, l1, l2, kVertexOfY, t);
      for (int p = 0; p < 4; ++p) rc.bary[p] = rc.weights[p] = p == t ? 1.0 : 0.0;  // weights unknown here (see fill())
    }
  }
  return consistent_;
}

}  // namespace

}  // namespace tetia::detail
