// Algorithm 2 of McCoid & Gander, "A provably robust algorithm for tetrahedron-tetrahedron
// intersections in floating-point arithmetic" (ACM TOMS, submitted), with the errata of
// shared/paper/ERRATA.md. Section numbers, lemmas and equations below refer to that paper.
//
// Notation (as in the paper): V is mapped to the reference tetrahedron Y, U to X. Every vertex
// x_i of X has barycentric coordinates C[i][p], p = 0..3 standing for (w, x, y, z); coordinate p
// is the barycentric coordinate of V's vertex p, and P_p = {p = 0} is the face of V opposite its
// vertex p. Signs are binary: sign(v) = 1 for v >= 0, 0 for v < 0 (Section 1); a zero is
// treated as "inside by an infinitesimal", which is what makes touching configurations
// consistent instead of special.
//
// The shape of the result is decided from signs only; a coordinate is evaluated only when a
// sign cannot be inherited, paired or forced, and a corner's coordinates only when it lies on Y.
// Every sign that two parts of the algorithm could compute separately is computed once and
// shared, which is what Theorem 6 needs: the corners then carry the labels of a simple
// polytope, and the facets follow from the labels.
//
// Implementation: the four binary signs of a point are kept as a 4-bit mask (bit p = sign of
// coordinate p), so inheritance and the sign tests of lines 8 and 18 are bit operations. Nothing
// here allocates; all arrays are sized by the worst case.
#include "tetia/tet_intersection.hpp"

#include <algorithm>
#include <bit>
#include <new>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tetia/kernel_trace.hpp"

#include "barycentric_map.hpp"  // BarycentricMap, TETIA_KERNEL_SSE2 (SSE2 or scalar loops)
#include "one_to_many.hpp"

namespace tetia {

IntersectionStats& IntersectionStats::operator+=(const IntersectionStats& o) {
  edge_inherited += o.edge_inherited;
  edge_paired += o.edge_paired;
  edge_straight_line += o.edge_straight_line;
  edge_computed += o.edge_computed;
  face_inherited += o.face_inherited;
  face_paired += o.face_paired;
  face_computed += o.face_computed;
  nonconvex_repairs += o.nonconvex_repairs;
  corner_coordinates += o.corner_coordinates;
  guardrail_clamps += o.guardrail_clamps;
  reference_swaps += o.reference_swaps;
  inconsistencies += o.inconsistencies;
  retries += o.retries;
  calls += o.calls;
  return *this;
}

namespace detail {

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

// Corner kinds, in the order of the hierarchy of Section 3.
enum : u8 { kVertexOfX = 0, kEdgeOfX = 1, kFaceOfX = 2, kVertexOfY = 3 };

// One corner as the kernel finds it: barycentric coordinates in the reference tetrahedron
// (exactly zero in the coordinates of the planes of Y it lies on) and its labels in the
// kernel's own numbering (0-3 faces of X, 4-7 planes P_0..P_3), ascending.
struct RawCorner {
  double bary[4];
  double weights[4];  // barycentric weights on X's vertices (not set for vertices of Y)
  u8 labels[3];
  u8 kind;
  u8 index;  // vertex of X, edge * 4 + plane, face * 8 + line, or vertex of Y
  // The guardrail moved the corner (clamped a coordinate): the weights on X's vertices describe
  // the point before the move and are not used (see PolyhedronBuilder::fill).
  bool moved;
};

// Everything the kernel produces; no heap. Facets are cycles over corner indices, in the
// direction of the walk (oriented later, only when a Polyhedron is built).
struct KernelResult {
  static constexpr int kMaxCorners = Polyhedron::max_corners;
  RawCorner corners[kMaxCorners];
  int num_corners = 0;
  int num_facets = 0;
  std::uint32_t on_plane[8];  // corners carrying each label, as bit masks
  u8 facet_label[8];
  u8 facet_begin[9];
  u8 facet_index[Polyhedron::max_facet_indices];
  bool contradiction = false;              // a sign relation failed (checked with statistics)
  bool corner_apex = false;                // fans from corner 0 (build_facets' kCornerApex)
  double facet_volume6[8];                // signed fan volumes (x6) of the facets as stored
  double coordinate_scale = 1.0;          // largest |coordinate| of X's vertices
  double ref_volume = 0.0;                // volume in the reference frame (Y has volume 1/6)
  double ref_first[3] = {0.0, 0.0, 0.0};  // first moments in the reference frame

