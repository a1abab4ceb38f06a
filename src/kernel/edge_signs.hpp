// src/kernel/edge_signs.hpp -- Section 3.2 of McCoid & Gander, lines 7-17 of Algorithm 2: the
// planes of Y that each edge of X crosses (line 9), and the signs of the coordinates of every
// crossing, by inheritance (Lemma 3), pairing (Lemma 2) and the straight line principle
// (Section 3.2.1), with eq. (2) deciding the comparisons that are computed.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <bit>
#include <cstdint>

#include "kernel.hpp"
#include "minor_sign.hpp"

namespace tetia::detail {

namespace {

// --- Section 3.2: edges of X against the planes of Y -------------------------------------

// Does edge e (from x_i to x_j) cross P_y before P_x? Decided by the sign of x_y^{ij}, the
// x-coordinate of the crossing with P_y, eq. (2): it still has x_i's sign iff P_x comes later.
// Only the signs of the numerator and of the denominator are needed; the numerator of
// y_x^{ij} is exactly the negative of this one in floating point, so the pairing of Lemma 2
// holds for computed values too. With exact_minors_ (the repair of a twisted cross-section,
// untwist) the numerator's sign is the exact sign of the minor of the computed C
// (minor_sign.hpp: where the products round to one nonzero double, their rounding errors
// decide); signs decided so cannot twist a cross-section (docs/architecture.md, step 8).
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::crosses_before(int i, int j, int y, int x) const {
  const double num = exact_minors_ ? minor_with_exact_sign(C_[j][x], C_[i][y], C_[i][x], C_[j][y])
                                   : C_[j][x] * C_[i][y] - C_[i][x] * C_[j][y];
  const bool den_positive = bit(sm_[i], y);  // y_i >= 0 > y_j, so y_i - y_j > 0
  const bool sign_x = num == 0.0 || ((num > 0.0) == den_positive);
  return sign_x == bit(sm_[i], x);
}

// Lines 7-17 of Algorithm 2 for one edge: flag the planes it crosses (line 9) and decide the
// signs of every crossing. A coordinate q the edge does not cross keeps the sign its two
// vertices share (Lemma 3). Among the crossed planes, signs follow from the order of the
// crossings along the edge: before its crossing with P_q a point has the q-sign of x_i, after
// it that of x_j. The order is found by insertion sort with a comparison computed by eq. (2):
// each comparison is one direct calculation and decides a pair of signs, sign(q_p^{ij}) and
// sign(p_q^{ij}) (Lemma 2); every order the sort infers without comparing is forced by the
// straight line principle (Section 3.2.1), which is what makes the signs of an edge crossing
// three or four planes those of a straight line.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::order_edge(int e) {
  const int i = tet_edges[e][0], j = tet_edges[e][1];
  const unsigned crossed = unsigned(sm_[i] ^ sm_[j]);
  cross_[e] = static_cast<u8>(crossed);
  if (!stats() && order_edge_by_pairs(e, i, j, crossed)) return;
  order_edge_sorted(e, i, j, crossed);
}

// order_edge by insertion sort, each comparison by crosses_before.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::order_edge_sorted(int e, int i, int j, unsigned crossed) {
  if (!crossed) return;
  int sorted[4], n = 0, comparisons = 0;
  for (unsigned rest = crossed; rest; rest &= rest - 1) {
    const int x = std::countr_zero(rest);
    int pos = n;
    while (pos > 0) {
      ++comparisons;
      if (crosses_before(i, j, sorted[pos - 1], x)) break;
      sorted[pos] = sorted[pos - 1];
      --pos;
    }
    sorted[pos] = x;
    ++n;
  }
  // Walk along the edge from x_i: each crossing flips one sign to x_j's.
  unsigned m = sm_[i], on_y = 0;
  for (int r = 0; r < n; ++r) {
    const unsigned b = 1u << sorted[r];
    const unsigned here = m | b;  // on P_p itself, p = 0: sign 1
    em_[e] = static_cast<std::uint16_t>(em_[e] | (here << (4 * sorted[r])));
    on_y |= unsigned(here == 0xFu) << sorted[r];
    m = (m & ~b) | (sm_[j] & b);
  }
  edge_corners_ |= on_y << (4 * e);
  if (stats()) {
    stats()->edge_inherited += n * (4 - n);
    stats()->edge_computed += comparisons;
    stats()->edge_paired += comparisons;
    stats()->edge_straight_line += n * (n - 1) - 2 * comparisons;
  }
}

