// src/kernel/tri_kernel.hpp -- the 2D kernel, compiled once for each instruction set the
// library dispatches to (src/kernel/kernel_variant.hpp): included by src/tri_intersection.cpp
// (the baseline) and by src/kernel/tri_intersection_x86_64_v3.cpp, each with
// TETIA_KERNEL_VARIANT naming the namespace its entry points go into. As for the 3D kernel
// (src/kernel/entry_points.hpp): the same bits from every variant, and every function defined
// here internal (anonymous namespace), templated on the variant (PolygonBuilder) or in the
// variant's namespace.
//
// Algorithm 1 (PANG2) of McCoid & Gander, "A provably robust algorithm for triangle-triangle
// intersections in floating-point arithmetic" (ACM TOMS 48, 2022), in the form it is summarized
// as Algorithm 1 of their tetrahedron paper (shared/paper), and built like the 3D kernel in
// src/kernel/. Line numbers below are those of Algorithm 1.
//
// Notation: B (the reference, the paper's V) is mapped to the reference triangle Y with vertices
// (0, 0), (1, 0), (0, 1); A (the paper's U) to X by the same affine map. Every point has
// barycentric coordinates (w, x, y), coordinate p being that of Y's vertex p, and
// P_p = {p = 0} is the line of Y opposite its vertex p. Signs are binary (sign(v) = 1 for
// v >= 0, 0 for v < 0): a zero is "inside by an infinitesimal", which makes touching
// configurations consistent instead of special.
//
// The shape of the result is decided from signs only. An edge of X that crosses two or three
// lines of Y decides every sign of its crossings from the order of the crossings along the edge:
// one direct calculation (line 9, eq. (2) of the 3D paper) orders two crossings and so decides
// the pair of signs of line 10; a third crossing is placed by the straight line principle when
// the two comparisons already made force it. The vertices of Y inside X (lines 11-13) then
// follow from those signs, and the polygon's corners are ordered counter-clockwise by their
// labels alone: each corner knows which of the six lines the boundary arrives on and leaves by.
// Coordinates are evaluated only for corners that lie on Y. Nothing here allocates.
#pragma once

#ifndef TETIA_KERNEL_VARIANT
#error "define TETIA_KERNEL_VARIANT (the variant's namespace) before including tri_kernel.hpp"
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "exact_fallback.hpp"
#include "exact_sign.hpp"
#include "rescale.hpp"  // scaled_exactly
#include "tri_certified_moments.hpp"
#include "tri_clip_check.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia {

namespace detail2 {
namespace {

using u8 = std::uint8_t;

constexpr bool bit(unsigned mask, int k) { return (mask >> k) & 1u; }

// Corner kinds, in the order of Algorithm 1.
enum : u8 { kVertexOfX = 0, kEdgeOfX = 1, kVertexOfY = 2 };

// One corner as the kernel finds it. Labels in the kernel's numbering: 0-2 edges of X (edge k
// is opposite X's vertex k), 3-5 the lines P_0..P_2 of Y. `in` is the line the counter-clockwise
// boundary of the intersection (in the frame of Y) arrives on, `out` the line it leaves by.
struct RawCorner {
  double bary[3];     // coordinates in Y; exactly 0 on the lines of Y the corner lies on
  double weight_b;    // for a crossing: the weight of the edge's second end (first: 1 - weight_b)
  u8 kind;
  u8 index;           // vertex of X, edge * 3 + line, or vertex of Y
  u8 in, out;
};

struct KernelResult {
  static constexpr int kMaxCorners = Polygon::max_corners;
  RawCorner corners[kMaxCorners];
  int num_corners = 0;
  u8 order[kMaxCorners];  // the corners counter-clockwise in the frame of Y
  bool contradiction = false;
  bool sub_frame = false;            // area and moments in the frame of X, not of Y
  double frame_det = 0.0;            // that frame's determinant
  double ref_area = 0.0;             // area in that frame (its triangle has area 1/2)
  double ref_first[2] = {0.0, 0.0};  // first moments in that frame
};

// The endpoints of edge e of a triangle (the edge opposite vertex e), in the cyclic order
// e + 1 -> e + 2, which is counter-clockwise for a counter-clockwise triangle.
constexpr int kEdgeFrom[3] = {1, 2, 0};
constexpr int kEdgeTo[3] = {2, 0, 1};

double orient2d_accurate(Vec2 a, Vec2 b, Vec2 c);

// What the kernel needs besides X's coordinates to decide a sign the coordinates cannot: the
// two triangles (X = sub, Y = ref, in the frame's scaled, canonical order), whether the signs
// need care (`careful`: some |coordinate| above 2^8, X's vertices far from Y for Y's size; or
// sizes more than 2^10 apart), a bound on every coordinate's error, and the sign of Y's
// determinant.
struct SignGeometry {
  const Triangle* sub;
  const Triangle* ref;
  bool careful;
  double c_error;
  double c_max;
  bool ref_positive;
};

// decide_edge_by_pairs' signs from the signs of the edge's ends (si, sj: bit p the sign of
// coordinate p) and the three comparisons (bit k of `pairs`: crosses_before for the k-th pair
// (1, 0), (2, 0), (2, 1), whose result counts only where both lines are crossed). cm[p]: the
// signs at the crossing with P_p. Returns whether the ranks along the edge are distinct.
constexpr bool edge_signs_from_pairs(unsigned si, unsigned sj, unsigned pairs, u8 (&cm)[3]) {
  const unsigned crossed = (si ^ sj) & 7u;
  unsigned before[3] = {0, 0, 0};  // before[p] bit q: P_p is crossed before P_q
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const int y = kPairs[k][0], x = kPairs[k][1];
    const unsigned both = unsigned(bit(crossed, x)) & unsigned(bit(crossed, y));
    const unsigned xy = unsigned(bit(pairs, k)) & both;
    before[x] |= xy << y;
    before[y] |= ((xy ^ 1u) & both) << x;
  }
  constexpr u8 kCount[8] = {0, 1, 1, 2, 1, 2, 2, 3};
  unsigned ranks = 0;
  for (int p = 0; p < 3; ++p) {
    const unsigned earlier = crossed & ~before[p] & ~(1u << p);  // crossed before P_p
    ranks |= unsigned(bit(crossed, p)) << kCount[earlier];
    // At the crossing with P_p: lines crossed earlier have x_j's sign, the others x_i's.
    cm[p] = static_cast<u8>(((si & ~earlier) | (sj & earlier) | (1u << p)) & 7u);
  }
  return ranks == (1u << kCount[crossed]) - 1u;
}

// edge_signs_from_pairs for every si | sj << 3 | pairs << 6: cm[0] | cm[1] << 3 | cm[2] << 6,
// and bit 9 its result.
struct EdgeTable {
  std::uint16_t entry[512];
  constexpr EdgeTable() : entry() {
    for (unsigned k = 0; k < 512; ++k) {
      u8 cm[3] = {0, 0, 0};
      const bool ok = edge_signs_from_pairs(k & 7u, k >> 3 & 7u, k >> 6, cm);
      entry[k] = static_cast<std::uint16_t>(cm[0] | cm[1] << 3 | cm[2] << 6 | unsigned(ok) << 9);
    }
  }
  constexpr unsigned operator[](unsigned k) const { return entry[k]; }
};
constexpr EdgeTable kEdgeTable;

class Kernel {
 public:
  // C: X's barycentric coordinates in Y; x_ccw: whether X's vertices 0, 1, 2 run
  // counter-clockwise in the frame of Y (the map preserves orientation iff det A and det B have
  // the same sign).
  Kernel(const double (&C)[3][3], bool x_ccw, const SignGeometry& geo, TriIntersectionStats* stats)
      : C_(C), x_ccw_(x_ccw), geo_(geo), stats_(stats) {
    for (int i = 0; i < 3; ++i) {
      unsigned m = 0;
      for (int p = 0; p < 3; ++p) m |= unsigned(C[i][p] >= 0.0) << p;  // binary sign
      sm_[i] = static_cast<u8>(m);
    }
  }

  // Runs Algorithm 1 and orders the corners. Returns false if the labels do not close into one
  // cycle (which the consistency of the signs excludes; checked, never seen in the tests).
  bool run(KernelResult& out);