  // The empty result: no corners, no facets, zero volume and moments.
  void set_empty() {
    num_corners = 0;
    num_facets = 0;
    facet_begin[0] = 0;
    ref_volume = 0.0;
    ref_first[0] = ref_first[1] = ref_first[2] = 0.0;
  }
};

namespace {

// Four coordinates of a point, held in two SSE2 registers where available (whole-vector loads
// and stores: a coordinate cleared in memory right before a vector load of the same point would
// stall the load). Every operation is the scalar one, lane by lane.
#if TETIA_KERNEL_SSE2
struct Quad {
  __m128d lo, hi;
};
// kKeepLanes[m]: all ones in the lanes not in m (m: 4-bit mask of lanes to clear).
struct KeepLanes {
  alignas(16) std::uint64_t v[16][4];
};
constexpr KeepLanes make_keep_lanes() {
  KeepLanes k{};
  for (unsigned m = 0; m < 16; ++m)
    for (int p = 0; p < 4; ++p) k.v[m][p] = bit(m, p) ? 0u : ~std::uint64_t{0};
  return k;
}
constexpr KeepLanes kKeepLanes = make_keep_lanes();
// kFlipLanes[s]: for a sign mask s, -0.0 in the lanes of the pairs (y, x) of
// order_edge_by_pairs (in the order of kLines) whose y-bit in s is 0, else +0.0.
struct FlipLanes {
  alignas(16) double v[16][6];
};
constexpr FlipLanes make_flip_lanes() {
  FlipLanes t{};
  for (unsigned m = 0; m < 16; ++m)
    for (int L = 0; L < 6; ++L) t.v[m][L] = bit(kPairLanes.y[m], L) ? 0.0 : -0.0;
  return t;
}
constexpr FlipLanes kFlipLanes = make_flip_lanes();
inline Quad zero4() { return {_mm_setzero_pd(), _mm_setzero_pd()}; }
inline Quad load4(const double* p) { return {_mm_loadu_pd(p), _mm_loadu_pd(p + 2)}; }
inline void store4(double* p, const Quad& q) {
  _mm_storeu_pd(p, q.lo);
  _mm_storeu_pd(p + 2, q.hi);
}
// s + t (o - s)
inline Quad lerp(const Quad& s, const Quad& o, double t) {
  const __m128d tt = _mm_set1_pd(t);
  return {_mm_add_pd(s.lo, _mm_mul_pd(tt, _mm_sub_pd(o.lo, s.lo))), _mm_add_pd(s.hi, _mm_mul_pd(tt, _mm_sub_pd(o.hi, s.hi)))};
}
// The lanes in m set to +0.0.
inline Quad clear_lanes(const Quad& q, unsigned m) {
  const std::uint64_t* k = kKeepLanes.v[m];
  return {_mm_and_pd(q.lo, _mm_castsi128_pd(_mm_load_si128(reinterpret_cast<const __m128i*>(k)))),
          _mm_and_pd(q.hi, _mm_castsi128_pd(_mm_load_si128(reinterpret_cast<const __m128i*>(k + 2))))};
}
// Bit p: lane p >= 0.
inline unsigned nonneg_lanes(const Quad& q) {
  const __m128d z = _mm_setzero_pd();
  return unsigned(_mm_movemask_pd(_mm_cmpge_pd(q.lo, z))) | unsigned(_mm_movemask_pd(_mm_cmpge_pd(q.hi, z))) << 2;
}
// Bit p: lane p == 0.
inline unsigned zero_lanes(const Quad& q) {
  const __m128d z = _mm_setzero_pd();
  return unsigned(_mm_movemask_pd(_mm_cmpeq_pd(q.lo, z))) | unsigned(_mm_movemask_pd(_mm_cmpeq_pd(q.hi, z))) << 2;
}
inline Quad mul4(const Quad& q, double x) {
  const __m128d xx = _mm_set1_pd(x);
  return {_mm_mul_pd(q.lo, xx), _mm_mul_pd(q.hi, xx)};
}
inline Quad div4(const Quad& q, double x) {
  const __m128d xx = _mm_set1_pd(x);
  return {_mm_div_pd(q.lo, xx), _mm_div_pd(q.hi, xx)};
}
inline Quad set4(double x) { return {_mm_set1_pd(x), _mm_set1_pd(x)}; }
#else
struct Quad {
  double v[4];
};
inline Quad zero4() { return {{0.0, 0.0, 0.0, 0.0}}; }
inline Quad load4(const double* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline void store4(double* p, const Quad& q) {
  for (int k = 0; k < 4; ++k) p[k] = q.v[k];
}
inline Quad lerp(const Quad& s, const Quad& o, double t) {
  Quad r;
  for (int k = 0; k < 4; ++k) r.v[k] = s.v[k] + t * (o.v[k] - s.v[k]);
  return r;
}
inline Quad clear_lanes(Quad q, unsigned m) {
  for (int k = 0; k < 4; ++k)
    if (bit(m, k)) q.v[k] = 0.0;
  return q;
}
inline unsigned nonneg_lanes(const Quad& q) {
  unsigned r = 0;
  for (int k = 0; k < 4; ++k) r |= unsigned(q.v[k] >= 0.0) << k;
  return r;
}
inline unsigned zero_lanes(const Quad& q) {
  unsigned r = 0;
  for (int k = 0; k < 4; ++k) r |= unsigned(q.v[k] == 0.0) << k;
  return r;
}
inline Quad mul4(Quad q, double x) {
  for (double& v : q.v) v *= x;
  return q;
}
inline Quad div4(Quad q, double x) {
  for (double& v : q.v) v /= x;
  return q;
}
inline Quad set4(double x) { return {{x, x, x, x}}; }
#endif

// The kernel state for one pair. With kWeights, each corner also gets its barycentric weights
// on X's vertices (only a full Polyhedron with U as the reference needs them). kStats: the
// statistics are kept (and contradictions looked for); without, every such test compiles away.
template <bool kWeights, bool kStats>
class Kernel {
 public:
  Kernel(const double (&C)[4][4], IntersectionStats* stats) : C_(C), stats_(kStats ? stats : nullptr) {
    for (int i = 0; i < 4; ++i) {
      unsigned m = 0, pos = 0;  // binary signs (Section 1) and strict positivity
#if TETIA_KERNEL_SSE2
      const __m128d r01 = _mm_loadu_pd(C[i]), r23 = _mm_loadu_pd(C[i] + 2), z = _mm_setzero_pd();
      m = unsigned(_mm_movemask_pd(_mm_cmpge_pd(r01, z))) | unsigned(_mm_movemask_pd(_mm_cmpge_pd(r23, z))) << 2;
      pos = unsigned(_mm_movemask_pd(_mm_cmpgt_pd(r01, z))) | unsigned(_mm_movemask_pd(_mm_cmpgt_pd(r23, z))) << 2;
      // Row i of C arranged for the pairs (y, x) of order_edge_by_pairs: the y-lanes are
      // (0,0), (0,1), (1,2) and the x-lanes (1,2), (3,2), (3,3).
      lanes_[i][0] = _mm_unpacklo_pd(r01, r01);
      lanes_[i][1] = r01;
      lanes_[i][2] = _mm_shuffle_pd(r01, r23, 1);
      lanes_[i][3] = _mm_shuffle_pd(r23, r23, 1);
      lanes_[i][4] = _mm_unpackhi_pd(r23, r23);
#else
      for (int p = 0; p < 4; ++p) {
        m |= unsigned(C[i][p] >= 0.0) << p;
        pos |= unsigned(C[i][p] > 0.0) << p;
      }
#endif
      sm_[i] = static_cast<u8>(m);
      pm_[i] = static_cast<u8>(pos);
    }
  }

  // Runs Algorithm 2; fills `out` with the corners. Returns false when the signs contradict
  // each other, which the proof of Theorem 6 excludes; such contradictions are only looked for
  // when statistics are requested (the tests always request them).
  [[gnu::always_inline]] bool run(KernelResult& out) {
    CornerList cl;
    const bool consistent = run_steps(out, cl);
    out.num_corners = cl.num_corners;
    out.num_facets = 0;
    for (int a = 0; a < 8; ++a) out.on_plane[a] = cl.on_plane[a];
    return consistent;
  }

  bool consistent() const { return consistent_; }

 private:
  // The corners' count and, per plane, the mask of the corners on it, while the corners are
  // added: a local of run() rather than members of `out`, so that the compiler can keep them
  // apart from the corners' byte-sized labels stored in between (a store through a char type
  // may alias anything reachable, a local whose address stays in run() nothing).
  struct CornerList {
    int num_corners = 0;
    std::uint32_t on_plane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  };
  // Algorithm 2 proper (see run).
  [[gnu::always_inline]] inline bool run_steps(KernelResult& out, CornerList& cl);

 public:
  void export_signs(KernelTrace& t) const;

 private:
  // --- Section 3.2: edges of X against the planes of Y -------------------------------------

  // Does edge e (from x_i to x_j) cross P_y before P_x? Decided by the sign of x_y^{ij}, the
  // x-coordinate of the crossing with P_y, eq. (2): it still has x_i's sign iff P_x comes later.
  // Only the signs of the numerator and of the denominator are needed; the numerator of
  // y_x^{ij} is exactly the negative of this one in floating point, so the pairing of Lemma 2
  // holds for computed values too.
  bool crosses_before(int i, int j, int y, int x) const {
    const double num = C_[j][x] * C_[i][y] - C_[i][x] * C_[j][y];
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
  void order_edge(int e) {
    const int i = tet_edges[e][0], j = tet_edges[e][1];
    const unsigned crossed = unsigned(sm_[i] ^ sm_[j]);
    cross_[e] = static_cast<u8>(crossed);
    if (!stats() && order_edge_by_pairs(e, i, j, crossed)) return;
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
  bool order_edge_by_pairs(int e, int i, int j, unsigned crossed) {
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

  // --- Section 3.3: faces of X against the lines of Y --------------------------------------

  // The segment (face f) ∩ P_a runs between the crossings of two edges of f with P_a; those
  // edges share the face's lone vertex in coordinate a (Proposition 1 for a triangle).
  // seg1_/seg2_ hold the sign masks at its two endpoints in nibble a, zero when there is no
  // segment. For face (u, v, w) and plane P_p the lone vertex is v when only u and v differ in
  // p-sign, w when only u and w differ, and u when both do; the endpoints are then on the
  // edges (v u, v w), (w u, w v) and (u v, u w): the same choice as kSegmentVerts, four planes
  // at a time.
  void build_segments() {
    for (int f = 0; f < 4; ++f) {
      const int u = kFaceVerts[f][0], v = kFaceVerts[f][1], w = kFaceVerts[f][2];
      const unsigned x = kNibbles[sm_[u] ^ sm_[v]], y = kNibbles[sm_[u] ^ sm_[w]];
      const unsigned uv = em_[kEdgeOf[u][v]], uw = em_[kEdgeOf[u][w]], vw = em_[kEdgeOf[v][w]];
      seg1_[f] = static_cast<std::uint16_t>((uv & x) | (uw & ~x & y));
      seg2_[f] = static_cast<std::uint16_t>((vw & (x ^ y)) | (uw & x & y));
    }
  }

  // The segment's vertices as kSegmentVerts lists them: lone vertex, then the other two.
  const u8* seg_verts(int f, int p) const {
    const int u = kFaceVerts[f][0], v = kFaceVerts[f][1], w = kFaceVerts[f][2];
    const int which = int(bit(sm_[u] ^ sm_[v], p)) | (int(bit(sm_[u] ^ sm_[w], p)) << 1);
    return kSegmentVerts[f][which];
  }
  u8 seg_m1(int f, int p) const { return static_cast<u8>((seg1_[f] >> (4 * p)) & 0xFu); }
  u8 seg_m2(int f, int p) const { return static_cast<u8>((seg2_[f] >> (4 * p)) & 0xFu); }

  // Line 18: face f meets line P_a ∩ P_b iff the endpoints of (f ∩ P_a) differ in b-sign.
  // Seen from P_b the answer must be the same (first part of the proof of Theorem 6).
  // With d = seg1_ ^ seg2_ (bit 4a + b: the endpoints in P_a differ in b-sign), line L = (a, b)
  // reads bit 4a + b from P_a and bit 4b + a from P_b.
  void face_line_flags() {
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
  bool pairing(int f, int a, int b, int c) const {
    return bit(seg_m1(f, a), c) == bit(seg_m2(f, a), b);
  }

  // 3x3 determinant of columns (c, a, b) over rows (i, j, k) of C: the numerator of eq. (5).
  double numerator5(int c, int a, int b, int i, int j, int k) const {
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
  bool direct_sign(int f, int a, int b, int c) const {
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
  void decide_face(int f) {
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
  void resolve_triple(int f, const Triple& T) {
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

  void note_inconsistency() { consistent_ = false; }
  u8 em(int e, int p) const { return static_cast<u8>((em_[e] >> (4 * p)) & 0xFu); }

  // --- corners ------------------------------------------------------------------------------

  // Appends a corner with its labels and returns it, for the caller to write its coordinates
  // (and, with kWeights, its weights) in place.
  // The count and the planes' masks are kept in `cl`, a local of run() (see there), and copied
  // to `out` when the kernel is done.
  RawCorner& add_corner(KernelResult& out, CornerList& cl, int l0, int l1, int l2, u8 kind, int index) {
    if (cl.num_corners >= KernelResult::kMaxCorners) {  // impossible for a simple polytope
      note_inconsistency();
      return overflow_;
    }
    const int c = cl.num_corners++;
    RawCorner& rc = out.corners[c];
    // Callers pass the labels ascending (faces of X first, then planes of Y, each ascending).
    rc.labels[0] = static_cast<u8>(l0);
    rc.labels[1] = static_cast<u8>(l1);
    rc.labels[2] = static_cast<u8>(l2);
    rc.kind = kind;
    rc.moved = false;
    rc.index = static_cast<u8>(index);
    const std::uint32_t b = 1u << c;
    cl.on_plane[l0] |= b;
    cl.on_plane[l1] |= b;
    cl.on_plane[l2] |= b;
    return rc;
  }

  // Guardrails (Section 4.1.1): a corner found on Y by its signs has all coordinates in [0, 1]
  // summing to 1. Computed coordinates that disagree (rounding when an edge of X lies in a
  // plane of Y) are clamped to 0 and the rest renormalized; the coordinates of the planes it
  // lies on stay exactly 0. If nothing is left, the midpoint of the admissible coordinates
  // (one choice in the spirit of Table 4).
  // nonneg: bit p set if b[p] >= 0 (nonneg_lanes of the values just stored in b).
  // Returns whether the point was moved.
  bool guardrail(double (&b)[4], unsigned zero_mask, unsigned nonneg) {
    // The usual case, nothing to clamp, without a call (and the rare one out of the way).
    if (nonneg != 0xF) [[unlikely]] {
      if (clamp_to_simplex(b, zero_mask)) {
        if (stats()) ++stats()->guardrail_clamps;
        return true;
      }
    }
    return false;
  }
  // The clamping of guardrail; returns whether a coordinate was clamped.
  [[gnu::noinline]] static bool clamp_to_simplex(double (&b)[4], unsigned zero_mask) {
    bool clamped = false;
    for (int p = 0; p < 4; ++p)
      if (!(b[p] >= 0.0)) {  // also catches NaN; the zero coordinates are exact zeros already
        b[p] = 0.0;
        clamped = true;
      }
    if (!clamped) return false;  // computed coordinates sum to 1 up to rounding: left as they are
    const double sum = b[0] + b[1] + b[2] + b[3];
    if (sum > 0.0 && sum < INFINITY) {
      const double inv = 1.0 / sum;
      for (double& x : b) x *= inv;
      return true;
    }
    const int free = 4 - std::popcount(zero_mask & 0xFu);
    for (int p = 0; p < 4; ++p) b[p] = bit(zero_mask, p) ? 0.0 : 1.0 / free;
    return true;
  }

  // The point where edge (s, o) of X meets P_p, s the vertex with p >= 0 and o the one with
  // p < 0: eq. (2) written as s + t (o - s), t = p_s / (p_s - p_o). The denominator is at least
  // |p_o| > 0 and t lies in [0, 1), so the point stays on the edge whatever the rounding; when
  // p_s is exactly 0 (a vertex on the plane, as on shared faces) it is the vertex exactly.
  // Also returns the point's barycentric weights on X's vertices in w (exact zeros off the
  // edge): they give the corner's coordinates in U when U is the caller's V (see fill()).
  Quad edge_point(int i, int j, int p, double (&w)[4]) const {
    const int s = j ^ ((i ^ j) & -int(bit(sm_[i], p))), o = i ^ j ^ s;  // without a branch
    const double t = C_[s][p] / (C_[s][p] - C_[o][p]);
    const Quad b = clear_lanes(lerp(load4(C_[s]), load4(C_[o]), t), 1u << p);
    if constexpr (kWeights) {
      w[0] = w[1] = w[2] = w[3] = 0.0;
      w[s] = 1.0 - t;
      w[o] = t;
    }
    return b;
  }

  // Coordinates of the corner where edge e meets P_p.
  void edge_corner_coords(int e, int p, RawCorner& rc) {
    const Quad q = edge_point(tet_edges[e][0], tet_edges[e][1], p, rc.weights);
    store4(rc.bary, q);
    if (stats()) stats()->corner_coordinates += 3;
    rc.moved = guardrail(rc.bary, 1u << p, nonneg_lanes(q));
  }

  // Eq. (5) for the corner where face f = (i, j, k) of X meets P_a ∩ P_b, where it is well
  // conditioned (the usual case; 98 % of the face corners of the benchmark pairs). By Cramer's
  // rule for the two conditions a = b = 0, the point is l_i x_i + l_j x_j + l_k x_k with weights
  // proportional to the 2x2 minors of columns (a, b), m_jk, m_ki and m_ij, whose sum is the
  // denominator det[1 a b] of eq. (5). It is used only when
  // - the three minors have the sign of their sum (tested by products, so that exact zeros
  //   pass): the weights are then non-negative, the point a convex combination of the face's
  //   vertices, and the sum free of cancellation;
  // - the sum is at least 2^-4 of the sum of the six products' magnitudes: each minor's
  //   rounding error is at most about 2 eps times its products, so the weights are then
  //   accurate to a few dozen ulps;
  // - the sum and the products are far from underflow and overflow: the bounds above hold,
  //   1 / sum is finite, and the sign test's products (minor times sum) cannot underflow to
  //   zero with a minor of the wrong sign unless that minor is below 2^-74 of the sum.
  // Leaves the point in res (the coordinates a and b not yet cleared) and, with kWeights, the
  // weights in w. Otherwise it returns false, and eq. (4) decides (face_corner_coords). Where a
  // face contains the line, eq. (5) is 0/0; its minors then cancel to rounding noise and fail
  // the second test.
  // The tests are combined without short-circuits: the sum's sign is data, and a branch on it
  // was mispredicted often enough to cost 5 % of intersection_volume.
  bool face_corner_by_eq5(int f, int a, int b, Quad& res, double (&w)[4]) const {
    const int i = kFaceVerts[f][0], j = kFaceVerts[f][1], k = kFaceVerts[f][2];
    const double* ci = C_[i];
    const double* cj = C_[j];
    const double* ck = C_[k];
    const double p_jk = cj[a] * ck[b], q_jk = cj[b] * ck[a];
    const double p_ki = ck[a] * ci[b], q_ki = ck[b] * ci[a];
    const double p_ij = ci[a] * cj[b], q_ij = ci[b] * cj[a];
    const double m_jk = p_jk - q_jk, m_ki = p_ki - q_ki, m_ij = p_ij - q_ij;
    const double den = (m_jk + m_ki) + m_ij;
    const double mag = ((std::abs(p_jk) + std::abs(q_jk)) + (std::abs(p_ki) + std::abs(q_ki))) +
                       (std::abs(p_ij) + std::abs(q_ij));
    const double size = std::abs(den);
    const bool same_sign = (m_jk * den >= 0.0) & (m_ki * den >= 0.0) & (m_ij * den >= 0.0);
    if (!(same_sign & (size >= 0x1p-4 * mag) & (size >= 0x1p-500) & (mag < 0x1p960))) return false;
    const double inv = 1.0 / den;
    const double li = m_jk * inv, lj = m_ki * inv, lk = m_ij * inv;
    const Quad qi = load4(ci), qj = load4(cj), qk = load4(ck);
#if TETIA_KERNEL_SSE2
    const __m128d Li = _mm_set1_pd(li), Lj = _mm_set1_pd(lj), Lk = _mm_set1_pd(lk);
    res = Quad{_mm_add_pd(_mm_add_pd(_mm_mul_pd(Li, qi.lo), _mm_mul_pd(Lj, qj.lo)), _mm_mul_pd(Lk, qk.lo)),
             _mm_add_pd(_mm_add_pd(_mm_mul_pd(Li, qi.hi), _mm_mul_pd(Lj, qj.hi)), _mm_mul_pd(Lk, qk.hi))};
#else
    for (int q = 0; q < 4; ++q) res.v[q] = (li * qi.v[q] + lj * qj.v[q]) + lk * qk.v[q];
#endif
    if constexpr (kWeights) {
      w[f] = 0.0;
      w[i] = li;
      w[j] = lj;
      w[k] = lk;
    }
    return true;
  }

  // Coordinates of the corner where face f meets P_a ∩ P_b: eq. (5) where it is well
  // conditioned (face_corner_by_eq5), else eq. (4). Eq. (5) is 0/0 when the face contains the
  // line (an edge of V lying in a face of U), and then places the point anywhere on the line,
  // outside X too. The recursive form, eq. (4), interpolates between the two ends
  // E1, E2 of the segment (f ∩ P_a) instead: whatever the rounding, the point stays on that
  // segment, that is on the face of X. Of the two segments through the point (in P_a and in
  // P_b) the one in P_a is used unless it is nearly parallel to the line; then the steeper. The point's value is computed once
  // per corner, so the choice cannot make two parts of the algorithm disagree; the decisions
  // were all taken on signs.
  void face_corner_coords(int f, int a, int b, RawCorner& rc) {
    Quad res;
    if (!face_corner_by_eq5(f, a, b, res, rc.weights)) face_corner_by_eq4(f, a, b, res, rc.weights);
    res = clear_lanes(res, (1u << a) | (1u << b));
    store4(rc.bary, res);
    if (stats()) stats()->corner_coordinates += 2;
    rc.moved = guardrail(rc.bary, (1u << a) | (1u << b), nonneg_lanes(res));
  }
  // Eq. (4) as described above: the point in res (a and b not yet cleared), the weights in w.
  void face_corner_by_eq4(int f, int a, int b, Quad& res, double (&w)[4]) const {
    res = zero4();  // set by the first view below
    if constexpr (kWeights)
      for (int q = 0; q < 4; ++q) w[q] = 0.0;
    double best = -1.0;
    for (const int view : {a, b}) {
      // A segment crossing the line at a clear angle is good enough; the second view is only
      // looked at when the first is nearly parallel to the line.
      if (best > 0x1p-10) break;
      const int cut = view == a ? b : a;  // the coordinate that vanishes along the segment
      const u8* v = seg_verts(f, view);
      const int i = v[0], j = v[1], k = v[2];
      double e[2][4], we[2][4];
      store4(e[0], edge_point(i, j, view, we[0]));
      store4(e[1], edge_point(i, k, view, we[1]));
      // Interpolate from the end with cut >= 0 to the one with cut < 0, as decided by signs.
      const int second = int(!bit(seg_m1(f, view), cut));
      const double* s = e[second];
      const double* o = e[second ^ 1];
      const double* ws = we[second];
      const double* wo = we[second ^ 1];
      const double cs = std::max(s[cut], 0.0), co = std::min(o[cut], 0.0);
      const double den = cs - co;
      if (!(den > best)) continue;
      best = den;
      const double t = den > 0.0 ? cs / den : 0.5;
      res = lerp(load4(s), load4(o), t);
      if constexpr (kWeights)
        for (int q = 0; q < 4; ++q) w[q] = ws[q] + t * (wo[q] - ws[q]);
    }
  }

  const double (&C_)[4][4];  // X's barycentric coordinates, row i = vertex x_i
#if TETIA_KERNEL_SSE2
  __m128d lanes_[4][5];
#endif
  u8 sm_[4];               // sign masks of the vertices of X
  u8 pm_[4];               // strict positivity masks (coordinate > 0)
  u8 cross_[6] = {0, 0, 0, 0, 0, 0};  // planes crossed by each edge (line 9)
  std::uint32_t edge_corners_ = 0;     // bit 4e + p: edge e ∩ P_p lies on Y
  std::uint16_t em_[6] = {};  // sign mask at edge e ∩ P_p in nibble p (read as 0 where none)
  std::uint16_t seg1_[4], seg2_[4];  // sign masks at the ends of (face f) ∩ P_p, nibble p
  u8 fexist_[4] = {0, 0, 0, 0};  // lines met by face f (bit L)
  std::uint32_t fsign_[4] = {};  // sign mask at face f ∩ line L, nibble L
  std::uint32_t undecided_[4];   // coordinates of face f ∩ line L not inherited, nibble L
  u8 fsign(int f, int L) const { return static_cast<u8>((fsign_[f] >> (4 * L)) & 0xFu); }
  bool consistent_ = true;
  IntersectionStats* stats_;  // only read through stats()
  IntersectionStats* stats() const {
    if constexpr (kStats) return stats_;
    else return nullptr;
  }
  RawCorner overflow_;  // where corners beyond kMaxCorners go (never, for a simple polytope)
};

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

  // Lines 7-17: edges of X against planes of Y; corners where all signs are 1.
  for (int e = 0; e < 6; ++e) order_edge(e);
  for (std::uint32_t rest = edge_corners_; rest; rest &= rest - 1) {
    const int bitpos = std::countr_zero(rest);
    const int e = bitpos >> 2, p = bitpos & 3;
    // Edge ij lies on the two faces of X opposite the vertices it does not contain, which are
    // the vertices of the opposite edge 5 - e.
    RawCorner& rc = add_corner(out, cl, tet_edges[5 - e][0], tet_edges[5 - e][1], 4 + p, kEdgeOfX, e * 4 + p);
    edge_corner_coords(e, p, rc);
  }

  // Line 18: faces of X against lines of Y.
  build_segments();
  face_line_flags();
  // A line of Y meets the boundary of X in zero or two points while every X ∩ P_p is convex.
  // Four would mean rounding twisted a quadrilateral (Fig. 6), which the proof of Theorem 6
  // repairs. Here each X ∩ P_p inherits its vertices' signs from totally ordered crossings
  // along the edges, which keeps it convex in the sign sense; the case is detected (and counted
  // as an inconsistency) rather than repaired, and the tests have never produced it.
  if (stats()) {
    for (int L = 0; L < 6; ++L) {
      int count = 0;
      for (int f = 0; f < 4; ++f) count += bit(fexist_[f], L);
      if (count != 0 && count != 2) {
        ++stats()->nonconvex_repairs;
        note_inconsistency();
      }
    }
  }
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

template <bool kWeights, bool kStats>
void Kernel<kWeights, kStats>::export_signs(KernelTrace& t) const {
  for (int e = 0; e < 6; ++e) {
    t.crossings[static_cast<std::size_t>(e)] = cross_[e];
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q)
        t.edge_sign[e][p][q] =
            bit(cross_[e], p) && q != p ? static_cast<std::int8_t>(bit(em(e, p), q)) : std::int8_t{-1};
  }
  const bool level2 = (sm_[0] | sm_[1] | sm_[2] | sm_[3]) == 0xF && (sm_[0] & sm_[1] & sm_[2] & sm_[3]) != 0xF;
  for (int f = 0; f < 4; ++f)
    for (int L = 0; L < 6; ++L)
      for (int c = 0; c < 4; ++c)
        t.face_sign[f][L][c] = level2 && bit(fexist_[f], L) && c != kLines[L][0] && c != kLines[L][1]
                                   ? static_cast<std::int8_t>(bit(fsign(f, L), c))
                                   : std::int8_t{-1};
}

// --- facets from labels ---------------------------------------------------------------------

// The facets of the polytope whose corners carry the labels: the corners on plane a form one
// cycle in which consecutive corners share a second label (the edge between them lies on both
// planes). With the corners of each plane as a bit mask, the neighbour of corner c across the
// pair {a, b} is the other bit of on_plane[a] & on_plane[b]. Returns false if the labels do not
// describe a closed simple polytope (each pair of planes shared by no corner or by two).
// This is the walk as stated; build_facets below follows the same cycles faster and falls
// back to it when a pair of planes is not shared by exactly two corners.
template <bool kVolume>
bool build_facets_walk(KernelResult& r) {
  const int n = r.num_corners;
  r.num_facets = 0;
  r.facet_begin[0] = 0;
  if (n == 0) return true;
  if (n < 4) return false;
  // With kVolume, each facet's fan is joined to the mean of the corners while it is walked
  // (see fan_moments for why absolute values per facet).
  double o[3] = {0.0, 0.0, 0.0}, vol6 = 0.0;
  if constexpr (kVolume) {
    for (int c = 0; c < n; ++c)
      for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
    const double inv = 1.0 / n;
    for (double& x : o) x *= inv;
  }
  int used = 0;
  for (int a = 0; a < 8; ++a) {
    const std::uint32_t here = r.on_plane[a];
    if (!here) continue;
    const int start = std::countr_zero(here);
    const u8* l = r.corners[start].labels;
    int prev_label = l[0] == a ? l[1] : l[0];
    int cur = start, prev = -1;
    std::uint32_t visited = 0;
    double fv = 0.0, ax = 0.0, ay = 0.0, az = 0.0, bx = 0.0, by = 0.0, bz = 0.0;
    do {
      const std::uint32_t cb = 1u << cur;
      if (visited & cb) return false;
      visited |= cb;
      r.facet_index[used++] = static_cast<u8>(cur);
      if constexpr (kVolume) {
        const double* p = r.corners[cur].bary;
        const double cx = p[1] - o[0], cy = p[2] - o[1], cz = p[3] - o[2];
        if (prev < 0) {
          ax = cx, ay = cy, az = cz;
        } else if (prev != start) {
          fv += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        }
        bx = cx, by = cy, bz = cz;
        prev = cur;
      }
      const u8* cl = r.corners[cur].labels;
      const int next_label = cl[0] + cl[1] + cl[2] - a - prev_label;  // labels are distinct
      const std::uint32_t pair = here & r.on_plane[next_label] & ~cb;
      if (pair == 0 || (pair & (pair - 1)) != 0) return false;  // exactly one neighbour
      prev_label = next_label;
      cur = std::countr_zero(pair);
    } while (cur != start);
    // All the plane's corners on one cycle of at least three.
    if (visited != here || r.facet_begin[r.num_facets] + 3 > used) return false;
    r.facet_label[r.num_facets] = static_cast<u8>(a);
    r.facet_begin[++r.num_facets] = static_cast<u8>(used);
    vol6 += std::abs(fv);
  }
  if constexpr (kVolume) r.ref_volume = vol6 / 6.0;
  // Euler's formula for a simple polytope: F = V/2 + 2.
  return 2 * r.num_facets == n + 4;
}

// build_facets_walk, with each corner's neighbours found once instead of at every step. Corner
// c with labels l0 < l1 < l2 has three edges; nb[k] is the other corner on the edge that does
// not lie on l_k. When every such neighbour is unique and no two corners carry the same three
// labels, each plane's corners and edges form cycles of at least three corners (two neighbours
// per corner on the plane, distinct, symmetric), so a walk cannot revisit a corner before it
// closes and needs no test for it. Otherwise the label walk above decides (and fails). On
// facet a the walk enters c from one of its two neighbours on a and leaves to the other: the
// next corner is (xor of c's two neighbours on a) xor the previous one. The first step from
// the start corner goes where the label walk goes (across the planes a and the label of start
// that is neither a nor the first other one), so the cycles and their directions are the same;
// without kCornerApex (below) so are the fan volumes, operation for operation, and with
// kMoments the walk also computes what reference_moments computes after the label walk (the
// same triangles in the same order).
enum FacetMode { kFacetsOnly, kFacetsVolume, kFacetsMoments };
template <bool kMoments>
void reference_moments(KernelResult& r);

template <FacetMode kMode>
bool facets_by_label_walk(KernelResult& r) {
  if constexpr (kMode == kFacetsMoments) {
    if (!build_facets_walk<false>(r)) return false;
    reference_moments<true>(r);
    return true;
  } else {
    return build_facets_walk<kMode == kFacetsVolume>(r);
  }
}

// build_facets' options.
// kCornerApex: the fans are joined to corner 0 instead of the mean of the corners. Corner 0 lies
// on the polytope, so every pyramid still has non-negative volume, and the three facets through
// it contribute exactly nothing: they are walked without geometry, which saves about half the
// walk. Their fan volumes are stored as 0; PolyhedronBuilder::fill orients them from a
// neighbouring facet instead (KernelResult::corner_apex tells it so). Every entry point uses it,
// so intersect(U, V).volume() and intersection_volume(U, V) stay the same number.
// kStore: the facets' corner indices, labels and fan volumes are stored (a Polyhedron reads
// them; the volume and the moments alone do not).
template <FacetMode kMode, bool kCornerApex = false, bool kStore = true>
bool build_facets(KernelResult& r) {
  constexpr bool kVolume = kMode != kFacetsOnly, kMoments = kMode == kFacetsMoments;
  static_assert(kVolume || !kCornerApex);
  static_assert(kStore || kCornerApex);
  r.corner_apex = false;
  const int n = r.num_corners;
  if (n == 0) {  // nothing found (X and Y apart): as the label walk leaves it, without the call
    r.set_empty();
    return true;
  }
  if (n < 4) return facets_by_label_walk<kMode>(r);
  u8 nb[KernelResult::kMaxCorners][2];  // nb[c][0], nb[c][1]: across the edges off l0, off l1
  u8 across[KernelResult::kMaxCorners][8];  // [c][a]: xor of c's two neighbours on facet a
  unsigned bad = 0;
  double o[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < n; ++c) {
    const u8* l = r.corners[c].labels;
    const std::uint32_t self = ~(1u << c), p0 = r.on_plane[l[0]], p1 = r.on_plane[l[1]], p2 = r.on_plane[l[2]];
    const std::uint32_t m0 = p1 & p2 & self, m1 = p0 & p2 & self, m2 = p0 & p1 & self;
    const int n0 = std::countr_zero(m0 | 0x80000000u), n1 = std::countr_zero(m1 | 0x80000000u),
              n2 = std::countr_zero(m2 | 0x80000000u);
    // Exactly one bit each (m equals its lowest bit; an empty m gets n = 31 and differs from
    // bit 31), and no other corner on all three planes.
    bad |= (m0 ^ (1u << n0)) | (m1 ^ (1u << n1)) | (m2 ^ (1u << n2)) | (m2 & p2);
    nb[c][0] = static_cast<u8>(n0);
    nb[c][1] = static_cast<u8>(n1);
    across[c][l[0]] = static_cast<u8>(n1 ^ n2);
    across[c][l[1]] = static_cast<u8>(n0 ^ n2);
    across[c][l[2]] = static_cast<u8>(n0 ^ n1);
    if constexpr (kVolume && !kCornerApex)
      for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
  }
  if (bad) return facets_by_label_walk<kMode>(r);
  if constexpr (kCornerApex) {
    for (int k = 0; k < 3; ++k) o[k] = r.corners[0].bary[k + 1];
  } else if constexpr (kVolume) {
    const double inv = 1.0 / n;
    for (double& x : o) x *= inv;
  }
  // A corner relative to the mean of the corners.
  const auto rel = [&](int c, double& x, double& y, double& z) {
    const double* p = r.corners[c].bary;
    x = p[1] - o[0], y = p[2] - o[1], z = p[3] - o[2];
  };
  r.num_facets = 0;
  r.facet_begin[0] = 0;
  double vol6 = 0.0, m[3] = {0.0, 0.0, 0.0};
  [[maybe_unused]] int used = 0;  // facet indices stored (with kStore)
  unsigned planes = 0;  // bit a: some corner lies on plane a
#if TETIA_KERNEL_SSE2
  {
    const __m128i z = _mm_setzero_si128();
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r.on_plane));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r.on_plane + 4));
    planes = ~(unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(lo, z)))) |
               unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(hi, z)))) << 4) &
             0xFFu;
  }
#else
  for (int a = 0; a < 8; ++a) planes |= unsigned(r.on_plane[a] != 0) << a;
#endif
  if constexpr (kCornerApex && !kStore) {
    // The facets through corner 0 (its three labels): no geometry, only the check that each is
    // one cycle. The three walks run side by side, from corner 0 to its neighbours on each
    // (as below); a walk that is back at corner 0 stays there. One loop instead of three: one
    // data-dependent exit, and three independent chains of loads instead of one after another.
    const u8* l = r.corners[0].labels;
    const int a0 = l[0], a1 = l[1], a2 = l[2];
    unsigned p0 = nb[0][1], p1 = nb[0][0], p2 = nb[0][0];  // the first steps, as below
    unsigned c0 = across[p0][a0], c1 = across[p1][a1], c2 = across[p2][a2];
    std::uint32_t v0 = 1u | (1u << p0), v1 = 1u | (1u << p1), v2 = v1;
    while ((c0 | c1 | c2) != 0) {
      v0 |= 1u << c0;  // bit 0 for a walk already back: set from the start
      v1 |= 1u << c1;
      v2 |= 1u << c2;
      const unsigned n0 = (across[c0][a0] ^ p0) & (0u - unsigned(c0 != 0));
      const unsigned n1 = (across[c1][a1] ^ p1) & (0u - unsigned(c1 != 0));
      const unsigned n2 = (across[c2][a2] ^ p2) & (0u - unsigned(c2 != 0));
      p0 = c0, p1 = c1, p2 = c2;
      c0 = n0, c1 = n1, c2 = n2;
    }
    if ((v0 ^ r.on_plane[a0]) | (v1 ^ r.on_plane[a1]) | (v2 ^ r.on_plane[a2])) return false;
    r.num_facets = std::popcount(planes);
    planes &= ~((1u << a0) | (1u << a1) | (1u << a2));
    r.corner_apex = true;
  } else if constexpr (kCornerApex) {
    // The same facets, stored (a Polyhedron reads them): one walk after the other, each stored
    // in its order. Corner 0 is the lowest corner on each, so it is where the walk starts.
    const u8* l = r.corners[0].labels;
    const unsigned apex_planes = (1u << l[0]) | (1u << l[1]) | (1u << l[2]);
    for (unsigned rest = apex_planes; rest; rest &= rest - 1) {
      const int a = std::countr_zero(rest);
      const int first = nb[0][l[0] == a ? 1 : 0];
      r.facet_index[used++] = 0;
      r.facet_index[used++] = static_cast<u8>(first);
      std::uint32_t visited = 1u | (1u << first);
      int prev = first, cur = across[first][a];  // across[first][a] ^ 0
      while (cur != 0) {
        visited |= 1u << cur;
        r.facet_index[used++] = static_cast<u8>(cur);
        const int next = across[cur][a] ^ prev;
        prev = cur;
        cur = next;
      }
      if (visited != r.on_plane[a]) return false;
      r.facet_volume6[r.num_facets] = 0.0;
      r.facet_label[r.num_facets] = static_cast<u8>(a);
      r.facet_begin[++r.num_facets] = static_cast<u8>(used);
    }
    planes &= ~apex_planes;
    r.corner_apex = true;
  }
  for (; planes; planes &= planes - 1) {
    const int a = std::countr_zero(planes);
    const std::uint32_t here = r.on_plane[a];
    const int start = std::countr_zero(here);
    const int first = nb[start][r.corners[start].labels[0] == a ? 1 : 0];
    if constexpr (kStore) {
      r.facet_index[used++] = static_cast<u8>(start);
      r.facet_index[used++] = static_cast<u8>(first);
    }
    std::uint32_t visited = (1u << start) | (1u << first);
    double fv = 0.0, ax = 0.0, ay = 0.0, az = 0.0, bx = 0.0, by = 0.0, bz = 0.0, fm[3] = {0.0, 0.0, 0.0};
    // For the moments: o + (start's coordinates), the same for every triangle of the fan, and
    // the previous corner's coordinates, kept in registers (the index stores are of a char
    // type and would otherwise force them to be loaded again at every step).
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, q0 = 0.0, q1 = 0.0, q2 = 0.0;
    if constexpr (kVolume) {
      rel(start, ax, ay, az);
      rel(first, bx, by, bz);
    }
    if constexpr (kMoments) {
      const double* p0 = r.corners[start].bary;
      const double* p1 = r.corners[first].bary;
      s0 = o[0] + p0[1], s1 = o[1] + p0[2], s2 = o[2] + p0[3];
      q0 = p1[1], q1 = p1[2], q2 = p1[3];
    }
    int prev = first, cur = across[first][a] ^ start;
    while (cur != start) {
      visited |= 1u << cur;
      if constexpr (kStore) r.facet_index[used++] = static_cast<u8>(cur);
      if constexpr (kVolume) {
        const double* p2 = r.corners[cur].bary;
        const double px = p2[1], py = p2[2], pz = p2[3];
        const double cx = px - o[0], cy = py - o[1], cz = pz - o[2];  // rel(cur)
        const double d = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        fv += d;
        if constexpr (kMoments) {  // d * (o + p0 + p1 + p2), in that order
          fm[0] += d * (s0 + q0 + px);
          fm[1] += d * (s1 + q1 + py);
          fm[2] += d * (s2 + q2 + pz);
          q0 = px, q1 = py, q2 = pz;
        }
        bx = cx, by = cy, bz = cz;
      }
      const int next = across[cur][a] ^ prev;
      prev = cur;
      cur = next;
    }
    // All the plane's corners on one cycle (of at least three, see above).
    if (visited != here) return false;
    if constexpr (kMoments) {  // as fan_moments
      if constexpr (kStore) r.facet_volume6[r.num_facets] = fv;
      const double sgn = 1.0 - 2.0 * double(fv < 0.0);  // fv < 0.0 ? -1.0 : 1.0, without a branch
      vol6 += sgn * fv;
      for (int c = 0; c < 3; ++c) m[c] += sgn * fm[c];
    } else {
      vol6 += std::abs(fv);
    }
    if constexpr (kStore) {
      r.facet_label[r.num_facets] = static_cast<u8>(a);
      r.facet_begin[++r.num_facets] = static_cast<u8>(used);
    }
  }
  if constexpr (kVolume) r.ref_volume = vol6 / 6.0;
  if constexpr (kMoments)
    for (int c = 0; c < 3; ++c) r.ref_first[c] = m[c] / 24.0;
  // Euler's formula for a simple polytope: F = V/2 + 2.
  return 2 * r.num_facets == n + 4;
}

// Orients the facets outward (in the reference frame) and consistently: each edge is walked in
// opposite directions by its two facets. A facet whose fan, joined to the mean of the corners,
// has a volume well above rounding is oriented by the sign of that volume (computed anyway for
// the moments). The others, the flat facets of degenerate intersections, take the orientation
// the combinatorics impose, propagated breadth first across shared edges from the oriented
// ones; with `check`, that propagation runs over every facet and verifies that geometry and
// labels agree everywhere. Returns false if they do not (never seen in the tests). dir[f] is
// -1 for the facets whose stored order must be reversed, +1 for the others.
bool orient_facet_dirs(const KernelResult& r, bool check, std::int8_t (&dir)[8]) {
  const int F = r.num_facets;
  for (auto& d : dir) d = 0;
  int queue[8], head = 0, tail = 0;
  // In the reference frame every corner lies in Y (coordinates in [0, 1]); a corner computed
  // from X's coordinates is accurate to about the unit roundoff times their magnitude, and so
  // is a fan volume. Facets 2^12 times above that are trusted.
  const double trust = 0x1p-40 * std::max(1.0, r.coordinate_scale);
  for (int f = 0; f < F; ++f) {
    const double v = r.facet_volume6[f];
    if (std::abs(v) > trust) {
      dir[f] = v > 0.0 ? 1 : -1;
      queue[tail++] = f;
    }
  }
  const bool seeded = tail > 0;
  if (tail < F || check) {
    if (!seeded) {  // a tiny or flat polytope: orient combinatorially, then by the total
      dir[0] = 1;
      queue[tail++] = 0;
    }
    // succ[c][a]: the corner after c in the facet of plane a, as stored.
    u8 succ[KernelResult::kMaxCorners][8];
    int facet_of[8];
    for (int f = 0; f < F; ++f) {
      facet_of[r.facet_label[f]] = f;
      const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
      for (int k = b; k < e; ++k) succ[r.facet_index[k]][r.facet_label[f]] = r.facet_index[k + 1 < e ? k + 1 : b];
    }
    while (head < tail) {
      const int f = queue[head++];
      const int a = r.facet_label[f];
      const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
      for (int k = b; k < e; ++k) {
        int u = r.facet_index[k], v = r.facet_index[k + 1 < e ? k + 1 : b];
        if (dir[f] < 0) std::swap(u, v);  // the edge u -> v as oriented in f
        // The neighbour across uv: the plane u and v share besides a.
        const std::uint32_t both = (1u << u) | (1u << v);
        int g_label = -1;
        for (const u8 l : r.corners[u].labels)
          if (l != a && (r.on_plane[l] & both) == both) g_label = l;
        if (g_label < 0) return false;
        const int g = facet_of[g_label];
        const std::int8_t want = succ[v][g_label] == u ? 1 : -1;  // g must walk v -> u
        if (dir[g] == 0) {
          dir[g] = want;
          queue[tail++] = g;
        } else if (dir[g] != want) {
          return false;
        }
      }
    }
    if (tail != F) return false;
    if (!seeded) {  // no facet was trusted: the sign of the whole decides
      double signed6 = 0.0;
      for (int f = 0; f < F; ++f) signed6 += dir[f] * r.facet_volume6[f];
      if (signed6 < 0.0)
        for (int f = 0; f < F; ++f) dir[f] = static_cast<std::int8_t>(-dir[f]);
    }
  }
  return true;
}

// orient_facet_dirs, applied to the stored facets.
bool orient_facets(KernelResult& r, bool check) {
  std::int8_t dir[8];
  if (!orient_facet_dirs(r, check, dir)) return false;
  for (int f = 0; f < r.num_facets; ++f)
    if (dir[f] < 0) std::reverse(r.facet_index + r.facet_begin[f], r.facet_index + r.facet_begin[f + 1]);
  return true;
}

// --- volume and moments in the reference frame --------------------------------------------

// Volume and first moments in the reference frame, where the corners' barycentric coordinates
// are the data the kernel decided. Each facet is fanned into triangles and joined to the mean
// of the corners, a point inside the polytope: every such pyramid has non-negative volume for
// a convex polytope, so its absolute value is taken and the facets' walking directions do not
// matter. Returns six times the signed volume as the facets are stored (for orientation).
template <bool kMoments>
double fan_moments(KernelResult& r, double& vol6, double (&m)[3]) {
  vol6 = 0.0;
  m[0] = m[1] = m[2] = 0.0;
  if (r.num_facets == 0) return 0.0;
  double o[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < r.num_corners; ++c)
    for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
  const double inv = 1.0 / r.num_corners;  // as in build_facets: the same rounding
  for (double& x : o) x *= inv;
  double signed6 = 0.0;
  for (int f = 0; f < r.num_facets; ++f) {
    const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
    const double* p0 = r.corners[r.facet_index[b]].bary;
    const double ax = p0[1] - o[0], ay = p0[2] - o[1], az = p0[3] - o[2];
    double fv = 0.0, fm[3] = {0.0, 0.0, 0.0};
    for (int k = b + 1; k + 1 < e; ++k) {
      const double* p1 = r.corners[r.facet_index[k]].bary;
      const double* p2 = r.corners[r.facet_index[k + 1]].bary;
      const double bx = p1[1] - o[0], by = p1[2] - o[1], bz = p1[3] - o[2];
      const double cx = p2[1] - o[0], cy = p2[2] - o[1], cz = p2[3] - o[2];
      const double d = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
      fv += d;
      if constexpr (kMoments)
        for (int c = 0; c < 3; ++c) fm[c] += d * (o[c] + p0[c + 1] + p1[c + 1] + p2[c + 1]);
    }
    signed6 += fv;
    r.facet_volume6[f] = fv;
    const double s = fv < 0.0 ? -1.0 : 1.0;
    vol6 += s * fv;
    if constexpr (kMoments)
      for (int c = 0; c < 3; ++c) m[c] += s * fm[c];
  }
  return signed6;
}

template <bool kMoments>
void reference_moments(KernelResult& r) {
  double vol6, m[3];
  fan_moments<kMoments>(r, vol6, m);
  r.ref_volume = vol6 / 6.0;
  for (int c = 0; c < 3; ++c) r.ref_first[c] = m[c] / 24.0;
}

// --- change of coordinates (Section 2) ------------------------------------------------------

// Conditioning of a tetrahedron as a reference: |det| / (sum of squared edge lengths)^(3/2),
// scale invariant, largest for the regular tetrahedron, zero when flat. The mapping to Y
// amplifies rounding by about the inverse of this ratio.
#if !TETIA_KERNEL_SSE2
Conditioning shape_quality(const Tet& t) {
  const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], e3 = t[3] - t[0];
  const Vec3 e4 = t[2] - t[1], e5 = t[3] - t[1], e6 = t[3] - t[2];
  Conditioning c;
  c.det6 = dot(e1, cross(e2, e3));
  const double s = dot(e1, e1) + dot(e2, e2) + dot(e3, e3) + dot(e4, e4) + dot(e5, e5) + dot(e6, e6);
  c.quality = std::abs(c.det6) / (s * std::sqrt(s));
  c.inv_det6 = 1.0 / c.det6;
  c.det6_sq = c.det6 * c.det6;
  c.s_cubed = s * s * s;
  return c;
}
#endif

