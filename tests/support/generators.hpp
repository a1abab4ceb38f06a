// tests/support/generators.hpp -- families of tetrahedron pairs for the kernel tests
// (test_kernel_vs_exact.cpp, test_kernel_properties.cpp).
//
// Every family is built from a fixed seed (std::mt19937_64), so a failure names a reproducible
// pair. Degenerate families are built so that the intended degeneracy holds *exactly* in
// doubles: small integer or dyadic coordinates, points on faces and edges as dyadic barycentric
// combinations of integer vertices, far-from-origin offsets added to coordinates on a grid
// coarse enough for the sum to be exact. Only the perturbation, rotation and sliver families
// contain arbitrary doubles, and the exact reference takes those as they are.
//
// Counts: 10^4 random pairs, about 2.5 * 10^4 degenerate ones, in every build (the whole set
// runs in a few seconds in Release and well under a minute under ASan + UBSan).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetia/exact.hpp"
#include "tetia/geometry.hpp"
#include "tetia/tet_intersection.hpp"

namespace tetia::testgen {

using Rng = std::mt19937_64;

// ---------------------------------------------------------------------------------------------
// Formatting (17 significant digits: every double round-trips).

inline std::string fmt(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

inline std::string fmt(const Vec3& p) {
  return "{" + fmt(p.x) + ", " + fmt(p.y) + ", " + fmt(p.z) + "}";
}

inline std::string fmt(const Tet& t) {
  return "{" + fmt(t[0]) + ", " + fmt(t[1]) + ", " + fmt(t[2]) + ", " + fmt(t[3]) + "}";
}

/// "U = {...}; V = {...};" ready to paste into a test.
inline std::string fmt_pair(const Tet& U, const Tet& V) {
  return "Tet U = " + fmt(U) + ";\n  Tet V = " + fmt(V) + ";";
}

inline std::string fmt_stats(const IntersectionStats& s) {
  std::ostringstream o;
  o << "edge_inherited=" << s.edge_inherited << " edge_paired=" << s.edge_paired
    << " edge_straight_line=" << s.edge_straight_line << " edge_computed=" << s.edge_computed
    << " face_inherited=" << s.face_inherited << " face_paired=" << s.face_paired
    << " face_computed=" << s.face_computed << " nonconvex_lines=" << s.nonconvex_lines
    << " corner_coordinates=" << s.corner_coordinates << " guardrail_clamps=" << s.guardrail_clamps
    << " reference_swaps=" << s.reference_swaps << " inconsistencies=" << s.inconsistencies
    << " calls=" << s.calls;
  return o.str();
}

// ---------------------------------------------------------------------------------------------
// Small helpers.

inline int irand(Rng& g, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g); }

inline bool coin(Rng& g) { return irand(g, 0, 1) == 1; }

inline double urand(Rng& g, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(g);
}

/// A random multiple of 2^-bits in [lo, hi) (lo, hi multiples of 2^-bits, |value| < 2^53).
inline double grid(Rng& g, int bits, double lo, double hi) {
  const auto a = static_cast<std::int64_t>(std::ldexp(lo, bits));
  const auto b = static_cast<std::int64_t>(std::ldexp(hi, bits)) - 1;
  return std::ldexp(static_cast<double>(std::uniform_int_distribution<std::int64_t>(a, b)(g)), -bits);
}

inline Vec3 ivec(Rng& g, int lo, int hi) {
  return {double(irand(g, lo, hi)), double(irand(g, lo, hi)), double(irand(g, lo, hi))};
}

inline Vec3 gvec(Rng& g, int bits, double lo, double hi) {
  return {grid(g, bits, lo, hi), grid(g, bits, lo, hi), grid(g, bits, lo, hi)};
}

inline Tet translate(const Tet& t, Vec3 o) { return {t[0] + o, t[1] + o, t[2] + o, t[3] + o}; }

inline Tet scale(const Tet& t, double s) { return {s * t[0], s * t[1], s * t[2], s * t[3]}; }

inline const std::array<std::array<int, 4>, 24>& perms4() {
  static const auto table = [] {
    std::array<std::array<int, 4>, 24> p{};
    std::array<int, 4> cur{0, 1, 2, 3};
    int k = 0;
    do p[static_cast<std::size_t>(k++)] = cur;
    while (std::next_permutation(cur.begin(), cur.end()));
    return p;
  }();
  return table;
}

inline Tet permute(const Tet& t, const std::array<int, 4>& p) {
  return {t[static_cast<std::size_t>(p[0])], t[static_cast<std::size_t>(p[1])],
          t[static_cast<std::size_t>(p[2])], t[static_cast<std::size_t>(p[3])]};
}

inline Tet random_perm(Rng& g, const Tet& t) {
  return permute(t, perms4()[static_cast<std::size_t>(irand(g, 0, 23))]);
}

/// A non-flat tetrahedron with integer coordinates in [lo, hi] (orient3d is exact for them).
inline Tet int_tet(Rng& g, int lo, int hi, double min_vol6 = 1.0) {
  for (;;) {
    Tet t{ivec(g, lo, hi), ivec(g, lo, hi), ivec(g, lo, hi), ivec(g, lo, hi)};
    if (std::abs(orient3d(t[0], t[1], t[2], t[3])) >= min_vol6) return t;
  }
}

/// A tetrahedron with coordinates on the 2^-bits grid in [lo, hi)^3 and volume >= min_vol.
inline Tet grid_tet(Rng& g, int bits, double lo, double hi, double min_vol) {
  for (;;) {
    Tet t{gvec(g, bits, lo, hi), gvec(g, bits, lo, hi), gvec(g, bits, lo, hi), gvec(g, bits, lo, hi)};
    if (volume(t) >= min_vol) return t;
  }
}

/// Exact dyadic combination sum w_k p_k / den (den a power of two, small integer weights,
/// small dyadic coordinates): every product and partial sum is exact.
inline Vec3 combo(const Vec3* p, const int* w, int n, int den) {
  Vec3 s{};
  for (int k = 0; k < n; ++k) s = s + double(w[k]) * p[k];
  return (1.0 / den) * s;
}

/// Random positive weights w_0..w_{n-1} >= 1 adding up to den.
inline void random_weights(Rng& g, int n, int den, int* w) {
  int left = den - n;  // each weight gets 1, then distribute the rest
  for (int k = 0; k < n; ++k) w[k] = 1;
  while (left > 0) {
    ++w[irand(g, 0, n - 1)];
    --left;
  }
}

/// Rotation of p about center c by angle theta around the unit axis a (computed in double).
inline Vec3 rotate(Vec3 p, Vec3 c, Vec3 a, double theta) {
  const Vec3 v = p - c;
  const double co = std::cos(theta), si = std::sin(theta);
  const Vec3 r = co * v + si * cross(a, v) + ((1.0 - co) * dot(a, v)) * a;
  return c + r;
}

inline Vec3 random_unit(Rng& g) {
  for (;;) {
    const Vec3 v{urand(g, -1, 1), urand(g, -1, 1), urand(g, -1, 1)};
    const double n = std::sqrt(dot(v, v));
    if (n > 0.1 && n <= 1.0) return (1.0 / n) * v;
  }
}

inline Tet rotate(const Tet& t, Vec3 c, Vec3 a, double theta) {
  return {rotate(t[0], c, a, theta), rotate(t[1], c, a, theta), rotate(t[2], c, a, theta),
          rotate(t[3], c, a, theta)};
}

/// Exact sign of orient3d(a, b, c, d) (GMP rationals).
inline int orient_sign(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  mpq_class e[3][3];
  const Vec3 q[3] = {b, c, d};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) e[i][k] = mpq_class(q[i][k]) - mpq_class(a[k]);
  const mpq_class det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                        e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                        e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  return sgn(det);
}