 private:
  // Does the edge from x_i to x_j cross P_y before P_x? One direct calculation (line 9): the
  // sign of the x-coordinate of the crossing with P_y, x_y^{ij} = (y_i x_j - y_j x_i) /
  // (y_i - y_j), eq. (2) of the 3D paper. The crossing still has x_i's x-sign iff P_x comes
  // later. The numerator of y_x^{ij} is exactly the negative of this one in floating point,
  // so the pairing of line 10 holds for the computed values too.
  //
  // The sign of the computed numerator may be wrong where it is within its error bound, by the
  // coordinates' errors and the products' rounding. Where X's coordinates are moderate (at most
  // 2^8) and the sizes comparable (the usual case, nothing is tested) that amounts to moving a
  // vertex of X by about eps times Y's size, a perturbation the result's accuracy does not
  // notice; the signs are then consistent (decided once, inherited), which is what Theorem 6
  // needs. Where they are large (`careful`: X much bigger than Y, so that the same error is eps
  // times X's size), or X far smaller than Y (`careful` too: eps times Y's size is then much of
  // X, near a vertex of Y where two coordinates are small), a
  // numerator within its bound, 4 c_error c_max + 2^-51 (|a| + |b|), takes its sign from the
  // input instead: with lambda_y, lambda_x affine and both zero at Y's vertex r, the numerator is
  // lambda_y(x_i) lambda_x(x_j) - lambda_y(x_j) lambda_x(x_i) = K orient2d(u_i, u_j, y_r), the
  // constant K fixed by x_i = y_x, x_j = y_y: K = -1 / orient2d(y_x, y_y, y_r), where
  // orient2d(y_x, y_y, y_r) is det2 for an even permutation (x, y, r) of (0, 1, 2) and -det2
  // for an odd one. orient2d_accurate(u_i, u_j, y_r) gets it right where X is far bigger than
  // Y, the coordinates huge and their products cancelling (Y 1e-16 of X, say).
  [[gnu::always_inline]] bool crosses_before(int i, int j, int y, int x) const {
    const double a = C_[j][x] * C_[i][y], b = C_[i][x] * C_[j][y];
    double num = a - b;
    if (geo_.careful) [[unlikely]] {
      if (!(std::abs(num) > 4.0 * geo_.c_error * geo_.c_max + 0x1p-51 * (std::abs(a) + std::abs(b))))
        num = numerator_from_input(i, j, y, x);
    }
    const bool den_positive = bit(sm_[i], y);  // y_i >= 0 > y_j
    const bool sign_x = num == 0.0 || ((num > 0.0) == den_positive);
    return sign_x == bit(sm_[i], x);
  }
  // The numerator's sign as K orient2d(u_i, u_j, y_r) (see crosses_before), out of the way.
  [[gnu::noinline]] double numerator_from_input(int i, int j, int y, int x) const {
    const int r = 3 - x - y;
    const bool even = (x + 1) % 3 == y;  // (x, y, r) a cyclic shift of (0, 1, 2)
    const double o = orient2d_accurate((*geo_.sub)[i], (*geo_.sub)[j], (*geo_.ref)[r]);
    if (stats_) ++stats_->refined;
    return (even == geo_.ref_positive) ? -o : o;
  }

  // Lines 7-10 for edge e: the lines it crosses are those whose signs differ at its ends
  // (line 8). A coordinate the edge does not cross keeps the sign its ends share (inherited).
  // Among the crossed lines, signs follow from the order of the crossings along the edge: before
  // its crossing with P_q a point has x_i's q-sign, after it x_j's. The order comes from an
  // insertion sort whose comparisons are direct calculations; each decides a pair of signs
  // (line 10), and an order the sort infers without comparing is the straight line principle.
  void decide_edge(int e) {
    const int i = kEdgeFrom[e], j = kEdgeTo[e];
    const unsigned crossed = (sm_[i] ^ sm_[j]) & 7u;
    int ord[3], n = 0, computed = 0;
    for (int p = 0; p < 3; ++p) {
      if (!bit(crossed, p)) continue;
      int pos = n;
      // Compare with the later crossings first; once p is found after one, it is after all
      // the earlier ones too (straight line principle, no calculation).
      while (pos > 0) {
        ++computed;
        if (!crosses_before(i, j, p, ord[pos - 1])) break;
        --pos;
      }
      for (int k = n; k > pos; --k) ord[k] = ord[k - 1];
      ord[pos] = p;
      ++n;
    }
    int rank[3] = {0, 0, 0};
    for (int k = 0; k < n; ++k) rank[ord[k]] = k;
    for (int p = 0; p < 3; ++p) {
      if (!bit(crossed, p)) continue;
      unsigned m = 1u << p;  // on P_p itself the coordinate is 0: sign 1
      for (int q = 0; q < 3; ++q) {
        if (q == p) continue;
        const bool s = !bit(crossed, q) ? bit(sm_[i], q) : (rank[p] < rank[q] ? bit(sm_[i], q) : bit(sm_[j], q));
        m |= unsigned(s) << q;
      }
      cm_[e][p] = static_cast<u8>(m);
    }
    if (stats_) {
      // n crossings, each with two other coordinates: 2n signs. Those of uncrossed lines are
      // inherited; the n(n-1) others come in pairs, one pair per comparison of two crossings.
      const int pairs = n * (n - 1) / 2;
      stats_->edge_inherited += 2 * n - 2 * pairs;
      stats_->edge_computed += computed;
      stats_->edge_paired += computed;
      stats_->edge_straight_line += 2 * (pairs - computed);
    }
  }

  // The same signs without branching on the data (the path taken without statistics): each
  // pair of crossed lines is compared once, by the very calculation the sort makes for it, and
  // a line's rank along the edge is the number of lines crossed before it. When the comparisons
  // are transitive this is the sort's order, so both paths decide the same signs; when rounding
  // makes them cyclic (ranks collide) the sort decides, which keeps the straight line principle.
  // Returns false in that case. (The sort skips a comparison the principle forces; this path
  // evaluates it and finds the same answer, so it is no different in the result.)
  // The three comparisons are made for every pair of lines, crossed or not; what follows from
  // them and the ends' signs is looked up (kEdgeTable, which edge_signs_from_pairs computes).
  bool decide_edge_by_pairs(int e) {
    const int i = kEdgeFrom[e], j = kEdgeTo[e];
    unsigned pairs;
    if (geo_.careful) [[unlikely]] {
      pairs = unsigned(crosses_before(i, j, 1, 0)) | unsigned(crosses_before(i, j, 2, 0)) << 1 |
              unsigned(crosses_before(i, j, 2, 1)) << 2;
    } else {
      // crosses_before(i, j, y, x) for (y, x) = (1, 0), (2, 0), (2, 1), side by side: the
      // numerators (the same products and differences), and bit k of `positive` and `zero`
      // their signs; den_positive is bit y of si, and the result is compared with bit x.
      const double* a = C_[i];
      const double* b = C_[j];
      const double num[3] = {b[0] * a[1] - a[0] * b[1], b[0] * a[2] - a[0] * b[2], b[1] * a[2] - a[1] * b[2]};
      unsigned positive = 0, zero = 0;
      for (int k = 0; k < 3; ++k) {
        positive |= unsigned(num[k] > 0.0) << k;
        zero |= unsigned(num[k] == 0.0) << k;
      }
      const unsigned si = sm_[i];
      const unsigned den_positive = (si >> 1 & 1u) | (si >> 2 & 1u) * 6u;  // bits y = 1, 2, 2
      const unsigned x_sign = (si & 1u) * 3u | (si >> 1 & 1u) << 2;          // bits x = 0, 0, 1
      const unsigned sign_x = zero | (~(positive ^ den_positive) & 7u);
      pairs = ~(sign_x ^ x_sign) & 7u;
    }
    const unsigned entry = kEdgeTable[sm_[i] | unsigned(sm_[j]) << 3 | pairs << 6];
    cm_[e][0] = static_cast<u8>(entry & 7u);
    cm_[e][1] = static_cast<u8>(entry >> 3 & 7u);
    cm_[e][2] = static_cast<u8>(entry >> 6 & 7u);
    return (entry >> 9) != 0;
  }

  // Lines 11-13: the vertex of Y at P_p ∩ P_q lies in X iff the two crossings of X's boundary
  // with P_p have different q-signs. A line crossed by X is crossed by exactly two edges, the
  // two at the vertex whose p-sign is the odd one out; a line not crossed sees no vertex.
  // line_views(view) sets bit q of view[p] where the two crossings with P_p have different
  // q-signs, and returns bit p set where X crosses P_p (only there does view[p] mean anything).
  unsigned line_views(unsigned (&view)[3]) const {
    // The vertex alone in its p-sign, from the pattern of the three signs (-1: none, all equal).
    constexpr std::int8_t kLone[8] = {-1, 0, 1, 2, 2, 1, 0, -1};
    unsigned crossed = 0;
    for (int p = 0; p < 3; ++p) {
      const unsigned pattern = unsigned(bit(sm_[0], p)) | unsigned(bit(sm_[1], p)) << 1 | unsigned(bit(sm_[2], p)) << 2;
      const int lone = kLone[pattern];
      const int l = lone < 0 ? 0 : lone;
      // The two edges at `lone` are those opposite the other two vertices.
      view[p] = unsigned(cm_[kEdgeFrom[l]][p] ^ cm_[kEdgeTo[l]][p]);
      crossed |= unsigned(lone >= 0) << p;
    }
    return crossed;
  }

  // Appends a corner if `exists`, without branching on it: the slot is written either way and
  // the count advances only for a corner (the last slot absorbs writes past a full array, which
  // run() then reports as a failure).
  void add_if(KernelResult& out, bool exists, u8 kind, u8 index, u8 in, u8 o) {
    const int n = out.num_corners;
    RawCorner& c = out.corners[n < KernelResult::kMaxCorners ? n : KernelResult::kMaxCorners - 1];
    c.kind = kind;
    c.index = index;
    c.in = in;
    c.out = o;
    out.num_corners = n + int(exists);
  }

