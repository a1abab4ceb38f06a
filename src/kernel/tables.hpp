// src/kernel/tables.hpp -- the constant index tables of the kernel: the numbering of the
// edges, faces and lines of X and Y, and the tables that turn the sign decisions of Sections
// 3.2-3.4 of McCoid & Gander into bit operations (edge orders, segments, triples, lanes).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <cstdint>

#include "tetia/geometry.hpp"

namespace tetia::detail {

using u8 = std::uint8_t;

namespace {

// Edge index of the vertex pair (i, j), in the order of tet_edges (Snippet 3's jmap).
constexpr int kEdgeOf[4][4] = {{-1, 0, 1, 3}, {0, -1, 2, 4}, {1, 2, -1, 5}, {3, 4, 5, -1}};
// The six lines P_p ∩ P_q of Y (edges of Y), p < q.
constexpr int kLines[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kLineOf[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
// The three vertices of face f (the face opposite vertex f), ascending.
constexpr int kFaceVerts[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

constexpr bool bit(unsigned mask, int k) { return (mask >> k) & 1u; }
constexpr u8 kPopcount4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// The triple of face-line intersections around vertex t of Y (Section 3.3, Fig. 3): with
// p < q < r the other three planes, slot s is the point F(f, {a, b}) on line[s] and its
// coordinate c, (a, b, c) = slot[s]; rel lists the pairs of slots that meet in a plane
// (slot, slot, plane, b, c) for Corollary 1.
struct Triple {
  int slot[3][3];
  int line[3];
  int rel[3][5];
};
constexpr Triple make_triple(int t) {
  int pl[3] = {0, 0, 0}, n = 0;
  for (int x = 0; x < 4; ++x)
    if (x != t) pl[n++] = x;
  const int p = pl[0], q = pl[1], r = pl[2];
  return {{{p, q, r}, {p, r, q}, {q, r, p}},
          {kLineOf[p][q], kLineOf[p][r], kLineOf[q][r]},
          {{0, 1, p, q, r}, {0, 2, q, p, r}, {1, 2, r, p, q}}};
}
constexpr Triple kTriples[4] = {make_triple(0), make_triple(1), make_triple(2), make_triple(3)};

// For face f and the pattern (sign of b differs from a) | (sign of c differs from a) << 1 of
// its vertices (a, b, c) in one coordinate: the lone vertex and the other two. Pattern 0 (no
// segment) maps to a harmless placeholder.
struct SegmentTable {
  u8 v[4][4][3];
};
constexpr SegmentTable make_segment_table() {
  SegmentTable t{};
  for (int f = 0; f < 4; ++f) {
    const u8 a = static_cast<u8>(kFaceVerts[f][0]), b = static_cast<u8>(kFaceVerts[f][1]),
             c = static_cast<u8>(kFaceVerts[f][2]);
    const u8 rows[4][3] = {{a, b, c}, {b, a, c}, {c, a, b}, {a, b, c}};
    for (int w = 0; w < 4; ++w)
      for (int k = 0; k < 3; ++k) t.v[f][w][k] = rows[w][k];
  }
  return t;
}
constexpr SegmentTable kSegmentTable = make_segment_table();
constexpr const u8 (&kSegmentVerts)[4][4][3] = kSegmentTable.v;

// The three lines of Y through vertex t, each with the coordinate that vanishes at t but not
// on the line (Section 3.4): {line, coordinate}.
constexpr int kVertexLines[4][3][2] = {{{kLineOf[2][3], 1}, {kLineOf[1][3], 2}, {kLineOf[1][2], 3}},
                                       {{kLineOf[2][3], 0}, {kLineOf[0][3], 2}, {kLineOf[0][2], 3}},
                                       {{kLineOf[1][3], 0}, {kLineOf[0][3], 1}, {kLineOf[0][1], 3}},
                                       {{kLineOf[1][2], 0}, {kLineOf[0][2], 1}, {kLineOf[0][1], 2}}};

// The pairs (y, x), y < x, of planes in the order of kLines, as 6-bit lane masks: for a sign
// mask s, lane L of y[s] is bit y_L of s, lane L of x[s] is bit x_L of s.
struct PairLanes {
  u8 y[16], x[16];
};
constexpr PairLanes make_pair_lanes() {
  PairLanes t{};
  for (unsigned s = 0; s < 16; ++s) {
    unsigned y = 0, x = 0;
    for (int L = 0; L < 6; ++L) {
      y |= ((s >> kLines[L][0]) & 1u) << L;
      x |= ((s >> kLines[L][1]) & 1u) << L;
    }
    t.y[s] = static_cast<u8>(y);
    t.x[s] = static_cast<u8>(x);
  }
  return t;
}
constexpr PairLanes kPairLanes = make_pair_lanes();

// The order of an edge's crossings from its pairwise comparisons (order_edge_by_pairs): for
// the crossed planes c and the comparisons yx (lane L set: P_y crossed before P_x; lanes of
// pairs not both crossed are ignored), nibble p holds the crossed planes met before P_p (all
// crossed planes when p is not crossed itself); kNotAnOrder when the comparisons are cyclic.
// Each plane's rank is the number of planes before it; the ranks of the crossed planes must
// be distinct for a total order.
constexpr std::uint16_t kNotAnOrder = 0xFFFF;
struct EdgeOrderTable {
  std::uint16_t v[16][64];
};
constexpr EdgeOrderTable make_edge_order_table() {
  EdgeOrderTable t{};
  for (unsigned c = 0; c < 16; ++c)
    for (unsigned yx = 0; yx < 64; ++yx) {
      unsigned before[4] = {0, 0, 0, 0};  // before[p] bit q: P_p is crossed before P_q
      for (int L = 0; L < 6; ++L) {
        const int y = kLines[L][0], x = kLines[L][1];
        if (!bit(c, x) || !bit(c, y)) continue;
        if (bit(yx, L)) before[y] |= 1u << x;
        else before[x] |= 1u << y;
      }
      unsigned ranks = 0, out = 0;  // one bit per rank taken
      for (int p = 0; p < 4; ++p) {
        const unsigned earlier = c & ~before[p] & ~(1u << p);
        ranks |= unsigned(bit(c, p)) << kPopcount4[earlier];
        out |= earlier << (4 * p);
      }
      t.v[c][yx] = ranks == (1u << kPopcount4[c]) - 1u ? static_cast<std::uint16_t>(out) : kNotAnOrder;
    }
  return t;
}
constexpr EdgeOrderTable kEdgeOrder = make_edge_order_table();

// Bit p of a 4-bit mask spread to nibble p (0xF); bit L of a 6-bit mask to nibble L (0xF).
struct SpreadTables {
  std::uint16_t nibbles[16];
  std::uint32_t lines[64];
};
constexpr SpreadTables make_spread_tables() {
  SpreadTables t{};
  for (unsigned m = 0; m < 16; ++m)
    for (int p = 0; p < 4; ++p) t.nibbles[m] = static_cast<std::uint16_t>(t.nibbles[m] | (bit(m, p) ? 0xFu << (4 * p) : 0u));
  for (unsigned m = 0; m < 64; ++m)
    for (int L = 0; L < 6; ++L) t.lines[m] |= (bit(m, L) ? 0xFu : 0u) << (4 * L);
  return t;
}
constexpr SpreadTables kSpread = make_spread_tables();
constexpr const std::uint16_t (&kNibbles)[16] = kSpread.nibbles;
constexpr const std::uint32_t (&kLineNibbles)[64] = kSpread.lines;

// For each triple (vertex t of Y), the bits 4 line + c of its three slots' coordinates c.
struct TripleBits {
  std::uint32_t v[4];
};
constexpr TripleBits make_triple_bits() {
  TripleBits b{};
  for (int t = 0; t < 4; ++t)
    for (int s = 0; s < 3; ++s) b.v[t] |= 1u << (4 * kTriples[t].line[s] + kTriples[t].slot[s][2]);
  return b;
}
constexpr TripleBits kTripleBitsTable = make_triple_bits();
constexpr const std::uint32_t (&kTripleBits)[4] = kTripleBitsTable.v;

}  // namespace

}  // namespace tetia::detail