/// Exactly flat (zero volume as rationals).
inline bool flat(const Tet& t) { return orient_sign(t[0], t[1], t[2], t[3]) == 0; }

inline double nudge(double x, int ulps) {
  const double dir = ulps > 0 ? INFINITY : -INFINITY;
  for (int k = 0; k < std::abs(ulps); ++k) x = std::nextafter(x, dir);
  return x;
}

// ---------------------------------------------------------------------------------------------
// Cases and families.

/// How a family's error is normalized: by min(|U|, |V|), which every 3D family uses, or by
/// max(|U|, |V|) (2D families that choose it, generators2d.hpp).
enum class Norm { Min, Max };

struct Case {
  Tet U, V;
  const char* kind = "";          ///< sub-family, for messages
  Norm norm = Norm::Min;
  bool exact_zero = false;        ///< touching from outside: the kernel must return exactly 0
};

struct Family {
  const char* name;
  bool random;  ///< counts towards the random pairs (else the degenerate ones)
  std::vector<Case> (*make)();
};

/// Randomly swaps the roles of U and V (keeps both orders in every family).
inline Case make_case(Rng& g, const Tet& A, const Tet& B, const char* kind, Norm norm = Norm::Min,
                      bool exact_zero = false) {
  Case c;
  if (coin(g)) {
    c.U = A;
    c.V = B;
  } else {
    c.U = B;
    c.V = A;
  }
  c.kind = kind;
  c.norm = norm;
  c.exact_zero = exact_zero;
  return c;
}

// --- random ----------------------------------------------------------------------------------

/// 10^4 random pairs: U in the unit cube, V in a unit cube shifted by up to 1/4 in each axis
/// (coordinates on the 2^-30 grid, volumes >= 10^-3); a quarter scaled by 2^k, |k| <= 20.
inline std::vector<Case> random_pairs() {
  Rng g(0x7e7a0001);
  std::vector<Case> v;
  for (int n = 0; n < 10000; ++n) {
    const Vec3 o = gvec(g, 30, -0.25, 0.25);
    Tet U = grid_tet(g, 30, 0.0, 1.0, 1e-3);
    Tet V = translate(grid_tet(g, 30, 0.0, 1.0, 1e-3), o);
    const char* kind = "unit";
    if (n % 4 == 3) {
      const double s = std::ldexp(1.0, irand(g, -20, 20));
      U = scale(U, s);
      V = scale(V, s);
      kind = "scaled";
    }
    v.push_back(make_case(g, U, V, kind));
  }
  return v;
}