// shape_quality of U and V at once: the same operations in the same order, U in the low lane
// and V in the high one; with 1 / det6 of each, which the barycentric map of the one chosen as
// the reference needs (the same division, done here in parallel with the quality's instead of
// after the choice).
void shape_qualities(const Tet& U, const Tet& V, Conditioning& cu, Conditioning& cv) {
#if TETIA_KERNEL_SSE2
  __m128d x[4], y[4], z[4];
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && offsetof(Vec3, y) == sizeof(double));
  for (int k = 0; k < 4; ++k) {  // (x, y) of each point as one load, then unpacked
    const __m128d u = _mm_loadu_pd(&U[k].x), v = _mm_loadu_pd(&V[k].x);
    x[k] = _mm_unpacklo_pd(u, v);
    y[k] = _mm_unpackhi_pd(u, v);
    z[k] = _mm_loadh_pd(_mm_load_sd(&U[k].z), &V[k].z);
  }
  struct V2 {
    __m128d x, y, z;
  };
  const auto sub = [&](int i, int j) {  // t[i] - t[j]
    return V2{_mm_sub_pd(x[i], x[j]), _mm_sub_pd(y[i], y[j]), _mm_sub_pd(z[i], z[j])};
  };
  const auto dot2 = [](const V2& a, const V2& b) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(a.x, b.x), _mm_mul_pd(a.y, b.y)), _mm_mul_pd(a.z, b.z));
  };
  const V2 e1 = sub(1, 0), e2 = sub(2, 0), e3 = sub(3, 0), e4 = sub(2, 1), e5 = sub(3, 1), e6 = sub(3, 2);
  const V2 c{_mm_sub_pd(_mm_mul_pd(e2.y, e3.z), _mm_mul_pd(e2.z, e3.y)),
             _mm_sub_pd(_mm_mul_pd(e2.z, e3.x), _mm_mul_pd(e2.x, e3.z)),
             _mm_sub_pd(_mm_mul_pd(e2.x, e3.y), _mm_mul_pd(e2.y, e3.x))};
  const __m128d det6 = dot2(e1, c);
  __m128d s = _mm_add_pd(dot2(e1, e1), dot2(e2, e2));
  s = _mm_add_pd(s, dot2(e3, e3));
  s = _mm_add_pd(s, dot2(e4, e4));
  s = _mm_add_pd(s, dot2(e5, e5));
  s = _mm_add_pd(s, dot2(e6, e6));
  const __m128d q = _mm_div_pd(_mm_andnot_pd(_mm_set1_pd(-0.0), det6), _mm_mul_pd(s, _mm_sqrt_pd(s)));
  const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), det6);
  const __m128d d2 = _mm_mul_pd(det6, det6), s3 = _mm_mul_pd(_mm_mul_pd(s, s), s);
  double qq[2], dd[2], ii[2], d2d[2], s3d[2];
  _mm_storeu_pd(qq, q);
  _mm_storeu_pd(dd, det6);
  _mm_storeu_pd(ii, inv);
  _mm_storeu_pd(d2d, d2);
  _mm_storeu_pd(s3d, s3);
  cu.quality = qq[0], cv.quality = qq[1], cu.det6 = dd[0], cv.det6 = dd[1], cu.inv_det6 = ii[0], cv.inv_det6 = ii[1];
  cu.det6_sq = d2d[0], cv.det6_sq = d2d[1], cu.s_cubed = s3d[0], cv.s_cubed = s3d[1];
