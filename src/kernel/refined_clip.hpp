// src/kernel/refined_clip.hpp -- the intersection's volume and first moments accurate relative
// to the smaller tetrahedron, for the pairs whose double result the kernel cannot certify to
// 1e-12 of it (a size ratio far from 1, a sliver): docs/architecture.md, "Accuracy relative to
// the smaller tetrahedron".
//
// Why a second method: the kernel's corners are resolved to eps of the reference's frame, so
// relative to a much smaller or much thinner tetrahedron its error is eps times the size ratio
// or eps over the shape quality; either frame loses that much in doubles. Here the frame is the
// smaller tetrahedron S's own barycentric coordinates, where S is the unit simplex whatever its
// size or shape, and each face plane j of the other tetrahedron B enters only through its four
// values at S's vertices, D[j][k] = orient3d(face j of B, s_k), evaluated in doubles where their
// error bound certifies them and in double-double from exact differences where not (planes
// nearly parallel to a sliver, far planes of a much bigger B). Plane j is the zero set of the
// linear function sum_k lambda_k D[j][k] of the barycentric coordinates lambda of S, so clipping
// the unit simplex by the four half-spaces D >= 0 gives S n B, up to the error of the D's
// (certified below 2^-47) and the rounding of the clipping itself, whose coordinates lie in
// [0, 1]: no ratio in them. What the clipping computes is then bounded from the computed
// polytope itself (clip_bound, derived below, not calibrated). The volume is the clipped volume
// times |det6(S)|, that determinant certified alike (a sliver's det6 in doubles is off by eps
// over its quality).
//
// Contract: refined_det6(t, det6) computes det6(t) = det[t1 - t0, t2 - t0, t3 - t0] to 2^-47 of
// itself, or returns false. refined_moments(S, B, det6_B, out) fills the volume and first
// moments of S n B and returns true only where the volume's error is certified: by the
// near-cover formula's derived bound (at most 2^-44 of S's volume; where every plane of B cuts
// at most a thin part off S it decides first, without clipping), by the clipping's derived
// bound (clip_bound or thin_bound, at most 2^-42 of S), or, for an empty result, by one plane of
// B keeping at most 2^-42 of S or by a plane separating S and B (separation.hpp). Each needs
// det6(S) and every D certified to 2^-47 of the largest of their plane (doubles where they
// suffice, double-double where not), which holds for size ratios up to about 2^50. False
// otherwise: the caller takes the exact last resort. The first moments carry no bound of their
// own. det6_B, B's det6 in doubles, gives only the sign of B's orientation (B is not flat to
// rounding: the caller checked its quality). Sizes within the kernel's range (frame.hpp's
// FrameStatus): an overflow is never certified. Allocation-free; not the hot path (one to two
// microseconds).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "exact_sign.hpp"  // two_sum, two_diff, two_product
#include "fan.hpp"
#include "separation.hpp"
#include "tetia/geometry.hpp"
#include "tetia/polyhedron.hpp"

namespace tetia::detail {

// Internal linkage, like the kernel's other steps: each kernel variant (entry_points.hpp) has
// its own copy, compiled for its instruction set, which no other object file can bind to.
namespace {

namespace refined_impl {

// A double-double: hi + lo with |lo| <= ulp(hi) / 2.
struct DD {
  double hi, lo;
};

inline DD fast_two_sum(double a, double b) {  // |a| >= |b| or a == 0
  const double s = a + b;
  return {s, b - (s - a)};
}

inline DD dd_diff(double a, double b) {  // a - b exactly
  DD r;
  exact_sign_impl::two_diff(a, b, r.hi, r.lo);
  return r;
}

// Products and sums of double-doubles, each with a relative error below 4 2^-106 of the
// magnitudes involved (|a| |b| for a product, |a| + |b| for a sum): the terms dropped are
// a.lo b.lo and the roundings of the low parts.
inline DD dd_mul(DD a, DD b) {
  double p, e;
  exact_sign_impl::two_product(a.hi, b.hi, p, e);
  e += a.hi * b.lo + a.lo * b.hi;
  return fast_two_sum(p, e);
}

inline DD dd_add(DD a, DD b) {
  double s, e, t, f;
  exact_sign_impl::two_sum(a.hi, b.hi, s, e);
  exact_sign_impl::two_sum(a.lo, b.lo, t, f);
  e += t;
  const DD u = fast_two_sum(s, e);
  return fast_two_sum(u.hi, u.lo + f);
}

inline DD dd_neg(DD a) { return {-a.hi, -a.lo}; }

// orient3d(a, b, c, d) = det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a), and its
// permanent P (the same products in absolute value). In doubles the error is below
// kDoubleError P: the differences carry one rounding each, the cross product's terms one more
// and its difference another (4 u of its terms, u = 2^-53), the product with d - a two more and
// the dot product's two sums one each: 8 u P to first order, and 2^-49 = 16 u allows for the
// rest. In double-double from the exact differences the error is below kDoubleDoubleError P:
// each product and sum of double-doubles is within 4 u^2 of the magnitudes involved, 20 u^2 in
// all (2^-101.7), and 2^-98 allows for the rest.
constexpr double kDoubleError = 0x1p-49;
constexpr double kDoubleDoubleError = 0x1p-98;

// The face's normal (b - a) x (c - a), in doubles (n) and in double-double (dd, filled by
// refine()), with its terms in absolute value for the permanent.
struct Face {
  Vec3 a, b, c;
  double n[3];
  double abs_terms[3];
  DD dd[3];

  Face(const Vec3& a_, const Vec3& b_, const Vec3& c_) : a(a_), b(b_), c(c_) {
    const Vec3 u = b - a, v = c - a;
    n[0] = u.y * v.z - u.z * v.y;
    n[1] = u.z * v.x - u.x * v.z;
    n[2] = u.x * v.y - u.y * v.x;
    abs_terms[0] = std::abs(u.y * v.z) + std::abs(u.z * v.y);
    abs_terms[1] = std::abs(u.z * v.x) + std::abs(u.x * v.z);
    abs_terms[2] = std::abs(u.x * v.y) + std::abs(u.y * v.x);
  }

  void refine() {
    const DD ux = dd_diff(b.x, a.x), uy = dd_diff(b.y, a.y), uz = dd_diff(b.z, a.z);
    const DD vx = dd_diff(c.x, a.x), vy = dd_diff(c.y, a.y), vz = dd_diff(c.z, a.z);
    dd[0] = dd_add(dd_mul(uy, vz), dd_neg(dd_mul(uz, vy)));
    dd[1] = dd_add(dd_mul(uz, vx), dd_neg(dd_mul(ux, vz)));
    dd[2] = dd_add(dd_mul(ux, vy), dd_neg(dd_mul(uy, vx)));
  }

  // orient3d(a, b, c, d) in doubles, with its permanent (enlarged by 2^-50 of itself for the
  // rounding of the permanent's own evaluation).
  double orient(const Vec3& d, double& permanent) const {
    const Vec3 w = d - a;
    permanent = (abs_terms[0] * std::abs(w.x) + abs_terms[1] * std::abs(w.y) + abs_terms[2] * std::abs(w.z)) *
                (1.0 + 0x1p-50);
    return (n[0] * w.x + n[1] * w.y) + n[2] * w.z;
  }