// --- identical tetrahedra in every vertex order ----------------------------------------------

inline std::vector<Case> identical() {
  Rng g(0x7e7a0002);
  std::vector<Case> v;
  // All 24 x 24 orders for three tetrahedra: integer, random on a fine grid, far from the origin.
  const Tet bases[3] = {
      Tet{Vec3{0, 0, 0}, Vec3{3, 0, 1}, Vec3{1, 4, 0}, Vec3{1, 1, 5}},
      grid_tet(g, 30, 0.0, 1.0, 1e-2),
      translate(grid_tet(g, 20, 0.0, 1.0, 1e-2), Vec3{1e6, -1e7, 1e8}),
  };
  for (const Tet& T : bases)
    for (const auto& p : perms4())
      for (const auto& q : perms4()) v.push_back({permute(T, p), permute(T, q), "24x24"});
  // Every order of one against a fixed order of the other, for 60 more tetrahedra.
  for (int n = 0; n < 60; ++n) {
    Tet T;
    switch (n % 3) {
      case 0: T = int_tet(g, -10, 10); break;
      case 1: T = grid_tet(g, 40, -1.0, 1.0, 1e-3); break;
      default: T = scale(grid_tet(g, 30, 0.0, 1.0, 1e-3), std::ldexp(1.0, irand(g, -30, 30))); break;
    }
    for (const auto& p : perms4()) v.push_back(make_case(g, T, permute(T, p), "24"));
  }
  return v;
}

// --- shared faces ----------------------------------------------------------------------------

/// U = (a, b, c, d), V = (a, b, c, e) with e on the other side of abc (touching from outside,
/// exact volume 0) or on the same side (overlapping from inside). Integer coordinates.
inline std::vector<Case> shared_faces() {
  Rng g(0x7e7a0003);
  std::vector<Case> v;
  for (int n = 0; n < 2000; ++n) {
    const bool outside = n % 2 == 0;
    const Tet U = int_tet(g, -8, 8);
    const int f = irand(g, 0, 3);
    Vec3 face[3];
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != f) face[m++] = U[static_cast<std::size_t>(k)];
    const double sd = orient3d(face[0], face[1], face[2], U[static_cast<std::size_t>(f)]);
    Vec3 e;
    for (;;) {
      e = ivec(g, -10, 10);
      const double se = orient3d(face[0], face[1], face[2], e);
      if (se != 0.0 && ((se > 0) != (sd > 0)) == outside) break;
    }
    const Tet V = random_perm(g, Tet{face[0], face[1], face[2], e});
    v.push_back(make_case(g, random_perm(g, U), V, outside ? "outside" : "inside", Norm::Min,
                          outside));
  }
  return v;
}

// --- coplanar faces --------------------------------------------------------------------------

/// V has a face in the plane of a face of U (not the same triangle): its three vertices are
/// a + s (b - a) + t (c - a) with s, t multiples of 1/4; the fourth on either side.
inline std::vector<Case> coplanar_faces() {
  Rng g(0x7e7a0004);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const bool opposite = n % 2 == 0;
    const Tet U = int_tet(g, -6, 6);
    const int f = irand(g, 0, 3);
    Vec3 face[3];
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != f) face[m++] = U[static_cast<std::size_t>(k)];
    const Vec3 e1 = face[1] - face[0], e2 = face[2] - face[0];
    auto on_plane = [&] {
      const double s = irand(g, -4, 8) / 4.0, t = irand(g, -4, 8) / 4.0;
      return face[0] + (s * e1 + t * e2);
    };
    Vec3 p, q, r;
    do {
      p = on_plane();
      q = on_plane();
      r = on_plane();
    } while (dot(cross(q - p, r - p), cross(q - p, r - p)) == 0.0);
    const double sd = orient3d(face[0], face[1], face[2], U[static_cast<std::size_t>(f)]);
    Vec3 e;
    for (;;) {
      e = ivec(g, -9, 9);
      const double se = orient3d(face[0], face[1], face[2], e);
      if (se != 0.0 && ((se > 0) != (sd > 0)) == opposite) break;
    }
    v.push_back(make_case(g, random_perm(g, U), random_perm(g, Tet{p, q, r, e}),
                          opposite ? "opposite-side" : "same-side"));
  }
  return v;
}

// --- a vertex on a face, an edge or a vertex; an edge in a face ------------------------------