  const double (&C_)[3][3];
  bool x_ccw_;
  SignGeometry geo_;
  TriIntersectionStats* stats_;
  u8 sm_[3];
  u8 cm_[3][3] = {};  // sign masks of the crossing of edge e with P_p
};

bool Kernel::run(KernelResult& out) {
  out.num_corners = 0;
  out.contradiction = false;
  // Early outs: X entirely on the negative side of a line of Y (all signs 0), or nowhere
  // strictly on its positive side (it then touches the line at most: zero area).
  unsigned positive = 0;  // bit p: some vertex has coordinate p > 0
  for (int i = 0; i < 3; ++i)
    for (int p = 0; p < 3; ++p) positive |= unsigned(C_[i][p] > 0.0) << p;
  if (positive != 7u) return true;
  // X's vertices in counter-clockwise order (in the frame of Y).
  const int nx[3] = {x_ccw_ ? 1 : 2, x_ccw_ ? 2 : 0, x_ccw_ ? 0 : 1};  // next
  const int px[3] = {nx[nx[0]], nx[nx[1]], nx[nx[2]]};                 // previous

  // Lines 2-6: vertices of X inside Y. The boundary arrives on the edge from the previous
  // vertex (the edge opposite the next one) and leaves on the edge opposite the previous one.
  for (int i = 0; i < 3; ++i)
    add_if(out, sm_[i] == 7, kVertexOfX, static_cast<u8>(i), static_cast<u8>(nx[i]), static_cast<u8>(px[i]));
  if (out.num_corners < 3) {
    // Lines 7-10: edges of X against the lines of Y.
    for (int e = 0; e < 3; ++e)
      if (stats_ || !decide_edge_by_pairs(e)) decide_edge(e);
    for (int e = 0; e < 3; ++e) {
      const unsigned crossed = (sm_[kEdgeFrom[e]] ^ sm_[kEdgeTo[e]]) & 7u;
      // The edge's counter-clockwise start: leaving the half-plane {p >= 0} there means the
      // boundary comes along the edge and goes on along P_p; entering, the reverse.
      const int start = x_ccw_ ? kEdgeFrom[e] : kEdgeTo[e];
      for (int p = 0; p < 3; ++p) {
        const bool leaving = bit(sm_[start], p);
        add_if(out, bit(crossed, p) && cm_[e][p] == 7, kEdgeOfX, static_cast<u8>(e * 3 + p),
               static_cast<u8>(leaving ? e : 3 + p), static_cast<u8>(leaving ? 3 + p : e));
      }
    }
    // Lines 11-13: vertex r of Y, at P_p ∩ P_q. Decided from P_p (or from P_q when X does not
    // cross P_p); the two views agree by the pairing of line 10 (checked with statistics).
    unsigned view[3];
    const unsigned crossed = line_views(view);
    for (int r = 0; r < 3; ++r) {
      const int p = (r + 1) % 3, q = (r + 2) % 3;
      const int first = bit(crossed, p) ? int(bit(view[p], q)) : -1;
      const int other = bit(crossed, q) ? int(bit(view[q], p)) : -1;
      const int inside = first < 0 ? other : first;
      if (stats_ && first >= 0 && other >= 0 && first != other) out.contradiction = true;
      // Y is counter-clockwise: the boundary arrives on the line opposite the next vertex.
      add_if(out, inside == 1, kVertexOfY, static_cast<u8>(r), static_cast<u8>(3 + (r + 1) % 3),
             static_cast<u8>(3 + (r + 2) % 3));
    }
  }
  if (out.num_corners > KernelResult::kMaxCorners) return false;  // impossible (checked)
  // The counter-clockwise order from the labels: the next corner is the one the boundary
  // arrives at on the line this one leaves by. Each line carries at most one side.
  const int n = out.num_corners;
  if (n == 0) return true;
  if (n < 3) return false;  // a closed boundary has at least three corners
  int arriving[6] = {-1, -1, -1, -1, -1, -1};
  for (int c = 0; c < n; ++c) {
    if (arriving[out.corners[c].in] >= 0) return false;
    arriving[out.corners[c].in] = c;
  }
  unsigned visited = 0;
  int cur = 0;
  for (int k = 0; k < n; ++k) {
    if (cur < 0 || bit(visited, cur)) return false;
    visited |= 1u << cur;
    out.order[k] = static_cast<u8>(cur);
    cur = arriving[out.corners[cur].out];
  }
  return cur == 0;
}

// Twice the signed area of (a, b, c) to nearly full relative accuracy, even for a needle whose
// vertices are almost collinear (there the plain formula loses all digits to the rounding of
// the differences). The differences and the two main products are formed exactly (Knuth's
// two-difference, Dekker's product: no fused multiply-add, which this project keeps off) and
// summed in double-double. Used for a triangle's own determinant when the plain one is not
// certain to 1e-14 (shape_quality): a needle's orientation, its flatness, and its area where
// it scales the result (corner_coordinates); and for a vertex of the reference inside a needle
// (BarycentricMap::accurate). The sign logic on X's coordinates does not use it.
struct DoubleDouble {
  double hi = 0.0, lo = 0.0;

  static void split(double a, double& h, double& l) {
    const double c = 134217729.0 * a;  // 2^27 + 1
    h = c - (c - a);
    l = a - h;
  }
  void add(double x) {  // Knuth's two-sum, then the error into lo
    const double s = hi + x;
    const double bb = s - hi;
    const double err = (hi - (s - bb)) + (x - bb);
    hi = s;
    lo += err;
  }
  void add_product(double a, double b) {
    const double p = a * b;
    double ah, al, bh, bl;
    split(a, ah, al);
    split(b, bh, bl);
    const double err = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
    add(p);
    lo += err;
  }
  double value() const { return hi + lo; }
};

// Correctly rounded where exact_sign.hpp's orient2d_nearest applies (differences below 2^496,
// and a determinant above 2^-900 where products of the differences' parts underflow: always,
// for rescaled input), else the double-double evaluation below, whose error is about eps^2
// times the permanent (not enough for the most extreme needles alone).
double orient2d_dd(Vec2 a, Vec2 b, Vec2 c);
double orient2d_accurate(Vec2 a, Vec2 b, Vec2 c) {
  double v;
  if (detail::orient2d_nearest(a.x, a.y, b.x, b.y, c.x, c.y, v)) return v;
  return orient2d_dd(a, b, c);
}
double orient2d_dd(Vec2 a, Vec2 b, Vec2 c) {
  // The differences exactly, as hi + lo (Knuth's two-difference), so that the result does not
  // depend on where the triangle is (coordinates of 1e8 with a triangle of size 1e-3 would
  // otherwise leave the products' rounding larger than the determinant).
  const auto diff = [](double x, double y, double& lo) {
    const double d = x - y;
    const double bv = x - d;
    lo = (x - (d + bv)) + (bv - y);
    return d;
  };
  double l1x, l1y, l2x, l2y;
  const double h1x = diff(b.x, a.x, l1x), h1y = diff(b.y, a.y, l1y);
  const double h2x = diff(c.x, a.x, l2x), h2y = diff(c.y, a.y, l2y);
  DoubleDouble d;
  d.add_product(h1x, h2y);
  d.add_product(-h1y, h2x);
  // The cross terms with one low part are eps times smaller; the low-low terms eps^2.
  d.lo += (h1x * l2y + l1x * h2y) - (h1y * l2x + l1y * h2x);
  return d.value();
}

// Conditioning of a triangle as a reference: |det| / (sum of squared edge lengths), scale
// invariant, largest for the equilateral triangle, zero when flat. The determinant is returned
// with a relative error below 1e-14: when Shewchuk's error bound for the plain evaluation,
// (3 + 16 eps) eps times the permanent, does not guarantee that (a needle, whose vertices are
// nearly collinear), it is evaluated accurately. A needle is then neither reported with the
// wrong orientation nor called flat when it is not (exactly collinear vertices give exactly
// zero: flat, empty result), and its area, which can scale the result (corner_coordinates),
// keeps its digits.
// s: the sum of squared edge lengths.
double shape_quality(const Triangle& t, double& det2, double& s) {
  const Vec2 e1 = t[1] - t[0], e2 = t[2] - t[0], e3 = t[2] - t[1];
  const double l = e1.x * e2.y, r = e1.y * e2.x;
  det2 = l - r;
  if (!(1e-14 * std::abs(det2) > (3.0 + 16.0 * 0x1p-53) * 0x1p-53 * (std::abs(l) + std::abs(r))))
    det2 = orient2d_accurate(t[0], t[1], t[2]);
  s = e1.x * e1.x + e1.y * e1.y + e2.x * e2.x + e2.y * e2.y + e3.x * e3.x + e3.y * e3.y;
  return std::abs(det2) / s;
}

// The change of coordinates, one edge at a time (the 2D form of the 3D kernel's
// BarycentricMap): coordinate k of u is orient2d(a_k, b_k, u) / orient2d(a_k, b_k, r_k) for
// the edge (a_k, b_k) opposite vertex k, with the edge translated to its own first vertex so
// that its direction is exact to its own size. A point equal to a vertex of the reference gets
// exactly that vertex's coordinates; a coordinate within Shewchuk's error bound for orient2d,
// (3 + 16 eps) eps times the permanent, has no reliable sign and is set to exactly 0 (the point
// is then on the line: the exact answer for an input perturbed below its own rounding).
struct BarycentricMap {
  Vec2 vertex[3];
  Vec2 anchor[3];
  Vec2 dir[3];
  Vec2 to[3];  // the edge's other end
  double inv;

  static constexpr double kErrBound = (3.0 + 16.0 * 0x1p-53) * 0x1p-53;

  BarycentricMap(const Triangle& r, double det2) : inv(1.0 / det2) {
    for (int k = 0; k < 3; ++k) {
      vertex[k] = r[k];
      anchor[k] = r[kEdgeFrom[k]];
      dir[k] = r[kEdgeTo[k]] - r[kEdgeFrom[k]];
      to[k] = r[kEdgeTo[k]];
      // orient2d(r_{k+1}, r_{k+2}, r_k) is a cyclic shift of orient2d(r_0, r_1, r_2) = det2.
    }
  }

  // The same with every numerator evaluated by orient2d_accurate (for a point inside a needle,
  // whose distance to the long edges the plain formula cannot resolve); no snapping needed.
  void accurate(Vec2 u, double (&out)[3]) const {
    for (int k = 0; k < 3; ++k) out[k] = orient2d_accurate(anchor[k], to[k], u) * inv;
    for (int k = 0; k < 3; ++k)
      if (u == vertex[k]) {
        for (int q = 0; q < 3; ++q) out[q] = q == k ? 1.0 : 0.0;
      }
  }

