// src/io/msh_mesh.hpp -- a parsed .msh file (msh_reader.hpp) as a mesh and its fields, with the
// same conventions as a mesh taken from Gmsh's model (io.cpp): nodes by increasing tag (all of
// the file's nodes), the first-order cells of the mesh type by increasing element tag, each
// node set once (a .msh 2.2 file lists a cell once per physical group); fields at their first
// time step with data (internal to the library).
//
// Errors, "tetia: FILE: ..." with the line (ASCII) or byte offset (binary) of the records at
// fault: a node tag given twice with other coordinates, an element tag given twice with other
// nodes, an element naming a node tag that no node has; and, for a 2D mesh, triangles off a
// plane z = const.
#pragma once

#include <string>
#include <vector>

#include "mesh_assembly.hpp"
#include "msh_reader.hpp"
#include "tetia/mesh.hpp"

namespace tetia::detail {

/// The cells of Mesh's type (TetMesh or TriMesh), not finalized; with `corner_nodes`, cells of
/// higher order too, by their corner nodes (Extracted::straightened counts them).
template <class Mesh>
Extracted<Mesh> extract_msh(const MshFile& file, const std::string& name, bool corner_nodes = false);

/// 3 if the file has tetrahedra (of any order), else 2 if it has triangles (of any order), else 0.
int msh_dimension(const MshFile& file);

/// The file's data blocks ($NodeData, $ElementData, $ElementNodeData), one ViewData each, in
/// file order; `with_values` = false keeps names, kinds, steps, components and one tag of a
/// block with values (so that field_values can tell empty steps).
std::vector<ViewData> msh_views(const MshFile& file, bool with_values);

}  // namespace tetia::detail
