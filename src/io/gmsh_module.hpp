// src/io/gmsh_module.hpp -- the Gmsh module (libtetia_gmsh.so, gmsh_module.cpp): what tetia does
// with the Gmsh library, loaded with dlopen the first time it is needed (internal).
//
// The library itself does not link Gmsh: a program that reads, intersects and remaps never
// loads it (libgmsh's start-up alone costs about 0.1 s). generate_box and the other generators
// of tetia/io.hpp, and Gmsh's reader for the tests (gmsh_reader.hpp), call through
// gmsh_module(), which loads the module once (thread-safe) from, in order: the path in the
// environment variable TETIA_GMSH_MODULE; for a shared libtetia, tetia/<module> next to
// libtetia.so itself (TETIA_GMSH_MODULE_RELATIVE, so a moved installation finds its own); the
// build tree's module (TETIA_GMSH_MODULE_BUILD, set by CMake); the installed one
// (TETIA_GMSH_MODULE_INSTALL). If none loads it throws
// std::runtime_error("tetia: generating meshes needs the Gmsh module ...") naming the paths
// tried and dlopen's reason. The module is built by the same build as the library (the same
// compiler and standard library), so the table passes C++ types and exceptions as they are;
// kGmshModuleVersion guards against a stale module from another build.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace tetia::detail {

inline constexpr int kGmshModuleVersion = 1;

struct GmshModule {
  int version;
  TetMesh (*generate_box)(Vec3 lo, Vec3 hi, double h);
  TetMesh (*generate_ball)(Vec3 center, double radius, double h);
  TetMesh (*generate_torus)(Vec3 center, double major_radius, double minor_radius, double h);
  TriMesh (*generate_rectangle)(Vec2 lo, Vec2 hi, double h);
  TriMesh (*generate_disk)(Vec2 center, double radius, double h);
  TriMesh (*generate_annulus)(Vec2 center, double inner_radius, double outer_radius, double h);
  AnyMesh (*read_any_mesh)(const std::filesystem::path& file, MeshReadInfo* info);
  std::vector<double> (*read_msh_field)(const std::filesystem::path& file, const std::string& name, bool on_cells);
};

/// The loaded module (see above).
const GmshModule& gmsh_module();

}  // namespace tetia::detail

/// The module's one exported symbol.
extern "C" const tetia::detail::GmshModule* tetia_gmsh_module();
