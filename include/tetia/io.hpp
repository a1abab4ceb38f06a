// tetia/io.hpp -- reading meshes (Gmsh .msh files, with tetia's own strict reader), writing VTU
// and .msh, and generating meshes with Gmsh (loaded on first use); tetrahedral (3D) and
// triangular (2D) alike.
//
// Contract: the readers accept .msh 2.x and 4.1, ASCII and binary, and never crash on a
// malformed file. read_mesh keeps the tetrahedra of all physical groups and their hexahedra,
// prisms and pyramids split into tetrahedra (TetMesh::cell_origin; a collapsed cell, with a node
// twice, by its pieces with volume); read_tri_mesh the triangles and quadrilaterals split into
// triangles, which must lie in a plane z = const (z is dropped). Cells of order > 1 are read by
// their corners with MeshReadOptions::corner_nodes. Both ignore other elements, counting them,
// and keep the file's node and element tags. A file's dimension is 3 if it has 3D cells, else 2
// if it has 2D cells (mesh_dimension, read_any_mesh); a 3D mesh's boundary triangles and
// quadrilaterals are just ignored elements. Results are finalized. Errors (missing file,
// unreadable file, malformed data, no cells, triangles off a plane) throw std::runtime_error
// with a message starting "tetia: FILE: ", naming the line (ASCII) or byte offset (binary) and
// the node, element or field where there is one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "tetia/mesh.hpp"

