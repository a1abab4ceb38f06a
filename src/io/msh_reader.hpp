// src/io/msh_reader.hpp -- a strict reader of Gmsh's .msh files, 2.x and 4.1, ASCII and binary:
// from the bytes of a file to what tetia keeps of it (internal to the library).
//
// Why not Gmsh's own reader: Gmsh 4.8's reader crashes the process on corrupted files (SIGSEGV
// in GModel::_readMSH2, assertions that abort), spends minutes and gigabytes on a count it
// trusts, and accepts broken files as a different mesh (a later duplicate node wins; a count
// smaller than the data drops the rest). None of that can be guarded against in-process. Gmsh
// stays for generating meshes (io.cpp); tests/test_msh_reader.cpp checks that this reader and
// Gmsh's agree on every variant Gmsh writes.
//
// Contract of parse_msh(bytes, name):
//  - returns the nodes (tags, coordinates), the first-order tetrahedra and triangles (tags,
//    node tags), counts of every other element type, and the $NodeData / $ElementData /
//    $ElementNodeData blocks, all in file order and with the byte offset each came from; or
//    throws std::runtime_error "tetia: NAME: line L: ..." (ASCII files) or "tetia: NAME: byte
//    offset B: ..." (binary files), naming the node, element or field where there is one;
//  - errors: a missing or malformed header or section, a truncated file, a count that
//    disagrees with the data that follows, a number that does not parse or is out of range,
//    a non-finite coordinate or field value, a tag that is 0 or negative, an $ElementNodeData
//    entry of no nodes or whose values are not its nodes times the components, an element
//    type whose size is unknown in a binary file, a big-endian binary file, a data size other
//    than 8. (A file may hold several meshes one after another, as Gmsh writes them when it
//    appends views: in a 2.x file the last copy is the mesh, as in Gmsh's 2.2 reader; in a 4.1
//    file all are read, as Gmsh merges them.) (Duplicate tags and unknown node references are
//    found where the mesh is assembled, msh_mesh.hpp, which knows what is kept.)
//  - time linear in the size of the file, and memory at most a small multiple of it: a count
//    read from the file is checked against the bytes left before anything is reserved for it.
//  - element types of known size that are not kept (points, lines, quadrilaterals, hexahedra,
//    prisms, pyramids, higher orders) are counted, not stored; in ASCII files an element of an
//    unknown type is counted too (its line says how long it is).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tetia::detail {

/// The elements of one kept type, in file order.
struct MshCells {
  std::vector<std::uint64_t> tags;
  std::vector<std::uint64_t> nodes;  ///< node tags, the type's node count per element
  std::vector<std::size_t> where;    ///< byte offset of each element in the file
  /// The higher_* lists only: each element's own Gmsh type (of order > 1), whose node count
  /// (msh_nodes_per_element) an $ElementNodeData entry must give; empty for first-order lists.
  std::vector<std::uint8_t> types;
};

/// One $NodeData, $ElementData or $ElementNodeData block (one time step of one field).
struct MshData {
  std::string name;
  bool on_elements = false;       ///< $ElementData
  bool on_element_nodes = false;  ///< $ElementNodeData (neither: $NodeData)
  std::int64_t step = 0;          ///< the time step (the first integer tag)
  int components = 1;
  std::vector<std::uint64_t> tags;
  /// `components` per tag; $ElementNodeData: nodes[i] * components for tag i, node after node
  /// (the element's nodes in its own order), each node's components in a row.
  std::vector<double> values;
  /// $ElementNodeData: each entry's number of nodes, as the file gives it (checked against the
  /// element's type where the mesh is assembled); empty for the other kinds.
  std::vector<std::uint32_t> nodes;
  std::vector<std::size_t> where;
};

struct MshFile {
  std::string_view bytes;  ///< the file's content (parse_msh's argument; must outlive this)
  bool binary = false;  ///< of the last $MeshFormat (a file may hold several meshes)
  int major = 0;        ///< 2 or 4, the same
  /// Where each $MeshFormat's data begins, and whether it is binary (for location()).
  std::vector<std::pair<std::size_t, bool>> formats;

  std::vector<std::uint64_t> node_tags;
  std::vector<double> xyz;  ///< three per node
  std::vector<std::size_t> node_where;

  MshCells tetrahedra;  ///< Gmsh type 4, 4 nodes
  MshCells triangles;   ///< Gmsh type 2, 3 nodes
  MshCells hexahedra;   ///< Gmsh type 5, 8 nodes (split into tetrahedra by extract_msh)
  MshCells prisms;      ///< Gmsh type 6, 6 nodes
  MshCells pyramids;    ///< Gmsh type 7, 5 nodes
  MshCells quadrangles; ///< Gmsh type 3, 4 nodes (split into triangles)
  std::size_t other_elements = 0;          ///< elements of every other type
  std::size_t higher_order_3d = 0;  ///< among them: tetrahedra, hexahedra, prisms, pyramids of order > 1
  std::size_t higher_order_2d = 0;  ///< and triangles, quadrilaterals of order > 1
  /// Those cells by their corner nodes only (Gmsh lists the corners first, in the first-order
  /// cell's order), for reading them as straight cells on request (MeshReadOptions::corner_nodes).
  MshCells higher_tetrahedra, higher_triangles, higher_hexahedra, higher_prisms, higher_pyramids, higher_quadrangles;

  std::vector<MshData> data;

  /// "line L" (ASCII) or "byte offset B" (binary) of a byte offset into `bytes`.
  std::string location(std::size_t where) const;
};

/// See the file comment. `name` (the file's name) starts every error message.
MshFile parse_msh(std::string_view bytes, const std::string& name);

/// The whole file, or "tetia: NAME: cannot open: ..." (missing, a directory, unreadable).
std::string read_file_bytes(const std::filesystem::path& file, const std::string& name);

/// The number of nodes of a Gmsh element type, 0 if tetia does not know the type.
int msh_nodes_per_element(int type);

}  // namespace tetia::detail