/// Vertices of U are even integers; points on its faces and edges are dyadic combinations with
/// denominator 8 or 16 (exact). The other vertices of V are random integers.
inline std::vector<Case> vertex_on_boundary() {
  Rng g(0x7e7a0005);
  std::vector<Case> v;
  auto even_tet = [&] { return scale(int_tet(g, -5, 5), 2.0); };
  auto rest_of_v = [&](Vec3 p0, Vec3 p1, int nfixed) {
    for (;;) {
      Tet V{p0, p1, ivec(g, -12, 12), ivec(g, -12, 12)};
      if (nfixed == 1) V[1] = ivec(g, -12, 12);
      if (orient3d(V[0], V[1], V[2], V[3]) != 0.0) return V;
    }
  };
  for (int n = 0; n < 3600; ++n) {
    const Tet U = even_tet();
    const int f = irand(g, 0, 3);
    Vec3 face[3];
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != f) face[m++] = U[static_cast<std::size_t>(k)];
    int w[3];
    Tet V;
    const char* kind;
    if (n < 1200) {  // a vertex of V strictly inside a face of U
      random_weights(g, 3, 16, w);
      V = rest_of_v(combo(face, w, 3, 16), Vec3{}, 1);
      kind = "vertex-on-face";
    } else if (n < 2200) {  // a vertex of V strictly inside an edge of U
      random_weights(g, 2, 8, w);
      V = rest_of_v(combo(face, w, 2, 8), Vec3{}, 1);
      kind = "vertex-on-edge";
    } else if (n < 3000) {  // a vertex of V on a vertex of U
      V = rest_of_v(face[0], Vec3{}, 1);
      kind = "vertex-on-vertex";
    } else {  // an edge of V inside a face of U (both endpoints on the face)
      int w2[3];
      random_weights(g, 3, 16, w);
      random_weights(g, 3, 16, w2);
      if (w[0] == w2[0] && w[1] == w2[1]) w2[0] += 1, w2[2] -= 1;  // distinct, still >= 0
      V = rest_of_v(combo(face, w, 3, 16), combo(face, w2, 3, 16), 2);
      kind = "edge-in-face";
    }
    v.push_back(make_case(g, random_perm(g, U), random_perm(g, V), kind));
  }
  return v;
}

// --- edges crossing exactly ------------------------------------------------------------------

/// An edge pq of V crosses an edge ab of U at m = (i a + (8 - i) b) / 8: p = m + t,
/// q = m - (j/4) t with an integer vector t (exact: multiples of 1/8, small).
inline std::vector<Case> edges_crossing() {
  Rng g(0x7e7a0006);
  std::vector<Case> v;
  for (int n = 0; n < 1000; ++n) {
    const Tet U = int_tet(g, -8, 8);
    const auto& e = tet_edges[irand(g, 0, 5)];
    const Vec3 ab[2] = {U[static_cast<std::size_t>(e[0])], U[static_cast<std::size_t>(e[1])]};
    int w[2];
    random_weights(g, 2, 8, w);
    const Vec3 m = combo(ab, w, 2, 8);
    Tet V;
    for (;;) {
      const Vec3 t = ivec(g, -6, 6);
      if (t == Vec3{}) continue;
      const double j = irand(g, 1, 8) / 4.0;
      V = Tet{m + t, m - j * t, ivec(g, -10, 10), ivec(g, -10, 10)};
      // The edge must cross, not lie along, ab: t not parallel to b - a.
      const Vec3 c = cross(t, ab[1] - ab[0]);
      if (dot(c, c) != 0.0 && orient3d(V[0], V[1], V[2], V[3]) != 0.0) break;
    }
    v.push_back(make_case(g, random_perm(g, U), random_perm(g, V), "edge-edge"));
  }
  return v;
}

// --- perturbations from 1 ulp to 1e-8 --------------------------------------------------------

inline std::vector<Case> perturbed() {
  Rng g(0x7e7a0007);
  std::vector<Case> v;
  auto base = [&](int n) {
    return n % 2 == 0 ? int_tet(g, -8, 8) : grid_tet(g, 30, 0.0, 1.0, 1e-3);
  };
  for (int n = 0; n < 2500; ++n) {
    const int variant = n % 5;
    Tet U = base(n / 5), V;
    const char* kind = "";
    if (variant == 0) {  // identical up to 1-3 ulps in random coordinates
      V = random_perm(g, U);
      for (auto& p : V)
        for (int k = 0; k < 3; ++k)
          if (coin(g)) p[k] = nudge(p[k], irand(g, 1, 3) * (coin(g) ? 1 : -1));
      kind = "ulps";
    } else if (variant == 1) {  // identical up to a relative 1e-16 .. 1e-8
      double diam = 0.0;
      for (const auto& e : tet_edges) {
        const Vec3 d = U[static_cast<std::size_t>(e[1])] - U[static_cast<std::size_t>(e[0])];
        diam = std::max(diam, std::sqrt(dot(d, d)));
      }
      const double delta = std::pow(10.0, -irand(g, 8, 16)) * diam;
      V = random_perm(g, U);
      for (auto& p : V)
        for (int k = 0; k < 3; ++k) p[k] += delta * urand(g, -1, 1);
      kind = "relative";
    } else if (variant == 2) {  // touching from outside through a face, then nudged 1-2 ulps
      U = int_tet(g, -8, 8);
      Vec3 e;
      const double sd = orient3d(U[0], U[1], U[2], U[3]);
      do e = ivec(g, -10, 10);
      while (!(orient3d(U[0], U[1], U[2], e) * sd < 0.0));
      V = Tet{U[0], U[1], U[2], e};
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c)
          if (coin(g)) V[static_cast<std::size_t>(k)][c] = nudge(V[static_cast<std::size_t>(k)][c], coin(g) ? 1 : -1);
      V = random_perm(g, V);
      kind = "touching-nudged";
    } else if (variant == 3) {  // rotated about the centroid by 1e-16 .. 1e-8
      const Vec3 c = 0.25 * (U[0] + U[1] + U[2] + U[3]);
      V = random_perm(g, rotate(U, c, random_unit(g), std::pow(10.0, -irand(g, 8, 16))));
      kind = "rotated";
    } else {  // a vertex of V on a face of U, nudged by 1 ulp in each coordinate
      U = scale(int_tet(g, -5, 5), 2.0);
      int w[3];
      random_weights(g, 3, 16, w);
      Vec3 p = combo(U.data(), w, 3, 16);
      for (int k = 0; k < 3; ++k) p[k] = nudge(p[k], irand(g, -1, 1));
      do V = Tet{p, ivec(g, -12, 12), ivec(g, -12, 12), ivec(g, -12, 12)};
      while (flat(V) || volume(V) < 0.5);  // not accidentally a sliver
      kind = "on-face-nudged";
    }
    v.push_back(make_case(g, random_perm(g, U), V, kind));
  }
  return v;
}

