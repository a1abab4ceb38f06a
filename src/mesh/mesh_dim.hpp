// src/mesh/mesh_dim.hpp -- internal: what differs between the 3D (tetrahedra) and the 2D
// (triangles) mesh layers, as one traits type per mesh type, so that finalize, the readers and
// the writers are written once as templates over it (not installed, not public API). The
// layers above add their own types (src/supermesh/dimension.hpp); this one names only meshes.
//
// Contract: MeshDim<Mesh> names the point and cell types of one dimension and gives uniform
// access to what is spelled differently (volumes / areas, Vec3 / Vec2 coordinates). Everything
// here is a trivial forwarding function; the logic lives in the templates that use it.
#pragma once

#include <vector>

#include "tetia/geometry.hpp"
#include "tetia/mesh.hpp"

namespace tetia::detail {

template <class Mesh>
struct MeshDim;

template <>
struct MeshDim<TetMesh> {
  static constexpr int d = 3;   // space dimension
  static constexpr int nv = 4;  // vertices of a cell
  using Mesh = TetMesh;
  using Point = Vec3;
  using Cell = Tet;
  static constexpr const char* cells_word = "tetrahedra";
  static constexpr const char* facet_word = "a face";

  static double coord(const Vec3& p, int k) { return p[k]; }
  static Vec3 point(const double* xyz) { return {xyz[0], xyz[1], xyz[2]}; }
  static const std::vector<double>& measures(const TetMesh& m) { return m.volumes; }
  static std::vector<double>& measures(TetMesh& m) { return m.volumes; }
  static double signed_measure(const Tet& t) { return signed_volume(t); }
};

template <>
struct MeshDim<TriMesh> {
  static constexpr int d = 2;
  static constexpr int nv = 3;
  using Mesh = TriMesh;
  using Point = Vec2;
  using Cell = Triangle;
  static constexpr const char* cells_word = "triangles";
  static constexpr const char* facet_word = "an edge";

  static double coord(const Vec2& p, int k) { return k == 0 ? p.x : p.y; }
  static Vec2 point(const double* xyz) { return {xyz[0], xyz[1]}; }
  static const std::vector<double>& measures(const TriMesh& m) { return m.areas; }
  static std::vector<double>& measures(TriMesh& m) { return m.areas; }
  static double signed_measure(const Triangle& t) { return signed_area(t); }
};

}  // namespace tetia::detail