  // A coordinate whose plain value is within the error bound has no reliable sign. Snapped to
  // 0, it moves the point by up to eps times its distance from the edge's anchor: harmless
  // between triangles of similar size (the point moves by eps of them), but for a triangle
  // much smaller than the reference (1e-14 of it, say) a good part of the small triangle, and
  // for one much larger (X far bigger than Y) many times Y. With `accurate_near_zero` (sizes
  // more than 2^10 apart, make_frame) such a coordinate is evaluated again, correctly rounded
  // (orient2d_nearest: its sign exact, nothing snapped, a point exactly on the line exactly 0),
  // or where that does not apply in double-double, and then only what is zero to that
  // evaluation's own error, 8 eps^2 times the permanent, is snapped. (Snapped after a correctly
  // rounded evaluation too, before 2026-12-06, a vertex of a needle 2.7e-11 wide moved by 2e-8
  // across a line of a triangle 1e23 big: fuzz/regressions/fuzz_tri_kernel/found-2026-12-06.txt.)
  //
  // perm[k]: the permanent of coordinate k; kErrBound perm[k] |inv| bounds its error (the
  // common rounding of inv scales all coordinates alike and changes no sign the kernel takes).
  // Inlined: make_frame calls it in two places (the second rare), and out of line it cost the
  // kernel 7 % on triangles that share a vertex.
  [[gnu::always_inline]] void operator()(Vec2 u, double (&out)[3], double (&perm)[3], bool accurate_near_zero) const {
    for (int k = 0; k < 3; ++k) {
      const Vec2 w = u - anchor[k];
      const double l = dir[k].x * w.y, rr = dir[k].y * w.x;
      double det = l - rr;
      const double permanent = std::abs(l) + std::abs(rr);
      perm[k] = permanent;
      if (!(std::abs(det) > kErrBound * permanent)) [[unlikely]] {
        if (!accurate_near_zero) {
          det = 0.0;
        } else if (!detail::orient2d_nearest(anchor[k].x, anchor[k].y, to[k].x, to[k].y, u.x, u.y, det)) {
          det = orient2d_dd(anchor[k], to[k], u);
          if (!(std::abs(det) > 8.0 * 0x1p-106 * permanent)) det = 0.0;
        }
      }
      out[k] = det * inv;
      if (std::abs(out[k]) < 0x1p-500) out[k] = 0.0;  // see make_frame: products stay normal
    }
    for (int k = 0; k < 3; ++k)
      if (u == vertex[k]) {
        for (int q = 0; q < 3; ++q) out[q] = q == k ? 1.0 : 0.0;
      }
  }
  void operator()(Vec2 u, double (&out)[3]) const {
    double perm[3];
    (*this)(u, out, perm, false);
  }
};

struct Frame {
  // Both triangles with their vertices in a canonical (lexicographic) order, so that the result
  // does not depend on the order the caller lists them in, bit for bit; perm maps a canonical
  // vertex index to the caller's.
  Triangle a_canonical, b_canonical;
  u8 a_perm[3], b_perm[3];
  const Triangle* sub;  // A's role in the paper (mapped to X)
  const Triangle* ref;  // B's role (mapped to Y)
  const u8* sub_perm;
  const u8* ref_perm;
  bool swapped;         // the caller's A is the reference
  bool x_ccw;           // X is counter-clockwise in the frame of Y
  double det2;          // det[r1 - r0, r2 - r0]
  double det2_sub;      // det[s1 - s0, s2 - s0]
  double inv_det2;      // 1 / det2, the scale of the reference's map
  double C[3][3];
  double C_perm[3][3];  // the permanents of C's entries (BarycentricMap)
  bool careful;         // some |entry| of C above 2^8 (X's vertices far from Y for Y's size),
                        // sizes more than 2^10 apart, or X thin for Y's resolution (make_frame)
  double C_error;       // a bound on every entry's error
  double C_max;         // the largest |entry|
  double size_squared_max;  // the larger sum of squared edge lengths (make_frame)
};

// Coordinates of the corners (only of those that exist), then the area and first moments by a
// fan from the first corner (differences first: no cancellation against the polygon's position).
//
// The area is measured in the frame of the smaller triangle. Each corner's coordinates carry an
// absolute rounding error of about eps in the frame they are expressed in, so the area comes out
// with an error of about eps times the area of that frame's triangle; the test bound is relative
// to the smaller triangle (a sliver against a big one, say). In the frame of Y (the reference)
// the coordinates are those the kernel computed; in the frame of X (the subject) every corner
// that lies on X is known there exactly or as the one weight t along an edge of X, and only a
// vertex of Y inside X needs a change of coordinates.
// kMoments: the first moments too, and every corner's coordinates in Y (a Polygon's); without,
// the area alone, and a crossing's coordinates in Y only where the area is measured there.
template <bool kMoments>
void corner_coordinates(const Frame& fr, KernelResult& r, TriIntersectionStats* stats) {
  const auto& C = fr.C;
  // The frame the area is measured in: X's when X is the smaller triangle.
  const bool sub_frame = std::abs(fr.det2_sub) < std::abs(fr.det2);
  // The map's error bound on X's coordinates of vertex i, in units of Y's frame: where the area
  // is measured there, a bound above 2^-47 (Y a needle, X's vertices far from Y's anchors) is
  // not accurate enough relative to Y, and what is built from those coordinates is made again
  // from the input (orient2d_accurate).
  // (fr.C_error, the bound over all nine, decides for the usual case at once.)
  const bool any_coarse = !sub_frame && !(fr.C_error <= 0x1p-47);
  const auto coarse = [&](int i) {
    const double perm = std::max(std::max(fr.C_perm[i][0], fr.C_perm[i][1]), fr.C_perm[i][2]);
    return any_coarse && !(BarycentricMap::kErrBound * perm * std::abs(fr.inv_det2) <= 0x1p-47);
  };
  for (int c = 0; c < r.num_corners; ++c) {
    RawCorner& k = r.corners[c];
    if (k.kind == kVertexOfX) {
      for (int p = 0; p < 3; ++p) k.bary[p] = C[k.index][p];
      if (coarse(k.index)) [[unlikely]] {
        // Inside Y by the signs: coordinates clamped to agree, exact zeros (on a line of Y, as
        // the signs decided) kept.
        double b[3];
        BarycentricMap(*fr.ref, fr.det2).accurate((*fr.sub)[k.index], b);
        for (int p = 0; p < 3; ++p) k.bary[p] = C[k.index][p] == 0.0 ? 0.0 : std::max(b[p], 0.0);
        if (stats) ++stats->refined;
      }
    } else if (k.kind == kVertexOfY) {
      for (int p = 0; p < 3; ++p) k.bary[p] = p == k.index ? 1.0 : 0.0;
    } else {
      // Crossing of edge e with P_p: eq. (2) for the two other coordinates, with the decided
      // signs (both >= 0 for a corner) enforced as guardrails, then scaled to sum to 1 (they do
      // up to rounding; the scaling keeps p exactly 0 and the corner exactly on P_p). Both are
      // evaluated, not one and its complement, so that a crossing at a vertex of Y gets an
      // exact zero (a collinear edge; touched_edges_of_b relies on it).
      const int e = k.index / 3, p = k.index % 3, i = kEdgeFrom[e], j = kEdgeTo[e];
      const int q1 = kEdgeFrom[p], q2 = kEdgeTo[p];  // the two other coordinates
      double ci = C[i][p], cj = C[j][p];
      // Where the crossing lies along the edge, t = ci / (ci - cj), is accurate to 2^-44 when
      // the map's error bound on ci and cj is that far below their difference. Otherwise (an
      // edge much shorter than the reference, the usual case of a small X crossing a big Y)
      // both are recomputed to full relative accuracy: t is then accurate relative to the edge,
      // and so is the area measured in X's frame. Exact zeros (a vertex on P_p, snapped by the
      // map) stay zero: the signs were decided on them.
      bool refine = BarycentricMap::kErrBound * (fr.C_perm[i][p] + fr.C_perm[j][p]) * std::abs(fr.inv_det2) >
                    0x1p-44 * std::abs(ci - cj);
      // In Y's frame (the area is measured there when Y is the smaller triangle) the two other
      // coordinates, v1 and v2 below, carry about eps M^2 / |den| of rounding, M the largest
      // coordinate involved; their effect on the area is about eps M^2 of Y's (a small |den|
      // moves the corner along a thin wedge), which matters only where X's vertices are far
      // from Y (X much bigger; fr.careful, M at most fr.C_max). There the corner is found from
      // the other side: it is the point of P_p,
      // lambda_q1 y_q1 + lambda_q2 y_q2, on the line of the edge, where orient2d(u_i, u_j, .)
      // vanishes; with o_q = orient2d(u_i, u_j, y_q) evaluated accurately,
      // lambda_q1 = o_q2 / (o_q2 - o_q1) and lambda_q2 = -o_q1 / (o_q2 - o_q1), accurate
      // relative to Y. Not where an end of the edge has coordinate p exactly 0 (on P_p, or
      // snapped there by the map): the corner is then that vertex, as the signs decided.
      bool dual = false;
      if (fr.careful && !sub_frame && ci != 0.0 && cj != 0.0) [[unlikely]] {
        const double M = fr.C_max;  // at least the largest coordinate involved
        dual = M * M > 128.0 * std::abs(ci - cj);
      }
      // Likewise where the ends' coordinates are coarse in Y's frame (coarse, above).
      if (ci != 0.0 && cj != 0.0 && (coarse(i) || coarse(j))) [[unlikely]]
        dual = true;
      refine |= dual;  // t then as accurate as the corner, so that both describe one point
      const Triangle& ref = *fr.ref;
      const Triangle& sub = *fr.sub;
      if (refine) [[unlikely]] {
        const Vec2 anchor = ref[kEdgeFrom[p]], to = ref[kEdgeTo[p]];
        if (ci != 0.0) ci = orient2d_accurate(anchor, to, sub[i]) * fr.inv_det2;
        if (cj != 0.0) cj = orient2d_accurate(anchor, to, sub[j]) * fr.inv_det2;
        if (stats) ++stats->refined;
      }
      const double den = ci - cj;
      if constexpr (!kMoments) {
        // The area alone (intersection_area), measured in X's frame: from the weight alone (the
        // coordinates in Y, which only a Polygon and the moments read, are not made).
        if (sub_frame) {
          k.weight_b = ci / den;
          continue;
        }
      }
      const double t = ci / den;  // in [0, 1]: ci and -cj have the same sign
      double v1 = (ci * C[j][q1] - cj * C[i][q1]) / den;
      double v2 = (ci * C[j][q2] - cj * C[i][q2]) / den;
      if (dual) [[unlikely]] {
        const double o1 = orient2d_accurate(sub[i], sub[j], ref[q1]), o2 = orient2d_accurate(sub[i], sub[j], ref[q2]);
        const double d = o2 - o1;
        if (d != 0.0 && std::isfinite(d)) {
          v1 = o2 / d;
          v2 = -o1 / d;
        }
      }
      if (stats) stats->guardrail_clamps += int(!(v1 >= 0.0)) + int(!(v2 >= 0.0));
      v1 = v1 >= 0.0 ? v1 : 0.0;
      v2 = v2 >= 0.0 ? v2 : 0.0;
      if (!(v1 + v2 > 0.0 && v1 + v2 < INFINITY)) [[unlikely]] {
        // Both clamped (or not finite): the point at t on the edge, clamped in turn, and the
        // midpoint of the admissible segment if nothing is left (Table 4's choice); never a
        // corner with all coordinates zero.
        v1 = std::max((1.0 - t) * C[i][q1] + t * C[j][q1], 0.0);
        v2 = std::max((1.0 - t) * C[i][q2] + t * C[j][q2], 0.0);
        if (!(v1 + v2 > 0.0) || !(v1 + v2 < INFINITY)) v1 = v2 = 0.5;
      }
      const double sum = v1 + v2;
      k.bary[p] = 0.0;
      k.bary[q1] = v1 / sum;
      k.bary[q2] = v2 / sum;
      k.weight_b = t;
      if (stats) stats->corner_coordinates += 2;
    }
  }
  r.sub_frame = sub_frame;
  // Both determinants are accurate to 1e-14 even for needles (shape_quality).
  r.frame_det = r.sub_frame ? fr.det2_sub : fr.det2;
  // The fan's planar coordinates: (x, y) of Y, or the last two barycentric coordinates in X.
  double xy[KernelResult::kMaxCorners][2] = {};
  for (int k = 0; k < r.num_corners; ++k) {
    const RawCorner& c = r.corners[r.order[k]];
    if (!r.sub_frame) {
      xy[k][0] = c.bary[1];
      xy[k][1] = c.bary[2];
      continue;
    }
    double b[3] = {0.0, 0.0, 0.0};
    if (c.kind == kVertexOfX) {
      b[c.index] = 1.0;
    } else if (c.kind == kEdgeOfX) {
      b[kEdgeFrom[c.index / 3]] = 1.0 - c.weight_b;
      b[kEdgeTo[c.index / 3]] = c.weight_b;
    } else {
      const BarycentricMap map(*fr.sub, r.frame_det);
      map.accurate((*fr.ref)[c.index], b);
      // The vertex is in X by the signs; its coordinates are clamped to agree (guardrail).
      for (double& v : b) v = v > 0.0 ? v : 0.0;
      if (stats) stats->corner_coordinates += 3;
    }
    xy[k][0] = b[1];
    xy[k][1] = b[2];
  }
  const double x0 = xy[0][0], y0 = xy[0][1];
  double a2 = 0.0, fx = 0.0, fy = 0.0;
  for (int k = 1; k + 1 < r.num_corners; ++k) {
    const double ux = xy[k][0] - x0, uy = xy[k][1] - y0, vx = xy[k + 1][0] - x0, vy = xy[k + 1][1] - y0;
    const double t2 = ux * vy - uy * vx;
    a2 += t2;
    if constexpr (kMoments) {
      fx += t2 * (ux + vx);
      fy += t2 * (uy + vy);
    }
  }
  // The order is counter-clockwise in the frame of Y; the frame of X sees it reversed when
  // the map between the two reverses orientation.
  if (r.sub_frame && !fr.x_ccw) {
    a2 = -a2;
    fx = -fx;
    fy = -fy;
  }
  // A convex polygon has a non-negative area; rounding in a degenerate (zero-area) one may not.
  if (!(a2 > 0.0)) {
    r.ref_area = 0.0;
    r.ref_first[0] = r.ref_first[1] = 0.0;
    return;
  }
  r.ref_area = 0.5 * a2;
  if constexpr (kMoments) {
    // Fan triangle (c0, c1, c2): area t2 / 2, centroid c0 + (u + v) / 3.
    r.ref_first[0] = r.ref_area * x0 + fx / 6.0;
    r.ref_first[1] = r.ref_area * y0 + fy / 6.0;
  }
}

// Picks the reference (the better-conditioned triangle; ties broken by the coordinates, so that
// (A, B) and (B, A) choose the same one) and computes X. False for flat or non-finite input.
void canonical_order(const Triangle& t, Triangle& out, u8 (&perm)[3]) {
  // Rank of each vertex = how many come before it (x, then y, then index for equal points),
  // without branches: the sort of three is on the path of every call.
  const auto before = [&t](int i, int j) {
    return int(unsigned(t[i].x < t[j].x) |
               (unsigned(t[i].x == t[j].x) & (unsigned(t[i].y < t[j].y) | (unsigned(t[i].y == t[j].y) & unsigned(i < j)))));
  };
  const int b01 = before(0, 1), b02 = before(0, 2), b12 = before(1, 2);
  const int rank[3] = {(1 - b01) + (1 - b02), b01 + (1 - b12), b02 + b12};
  for (int k = 0; k < 3; ++k) {
    out[static_cast<std::size_t>(rank[k])] = t[static_cast<std::size_t>(k)];
    perm[rank[k]] = static_cast<u8>(k);
  }
}

// make_frame's outcome. `rescale`: an edge length of A or B is outside [2^-250, 2^250], where
// the kernel's products of two differences and their error bounds would leave the normal
// range: solve() scales the input by a power of two (rescale.hpp) and makes the frame again.
enum class FrameStatus { ok, flat_or_not_finite, rescale };

FrameStatus make_frame(const Triangle& A_in, const Triangle& B_in, Frame& fr, bool other_reference = false) {
  canonical_order(A_in, fr.a_canonical, fr.a_perm);
  canonical_order(B_in, fr.b_canonical, fr.b_perm);
  const Triangle& A = fr.a_canonical;
  const Triangle& B = fr.b_canonical;
  double detA, detB, sA, sB;
  const double qA = shape_quality(A, detA, sA), qB = shape_quality(B, detB, sB);
  fr.size_squared_max = std::max(sA, sB);
  const bool accurate_near_zero = !(sA <= 0x1p20 * sB && sB <= 0x1p20 * sA);
  // (Also when the sizes are more than 2^250 apart: after scaling the larger to 1 the smaller is
  // then out of range, and the exact last resort decides. Products of two coordinates then stay
  // normal once coordinates below 2^-500 are 0, which moves a vertex by 2^-250 of the smaller.)
  if (!(sA >= 0x1p-500 && sB >= 0x1p-500 && sA <= 0x1p500 && sB <= 0x1p500 && sA <= 0x1p500 * sB && sB <= 0x1p500 * sA))
    return FrameStatus::rescale;
  if (!(qA > 0.0) || !(qB > 0.0) || !(qA < INFINITY) || !(qB < INFINITY)) return FrameStatus::flat_or_not_finite;
  bool use_a = qA > qB;
  if (qA == qB) {
    const double* pa = &A[0].x;
    const double* pb = &B[0].x;
    use_a = std::lexicographical_compare(pa, pa + 6, pb, pb + 6);
  }
  use_a = use_a != other_reference;
  fr.swapped = use_a;
  fr.sub = use_a ? &B : &A;
  fr.ref = use_a ? &A : &B;
  fr.sub_perm = use_a ? fr.b_perm : fr.a_perm;
  fr.ref_perm = use_a ? fr.a_perm : fr.b_perm;
  fr.det2 = use_a ? detA : detB;
  fr.det2_sub = use_a ? detB : detA;
  fr.x_ccw = (detA > 0.0) == (detB > 0.0);
  const BarycentricMap bary(*fr.ref, fr.det2);
  fr.inv_det2 = bary.inv;
  for (int i = 0; i < 3; ++i) bary((*fr.sub)[i], fr.C[i], fr.C_perm[i], accurate_near_zero);
  // Whether every coordinate is finite (not NaN, not infinite) and whether some is large; as
  // bitwise operations on the comparisons, over the nine as one array (vectorizable). Their
  // largest magnitude and permanent: C_error bounds every coordinate's error.
  unsigned finite = 1, big = 0;
  double c_max = 0.0, perm_max = 0.0;
  for (int k = 0; k < 9; ++k) {
    const double m = std::abs(fr.C[k / 3][k % 3]);
    finite &= unsigned(m <= 0x1.fffffffffffffp1023);
    big |= unsigned(m > 0x1p8);
    c_max = std::max(c_max, m);
    perm_max = std::max(perm_max, fr.C_perm[k / 3][k % 3]);
  }
  fr.C_max = c_max;
  fr.C_error = BarycentricMap::kErrBound * perm_max * std::abs(bary.inv) * (1.0 + 0x1p-50);
  // X thin for the resolution of Y's coordinates: moving X's vertices by C_error would change
  // its area, |det2_sub / det2| in Y's units, by more than 2^-40 of it (a needle across a flat
  // Y). Its coordinates near 0 are then evaluated accurately, as between sizes far apart, and
  // its signs decided with care (below).
  const bool x_thin = fr.C_error * std::max(c_max, 1.0) > 0x1p-40 * std::abs(fr.det2_sub * bary.inv);
  if (x_thin && !accurate_near_zero) [[unlikely]]
    for (int i = 0; i < 3; ++i) bary((*fr.sub)[i], fr.C[i], fr.C_perm[i], true);
  // Careful too where the sizes are far apart and X is the smaller: X's coordinates are then
  // moderate, but their errors, eps times Y's size, are a good part of X; the order of two
  // crossings along an edge of X (crosses_before) near a vertex of Y, the product of two such
  // coordinates, then has no reliable sign in doubles (a small X around a vertex of a 1e15
  // times bigger Y lost its whole intersection before 2026-12-06); and where X is thin for Y's
  // resolution (x_thin).
  fr.careful = (big != 0) | accurate_near_zero | x_thin;
  return finite ? FrameStatus::ok : FrameStatus::flat_or_not_finite;
}

template <bool kMoments>
bool run_kernel(const Frame& fr, KernelResult& res, TriIntersectionStats* stats) {
  const SignGeometry geo{fr.sub, fr.ref, fr.careful, fr.C_error, fr.C_max, fr.det2 > 0.0};
  Kernel k(fr.C, fr.x_ccw, geo, stats);
  const bool ok = k.run(res);
  if (!ok) {
    res.num_corners = 0;
    res.ref_area = 0.0;
    res.ref_first[0] = res.ref_first[1] = 0.0;
    return false;
  }
  if (stats && res.contradiction) ++stats->inconsistencies;
  if (res.num_corners == 0) {
    res.ref_area = 0.0;
    res.ref_first[0] = res.ref_first[1] = 0.0;
    return true;
  }
  // Corners whose computed area is not positive are kept: the labels say the polygon exists,
  // and solve() lets exact arithmetic decide (a tangent contact, exactly zero, is then empty).
  corner_coordinates<kMoments>(fr, res, stats);
  return true;
}

// How solve() obtained the result.
enum class Outcome {
  empty,   // no intersection (disjoint, tangent, flat, or non-finite input)
  kernel,  // the double kernel's result, in the frame of the (scaled) input
  exact,   // the exact last resort (exact_polygon), for the caller's input as given
};

bool finite(const Triangle& t) {
  for (const Vec2& p : t)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  return true;
}

// Whether the bounding boxes of A and B are disjoint: on some axis max A < min B or
// max B < min A, compared exactly on the input, so that a line x = c (or y = c) separates the
// two strictly and the exact area is 0. Boxes that touch are not disjoint (the kernel decides
// those). NaN compares false: non-finite input goes on to make_frame, which rejects it. As the
// 3D kernel's first test (solve.hpp): a fifth of the pairs of random triangles in a square end
// here, for about 30 instructions, where the frame and the kernel took 1,500 for the same result.
bool boxes_disjoint(const Triangle& A, const Triangle& B) {
  double a_lo[2] = {A[0].x, A[0].y}, a_hi[2] = {A[0].x, A[0].y};
  double b_lo[2] = {B[0].x, B[0].y}, b_hi[2] = {B[0].x, B[0].y};
  for (int k = 1; k < 3; ++k) {
    const double a[2] = {A[k].x, A[k].y}, b[2] = {B[k].x, B[k].y};
    for (int i = 0; i < 2; ++i) {  // min and max written out: the same without branches
      a_lo[i] = a[i] < a_lo[i] ? a[i] : a_lo[i];
      a_hi[i] = a_hi[i] < a[i] ? a[i] : a_hi[i];
      b_lo[i] = b[i] < b_lo[i] ? b[i] : b_lo[i];
      b_hi[i] = b_hi[i] < b[i] ? b[i] : b_hi[i];
    }
  }
  return (unsigned(a_hi[0] < b_lo[0]) | unsigned(b_hi[0] < a_lo[0]) | unsigned(a_hi[1] < b_lo[1]) |
          unsigned(b_hi[1] < a_lo[1])) != 0;
}

// Whether A and B only touch, decided exactly (exact_sign.hpp): 1 if some edge line of one has
// all of the other on its closed outer side (two convex polygons whose interiors are disjoint
// are separated by the line of an edge of one of them), 0 if none does (their interiors
// meet: the exact area is positive), 2 if an exact sign could not be had.
int only_touch(const Triangle& A, const Triangle& B) {
  // Both triangles' lines are looked at whatever the first finds, so that the answer does not
  // depend on the argument order: 1 if some line has the other triangle certainly on its
  // outer side, else 2 if some sign was uncertain.
  bool uncertain = false;
  for (const auto& [T, O] : {std::pair{&A, &B}, std::pair{&B, &A}}) {
    const Triangle& t = *T;
    const int o = detail::orient2d_sign(t[0].x, t[0].y, t[1].x, t[1].y, t[2].x, t[2].y);
    if (o == 2 || o == 0) {
      uncertain = true;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = t[kEdgeFrom[k]], b = t[kEdgeTo[k]];
      bool outside = true, certain = true;
      for (const Vec2& p : *O) {
        const int side = detail::orient2d_sign(a.x, a.y, b.x, b.y, p.x, p.y);
        certain &= side != 2;
        outside &= side * o <= 0;
      }
      if (outside && certain) return 1;
      uncertain |= !certain;
    }
  }
  return uncertain ? 2 : 0;
}

// The exponent k by which solve() scales the input (coordinates times 2^k) where make_frame
// asks for it: the larger triangle's size to about 1.
inline int rescale_exponent(const Frame& fr) { return -(std::ilogb(fr.size_squared_max) / 2); }

// The double kernel with what certifies its result, as in 3D: a quick exit for disjoint
// bounding boxes (boxes_disjoint); the input scaled into the range the kernel is made for
// (rescale.hpp; `scale` receives the exponent k, results scale back by 2^(2k) and 2^(3k)); if
// the labels do not close, the other triangle as the reference, which rounds differently. The
// exact last resort (counted in stats) when
//  - the frame is flat or not finite in doubles although the input is finite (a triangle far
//    smaller than its distance from the origin, say);
//  - the labels do not close with either reference;
//  - the corners enclose a computed area that is not positive, and the triangles do not only
//    touch (only_touch, exact and cheap, decides the usual case of a tangent contact: empty),
//    or an area that is not finite;
//  - the area exceeds the smaller triangle's (|det| / 2, accurate to 1e-14, shape_quality) by
//    more than 1e-12 of it;
//  - the check (tri_clip_check.hpp) does not put the area, or an empty result, within 2^-42 of
//    the smaller triangle of the exact one.
// Every test is on numbers all entry points compute alike, so they all take the same way.
template <bool kMoments>
Outcome solve(const Triangle& A_in, const Triangle& B_in, Frame& fr, KernelResult& res, int& scale,
              TriIntersectionStats* stats) {
  res.num_corners = 0;
  res.ref_area = 0.0;
  scale = 0;
  if (boxes_disjoint(A_in, B_in)) return Outcome::empty;
  Triangle scaled_a, scaled_b;
  const Triangle* As = &A_in;
  const Triangle* Bs = &B_in;
  FrameStatus status = make_frame(A_in, B_in, fr);
  if (status == FrameStatus::rescale) [[unlikely]] {
    // Scale the larger triangle's size to about 1; the smaller one must then be in range too.
    if (!finite(A_in) || !finite(B_in)) return Outcome::empty;
    if (stats) ++stats->rescaled;
    scale = rescale_exponent(fr);
    if (!detail::scaled_exactly(&A_in[0].x, 6, scale, &scaled_a[0].x) ||
        !detail::scaled_exactly(&B_in[0].x, 6, scale, &scaled_b[0].x))
      return Outcome::exact;
    As = &scaled_a;
    Bs = &scaled_b;
    status = make_frame(*As, *Bs, fr);
    if (status == FrameStatus::rescale) return Outcome::exact;  // sizes 2^500 apart
  }
  if (status != FrameStatus::ok) {
    // Non-finite input is empty (the documented contract); a frame that fails on finite input
    // is a triangle that is flat in doubles: exactly flat ones are empty in exact arithmetic too.
    return finite(A_in) && finite(B_in) ? Outcome::exact : Outcome::empty;
  }
  // A doubled area below 2^-969 has fewer than 53 significant bits above the subnormal range:
  // the products of differences it (and the kernel's coordinates) are made of round to absolute
  // multiples of 2^-1074, not relative to the area, and the result could exceed the smaller
  // triangle by several units of that (a needle 1e-314 wide). Exact arithmetic rounds once.
  if (!(std::min(std::abs(fr.det2), std::abs(fr.det2_sub)) >= 0x1p-969)) [[unlikely]]
    return Outcome::exact;
  if (stats && fr.swapped) ++stats->reference_swaps;
  bool ok = run_kernel<kMoments>(fr, res, stats);
  if (!ok) {
    if (stats) {  // as in 3D: every attempt whose labels do not close is an inconsistency
      ++stats->inconsistencies;
      ++stats->retries;
    }
    ok = make_frame(*As, *Bs, fr, true) == FrameStatus::ok && run_kernel<kMoments>(fr, res, stats);
    if (!ok) {
      if (stats) ++stats->inconsistencies;
      return Outcome::exact;
    }
  }
  // The kernel's result stands only where the clipping's derived bound (tri_clip_check.hpp)
  // puts it within 2^-42 of the smaller triangle of the exact area; a tangent contact that
  // only_touch decides exactly needs no bound.
  const auto stands = [&](double result) {
    const bool accepted = kernel_area_stands(fr.a_canonical, fr.b_canonical, result);
    if (stats) {
      ++stats->checked;
      stats->check_rejected += accepted ? 0 : 1;
    }
    return accepted;
  };
  if (res.num_corners == 0) return stands(0.0) ? Outcome::empty : Outcome::exact;
  const double area = res.ref_area * std::abs(res.frame_det);
  if (!(area > 0.0)) [[unlikely]]
    return only_touch(*As, *Bs) == 1 ? Outcome::empty : Outcome::exact;
  const double smaller = 0.5 * std::min(std::abs(fr.det2), std::abs(fr.det2_sub));
  if (!(area <= smaller * (1.0 + 1e-12)) || !(area < INFINITY)) return Outcome::exact;
  if (!stands(area)) return Outcome::exact;
  // Scaled back, an area in the subnormal range (or beyond the largest double) would be rounded
  // a second time, which can make it 0 (or infinite) where the exact area does not round to
  // that: exact arithmetic rounds it once.
  if (scale != 0) {
    const double back = std::ldexp(area, -2 * scale);
    if (!(back >= 0x1p-1022) || !(back < INFINITY)) return Outcome::exact;
  }
  return Outcome::kernel;
}

Moments2 original_moments(const Frame& fr, const KernelResult& res) {
  Moments2 m;
  const double scale = std::abs(res.frame_det);
  m.area = res.ref_area * scale;
  const Triangle& r = res.sub_frame ? *fr.sub : *fr.ref;
  const Vec2 a1 = r[1] - r[0], a2 = r[2] - r[0];
  m.first = m.area * r[0] + scale * (res.ref_first[0] * a1 + res.ref_first[1] * a2);
  return m;
}

}  // namespace
}  // namespace detail2

