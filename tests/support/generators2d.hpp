// tests/support/generators2d.hpp -- families of triangle pairs for the 2D kernel tests
// (test_tri_vs_exact.cpp, test_tri_properties.cpp): the 2D counterpart of generators.hpp, whose
// small helpers (random numbers, the dyadic grid, ulp nudges, number formatting) it reuses.
//
// Every family is built from a fixed seed (std::mt19937_64), so a failure names a reproducible
// pair. Degenerate families are built so that the intended degeneracy holds *exactly* in
// doubles: small integer or dyadic coordinates, points on edges as dyadic combinations of
// integer vertices, far-from-origin offsets added to coordinates on a grid coarse enough for
// the sum to be exact. Only the random, perturbation, rotation and sliver families contain
// arbitrary doubles, and the exact reference takes those as they are.
//
// Counts: 10^4 random pairs, about 1.7 * 10^4 degenerate ones, in every build.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "support/generators.hpp"
#include "tetia/exact.hpp"
#include "tetia/geometry.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::testgen2d {

using testgen::coin;
using testgen::fmt;
using testgen::grid;
using testgen::irand;
using testgen::Norm;
using testgen::nudge;
using testgen::random_weights;
using testgen::Rng;
using testgen::urand;

// ---------------------------------------------------------------------------------------------
// Formatting: 17 significant digits (every double round-trips) and, for the worst cases, hex
// floats (the bits themselves).

inline std::string fmt(const Vec2& p) { return "{" + fmt(p.x) + ", " + fmt(p.y) + "}"; }

inline std::string fmt(const Triangle& t) {
  return "{" + fmt(t[0]) + ", " + fmt(t[1]) + ", " + fmt(t[2]) + "}";
}

/// "Triangle A = {...}; Triangle B = {...};" ready to paste into a test.
inline std::string fmt_pair(const Triangle& A, const Triangle& B) {
  return "Triangle A = " + fmt(A) + ";\n  Triangle B = " + fmt(B) + ";";
}

inline std::string hex(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

inline std::string hex(const Triangle& t) {
  std::string s = "{";
  for (int i = 0; i < 3; ++i) {
    const Vec2& p = t[static_cast<std::size_t>(i)];
    s += (i ? ", {" : "{") + hex(p.x) + ", " + hex(p.y) + "}";
  }
  return s + "}";
}

inline std::string hex_pair(const Triangle& A, const Triangle& B) {
  return "Triangle A = " + hex(A) + ";\n  Triangle B = " + hex(B) + ";";
}

inline std::string fmt_stats(const TriIntersectionStats& s) {
  std::ostringstream o;
  o << "edge_inherited=" << s.edge_inherited << " edge_paired=" << s.edge_paired
    << " edge_straight_line=" << s.edge_straight_line << " edge_computed=" << s.edge_computed
    << " corner_coordinates=" << s.corner_coordinates << " guardrail_clamps=" << s.guardrail_clamps
    << " reference_swaps=" << s.reference_swaps << " inconsistencies=" << s.inconsistencies
    << " retries=" << s.retries << " refined=" << s.refined << " rescaled=" << s.rescaled
    << " exact_fallbacks=" << s.exact_fallbacks << " certified=" << s.certified << " checked=" << s.checked
    << " check_rejected=" << s.check_rejected << " calls=" << s.calls;
  return o.str();
}

// ---------------------------------------------------------------------------------------------
// Small helpers.

inline Vec2 ivec(Rng& g, int lo, int hi) { return {double(irand(g, lo, hi)), double(irand(g, lo, hi))}; }

inline Vec2 gvec(Rng& g, int bits, double lo, double hi) {
  return {grid(g, bits, lo, hi), grid(g, bits, lo, hi)};
}

inline Triangle translate(const Triangle& t, Vec2 o) { return {t[0] + o, t[1] + o, t[2] + o}; }

inline Triangle scale(const Triangle& t, double s) { return {s * t[0], s * t[1], s * t[2]}; }

/// The six vertex orders; three keep the orientation, three reverse it.
inline constexpr std::array<std::array<int, 3>, 6> kPerms3 = {
    {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}}};

inline Triangle permute(const Triangle& t, const std::array<int, 3>& p) {
  return {t[static_cast<std::size_t>(p[0])], t[static_cast<std::size_t>(p[1])],
          t[static_cast<std::size_t>(p[2])]};
}

inline Triangle random_perm(Rng& g, const Triangle& t) {
  return permute(t, kPerms3[static_cast<std::size_t>(irand(g, 0, 5))]);
}

/// Exact sign of orient2d(a, b, c) (GMP rationals).
inline int orient_sign(Vec2 a, Vec2 b, Vec2 c) {
  const mpq_class det = (mpq_class(b.x) - mpq_class(a.x)) * (mpq_class(c.y) - mpq_class(a.y)) -
                        (mpq_class(b.y) - mpq_class(a.y)) * (mpq_class(c.x) - mpq_class(a.x));
  return sgn(det);
}