// The same order, found without branching on the data (the fast path when no statistics
// are kept): every pair of crossed planes y < x is compared once, by the same computation
// the sort would make, and each plane's rank is the number of planes crossed before it. When
// the comparisons are transitive this is the order the sort finds, so both paths give the
// same signs; when rounding makes them cyclic (ranks collide), the sort above decides, as
// the straight line principle requires. Returns false in that case.
//
// All six pairs are evaluated (those not both crossed are ignored by the table), as bit
// masks over the pairs in the order of kLines: the comparison of crosses_before for pair
// (y, x) is  (num == 0 || (num > 0) == sign y_i) == sign x_i.  kEdgeOrder then gives, for
// the crossed planes and the comparisons, the planes crossed before each plane (or that the
// comparisons are not a total order).
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::order_edge_by_pairs(int e, int i, int j, unsigned crossed) {
#if TETIA_KERNEL_SSE2
  // Lanes (0,1),(0,2) | (0,3),(1,2) | (1,3),(2,3): the same products and difference per
  // lane as the scalar loop below, two at a time.
  const __m128d* a = lanes_[i];
  const __m128d* b = lanes_[j];
  const __m128d z = _mm_setzero_pd();
  const __m128d n0 = _mm_sub_pd(_mm_mul_pd(b[2], a[0]), _mm_mul_pd(a[2], b[0]));
  const __m128d n1 = _mm_sub_pd(_mm_mul_pd(b[3], a[1]), _mm_mul_pd(a[3], b[1]));
  const __m128d n2 = _mm_sub_pd(_mm_mul_pd(b[4], a[2]), _mm_mul_pd(a[4], b[2]));
  // sign_x below in one comparison per register: with the sign of num flipped in the lanes
  // where y_i < 0 (an exact negation), (num == 0 || (num > 0) == sign y_i) is num >= 0.
  const double* flip = kFlipLanes.v[sm_[i]];
  const unsigned sign_x = unsigned(_mm_movemask_pd(_mm_cmpge_pd(_mm_xor_pd(n0, _mm_load_pd(flip)), z))) |
                          unsigned(_mm_movemask_pd(_mm_cmpge_pd(_mm_xor_pd(n1, _mm_load_pd(flip + 2)), z))) << 2 |
                          unsigned(_mm_movemask_pd(_mm_cmpge_pd(_mm_xor_pd(n2, _mm_load_pd(flip + 4)), z))) << 4;
#else
  const double* ci = C_[i];
  const double* cj = C_[j];
  unsigned pos = 0, zero = 0;
  for (int L = 0; L < 6; ++L) {
    const int y = kLines[L][0], x = kLines[L][1];
    const double num = cj[x] * ci[y] - ci[x] * cj[y];
    pos |= unsigned(num > 0.0) << L;
    zero |= unsigned(num == 0.0) << L;
  }
  const unsigned sign_x = zero | ~(pos ^ kPairLanes.y[sm_[i]]);
#endif
  const unsigned si = sm_[i];
  const unsigned yx = ~(sign_x ^ kPairLanes.x[si]) & 63u;
  const unsigned earlier = kEdgeOrder.v[crossed][yx];
  if (earlier == kNotAnOrder) return false;
  // At the crossing with P_p: planes not crossed keep x_i's sign (Lemma 3), planes crossed
  // later still have x_i's, planes crossed earlier have x_j's; p itself is 0. As x_j's sign
  // differs from x_i's exactly in the crossed planes, that is x_i's mask with the earlier
  // planes flipped (one nibble per plane).
  const unsigned here = ((si * 0x1111u) ^ earlier) | 0x8421u;
  em_[e] = static_cast<std::uint16_t>(here);
  const unsigned full = here & (here >> 1) & (here >> 2) & (here >> 3) & 0x1111u;  // nibble == 0xF
  edge_corners_ |= (((full * 0x1248u) >> 12) & crossed) << (4 * e);  // bit 4p -> bit p
  return true;
}

}  // namespace

}  // namespace tetia::detail
