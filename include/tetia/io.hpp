// tetia/io.hpp -- reading meshes (Gmsh files, through the Gmsh library), writing VTU and .msh,
// and generating meshes with Gmsh.
//
// Contract: read_mesh accepts .msh 2.2 and 4.1, ASCII and binary; it keeps the tetrahedra of
// all physical groups (first-order, 4-node) and ignores other elements, counting them.
// The result is finalized. Errors (missing file, unreadable file, no tetrahedra, bad data)
// throw std::runtime_error with a message starting "tetia: FILE: ".
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "tetia/mesh.hpp"

namespace tetia {

struct MeshReadInfo {
  std::size_t ignored_elements = 0;  ///< elements other than 4-node tetrahedra
  std::vector<std::string> node_fields, cell_fields;  ///< names of data found in the file (if any)
};

/// A named field on a mesh: one value per node or per cell.
struct Field {
  std::string name;
  std::vector<double> values;
};

TetMesh read_mesh(const std::filesystem::path& file, MeshReadInfo* info = nullptr);

/// Reads a named scalar field (node data or element data) from a .msh file written by Gmsh or
/// write_msh; `on_cells` says which. Throws if the field is absent.
std::vector<double> read_msh_field(const std::filesystem::path& file, const std::string& name, bool on_cells);

/// ParaView's unstructured grid, ASCII, with cell and point data.
void write_vtu(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {});

/// Gmsh .msh 4.1 ASCII, with node and element data.
void write_msh(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {});

/// Meshes generated with the Gmsh library at element size h.
TetMesh generate_box(Vec3 lo, Vec3 hi, double h);
TetMesh generate_ball(Vec3 center, double radius, double h);
TetMesh generate_torus(Vec3 center, double major_radius, double minor_radius, double h);

}  // namespace tetia
