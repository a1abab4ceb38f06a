// src/supermesh/dimension.hpp -- internal: what differs between the 3D (tetrahedra) and the 2D
// (triangles) supermesh and remap, on top of the meshes' own traits (src/mesh/mesh_dim.hpp), so
// that the supermesh and the remap are written once as templates (not installed, not public
// API).
//
// Contract: Dim<Mesh> is MeshDim<Mesh> (points, cells, measures) plus the types of the layers
// above the meshes (kernel moments, supermesh piece and result, a piece's shape and its local
// mixed mass matrix) and uniform access to them. Everything here is a trivial forwarding
// function; the logic lives in the templates that use it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "../mesh/mesh_dim.hpp"
#include "tetia/polygon.hpp"
#include "tetia/polyhedron.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::detail {

template <class Mesh>
struct Dim;

template <>
struct Dim<TetMesh> : MeshDim<TetMesh> {
  using Moments = tetia::Moments;
  using Shape = Polyhedron;
  using Piece = SupermeshPiece;
  using Result = Supermesh;
  using LocalMass = std::array<double, 16>;  // a piece's mixed mass matrix, row-major

  static double measure(const Moments& m) { return m.volume; }
  static double measure(const Piece& p) { return p.volume; }
  static Piece piece(std::int32_t s, std::int32_t t, const Moments& m) { return {s, t, m.volume, m.first}; }
  static const std::vector<Shape>& shapes(const Result& r) { return r.polyhedra; }
  static std::vector<Shape>& shapes(Result& r) { return r.polyhedra; }
  static const std::vector<LocalMass>& local_mass(const Result& r) { return r.local_mass; }
  static std::vector<LocalMass>& local_mass(Result& r) { return r.local_mass; }
};

template <>
struct Dim<TriMesh> : MeshDim<TriMesh> {
  using Moments = Moments2;
  using Shape = Polygon;
  using Piece = SupermeshPiece2;
  using Result = Supermesh2;
  using LocalMass = std::array<double, 9>;

  static double measure(const Moments& m) { return m.area; }
  static double measure(const Piece& p) { return p.area; }
  static Piece piece(std::int32_t s, std::int32_t t, const Moments& m) { return {s, t, m.area, m.first}; }
  static const std::vector<Shape>& shapes(const Result& r) { return r.polygons; }
  static std::vector<Shape>& shapes(Result& r) { return r.polygons; }
  static const std::vector<LocalMass>& local_mass(const Result& r) { return r.local_mass; }
  static std::vector<LocalMass>& local_mass(Result& r) { return r.local_mass; }
};

}  // namespace tetia::detail
