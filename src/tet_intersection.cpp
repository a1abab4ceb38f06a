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
#include "tetia/tet_intersection.hpp"
#include "tetia/kernel_trace.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

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
  calls += o.calls;
  return *this;
}

namespace detail {
namespace {

using u8 = std::uint8_t;

// Edge index of the vertex pair (i, j), in the order of tet_edges (Snippet 3's jmap).
constexpr int kEdgeOf[4][4] = {{-1, 0, 1, 3}, {0, -1, 2, 4}, {1, 2, -1, 5}, {3, 4, 5, -1}};
// The six lines P_p ∩ P_q of Y (edges of Y), p < q.
constexpr int kLines[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kLineOf[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
// The three vertices of face f (the face opposite vertex f), ascending.
constexpr int kFaceVerts[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

// Corner kinds, in the order of the hierarchy of Section 3.
enum : u8 { kVertexOfX = 0, kEdgeOfX = 1, kFaceOfX = 2, kVertexOfY = 3 };

}  // namespace

// One corner as the kernel finds it: barycentric coordinates in the reference tetrahedron
// (always exactly zero in the coordinates of the planes of Y it lies on) and its labels in the
// kernel's own numbering (0-3 faces of X, 4-7 planes P_0..P_3).
struct RawCorner {
  double bary[4];
  u8 labels[3];
  u8 kind;
  u8 index;  // vertex of X, edge*4 + plane, face*8 + line, or vertex of Y
};

// Everything the kernel produces; no heap. Facets are cycles over corner indices.
struct KernelResult {
  static constexpr int kMaxCorners = Polyhedron::max_corners;
  RawCorner corners[kMaxCorners];
  int num_corners = 0;
  int num_facets = 0;
  u8 facet_label[8];
  u8 facet_begin[9];
  u8 facet_index[Polyhedron::max_facet_indices];
  double ref_volume = 0.0;  // volume in the reference frame (Y has volume 1/6)
  double ref_first[3] = {0.0, 0.0, 0.0};  // first moments in the reference frame
};

namespace {

// The kernel state for one pair. Arrays are indexed [vertex][coordinate] for X, [edge][plane]
// for edge-plane intersections and [face][line] for face-line intersections.
class Kernel {
 public:
  Kernel(const double (&C)[4][4], IntersectionStats* stats) : stats_(stats) {
    for (int i = 0; i < 4; ++i)
      for (int p = 0; p < 4; ++p) {
        C_[i][p] = C[i][p];
        S_[i][p] = C[i][p] >= 0.0;  // binary sign, Section 1
      }
  }

  // Runs Algorithm 2; fills `out` with corners and facets. Returns false when the labels do
  // not close up into a polytope, which the proof of Theorem 6 excludes (counted, never seen in
  // the tests); the caller then reports an empty result rather than a wrong shape.
  bool run(KernelResult& out);

 private:
  // --- Section 3.2: edges of X against the planes of Y -------------------------------------

  // Sign of coordinate q at the intersection of edge e with plane P_p (p crossed by e, q != p).
  // Lemma 3: if e does not cross P_q the sign is inherited from the edge's vertices. Otherwise
  // it follows from the order in which the edge crosses P_p and P_q: before its crossing with
  // P_q, the point still has the q-sign of the edge's first vertex. That order is what Lemma 2
  // pairs (one computation decides sign(q_p^{ij}) and sign(p_q^{ij})) and what the straight line
  // principle of Section 3.2.1 makes transitive.
  bool edge_sign(int e, int p, int q) const {
    const int i = tet_edges[e][0], j = tet_edges[e][1];
    if (!((cross_[e] >> q) & 1)) return S_[i][q];
    return rank_[e][p] < rank_[e][q] ? S_[i][q] : S_[j][q];
  }

  // Does edge e (from x_i to x_j) cross P_y before P_x? Decided by the sign of x_y^{ij}, the
  // x-coordinate of the crossing with P_y, eq. (2): it still has x_i's sign iff P_x comes later.
  // Only the signs of the numerator and of the denominator are needed; the numerator of
  // y_x^{ij} is exactly the negative of this one in floating point, so the pairing of Lemma 2
  // holds for computed values too.
  bool crosses_before(int e, int y, int x) const {
    const int i = tet_edges[e][0], j = tet_edges[e][1];
    const double num = C_[j][x] * C_[i][y] - C_[i][x] * C_[j][y];
    const bool den_positive = S_[i][y];  // y_i >= 0 > y_j, so y_i - y_j > 0
    const bool sign_x = num == 0.0 || ((num > 0.0) == den_positive);
    return sign_x == S_[i][x];
  }

  // Lines 7-17 of Algorithm 2 for one edge: flag the planes it crosses (line 9) and order the
  // crossings. The order is found by insertion sort with a comparison computed by eq. (2): each
  // comparison is one direct calculation, its mirror sign is paired (Lemma 2), and every sign
  // the sort infers without comparing is forced by the straight line principle (3.2.1).
  void order_edge(int e) {
    const int i = tet_edges[e][0], j = tet_edges[e][1];
    int crossed[4], n = 0;
    u8 mask = 0;
    for (int p = 0; p < 4; ++p)
      if (S_[i][p] != S_[j][p]) {
        crossed[n++] = p;
        mask = static_cast<u8>(mask | (1u << p));
      }
    cross_[e] = mask;
    if (n == 0) return;
    int sorted[4], m = 0, comparisons = 0;
    for (int a = 0; a < n; ++a) {
      const int x = crossed[a];
      int pos = m;
      while (pos > 0) {
        ++comparisons;
        if (crosses_before(e, sorted[pos - 1], x)) break;
        sorted[pos] = sorted[pos - 1];
        --pos;
      }
      sorted[pos] = x;
      ++m;
    }
    for (int r = 0; r < n; ++r) rank_[e][sorted[r]] = static_cast<std::int8_t>(r);
    if (stats_) {
      stats_->edge_inherited += n * (4 - n);
      stats_->edge_computed += comparisons;
      stats_->edge_paired += comparisons;
      stats_->edge_straight_line += n * (n - 1) - 2 * comparisons;
    }
  }

  // --- Section 3.3: faces of X against the lines of Y --------------------------------------

  // The segment sigma = (face f) ∩ P_a runs between the crossings of two edges of f with P_a.
  // Those edges share the face's lone vertex in coordinate a (Proposition 1 for the face).
  struct Segment {
    std::int8_t e1 = -1, e2 = -1;  // edges (lone, j) and (lone, k)
    std::int8_t lone = -1, j = -1, k = -1;
    bool exists() const { return e1 >= 0; }
  };

  void build_segments() {
    for (int f = 0; f < 4; ++f) {
      const int a = kFaceVerts[f][0], b = kFaceVerts[f][1], c = kFaceVerts[f][2];
      for (int p = 0; p < 4; ++p) {
        Segment s;
        const bool sa = S_[a][p], sb = S_[b][p], sc = S_[c][p];
        int lone = -1, j = -1, k = -1;
        if (sa != sb && sa != sc) lone = a, j = b, k = c;
        else if (sb != sa && sb != sc) lone = b, j = a, k = c;
        else if (sc != sa && sc != sb) lone = c, j = a, k = b;
        if (lone >= 0) {
          s.lone = static_cast<std::int8_t>(lone);
          s.j = static_cast<std::int8_t>(j);
          s.k = static_cast<std::int8_t>(k);
          s.e1 = static_cast<std::int8_t>(kEdgeOf[lone][j]);
          s.e2 = static_cast<std::int8_t>(kEdgeOf[lone][k]);
        }
        seg_[f][p] = s;
      }
    }
  }

  // Face f meets line P_a ∩ P_b iff the segment (f ∩ P_a) has endpoints of different b-sign
  // (line 18 of Algorithm 2 repeating line 8 one level down). Seen from P_b instead, the answer
  // is the same by the first part of the proof of Theorem 6; both views are checked.
  bool segment_crosses(int f, int a, int b) const {
    const Segment& s = seg_[f][a];
    return s.exists() && edge_sign(s.e1, a, b) != edge_sign(s.e2, a, b);
  }

  // Inherited sign of coordinate c at F(f, {a, b}) from the parent pair in P_a, or -1.
  int inherited_from(int f, int a, int c) const {
    const Segment& s = seg_[f][a];
    const bool s1 = edge_sign(s.e1, a, c), s2 = edge_sign(s.e2, a, c);
    return s1 == s2 ? int(s1) : -1;
  }

  // Corollary 1 (with ERRATA's reading of its condition), in the plane P_a: on the segment
  // (f ∩ P_a) crossing both P_b and P_c, the c-sign at the b-crossing and the b-sign at the
  // c-crossing satisfy  sign(c_ab) ⊗ sign(b_ac) = sign(c at E1) ⊗ sign(b at E2),  the two
  // endpoints E1, E2 of the segment (Lemma 2 one dimension down). Returns the right side.
  bool pairing(int f, int a, int b, int c) const {
    const Segment& s = seg_[f][a];
    return edge_sign(s.e1, a, c) == edge_sign(s.e2, a, b);
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
  // is evaluated; the sign of the denominator det[1 a b] is not, it follows from signs already
  // decided by Lemma 5: sign det[1 b a](i,j,k) = sign det[b_i a_i; b_j a_j], and the latter is
  // sign(b_a^{ij}) ⊗ sign(a_j - a_i), both known. This keeps the new sign consistent with the
  // previous level even when the face is nearly parallel to the line.
  bool direct_sign(int f, int a, int b, int c) const {
    const Segment& s = seg_[f][a];
    const double num = numerator5(c, a, b, s.lone, s.j, s.k);
    const bool det_1ba = edge_sign(s.e1, a, b) == S_[s.j][a];
    const bool den_positive = !det_1ba;  // det[1 a b] = -det[1 b a]
    return num == 0.0 || ((num > 0.0) == den_positive);
  }

  // The coordinate slot (point F(f, {a, b}), coordinate c).
  struct Slot {
    int a, b, c;
  };

  // Signs of the coordinates of the face-line intersections, one triple at a time: for face f
  // and vertex t of Y, the three points F(f,{p,q}), F(f,{p,r}), F(f,{q,r}) around the vertex
  // P_p ∩ P_q ∩ P_r share one numerator up to sign (the "tripling" of Section 3.3, Fig. 3), so
  // their coordinates r, q, p are decided together: inherited from either parent pair where
  // possible, otherwise linked pairwise by Corollary 1, and one direct calculation (eq. 5) per
  // connected group at most.
  void decide_triple(int f, int t) {
    int pl[3], n = 0;
    for (int p = 0; p < 4; ++p)
      if (p != t) pl[n++] = p;
    const int p = pl[0], q = pl[1], r = pl[2];
    const Slot slots[3] = {{p, q, r}, {p, r, q}, {q, r, p}};
    int value[3];
    bool exists[3];
    for (int s = 0; s < 3; ++s) {
      const Slot& sl = slots[s];
      exists[s] = fl_exists_[f][kLineOf[sl.a][sl.b]];
      value[s] = -1;
      if (!exists[s]) continue;
      const int va = inherited_from(f, sl.a, sl.c);
      const int vb = inherited_from(f, sl.b, sl.c);
      if (va >= 0 && vb >= 0 && va != vb) note_inconsistency();
      value[s] = va >= 0 ? va : vb;
      if (value[s] >= 0 && stats_) ++stats_->face_inherited;
    }
    // Relations: slots 0-1 meet in P_p, 0-2 in P_q, 1-2 in P_r.
    struct Rel {
      int s1, s2, plane, b, c;
    };
    const Rel rels[3] = {{0, 1, p, q, r}, {0, 2, q, p, r}, {1, 2, r, p, q}};
    for (int round = 0; round < 3; ++round) {
      bool progress = true;
      while (progress) {
        progress = false;
        for (const Rel& rel : rels) {
          if (!exists[rel.s1] || !exists[rel.s2]) continue;
          const int k1 = value[rel.s1], k2 = value[rel.s2];
          if ((k1 >= 0) == (k2 >= 0)) continue;
          const bool xnor = pairing(f, rel.plane, rel.b, rel.c);
          const int known = k1 >= 0 ? k1 : k2;
          value[k1 >= 0 ? rel.s2 : rel.s1] = (bool(known) == xnor) ? 1 : 0;
          if (stats_) ++stats_->face_paired;
          progress = true;
        }
      }
      // One direct calculation for the first slot still undecided, then propagate again.
      int undecided = -1;
      for (int s = 0; s < 3 && undecided < 0; ++s)
        if (exists[s] && value[s] < 0) undecided = s;
      if (undecided < 0) break;
      const Slot& sl = slots[undecided];
      value[undecided] = direct_sign(f, sl.a, sl.b, sl.c) ? 1 : 0;
      if (stats_) ++stats_->face_computed;
    }
    // Every relation must now hold (Theorem 6); a violation would mean a logic error.
    for (const Rel& rel : rels)
      if (exists[rel.s1] && exists[rel.s2] &&
          ((value[rel.s1] == value[rel.s2]) != pairing(f, rel.plane, rel.b, rel.c)))
        note_inconsistency();
    for (int s = 0; s < 3; ++s)
      if (exists[s])
        fl_sign_[f][kLineOf[slots[s].a][slots[s].b]][slots[s].c] = static_cast<u8>(value[s]);
  }

  void note_inconsistency() {
    consistent_ = false;
    if (stats_) ++stats_->inconsistencies;
  }

  // --- corners ------------------------------------------------------------------------------

  bool add_corner(KernelResult& out, const double (&bary)[4], int l0, int l1, int l2, u8 kind,
                  int index) {
    if (out.num_corners >= KernelResult::kMaxCorners) {
      note_inconsistency();
      return false;
    }
    RawCorner& c = out.corners[out.num_corners++];
    for (int p = 0; p < 4; ++p) c.bary[p] = bary[p];
    int l[3] = {l0, l1, l2};
    std::sort(l, l + 3);
    c.labels[0] = static_cast<u8>(l[0]);
    c.labels[1] = static_cast<u8>(l[1]);
    c.labels[2] = static_cast<u8>(l[2]);
    c.kind = kind;
    c.index = static_cast<u8>(index);
    return true;
  }

  // Guardrails (Section 4.1.1): a corner found on Y by its signs has all coordinates in [0, 1]
  // summing to 1. Computed coordinates that disagree (rounding when an edge of X lies in a
  // plane of Y) are clamped to 0 and the rest renormalized; the coordinates of the planes it
  // lies on stay exactly 0. If nothing is left, the midpoint of the admissible coordinates.
  void guardrail(double (&b)[4], u8 zero_mask) {
    double sum = 0.0;
    bool clamped = false;
    for (int p = 0; p < 4; ++p) {
      if ((zero_mask >> p) & 1) {
        b[p] = 0.0;
        continue;
      }
      if (!(b[p] >= 0.0)) {  // also catches NaN
        b[p] = 0.0;
        clamped = true;
      }
      sum += b[p];
    }
    if (!(sum > 0.0) || !std::isfinite(sum)) {
      int free = 0;
      for (int p = 0; p < 4; ++p) free += !((zero_mask >> p) & 1);
      for (int p = 0; p < 4; ++p) b[p] = ((zero_mask >> p) & 1) ? 0.0 : 1.0 / free;
      clamped = true;
    } else if (clamped || std::abs(sum - 1.0) > 0.0) {
      for (int p = 0; p < 4; ++p) b[p] /= sum;
    }
    if (clamped && stats_) ++stats_->guardrail_clamps;
  }

  // Coordinates of the corner where edge e meets P_p, eq. (2).
  void edge_corner_coords(int e, int p, double (&b)[4]) {
    const int i = tet_edges[e][0], j = tet_edges[e][1];
    const double den = C_[i][p] - C_[j][p];
    for (int q = 0; q < 4; ++q)
      b[q] = q == p ? 0.0 : (C_[j][q] * C_[i][p] - C_[i][q] * C_[j][p]) / den;
    if (stats_) stats_->corner_coordinates += 3;
    guardrail(b, static_cast<u8>(1u << p));
  }

  // Coordinates of the corner where face f meets P_a ∩ P_b, eq. (5). The two numerators add up
  // to the denominator, so normalizing by their sum gives coordinates that sum to 1.
  void face_corner_coords(int f, int a, int b, double (&out)[4]) {
    const Segment& s = seg_[f][a];
    int rest[2], n = 0;
    for (int p = 0; p < 4; ++p)
      if (p != a && p != b) rest[n++] = p;
    const double n0 = numerator5(rest[0], a, b, s.lone, s.j, s.k);
    const double n1 = numerator5(rest[1], a, b, s.lone, s.j, s.k);
    const double den = n0 + n1;
    out[a] = out[b] = 0.0;
    out[rest[0]] = n0 / den;
    out[rest[1]] = n1 / den;
    if (stats_) stats_->corner_coordinates += 2;
    guardrail(out, static_cast<u8>((1u << a) | (1u << b)));
  }

  double C_[4][4];
  bool S_[4][4];
  u8 cross_[6] = {0, 0, 0, 0, 0, 0};
  std::int8_t rank_[6][4] = {};
  Segment seg_[4][4];
  bool fl_exists_[4][6] = {};
  u8 fl_sign_[4][6][4] = {};  // sign of coordinate c at F(f, line)
  bool consistent_ = true;
  IntersectionStats* stats_;

 public:
  bool consistent() const { return consistent_; }

  // Exports the decided signs (tests only).
  void export_signs(KernelTrace& t) const {
    for (int e = 0; e < 6; ++e) {
      t.crossings[static_cast<std::size_t>(e)] = cross_[e];
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
          t.edge_sign[e][p][q] = ((cross_[e] >> p) & 1) && q != p
                                     ? static_cast<std::int8_t>(edge_sign(e, p, q))
                                     : std::int8_t{-1};
    }
    for (int f = 0; f < 4; ++f)
      for (int L = 0; L < 6; ++L)
        for (int c = 0; c < 4; ++c)
          t.face_sign[f][L][c] = fl_exists_[f][L] && c != kLines[L][0] && c != kLines[L][1]
                                     ? static_cast<std::int8_t>(fl_sign_[f][L][c])
                                     : std::int8_t{-1};
  }
};

bool Kernel::run(KernelResult& out) {
  out.num_corners = 0;
  out.num_facets = 0;

  // Lines 2-6 (Snippet 2): an empty intersection if X lies on the negative side of a plane.
  for (int p = 0; p < 4; ++p)
    if (!S_[0][p] && !S_[1][p] && !S_[2][p] && !S_[3][p]) return true;

  // Vertices of X inside Y: all four binary signs are 1 (Section 3.1). Corner labels are the
  // three faces of X through the vertex.
  for (int i = 0; i < 4; ++i)
    if (S_[i][0] && S_[i][1] && S_[i][2] && S_[i][3]) {
      double b[4] = {C_[i][0], C_[i][1], C_[i][2], C_[i][3]};
      guardrail(b, 0);
      int l[3], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != i) l[n++] = k;
      add_corner(out, b, l[0], l[1], l[2], kVertexOfX, i);
    }

  // Lines 7-17: edges of X against planes of Y.
  for (int e = 0; e < 6; ++e) order_edge(e);
  for (int e = 0; e < 6; ++e) {
    for (int p = 0; p < 4; ++p) {
      if (!((cross_[e] >> p) & 1)) continue;
      bool on_y = true;
      for (int q = 0; q < 4 && on_y; ++q)
        if (q != p && !edge_sign(e, p, q)) on_y = false;
      if (!on_y) continue;
      double b[4];
      edge_corner_coords(e, p, b);
      // The edge lies on the two faces of X opposite the vertices it does not contain.
      const int i = tet_edges[e][0], j = tet_edges[e][1];
      int l[2], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != i && k != j) l[n++] = k;
      add_corner(out, b, l[0], l[1], 4 + p, kEdgeOfX, e * 4 + p);
    }
  }

  // Line 18: faces of X against lines of Y. Existence from both planes of each line.
  build_segments();
  for (int f = 0; f < 4; ++f)
    for (int L = 0; L < 6; ++L) {
      const int a = kLines[L][0], b = kLines[L][1];
      const bool via_a = segment_crosses(f, a, b);
      const bool via_b = segment_crosses(f, b, a);
      if (via_a != via_b) note_inconsistency();
      fl_exists_[f][L] = via_a && via_b;
    }
  // A line of Y meets the boundary of X in zero or two points when X ∩ P_p is convex. Four
  // means rounding twisted a quadrilateral (Fig. 6); the proof of Theorem 6 repairs it. Its
  // repair is not implemented: the configuration is detected and counted; tests have not
  // produced it, because the orders along each edge (above) keep every X ∩ P_p convex.
  for (int L = 0; L < 6; ++L) {
    int count = 0;
    for (int f = 0; f < 4; ++f) count += fl_exists_[f][L];
    if (count != 0 && count != 2) {
      if (stats_) ++stats_->nonconvex_repairs;
      note_inconsistency();
    }
  }
  for (int f = 0; f < 4; ++f)
    for (int t = 0; t < 4; ++t) decide_triple(f, t);

  for (int f = 0; f < 4; ++f)
    for (int L = 0; L < 6; ++L) {
      if (!fl_exists_[f][L]) continue;
      const int a = kLines[L][0], b = kLines[L][1];
      bool on_y = true;
      for (int c = 0; c < 4; ++c)
        if (c != a && c != b && !fl_sign_[f][L][c]) on_y = false;
      if (!on_y) continue;
      double bary[4];
      face_corner_coords(f, a, b, bary);
      add_corner(out, bary, f, 4 + a, 4 + b, kFaceOfX, f * 8 + L);
    }

  // Lines 19-23 (Section 3.4): vertex t of Y lies in X iff, on a line of Y through it, the two
  // intersections with faces of X have different signs in the coordinate that vanishes at t
  // and is not one of the line's. All three lines through t are consulted; they agree when the
  // previous levels are consistent (end of the proof of Theorem 6).
  for (int t = 0; t < 4; ++t) {
    int votes = 0, lines = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        if (a == t || b == t) continue;
        const int r = 6 - a - b - t;
        const int L = kLineOf[a][b];
        int s[2], n = 0;
        for (int f = 0; f < 4; ++f)
          if (fl_exists_[f][L] && n < 2) s[n++] = fl_sign_[f][L][r];
        ++lines;
        votes += (n == 2 && s[0] != s[1]);
      }
    if (votes != 0 && votes != lines) note_inconsistency();
    if (votes * 2 > lines) {
      double b[4] = {0.0, 0.0, 0.0, 0.0};
      b[t] = 1.0;
      int l[3], n = 0;
      for (int p = 0; p < 4; ++p)
        if (p != t) l[n++] = 4 + p;
      add_corner(out, b, l[0], l[1], l[2], kVertexOfY, t);
    }
  }
  return consistent_;
}

// --- facets from labels ---------------------------------------------------------------------

// Builds the facets of the polytope whose corners carry `labels`: the corners on plane a form
// one cycle in which consecutive corners share a second label (the edge between them lies on
// both planes). Orientation is propagated across shared edges (each edge is walked in
// opposite directions by its two facets) and fixed globally by the sign of the volume.
// Returns false if the labels do not describe a closed simple polytope.
bool build_facets(KernelResult& r) {
  const int n = r.num_corners;
  r.num_facets = 0;
  if (n < 4) return n == 0;
  // pair_corner[a][b]: the (at most two) corners carrying both labels a and b.
  std::int8_t pair_corner[8][8][2];
  u8 pair_count[8][8] = {};
  for (int c = 0; c < n; ++c) {
    const u8* l = r.corners[c].labels;
    const int pairs[3][2] = {{l[0], l[1]}, {l[0], l[2]}, {l[1], l[2]}};
    for (const auto& pr : pairs) {
      u8& cnt = pair_count[pr[0]][pr[1]];
      if (cnt == 2) return false;
      pair_corner[pr[0]][pr[1]][cnt] = static_cast<std::int8_t>(c);
      pair_corner[pr[1]][pr[0]][cnt] = static_cast<std::int8_t>(c);
      ++cnt;
      pair_count[pr[1]][pr[0]] = cnt;
    }
  }
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b)
      if (pair_count[a][b] == 1) return false;

  // The label two adjacent corners share besides the facet's own.
  auto other_label_pair = [](const u8* l1, const u8* l2, int a) {
    for (int x = 0; x < 3; ++x)
      if (l1[x] != a)
        for (int y = 0; y < 3; ++y)
          if (l2[y] == l1[x]) return int(l1[x]);
    return 0;
  };
  auto other_label = [&](int c, int a, int b) {
    const u8* l = r.corners[c].labels;
    for (int k = 0; k < 3; ++k)
      if (l[k] != a && l[k] != b) return int(l[k]);
    return -1;
  };

  int used = 0;
  r.facet_begin[0] = 0;
  for (int a = 0; a < 8; ++a) {
    int start = -1, on_plane = 0;
    for (int c = 0; c < n; ++c) {
      const u8* l = r.corners[c].labels;
      if (l[0] == a || l[1] == a || l[2] == a) {
        if (start < 0) start = c;
        ++on_plane;
      }
    }
    if (start < 0) continue;
    if (on_plane < 3) return false;
    // Walk: leave each corner along the label pair it was not entered by.
    const u8* l = r.corners[start].labels;
    int prev_label = l[0] == a ? l[1] : l[0];
    int cur = start, steps = 0;
    do {
      if (steps >= on_plane || used >= Polyhedron::max_facet_indices) return false;
      r.facet_index[used++] = static_cast<u8>(cur);
      ++steps;
      const int next_label = other_label(cur, a, prev_label);
      const std::int8_t* pc = pair_corner[a][next_label];
      const int next = pc[0] == cur ? pc[1] : pc[0];
      prev_label = next_label;
      cur = next;
    } while (cur != start);
    if (steps != on_plane) return false;  // the plane's corners form more than one cycle
    r.facet_label[r.num_facets] = static_cast<u8>(a);
    r.facet_begin[++r.num_facets] = static_cast<u8>(used);
  }

  // Orientation: facets are walked in arbitrary directions; make every shared edge run in
  // opposite directions in its two facets (a breadth-first pass over facets).
  const int F = r.num_facets;
  int facet_of_label[8];
  std::fill(facet_of_label, facet_of_label + 8, -1);
  for (int f = 0; f < F; ++f) facet_of_label[r.facet_label[f]] = f;
  auto follows = [&](int f, int u, int v) {  // does v follow u in facet f as stored?
    const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
    for (int k = b; k < e; ++k)
      if (r.facet_index[k] == u) return r.facet_index[k + 1 < e ? k + 1 : b] == v;
    return false;
  };
  std::int8_t dir[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int queue[8], head = 0, tail = 0;
  dir[0] = 1;
  queue[tail++] = 0;
  while (head < tail) {
    const int f = queue[head++];
    const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
    for (int k = b; k < e; ++k) {
      int u = r.facet_index[k], v = r.facet_index[k + 1 < e ? k + 1 : b];
      if (dir[f] < 0) std::swap(u, v);  // the edge u -> v as oriented in f
      // The neighbour across edge uv is the plane u and v share besides f's.
      const int g = facet_of_label[other_label_pair(r.corners[u].labels, r.corners[v].labels,
                                                    r.facet_label[f])];
      if (g < 0) return false;
      const std::int8_t want = follows(g, v, u) ? 1 : -1;  // g must walk v -> u
      if (dir[g] == 0) {
        dir[g] = want;
        queue[tail++] = g;
      } else if (dir[g] != want) {
        return false;
      }
    }
  }
  if (tail != F) return false;  // not connected
  for (int f = 0; f < F; ++f)
    if (dir[f] < 0) std::reverse(r.facet_index + r.facet_begin[f], r.facet_index + r.facet_begin[f + 1]);
  return true;
}

}  // namespace

// --- volume and moments in the reference frame --------------------------------------------

// Volume and first moments of the polytope, in the reference frame where the corners'
// barycentric coordinates are exact: a fan of tetrahedra from corner 0 over every facet that
// does not contain it. Facet orientation is fixed here globally: if the signed volume comes out
// negative, every facet is reversed.
void reference_moments(KernelResult& r) {
  r.ref_volume = 0.0;
  r.ref_first[0] = r.ref_first[1] = r.ref_first[2] = 0.0;
  if (r.num_facets == 0) return;
  const double* o = r.corners[0].bary;  // (w, x, y, z); x, y, z are the reference coordinates
  double vol6 = 0.0, m[3] = {0.0, 0.0, 0.0};
  for (int f = 0; f < r.num_facets; ++f) {
    const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
    bool has_apex = false;
    for (int k = b; k < e; ++k) has_apex |= r.facet_index[k] == 0;
    if (has_apex) continue;
    const double* p0 = r.corners[r.facet_index[b]].bary;
    for (int k = b + 1; k + 1 < e; ++k) {
      const double* p1 = r.corners[r.facet_index[k]].bary;
      const double* p2 = r.corners[r.facet_index[k + 1]].bary;
      const double ax = p0[1] - o[1], ay = p0[2] - o[2], az = p0[3] - o[3];
      const double bx = p1[1] - o[1], by = p1[2] - o[2], bz = p1[3] - o[3];
      const double cx = p2[1] - o[1], cy = p2[2] - o[2], cz = p2[3] - o[3];
      const double d = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
      vol6 += d;
      for (int c = 1; c <= 3; ++c) m[c - 1] += d * (o[c] + p0[c] + p1[c] + p2[c]);
    }
  }
  if (vol6 < 0.0) {
    vol6 = -vol6;
    for (double& x : m) x = -x;
    for (int f = 0; f < r.num_facets; ++f)
      std::reverse(r.facet_index + r.facet_begin[f], r.facet_index + r.facet_begin[f + 1]);
  }
  r.ref_volume = vol6 / 6.0;
  for (int c = 0; c < 3; ++c) r.ref_first[c] = m[c] / 24.0;
}

// --- change of coordinates (Section 2) ------------------------------------------------------

// Conditioning of a tetrahedron as a reference: |det| / (sum of squared edge lengths)^(3/2),
// scale invariant, largest for the regular tetrahedron, zero when flat. The mapping to Y
// amplifies rounding by about the inverse of this ratio.
double shape_quality(const Tet& t, double& det6) {
  det6 = orient3d(t[0], t[1], t[2], t[3]);
  double s = 0.0;
  for (const auto& e : tet_edges) {
    const Vec3 d = t[e[1]] - t[e[0]];
    s += dot(d, d);
  }
  return std::abs(det6) / (s * std::sqrt(s));
}

// The frame of the reference tetrahedron and X's barycentric coordinates in it.
struct Frame {
  const Tet* sub;  // U's role in the paper (mapped to X)
  const Tet* ref;  // V's role (mapped to Y)
  bool swapped;    // the caller's U is the reference
  double det6;     // det[r1 - r0, r2 - r0, r3 - r0]
  double C[4][4];
};

// Barycentric coordinates of point u in tetrahedron r with orientation determinant det6, eq. (1)
// solved by Cramer's rule on the differences d_k = r_k - u. Forming the differences from u
// translates to the point first (Section 2), and when u coincides with a vertex of r the
// difference is an exact zero vector, so the coordinates of the faces through that vertex come
// out exactly 0: shared vertices, faces and identical tetrahedra are then exact, not rounded.
inline void barycentric(const Tet& r, double inv_det6, Vec3 u, double (&out)[4]) {
  const Vec3 d0 = r[0] - u, d1 = r[1] - u, d2 = r[2] - u, d3 = r[3] - u;
  const Vec3 a = cross(d2, d3), b = cross(d0, d1);
  out[0] = dot(d1, a) * inv_det6;
  out[1] = -dot(d0, a) * inv_det6;
  out[2] = dot(d3, b) * inv_det6;
  out[3] = -dot(d2, b) * inv_det6;
}

bool all_finite(const Tet& t) {
  for (const Vec3& v : t)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
  return true;
}

// Picks the reference (the better-conditioned tetrahedron; ties broken by comparing the
// coordinates, so that (U, V) and (V, U) always choose the same one) and computes X.
// Returns false for flat or non-finite input: the intersection is then empty.
bool make_frame(const Tet& U, const Tet& V, Frame& fr) {
  if (!all_finite(U) || !all_finite(V)) return false;
  double detU = 0.0, detV = 0.0;
  const double qU = shape_quality(U, detU), qV = shape_quality(V, detV);
  if (!(detU != 0.0) || !(detV != 0.0) || !std::isfinite(qU) || !std::isfinite(qV)) return false;
  bool use_u = qU > qV;
  if (qU == qV) {
    const double* pu = &U[0].x;
    const double* pv = &V[0].x;
    use_u = std::lexicographical_compare(pu, pu + 12, pv, pv + 12);
  }
  fr.swapped = use_u;
  fr.sub = use_u ? &V : &U;
  fr.ref = use_u ? &U : &V;
  fr.det6 = use_u ? detU : detV;
  const double inv = 1.0 / fr.det6;
  for (int i = 0; i < 4; ++i) barycentric(*fr.ref, inv, (*fr.sub)[i], fr.C[i]);
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p)
      if (!std::isfinite(fr.C[i][p])) return false;
  return true;
}

// Runs the kernel on a prepared frame. On an inconsistency (never observed; see Kernel::run)
// the result is empty.
bool run_kernel(const Frame& fr, KernelResult& res, IntersectionStats* stats) {
  Kernel k(fr.C, stats);
  if (!k.run(res) || !build_facets(res)) {
    if (stats && k.consistent()) ++stats->inconsistencies;
    res.num_corners = 0;
    res.num_facets = 0;
    return false;
  }
  reference_moments(res);
  return true;
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

void trace_kernel(const double (&C)[4][4], KernelTrace& t, IntersectionStats* stats) {
  Kernel k(C, stats);
  KernelResult res;
  const bool ran = k.run(res);
  k.export_signs(t);
  t.num_corners = res.num_corners;
  for (int c = 0; c < res.num_corners; ++c)
    for (int x = 0; x < 4; ++x) {
      if (x < 3) t.labels[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].labels[x];
      t.bary[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].bary[x];
    }
  t.consistent = ran && build_facets(res);
  if (t.consistent) reference_moments(res);
  t.num_facets = res.num_facets;
  t.volume = res.ref_volume;
}

}  // namespace detail

// Fills a Polyhedron from the kernel's result: original coordinates by eq. (3) (exact vertices
// where a corner is one), labels and barycentric coordinates relative to the caller's order.
struct PolyhedronBuilder {
  static void fill(Polyhedron& P, const detail::Frame& fr, const detail::KernelResult& res) {
    using detail::RawCorner;
    const Tet& r = *fr.ref;
    const Vec3 a1 = r[1] - r[0], a2 = r[2] - r[0], a3 = r[3] - r[0];
    P.num_corners_ = res.num_corners;
    const Tet& V = fr.swapped ? *fr.sub : *fr.ref;
    const double invV = fr.swapped ? 1.0 / orient3d(V[0], V[1], V[2], V[3]) : 0.0;
    for (int c = 0; c < res.num_corners; ++c) {
      const RawCorner& rc = res.corners[c];
      Corner& out = P.corners_[static_cast<std::size_t>(c)];
      if (rc.kind == 0) out.point = (*fr.sub)[rc.index];
      else if (rc.kind == 3) out.point = r[rc.index];
      else out.point = r[0] + (rc.bary[1] * a1 + rc.bary[2] * a2 + rc.bary[3] * a3);
      int labels[3];
      for (int k = 0; k < 3; ++k) labels[k] = fr.swapped ? (rc.labels[k] + 4) % 8 : rc.labels[k];
      std::sort(labels, labels + 3);
      for (int k = 0; k < 3; ++k) out.labels[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(labels[k]);
      if (!fr.swapped) {
        for (int p = 0; p < 4; ++p) out.bary[static_cast<std::size_t>(p)] = rc.bary[p];
      } else {
        // The reference was U: V's coordinates come from the point itself, with the
        // coordinates of V's planes the corner lies on set to exactly zero, then clamped into
        // the simplex (the corner is on V by construction).
        double b[4];
        if (rc.kind == 0) {
          for (int p = 0; p < 4; ++p) b[p] = p == rc.index ? 1.0 : 0.0;
        } else {
          detail::barycentric(V, invV, out.point, b);
        }
        double sum = 0.0;
        for (int p = 0; p < 4; ++p) {
          bool on_plane = false;
          for (int k = 0; k < 3; ++k) on_plane |= labels[k] == 4 + p;
          if (on_plane || !(b[p] > 0.0)) b[p] = 0.0;
          sum += b[p];
        }
        for (int p = 0; p < 4; ++p) out.bary[static_cast<std::size_t>(p)] = sum > 0.0 ? b[p] / sum : 0.25;
      }
    }
    P.num_facets_ = res.num_facets;
    P.touched_v_ = 0;
    for (int f = 0; f <= res.num_facets; ++f) P.facet_begin_[static_cast<std::size_t>(f)] = res.facet_begin[f];
    for (int k = 0; k < res.facet_begin[res.num_facets]; ++k)
      P.facet_index_[static_cast<std::size_t>(k)] = res.facet_index[k];
    // Facets are outward in the reference frame; a negatively oriented reference maps them
    // inward in the original coordinates.
    if (fr.det6 < 0.0)
      for (int f = 0; f < res.num_facets; ++f)
        std::reverse(P.facet_index_.begin() + res.facet_begin[f], P.facet_index_.begin() + res.facet_begin[f + 1]);
    for (int f = 0; f < res.num_facets; ++f) {
      const int label = fr.swapped ? (res.facet_label[f] + 4) % 8 : res.facet_label[f];
      P.facet_label_[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(label);
      if (label >= 4) {
        P.touched_v_ |= 1u << (label - 4);
        continue;
      }
      // A facet of U lying in a plane of V: every corner has that coordinate exactly zero.
      for (int p = 0; p < 4; ++p) {
        bool all_zero = true;
        for (int k = res.facet_begin[f]; k < res.facet_begin[f + 1]; ++k)
          all_zero &= P.corners_[res.facet_index[k]].bary[static_cast<std::size_t>(p)] == 0.0;
        if (all_zero) P.touched_v_ |= 1u << p;
      }
    }
    P.moments_ = detail::original_moments(fr, res);
  }
};

Polyhedron intersect(const Tet& U, const Tet& V, IntersectionStats* stats) {
  Polyhedron P;
  if (stats) ++stats->calls;
  detail::Frame fr;
  if (!detail::make_frame(U, V, fr)) return P;
  if (stats && fr.swapped) ++stats->reference_swaps;
  detail::KernelResult res;
  if (!detail::run_kernel(fr, res, stats)) return P;
  PolyhedronBuilder::fill(P, fr, res);
  return P;
}

double intersection_volume(const Tet& U, const Tet& V) {
  detail::Frame fr;
  if (!detail::make_frame(U, V, fr)) return 0.0;
  detail::KernelResult res;
  if (!detail::run_kernel(fr, res, nullptr)) return 0.0;
  return res.ref_volume * std::abs(fr.det6);
}

Moments intersection_moments(const Tet& U, const Tet& V) {
  detail::Frame fr;
  if (!detail::make_frame(U, V, fr)) return {};
  detail::KernelResult res;
  if (!detail::run_kernel(fr, res, nullptr)) return {};
  return detail::original_moments(fr, res);
}

}  // namespace tetia
