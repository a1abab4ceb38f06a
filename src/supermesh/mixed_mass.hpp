// src/supermesh/mixed_mass.hpp -- internal: the local mixed mass matrix of one supermesh piece, shared by
// the supermesh (SupermeshOptions::keep_mixed_mass: computed while the kernel's polyhedron or
// polygon is at hand, only the numbers kept) and the remap (from kept polyhedra or polygons).
// Not installed, not public API.
//
// Contract: piece_mixed_mass<Mesh>(U, P, A) sets A[i * nv + j] (nv = d + 1 vertices of a cell)
// to the integral over the piece P of (target basis i) x (source basis j), where U is the
// source cell and P = intersect(U, target cell) (corners' `bary` are their target barycentric
// coordinates). The piece is split into simplices (a fan from corner 0 over the facets of a
// polyhedron not containing it; a fan from corner 0 for a polygon) and the product of two linear
// functions is integrated exactly on each: |S| / ((d + 1)(d + 2)) (sum_v f_v g_v + (sum_v f_v)
// (sum_v g_v)). One function, called from both places, so kept numbers and numbers recomputed
// from kept shapes are the same bit for bit (the build has no FP contraction or fast math).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "dimension.hpp"

namespace tetia::detail {

// Barycentric coordinates of p in U, not normalized for rounding (det is U's determinant).
inline std::array<double, 4> barycentric(const Tet& U, Vec3 p, double det) {
  return {orient3d(p, U[1], U[2], U[3]) / det, orient3d(U[0], p, U[2], U[3]) / det,
          orient3d(U[0], U[1], p, U[3]) / det, orient3d(U[0], U[1], U[2], p) / det};
}
inline std::array<double, 3> barycentric(const Triangle& U, Vec2 p, double det) {
  return {orient2d(p, U[1], U[2]) / det, orient2d(U[0], p, U[2]) / det, orient2d(U[0], U[1], p) / det};
}
inline double determinant(const Tet& U) { return orient3d(U[0], U[1], U[2], U[3]); }
inline double determinant(const Triangle& U) { return orient2d(U[0], U[1], U[2]); }

// The simplices of a kernel result as corner indices, each with its weight |S| / ((d+1)(d+2))
// (the factor of the exact product rule, see the top), computed as one determinant divided by
// d! (d+1) (d+2). A polyhedron: the fan from corner 0 over the facets that do not contain it
// (facets are counter-clockwise seen from outside, so the determinants are positive).
template <class F>
void for_each_simplex(const Polyhedron& P, F&& f) {
  const Vec3 apex = P.corner(0).point;
  for (int fa = 0; fa < P.num_facets(); ++fa) {
    const auto ids = P.facet(fa);
    if (std::find(ids.begin(), ids.end(), std::uint8_t{0}) != ids.end()) continue;
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
      const std::array<int, 4> v = {0, ids[0], ids[k], ids[k + 1]};
      f(v, orient3d(apex, P.corner(v[1]).point, P.corner(v[2]).point, P.corner(v[3]).point) / 120.0);
    }
  }
}
// A polygon: the fan from corner 0 (corners are counter-clockwise).
template <class F>
void for_each_simplex(const Polygon& P, F&& f) {
  const Vec2 apex = P.corner(0).point;
  for (int k = 1; k + 1 < P.num_corners(); ++k) {
    const std::array<int, 3> v = {0, k, k + 1};
    f(v, orient2d(apex, P.corner(k).point, P.corner(k + 1).point) / 24.0);
  }
}

template <class Mesh>
using CornerBary = std::array<std::array<double, Dim<Mesh>::nv>, Dim<Mesh>::Shape::max_corners>;

// Barycentric coordinates of the corners of a piece in its source cell U: computed from the
// point, with the coordinates of U's facets the corner lies on (labels below nv) set to exactly
// zero, negatives (rounding) clamped, scaled to sum to 1.
template <class Mesh>
void source_bary(const typename Dim<Mesh>::Cell& U, const typename Dim<Mesh>::Shape& P, CornerBary<Mesh>& out) {
  constexpr std::size_t nv = Dim<Mesh>::nv;
  const double det = determinant(U);
  for (int c = 0; c < P.num_corners(); ++c) {
    const auto& k = P.corner(c);
    auto b = barycentric(U, k.point, det);
    for (const auto l : k.labels)
      if (l < nv) b[l] = 0.0;
    double sum = 0.0;
    for (double& x : b) {
      if (!(x > 0.0)) x = 0.0;
      sum += x;
    }
    auto& o = out[static_cast<std::size_t>(c)];
    for (std::size_t q = 0; q < nv; ++q) o[q] = sum > 0.0 ? b[q] / sum : 1.0 / static_cast<double>(nv);
  }
}

// Local mixed mass matrix of one piece, row-major: A[i * nv + j] = integral over the piece of
// (target basis i) x (source basis j), exact for the product of two linear functions on each
// simplex. sb: the corners' source barycentric coordinates (source_bary).
template <class Mesh>
void local_mixed(const typename Dim<Mesh>::Shape& P, const CornerBary<Mesh>& sb, typename Dim<Mesh>::LocalMass& A) {
  constexpr std::size_t nv = Dim<Mesh>::nv;
  A.fill(0.0);
  for_each_simplex(P, [&](const std::array<int, nv>& v, double w) {
    double F[nv] = {}, G[nv] = {}, FG[nv][nv] = {};
    for (const int c : v) {
      const auto& f = P.corner(c).bary;
      const auto& g = sb[static_cast<std::size_t>(c)];
      for (std::size_t i = 0; i < nv; ++i) {
        F[i] += f[i];
        G[i] += g[i];
        for (std::size_t j = 0; j < nv; ++j) FG[i][j] += f[i] * g[j];
      }
    }
    for (std::size_t i = 0; i < nv; ++i)
      for (std::size_t j = 0; j < nv; ++j) A[i * nv + j] += w * (FG[i][j] + F[i] * G[j]);
  });
}

// The whole computation for one piece: U the source cell, P = intersect(U, target cell).
template <class Mesh>
void piece_mixed_mass(const typename Dim<Mesh>::Cell& U, const typename Dim<Mesh>::Shape& P,
                      typename Dim<Mesh>::LocalMass& A) {
  CornerBary<Mesh> sb;
  source_bary<Mesh>(U, P, sb);
  local_mixed<Mesh>(P, sb, A);
}

}  // namespace tetia::detail