#else
  cu = shape_quality(U);
  cv = shape_quality(V);
#endif
}

// The frame of the reference tetrahedron and X's barycentric coordinates in it.
struct Frame {
  const Tet* sub;  // U's role in the paper (mapped to X)
  const Tet* ref;  // V's role (mapped to Y)
  bool swapped;    // the caller's U is the reference
  double det6;     // det[r1 - r0, r2 - r0, r3 - r0]
  double C[4][4];
};

// make_frame once the conditioning of U and V is known; map_u: U's barycentric map if the
// caller has it (OneToMany), used when U is the reference instead of building it again (the
// same map: the same constructor on the same data).
bool frame_from(const Tet& U, const Conditioning& cu, const BarycentricMap* map_u, const Tet& V,
                const Conditioning& cv, Frame& fr, bool other_reference) {
  const double qU = cu.quality, qV = cv.quality;
  // Non-finite coordinates make a quality NaN or infinite; flat ones make it zero.
  if (!(qU > 0.0) || !(qV > 0.0) || !(qU < INFINITY) || !(qV < INFINITY)) return false;
  // With q^2 = det6^2 / s^3, qU > qV is det6U^2 sV^3 > det6V^2 sU^3: products only, so the
  // choice, and the map that waits for it, need not wait for the square roots and divisions of
  // the qualities. Where the products leave the normal range (edges beyond about 1e25 or below
  // 1e-25) the qualities themselves are compared. The two sides are swapped with U and V, so
  // (U, V) and (V, U) still choose the same reference.
  const double lhs = cu.det6_sq * cv.s_cubed, rhs = cv.det6_sq * cu.s_cubed;
  const bool products_fit = lhs >= 0x1p-1000 && rhs >= 0x1p-1000 && lhs < 0x1p1000 && rhs < 0x1p1000;
  bool use_u = products_fit ? lhs > rhs : qU > qV;
  if (products_fit ? lhs == rhs : qU == qV) {
    const double* pu = &U[0].x;
    const double* pv = &V[0].x;
    use_u = std::lexicographical_compare(pu, pu + 12, pv, pv + 12);
  }
  use_u = use_u != other_reference;
  fr.swapped = use_u;
  // Selected, not branched on: the choice is data (conditional moves, not a table on the stack,
  // whose store and load would lengthen the path to the map).
  fr.sub = use_u ? &V : &U;
  fr.ref = use_u ? &U : &V;
  fr.det6 = use_u ? cu.det6 : cv.det6;
  if (use_u && map_u) {
    for (int i = 0; i < 4; ++i) (*map_u)((*fr.sub)[i], fr.C[i]);
  } else {
    const BarycentricMap bary(*fr.ref, use_u ? cu.inv_det6 : cv.inv_det6);
    for (int i = 0; i < 4; ++i) bary((*fr.sub)[i], fr.C[i]);
  }
  // The sum of 0 * coordinate stays 0 unless a coordinate is infinite or NaN (in any order).
#if TETIA_KERNEL_SSE2
  const __m128d z = _mm_setzero_pd();
  __m128d probe = z;
  for (int i = 0; i < 4; ++i)
    probe = _mm_add_pd(probe, _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(fr.C[i]), z), _mm_mul_pd(_mm_loadu_pd(fr.C[i] + 2), z)));
  return _mm_movemask_pd(_mm_cmpeq_pd(probe, z)) == 3;