/// Exactly flat (zero area as rationals).
inline bool flat(const Triangle& t) { return orient_sign(t[0], t[1], t[2]) == 0; }

/// A non-flat triangle with integer coordinates in [lo, hi] (orient2d is exact for them) and
/// twice its area at least min_area2.
inline Triangle int_tri(Rng& g, int lo, int hi, double min_area2 = 1.0) {
  for (;;) {
    const Triangle t{ivec(g, lo, hi), ivec(g, lo, hi), ivec(g, lo, hi)};
    if (std::abs(orient2d(t[0], t[1], t[2])) >= min_area2) return t;
  }
}

/// A triangle with coordinates on the 2^-bits grid in [lo, hi)^2 and area >= min_area.
inline Triangle grid_tri(Rng& g, int bits, double lo, double hi, double min_area) {
  for (;;) {
    const Triangle t{gvec(g, bits, lo, hi), gvec(g, bits, lo, hi), gvec(g, bits, lo, hi)};
    if (area(t) >= min_area && !flat(t)) return t;
  }
}

/// Three points uniform in the unit square [0, 1)^2 (arbitrary doubles).
inline Triangle unit_random_tri(Rng& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Triangle t;
  for (Vec2& p : t) p = {u(g), u(g)};
  return t;
}

/// Exact dyadic combination sum w_k p_k / den (den a power of two, small integer weights,
/// small dyadic coordinates): every product and partial sum is exact.
inline Vec2 combo(const Vec2* p, const int* w, int n, int den) {
  Vec2 s{};
  for (int k = 0; k < n; ++k) s = s + double(w[k]) * p[k];
  return (1.0 / den) * s;
}

/// Rotation of p about c by theta (computed in double).
inline Vec2 rotate(Vec2 p, Vec2 c, double theta) {
  const Vec2 v = p - c;
  const double co = std::cos(theta), si = std::sin(theta);
  return c + Vec2{co * v.x - si * v.y, si * v.x + co * v.y};
}

inline Triangle rotate(const Triangle& t, Vec2 c, double theta) {
  return {rotate(t[0], c, theta), rotate(t[1], c, theta), rotate(t[2], c, theta)};
}

/// The endpoints of edge k (the edge opposite vertex k).
inline std::array<Vec2, 2> edge(const Triangle& t, int k) {
  return {t[static_cast<std::size_t>((k + 1) % 3)], t[static_cast<std::size_t>((k + 2) % 3)]};
}

inline double diameter(const Triangle& t) {
  double d = 0.0;
  for (int k = 0; k < 3; ++k) {
    const auto e = edge(t, k);
    const Vec2 v = e[1] - e[0];
    d = std::max(d, std::sqrt(v.x * v.x + v.y * v.y));
  }
  return d;
}

/// A point e with an exact side of the line ab: beyond it from c (outside == true) or on c's
/// side, found among random integer points in [lo, hi]^2.
inline Vec2 int_point_on_side(Rng& g, Vec2 a, Vec2 b, Vec2 c, bool outside, int lo, int hi) {
  const int sc = orient_sign(a, b, c);
  for (;;) {
    const Vec2 e = ivec(g, lo, hi);
    const int se = orient_sign(a, b, e);
    if (se != 0 && (se != sc) == outside) return e;
  }
}

// ---------------------------------------------------------------------------------------------
// Cases and families.

struct Case {
  Triangle A, B;
  const char* kind = "";     ///< sub-family, for messages
  Norm norm = Norm::Min;     ///< errors relative to min(|A|, |B|) or max (slivers, tiny-in-big)
  /// Exact area 0 by construction (touching from outside; on the lattice, every pair of exact
  /// area 0): the kernel must return exactly 0 and an empty polygon.
  bool exact_zero = false;
};

struct Family {
  const char* name;
  bool random;  ///< counts towards the random pairs (else the degenerate ones)
  std::vector<Case> (*make)();
};

/// Randomly swaps the roles of A and B (keeps both orders in every family).
inline Case make_case(Rng& g, const Triangle& P, const Triangle& Q, const char* kind,
                      Norm norm = Norm::Min, bool exact_zero = false) {
  Case c;
  if (coin(g)) {
    c.A = P;
    c.B = Q;
  } else {
    c.A = Q;
    c.B = P;
  }
  c.kind = kind;
  c.norm = norm;
  c.exact_zero = exact_zero;
  return c;
}

// --- random ----------------------------------------------------------------------------------

/// 10^4 random pairs: each triangle three uniform points in the unit square (arbitrary
/// doubles), redrawn while its area is below 10^-3 (the error is measured relative to the
/// smaller area; thin triangles are the sliver family's business); a quarter scaled by 2^k,
/// |k| <= 20 (exact).
inline std::vector<Case> random_pairs() {
  Rng g(0x7e7a2001);
  std::vector<Case> v;
  auto tri = [&] {
    for (;;) {
      const Triangle t = unit_random_tri(g);
      if (area(t) >= 1e-3) return t;
    }
  };
  for (int n = 0; n < 10000; ++n) {
    Triangle A = tri(), B = tri();
    const char* kind = "unit";
    if (n % 4 == 3) {
      const double s = std::ldexp(1.0, irand(g, -20, 20));
      A = scale(A, s);
      B = scale(B, s);
      kind = "scaled";
    }
    v.push_back(make_case(g, A, B, kind));
  }
  return v;
}

