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
// [0, 1]: errors of a few ulps of S, with no ratio in them. The volume is the clipped volume
// times |det6(S)|, that determinant certified alike (a sliver's det6 in doubles is off by eps
// over its quality).
//
// Contract: refined_det6(t, det6) computes det6(t) = det[t1 - t0, t2 - t0, t3 - t0] to 2^-47 of
// itself, or returns false. refined_moments(S, B, det6_B, out) fills the volume and first
// moments of S n B and returns true when det6(S) and every D are certified to 2^-47 of the
// largest of their plane (error bounds below: doubles where they suffice, double-double where
// not), which holds for size ratios up to about 2^50; false otherwise (the caller takes the
// exact last resort). Where every plane of B cuts at most a thin part off S, the near-cover
// formula (below) decides first, without clipping, when its derived bound is at most 2^-44 of
// S's volume. det6_B, B's det6 in doubles, gives only the sign of B's orientation (B is
// not flat to rounding: the caller checked its quality). Sizes within the kernel's range
// (frame.hpp's FrameStatus): no overflow. Allocation-free; not the hot path (about a
// microsecond).
#pragma once

#include <cmath>
#include <cstdint>

#include "exact_sign.hpp"  // two_sum, two_diff, two_product
#include "fan.hpp"
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
  }
}

// Keeps the part of P where sum_k lambda_k d[k] >= 0. Returns false if nothing is left with a
// positive value (the polytope is empty or flat). A vertex with value 0 is kept; new vertices
// are made on the edges from a kept vertex to a removed one, then linked around the new face.
inline bool clip(ClipPoly& P, const double (&d)[4]) {
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

// Volume and first moments (in lambda1..lambda3, the unit simplex having volume 1/6) by fans
// over the faces (fan.hpp), each joined to the mean of the vertices and taken in absolute value
// (a convex polytope: every such pyramid is non-negative), as the kernel's fan_moments does.
// kMoments: the first moments too (the volume is the same number either way).
template <bool kMoments>
void clip_moments(const ClipPoly& P, double& vol, double (&first)[3]) {
  vol = 0.0;
  first[0] = first[1] = first[2] = 0.0;
  int alive = 0;
  double o[3] = {0.0, 0.0, 0.0};
  for (int v = 0; v < P.n; ++v) {
    if (P.dead[v]) continue;
    ++alive;
    for (int c = 0; c < 3; ++c) o[c] += P.lam[v][c + 1];
  }
  if (alive < 4) return;
  for (double& x : o) x /= alive;
  std::uint64_t used[3] = {0, 0, 0};  // bit v of used[i]: the directed edge v -> nbr[v][i] walked
  double vol6 = 0.0, m[3] = {0.0, 0.0, 0.0};
  for (int v0 = 0; v0 < P.n; ++v0)
    for (int i0 = 0; i0 < 3; ++i0) {
      if (P.dead[v0] || (used[i0] >> v0 & 1u)) continue;
      // The face through the directed edge v0 -> nbr[v0][i0].
      int face[ClipPoly::kMax];
      int len = 0;
      int a = v0, ia = i0;
      do {
        used[ia] |= std::uint64_t{1} << a;
        face[len++] = a;
        const int b = P.nbr[a][ia];
        int j = 0;
        while (P.nbr[b][j] != a) ++j;
        a = b;
        ia = (j + 1) % 3;
      } while (!(a == v0 && ia == i0) && len < ClipPoly::kMax);
      double fv = 0.0, fm[3] = {0.0, 0.0, 0.0};
      fan_pyramids<kMoments>(o, len, [&](int k) { return P.lam[face[k]]; }, fv, fm);
      const double s = fv < 0.0 ? -1.0 : 1.0;
      vol6 += s * fv;
      if constexpr (kMoments)
        for (int c = 0; c < 3; ++c) m[c] += s * fm[c];
    }
  vol = vol6 / 6.0;
  for (int c = 0; c < 3; ++c) first[c] = m[c] / 24.0;
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

// What the near-cover formula found (for the tests: kernel_trace.hpp's near_cover_trace).
struct NearCoverReport {
  bool tried = false;    // all four planes thin: the formula was evaluated
  bool decided = false;  // and accepted
  double bound = 0.0;    // its error bound relative to S's exact volume
};

// kMoments: the first moments too (else out.first is 0; the volume is the same number).
// clip_only: the clipping whatever the planes (for the tests).
template <bool kMoments = true>
bool refined_moments(const Tet& S, const Tet& B, double det6_B, Moments& out, NearCoverReport* report = nullptr,
                     bool clip_only = false) {
  using namespace refined_impl;
  static constexpr int kFaceVerts[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  ClipPoly P;
  unit_simplex(P);
  // Each plane's values are kept; the planes that cut only a thin part off S along one of its
  // faces (or nothing) are not clipped yet: if all four are such, the near-cover formula may
  // decide without clipping (above). Otherwise the planes are clipped in their order, as if
  // none had waited.
  double planes[4][4];
  CoverPlane cover[4];
  bool covering = !clip_only;
  int clipped = 0;
  const auto clip_up_to = [&](int last) {  // false: the polytope is empty (or broke)
    for (; clipped <= last; ++clipped)
      if (!clip(P, planes[clipped])) return false;
    return true;
  };
  for (int j = 0; j < 4; ++j) {
    // Face j of B oriented so that B's vertex j is on its positive side:
    // orient3d(f0, f1, f2, b_j) = (-1)^(j+1) det6(B) (barycentric_map.hpp).
    Face f(B[kFaceVerts[j][0]], B[kFaceVerts[j][1]], B[kFaceVerts[j][2]]);
    double error[4];
    if (!certified_orientations(f, S.data(), 4, planes[j], error)) return false;
    if (((j % 2 == 0) ? -det6_B : det6_B) < 0.0)
      for (double& x : planes[j]) x = -x;
    if (covering) {
      cover_plane<kMoments>(planes[j], error, cover[j]);
      if (thin_cut(cover[j])) continue;
      covering = false;
    }
    if (!clip_up_to(j)) {
      if (P.failed) return false;
      out = Moments{};
      return true;
    }
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
    if (report) *report = NearCoverReport{true, accepted, total};
    if (accepted) {
      out.volume = fraction * scale * (1.0 / 6.0);
      if constexpr (kMoments) {
        const Vec3 e1 = S[1] - S[0], e2 = S[2] - S[0], e3 = S[3] - S[0];
        const double v6 = scale * (1.0 / 6.0);
        out.first = out.volume * S[0] + v6 * (first_bary[1] * e1 + first_bary[2] * e2 + first_bary[3] * e3);
      }
      return true;
    }
    if (!clip_up_to(3)) {
      if (P.failed) return false;
      out = Moments{};
      return true;
    }
  }
  double vol_ref, first_ref[3];
  clip_moments<kMoments>(P, vol_ref, first_ref);
  out.volume = vol_ref * scale;
  if (!(out.volume > 0.0)) {
    out = Moments{};
    return true;
  }
  // Back to the caller's coordinates: lambda_k weighs s_k, the mean lambda of the polytope is
  // first_ref / vol_ref, so the first moment is volume * s_0 + scale * sum_k first_ref_k (s_k - s_0).
  if constexpr (!kMoments) return true;
  const Vec3 e1 = S[1] - S[0], e2 = S[2] - S[0], e3 = S[3] - S[0];
  out.first = out.volume * S[0] + scale * (first_ref[0] * e1 + first_ref[1] * e2 + first_ref[2] * e3);
  return true;
}

}  // namespace

}  // namespace tetia::detail