// Fills a Polygon from the kernel's result: corners counter-clockwise in the original
// coordinates (the kernel's order is counter-clockwise in the frame of Y, which a negatively
// oriented reference reverses), exact input vertices where a corner is one, labels and
// barycentric coordinates relative to the caller's argument order. `scale`: the exponent the
// input was scaled by (solve), undone here.
// A template on the kernel variant only so that each variant's copy of these inline functions
// has its own name (src/kernel/entry_points.hpp, "Linkage").
template <class Variant>
struct PolygonBuilder {
  static void fill(Polygon& P, const detail2::Frame& fr, const detail2::KernelResult& res, int scale) {
    using detail2::RawCorner;
    const int n = res.num_corners;
    P.num_corners_ = n;
    P.touched_b_ = 0;
    if (n == 0) return;
    const Triangle& r = *fr.ref;
    const Triangle& s = *fr.sub;
    const Vec2 a1 = r[1] - r[0], a2 = r[2] - r[0];
    const bool reverse = fr.det2 < 0.0;
    const Triangle& B = fr.swapped ? s : r;
    for (int k = 0; k < n; ++k) {
      const RawCorner& rc = res.corners[res.order[reverse ? n - 1 - k : k]];
      PolygonCorner& out = P.corners_[static_cast<std::size_t>(k)];
      if (rc.kind == detail2::kVertexOfX) {
        out.point = s[rc.index];
      } else if (rc.kind == detail2::kVertexOfY) {
        out.point = r[rc.index];
      } else if (res.sub_frame) {
        // X is the smaller triangle: the crossing from its weight along X's edge, accurate
        // relative to X (the frame of Y resolves it only to eps times Y's size). The weight and
        // the coordinates in Y describe the same point to that accuracy: both come from the
        // same coordinates of the edge's ends, recomputed accurately where needed.
        const int e = rc.index / 3;
        const Vec2 from = s[detail2::kEdgeFrom[e]], to = s[detail2::kEdgeTo[e]];
        out.point = from + rc.weight_b * (to - from);
      } else {
        out.point = r[0] + (rc.bary[1] * a1 + rc.bary[2] * a2);
      }
      if (scale != 0) out.point = {std::ldexp(out.point.x, -scale), std::ldexp(out.point.y, -scale)};
      // Kernel labels in canonical numbering -> the caller's vertex numbering of each triangle.
      const auto to_caller = [&fr](int l) { return l < 3 ? int(fr.sub_perm[l]) : 3 + int(fr.ref_perm[l - 3]); };
      int l0 = to_caller(rc.in), l1 = to_caller(rc.out);
      if (fr.swapped) {
        l0 = (l0 + 3) % 6;
        l1 = (l1 + 3) % 6;
      }
      out.labels = {static_cast<std::uint8_t>(std::min(l0, l1)), static_cast<std::uint8_t>(std::max(l0, l1))};
      if (!fr.swapped) {
        for (int p = 0; p < 3; ++p) out.bary[fr.ref_perm[p]] = rc.bary[p];
        continue;
      }
      // The reference was A, so B is X: its coordinates of a vertex of X or of a crossing on
      // an edge of X are exact unit vectors or the crossing's weights; only a vertex of A
      // inside B needs a change of coordinates.
      double b[3] = {0.0, 0.0, 0.0};
      if (rc.kind == detail2::kVertexOfX) {
        b[rc.index] = 1.0;
      } else if (rc.kind == detail2::kEdgeOfX) {
        const int e = rc.index / 3;
        b[detail2::kEdgeFrom[e]] = 1.0 - rc.weight_b;
        b[detail2::kEdgeTo[e]] = rc.weight_b;
      } else {
        // B's determinant as shape_quality has it (accurate for a needle too), and the vertex's
        // coordinates accurately: a vertex of A inside a needle B.
        const detail2::BarycentricMap map(B, fr.det2_sub);
        map.accurate(r[rc.index], b);
        double sum = 0.0;
        for (double& v : b) {
          v = v > 0.0 ? v : 0.0;  // the corner is in B by construction
          sum += v;
        }
        for (double& v : b) v = sum > 0.0 ? v / sum : 1.0 / 3.0;
      }
      for (int p = 0; p < 3; ++p) out.bary[fr.sub_perm[p]] = b[p];  // B is X, canonically numbered
    }
    touched_edges(P);
    P.moments_ = detail2::original_moments(fr, res);
    if (scale != 0) {
      P.moments_.area = std::ldexp(P.moments_.area, -2 * scale);
      P.moments_.first = {std::ldexp(P.moments_.first.x, -3 * scale), std::ldexp(P.moments_.first.y, -3 * scale)};
    }
  }