// --- identical triangles in every vertex order -----------------------------------------------

/// All 6 x 6 vertex orders (both roles, both orientations) for 24 triangles: integer, random
/// in the unit square, on a fine grid and scaled by 2^k, far from the origin.
inline std::vector<Case> identical() {
  Rng g(0x7e7a2002);
  std::vector<Case> v;
  for (int n = 0; n < 24; ++n) {
    Triangle T;
    const char* kind = "";
    switch (n % 4) {
      case 0: T = int_tri(g, -10, 10); kind = "integer"; break;
      case 1:
        do T = unit_random_tri(g);
        while (area(T) < 1e-3);
        kind = "unit-random";
        break;
      case 2:
        T = scale(grid_tri(g, 30, 0.0, 1.0, 1e-3), std::ldexp(1.0, irand(g, -30, 30)));
        kind = "scaled";
        break;
      default:
        T = translate(grid_tri(g, 20, 0.0, 1.0, 1e-2), Vec2{1e6, -1e8});
        kind = "far";
        break;
    }
    for (const auto& p : kPerms3)
      for (const auto& q : kPerms3) v.push_back({permute(T, p), permute(T, q), kind});
  }
  return v;
}

// --- shared edges ----------------------------------------------------------------------------

/// A = (a, b, c), B = (a, b, e) with e beyond the line ab (touching from outside: exact area
/// 0, and the kernel must give exactly 0) or on c's side (overlapping from inside). Integer
/// coordinates, random vertex orders.
inline std::vector<Case> shared_edges() {
  Rng g(0x7e7a2003);
  std::vector<Case> v;
  for (int n = 0; n < 2000; ++n) {
    const bool outside = n % 2 == 0;
    const Triangle A = int_tri(g, -8, 8);
    const int k = irand(g, 0, 2);
    const auto ab = edge(A, k);
    const Vec2 e = int_point_on_side(g, ab[0], ab[1], A[static_cast<std::size_t>(k)], outside, -10, 10);
    const Triangle B = random_perm(g, Triangle{ab[0], ab[1], e});
    v.push_back(make_case(g, random_perm(g, A), B, outside ? "outside" : "inside", Norm::Min, outside));
  }
  return v;
}

// --- collinear edges -------------------------------------------------------------------------

/// B has an edge on the line of an edge ab of A, overlapping it partly, containing it, inside
/// it or beside it: its ends are a + s (b - a), s a multiple of 1/8 in [-1, 2]; the third
/// vertex an integer point on either side (beyond the line: exact area 0).
inline std::vector<Case> collinear_edges() {
  Rng g(0x7e7a2004);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const bool opposite = n % 2 == 0;
    const Triangle A = int_tri(g, -6, 6);
    const int k = irand(g, 0, 2);
    const auto ab = edge(A, k);
    int s0 = irand(g, -8, 16), s1;
    do s1 = irand(g, -8, 16);
    while (s1 == s0);
    const Vec2 p = ab[0] + (s0 / 8.0) * (ab[1] - ab[0]);
    const Vec2 q = ab[0] + (s1 / 8.0) * (ab[1] - ab[0]);
    const Vec2 e = int_point_on_side(g, ab[0], ab[1], A[static_cast<std::size_t>(k)], opposite, -9, 9);
    v.push_back(make_case(g, random_perm(g, A), random_perm(g, Triangle{p, q, e}),
                          opposite ? "opposite-side" : "same-side", Norm::Min, opposite));
  }
  return v;
}

// --- a vertex on an edge or a vertex, an edge through a vertex -------------------------------