#else
  double probe = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) probe += fr.C[i][p] * 0.0;
  return probe == 0.0;
#endif
}

// Picks the reference (the better-conditioned tetrahedron; ties broken by comparing the
// coordinates, so that (U, V) and (V, U) always choose the same one) and computes X.
// Returns false for flat or non-finite input: the intersection is then empty.
bool make_frame(const Tet& U, const Tet& V, Frame& fr, bool other_reference = false) {
  Conditioning cu, cv;
  shape_qualities(U, V, cu, cv);
  return frame_from(U, cu, nullptr, V, cv, fr, other_reference);
}

// Runs the kernel on a prepared frame. Returns false if the labels do not close up into a
// simple polytope (see Kernel::run and build_facets); the result is then empty.
// kFull: the result becomes a Polyhedron (weights, and the coordinate scale orient_facets uses).
template <bool kMoments, bool kFull>
bool run_kernel(const double (&C)[4][4], KernelResult& res, IntersectionStats* stats) {
  // Kernel::run's first test (lines 2-6) ahead of the kernel: some plane of Y has no vertex of
  // X strictly on its positive side (which covers X on its negative side: C >= 0 implies
  // C > 0 fails only for zeros). The result is then empty, as run and build_facets leave it.
  unsigned positive = 0;
#if TETIA_KERNEL_SSE2
  {
    const __m128d z = _mm_setzero_pd();
    __m128d lo = _mm_cmpgt_pd(_mm_loadu_pd(C[0]), z), hi = _mm_cmpgt_pd(_mm_loadu_pd(C[0] + 2), z);
    for (int i = 1; i < 4; ++i) {
      lo = _mm_or_pd(lo, _mm_cmpgt_pd(_mm_loadu_pd(C[i]), z));
      hi = _mm_or_pd(hi, _mm_cmpgt_pd(_mm_loadu_pd(C[i] + 2), z));
    }
    positive = unsigned(_mm_movemask_pd(lo)) | unsigned(_mm_movemask_pd(hi)) << 2;
  }
#else
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) positive |= unsigned(C[i][p] > 0.0) << p;
#endif
  if (positive != 0xFu) {
    res.set_empty();
    res.contradiction = false;
    return true;
  }
  if (stats) {
    Kernel<kFull, true> k(C, stats);
    k.run(res);
    res.contradiction = !k.consistent();  // looked for only with statistics
  } else {
    Kernel<kFull, false> k(C, nullptr);
    k.run(res);
    res.contradiction = !k.consistent();
  }
  if constexpr (kFull) {  // the largest of 1 and the |coordinates| (finite here: make_frame)
#if TETIA_KERNEL_SSE2
    const __m128d sign = _mm_set1_pd(-0.0);
    __m128d m = _mm_set1_pd(1.0);
    for (int i = 0; i < 4; ++i)
      m = _mm_max_pd(m, _mm_max_pd(_mm_andnot_pd(sign, _mm_loadu_pd(C[i])), _mm_andnot_pd(sign, _mm_loadu_pd(C[i] + 2))));
    res.coordinate_scale = _mm_cvtsd_f64(_mm_max_sd(m, _mm_unpackhi_pd(m, m)));
#else
    double scale = 1.0;
    for (int i = 0; i < 4; ++i)
      for (int p = 0; p < 4; ++p) scale = std::max(scale, std::abs(C[i][p]));
    res.coordinate_scale = scale;
#endif
  }
  // Only a Polyhedron reads the facets and their fan volumes.
  const bool ok = build_facets<kMoments ? kFacetsMoments : kFacetsVolume, true, kFull>(res);
  if (!ok) {
    res.set_empty();
    return false;
  }
  return true;
}