  // The certified formula's area and first moments (tri_certified_moments.hpp) replace the
  // kernel's, which they agree with to the kernel's accuracy, so that every entry point gives
  // the same bits.
  static void set_moments(Polygon& P, const Moments2& m) { P.moments_ = m; }

  // The polygon of a certified result, from the formula's own parts (tri_certified_moments.hpp)
  // instead of the kernel: its signs are all certain there, so the parts are the exact
  // intersection's sides, in the same order. The boundary is walked counter-clockwise: after
  // S's part on edge f comes L's part on the line it ends on (or S's part on edge f + 1, from
  // S's vertex f + 1); after L's part on edge e, S's part that starts on line e (or L's part on
  // edge e + 1). Each corner starts one part: a vertex of S or L (exact input), or a crossing
  // of S's edge f, at its weight t along f (its point as the kernel makes one on the smaller
  // triangle's edge). Labels and barycentric coordinates in B, in the caller's numbering, with
  // the coordinate of B's vertex opposite an edge the corner lies on exactly 0: where B is S, a
  // crossing's are its weight along S's edge; where B is L, S's vertices' coordinates in L
  // interpolated with that weight (crossing_coordinates); a vertex of one triangle inside the
  // other gets its orientations over the determinant, clamped to >= 0 and summing to 1, as the
  // kernel does. False (the kernel then builds it) if the walk does not close within the corners
  // it may have (never seen).
  static bool fill_certified(Polygon& P, const detail2::CertifiedShape& sh, const Moments2& m) {
    const detail2::certified::Canonical& S = sh.S;
    const detail2::certified::Canonical& L = sh.L;
    const int s_base = sh.s_is_a ? 0 : 3, l_base = sh.s_is_a ? 3 : 0;
    // Edge k (from p[k] to p[k + 1]) is the caller's edge opposite p[k + 2].
    const auto s_edge = [&](int f) { return s_base + S.index[(f + 2) % 3]; };
    const auto l_edge = [&](int e) { return l_base + L.index[(e + 2) % 3]; };
    const bool b_is_s = !sh.s_is_a;
    const detail2::certified::Canonical& Bc = b_is_s ? S : L;
    // A vertex of the other triangle inside B: orientations against B's edge lines, which
    // are the coordinates times det(B) (coordinate v: the edge opposite v, edge v + 1).
    const auto inside_coordinates = [&](const double (&g)[3][3], int i, double (&b)[3]) {
      double sum = 0.0;
      for (int v = 0; v < 3; ++v) {
        b[v] = std::max(g[(v + 1) % 3][i] / Bc.det, 0.0);
        sum += b[v];
      }
      for (double& v : b) v = sum > 0.0 ? v / sum : 1.0 / 3.0;
    };
    // A crossing of S's edge f (weight t) with L's edge k, in L's coordinates: those of S's
    // vertices f and f + 1 interpolated with t, as the point is (a weight along L's edge from
    // the orientations of its ends would be far less accurate where the edges are nearly
    // parallel), the one of L's vertex opposite edge k exactly 0.
    const auto crossing_coordinates = [&](int f, double t, int k, double (&b)[3]) {
      const int g = (f + 1) % 3;
      double sum = 0.0;
      for (int v = 0; v < 3; ++v) {
        const int line = (v + 1) % 3;
        const double c = v == (k + 2) % 3 ? 0.0 : ((1.0 - t) * sh.gl[line][f] + t * sh.gl[line][g]) / L.det;
        b[v] = std::max(c, 0.0);
        sum += b[v];
      }
      if (!(sum > 0.0)) {  // (never: the point lies on L's edge k) its midpoint
        b[k] = b[(k + 1) % 3] = 0.5;
        sum = 1.0;
      }
      for (double& v : b) v /= sum;
    };
    // The crossing of S's edge f with L's line k at weight t along f: its point, its labels,
    // its coordinates in B.
    const auto crossing = [&](int f, double t, int k, PolygonCorner& out, double (&b)[3], int& la, int& lb) {
      const int g = (f + 1) % 3;
      out.point = S.p[f] + t * (S.p[g] - S.p[f]);
      la = s_edge(f);
      lb = l_edge(k);
      if (b_is_s) {
        b[f] = 1.0 - t;
        b[g] = t;
      } else {
        crossing_coordinates(f, t, k, b);
      }
    };
    int n = 0;
    // Segments: 0-2 S's parts, 3-5 L's parts (3 + e).
    int first = -1;
    for (int e = 0; e < 3 && first < 0; ++e)
      if (sh.start_f[e] >= 0 || sh.l_inside[e]) first = 3 + e;
    for (int f = 0; f < 3 && first < 0; ++f)
      if (sh.part[f].nonempty) first = f;
    if (first < 0) return false;
    int seg = first;
    do {
      if (n == Polygon::max_corners) return false;
      PolygonCorner& out = P.corners_[static_cast<std::size_t>(n++)];
      double b[3] = {0.0, 0.0, 0.0};  // in B's canonical order
      int la, lb;
      if (seg < 3) {
        const int f = seg;
        const detail2::certified::EdgePart& part = sh.part[f];
        if (part.k0 >= 0) {  // where S's edge f enters L, across L's line k0
          crossing(f, part.t0, part.k0, out, b, la, lb);
        } else {  // S's vertex f
          out.point = S.p[f];
          la = s_edge((f + 2) % 3);
          lb = s_edge(f);
          if (b_is_s)
            b[f] = 1.0;
          else
            inside_coordinates(sh.gl, f, b);
        }
        seg = part.k1 >= 0 ? 3 + part.k1 : (f + 1) % 3;
      } else {
        const int e = seg - 3;
        const int fs = sh.start_f[e];
        if (fs >= 0) {  // where S's part on edge fs ends, on L's line e
          crossing(fs, sh.part[fs].t1, e, out, b, la, lb);
        } else {  // L's vertex e
          out.point = L.p[e];
          la = l_edge((e + 2) % 3);
          lb = l_edge(e);
          if (b_is_s)
            inside_coordinates(sh.gs, e, b);
          else
            b[e] = 1.0;
        }
        seg = sh.end_f[e] >= 0 ? sh.end_f[e] : 3 + (e + 1) % 3;
      }
      out.labels = {static_cast<std::uint8_t>(std::min(la, lb)), static_cast<std::uint8_t>(std::max(la, lb))};
      for (int v = 0; v < 3; ++v) out.bary[static_cast<std::size_t>(Bc.index[v])] = b[v];
    } while (seg != first);
    P.num_corners_ = n;
    touched_edges(P);
    P.moments_ = m;
    return true;
  }