/// Vertices of A are even integers; points on its edges are dyadic combinations with
/// denominator 8 (exact). The other vertices of B are random integers.
inline std::vector<Case> vertex_on_boundary() {
  Rng g(0x7e7a2005);
  std::vector<Case> v;
  auto rest_of_b = [&](const Vec2* fixed, int nfixed) {
    for (;;) {
      Triangle B{ivec(g, -12, 12), ivec(g, -12, 12), ivec(g, -12, 12)};
      for (int i = 0; i < nfixed; ++i) B[static_cast<std::size_t>(i)] = fixed[i];
      if (!flat(B)) return B;
    }
  };
  for (int n = 0; n < 2000; ++n) {
    const Triangle A = scale(int_tri(g, -5, 5), 2.0);
    const int k = irand(g, 0, 2);
    const auto ab = edge(A, k);
    int w[2];
    Vec2 fixed[2];
    const char* kind;
    if (n < 600) {  // a vertex of B strictly inside an edge of A
      random_weights(g, 2, 8, w);
      fixed[0] = combo(ab.data(), w, 2, 8);
      v.push_back(make_case(g, random_perm(g, A), random_perm(g, rest_of_b(fixed, 1)), "vertex-on-edge"));
      continue;
    }
    if (n < 1100) {  // a vertex of B on a vertex of A
      fixed[0] = ab[0];
      kind = "vertex-on-vertex";
      v.push_back(make_case(g, random_perm(g, A), random_perm(g, rest_of_b(fixed, 1)), kind));
      continue;
    }
    if (n < 1600) {  // an edge of B through a vertex a of A: b0 = a + t, b1 = a - j t
      const Vec2 a = ab[0];
      Triangle B;
      for (;;) {
        const Vec2 t = ivec(g, -6, 6);
        if (t == Vec2{}) continue;
        const double j = irand(g, 1, 8) / 4.0;
        B = Triangle{a + t, a - j * t, ivec(g, -12, 12)};
        if (!flat(B)) break;
      }
      v.push_back(make_case(g, random_perm(g, A), random_perm(g, B), "edge-through-vertex"));
      continue;
    }
    // Two vertices of B on edges of A (the same edge or two different ones).
    random_weights(g, 2, 8, w);
    fixed[0] = combo(ab.data(), w, 2, 8);
    const auto cd = edge(A, coin(g) ? k : (k + irand(g, 1, 2)) % 3);
    int w2[2];
    do random_weights(g, 2, 8, w2);
    while (cd[0] == ab[0] && cd[1] == ab[1] && w2[0] == w[0]);
    fixed[1] = combo(cd.data(), w2, 2, 8);
    v.push_back(make_case(g, random_perm(g, A), random_perm(g, rest_of_b(fixed, 2)), "two-on-edges"));
  }
  return v;
}

// --- perturbations from 1 ulp to 1e-8 --------------------------------------------------------

inline std::vector<Case> perturbed() {
  Rng g(0x7e7a2007);
  std::vector<Case> v;
  auto base = [&](int n) { return n % 2 == 0 ? int_tri(g, -8, 8) : grid_tri(g, 30, 0.0, 1.0, 1e-3); };
  for (int n = 0; n < 2000; ++n) {
    const int variant = n % 4;
    Triangle A = base(n / 4), B;
    const char* kind = "";
    if (variant == 0) {  // identical up to 1-3 ulps in random coordinates
      B = random_perm(g, A);
      for (Vec2& p : B) {
        if (coin(g)) p.x = nudge(p.x, irand(g, 1, 3) * (coin(g) ? 1 : -1));
        if (coin(g)) p.y = nudge(p.y, irand(g, 1, 3) * (coin(g) ? 1 : -1));
      }
      kind = "ulps";
    } else if (variant == 1) {  // identical up to a relative 1e-16 .. 1e-8
      const double delta = std::pow(10.0, -irand(g, 8, 16)) * diameter(A);
      B = random_perm(g, A);
      for (Vec2& p : B) p = p + Vec2{delta * urand(g, -1, 1), delta * urand(g, -1, 1)};
      kind = "relative";
    } else if (variant == 2) {  // touching from outside along an edge, then nudged 1-2 ulps
      A = int_tri(g, -8, 8);
      const Vec2 e = int_point_on_side(g, A[0], A[1], A[2], true, -10, 10);
      B = Triangle{A[0], A[1], e};
      for (int k = 0; k < 2; ++k) {
        Vec2& p = B[static_cast<std::size_t>(k)];
        if (coin(g)) p.x = nudge(p.x, coin(g) ? irand(g, 1, 2) : -irand(g, 1, 2));
        if (coin(g)) p.y = nudge(p.y, coin(g) ? irand(g, 1, 2) : -irand(g, 1, 2));
      }
      B = random_perm(g, B);
      kind = "touching-nudged";
    } else {  // a vertex of B on an edge of A, nudged by up to 1 ulp in each coordinate
      A = scale(int_tri(g, -5, 5), 2.0);
      int w[2];
      random_weights(g, 2, 8, w);
      const auto ab = edge(A, irand(g, 0, 2));
      Vec2 p = combo(ab.data(), w, 2, 8);
      p.x = nudge(p.x, irand(g, -1, 1));
      p.y = nudge(p.y, irand(g, -1, 1));
      do B = Triangle{p, ivec(g, -12, 12), ivec(g, -12, 12)};
      while (flat(B) || area(B) < 0.5);  // not accidentally a sliver
      kind = "on-edge-nudged";
    }
    v.push_back(make_case(g, random_perm(g, A), B, kind));
  }
  return v;
}

// --- rotations by 1e-16 .. 1e-8 rad ----------------------------------------------------------

