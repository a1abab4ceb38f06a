// src/kernel/face_signs.hpp -- Section 3.3 of McCoid & Gander, line 18 of Algorithm 2: which
// faces of X meet which lines P_a ∩ P_b of Y, and the signs of the coordinates of those
// intersections, by inheritance, Corollary 1 (the triples around each vertex of Y, Fig. 3) and
// the direct calculation of eq. (5) with its denominator's sign from Lemma 5.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <bit>
#include <cstdint>

#include "kernel.hpp"

namespace tetia::detail {

namespace {

// --- Section 3.3: faces of X against the lines of Y --------------------------------------

// The segment (face f) ∩ P_a runs between the crossings of two edges of f with P_a; those
// edges share the face's lone vertex in coordinate a (Proposition 1 for a triangle).
// seg1_/seg2_ hold the sign masks at its two endpoints in nibble a, zero when there is no
// segment. For face (u, v, w) and plane P_p the lone vertex is v when only u and v differ in
// p-sign, w when only u and w differ, and u when both do; the endpoints are then on the
// edges (v u, v w), (w u, w v) and (u v, u w): the same choice as kSegmentVerts, four planes
// at a time.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::build_segments() {
  for (int f = 0; f < 4; ++f) {
    const int u = kFaceVerts[f][0], v = kFaceVerts[f][1], w = kFaceVerts[f][2];
    const unsigned x = kNibbles[sm_[u] ^ sm_[v]], y = kNibbles[sm_[u] ^ sm_[w]];
    const unsigned uv = em_[kEdgeOf[u][v]], uw = em_[kEdgeOf[u][w]], vw = em_[kEdgeOf[v][w]];
    seg1_[f] = static_cast<std::uint16_t>((uv & x) | (uw & ~x & y));
    seg2_[f] = static_cast<std::uint16_t>((vw & (x ^ y)) | (uw & x & y));
  }
}

// Line 18: face f meets line P_a ∩ P_b iff the endpoints of (f ∩ P_a) differ in b-sign.
// Seen from P_b the answer must be the same (first part of the proof of Theorem 6).
// With d = seg1_ ^ seg2_ (bit 4a + b: the endpoints in P_a differ in b-sign), line L = (a, b)
// reads bit 4a + b from P_a and bit 4b + a from P_b.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::face_line_flags() {
  for (int f = 0; f < 4; ++f) {
    const unsigned d = unsigned(seg1_[f] ^ seg2_[f]);
    // The transpose of d as a 4x4 bit matrix (bit 4b + a), by two delta swaps: bit 4a + b
    // of (d & dt) holds both views of line (a, b).
    unsigned dt = d, x = (dt ^ (dt >> 3)) & 0x0A0Au;
    dt ^= x ^ (x << 3);
    x = (dt ^ (dt >> 6)) & 0x00CCu;
    dt ^= x ^ (x << 6);
    // Bits 1, 2, 3, 6, 7, 11 to bits 0-5 (lines in kLines order).
    const auto lines = [](unsigned m) { return ((m >> 1) & 0x7u) | ((m >> 3) & 0x18u) | ((m >> 6) & 0x20u); };
    if (stats() && lines(d) != lines(dt)) note_inconsistency();
    fexist_[f] = static_cast<u8>(lines(d & dt));
  }
}

// Corollary 1 (with ERRATA's reading of its condition) in the plane P_a: on the segment
// (f ∩ P_a) crossing both P_b and P_c, the c-sign at the b-crossing and the b-sign at the
// c-crossing satisfy  sign(c_ab) ⊗ sign(b_ac) = sign(c at E1) ⊗ sign(b at E2),  for the two
// endpoints E1, E2 of the segment (Lemma 2 one dimension down). Returns the right side.
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::pairing(int f, int a, int b, int c) const {
  return bit(seg_m1(f, a), c) == bit(seg_m2(f, a), b);
}

// 3x3 determinant of columns (c, a, b) over rows (i, j, k) of C: the numerator of eq. (5).
template <bool kWeights, bool kStats>
inline double Kernel<kWeights, kStats>::numerator5(int c, int a, int b, int i, int j, int k) const {
  const double* ri = C_[i];
  const double* rj = C_[j];
  const double* rk = C_[k];
  return ri[c] * (rj[a] * rk[b] - rj[b] * rk[a]) - ri[a] * (rj[c] * rk[b] - rj[b] * rk[c]) +
         ri[b] * (rj[c] * rk[a] - rj[a] * rk[c]);
}

// Direct calculation of sign(c_ab^{f}), eq. (5), through the segment in P_a. The numerator
// is evaluated; the sign of the denominator det[1 a b] is not: it follows from signs already
// decided, by Lemma 5: sign det[1 b a](i,j,k) = sign det[b_i a_i; b_j a_j], which is
// sign(b_a^{ij}) ⊗ sign(a_j - a_i). This keeps the new sign consistent with the previous
// level even when the face is nearly parallel to the line.
template <bool kWeights, bool kStats>
inline bool Kernel<kWeights, kStats>::direct_sign(int f, int a, int b, int c) const {
  const u8* v = seg_verts(f, a);
  const int i = v[0], j = v[1], k = v[2];
  const double num = numerator5(c, a, b, i, j, k);
  const bool det_1ba = bit(seg_m1(f, a), b) == bit(sm_[j], a);
  const bool den_positive = !det_1ba;  // det[1 a b] = -det[1 b a]
  return num == 0.0 || ((num > 0.0) == den_positive);
}