// The kernel with its one repair: rounding in a degenerate configuration (an edge of one
// tetrahedron lying in a face of the other, say) can leave sign decisions that Theorem 6's
// relations accept but that no polytope realizes; the labels then do not close up. The other
// tetrahedron is then taken as the reference, which rounds differently and in the tests has
// always given a closed polytope. Only if that fails too is the result empty (and counted).
// make_frame(fr, other_reference) prepares the frame (see make_frame).
template <bool kMoments, bool kFull, class MakeFrame>
bool solve_with(const MakeFrame& make_frame, Frame& fr, KernelResult& res, IntersectionStats* stats) {
  if (!make_frame(fr, false)) {
    res.set_empty();
    return false;
  }
  if (stats && fr.swapped) ++stats->reference_swaps;
  bool ok = run_kernel<kMoments, kFull>(fr.C, res, stats);
  if (!ok) {
    if (stats) ++stats->retries;
    ok = make_frame(fr, true) && run_kernel<kMoments, kFull>(fr.C, res, stats);
  }
  if (stats && (!ok || res.contradiction)) ++stats->inconsistencies;
  return ok;
}

// Whether the bounding boxes of U and V are disjoint: some axis has max U < min V or
// max V < min U, compared exactly on the input. A plane x = c (or y, z) then separates the two
// strictly, and the intersection is empty: no map, no kernel. Boxes that touch are not disjoint;
// the kernel decides those. NaN compares false; non-finite input is empty either way (if no
// axis separates it here, make_frame rejects it).
bool boxes_disjoint(const Tet& U, const Tet& V) {
#if TETIA_KERNEL_SSE2
  __m128d u_lo = _mm_loadu_pd(&U[0].x), u_hi = u_lo, v_lo = _mm_loadu_pd(&V[0].x), v_hi = v_lo;  // (x, y)
  __m128d uz_lo = _mm_load_sd(&U[0].z), uz_hi = uz_lo, vz_lo = _mm_load_sd(&V[0].z), vz_hi = vz_lo;
  for (int k = 1; k < 4; ++k) {
    const __m128d u = _mm_loadu_pd(&U[k].x), v = _mm_loadu_pd(&V[k].x);
    const __m128d uz = _mm_load_sd(&U[k].z), vz = _mm_load_sd(&V[k].z);
    u_lo = _mm_min_pd(u_lo, u), u_hi = _mm_max_pd(u_hi, u), v_lo = _mm_min_pd(v_lo, v), v_hi = _mm_max_pd(v_hi, v);
    uz_lo = _mm_min_sd(uz_lo, uz), uz_hi = _mm_max_sd(uz_hi, uz);
    vz_lo = _mm_min_sd(vz_lo, vz), vz_hi = _mm_max_sd(vz_hi, vz);
  }
  const __m128d apart = _mm_or_pd(_mm_cmplt_pd(u_hi, v_lo), _mm_cmplt_pd(v_hi, u_lo));
  const __m128d apart_z = _mm_or_pd(_mm_cmplt_sd(uz_hi, vz_lo), _mm_cmplt_sd(vz_hi, uz_lo));
  return (_mm_movemask_pd(apart) | (_mm_movemask_pd(apart_z) & 1)) != 0;
#else
  bool apart = false;
  for (int axis = 0; axis < 3; ++axis) {
    const auto coord = [axis](const Vec3& p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
    double u_lo = coord(U[0]), u_hi = u_lo, v_lo = coord(V[0]), v_hi = v_lo;
    for (int k = 1; k < 4; ++k) {
      u_lo = std::min(u_lo, coord(U[k])), u_hi = std::max(u_hi, coord(U[k]));
      v_lo = std::min(v_lo, coord(V[k])), v_hi = std::max(v_hi, coord(V[k]));
    }
    apart |= u_hi < v_lo || v_hi < u_lo;
  }
  return apart;
#endif
}

// The pairwise entry points' kernel call: a quick exit for disjoint bounding boxes, then
// solve_with. Returns false when the intersection is empty for lack of a frame (see solve_with).
template <bool kMoments, bool kFull>
bool solve(const Tet& U, const Tet& V, Frame& fr, KernelResult& res, IntersectionStats* stats) {
  if (boxes_disjoint(U, V)) {
    res.set_empty();
    return false;
  }
  return solve_with<kMoments, kFull>([&](Frame& f, bool other) { return make_frame(U, V, f, other); }, fr, res,
                                     stats);
}

Moments original_moments(const Frame& fr, const KernelResult& res) {
  Moments m;
  const double scale = std::abs(fr.det6);
  m.volume = res.ref_volume * scale;
  const Tet& r = *fr.ref;
  const Vec3 a1 = r[1] - r[0], a2 = r[2] - r[0], a3 = r[3] - r[0];
  const Vec3 lin = res.ref_first[0] * a1 + res.ref_first[1] * a2 + res.ref_first[2] * a3;
  m.first = m.volume * r[0] + scale * lin;
  return m;
}

}  // namespace