namespace tetia {

/// A named field on a mesh: `components` values per node or per cell, in a row (1: scalar;
/// 3: a vector; 9: a tensor).
struct Field {
  std::string name;
  std::vector<double> values;
  int components = 1;
};

/// read_msh_field's default step: the field's only time step with values (an error naming the
/// steps if it has several).
inline constexpr std::int64_t kOnlyStep = std::numeric_limits<std::int64_t>::min();

struct MeshReadInfo {
  std::size_t ignored_elements = 0;  ///< elements of other types and dimensions, and repeated cells
  std::size_t straightened_cells = 0;  ///< higher-order cells read by their corners (corner_nodes)
  std::vector<std::string> node_fields, cell_fields;  ///< names of data found in the file (if any)
  /// The fields MeshReadOptions::fields asked for, in that order, as read_msh_field gives them
  /// (with their components), read in the same pass as the mesh.
  std::vector<Field> fields;
  /// Names of element-node data ($ElementNodeData) found in the file (if any).
  std::vector<std::string> cell_node_fields;
};

struct MeshReadOptions {
  /// Read cells of order > 1 by their corner nodes: straight cells, which approximate curved
  /// ones (their other nodes are ignored; MeshReadInfo counts them). Off: a file with only such
  /// cells is an error that says so.
  bool corner_nodes = false;
  /// Fields to read with the mesh (into MeshReadInfo::fields, which must then be given):
  /// element data if fields_on_cells, else node data (element-node data if
  /// fields_on_cell_nodes), at time step `step` (as read_msh_field).
  std::vector<std::string> fields;
  bool fields_on_cells = true;
  std::int64_t step = kOnlyStep;
  /// Read `fields` from element-node data ($ElementNodeData: discontinuous fields, one value
  /// per node of each element) instead, whatever fields_on_cells says. Each Field then holds,
  /// per simplex c of the returned mesh (mesh.cells, after the split of hexahedra, prisms,
  /// pyramids and quadrilaterals and the reorientation of inverted cells), per vertex k of it
  /// (mesh.cells[c][k]), `components` values: value j at index (c * nv + k) * components + j
  /// (nv = 4 for tetrahedra, 3 for triangles), the one its element (its file cell) has at that
  /// node, found by the node (not by its position, which splitting and reorienting change);
  /// cells of order > 1 read by their corners give their corners' values. Errors name the
  /// field and the element: an entry whose number of nodes is not its element type's, a cell
  /// without a value, a tag given twice.
  bool fields_on_cell_nodes = false;
};

TetMesh read_mesh(const std::filesystem::path& file, MeshReadInfo* info = nullptr, const MeshReadOptions& options = {});

/// A 2D mesh: the file's triangles (z dropped). Nodes by increasing tag, cells by increasing
/// element tag, as read_mesh.
TriMesh read_tri_mesh(const std::filesystem::path& file, MeshReadInfo* info = nullptr,
                      const MeshReadOptions& options = {});

/// 3 if the file has tetrahedra (of any order), else 2 if it has triangles, else an error.
int mesh_dimension(const std::filesystem::path& file);

/// Either mesh, by the file's dimension, read in one pass (what read_mesh or read_tri_mesh
/// would return).
using AnyMesh = std::variant<TetMesh, TriMesh>;
AnyMesh read_any_mesh(const std::filesystem::path& file, MeshReadInfo* info = nullptr,
                      const MeshReadOptions& options = {});

/// Reads a named field (node data or element data) from a .msh file, in the order of the nodes
/// or cells of the file's dimension (read_mesh's for a 3D file, read_tri_mesh's for a 2D one);
/// `on_cells` says which. `step`: the time step (the data block's first integer tag), or
/// kOnlyStep. With `components`, fields of any number of components are read (each entity's
/// values in a row; *components receives how many); without, only scalar ones. Throws if the
/// field or the step is absent, a node or cell has no value, or a tag has two. With
/// options.fields_on_cell_nodes, reads element-node data instead (whatever `on_cells` says), as
/// MeshReadOptions::fields_on_cell_nodes describes: per vertex of the simplices of read_mesh's
/// (or read_tri_mesh's) mesh, finalized.
std::vector<double> read_msh_field(const std::filesystem::path& file, const std::string& name, bool on_cells,
                                   std::int64_t step = kOnlyStep, int* components = nullptr,
                                   const MeshReadOptions& options = {});

/// What a field of a .msh file is: its name, kind, components, and the time steps with values.
struct FieldInfo {
  std::string name;
  bool on_cells = false;  ///< element data (false for node data and element-node data)
  int components = 1;
  std::vector<std::int64_t> steps;  ///< ascending
  bool on_cell_nodes = false;  ///< element-node data ($ElementNodeData)
};

/// The fields of a .msh file, in the order they first appear.
std::vector<FieldInfo> msh_fields(const std::filesystem::path& file);

/// An integer field for VTU output (ids: written as Int64).
struct IdField {
  std::string name;
  std::vector<std::int64_t> values;
};

enum class VtuFormat {
  binary,  ///< appended raw data, zlib-compressed (what ParaView and VTK write by default)
  ascii,   ///< every number as text (shortest round-trip form)
};

struct VtuOptions {
  VtuFormat format = VtuFormat::binary;
  std::vector<IdField> cell_ids, point_ids;  ///< extra Int64 arrays, after cell_id / node_id
  int threads = 0;  ///< for the compression (0: OpenMP's default); the file is the same for any
  /// For a mesh with split file cells (TetMesh::cell_origin): write its simplices (cell data
  /// per simplex, cell_id its file cell's tag) instead of the file's cells (cell data per file
  /// cell, tetia/file_cells.hpp).
  bool simplices = false;
};

/// ParaView's unstructured grid (VTK XML 1.0) with cell and point data (triangles at z = 0);
/// a mesh with split file cells is written as the file's cells (VTK hexahedra, wedges,
/// pyramids, quadrilaterals, tetrahedra, triangles), its cell data one value per file cell:
/// point data "node_id" and cell data "cell_id" (Int64: the mesh's tags, when it has them),
/// then the options' id fields, then the fields (Float64). Binary by default.
void write_vtu(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {}, const VtuOptions& options = {});
void write_vtu(const std::filesystem::path& file, const TriMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {}, const VtuOptions& options = {});

/// Gmsh .msh 4.1 ASCII, with node and element data (triangles at z = 0); a mesh with split file
/// cells is written as the file's cells (element data per file cell), with their tags.
/// `cell_node_data`: element-node data ($ElementNodeData), the layout of
/// MeshReadOptions::fields_on_cell_nodes (per simplex, per vertex, the components), which reads
/// it back bit for bit; it needs a mesh without split file cells (std::invalid_argument
/// otherwise: its simplices are not the file's cells).
void write_msh(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {}, const std::vector<Field>& cell_node_data = {});
void write_msh(const std::filesystem::path& file, const TriMesh& mesh, const std::vector<Field>& cell_data = {},
               const std::vector<Field>& point_data = {}, const std::vector<Field>& cell_node_data = {});

/// Meshes generated with the Gmsh library at element size h.
TetMesh generate_box(Vec3 lo, Vec3 hi, double h);
TetMesh generate_ball(Vec3 center, double radius, double h);
TetMesh generate_torus(Vec3 center, double major_radius, double minor_radius, double h);

/// 2D meshes generated with the Gmsh library at element size h, in the plane z = 0.
TriMesh generate_rectangle(Vec2 lo, Vec2 hi, double h);
TriMesh generate_disk(Vec2 center, double radius, double h);
/// A disk with a concentric hole: non-convex, not simply connected.
TriMesh generate_annulus(Vec2 center, double inner_radius, double outer_radius, double h);

}  // namespace tetia