  // The exact last resort's polygon (exact_fallback.hpp): already in the caller's numbering.
  static void fill_exact(Polygon& P, const detail::ExactPolygon& x) {
    P.num_corners_ = x.num_corners;
    for (int k = 0; k < x.num_corners; ++k) {
      PolygonCorner& out = P.corners_[static_cast<std::size_t>(k)];
      out.point = x.point[k];
      out.bary = {x.bary[k][0], x.bary[k][1], x.bary[k][2]};
      out.labels = {x.labels[k][0], x.labels[k][1]};
    }
    touched_edges(P);
    P.moments_ = x.moments;
  }

  // Sides: between consecutive corners, on the line both carry (the one corner k leaves by).
  // A side on a line of B touches that edge; a side on an edge of A touches the edge of B
  // whose coordinate is exactly zero at both of its ends (a shared or collinear edge).
  static void touched_edges(Polygon& P) {
    const int n = P.num_corners_;
    P.touched_b_ = 0;
    for (int k = 0; k < n; ++k) {
      const PolygonCorner& c0 = P.corners_[static_cast<std::size_t>(k)];
      const PolygonCorner& c1 = P.corners_[static_cast<std::size_t>((k + 1) % n)];
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          const int l = c0.labels[static_cast<std::size_t>(a)];
          if (l != c1.labels[static_cast<std::size_t>(b)]) continue;
          if (l >= 3) {
            P.touched_b_ |= 1u << (l - 3);
            continue;
          }
          for (int p = 0; p < 3; ++p)
            if (c0.bary[static_cast<std::size_t>(p)] == 0.0 && c1.bary[static_cast<std::size_t>(p)] == 0.0)
              P.touched_b_ |= 1u << p;
        }
    }
  }
};