Conditioning conditioning(const Tet& t) {
  Conditioning c, unused;  // both lanes compute t: lane for lane what a pair computes
  shape_qualities(t, t, c, unused);
  return c;
}

void conditioning(const Tet& a, const Tet& b, Conditioning& ca, Conditioning& cb) { shape_qualities(a, b, ca, cb); }

OneToMany::OneToMany(const Tet& s) : s_(s), cs_(conditioning(s)), map_(s, cs_.inv_det6) {}

Moments OneToMany::moments(const Tet& t, const Conditioning& ct, unsigned* t_faces) const {
  Frame fr;
  KernelResult res;
  const auto make = [&](Frame& f, bool other) { return frame_from(s_, cs_, &map_, t, ct, f, other); };
  const bool ok = solve_with<true, false>(make, fr, res, nullptr);
  if (t_faces) {
    // The faces of t on which the polytope has a facet: labels 4-7 (planes of Y) when t was the
    // reference, 0-3 (faces of X) when s was. Where int(s) crosses the interior of t's face k,
    // a small ball around the crossing lies in s and half of it in t, so s n t has a facet on
    // that face; without one, no path inside s crosses it. The labels are trusted only when the
    // sign of the reference's det6, and so of its map, is certain (kSignCertainQuality).
    *t_faces = 0xFu;
    if (ok && res.num_corners > 0 && (fr.swapped ? cs_.quality : ct.quality) > kSignCertainQuality) {
      const int base = fr.swapped ? 0 : 4;
      unsigned faces = 0;
      for (int k = 0; k < 4; ++k) faces |= unsigned(res.on_plane[base + k] != 0) << k;
      *t_faces = faces | kPlanesTested;
    }
  }
  if (!ok) return {};
  return original_moments(fr, res);
}

void trace_kernel(const double (&C)[4][4], KernelTrace& t, IntersectionStats* stats) {
  Kernel<true, true> k(C, stats);
  KernelResult res;
  const bool ran = k.run(res);
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) res.coordinate_scale = std::max(res.coordinate_scale, std::abs(C[i][p]));
  k.export_signs(t);
  t.num_corners = res.num_corners;
  for (int c = 0; c < res.num_corners; ++c)
    for (int x = 0; x < 4; ++x) {
      if (x < 3) t.labels[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].labels[x];
      t.bary[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].bary[x];
    }
  t.consistent = ran && build_facets<kFacetsOnly>(res);
  if (t.consistent) reference_moments<true>(res);
  t.consistent = t.consistent && (res.num_facets == 0 || orient_facets(res, true));
  t.num_facets = res.num_facets;
  t.volume = res.ref_volume;
}

}  // namespace detail

// Fills a Polyhedron from the kernel's result: facets oriented outward, original coordinates
// by eq. (3) (exact input vertices where a corner is one), labels and barycentric coordinates
// relative to the caller's argument order.
struct PolyhedronBuilder {
  static void clear(Polyhedron& P) {
    P.num_corners_ = P.num_facets_ = 0;
    P.touched_v_ = 0;
    P.moments_ = {};
  }

  // Facet f (through corner 0, stored from it) walks its edge (second corner, third corner)
  // opposite to the way the facet g across that edge walks it, as oriented by dir[g]; g is
  // found from the labels (the plane both corners lie on besides f's). Returns false if g is
  // not found or is itself through corner 0 (labels that do not describe a simple polytope).
  static bool orient_from_neighbour(const detail::KernelResult& res, int f, std::int8_t (&dir)[8]) {
    const int b = res.facet_begin[f];
    const int u = res.facet_index[b + 1], v = res.facet_index[b + 2];
    const unsigned a = res.facet_label[f];
    int g_label = -1;
    for (const std::uint8_t l : res.corners[u].labels)
      if (l != a && ((res.on_plane[l] >> v) & 1u)) g_label = l;
    for (int g = 3; g < res.num_facets; ++g) {
      if (res.facet_label[g] != g_label) continue;
      const int gb = res.facet_begin[g], ge = res.facet_begin[g + 1];
      for (int k = gb; k < ge; ++k) {
        if (res.facet_index[k] != u) continue;
        const bool stored_uv = res.facet_index[k + 1 < ge ? k + 1 : gb] == v;  // else v -> u
        dir[f] = static_cast<std::int8_t>(stored_uv == (dir[g] > 0) ? -1 : 1);
        return true;
      }
      return false;
    }
    return false;
  }

