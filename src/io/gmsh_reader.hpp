// src/io/gmsh_reader.hpp -- the same reads through the Gmsh library's own reader (internal):
// for the tests that check the strict reader (msh_reader.hpp) against Gmsh on the files Gmsh
// writes, and for the reading benchmark. Not for user input: Gmsh 4.8's reader can crash the
// process on a corrupted file (see msh_reader.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tetia/io.hpp"

namespace tetia::detail {

/// read_any_mesh through Gmsh (its node and cell order, the same conventions).
AnyMesh gmsh_read_any_mesh(const std::filesystem::path& file, MeshReadInfo* info = nullptr);

/// read_msh_field through Gmsh.
std::vector<double> gmsh_read_msh_field(const std::filesystem::path& file, const std::string& name, bool on_cells);

}  // namespace tetia::detail