/// B is A rotated by +-10^-k rad (k = 8..16) about its centroid, about one of its vertices
/// (that vertex stays exactly where it is), or, for the neighbour across a shared edge, about
/// the shared edge's midpoint (nearly touching from outside).
inline std::vector<Case> rotated() {
  Rng g(0x7e7a2008);
  static const char* const kinds[3][9] = {
      {"centroid-1e-8", "centroid-1e-9", "centroid-1e-10", "centroid-1e-11", "centroid-1e-12",
       "centroid-1e-13", "centroid-1e-14", "centroid-1e-15", "centroid-1e-16"},
      {"vertex-1e-8", "vertex-1e-9", "vertex-1e-10", "vertex-1e-11", "vertex-1e-12",
       "vertex-1e-13", "vertex-1e-14", "vertex-1e-15", "vertex-1e-16"},
      {"neighbour-1e-8", "neighbour-1e-9", "neighbour-1e-10", "neighbour-1e-11",
       "neighbour-1e-12", "neighbour-1e-13", "neighbour-1e-14", "neighbour-1e-15",
       "neighbour-1e-16"}};
  std::vector<Case> v;
  for (int n = 0; n < 1800; ++n) {
    const int k = n % 9;  // 10^-(8 + k)
    const int variant = (n / 9) % 3;
    const double theta = (coin(g) ? 1.0 : -1.0) * std::pow(10.0, -(8 + k));
    const Triangle A = (n / 27) % 2 == 0 ? int_tri(g, -8, 8) : grid_tri(g, 30, 0.0, 1.0, 1e-3);
    Triangle B;
    if (variant == 0) {
      const Vec2 c = (1.0 / 3) * (A[0] + A[1] + A[2]);
      B = rotate(A, c, theta);
    } else if (variant == 1) {
      B = rotate(A, A[static_cast<std::size_t>(irand(g, 0, 2))], theta);
    } else {
      // The neighbour across edge 2 (A[0] A[1]): A's third vertex reflected through the edge's
      // midpoint, so (A[0], A[1], e) lies on the other side, then rotated about the midpoint.
      const Vec2 m = 0.5 * (A[0] + A[1]);
      const Vec2 e = m + (m - A[2]);
      B = rotate(Triangle{A[0], A[1], e}, m, theta);
    }
    if (flat(B)) continue;
    v.push_back(make_case(g, random_perm(g, A), random_perm(g, B), kinds[variant][k]));
  }
  return v;
}

// --- far from the origin ---------------------------------------------------------------------

/// Local configurations on a grid no finer than 2^-20 (integers, eighths, the 2^-20 grid) plus
/// an offset of magnitude 1e6, 1e7 or 1e8 per axis: every sum is exact (|x| < 2^27 needs at
/// most 47 bits at 2^-20).
inline std::vector<Case> far_from_origin() {
  Rng g(0x7e7a2009);
  std::vector<Case> v;
  const double mags[3] = {1e6, 1e7, 1e8};
  for (int n = 0; n < 1500; ++n) {
    const double m = mags[n % 3];
    const Vec2 o{coin(g) ? m : -m, coin(g) ? m : -m};
    Triangle A, B;
    const char* kind = "";
    bool exact_zero = false;
    switch ((n / 3) % 6) {
      case 0:  // random on the 2^-20 grid
        A = grid_tri(g, 20, 0.0, 1.0, 1e-3);
        B = translate(grid_tri(g, 20, 0.0, 1.0, 1e-3), gvec(g, 20, -0.5, 0.5));
        kind = "random";
        break;
      case 1:
      case 2: {  // shared edge, either side
        const bool outside = (n / 3) % 6 == 1;
        A = int_tri(g, -8, 8);
        const Vec2 e = int_point_on_side(g, A[0], A[1], A[2], outside, -10, 10);
        B = random_perm(g, Triangle{A[0], A[1], e});
        kind = outside ? "shared-edge-outside" : "shared-edge-inside";
        exact_zero = outside;
        break;
      }
      case 3: {  // a vertex on an edge
        A = scale(int_tri(g, -5, 5), 2.0);
        int w[2];
        random_weights(g, 2, 8, w);
        const auto ab = edge(A, irand(g, 0, 2));
        do B = Triangle{combo(ab.data(), w, 2, 8), ivec(g, -12, 12), ivec(g, -12, 12)};
        while (flat(B));
        kind = "vertex-on-edge";
        break;
      }
      case 4:  // identical, permuted
        A = grid_tri(g, 20, 0.0, 1.0, 1e-3);
        B = random_perm(g, A);
        kind = "identical";
        break;
      default: {  // collinear edges, same side
        A = int_tri(g, -6, 6);
        const Vec2 p = A[0] + (irand(g, -8, 4) / 8.0) * (A[1] - A[0]);
        const Vec2 q = A[0] + (irand(g, 5, 16) / 8.0) * (A[1] - A[0]);
        B = Triangle{p, q, int_point_on_side(g, A[0], A[1], A[2], false, -9, 9)};
        kind = "collinear-edge";
        break;
      }
    }
    v.push_back(make_case(g, translate(random_perm(g, A), o), translate(random_perm(g, B), o), kind,
                          Norm::Min, exact_zero));
  }
  return v;
}

// --- slivers ---------------------------------------------------------------------------------