  // orient3d(a, b, c, d) in double-double (after refine()), rounded to a double.
  double orient_refined(const Vec3& d) const {
    const DD wx = dd_diff(d.x, a.x), wy = dd_diff(d.y, a.y), wz = dd_diff(d.z, a.z);
    const DD s = dd_add(dd_add(dd_mul(dd[0], wx), dd_mul(dd[1], wy)), dd_mul(dd[2], wz));
    return s.hi + s.lo;
  }
};

// Each orientation is wanted to 2^-47 of the largest of its plane's four (the plane's position
// in S's frame to about that relative to S): doubles where their bound allows it, double-double
// where not; false where neither does (the exact last resort decides).
constexpr double kWanted = 0x1p-47;

// The four orientations of face f at the points p[0..3] (out), to kWanted of the largest, and
// each one's own error bound (error[k]: |out[k] - exact| <= error[k]).
inline bool certified_orientations(Face& f, const Vec3* p, int count, double* out, double* error) {
  double largest = 0.0, permanent = 0.0, perm[4];
  for (int k = 0; k < count; ++k) {
    out[k] = f.orient(p[k], perm[k]);
    error[k] = kDoubleError * perm[k] + 0x1p-1000;  // 2^-1000: roundings in the subnormal range
    permanent = std::max(permanent, perm[k]);
    largest = std::max(largest, std::abs(out[k]));
  }
  if (kDoubleError * permanent <= kWanted * largest) return true;
  f.refine();
  largest = 0.0;
  for (int k = 0; k < count; ++k) {
    largest = std::max(largest, std::abs(out[k] = f.orient_refined(p[k])));
    // The double-double's bound, 2^-1000 for what underflow can take from its low parts, and
    // the rounding of hi + lo to a double (half an ulp: 2^-53 of the value).
    error[k] = (kDoubleDoubleError * perm[k] + 0x1p-1000) + 0x1p-53 * std::abs(out[k]);
  }
  return kDoubleDoubleError * permanent + 0x1p-1000 <= kWanted * largest;
}

// The clipped polytope: a simple polytope (three edges at every vertex), each vertex's
// neighbours in one rotational order, as in r3d's representation; positions are barycentric
// coordinates in S (four, summing to 1 up to rounding). Clipped vertices are only marked dead
// (no compaction): four planes add at most 4 x 12 vertices to the simplex's 4.
struct ClipPoly {
  static constexpr int kMax = 64;
  double lam[kMax][4];
  int nbr[kMax][3];
  bool dead[kMax];
  // The planes a vertex lies on by construction: bit k (0..3) the face lambda_k = 0 of S, bit
  // 4 + j plane j of B (a new vertex: those its edge's two ends share, and the plane that made
  // it). A face lies on the planes all its vertices share (clip_bound).
  unsigned char planes[kMax];
  int n = 0;
  bool failed = false;  // the structure broke (never for a simple polytope): not certified
};

inline void unit_simplex(ClipPoly& P) {
  // Neighbours in the order with det[n0 - v, n1 - v, n2 - v] < 0 in (lambda1, lambda2,
  // lambda3), the same rotational sense at every vertex.
  static constexpr int kNbr[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  P.n = 4;
  for (int v = 0; v < 4; ++v) {
    for (int k = 0; k < 4; ++k) P.lam[v][k] = v == k ? 1.0 : 0.0;
    for (int i = 0; i < 3; ++i) P.nbr[v][i] = kNbr[v][i];
    P.dead[v] = false;
    P.planes[v] = static_cast<unsigned char>(0xFu & ~(1u << v));
  }
}

// Keeps the part of P where sum_k lambda_k d[k] >= 0 (plane `plane` of B, 0..3). Returns false
// if nothing is left with a positive value (the polytope is empty or flat). A vertex with value
// 0 is kept; new vertices are made on the edges from a kept vertex to a removed one, then linked
// around the new face.
inline bool clip(ClipPoly& P, const double (&d)[4], int plane) {
  double sd[ClipPoly::kMax];
  bool any_out = false, any_pos = false;
  for (int v = 0; v < P.n; ++v) {
    if (P.dead[v]) continue;
    const double* l = P.lam[v];
    sd[v] = ((l[0] * d[0] + l[1] * d[1]) + l[2] * d[2]) + l[3] * d[3];
    any_out |= sd[v] < 0.0;
    any_pos |= sd[v] > 0.0;
  }
  if (!any_pos) return false;
  if (!any_out) return true;
  const int old_n = P.n;
  for (int v = 0; v < old_n; ++v) {
    if (P.dead[v] || sd[v] < 0.0) continue;
    for (int i = 0; i < 3; ++i) {
      const int w = P.nbr[v][i];
      if (w >= old_n || !(sd[w] < 0.0)) continue;
      if (P.n == ClipPoly::kMax) {
        P.failed = true;
        return false;
      }
      const int m = P.n++;
      // t in [0, 1): sd[v] >= 0 > sd[w]; the point is a convex combination of v and w.
      const double t = sd[v] / (sd[v] - sd[w]);
      for (int k = 0; k < 4; ++k) P.lam[m][k] = P.lam[v][k] + t * (P.lam[w][k] - P.lam[v][k]);
      P.nbr[m][0] = v;
      P.nbr[m][1] = P.nbr[m][2] = -1;
      P.dead[m] = false;
      P.planes[m] = static_cast<unsigned char>((P.planes[v] & P.planes[w]) | 1u << (4 + plane));
      P.nbr[v][i] = m;
    }
  }
  // Link the new vertices: from new vertex m along the face on one side of its edge to v, the
  // walk around that face through kept vertices reaches the next new vertex.
  for (int m = old_n; m < P.n; ++m) {
    int prev = m, cur = P.nbr[m][0];
    for (int guard = 0; cur < old_n; ++guard) {
      int j = 0;
      while (j < 3 && P.nbr[cur][j] != prev) ++j;
      if (j == 3 || guard == ClipPoly::kMax) {
        P.failed = true;
        return false;
      }
      prev = cur;
      cur = P.nbr[cur][(j + 1) % 3];
    }
    P.nbr[m][2] = cur;
    P.nbr[cur][1] = m;
  }
  for (int v = 0; v < old_n; ++v) P.dead[v] = P.dead[v] || sd[v] < 0.0;
  return true;
}

// The faces of the clipped polytope, each a cycle of vertices from its first, walked along the
// neighbours' rotational order (every directed edge once: each face once, with the same
// orientation), in the order of their first directed edge (vertex, then neighbour slot).
struct ClipFaces {
  static constexpr int kMaxFaces = ClipPoly::kMax;
  int count = 0;
  int start[kMaxFaces + 1];
  int vertex[3 * ClipPoly::kMax];  // each vertex is on three faces
};

// False where the walk does not close (a broken structure; never for a simple polytope).
inline bool walk_faces(const ClipPoly& P, ClipFaces& F) {
  std::uint64_t used[3] = {0, 0, 0};  // bit v of used[i]: the directed edge v -> nbr[v][i] walked
  F.count = 0;
  F.start[0] = 0;
  int total = 0;
  for (int v0 = 0; v0 < P.n; ++v0)
    for (int i0 = 0; i0 < 3; ++i0) {
      if (P.dead[v0] || (used[i0] >> v0 & 1u)) continue;
      if (F.count == ClipFaces::kMaxFaces) return false;
      int a = v0, ia = i0;
      do {
        if (total == 3 * ClipPoly::kMax) return false;
        used[ia] |= std::uint64_t{1} << a;
        F.vertex[total++] = a;
        const int b = P.nbr[a][ia];
        int j = 0;
        while (j < 3 && P.nbr[b][j] != a) ++j;
        if (j == 3) return false;
        a = b;
        ia = (j + 1) % 3;
      } while (!(a == v0 && ia == i0));
      F.start[++F.count] = total;
    }
  return true;
}

// The mean of the living vertices (lambda1..lambda3), the fans' apex; their number.
inline int vertex_mean(const ClipPoly& P, double (&o)[3]) {
  int alive = 0;
  o[0] = o[1] = o[2] = 0.0;
  for (int v = 0; v < P.n; ++v) {
    if (P.dead[v]) continue;
    ++alive;
    for (int c = 0; c < 3; ++c) o[c] += P.lam[v][c + 1];
  }
  if (alive > 0)
    for (double& x : o) x /= alive;
  return alive;
}

// Volume and first moments (in lambda1..lambda3, the unit simplex having volume 1/6) by fans
// over the faces (fan.hpp), each joined to the mean of the vertices and taken in absolute value
// (a convex polytope: every such pyramid is non-negative), as the kernel's fan_moments does.
// kMoments: the first moments too (the volume is the same number either way). vol6: six times
// the volume, before the division (clip_bound's evaluation bound is on it); fan_det: each fan
// triangle's six-fold volume, face by face in the walk's order, and o the fans' apex
// (clip_bound reuses both).
template <bool kMoments>
void clip_moments(const ClipPoly& P, const ClipFaces& F, double& vol, double (&first)[3], double& vol6,
                  double (&fan_det)[3 * ClipPoly::kMax], double (&o)[3]) {
  vol = vol6 = 0.0;
  first[0] = first[1] = first[2] = 0.0;
  if (vertex_mean(P, o) < 4) return;
  double m[3] = {0.0, 0.0, 0.0};
  int triangles = 0;
  const auto record = [&](double d) { fan_det[triangles++] = d; };
  for (int f = 0; f < F.count; ++f) {
    const int* face = F.vertex + F.start[f];
    double fv = 0.0, fm[3] = {0.0, 0.0, 0.0};
    fan_pyramids<kMoments>(o, F.start[f + 1] - F.start[f], [&](int k) { return P.lam[face[k]]; }, fv, fm, record);
    const double s = fv < 0.0 ? -1.0 : 1.0;
    vol6 += s * fv;
    if constexpr (kMoments)
      for (int c = 0; c < 3; ++c) m[c] += s * fm[c];
  }
  vol = vol6 / 6.0;
  for (int c = 0; c < 3; ++c) first[c] = m[c] / 24.0;
}

// --- the clipping's error bound (derived) -------------------------------------------------
//
// What the clipping computes is the volume of a closed triangulated surface Sigma: the fan
// triangles of its faces, corners the computed vertices x_v (lambda1..lambda3, exact doubles),
// each face a cycle of the clip's structure. Whatever the rounding that placed them, that volume
// (in exact arithmetic on the x_v) is the integral of Sigma's winding number w, for any apex o.
// The exact S n B, in S's frame, is P* = {x in the unit simplex : g*_j(x) >= 0, j = 0..3},
// g*_j the exact plane functions; the clipping used g_j, the same with the computed D (within E_j
// at each vertex of S). The bound rests on three facts, each checked on the computed surface:
//  (1) Every face lies on a plane: its vertices share a plane bit (ClipPoly::planes), and each
//      vertex lies within a computed distance of each plane of its bits: g_q(x_v) <= in_q for
//      the vertices on plane q, g_q(x_v) >= -out_q for all of them (q: the four faces of S,
//      g_q = lambda_q, and B's planes that the surface touches; in_q and out_q include E_q on
//      the grown simplex). Planes that no face lies on and that every vertex is certainly inside
//      of (beyond E_q) are left out.
//  (2) Every fan triangle with three distinct corners is certainly oriented alike seen from o,
//      the vertices' mean: det(a - o, b - a, c - a) beyond its rounding bound, with the sign of
//      the first (the walk's orientation: inwards for the neighbour order of unit_simplex; the
//      argument below is the same with w and the crossings negated).
//  (3') A few triangles may fail (2) (bad: corners near each other, no certain orientation even
//      in double-double, or a fold of the other orientation): the ray of (3) certainly misses
//      each (two of its edge determinants certainly differ in sign), which keeps w(o) = 1; the
//      rays through them (a solid angle of at most their area over the squared distance from o
//      to their face's slab) may cross Sigma more than once, where |w - w_R| <= 2 + 2 n_bad,
//      out to the farthest vertex: 4 (1 + n_bad) angle R^3 more (6-fold volume), and twice their
//      pyramids' volume for a face whose sum they could turn.
//  (3) One ray from o (towards the centroid of the largest triangle) crosses Sigma exactly once,
//      certainly: that triangle's three edge determinants with the ray are certainly positive,
//      every other triangle has one certainly negative, or its face lies on a plane q that the
//      ray certainly does not reach inside G (g_q grows along it from g_q(o) > in_q, or it
//      reaches {g_q <= in_q} only after it has left G through another plane's slab). And o is
//      certainly in I = {g_q > in_q for the planes kept}.
// By (2) every crossing of a ray from o with Sigma counts +1 in the winding number; by (3) and
// the cycle property (the signed count of crossings is the same, w(o), along every generic
// ray from o) every generic ray crosses exactly once, so w is 0 or 1 everywhere off Sigma and
// the computed volume is that of R = {w = 1}. Sigma misses the convex set I (each face is in
// {g_q <= in_q} of its plane) and I contains o, where w = 1: I lies in R. R lies in the convex
// hull of the vertices (w = 0 outside), hence in G = {lambda >= -rho} n {g_q >= -out_q}; and
// I <= P* <= G as well (in_q, out_q include E_q; the planes left out hold the hull, and I
// in R, strictly inside them). So |vol R - vol P*| <= vol(G \ I), which lies in the union of
// the slabs {-out_q <= g_q <= in_q} n G. A slab of width h across the simplex grown by rho has
// at most volume h / |grad| times the largest cross-section, at most the area of the projection,
// (1/4)(|n|_1 + |n1 + n2 + n3|) <= |n|_1 / 2 for the unit simplex and unit normal n, times
// (1 + 4 rho)^2: as a fraction of the simplex's 1/6, 3 h |grad|_1 / |grad|_2^2 (1 + 4 rho)^2.
// To that the rounding of the volume's own evaluation: each fan determinant within kDoubleError
// of its permanent (o-relative, as fan_pyramids evaluates it), the sums within 2 (T + 1) u of
// the sum of their magnitudes (T triangles). Evaluations of g_q at a point are bounded the same
// way (plane_value). The bound is a fraction of S's volume; infinite where a check fails.

// A plane as an affine function of x = (lambda1, lambda2, lambda3): g(x) = c0 + g . x.
struct ClipPlane {
  double c0, g[3];
  double data_error;  // |g* - g| on the unit simplex: the largest of its D's error bounds
  double slab;        // |g|_1 / |g|_2^2, rounded up (3 times this per unit width: a slab's fraction)
  double norm;        // |g|_2, rounded up
};

// g(x) within `bound` (see the top of this section: the sum of four terms, each with at most
// four roundings and g's own rounding from the D's, 5.0001 u of the sum of magnitudes; 7 u
// leaves room for the rounding of the magnitudes and of value -+ bound; 2^-1070 for underflow).
inline double plane_value(const ClipPlane& p, const double* x, double& bound) {
  bound = 0x1.cp-51 * (((std::abs(p.c0) + std::abs(p.g[0] * x[0])) + std::abs(p.g[1] * x[1])) +
                       std::abs(p.g[2] * x[2])) +
          0x1p-1070;
  return ((p.c0 + p.g[0] * x[0]) + p.g[1] * x[1]) + p.g[2] * x[2];
}

// Plane q = 0..3: S's face lambda_q = 0; q = 4..7: B's plane q - 4 with values d at S's
// vertices (lambda_0 = 1 - x1 - x2 - x3), each within e.
inline ClipPlane simplex_plane(int q) {
  ClipPlane p{q == 0 ? 1.0 : 0.0, {0.0, 0.0, 0.0}, 0.0, 1.0, q == 0 ? 1.7320508075688774 : 1.0};
  for (int k = 0; k < 3; ++k) p.g[k] = q == 0 ? -1.0 : (k + 1 == q ? 1.0 : 0.0);
  return p;
}

inline ClipPlane b_plane(const double (&d)[4], const double (&e)[4]) {
  ClipPlane p;
  p.c0 = d[0];
  double largest = 0.0;
  for (int k = 0; k < 3; ++k) {
    p.g[k] = d[k + 1] - d[0];
    largest = std::max(largest, std::abs(p.g[k]));
  }
  p.data_error = std::max(std::max(e[0], e[1]), std::max(e[2], e[3]));
  if (!(largest > 0.0 && largest < INFINITY)) {
    p.slab = p.norm = INFINITY;
    return p;
  }
  // |g|_1 / |g|_2^2, of g scaled by a power of two near 1 / largest where the squares would
  // leave the normal range (exact; the D's may be anywhere in the double range), scaled back.
  // g rounded (u of each entry): |g|_1 and |g|_2^2 within 4 u and 6 u of the exact gradient's.
  const bool in_range = largest > 0x1p-400 && largest < 0x1p400;
  const double scale = in_range ? 1.0 : std::ldexp(1.0, -std::ilogb(largest));
  double l1 = 0.0, l2 = 0.0;
  for (const double x : p.g) {
    const double y = x * scale;
    l1 += std::abs(y);
    l2 += y * y;
  }
  p.slab = (l1 / l2) * scale * (1.0 + 0x1p-48);
  p.norm = std::sqrt(l2) / scale * (1.0 + 0x1p-49);
  return p;
}

// det[u, v, w] as fan_pyramids evaluates it, and its permanent.
inline double det3(const double (&u)[3], const double (&v)[3], const double (&w)[3], double& permanent) {
  permanent = std::abs(u[0]) * (std::abs(v[1] * w[2]) + std::abs(v[2] * w[1])) +
              std::abs(u[1]) * (std::abs(v[0] * w[2]) + std::abs(v[2] * w[0])) +
              std::abs(u[2]) * (std::abs(v[0] * w[1]) + std::abs(v[1] * w[0]));
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

inline bool equal(const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

// det[a - o, b - a, c - a] in double-double from the exact differences, rounded to a double:
// within kDoubleDoubleError of the permanent (as orient_refined).
inline double det_refined(const double* o, const double* a, const double* b, const double* c) {
  DD u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = dd_diff(a[k], o[k]);
    v[k] = dd_diff(b[k], a[k]);
    w[k] = dd_diff(c[k], a[k]);
  }
  const DD n0 = dd_add(dd_mul(v[1], w[2]), dd_neg(dd_mul(v[2], w[1])));
  const DD n1 = dd_add(dd_mul(v[2], w[0]), dd_neg(dd_mul(v[0], w[2])));
  const DD n2 = dd_add(dd_mul(v[0], w[1]), dd_neg(dd_mul(v[1], w[0])));
  const DD s = dd_add(dd_add(dd_mul(u[0], n0), dd_mul(u[1], n1)), dd_mul(u[2], n2));
  return s.hi + s.lo;
}

// Whether u x r is certainly not 0 (u rounded from a difference: 4 u of each product covers it
// and the products' and the difference's roundings).
inline bool off_ray(const double (&u)[3], const double (&r)[3]) {
  for (int c = 0; c < 3; ++c) {
    const int i = (c + 1) % 3, j = (c + 2) % 3;
    const double x = u[i] * r[j] - u[j] * r[i];
    if (std::abs(x) > 0x1p-51 * (std::abs(u[i] * r[j]) + std::abs(u[j] * r[i])) + 0x1p-1070) return true;
  }
  return false;
}

inline void difference(const double* a, const double* b, double (&out)[3]) {  // a - b
  for (int c = 0; c < 3; ++c) out[c] = a[c] - b[c];
}

// The bound (as a fraction of S's volume) on |vol6 / 6 - |P*|| for the clipped polytope P with
// faces F (walk_faces), six times its volume vol6, its fans' determinants and apex o
// (clip_moments), B's planes d with errors e.
// Infinite where (1)-(3) above are not all certain. What each vertex needs is computed once:
// its plane values, x - o, and (x - o) x r for the ray's determinants (det[u_a, u_b, r] =
// u_a . (u_b x r)).
inline double clip_bound(const ClipPoly& P, const ClipFaces& F, const double (&d)[4][4], const double (&e)[4][4],
                         double vol6, const double (&fan_det)[3 * ClipPoly::kMax], const double (&o)[3]) {
  constexpr int kMax = ClipPoly::kMax;
  int n = 0;
  for (int v = 0; v < P.n; ++v) n += !P.dead[v];
  // A simple polytope: 3n / 2 edges, so n / 2 + 2 faces (Euler).
  if (n < 4 || 2 * F.count != n + 4) return INFINITY;
  ClipPlane plane[8];
  for (int q = 0; q < 4; ++q) plane[q] = simplex_plane(q);
  for (int j = 0; j < 4; ++j) plane[4 + j] = b_plane(d[j], e[j]);
  const auto x_of = [&](int v) { return &P.lam[v][1]; };
  // Each plane's lowest value over the vertices (a lower bound) and highest over the vertices
  // on it (an upper bound); rho, how far outside the simplex a vertex may lie.
  double low[8], high_on[8];
  for (int q = 0; q < 8; ++q) low[q] = INFINITY, high_on[q] = -INFINITY;
  // B's four planes side by side (plane_value's operations, lane by lane: vectorized).
  double c0[4], g0[4], g1[4], g2[4];
  for (int j = 0; j < 4; ++j) c0[j] = plane[4 + j].c0, g0[j] = plane[4 + j].g[0], g1[j] = plane[4 + j].g[1],
                               g2[j] = plane[4 + j].g[2];
  for (int v = 0; v < P.n; ++v) {
    if (P.dead[v]) continue;
    const double* x = x_of(v);
    const unsigned on = P.planes[v];
    for (int q = 1; q < 4; ++q) {  // lambda_q: exact
      low[q] = std::min(low[q], x[q - 1]);
      if (on >> q & 1u) high_on[q] = std::max(high_on[q], x[q - 1]);
    }
    {
      double b;
      const double g = plane_value(plane[0], x, b);
      low[0] = std::min(low[0], g - b);
      if (on & 1u) high_on[0] = std::max(high_on[0], g + b);
    }
    double lo[4], hi[4];
    for (int j = 0; j < 4; ++j) {
      const double t0 = g0[j] * x[0], t1 = g1[j] * x[1], t2 = g2[j] * x[2];
      const double g = ((c0[j] + t0) + t1) + t2;
      const double b = 0x1.cp-51 * (((std::abs(c0[j]) + std::abs(t0)) + std::abs(t1)) + std::abs(t2)) + 0x1p-1070;
      lo[j] = g - b;
      hi[j] = g + b;
    }
    for (int j = 0; j < 4; ++j) {
      low[4 + j] = std::min(low[4 + j], lo[j]);
      if (on >> (4 + j) & 1u) high_on[4 + j] = std::max(high_on[4 + j], hi[j]);
    }
  }
  double rho = 0.0;
  for (int q = 0; q < 4; ++q) rho = std::max(rho, -low[q]);
  // B's planes' data error on the simplex grown by rho (the sum of |lambda| there is at most
  // 1 + 8 rho).
  const double grown = (1.0 + 8.0 * rho) * (1.0 + 0x1p-50);
  for (int j = 4; j < 8; ++j) plane[j].data_error *= grown;
  // (1) every face on a plane; the planes kept: those with a face, and those some vertex is
  // not certainly inside of.
  unsigned face_plane[ClipFaces::kMaxFaces];
  unsigned kept = 0;
  for (int f = 0; f < F.count; ++f) {
    unsigned common = 0xFFu;
    for (int k = F.start[f]; k < F.start[f + 1]; ++k) common &= P.planes[F.vertex[k]];
    if (common == 0) return INFINITY;
    face_plane[f] = common;
    kept |= common;
  }
  double in[8], out[8], at_o[8], at_o_bound[8];
  for (int q = 0; q < 8; ++q) {
    if (!(kept >> q & 1u) && low[q] > plane[q].data_error) continue;  // certainly holds the hull
    kept |= 1u << q;
    in[q] = std::max(high_on[q], 0.0) + plane[q].data_error;
    out[q] = std::max(-low[q], 0.0) + plane[q].data_error;
    at_o[q] = plane_value(plane[q], o, at_o_bound[q]);
    if (!(at_o[q] - at_o_bound[q] > in[q])) return INFINITY;  // o certainly in I
  }
  // u = x - o per vertex, its largest |entry| and the sum of its |entries|.
  double u[kMax][3], norm[kMax], norm1[kMax];
  for (int v = 0; v < P.n; ++v) {
    if (P.dead[v]) continue;
    difference(x_of(v), o, u[v]);
    norm[v] = std::max(std::max(std::abs(u[v][0]), std::abs(u[v][1])), std::abs(u[v][2]));
    norm1[v] = (std::abs(u[v][0]) + std::abs(u[v][1])) + std::abs(u[v][2]);
  }
  // (2) and the evaluation bound (each fan determinant's permanent, sum_i |a_i| (|b_j c_k| +
  // |b_k c_j|), at most 2 |a|_1 |b|_inf |c|_inf); the largest triangle for (3).
  double evaluation = 0.0, largest = 0.0;
  double orientation = 0.0;  // the walk's: a triangle's determinant with its sign is good
  int triangles = 0, best_face = -1, best_k = 0;
  // Bad triangles (3'): no certain orientation, or the other one. Their pyramids from o are
  // within bad_volume (6-fold), and the directions from o through them within bad_angle.
  std::uint64_t bad[3] = {0, 0, 0};  // bit t of bad[t / 64]: triangle t (walk order)
  int bad_count = 0;
  double bad_volume = 0.0, bad_angle = 0.0;
  for (int f = 0; f < F.count; ++f) {
    const int* face = F.vertex + F.start[f];
    const int len = F.start[f + 1] - F.start[f];
    const double* a = x_of(face[0]);
    for (int k = 1; k + 1 < len; ++k) {
      const double product = 2.0 * norm1[face[0]] * norm[face[k]] * norm[face[k + 1]] * (1.0 + 0x1p-50);
      evaluation += product;
      const int t = triangles++;
      const double fan = fan_det[t];  // as fan_pyramids evaluated it, o-relative
      double det = fan;
      const double *b = x_of(face[k]), *c = x_of(face[k + 1]);
      if (equal(a, b) || equal(b, c) || equal(c, a)) continue;  // a segment or a point: no area (see (3))
      // Where its permanent's bound does not certify its sign, det[a - o, b - a, c - a] with its
      // own permanent (smaller for a thin triangle), then double-double.
      bool certain = std::abs(det) > kDoubleError * product + 0x1p-1070;
      double ba[3], ca[3];
      if (!certain) {
        double permanent;
        difference(b, a, ba);
        difference(c, a, ca);
        det = det3(u[face[0]], ba, ca, permanent);
        certain = std::abs(det) > kDoubleError * permanent + 0x1p-1070;
        if (!certain) {
          // Within the doubles' rounding (corners near each other): again in double-double from
          // the exact differences (kDoubleDoubleError, the rounding of hi + lo, and 2^-1000 for
          // underflow, as certified_orientations).
          det = det_refined(o, a, b, c);
          certain = std::abs(det) >
                    (kDoubleDoubleError * permanent + 0x1p-1000) * (1.0 + 0x1p-50) + 0x1p-53 * std::abs(det);
        }
      }
      if (certain && orientation == 0.0) orientation = det < 0.0 ? -1.0 : 1.0;
      if (certain && det * orientation > 0.0) {
        if (det * orientation > largest) largest = det * orientation, best_face = f, best_k = k;
        continue;
      }
      // (3'): its pyramid's 6-fold volume within |fan| and its rounding; its solid angle from o
      // at most its area over the squared distance to its face's slab, which o is beyond.
      if (certain) {  // the first difference was not needed to certify it
        difference(b, a, ba);
        difference(c, a, ca);
      }
      double area2 = 0.0;  // twice the area, rounded up: |ba x ca|_1 with 4 u of room
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, l = (i + 2) % 3;
        area2 += std::abs(ba[j] * ca[l]) + std::abs(ba[l] * ca[j]);
      }
      area2 *= 1.0 + 0x1p-50;
      double distance = 0.0;
      for (int q = 0; q < 8; ++q)
        if (face_plane[f] >> q & 1u)
          distance = std::max(distance, (at_o[q] - at_o_bound[q] - in[q]) / plane[q].norm * (1.0 - 0x1p-50));
      if (!(distance > 0.0)) return INFINITY;
      bad[t / 64] |= std::uint64_t{1} << (t % 64);
      ++bad_count;
      bad_volume += std::abs(fan) + kDoubleError * product;
      bad_angle += 0.5 * area2 / (distance * distance) * (1.0 + 0x1p-50);
    }
  }
  if (best_face < 0) return INFINITY;
  // (3) the ray from o towards the centroid of the largest triangle.
  double r[3];
  {
    const int* face = F.vertex + F.start[best_face];
    const double *a = x_of(face[0]), *b = x_of(face[best_k]), *c = x_of(face[best_k + 1]);
    for (int k = 0; k < 3; ++k) r[k] = (a[k] + b[k] + c[k]) * (1.0 / 3.0) - o[k];
  }
  // w = u x r per vertex, with its terms' magnitudes (the permanent of det[u_a, u_b, r] is
  // |u_a| . w_abs_b): made where a face needs them.
  double w[kMax][3], w_abs[kMax][3];
  std::uint64_t w_made = 0;
  const auto make_w = [&](int v) {
    if (w_made >> v & 1u) return;
    w_made |= std::uint64_t{1} << v;
    const double* x = u[v];
    w[v][0] = x[1] * r[2] - x[2] * r[1];
    w[v][1] = x[2] * r[0] - x[0] * r[2];
    w[v][2] = x[0] * r[1] - x[1] * r[0];
    w_abs[v][0] = std::abs(x[1] * r[2]) + std::abs(x[2] * r[1]);
    w_abs[v][1] = std::abs(x[2] * r[0]) + std::abs(x[0] * r[2]);
    w_abs[v][2] = std::abs(x[0] * r[1]) + std::abs(x[1] * r[0]);
  };
  const int sign = orientation < 0.0 ? -1 : 1;
  // The sign of det[u_a, u_b, r] where certain (times the orientation), else 0.
  const auto edge_sign = [&](int a, int b) {
    const double det = (u[a][0] * w[b][0] + u[a][1] * w[b][1]) + u[a][2] * w[b][2];
    const double bound = kDoubleError * ((std::abs(u[a][0]) * w_abs[b][0] + std::abs(u[a][1]) * w_abs[b][1]) +
                                         std::abs(u[a][2]) * w_abs[b][2]) +
                         0x1p-1070;
    return det > bound ? sign : (det < -bound ? -sign : 0);
  };
  // Along the ray x(s) = o + s r, each kept plane's value g_q(o) + s slope_q (slope_q within its
  // bound: products and sums, and g's rounding). The ray leaves G, for good, once some g_q with
  // a certainly negative slope passes -out_q: at s_exit at the latest (an upper bound). A face
  // on plane q lies in {g_q <= in_q}, which the ray reaches at s_q >= (g_q(o) - in_q) / |slope_q|
  // (a lower bound; never where the slope is certainly >= 0). A face whose every such s_q
  // certainly exceeds s_exit is not crossed; the others are tested triangle by triangle.
  double slope_lo[8], slope_hi[8];
  double exit_at = INFINITY;
  for (int q = 0; q < 8; ++q) {
    if (!(kept >> q & 1u)) continue;
    const ClipPlane& p = plane[q];
    const double slope = (p.g[0] * r[0] + p.g[1] * r[1]) + p.g[2] * r[2];
    const double b = 0x1.cp-51 * ((std::abs(p.g[0] * r[0]) + std::abs(p.g[1] * r[1])) + std::abs(p.g[2] * r[2]));
    slope_lo[q] = slope - b;
    slope_hi[q] = slope + b;
    if (slope_hi[q] < 0.0)
      exit_at = std::min(exit_at, (at_o[q] + at_o_bound[q] + out[q]) / -slope_hi[q] * (1.0 + 0x1p-50));
  }
  const auto not_reached = [&](int f) {
    for (int q = 0; q < 8; ++q) {
      if (!(face_plane[f] >> q & 1u)) continue;
      if (slope_lo[q] >= 0.0) return true;  // g_q grows along the ray: it stays above in_q
      if ((at_o[q] - at_o_bound[q] - in[q]) / -slope_lo[q] * (1.0 - 0x1p-50) > exit_at) return true;
    }
    return false;
  };
  for (int f = 0; f < F.count; ++f) {
    if (f != best_face && not_reached(f)) continue;
    const int* face = F.vertex + F.start[f];
    const int len = F.start[f + 1] - F.start[f];
    for (int k = 0; k < len; ++k) make_w(face[k]);
    int spoke = edge_sign(face[0], face[1]);  // det[u_0, u_k, r]
    for (int k = 1; k + 1 < len; ++k) {
      const int next = edge_sign(face[0], face[k + 1]);
      const int s0 = spoke, s1 = edge_sign(face[k], face[k + 1]), s2 = -next;
      spoke = next;
      const bool crossed = s0 > 0 && s1 > 0 && s2 > 0;
      const int t = F.start[f] - 2 * f + k - 1;  // the triangle's number in the walk
      if (f == best_face && k == best_k) {
        if (!crossed) return INFINITY;
      } else if (bad[t / 64] >> (t % 64) & 1u) {
        // Whatever its orientation, the ray misses it where two of its edge determinants
        // certainly differ in sign.
        if (!((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0))) return INFINITY;
      } else if (!(s0 < 0 || s1 < 0 || s2 < 0)) {
        // Crossed, or uncertain; a triangle with two equal corners is a segment, which one of
        // these determinants certainly excludes; one with three equal corners is a point, off the
        // ray where (point - o) x r is certainly not 0.
        if (!(equal(x_of(face[0]), x_of(face[k])) && equal(x_of(face[0]), x_of(face[k + 1])) && off_ray(u[face[0]], r)))
          return INFINITY;
      }
    }
  }
  double slabs = 0.0;
  for (int q = 0; q < 8; ++q)
    if (kept >> q & 1u) slabs += (in[q] + out[q]) * plane[q].slab;
  const double grow2 = (1.0 + 4.0 * rho) * (1.0 + 4.0 * rho);
  // The computed determinants' magnitudes sum to at most vol6 plus their errors (the good ones
  // positive, the bad ones within bad_volume); the running sums, within each face and over the
  // faces, round at most T + F <= 2 T times. The determinants' errors count three times: once
  // as errors, and twice more where a face's computed sum came out of the other sign only
  // through them (clip_moments takes each face's sum in absolute value).
  const double sum_rounding = 2.0 * (triangles + 1) * 0x1p-53 * ((vol6 + kDoubleError * evaluation) + 2.0 * bad_volume);
  double bound = (3.0 * slabs * grow2 + 3.0 * kDoubleError * evaluation) + sum_rounding;
  if (bad_count > 0) {
    // (3'): rays through bad triangles (solid angle at most bad_angle) may cross the surface
    // more than once; along them |w - w_R| <= 2 + 2 bad_count, out to the farthest vertex
    // (radius at most sqrt(3) times the largest |x - o| entry): 6-fold, 6 (2 + 2 n) angle R^3 / 3.
    // And a face whose pyramids sum to the other sign counts twice its bad part (2 bad_volume).
    double far = 0.0;
    for (int v = 0; v < P.n; ++v)
      if (!P.dead[v]) far = std::max(far, norm[v]);
    const double radius3 = 5.196152422706633 * far * far * far * (1.0 + 0x1p-48);  // (sqrt 3)^3
    bound += 4.0 * (1.0 + bad_count) * bad_angle * radius3 + 2.0 * bad_volume;
  }
  return bound * (1.0 + 0x1p-48);
}

// --- S almost inside B: the volume from the parts of S that B's planes cut off ----------------
//
// Where each plane of B that cuts S cuts off only a thin part of it along one face of S (nearly
// identical tetrahedra, as in a mesh and the same mesh slightly moved; a small S just across a
// face of B), S n B = S minus the union of those parts W_j = S n {g_j < 0}, and each W_j has a
// closed form: a tetrahedron, a wedge, or S less a tetrahedron, with corners on S's edges at
// t = A / (A + C), A = -g at the edge's end beyond the plane, C = g at the other (no
// cancellation: a sum of non-negative numbers). Volume fractions of the unit simplex:
//  - one vertex a beyond: the tetrahedron (a, a + t_ab (b - a), ...): t_ab t_ac t_ad;
//  - three beyond, b not: 1 - s_a s_c s_d, s_k = D_b / (D_b + A_k) (S less b's tetrahedron);
//  - two, a and b, beyond, c and d not: the wedge between the triangles (a, p_ac, p_ad) and
//    (b, p_bc, p_bd), the three tetrahedra (a, p_ac, p_ad, b), (p_ac, p_ad, b, p_bc),
//    (p_ad, b, p_bc, p_bd), whose barycentric determinants are u v, v x (1 - u) and
//    (1 - v) x y (u = t_ac, v = t_ad, x = t_bc, y = t_bd): all terms non-negative.
// Each is evaluated to within 64 eps absolute (a fraction of at most 1; a dozen roundings of
// relative eps each, on non-negative terms, and one subtraction from 1).
// Error bound, as a fraction of S (derived, not calibrated):
//  (1) The plane's values D are each within its bound E of the exact ones
//      (certified_orientations). W_j shrinks as any D grows, so its exact fraction lies between
//      the fractions at D + E and at D - E (rounded outward), each within 64 eps.
//  (2) S n B = S minus the union of the W_j: its fraction lies between 1 - sum F_j and that plus
//      the pairwise overlaps (Bonferroni). On W_j, with sigma the vertex of largest D (D > 0
//      there even at D - E), lambda_sigma D_sigma < sum_{k != sigma} lambda_k (-D_k)+ <= max
//      (-D_k)+, so W_j lies in {lambda_sigma < tau_j}, tau_j = max (E_k - D_k)+ / (D_sigma -
//      E_sigma). For sigma_i != sigma_j the overlap is then at most the fraction of the unit
//      simplex with lambda_a < tau_i and lambda_b < tau_j, 1 - (1 - x)^3 - (1 - y)^3 + (1 - x -
//      y)_+^3 = 6 x y - 3 x^2 y - 3 x y^2 <= 6 x y (x + y <= 1; beyond, at most 3 min(x, y)); in
//      any case at most the smaller W.
//  (3) The result 1 - sum F_j (computed at D) is off by at most the sum of each F_j's distance
//      to its interval, the overlaps, and the rounding of the four subtractions (4 eps).
// The first moments: S's less each W_j's (the tetrahedra's centroids, exact in form), the
// overlaps left out (at most 6 tau_i tau_j of S's volume, not bounded further).

// The fraction of the unit simplex where sum_k lambda_k d[k] < 0, and with kFirst the first
// moment of that part as four barycentric coordinates (fractions of S's volume times the mean
// lambda).
template <bool kFirst>
double beyond_fraction(const double (&d)[4], double (&first)[4]) {
  int neg[4], pos[4], nn = 0, np = 0;
  for (int k = 0; k < 4; ++k) {
    if (d[k] < 0.0)
      neg[nn++] = k;
    else
      pos[np++] = k;
  }
  if constexpr (kFirst) first[0] = first[1] = first[2] = first[3] = 0.0;
  if (nn == 0) return 0.0;
  if (nn == 4) {
    if constexpr (kFirst) first[0] = first[1] = first[2] = first[3] = 0.25;
    return 1.0;
  }
  if (nn == 1) {
    const int a = neg[0];
    const double A = -d[a];
    double t[3], f = 1.0, sum_t = 0.0;
    for (int i = 0; i < 3; ++i) {
      t[i] = A / (A + d[pos[i]]);
      f *= t[i];
      sum_t += t[i];
    }
    if constexpr (kFirst) {
      // The tetrahedron's centroid: (a + sum_k (a + t_ak (k - a))) / 4.
      first[a] = f * ((4.0 - sum_t) * 0.25);
      for (int i = 0; i < 3; ++i) first[pos[i]] = f * (t[i] * 0.25);
    }
    return f;
  }
  if (nn == 3) {
    const int b = pos[0];
    const double P = d[b];
    double s[3], g = 1.0, sum_s = 0.0;
    for (int i = 0; i < 3; ++i) {
      s[i] = P / (P - d[neg[i]]);
      g *= s[i];
      sum_s += s[i];
    }
    if constexpr (kFirst) {
      // S's first moment (1/4 each) less that of b's tetrahedron.
      first[b] = 0.25 - g * ((4.0 - sum_s) * 0.25);
      for (int i = 0; i < 3; ++i) first[neg[i]] = 0.25 - g * (s[i] * 0.25);
    }
    return 1.0 - g;
  }
  // Two beyond (a, b), two not (c, d).
  const int a = neg[0], b = neg[1], c = pos[0], e = pos[1];
  const double A = -d[a], B = -d[b];
  const double u = A / (A + d[c]), v = A / (A + d[e]), x = B / (B + d[c]), y = B / (B + d[e]);
  const double w1 = u * v, w2 = (v * x) * (1.0 - u), w3 = ((1.0 - v) * x) * y;
  if constexpr (kFirst) {
    // Sums of the three tetrahedra's vertices, coordinate by coordinate (a, b, c, d):
    // (a, p_ac, p_ad, b), (p_ac, p_ad, b, p_bc), (p_ad, b, p_bc, p_bd).
    first[a] = (w1 * ((3.0 - u) - v) + w2 * ((1.0 - u) + (1.0 - v)) + w3 * (1.0 - v)) * 0.25;
    first[b] = (w1 + w2 * (2.0 - x) + w3 * ((3.0 - x) - y)) * 0.25;
    first[c] = (w1 * u + w2 * (u + x) + w3 * x) * 0.25;
    first[e] = (w1 * v + w2 * v + w3 * (v + y)) * 0.25;
  }
  return (w1 + w2) + w3;
}

// What near_cover keeps of one plane.
struct CoverPlane {
  double fraction;   // F_j at the computed D
  double deviation;  // how far the exact F_j can be from it
  double upper;      // an upper bound on the exact F_j
  double tau;        // W_j lies in {lambda_sigma < tau} (infinite where no sigma is certain)
  int sigma;
  bool cuts;         // false: the plane certainly cuts nothing off S (every D - E >= 0)
  double first[4];   // W_j's first moment (barycentric), at the computed D
};

constexpr double kFractionError = 64.0 * 0x1p-53;  // beyond_fraction's own rounding (above)

// The largest bound the near-cover formula is accepted with, relative to S's volume.
constexpr double kNearCoverAccepted = 0x1p-44;

// kFirst: W_j's first moment too (c.first; else left alone: only the moments read it).
template <bool kFirst>
void cover_plane(const double (&d)[4], const double (&e)[4], CoverPlane& c) {
  double up[4], down[4];
  for (int k = 0; k < 4; ++k) {
    const double u = d[k] + e[k], l = d[k] - e[k];
    up[k] = u + 0x1p-52 * std::abs(u);  // at least d + e, whatever the rounding
    down[k] = l - 0x1p-52 * std::abs(l);
  }
  double unused[4];
  const double f_down = beyond_fraction<false>(down, unused);
  c.cuts = f_down != 0.0;  // 0 only where every d - e >= 0: nothing cut off exactly either
  c.fraction = beyond_fraction<kFirst>(d, c.first);
  if (!c.cuts) {
    c.deviation = c.upper = 0.0;
    c.tau = 0.0;
    c.sigma = -1;
    return;
  }
  const double f_up = beyond_fraction<false>(up, unused);
  c.upper = f_down + kFractionError;
  c.deviation = std::max(c.upper - c.fraction, c.fraction - (f_up - kFractionError));
  int s = 0;
  for (int k = 1; k < 4; ++k) s = d[k] > d[s] ? k : s;
  c.sigma = s;
  double beyond = 0.0;
  for (int k = 0; k < 4; ++k)
    if (k != s) beyond = std::max(beyond, -down[k]);
  c.tau = down[s] > 0.0 ? (beyond / down[s]) * (1.0 + 0x1p-50) : INFINITY;
}

// Whether a plane is worth keeping for near_cover: it cuts nothing, or only a thin part
// along one face of S. (Only a filter: near_cover's bound decides.)
inline bool thin_cut(const CoverPlane& c) { return !c.cuts || c.tau <= 0x1p-10; }

// S n B's fraction of S from the four planes (near-cover, above), with kFirst its first moment
// (barycentric), and the bound on the fraction's error.
template <bool kFirst>
double near_cover(const CoverPlane (&c)[4], double& bound, double (&first)[4]) {
  double cut = 0.0;
  bound = 0.0;
  for (int k = 0; k < 4; ++k) first[k] = 0.25;
  for (int j = 0; j < 4; ++j) {
    cut += c[j].fraction;
    bound += c[j].deviation;
    if constexpr (kFirst)
      for (int k = 0; k < 4; ++k) first[k] -= c[j].first[k];
    for (int i = 0; i < j; ++i) {
      if (!c[i].cuts || !c[j].cuts) continue;
      double overlap = std::min(c[i].upper, c[j].upper);
      if (c[i].sigma != c[j].sigma) overlap = std::min(overlap, (6.0 * c[i].tau) * c[j].tau * (1.0 + 0x1p-50));
      bound += overlap;
    }
  }
  bound = (bound + 4.0 * 0x1p-53) * (1.0 + 0x1p-50);
  return 1.0 - cut;
}

}  // namespace refined_impl

// det6(t) = orient3d(t0, t1, t2, t3), certified to 2^-47 of itself, with its own error bound;
// false where it is not certified.
inline bool refined_det6(const Tet& t, double& det6, double& error) {
  refined_impl::Face f(t[0], t[1], t[2]);
  return refined_impl::certified_orientations(f, &t[3], 1, &det6, &error);
}

inline bool refined_det6(const Tet& t, double& det6) {
  double error;
  return refined_det6(t, det6, error);
}

// A bound for a result that is a thin part of S, where clip_bound's checks need not hold (the
// vertices' mean outside the inner region, say): both the computed fraction vol6 and the exact
// one lie in [0, max(vol6, keep)], keep the smallest fraction of S that one plane of B alone
// keeps at its D's less their errors (beyond_fraction at D + E rounded up, less its own
// rounding), so their difference is at most that. Infinite where no plane keeps less than
// 2^-43 (only thin results are meant; S n B lies in each plane's kept part).
// The smallest fraction of S that one of B's first `count` planes keeps (an upper bound).
inline double plane_keeps(const double (&d)[4][4], const double (&e)[4][4], int count) {
  using namespace refined_impl;
  double keep = INFINITY;
  for (int j = 0; j < count; ++j) {
    double up[4], unused[4];
    bool finite = true;
    for (int k = 0; k < 4; ++k) {
      const double u = d[j][k] + e[j][k];
      up[k] = u + 0x1p-52 * std::abs(u);  // at least d + e, whatever the rounding
      finite = finite && std::abs(up[k]) < INFINITY;
    }
    if (finite) keep = std::min(keep, (1.0 - beyond_fraction<false>(up, unused)) + kFractionError);
  }
  return keep;
}

inline double thin_bound(const double (&d)[4][4], const double (&e)[4][4], double vol6) {
  const double keep = plane_keeps(d, e, 4);
  return keep <= 0x1p-43 ? std::max(vol6, keep) : INFINITY;
}

// What the refinement found (for the tests: kernel_trace.hpp's near_cover_trace).
struct NearCoverReport {
  bool tried = false;        // all four planes thin: the near-cover formula was evaluated
  bool decided = false;      // and accepted
  double bound = 0.0;        // its error bound relative to S's exact volume
  double clip_bound = -1.0;  // the clipping's bound relative to S's exact volume (-1: not clipped to a volume)
  bool separated = false;    // an empty clipping certified by a separating plane
};

// The largest bound the clipping is accepted with, relative to S's exact volume.
constexpr double kClipAccepted = 0x1p-42;

// kMoments: the first moments too (else out.first is 0; the volume is the same number).
// clip_only: the clipping whatever the planes (for the tests).
template <bool kMoments = true>
bool refined_moments(const Tet& S, const Tet& B, double det6_B, Moments& out, NearCoverReport* report = nullptr,
                     bool clip_only = false) {
  using namespace refined_impl;
  static constexpr int kFaceVerts[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  NearCoverReport unused_report;
  NearCoverReport& rep = report ? *report : unused_report;
  rep = NearCoverReport{};
  ClipPoly P;
  unit_simplex(P);
  // Each plane's values are kept; the planes that cut only a thin part off S along one of its
  // faces (or nothing) are not clipped yet: if all four are such, the near-cover formula may
  // decide without clipping (above). Otherwise the planes are clipped in their order, as if
  // none had waited.
  double planes[4][4], errors[4][4];
  CoverPlane cover[4];
  bool covering = !clip_only;
  int clipped = 0, computed = 0;
  const auto clip_up_to = [&](int last) {  // false: the polytope is empty (or broke)
    for (; clipped <= last; ++clipped)
      if (!clip(P, planes[clipped], clipped)) return false;
    return true;
  };
  // An empty clipping stands (out = 0, true) where it is certain: one plane of B keeps at most
  // kClipAccepted of S (thin_bound's keep: S n B lies in that part; a plane through a shared
  // vertex or along a shared face, its D's 0 or within rounding of it, keeps that little), or a
  // plane separates S and B (separation.hpp). Otherwise (a flat or vanishing polytope that
  // neither certifies) the exact last resort decides.
  const auto empty = [&]() {
    if (P.failed) return false;
    out = Moments{};
    if (plane_keeps(planes, errors, computed) <= kClipAccepted) return true;
    rep.separated = certainly_separated(B, S);
    return rep.separated;
  };
  for (int j = 0; j < 4; ++j) {
    // Face j of B oriented so that B's vertex j is on its positive side:
    // orient3d(f0, f1, f2, b_j) = (-1)^(j+1) det6(B) (barycentric_map.hpp).
    Face f(B[kFaceVerts[j][0]], B[kFaceVerts[j][1]], B[kFaceVerts[j][2]]);
    if (!certified_orientations(f, S.data(), 4, planes[j], errors[j])) return false;
    computed = j + 1;
    if (((j % 2 == 0) ? -det6_B : det6_B) < 0.0)
      for (double& x : planes[j]) x = -x;
    if (covering) {
      cover_plane<kMoments>(planes[j], errors[j], cover[j]);
      if (thin_cut(cover[j])) continue;
      covering = false;
    }
    if (!clip_up_to(j)) return empty();
  }
  // S's det6 only now: an empty intersection (the usual case among the pairs refined) does not
  // need it.
  double det6_S, det6_error;
  if (!refined_det6(S, det6_S, det6_error)) return false;
  const double scale = std::abs(det6_S);
  if (covering) {
    double bound, first_bary[4];
    const double fraction = near_cover<kMoments>(cover, bound, first_bary);
    // In units of S's exact volume: the fraction's error, S's det6's error times the fraction,
    // and the rounding of the product below (three roundings and 1/6's).
    const double total = (bound * scale + fraction * det6_error) / (scale - det6_error) + 5.0 * 0x1p-53;
    const bool accepted = fraction >= 0.5 && total <= kNearCoverAccepted;
    rep.tried = true;
    rep.decided = accepted;
    rep.bound = total;
    if (accepted) {
      out.volume = fraction * scale * (1.0 / 6.0);
      if constexpr (kMoments) {
        const Vec3 e1 = S[1] - S[0], e2 = S[2] - S[0], e3 = S[3] - S[0];
        const double v6 = scale * (1.0 / 6.0);
        out.first = out.volume * S[0] + v6 * (first_bary[1] * e1 + first_bary[2] * e2 + first_bary[3] * e3);
      }
      return true;
    }
    if (!clip_up_to(3)) return empty();
  }
  ClipFaces F;
  if (!walk_faces(P, F)) return false;
  double vol_ref, first_ref[3], vol6, fan_det[3 * ClipPoly::kMax], apex[3];
  clip_moments<kMoments>(P, F, vol_ref, first_ref, vol6, fan_det, apex);
  out.volume = vol_ref * scale;
  if (!(out.volume > 0.0)) return empty();
  // The clipping's bound (clip_bound) in units of S's exact volume, with S's det6's error and
  // the rounding of vol6 / 6 and of the product with scale, as the near-cover formula's.
  double bound = clip_bound(P, F, planes, errors, vol6, fan_det, apex);
  if (!(bound <= kClipAccepted)) bound = std::min(bound, thin_bound(planes, errors, vol6));
  const double total = (bound * scale + (vol6 + bound) * det6_error) / (scale - det6_error) + 5.0 * 0x1p-53;
  rep.clip_bound = total;
  if (!(total <= kClipAccepted)) return false;
  // Back to the caller's coordinates: lambda_k weighs s_k, the mean lambda of the polytope is
  // first_ref / vol_ref, so the first moment is volume * s_0 + scale * sum_k first_ref_k (s_k - s_0).
  if constexpr (!kMoments) return true;
  const Vec3 e1 = S[1] - S[0], e2 = S[2] - S[0], e3 = S[3] - S[0];
  out.first = out.volume * S[0] + scale * (first_ref[0] * e1 + first_ref[1] * e2 + first_ref[2] * e3);
  return true;
}

}  // namespace

}  // namespace tetia::detail