// --- far from the origin ---------------------------------------------------------------------

/// Local configurations on a grid no finer than 2^-20 (integers, eighths, sixteenths, 2^-20
/// grid) plus an offset of magnitude 1e6, 1e7 or 1e8 per axis: every sum is exact
/// (|x| < 2^27 needs at most 47 bits at 2^-20).
inline std::vector<Case> far_from_origin() {
  Rng g(0x7e7a0008);
  std::vector<Case> v;
  const double mags[3] = {1e6, 1e7, 1e8};
  for (int n = 0; n < 1800; ++n) {
    const double m = mags[n % 3];
    const Vec3 o{coin(g) ? m : -m, coin(g) ? m : -m, coin(g) ? m : -m};
    Tet U, V;
    const char* kind = "";
    switch ((n / 3) % 5) {
      case 0:  // random on the 2^-20 grid
        U = grid_tet(g, 20, 0.0, 1.0, 1e-3);
        V = translate(grid_tet(g, 20, 0.0, 1.0, 1e-3), gvec(g, 20, -0.5, 0.5));
        kind = "random";
        break;
      case 1: {  // shared face, either side
        U = int_tet(g, -8, 8);
        Vec3 e;
        const bool outside = coin(g);
        const double sd = orient3d(U[0], U[1], U[2], U[3]);
        for (;;) {
          e = ivec(g, -10, 10);
          const double se = orient3d(U[0], U[1], U[2], e);
          if (se != 0.0 && ((se * sd) < 0.0) == outside) break;
        }
        V = random_perm(g, Tet{U[0], U[1], U[2], e});
        kind = outside ? "shared-face-outside" : "shared-face-inside";
        break;
      }
      case 2: {  // a vertex on a face
        U = scale(int_tet(g, -5, 5), 2.0);
        int w[3];
        random_weights(g, 3, 16, w);
        do V = Tet{combo(U.data(), w, 3, 16), ivec(g, -12, 12), ivec(g, -12, 12), ivec(g, -12, 12)};
        while (orient3d(V[0], V[1], V[2], V[3]) == 0.0);
        kind = "vertex-on-face";
        break;
      }
      case 3:  // identical, permuted
        U = grid_tet(g, 20, 0.0, 1.0, 1e-3);
        V = random_perm(g, U);
        kind = "identical";
        break;
      default: {  // an edge crossing an edge
        U = int_tet(g, -8, 8);
        const Vec3 mid = 0.5 * (U[0] + U[1]);
        for (;;) {
          const Vec3 t = ivec(g, -6, 6);
          const Vec3 c = cross(t, U[1] - U[0]);
          V = Tet{mid + t, mid - t, ivec(g, -10, 10), ivec(g, -10, 10)};
          if (dot(c, c) != 0.0 && orient3d(V[0], V[1], V[2], V[3]) != 0.0) break;
        }
        kind = "edge-edge";
        break;
      }
    }
    Case c = make_case(g, translate(random_perm(g, U), o), translate(random_perm(g, V), o), kind);
    c.exact_zero = std::string(kind) == "shared-face-outside";
    v.push_back(c);
  }
  return v;
}

// --- slivers ---------------------------------------------------------------------------------

/// A flat tetrahedron: four points near a plane (height h), or a needle (two points close to
/// the line of the other two); randomly rotated and placed near the unit cube.
inline Tet sliver(Rng& g, double h, bool force_flat = false) {
  Tet t;
  if (force_flat || coin(g)) {  // flat: a quadrilateral-ish sliver or a cap
    for (auto& p : t) p = Vec3{urand(g, 0, 1), urand(g, 0, 1), 0.0};
    t[3].z = h;
    t[static_cast<std::size_t>(irand(g, 0, 2))].z = coin(g) ? 0.0 : -h * urand(g, 0, 1);
  } else {  // needle
    t[0] = Vec3{0, 0, 0};
    t[1] = Vec3{1, 0, 0};
    t[2] = Vec3{urand(g, 0, 1), h * urand(g, 0.5, 1), 0};
    t[3] = Vec3{urand(g, 0, 1), h * urand(g, -1, 1), h * urand(g, 0.5, 1)};
  }
  const Vec3 c{0.5, 0.5, 0.0};
  t = rotate(t, c, random_unit(g), urand(g, 0, 3.14159));
  return translate(t, Vec3{0.25, 0.25, 0.5});
}