/// A needle of length 1 and width 1 / aspect through the origin, and a fat triangle around the
/// origin (the pairs of test_tri_certified.cpp and test_tri_clip_check.cpp).
inline std::pair<Triangle, Triangle> needle_and_fat(Rng& g, double aspect) {
  const Triangle needle = {Vec2{-0.5, 0.0}, Vec2{0.5, urand(g, -0.5, 0.5) / aspect}, Vec2{urand(g, -0.4, 0.4), 1.0 / aspect}};
  const Triangle fat = {Vec2{urand(g, -0.6, 0.0), urand(g, -0.6, -0.1)}, Vec2{urand(g, 0.0, 0.6), urand(g, -0.6, 0.6)},
                        Vec2{urand(g, -0.6, 0.6), urand(g, 0.1, 0.6)}};
  return {needle, fat};
}

/// A thin triangle of height about h over an edge of length about 1: a needle (the apex over
/// the edge) or a cap (the apex beyond an end, all three nearly collinear); randomly rotated
/// and placed in the unit square.
inline Triangle sliver(Rng& g, double h) {
  Triangle t;
  t[0] = {0, 0};
  t[1] = {1, 0};
  const double along = coin(g) ? urand(g, 0, 1) : urand(g, 1, 1.5);
  t[2] = {along, h * urand(g, 0.5, 1) * (coin(g) ? 1 : -1)};
  t = rotate(t, Vec2{0.5, 0}, urand(g, 0, 3.14159));
  return translate(t, Vec2{0.25, 0.5});
}

/// Slivers (height 1e-2 .. 1e-10) against a random triangle (area >= 1e-2), against a mildly
/// thin one (area >= 1e-3), and sharing their long edge exactly with a well-shaped triangle
/// (touching from outside: exactly 0; or from inside). The error is relative to
/// max(|A|, |B|): from rounded points 1e-12 of the sliver's own area is out of reach.
inline std::vector<Case> slivers() {
  Rng g(0x7e7a200a);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const double h = std::pow(10.0, -irand(g, 2, 10));
    Triangle S;
    do S = sliver(g, h);
    while (flat(S));
    Triangle T;
    const char* kind = "";
    bool exact_zero = false;
    switch (n % 4) {
      case 0:
        do T = unit_random_tri(g);
        while (area(T) < 1e-2);
        kind = "vs-random";
        break;
      case 1:
        do T = sliver(g, 0.3);
        while (!(area(T) >= 1e-3) || flat(T));
        kind = "vs-mild-sliver";
        break;
      default: {  // sharing the long edge (S[0], S[1]); the apex about a unit off the line
        const bool outside = n % 4 == 2;
        const Vec2 a = S[0], b = S[1];
        const Vec2 d = b - a;
        const Vec2 mid = 0.5 * (a + b);
        for (;;) {
          const double len = urand(g, 0.5, 1.0) * (coin(g) ? 1 : -1);
          const Vec2 e = mid + Vec2{-len * d.y, len * d.x};
          const int se = orient_sign(a, b, e), sc = orient_sign(a, b, S[2]);
          T = Triangle{a, b, e};
          if (se != 0 && (se != sc) == outside && area(T) >= 1e-2) break;
        }
        kind = outside ? "shared-edge-outside" : "shared-edge-inside";
        exact_zero = outside;
        break;
      }
    }
    v.push_back(make_case(g, random_perm(g, S), random_perm(g, T), kind, Norm::Min, exact_zero));
  }
  return v;
}

// --- a tiny triangle inside or on the boundary of a big one ----------------------------------