  static bool fill(Polyhedron& P, const detail::Frame& fr, detail::KernelResult& res, bool check) {
    using detail::RawCorner;
    std::int8_t dir[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    if (res.num_facets > 0) {
      // orient_facet_dirs' usual outcome without `check`: every facet's fan volume trusted, and
      // its sign the facet's direction. Otherwise (or with `check`) it decides.
      bool trusted = !check;
      if (trusted) {
        // With fans from corner 0, the facets through it (stored first) have no fan volume;
        // each takes the direction opposite to the facet across its edge from its second to its
        // third corner, an edge off corner 0: that facet does not contain corner 0 (two planes
        // of corner 0 meet in one edge of it), so its fan volume is there.
        const int skip = res.corner_apex ? 3 : 0;
        const double trust = 0x1p-40 * std::max(1.0, res.coordinate_scale);
        for (int f = skip; f < res.num_facets; ++f) {
          const double v = res.facet_volume6[f];
          trusted &= std::abs(v) > trust;
          dir[f] = static_cast<std::int8_t>(1 - 2 * int(!(v > 0.0)));  // v > 0.0 ? 1 : -1
        }
        for (int f = 0; f < skip && trusted; ++f) trusted = orient_from_neighbour(res, f, dir);
      }
      if (!trusted && !detail::orient_facet_dirs(res, check, dir)) return false;
    }
    // Outward in the reference frame; a negatively oriented reference maps outward to inward,
    // so the facets are then reversed once more.
    const bool flip_all = fr.det6 < 0.0;
    const Tet& r = *fr.ref;
    const Vec3 a1 = r[1] - r[0], a2 = r[2] - r[0], a3 = r[3] - r[0];
    P.num_corners_ = res.num_corners;
    const bool swapped = fr.swapped;
    const unsigned relabel = unsigned(swapped) << 2;  // (label + 4) % 8 when U was the reference
    const Tet* const sub_ref[2] = {fr.ref, fr.sub};
    const Tet& V = *sub_ref[swapped];  // the caller's V, chosen without a branch
    // V's map, built only for vertices of U inside V (in place, on first use).
    union MapStorage {
      MapStorage() {}
      detail::BarycentricMap map;
    } bary_v;
    bool have_bary_v = false;
    unsigned label_zero[8] = {0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu};  // see touched_v_ below
    for (int c = 0; c < res.num_corners; ++c) {
      const RawCorner& rc = res.corners[c];
      Corner& out = P.corners_[static_cast<std::size_t>(c)];
      // A vertex of X or Y is the input vertex itself; other corners by eq. (3). Chosen by
      // index rather than by a branch on the kind.
      const Vec3 mapped = r[0] + (rc.bary[1] * a1 + rc.bary[2] * a2 + rc.bary[3] * a3);
      const Vec3* const point[4] = {&(*fr.sub)[rc.index & 3], &mapped, &mapped, &r[rc.index & 3]};
      out.point = *point[rc.kind];
      // The labels relative to the caller's order, ascending (a sorting network).
      const auto min = [](unsigned x, unsigned y) { return y ^ ((x ^ y) & (0u - unsigned(x < y))); };
      const auto max = [](unsigned x, unsigned y) { return x ^ ((x ^ y) & (0u - unsigned(x < y))); };
      const unsigned k0 = rc.labels[0] ^ relabel, k1 = rc.labels[1] ^ relabel, k2 = rc.labels[2] ^ relabel;
      const unsigned l0 = min(min(k0, k1), k2), l2 = max(max(k0, k1), k2);
      const unsigned l1 = k0 ^ k1 ^ k2 ^ l0 ^ l2;  // the remaining one
      out.labels = {static_cast<std::uint8_t>(l0), static_cast<std::uint8_t>(l1), static_cast<std::uint8_t>(l2)};
      detail::Quad bary;  // V's barycentric coordinates of the corner
      if (!swapped) {
        // The kernel's coordinates sum to 1 up to the conditioning of the map; the reported
        // ones are scaled to sum to 1 (zeros stay exact zeros): they are P1 basis values.
        const double inv = 1.0 / (rc.bary[0] + rc.bary[1] + rc.bary[2] + rc.bary[3]);
        bary = detail::mul4(detail::load4(rc.bary), inv);
      } else {
        // The reference was U: V's coordinates come from the point itself, with the coordinates
        // of V's planes the corner lies on set to exactly zero, then clamped into the simplex
        // (the corner is on V by construction).
        // Where the guardrail moved the corner, its weights describe the point before the move
        // (in the issue that found it, a point on the line of an edge of U lying in a face of
        // V, 0.25 of V's diameter away): V's coordinates then come from the point, as for a
        // vertex of Y, so that point and coordinates describe one position.
        double b[4];
        if (rc.kind != detail::kVertexOfY && !rc.moved) {
          for (int p = 0; p < 4; ++p) b[p] = rc.weights[p];  // X is V: its weights are V's coordinates
        } else {
          if (!have_bary_v) {
            new (&bary_v.map) detail::BarycentricMap(V, 1.0 / orient3d(V[0], V[1], V[2], V[3]));
            have_bary_v = true;
          }
          bary_v.map(out.point, b);
        }
        const unsigned on_plane = ((1u << l0) | (1u << l1) | (1u << l2)) >> 4;  // labels 4 + p
        double sum = 0.0;
#if TETIA_KERNEL_SSE2
        {  // b[p] > 0 and p not a plane of the corner, else 0; as the loop below
          const __m128i off = _mm_set_epi64x(-std::int64_t((on_plane >> 1) & 1u), -std::int64_t(on_plane & 1u));
          const __m128i off2 = _mm_set_epi64x(-std::int64_t((on_plane >> 3) & 1u), -std::int64_t((on_plane >> 2) & 1u));
          const __m128d z = _mm_setzero_pd(), b01 = _mm_loadu_pd(b), b23 = _mm_loadu_pd(b + 2);
          _mm_storeu_pd(b, _mm_andnot_pd(_mm_castsi128_pd(off), _mm_and_pd(_mm_cmpgt_pd(b01, z), b01)));
          _mm_storeu_pd(b + 2, _mm_andnot_pd(_mm_castsi128_pd(off2), _mm_and_pd(_mm_cmpgt_pd(b23, z), b23)));
        }
        for (int p = 0; p < 4; ++p) sum += b[p];
#else
        for (int p = 0; p < 4; ++p) {
          b[p] = ((on_plane >> p) & 1u) || !(b[p] > 0.0) ? 0.0 : b[p];
          sum += b[p];
        }
#endif
        bary = sum > 0.0 ? detail::div4(detail::load4(b), sum) : detail::set4(0.25);
      }
      // Which of V's barycentric coordinates are exactly zero, for every plane of the corner.
      detail::store4(out.bary.data(), bary);
      const unsigned zero = detail::zero_lanes(bary);
      for (int k = 0; k < 3; ++k) label_zero[rc.labels[k]] &= zero;
    }
    P.num_facets_ = res.num_facets;
    P.touched_v_ = 0;
    if constexpr (std::endian::native == std::endian::little) {
      // facet_begin[0..num_facets] as one 64-bit word and a byte; the entries after stay 0
      static_assert(Polyhedron::max_facets == 8);
      const unsigned nf = unsigned(res.num_facets);  // at most 8
      std::uint64_t w;
      std::memcpy(&w, res.facet_begin, 8);
      w &= ~std::uint64_t(0) >> ((8 * (7 - nf)) & 63u) | (0u - std::uint64_t(nf >= 7));
      std::memcpy(P.facet_begin_.data(), &w, 8);
      P.facet_begin_[8] = static_cast<std::uint8_t>(res.facet_begin[8] & (0u - unsigned(nf == 8)));
    } else {
      for (int f = 0; f <= res.num_facets; ++f) P.facet_begin_[static_cast<std::size_t>(f)] = res.facet_begin[f];
    }
    for (int f = 0; f < res.num_facets; ++f) {
      const unsigned kernel_label = res.facet_label[f], label = kernel_label ^ relabel;
      P.facet_label_[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(label);
      // A facet of V (label 4 + k), or a facet of U lying in a plane of V: every corner has
      // that coordinate exactly zero.
      const unsigned of_v = 0u - (label >> 2);
      P.touched_v_ |= (of_v & (1u << (label & 3u))) | (~of_v & label_zero[kernel_label]);
      // Stored in walking order; reversed where orient_facet_dirs says so, and once more for a
      // negatively oriented reference.
      const bool flip = (dir[f] < 0) != flip_all;
      const int b = res.facet_begin[f], e = res.facet_begin[f + 1];
      const unsigned len = unsigned(e - b);
      if (std::endian::native == std::endian::little && len <= 8 && b + 8 <= Polyhedron::max_facet_indices) {
        // The usual case (a facet has at most seven corners): the facet's indices as one
        // 64-bit word, reversed by a byte swap. The bytes past the facet are overwritten by the
        // next facet, or lie past the last one.
        std::uint64_t x;
        std::memcpy(&x, res.facet_index + b, 8);
        const std::uint64_t reversed = __builtin_bswap64(x) >> ((8 * (8 - len)) & 63u);
        const std::uint64_t keep = std::uint64_t(flip) - 1u;  // all ones unless flipped
        x = (x & keep) | (reversed & ~keep);
        std::memcpy(P.facet_index_.data() + b, &x, 8);
      } else {
        for (int k = b; k < e; ++k)
          P.facet_index_[static_cast<std::size_t>(k)] = res.facet_index[flip ? b + e - 1 - k : k];
      }
    }
    P.moments_ = detail::original_moments(fr, res);
    return true;
  }
};

Polyhedron intersect(const Tet& U, const Tet& V, IntersectionStats* stats) {
  Polyhedron P;  // one object on every path, so that it is constructed in place (no copy)
  if (stats) ++stats->calls;
  detail::Frame fr;
  detail::KernelResult res;
  if (detail::solve<true, true>(U, V, fr, res, stats) && !PolyhedronBuilder::fill(P, fr, res, stats != nullptr)) {
    if (stats) ++stats->inconsistencies;
    PolyhedronBuilder::clear(P);
  }
  return P;
}

double intersection_volume(const Tet& U, const Tet& V) {
  detail::Frame fr;
  detail::KernelResult res;
  if (!detail::solve<false, false>(U, V, fr, res, nullptr)) return 0.0;
  return res.ref_volume * std::abs(fr.det6);
}

Moments intersection_moments(const Tet& U, const Tet& V) {
  detail::Frame fr;
  detail::KernelResult res;
  if (!detail::solve<true, false>(U, V, fr, res, nullptr)) return {};
  return detail::original_moments(fr, res);
}

}  // namespace tetia