/// Slivers (height 1e-2 .. 1e-10) against a well-shaped tetrahedron, against a mildly flat one
/// (volume >= 1e-3), and sharing one of their faces exactly with a well-shaped tetrahedron
/// (touching from outside: exactly 0; or from inside). The error is relative to the smaller
/// volume, the sliver's (the kernel refines what its estimate does not certify).
inline std::vector<Case> slivers() {
  Rng g(0x7e7a0009);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const double h = std::pow(10.0, -irand(g, 2, 10));
    Tet S;
    do S = sliver(g, h);
    while (flat(S));
    Tet T;
    const char* kind = "";
    bool exact_zero = false;
    switch (n % 4) {
      case 0:  // against a random tetrahedron
        T = grid_tet(g, 30, 0.0, 1.0, 1e-3);
        kind = "vs-random";
        break;
      case 1:  // against a mildly flat one
        do T = sliver(g, 0.3);
        while (!(volume(T) >= 1e-3));
        kind = "vs-mild-sliver";
        break;
      default: {  // sharing its largest face: the fourth vertex about a unit off the plane
        const bool outside = n % 4 == 2;
        for (;;) {
          do S = sliver(g, h, true);
          while (flat(S));
          int f = 0;
          double best = -1.0;
          for (int k = 0; k < 4; ++k) {  // face k is opposite vertex k
            const Vec3& a = S[static_cast<std::size_t>((k + 1) % 4)];
            const Vec3& b = S[static_cast<std::size_t>((k + 2) % 4)];
            const Vec3& c = S[static_cast<std::size_t>((k + 3) % 4)];
            const Vec3 nk = cross(b - a, c - a);
            if (dot(nk, nk) > best) best = dot(nk, nk), f = k;
          }
          Vec3 face[3];
          for (int k = 0, m = 0; k < 4; ++k)
            if (k != f) face[m++] = S[static_cast<std::size_t>(k)];
          const Vec3 nrm = cross(face[1] - face[0], face[2] - face[0]);
          const Vec3 c = (1.0 / 3) * (face[0] + face[1] + face[2]);
          const int side_d = orient_sign(face[0], face[1], face[2], S[static_cast<std::size_t>(f)]);
          const double len = urand(g, 0.5, 1.0);
          const Vec3 e = c + ((coin(g) ? len : -len) / std::sqrt(dot(nrm, nrm))) * nrm;
          const int side_e = orient_sign(face[0], face[1], face[2], e);
          T = Tet{face[0], face[1], face[2], e};
          if (side_e != 0 && (side_e != side_d) == outside && volume(T) >= 1e-3) break;
        }
        T = random_perm(g, T);
        kind = outside ? "shared-face-outside" : "shared-face-inside";
        exact_zero = outside;
        break;
      }
    }
    v.push_back(make_case(g, random_perm(g, S), T, kind, Norm::Min, exact_zero));
  }
  return v;
}

// --- a tiny tetrahedron inside or on the boundary of a big one -------------------------------

/// Big: integer coordinates in [-8, 8]. Tiny: scale s = 2^-k (k = 10..35, about 1e-3..3e-11)
/// around an anchor that is a dyadic combination (denominator 16) of the big vertices; offsets
/// s * w with w on the 2^-10 grid, or s * (i (b - a) + j (c - a)) for points in a face plane.
/// All sums are exact (at most 3 + 45 bits).
inline std::vector<Case> tiny_in_big() {
  Rng g(0x7e7a000a);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const Tet B = int_tet(g, -8, 8, 24.0);
    const double s = std::ldexp(1.0, -irand(g, 10, 35));
    auto off = [&] { return s * gvec(g, 10, -1.0, 1.0); };
    int w[4];
    Vec3 anchor;
    Tet T;
    const char* kind = "";
    const int variant = n % 5;
    const int f = irand(g, 0, 3);
    Vec3 face[3];
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != f) face[m++] = B[static_cast<std::size_t>(k)];
    for (;;) {
      if (variant == 0) {  // strictly inside
        random_weights(g, 4, 16, w);
        anchor = combo(B.data(), w, 4, 16);
        T = Tet{anchor + off(), anchor + off(), anchor + off(), anchor + off()};
        kind = "inside";
      } else if (variant == 1) {  // a vertex on a face of the big one
        random_weights(g, 3, 16, w);
        anchor = combo(face, w, 3, 16);
        T = Tet{anchor, anchor + off(), anchor + off(), anchor + off()};
        kind = "vertex-on-face";
      } else if (variant == 2) {  // a face in a face plane of the big one
        random_weights(g, 3, 16, w);
        anchor = combo(face, w, 3, 16);
        const Vec3 e1 = face[1] - face[0], e2 = face[2] - face[0];
        auto in_plane = [&] { return anchor + s * (double(irand(g, -4, 4)) * e1 + double(irand(g, -4, 4)) * e2); };
        T = Tet{in_plane(), in_plane(), in_plane(), anchor + off()};
        kind = "face-in-face";
      } else if (variant == 3) {  // a vertex on an edge of the big one
        random_weights(g, 2, 16, w);
        anchor = combo(face, w, 2, 16);
        T = Tet{anchor, anchor + off(), anchor + off(), anchor + off()};
        kind = "vertex-on-edge";
      } else {  // a vertex at a vertex of the big one
        anchor = face[0];
        T = Tet{anchor, anchor + off(), anchor + off(), anchor + off()};
        kind = "vertex-at-vertex";
      }
      // Not too flat: the tiny one's volume at least 1e-4 of its bounding cube.
      if (volume(T) > 1e-4 * s * s * s) break;
    }
    v.push_back(make_case(g, random_perm(g, B), random_perm(g, T), kind, Norm::Min));
  }
  return v;
}