/// Big: integer coordinates in [-8, 8]. Tiny: scale s = 2^-k (k = 10..35, about 1e-3..3e-11)
/// around an anchor that is a dyadic combination (denominator 16) of the big vertices; offsets
/// s * w with w on the 2^-10 grid, or s * i (b - a) for points on an edge's line. All sums are
/// exact (at most 4 + 46 bits).
inline std::vector<Case> tiny_in_big() {
  Rng g(0x7e7a200b);
  std::vector<Case> v;
  for (int n = 0; n < 1500; ++n) {
    const Triangle Big = int_tri(g, -8, 8, 24.0);
    const double s = std::ldexp(1.0, -irand(g, 10, 35));
    auto off = [&] { return s * gvec(g, 10, -1.0, 1.0); };
    const auto ab = edge(Big, irand(g, 0, 2));
    const int variant = n % 5;
    Triangle T;
    const char* kind = "";
    for (;;) {
      int w[3];
      Vec2 anchor;
      if (variant == 0) {  // strictly inside
        random_weights(g, 3, 16, w);
        anchor = combo(Big.data(), w, 3, 16);
        T = Triangle{anchor + off(), anchor + off(), anchor + off()};
        kind = "inside";
      } else if (variant == 1) {  // a vertex on an edge of the big one
        random_weights(g, 2, 16, w);
        anchor = combo(ab.data(), w, 2, 16);
        T = Triangle{anchor, anchor + off(), anchor + off()};
        kind = "vertex-on-edge";
      } else if (variant == 2) {  // an edge on an edge's line of the big one
        random_weights(g, 2, 16, w);
        anchor = combo(ab.data(), w, 2, 16);
        const Vec2 d = ab[1] - ab[0];
        const int i0 = irand(g, -4, 4);
        int i1;
        do i1 = irand(g, -4, 4);
        while (i1 == i0);
        T = Triangle{anchor + s * (double(i0) * d), anchor + s * (double(i1) * d), anchor + off()};
        kind = "edge-on-edge";
      } else if (variant == 3) {  // a vertex at a vertex of the big one
        anchor = ab[0];
        T = Triangle{anchor, anchor + off(), anchor + off()};
        kind = "vertex-at-vertex";
      } else {  // two vertices on two edges of the big one near their common vertex
        const Vec2 c = ab[0];
        const Vec2 p = Big[0] == c ? Big[1] : Big[0];
        const Vec2 q = Big[2] == c ? Big[1] : Big[2];
        T = Triangle{c + (s * irand(g, 1, 8)) * (p - c), c + (s * irand(g, 1, 8)) * (q - c),
                     c + off()};
        kind = "corner-cut";
      }
      // Not too flat: at least 1e-2 of s^2 (the tiny triangle's scale).
      if (!flat(T) && area(T) > 1e-2 * s * s) break;
    }
    v.push_back(make_case(g, random_perm(g, Big), random_perm(g, T), kind));
  }
  return v;
}

// --- adversarial: size ratios, slivers, scales and translations (issue 15) ------------------

/// Pairs whose error is measured against the smaller triangle at every size ratio, sliver
/// height, scale and distance from the origin (arbitrary doubles; the exact reference takes
/// them as they are):
///  - ratio-cut-R, ratio-in-R, ratio-vertex-R: a random triangle 1/R the size of a rotated
///    reference (no edge axis-aligned), centred on the midpoint of one of its edges (cut by it),
///    strictly inside, or with one of its vertices within 0.6 of its centroid, R = 1e3, 1e6,
///    1e9, 1e12, 1e14, 1e16;
///  - sliver-H: a triangle of relative height H = 1e-6, 1e-9, 1e-12 across a fat one, rotated;
///  - scale-K: a random pair scaled by 2^K, K = +-300, +-400, +-500 (the products of the
///    kernel leave the double range there without the rescaling);
///  - translate-K: a random pair translated by (2^K, -2^K) (rounded), K = 20, 35, 50.
inline std::vector<Case> adversarial() {
  Rng g(0x7e7a200d);
  std::vector<Case> v;
  const double ratios[] = {1e3, 1e6, 1e9, 1e12, 1e14, 1e16};
  const char* cut_kinds[] = {"ratio-cut-1e3", "ratio-cut-1e6", "ratio-cut-1e9", "ratio-cut-1e12", "ratio-cut-1e14", "ratio-cut-1e16"};
  const char* in_kinds[] = {"ratio-in-1e3", "ratio-in-1e6", "ratio-in-1e9", "ratio-in-1e12", "ratio-in-1e14", "ratio-in-1e16"};
  const char* vertex_kinds[] = {"ratio-vertex-1e3", "ratio-vertex-1e6", "ratio-vertex-1e9", "ratio-vertex-1e12", "ratio-vertex-1e14",
                                "ratio-vertex-1e16"};
  auto fat = [&](double size) {
    for (;;) {
      const Triangle t = scale(unit_random_tri(g), size);
      if (area(t) >= 0.05 * size * size) return t;
    }
  };
  // The small triangle is of size 1 near the origin, where its coordinates resolve it, and the
  // big one R times larger (a small triangle of size 1e-16 at coordinates of order 1 would be
  // flat to the rounding of its own coordinates).
  for (int r = 0; r < 6; ++r)
    for (int n = 0; n < 150; ++n) {
      const double theta = urand(g, 0.1, 6.2);
      const Triangle big = scale(rotate(Triangle{Vec2{0, 0}, Vec2{1, 0}, Vec2{0.3, 0.9}}, Vec2{0, 0}, theta), ratios[r]);
      const Triangle t = fat(1.0);
      const Vec2 c = (1.0 / 3.0) * (t[0] + t[1] + t[2]);
      const int e = irand(g, 0, 2);
      const Vec2 mid = 0.5 * (big[(e + 1) % 3] + big[(e + 2) % 3]);
      v.push_back(make_case(g, random_perm(g, translate(big, c - mid)), random_perm(g, t), cut_kinds[r]));
      const Vec2 inside = (1.0 / 3.0) * (big[0] + big[1] + big[2]);
      v.push_back(make_case(g, random_perm(g, translate(big, c - inside)), random_perm(g, t), in_kinds[r]));
      // A vertex of the big one in or near the small one: two of its lines cross the small
      // triangle close together, where the order of their crossings along its edges is decided.
      const double phi = urand(g, 0.0, 6.2), rho = urand(g, 0.0, 0.6);
      const Vec2 near = c + Vec2{rho * std::cos(phi), rho * std::sin(phi)};
      v.push_back(make_case(g, random_perm(g, translate(big, near - big[irand(g, 0, 2)])), random_perm(g, t), vertex_kinds[r]));
    }
  const double heights[] = {1e-6, 1e-9, 1e-12};
  const char* sliver_kinds[] = {"sliver-1e-6", "sliver-1e-9", "sliver-1e-12"};
  for (int h = 0; h < 3; ++h)
    for (int n = 0; n < 200; ++n) {
      const double theta = urand(g, 0.1, 6.2);
      const Vec2 o{urand(g, 0.2, 0.8), urand(g, 0.2, 0.8)};
      const Triangle S{Vec2{-0.6, 0.0}, Vec2{0.7, urand(g, -0.1, 0.1)}, Vec2{urand(g, -0.3, 0.3), heights[h]}};
      v.push_back(make_case(g, random_perm(g, rotate(fat(1.0), o, theta)), random_perm(g, translate(rotate(S, Vec2{0, 0}, theta), o)),
                            sliver_kinds[h]));
    }
  const int exps[] = {-500, -400, -300, 300, 400, 500};
  const char* scale_kinds[] = {"scale-2^-500", "scale-2^-400", "scale-2^-300", "scale-2^300", "scale-2^400", "scale-2^500"};
  for (int k = 0; k < 6; ++k)
    for (int n = 0; n < 150; ++n) {
      const double f = std::ldexp(1.0, exps[k]);
      v.push_back(make_case(g, scale(fat(1.0), f), scale(fat(1.0), f), scale_kinds[k]));
    }
  const int shifts[] = {20, 35, 50};
  const char* shift_kinds[] = {"translate-2^20", "translate-2^35", "translate-2^50"};
  for (int k = 0; k < 3; ++k)
    for (int n = 0; n < 150; ++n) {
      const Vec2 o{std::ldexp(1.0, shifts[k]), -std::ldexp(1.0, shifts[k])};
      Triangle A, B;
      do {  // rounded to the grid of doubles near 2^K: redrawn if that flattens one
        A = translate(fat(1.0), o), B = translate(fat(1.0), o);
      } while (area(A) < 0.02 || area(B) < 0.02);
      v.push_back(make_case(g, A, B, shift_kinds[k]));
    }
  return v;
}