// Signs of the coordinates of the face-line intersections of face f. A coordinate c of
// F(f, {a, b}) is inherited when either parent pair agrees in it, that is when the segment
// (f ∩ P_a) or (f ∩ P_b) does not cross P_c; as masks, all of a face's inheritances are a few
// bit operations, for the six lines at once (nibble L of fsign_[f] and undecided_[f]). What
// is left is decided one triple at a time (resolve_triple).
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::decide_face(int f) {
  // Nibble L of the spread masks: nibble a_L (spread_a) or b_L (spread_b) of a 16-bit mask.
  const auto spread_a = [](unsigned v) {
    return (v & 0xFu) * 0x111u | ((v >> 4) & 0xFu) * 0x11000u | ((v >> 8) & 0xFu) << 20;
  };
  const auto spread_b = [](unsigned v) {
    return ((v >> 4) & 0xFu) | ((v >> 8) & 0xFu) * 0x1010u | ((v >> 12) & 0xFu) * 0x110100u;
  };
  constexpr unsigned on_line = 0xCA6953u;  // nibble L: the bits a_L and b_L
  const unsigned m1 = seg1_[f], d = m1 ^ seg2_[f];
  const unsigned ma = spread_a(m1), mb = spread_b(m1), da = spread_a(d), db = spread_b(d);
  // Prefer the parents in P_a; those in P_b where the P_a pair crosses P_c.
  fsign_[f] = (on_line | (ma & ~da) | (mb & ~db & da)) & 0xFFFFFFu;
  const unsigned undecided = da & db & ~on_line & 0xFFFFFFu;
  undecided_[f] = undecided;
  if (stats()) {
    for (unsigned lines = fexist_[f]; lines; lines &= lines - 1) {
      const int L = std::countr_zero(lines);
      const unsigned both = ~(da >> (4 * L)) & ~(db >> (4 * L)) & ~(on_line >> (4 * L)) & 0xFu;  // inherited twice
      if (((ma ^ mb) >> (4 * L)) & both) note_inconsistency();
      stats()->face_inherited += 2 - kPopcount4[(undecided >> (4 * L)) & 0xFu];
    }
  }
  const unsigned open = undecided & kLineNibbles[fexist_[f]];
  if (!open) return;
  for (int t = 0; t < 4; ++t)
    if (open & kTripleBits[t]) resolve_triple(f, kTriples[t]);
}

// For face f and vertex t of Y, the three points F(f,{p,q}), F(f,{p,r}), F(f,{q,r}) around
// the vertex P_p ∩ P_q ∩ P_r share one numerator up to sign (the "tripling" of Section 3.3,
// Fig. 3). Their coordinates r, q, p not inherited are linked pairwise by Corollary 1
// wherever two of the points exist; a group with no known sign gets one direct calculation
// (eq. 5), and the others follow.
template <bool kWeights, bool kStats>
inline void Kernel<kWeights, kStats>::resolve_triple(int f, const Triple& T) {
  const unsigned ex = fexist_[f];
  const bool exists[3] = {bit(ex, T.line[0]), bit(ex, T.line[1]), bit(ex, T.line[2])};
  int value[3] = {-1, -1, -1};
  unsigned known = 0;  // bit s: slot s exists and its sign was inherited
  for (int s = 0; s < 3; ++s)
    if (exists[s] && !bit(undecided_[f], 4 * T.line[s] + T.slot[s][2])) {
      value[s] = bit(fsign_[f], 4 * T.line[s] + T.slot[s][2]);
      known |= 1u << s;
    }
  if (!stats() && known == 0) {
    // The usual case: no sign known. The existing slots are pairwise related (T.rel lists
    // every pair), so the loop below computes the first existing slot's sign directly and
    // gives each other existing slot its sign from that one's through their relation; the
    // same, without the loop's searching.
    const int s = exists[0] ? 0 : exists[1] ? 1 : 2;
    const bool vs = direct_sign(f, T.slot[s][0], T.slot[s][1], T.slot[s][2]);
    unsigned signs = unsigned(vs) << (4 * T.line[s] + T.slot[s][2]);
    for (int t = s + 1; t < 3; ++t) {
      const auto& R = T.rel[s + t - 1];  // the relation of slots s < t: (0,1), (0,2), (1,2)
      signs |= unsigned(exists[t] && vs == pairing(f, R[2], R[3], R[4])) << (4 * T.line[t] + T.slot[t][2]);
    }
    fsign_[f] |= signs;
    return;
  }
  const int before[3] = {value[0], value[1], value[2]};
  for (;;) {
    // Propagate known signs along the relations (two passes settle a triangle).
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& R : T.rel) {
        if (!exists[R[0]] || !exists[R[1]]) continue;
        const int k1 = value[R[0]], k2 = value[R[1]];
        if ((k1 >= 0) == (k2 >= 0)) continue;
        const bool xnor = pairing(f, R[2], R[3], R[4]);
        const int known = k1 >= 0 ? k1 : k2;
        value[k1 >= 0 ? R[1] : R[0]] = (bool(known) == xnor) ? 1 : 0;
        if (stats()) ++stats()->face_paired;
      }
    int undecided = -1;
    for (int s = 0; s < 3 && undecided < 0; ++s)
      if (exists[s] && value[s] < 0) undecided = s;
    if (undecided < 0) break;
    value[undecided] = direct_sign(f, T.slot[undecided][0], T.slot[undecided][1], T.slot[undecided][2]);
    if (stats()) ++stats()->face_computed;
  }
  if (stats()) {  // every relation must hold (Theorem 6)
    for (const auto& R : T.rel)
      if (exists[R[0]] && exists[R[1]] &&
          ((value[R[0]] == value[R[1]]) != pairing(f, R[2], R[3], R[4])))
        note_inconsistency();
  }
  for (int s = 0; s < 3; ++s)
    if (exists[s] && before[s] < 0)
      fsign_[f] |= unsigned(value[s]) << (4 * T.line[s] + T.slot[s][2]);
}

}  // namespace

}  // namespace tetia::detail