// --- multiscale: accuracy relative to the smaller tetrahedron ---------------------------------

/// A random tetrahedron of size about 1 near the origin, well shaped (quality check by volume).
inline Tet fat_tet(Rng& g) {
  for (;;) {
    Tet t{random_unit(g), random_unit(g), random_unit(g), random_unit(g)};
    if (volume(t) >= 0.05) return t;
  }
}

/// The multiscale families, every error relative to the smaller tetrahedron (Norm::Min):
///  - cut-1eK: a tetrahedron 10^K times smaller (K = 3, 6, 8, 10, 12, 14, 16) centred on a face,
///    an edge or a vertex of a big one, so that one to three of its planes cut it; both are
///    randomly rotated, so no face is axis-aligned;
///  - inside-1eK: the same, strictly inside (exact by containment);
///  - sliver-1eK: a sliver of relative height 10^-K (K = 3, 6, 9, 12) against a well-shaped
///    tetrahedron that cuts it;
///  - scale-2^k: a random overlapping pair scaled by 2^k (k = -500, -250, 250, 500; exact);
///  - translate-2^k: a pair of size 2^(k-20) at 2^k from the origin (k = 20, 35, 50),
///    coordinates on a grid fine enough to need every bit up to 2^(k-50).
inline std::vector<Case> multiscale() {
  Rng g(0x7e7a000c);
  std::vector<Case> v;
  static const char* const kCut[7] = {"cut-1e3", "cut-1e6", "cut-1e8", "cut-1e10", "cut-1e12", "cut-1e14", "cut-1e16"};
  static const char* const kInside[7] = {"inside-1e3", "inside-1e6", "inside-1e8", "inside-1e10",
                                         "inside-1e12", "inside-1e14", "inside-1e16"};
  static const int kRatioExp[7] = {3, 6, 8, 10, 12, 14, 16};
  for (int r = 0; r < 7; ++r)
    for (int n = 0; n < 150; ++n) {
      const double ratio = std::pow(10.0, kRatioExp[r]);
      const Tet B = fat_tet(g);
      const bool inside = n % 3 == 2;
      // The centre: a point of a face (random weights on 1, 2 or 3 of its vertices) or inside.
      double w[4] = {0, 0, 0, 0};
      const int used = inside ? 4 : irand(g, 1, 3);
      double sum = 0.0;
      for (int k = 0; k < used; ++k) sum += (w[k] = urand(g, 0.2, 1.0));
      Vec3 c{};
      for (int k = 0; k < 4; ++k) c = c + (w[k] / sum) * B[static_cast<std::size_t>(k)];
      Tet T = fat_tet(g);
      for (Vec3& p : T) p = c + (1.0 / ratio) * p;
      if (flat(T)) continue;
      if (inside) {
        bool all_in = true;  // the four vertices strictly inside B (exactly)
        for (const Vec3& p : T)
          for (int k = 0; k < 4; ++k) {
            Tet F = B;
            F[static_cast<std::size_t>(k)] = p;
            all_in &= orient_sign(F[0], F[1], F[2], F[3]) == orient_sign(B[0], B[1], B[2], B[3]);
          }
        if (!all_in) continue;
      }
      v.push_back(make_case(g, random_perm(g, B), random_perm(g, T), inside ? kInside[r] : kCut[r]));
    }
  static const char* const kSliver[4] = {"sliver-1e3", "sliver-1e6", "sliver-1e9", "sliver-1e12"};
  for (int r = 0; r < 4; ++r)
    for (int n = 0; n < 300; ++n) {
      const double h = std::pow(10.0, -3.0 * (r + 1));
      Tet S;
      do S = sliver(g, h);
      while (flat(S));
      Tet T;
      do T = translate(fat_tet(g), Vec3{0.5, 0.5, 0.5} + 0.3 * random_unit(g));
      while (exact::intersection_volume(S, T) == 0);
      v.push_back(make_case(g, random_perm(g, S), T, kSliver[r]));
    }
  static const char* const kScale[4] = {"scale-2^-500", "scale-2^-250", "scale-2^250", "scale-2^500"};
  static const int kScaleExp[4] = {-500, -250, 250, 500};
  for (int r = 0; r < 4; ++r)
    for (int n = 0; n < 150; ++n) {
      const Tet A = fat_tet(g), B = translate(fat_tet(g), 0.5 * random_unit(g));
      auto sc = [&](const Tet& t) {
        Tet s = t;
        for (Vec3& p : s) p = {std::ldexp(p.x, kScaleExp[r]), std::ldexp(p.y, kScaleExp[r]), std::ldexp(p.z, kScaleExp[r])};
        return s;
      };
      v.push_back(make_case(g, sc(A), sc(B), kScale[r]));
    }
  static const char* const kTranslate[3] = {"translate-2^20", "translate-2^35", "translate-2^50"};
  static const int kTranslateExp[3] = {20, 35, 50};
  for (int r = 0; r < 3; ++r)
    for (int n = 0; n < 150; ++n) {
      const int k = kTranslateExp[r];
      const Vec3 o{std::ldexp(double(irand(g, 1, 3)), k), std::ldexp(double(irand(g, -3, 3)), k),
                   std::ldexp(double(irand(g, 1, 3)), k)};
      // Vertices on the 2^-30 grid of a unit cube, scaled to 2^(k-20): bits from 2^(k+2) down to
      // 2^(k-50), exact in a double.
      auto place = [&](Vec3 shift) {
        Tet t = grid_tet(g, 30, 0.0, 1.0, 1e-2);
        for (Vec3& p : t)
          p = o + Vec3{std::ldexp(p.x + shift.x, k - 20), std::ldexp(p.y + shift.y, k - 20), std::ldexp(p.z + shift.z, k - 20)};
        return t;
      };
      const Tet A = place({0, 0, 0}), B = place({grid(g, 2, -0.25, 0.25), grid(g, 2, -0.25, 0.25), 0.0});
      v.push_back(make_case(g, A, B, kTranslate[r]));
    }
  return v;
}