// --- lattice: right triangles of a grid ------------------------------------------------------

/// The four right triangles that the two diagonals of the unit square cut it into (lower-left
/// and upper-right of the diagonal x = y; lower-right and upper-left of x + y = 1), CCW.
inline std::array<Triangle, 4> lattice_tris() {
  return {Triangle{Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}}, Triangle{Vec2{1, 1}, Vec2{0, 1}, Vec2{1, 0}},
          Triangle{Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}}, Triangle{Vec2{0, 0}, Vec2{1, 1}, Vec2{0, 1}}};
}

/// The four lattice triangles against copies scaled by 1, 1/2, 2 and shifted on the matching
/// quarter-lattice (8 x 8 shifts each): 3 x 64 x 16 = 3072 pairs, with shared edges, collinear
/// edges, vertices on edges and on vertices everywhere. Everything is exact, so a pair whose
/// exact area is 0 (touching or disjoint) must give exactly 0.
inline std::vector<Case> lattice() {
  std::vector<Case> v;
  const auto K = lattice_tris();
  const double scales[3] = {1.0, 0.5, 2.0};
  const double shift0[3] = {-1.0, -0.5, -2.0};
  const double step[3] = {0.25, 0.125, 0.5};
  const char* kinds[3] = {"scale-1", "scale-1/2", "scale-2"};
  for (int si = 0; si < 3; ++si)
    for (int ix = 0; ix < 8; ++ix)
      for (int iy = 0; iy < 8; ++iy) {
        const Vec2 o{shift0[si] + ix * step[si], shift0[si] + iy * step[si]};
        for (const Triangle& A : K)
          for (const Triangle& B : K) {
            Case c;
            c.A = A;
            c.B = translate(scale(B, scales[si]), o);
            c.kind = kinds[si];
            c.exact_zero = sgn(exact::intersection_area(c.A, c.B)) == 0;
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
      {"SharedEdges", false, shared_edges},
      {"CollinearEdges", false, collinear_edges},
      {"VertexOnBoundary", false, vertex_on_boundary},
      {"Perturbed", false, perturbed},
      {"Rotated", false, rotated},
      {"FarFromOrigin", false, far_from_origin},
      {"Slivers", false, slivers},
      {"TinyInBig", false, tiny_in_big},
      {"Lattice", false, lattice},
      {"Adversarial", false, adversarial},
  };
  return list;
}

inline const Family& family(const char* name) {
  for (const Family& f : families())
    if (std::string(f.name) == name) return f;
  throw std::runtime_error(std::string("no 2D family ") + name);
}

}  // namespace tetia::testgen2d
