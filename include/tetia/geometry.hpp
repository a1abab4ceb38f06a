// tetia/geometry.hpp -- points, tetrahedra and triangles, and the few exact-rounding-aware
// helpers every layer above uses.
//
// Contract: plain aggregates, no invariants. A `Tet` is four vertices in any orientation;
// functions that need a positive orientation say so and reorient themselves.
#pragma once

#include <array>
#include <cmath>

namespace tetia {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
  friend constexpr bool operator==(Vec3 a, Vec3 b) = default;
};

constexpr double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Four vertices; faces are numbered by the vertex they do not contain.
using Tet = std::array<Vec3, 4>;

/// Six times the signed volume: det[b - a, c - a, d - a]. Positive when (b - a, c - a, d - a)
/// is right-handed. Plain floating point (not an exact predicate).
constexpr double orient3d(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  return dot(b - a, cross(c - a, d - a));
}

/// Signed volume of a tetrahedron (positive for a right-handed vertex order).
constexpr double signed_volume(const Tet& t) { return orient3d(t[0], t[1], t[2], t[3]) / 6.0; }

/// Unsigned volume of a tetrahedron.
inline double volume(const Tet& t) { return std::abs(signed_volume(t)); }

/// The six edges of a tetrahedron as vertex pairs, in the order of the paper's Snippet 3
/// (01, 02, 12, 03, 13, 23 in 0-based numbering: jmap = [1,1,2,1,2,3; 2,3,3,4,4,4]).
inline constexpr int tet_edges[6][2] = {{0, 1}, {0, 2}, {1, 2}, {0, 3}, {1, 3}, {2, 3}};

struct Vec2 {
  double x = 0.0, y = 0.0;
  friend constexpr Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
  friend constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
  friend constexpr Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
  friend constexpr bool operator==(Vec2 a, Vec2 b) = default;
};

/// Three vertices in any orientation; edges are numbered by the vertex they do not contain.
using Triangle = std::array<Vec2, 3>;

/// Twice the signed area: det[b - a, c - a]. Positive when (a, b, c) is counter-clockwise.
/// Plain floating point (not an exact predicate).
constexpr double orient2d(Vec2 a, Vec2 b, Vec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Signed area of a triangle (positive for counter-clockwise vertices).
constexpr double signed_area(const Triangle& t) { return orient2d(t[0], t[1], t[2]) / 2.0; }

/// Unsigned area of a triangle.
inline double area(const Triangle& t) { return std::abs(signed_area(t)); }

}  // namespace tetia
