// app/mesh_kind.hpp -- what the mesh commands need to know about a dimension: its types and
// its words (tetrahedral meshes: 3D, volumes; triangular ones: 2D, areas).
#pragma once

#include <vector>

#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::app {

// What the commands need to know about a dimension: its types and its words.
template <class Mesh>
struct Kind;
template <>
struct Kind<TetMesh> {
  static constexpr int dim = 3;
  using Point = Vec3;
  using Result = Supermesh;
  using Piece = SupermeshPiece;
  using Loads = P1Loads;
  static constexpr const char* measure = "volume";  // the JSON keys' suffix
  static constexpr const char* cells = "tetrahedra";
  static const std::vector<double>& measures(const TetMesh& m) { return m.volumes; }
  static double total(const TetMesh& m) { return m.total_volume(); }
  static double total(const Supermesh& s) { return s.intersection_volume(); }
  static double measure_of(const SupermeshPiece& p) { return p.volume; }
};
template <>
struct Kind<TriMesh> {
  static constexpr int dim = 2;
  using Point = Vec2;
  using Result = Supermesh2;
  using Piece = SupermeshPiece2;
  using Loads = P1Loads2;
  static constexpr const char* measure = "area";
  static constexpr const char* cells = "triangles";
  static const std::vector<double>& measures(const TriMesh& m) { return m.areas; }
  static double total(const TriMesh& m) { return m.total_area(); }
  static double total(const Supermesh2& s) { return s.intersection_area(); }
  static double measure_of(const SupermeshPiece2& p) { return p.area; }
};

}  // namespace tetia::app