namespace detail::TETIA_KERNEL_VARIANT {

struct TriTag {};  // names this variant's PolygonBuilder
using Builder = PolygonBuilder<TriTag>;

// Every entry point first tries the certified formula (tri_certified_moments.hpp) on pairs
// whose boxes overlap: where it decides, its area and first moments are the result, bit for
// bit the same from every entry point (the polygon's corners, where asked for, still come from
// the kernel); elsewhere the kernel decides, as before.
template <bool kFirst>
detail2::Certified certified_first(const Triangle& A, const Triangle& B, Moments2& m) {
  if (detail2::boxes_disjoint(A, B)) return detail2::Certified::kSeparated;
  return detail2::certified_moments<kFirst>(A, B, m);
}

// tetia::intersect (2D).
Polygon tri_intersect(const Triangle& A, const Triangle& B, TriIntersectionStats* stats) {
  Polygon P;
  if (stats) ++stats->calls;
  if (detail2::boxes_disjoint(A, B)) return P;
  Moments2 certified;
  detail2::CertifiedShape shape;
  const detail2::Certified how = detail2::certified_moments<true>(A, B, certified, &shape);
  if (stats && how != detail2::Certified::kUncertain) ++stats->certified;
  if (how == detail2::Certified::kSeparated) return P;
  if (how == detail2::Certified::kCertified && Builder::fill_certified(P, shape, certified)) return P;
  detail2::Frame fr;
  detail2::KernelResult res;
  int scale = 0;
  switch (detail2::solve<true>(A, B, fr, res, scale, stats)) {
    case detail2::Outcome::empty:
      // Not where the formula certified an area (at least 2^-30 of the smaller triangle, within
      // 2^-47 of it; the kernel is within 1e-12): the exact polygon, should it ever happen.
      if (how == detail2::Certified::kCertified) {
        if (stats) ++stats->exact_fallbacks;
        ExactPolygon x;
        exact_polygon(A, B, x);
        Builder::fill_exact(P, x);
      }
      break;
    case detail2::Outcome::kernel:
      Builder::fill(P, fr, res, scale);
      break;
    case detail2::Outcome::exact: {
      if (stats) ++stats->exact_fallbacks;
      ExactPolygon x;
      exact_polygon(A, B, x);
      Builder::fill_exact(P, x);
      break;
    }
  }
  if (how == detail2::Certified::kCertified) Builder::set_moments(P, certified);
  return P;
}

// tetia::intersection_moments (2D).
Moments2 tri_moments(const Triangle& A, const Triangle& B) {
  Moments2 certified;
  switch (certified_first<true>(A, B, certified)) {
    case detail2::Certified::kSeparated:
      return {};
    case detail2::Certified::kCertified:
      return certified;
    case detail2::Certified::kUncertain:
      break;
  }
  detail2::Frame fr;
  detail2::KernelResult res;
  int scale = 0;
  switch (detail2::solve<true>(A, B, fr, res, scale, nullptr)) {
    case detail2::Outcome::empty:
      return {};
    case detail2::Outcome::kernel: {
      Moments2 m = detail2::original_moments(fr, res);
      if (scale != 0) m = {std::ldexp(m.area, -2 * scale), {std::ldexp(m.first.x, -3 * scale), std::ldexp(m.first.y, -3 * scale)}};
      return m;
    }
    case detail2::Outcome::exact:
      break;
  }
  ExactPolygon x;
  exact_polygon(A, B, x);
  return x.moments;
}

// tetia::intersection_area.
double tri_area(const Triangle& A, const Triangle& B) {
  Moments2 certified;
  switch (certified_first<false>(A, B, certified)) {
    case detail2::Certified::kSeparated:
      return 0.0;
    case detail2::Certified::kCertified:
      return certified.area;
    case detail2::Certified::kUncertain:
      break;
  }
  detail2::Frame fr;
  detail2::KernelResult res;
  int scale = 0;
  switch (detail2::solve<false>(A, B, fr, res, scale, nullptr)) {
    case detail2::Outcome::empty:
      return 0.0;
    case detail2::Outcome::kernel: {
      const double area = res.ref_area * std::abs(res.frame_det);
      return scale == 0 ? area : std::ldexp(area, -2 * scale);
    }
    case detail2::Outcome::exact:
      break;
  }
  ExactPolygon x;
  exact_polygon(A, B, x);
  return x.moments.area;
}

}  // namespace detail::TETIA_KERNEL_VARIANT

}  // namespace tetia