// --- lattice: the six Kuhn tetrahedra of a cube ----------------------------------------------

/// The reference tetrahedron 0, e1, e2, e3.
inline const Tet kRefTet{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

/// Four points uniform in the unit cube.
inline Tet unit_random_tet(Rng& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Tet t;
  for (Vec3& p : t) p = {u(g), u(g), u(g)};
  return t;
}

/// Four points on the grid {0, 1/4, ..., 1}^3: many coplanar faces, shared vertices and edges.
inline Tet quarter_grid_tet(Rng& g) {
  Tet t;
  for (Vec3& p : t) p = {irand(g, 0, 4) / 4.0, irand(g, 0, 4) / 4.0, irand(g, 0, 4) / 4.0};
  return t;
}

/// The Kuhn tetrahedron of the unit cube for the axis order (a, b, c): 0, e_a, e_a + e_b, 1.
inline std::array<Tet, 6> kuhn_tets() {
  std::array<Tet, 6> out{};
  int k = 0;
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& o : orders) {
    Vec3 p1{}, p2{};
    p1[o[0]] = 1;
    p2 = p1;
    p2[o[1]] = 1;
    out[static_cast<std::size_t>(k++)] = Tet{Vec3{0, 0, 0}, p1, p2, Vec3{1, 1, 1}};
  }
  return out;
}

/// The six Kuhn tetrahedra against copies scaled by 1, 1/2, 2 and shifted on the matching
/// half-lattice (4^3 shifts each): 3 x 64 x 36 = 6912 pairs.
inline std::vector<Case> lattice() {
  Rng g(0x7e7a000b);
  std::vector<Case> v;
  const auto K = kuhn_tets();
  const double scales[3] = {1.0, 0.5, 2.0};
  const double shift0[3] = {-1.0, 0.0, -2.0};
  const double step[3] = {0.5, 0.25, 1.0};
  for (int si = 0; si < 3; ++si)
    for (int ix = 0; ix < 4; ++ix)
      for (int iy = 0; iy < 4; ++iy)
        for (int iz = 0; iz < 4; ++iz) {
          const Vec3 o{shift0[si] + ix * step[si], shift0[si] + iy * step[si], shift0[si] + iz * step[si]};
          for (const Tet& A : K)
            for (const Tet& B : K) {
              Case c;
              c.U = A;
              c.V = translate(scale(B, scales[si]), o);
              c.kind = si == 0 ? "scale-1" : (si == 1 ? "scale-1/2" : "scale-2");
              v.push_back(c);
            }
        }
  return v;
}

// ---------------------------------------------------------------------------------------------

inline const std::vector<Family>& families() {
  static const std::vector<Family> list = {
      {"Random", true, random_pairs},
      {"IdenticalPermuted", false, identical},
      {"SharedFaces", false, shared_faces},
      {"CoplanarFaces", false, coplanar_faces},
      {"VertexOnBoundary", false, vertex_on_boundary},
      {"EdgesCrossing", false, edges_crossing},
      {"Perturbed", false, perturbed},
      {"FarFromOrigin", false, far_from_origin},
      {"Slivers", false, slivers},
      {"TinyInBig", false, tiny_in_big},
      {"Lattice", false, lattice},
      {"Multiscale", false, multiscale},
  };
  return list;
}

inline const Family& family(const char* name) {
  for (const Family& f : families())
    if (std::string(f.name) == name) return f;
  throw std::runtime_error(std::string("no family ") + name);
}

}  // namespace tetia::testgen
