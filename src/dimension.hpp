// src/dimension.hpp -- internal: what differs between the 3D (tetrahedra) and the 2D (triangles)
// mesh layers, as one traits type per mesh type, so that finalize, the supermesh, the remap and
// the file writers are written once as templates over it (not installed, not public API).
//
// Contract: Dim<Mesh> names the types of one dimension (point, cell, supermesh piece, kernel
// result, supermesh, a piece's local mixed mass matrix) and gives uniform access to what is
// spelled differently (volumes / areas, polyhedra / polygons, Vec3 / Vec2 coordinates).
// Everything here is a trivial forwarding function; the logic lives in the templates that use it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tetia/geometry.hpp"
#include "tetia/mesh.hpp"
#include "tetia/polygon.hpp"
#include "tetia/polyhedron.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::detail {

template <class Mesh>
struct Dim;

template <>
struct Dim<TetMesh> {
  static constexpr int d = 3;   // space dimension
  static constexpr int nv = 4;  // vertices of a cell
  using Mesh = TetMesh;
  using Point = Vec3;
  using Cell = Tet;
  using Moments = tetia::Moments;
  using Shape = Polyhedron;
  using Piece = SupermeshPiece;
  using Result = Supermesh;
  using LocalMass = std::array<double, 16>;  // a piece's mixed mass matrix, row-major
  static constexpr const char* cells_word = "tetrahedra";
  static constexpr const char* facet_word = "a face";

  static double coord(const Vec3& p, int k) { return p[k]; }
  static Vec3 point(const double* xyz) { return {xyz[0], xyz[1], xyz[2]}; }
  static const std::vector<double>& measures(const TetMesh& m) { return m.volumes; }
  static std::vector<double>& measures(TetMesh& m) { return m.volumes; }
  static double signed_measure(const Tet& t) { return signed_volume(t); }
  static double measure(const Moments& m) { return m.volume; }
  static double measure(const Piece& p) { return p.volume; }
  static Piece piece(std::int32_t s, std::int32_t t, const Moments& m) { return {s, t, m.volume, m.first}; }
  static const std::vector<Shape>& shapes(const Result& r) { return r.polyhedra; }
  static std::vector<Shape>& shapes(Result& r) { return r.polyhedra; }
  static const std::vector<LocalMass>& local_mass(const Result& r) { return r.local_mass; }
  static std::vector<LocalMass>& local_mass(Result& r) { return r.local_mass; }
};

template <>
struct Dim<TriMesh> {
  static constexpr int d = 2;
  static constexpr int nv = 3;
  using Mesh = TriMesh;
  using Point = Vec2;
  using Cell = Triangle;
  using Moments = Moments2;
  using Shape = Polygon;
  using Piece = SupermeshPiece2;
  using Result = Supermesh2;
  using LocalMass = std::array<double, 9>;
  static constexpr const char* cells_word = "triangles";
  static constexpr const char* facet_word = "an edge";

  static double coord(const Vec2& p, int k) { return k == 0 ? p.x : p.y; }
  static Vec2 point(const double* xyz) { return {xyz[0], xyz[1]}; }
  static const std::vector<double>& measures(const TriMesh& m) { return m.areas; }
  static std::vector<double>& measures(TriMesh& m) { return m.areas; }
  static double signed_measure(const Triangle& t) { return signed_area(t); }
  static double measure(const Moments& m) { return m.area; }
  static double measure(const Piece& p) { return p.area; }
  static Piece piece(std::int32_t s, std::int32_t t, const Moments& m) { return {s, t, m.area, m.first}; }
  static const std::vector<Shape>& shapes(const Result& r) { return r.polygons; }
  static std::vector<Shape>& shapes(Result& r) { return r.polygons; }
  static const std::vector<LocalMass>& local_mass(const Result& r) { return r.local_mass; }
  static std::vector<LocalMass>& local_mass(Result& r) { return r.local_mass; }
};

}  // namespace tetia::detail
