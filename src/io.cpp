// src/io.cpp -- reading .msh files with the strict reader (io/msh_reader.hpp, io/msh_mesh.hpp),
// writing VTU and .msh 4.1 (as text, here), and the generators, which call the Gmsh module
// (io/gmsh_module.hpp: the Gmsh library is loaded only when a mesh is generated).
//
// Node and cell order of a mesh read from a file: nodes by increasing node tag, cells (the
// 4-node tetrahedra, or the 3-node triangles of a 2D file) by increasing element tag. For files
// written by write_msh (tags 1..N and 1..M) that is the order of the file, and of the mesh that
// was written.
//
// Both dimensions share every function here (templates over the mesh type, src/mesh/mesh_dim.hpp);
// only the Gmsh and VTK element types and the plane check of 2D files differ.
#include "tetia/io.hpp"

#include <dlfcn.h>
#include <omp.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <limits>
#include <new>
#include <numeric>
#include <stdexcept>
#include <string>
#include <span>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

#include "mesh/mesh_dim.hpp"
#include "io/gmsh_module.hpp"
#include "io/gmsh_reader.hpp"
#include "io/mesh_assembly.hpp"
#include "io/msh_mesh.hpp"
#include "io/msh_reader.hpp"
#include "mesh/check_file_cells.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define TETIA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TETIA_ASAN 1
#endif
#endif
#ifdef TETIA_ASAN
// Sanitizer builds only. Gmsh 4.8 itself leaks (its surface mesher on every generation, its
// .msh 2.2 reader on error paths): not ours to fix, and LeakSanitizer would fail every program
// that meshes or reads a bad file. The suppression matches allocations made from inside
// libgmsh only, so leaks of our own code are still reported. (LeakSanitizer reads this hook
// from any linked object: no other object of a program may define it.)
extern "C" const char* __lsan_default_suppressions() { return "leak:libgmsh.so\n"; }
#endif

namespace tetia {

namespace {

namespace fs = std::filesystem;

using detail::GmshCell;
using detail::ViewData;
using detail::field_values;

[[noreturn]] void fail(const std::string& name, const std::string& what) { detail::io_fail(name, what); }

// ---------------------------------------------------------------------------------------------
// Text output

// Buffered text output to one file. Contract: errors (cannot open, short write) throw
// "tetia: FILE: ..."; `close` must be called for the file to be complete; a writer destroyed
// without close (an exception on the way) removes its partial file.
class TextOut {
 public:
  explicit TextOut(const fs::path& file) : path_(file), name_(file.string()) {
    f_ = std::fopen(file.c_str(), "wb");
    if (f_ == nullptr) fail(name_, std::string("cannot open for writing: ") + std::strerror(errno));
    buf_.reserve(kCapacity);
  }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  ~TextOut() {
    if (f_ == nullptr) return;
    std::fclose(f_);
    std::error_code ec;
    fs::remove(path_, ec);
  }

  TextOut& operator<<(std::string_view s) {
    if (buf_.size() + s.size() > kCapacity) flush();
    buf_.append(s);
    return *this;
  }
  TextOut& operator<<(char c) { return *this << std::string_view(&c, 1); }
  // Shortest text that reads back as the same double (to_chars): exact round trips.
  TextOut& operator<<(double v) { return put(v); }
  TextOut& operator<<(std::int64_t v) { return put(v); }
  TextOut& operator<<(std::size_t v) { return put(v); }
  TextOut& operator<<(int v) { return put(v); }

  void close() {
    flush();
    const bool bad = std::ferror(f_) != 0;
    const bool close_failed = std::fclose(f_) != 0;
    f_ = nullptr;
    if (bad || close_failed) {
      std::error_code ec;
      fs::remove(path_, ec);
      fail(name_, "write error");
    }
  }

 private:
  static constexpr std::size_t kCapacity = 1 << 16;

  template <class T>
  TextOut& put(T v) {
    char tmp[32];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    return *this << std::string_view(tmp, static_cast<std::size_t>(r.ptr - tmp));
  }
  void flush() {
    if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size()) {
      std::fclose(f_);
      f_ = nullptr;
      std::error_code ec;
      fs::remove(path_, ec);
      fail(name_, "write error");
    }
    buf_.clear();
  }

  fs::path path_;
  std::string name_;
  std::FILE* f_ = nullptr;
  std::string buf_;
};

// Field names must survive both formats: XML attributes (escaped) and .msh string tags, which
// are double-quoted with no escape. Sizes must match the mesh.
void check_fields(const std::string& name, const std::vector<Field>& fields, std::size_t expected) {
  std::unordered_set<std::string> seen;
  for (const auto& f : fields) {
    if (f.name.empty()) fail(name, "a field has an empty name");
    for (const char c : f.name)
      if (c == '"' || static_cast<unsigned char>(c) < 0x20)
        fail(name, "field " + f.name + ": name contains a quote or a control character");
    if (!seen.insert(f.name).second) fail(name, "field " + f.name + " given twice");
    if (f.components < 1 || f.components > 9)
      fail(name, "field " + f.name + " has " + std::to_string(f.components) + " components (1 to 9 are valid)");
    const std::size_t want = expected * static_cast<std::size_t>(f.components);
    if (f.values.size() != want)
      fail(name, "field " + f.name + " has " + std::to_string(f.values.size()) + " values, expected " +
                     std::to_string(want));
  }
}

template <class Mesh>
void check_mesh(const std::string& name, const Mesh& mesh) {
  if (mesh.cells.empty()) fail(name, std::string("no ") + detail::MeshDim<Mesh>::cells_word + " to write");
  const auto n = static_cast<std::int64_t>(mesh.nodes.size());
  for (std::size_t c = 0; c < mesh.cells.size(); ++c)
    for (const auto idx : mesh.cells[c])
      if (idx < 0 || idx >= n)
        fail(name, "cell " + std::to_string(c) + ": node index " + std::to_string(idx) + " out of range");
  // Split file cells (written as the file's cells): what finalize checks, for meshes built by hand.
  if (const std::string problem = detail::file_cells_problem(mesh); !problem.empty()) fail(name, problem);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

// Gmsh's $NodeData / $ElementData block for one field at time step 0, entity i at tag tags[i];
// with `nodes` > 0 $ElementNodeData: each entity (a cell) "tag nodes" and that many nodes'
// values (the field's values are then nodes * components per cell).
void write_msh_data(TextOut& out, const char* section, const Field& f, const std::vector<std::int64_t>& tags,
                    int nodes = 0) {
  const auto nc = static_cast<std::size_t>(f.components) * static_cast<std::size_t>(nodes > 0 ? nodes : 1);
  const std::size_t n = f.values.size() / nc;
  out << '$' << section << "\n1\n\"" << f.name << "\"\n1\n0\n3\n0\n" << f.components << '\n' << n << '\n';
  for (std::size_t i = 0; i < n; ++i) {
    out << tags[i];
    if (nodes > 0) out << ' ' << nodes;
    for (std::size_t k = 0; k < nc; ++k) out << ' ' << f.values[i * nc + k];
    out << '\n';
  }
  out << "$End" << section << '\n';
}


// The strict reader (io/msh_reader.hpp, io/msh_mesh.hpp) on the file's bytes.
struct ParsedFile {
  std::string bytes;
  detail::MshFile msh;
  ParsedFile(const fs::path& file, const std::string& name)
      : bytes(detail::read_file_bytes(file, name)), msh(detail::parse_msh(bytes, name)) {}
};

// Nodes by increasing tag (all of the file's nodes, used or not), first-order cells of every
// entity and physical group by increasing tag, each node set once; then finalize(mesh, FILE).
// Element-node data is read on the final simplices (after finalize reorients them), each vertex
// found among its element's nodes: `ex` is finalized here, its cells in the file's node order
// kept for that first (where no cell is split; split cells keep theirs in origin_nodes).
template <class Mesh>
void finalize_for_cell_nodes(detail::Extracted<Mesh>& ex, const std::string& name,
                             std::vector<std::array<std::int32_t, detail::MeshDim<Mesh>::nv>>& file_cells) {
  if (ex.mesh.cell_origin.empty()) file_cells = ex.mesh.cells;
  detail::finalize_extracted(ex, name);
}

template <class Mesh>
Mesh read(const ParsedFile& f, const std::string& name, MeshReadInfo* info, const MeshReadOptions& options) {
  if (!options.fields.empty() && info == nullptr)
    throw std::invalid_argument("tetia: " + name + ": MeshReadOptions::fields needs a MeshReadInfo to return them in");
  const std::vector<ViewData> views =
      info != nullptr ? detail::msh_views(f.msh, !options.fields.empty()) : std::vector<ViewData>{};
  detail::Extracted<Mesh> ex = detail::extract_msh<Mesh>(f.msh, name, options.corner_nodes);
  std::vector<Field> fields;
  const bool on_cell_nodes = options.fields_on_cell_nodes && !options.fields.empty();
  if (on_cell_nodes) {
    std::vector<std::array<std::int32_t, detail::MeshDim<Mesh>::nv>> file_cells;
    finalize_for_cell_nodes(ex, name, file_cells);
    for (const std::string& field : options.fields) {
      Field out{field, {}, 1};
      out.values = detail::cell_node_values(name, ex, file_cells, views, field, options.step, &out.components);
      fields.push_back(std::move(out));
    }
  } else {
    for (const std::string& field : options.fields) {
      Field out{field, {}, 1};
      out.values = field_values(name, ex, views, field, options.fields_on_cells, options.step, &out.components);
      fields.push_back(std::move(out));
    }
  }
  Mesh mesh = detail::finish_read(std::move(ex), name, views, info, on_cell_nodes);
  if (info != nullptr) info->fields = std::move(fields);
  return mesh;
}

template <class Mesh>
Mesh read(const std::filesystem::path& file, MeshReadInfo* info, const MeshReadOptions& options) {
  const std::string name = file.string();
  return read<Mesh>(ParsedFile(file, name), name, info, options);
}

// VTK XML UnstructuredGrid (format 1.0). Float64 points (z = 0 for triangles) and fields, Int32
// connectivity and offsets (the mesh's own), Int64 ids, UInt8 cell types 10 (VTK_TETRA) or 5 (VTK_TRIANGLE); point data
// "node_id" and cell data "cell_id", the mesh's tags (when it has them), before the caller's
// arrays. Binary: every array in the appended section, raw, compressed with zlib in
// blocks of 32 KiB with VTK's UInt64 header (number of blocks, block size, size of a partial
// last block or 0, compressed size of each block); ASCII: every number as the shortest text that
// reads back to the same double, a non-finite value as nan / inf / -inf. Everything is
// validated before the file is opened.
class VtuArrays {
 public:
  VtuArrays(VtuFormat format, int threads) : binary_(format == VtuFormat::binary), threads_(threads) {}

  // The DataArray element of one array, its data appended (binary) or inline (ASCII).
  template <class T>
  std::string array(const char* type, const std::string& name, int components, std::span<const T> v,
                    std::size_t per_line = 1) {
    std::string head = "<DataArray type=\"" + std::string(type) + "\"";
    if (!name.empty()) head += " Name=\"" + xml_escape(name) + "\"";
    if (components > 1) head += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    if (binary_) {
      head += " format=\"appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
      append_compressed(reinterpret_cast<const unsigned char*>(v.data()), v.size() * sizeof(T));
      return head;
    }
    std::string out = head + " format=\"ascii\">\n";
    char tmp[32];
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto r = std::to_chars(tmp, tmp + sizeof tmp, static_cast<std::conditional_t<std::is_same_v<T, std::uint8_t>, int, T>>(v[i]));
      out.append(tmp, static_cast<std::size_t>(r.ptr - tmp));
      out += (i + 1) % per_line == 0 || i + 1 == v.size() ? '\n' : ' ';
    }
    return out + "</DataArray>\n";
  }
  const std::string& appended() const { return appended_; }

 private:
  static constexpr std::size_t kBlock = 1 << 15;

  // The blocks are independent: compressed in parallel (`threads_`, 0: OpenMP's default), then
  // concatenated in order, so the file is the same for any number of threads.
  void append_compressed(const unsigned char* data, std::size_t bytes) {
    const std::size_t blocks = (bytes + kBlock - 1) / kBlock;
    std::vector<std::uint64_t> header(3 + blocks);
    header[0] = blocks;
    header[1] = kBlock;
    header[2] = bytes % kBlock;
    std::vector<std::vector<unsigned char>> out(blocks);
    bool failed = false, out_of_memory = false;
    const auto nblocks = static_cast<std::int64_t>(blocks);
    const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();
    // A block's buffer that cannot be allocated is noted, not thrown: an exception must not
    // leave the OpenMP region (it would terminate the process).
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads) reduction(|| : failed, out_of_memory)
    for (std::int64_t k = 0; k < nblocks; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const std::size_t n = std::min(kBlock, bytes - kk * kBlock);
      try {
        out[kk].resize(compressBound(static_cast<uLong>(n)));
      } catch (const std::bad_alloc&) {
        out_of_memory = true;
        continue;
      }
      uLongf got = static_cast<uLongf>(out[kk].size());
      // Level 1: about as small as the default on these arrays, several times faster.
      failed = failed || compress2(out[kk].data(), &got, data + kk * kBlock, static_cast<uLong>(n), 1) != Z_OK;
      out[kk].resize(got);
    }
    if (out_of_memory) throw std::bad_alloc();
    if (failed) throw std::runtime_error("tetia: zlib compression failed");
    for (std::size_t k = 0; k < blocks; ++k) header[3 + k] = out[k].size();
    appended_.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
    for (const auto& b : out) appended_.append(reinterpret_cast<const char*>(b.data()), b.size());
  }

  bool binary_;
  int threads_;
  std::string appended_;
};

std::vector<std::int64_t> ids_or_positions(const std::vector<std::int64_t>& tags, std::size_t n) {
  if (!tags.empty()) return tags;
  std::vector<std::int64_t> ids(n);
  std::iota(ids.begin(), ids.end(), std::int64_t{1});
  return ids;
}

template <class Mesh>
void vtu(const std::filesystem::path& file, const Mesh& mesh, const std::vector<Field>& cell_data,
         const std::vector<Field>& point_data, const VtuOptions& options) {
  using Dm = detail::MeshDim<Mesh>;
  const std::string name = file.string();
  check_mesh(name, mesh);
  // A mesh with split file cells is written as the file's cells (hexahedra, prisms, pyramids,
  // quadrilaterals, simplices), unless the simplices are asked for.
  const bool file_cells = !mesh.cell_origin.empty() && !options.simplices;
  const std::size_t num_cells = file_cells ? mesh.num_file_cells() : mesh.cells.size();
  check_fields(name, cell_data, num_cells);
  check_fields(name, point_data, mesh.nodes.size());
  for (const auto& ids : {std::pair{&options.cell_ids, num_cells}, std::pair{&options.point_ids, mesh.nodes.size()}})
    for (const IdField& f : *ids.first)
      if (f.values.size() != ids.second)
        fail(name, "id field " + f.name + " has " + std::to_string(f.values.size()) + " values, expected " +
                       std::to_string(ids.second));
  if (!mesh.node_tags.empty() && mesh.node_tags.size() != mesh.nodes.size()) fail(name, "node tags do not match the nodes");
  if (!mesh.cell_tags.empty() && mesh.cell_tags.size() != mesh.cells.size()) fail(name, "cell tags do not match the cells");
  VtuArrays arrays(options.format, options.threads);
  std::string xml;
  const auto data_section = [&](const char* tag, const char* id_name, const std::vector<std::int64_t>& ids,
                                const std::vector<IdField>& more_ids, const std::vector<Field>& fields) {
    xml += "      <" + std::string(tag) + (fields.empty() ? "" : " Scalars=\"" + xml_escape(fields.front().name) + "\"") + ">\n";
    if (!ids.empty()) xml += "        " + arrays.array("Int64", id_name, 1, std::span(ids));
    for (const auto& f : more_ids) xml += "        " + arrays.array("Int64", f.name, 1, std::span(f.values));
    for (const auto& f : fields)
      xml += "        " + arrays.array("Float64", f.name, f.components, std::span(f.values),
                                       static_cast<std::size_t>(f.components));
    xml += "      </" + std::string(tag) + ">\n";
  };
  // The file's tags, if the mesh has them (positions would tell nothing: they are the ids VTK
  // numbers by anyway).
  data_section("PointData", "node_id", mesh.node_tags, options.point_ids, point_data);
  if (mesh.cell_origin.empty()) {
    data_section("CellData", "cell_id", mesh.cell_tags, options.cell_ids, cell_data);
  } else if (file_cells) {
    data_section("CellData", "cell_id", mesh.origin_tags, options.cell_ids, cell_data);
  } else {  // the simplices of split file cells: each carries its file cell's tag
    std::vector<std::int64_t> origin(mesh.cells.size());
    for (std::size_t c = 0; c < origin.size(); ++c)
      origin[c] = mesh.origin_tags[static_cast<std::size_t>(mesh.cell_origin[c])];
    data_section("CellData", "cell_id", origin, options.cell_ids, cell_data);
  }
  {
    // 3D points are written straight from the mesh (three doubles each); 2D ones get z = 0.
    std::vector<double> xyz;
    std::span<const double> points;
    if constexpr (Dm::d == 3) {
      static_assert(sizeof(Vec3) == 3 * sizeof(double));
      points = std::span<const double>(&mesh.nodes[0].x, 3 * mesh.nodes.size());
    } else {
      xyz.reserve(3 * mesh.nodes.size());
      for (const auto& p : mesh.nodes) xyz.insert(xyz.end(), {p.x, p.y, 0.0});
      points = xyz;
    }
    xml += "      <Points>\n        " + arrays.array("Float64", "", 3, points, 3) + "      </Points>\n";
  }
  if (file_cells) {
    // VTK's node orders are Gmsh's except the wedge's, whose first triangle VTK lists the
    // other way round (its normal pointing away from the second).
    std::vector<std::int32_t> connectivity;
    connectivity.reserve(mesh.origin_nodes.size());
    std::vector<std::int32_t> offsets(num_cells);
    std::vector<std::uint8_t> types(num_cells);
    std::size_t at = 0;
    for (std::size_t f = 0; f < num_cells; ++f) {
      const int type = mesh.origin_types[f];
      const auto n = static_cast<std::size_t>(file_cell_nodes(type));
      const std::int32_t* v = &mesh.origin_nodes[at];
      if (type == 6) {
        connectivity.insert(connectivity.end(), {v[0], v[2], v[1], v[3], v[5], v[4]});
      } else {
        connectivity.insert(connectivity.end(), v, v + n);
      }
      at += n;
      offsets[f] = static_cast<std::int32_t>(at);
      // Gmsh types 2-7 as VTK's: triangle 5, quadrilateral 9, tetrahedron 10, hexahedron 12,
      // wedge 13, pyramid 14.
      static constexpr std::uint8_t kVtkType[8] = {0, 0, 5, 9, 10, 12, 13, 14};
      types[f] = kVtkType[type];
    }
    // One statement each: the operands of + are evaluated in no specified order, and each call
    // appends its data, so one expression gave another file layout with another compiler.
    xml += "      <Cells>\n        " + arrays.array("Int32", "connectivity", 1, std::span<const std::int32_t>(connectivity));
    xml += "        " + arrays.array("Int32", "offsets", 1, std::span<const std::int32_t>(offsets));
    xml += "        " + arrays.array("UInt8", "types", 1, std::span<const std::uint8_t>(types)) + "      </Cells>\n";
  } else {
    // Int32 connectivity and offsets, as the mesh holds them (VTK takes either width).
    static_assert(sizeof(mesh.cells[0]) == Dm::nv * sizeof(std::int32_t));
    const std::span<const std::int32_t> connectivity(&mesh.cells[0][0], Dm::nv * mesh.cells.size());
    std::vector<std::int32_t> offsets(mesh.cells.size());
    for (std::size_t c = 0; c < mesh.cells.size(); ++c) offsets[c] = static_cast<std::int32_t>(Dm::nv * (c + 1));
    const std::vector<std::uint8_t> types(mesh.cells.size(), Dm::d == 3 ? 10 : 5);  // VTK_TETRA, VTK_TRIANGLE
    xml += "      <Cells>\n        " + arrays.array("Int32", "connectivity", 1, connectivity, Dm::nv);  // one by one, as above
    xml += "        " + arrays.array("Int32", "offsets", 1, std::span<const std::int32_t>(offsets));
    xml += "        " + arrays.array("UInt8", "types", 1, std::span<const std::uint8_t>(types)) + "      </Cells>\n";
  }
  const bool binary = options.format == VtuFormat::binary;
  TextOut out(file);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\""
      << (binary ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << mesh.nodes.size() << "\" NumberOfCells=\"" << num_cells << "\">\n"
      << xml << "    </Piece>\n  </UnstructuredGrid>\n";
  if (binary) out << "  <AppendedData encoding=\"raw\">\n   _" << std::string_view(arrays.appended()) << "\n  </AppendedData>\n";
  out << "</VTKFile>\n";
  out.close();
}

// .msh 4.1 ASCII, written as text (exact numbers, unlike Gmsh's 16 digits): one discrete
// volume (surface, for triangles: z = 0) holding every node and cell, tagged with the mesh's
// tags (1, 2, ... by position without), so that the reader gives back the same mesh; a mesh
// with split file cells as the file's cells, one block per element type; one $NodeData /
// $ElementData / $ElementNodeData per field (time step 0).
template <class Mesh>
void msh(const std::filesystem::path& file, const Mesh& mesh, const std::vector<Field>& cell_data,
         const std::vector<Field>& point_data, const std::vector<Field>& cell_node_data) {
  using Dm = detail::MeshDim<Mesh>;
  const std::string name = file.string();
  check_mesh(name, mesh);
  // A mesh with split file cells is written as the file's cells, one element block per type.
  const bool file_cells = !mesh.cell_origin.empty();
  // Element-node data is per simplex vertex: written on the file's cells, a hexahedron's nodes
  // could get several values from its simplices, and a reader would split it anew.
  if (file_cells && !cell_node_data.empty())
    throw std::invalid_argument("tetia: " + name + ": element-node data needs a simplicial mesh (this one has " +
                                std::to_string(mesh.num_file_cells()) + " file cells split into " +
                                std::to_string(mesh.cells.size()) + " " + Dm::cells_word + ")");
  check_fields(name, cell_data, file_cells ? mesh.num_file_cells() : mesh.cells.size());
  check_fields(name, point_data, mesh.nodes.size());
  check_fields(name, cell_node_data, mesh.cells.size() * Dm::nv);
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int d = 0; d < Dm::d; ++d) lo[d] = hi[d] = Dm::coord(mesh.nodes.front(), d);
  for (const auto& p : mesh.nodes)
    for (int d = 0; d < Dm::d; ++d) {
      lo[d] = std::min(lo[d], Dm::coord(p, d));
      hi[d] = std::max(hi[d], Dm::coord(p, d));
    }
  const std::size_t n = mesh.nodes.size(), m = file_cells ? mesh.num_file_cells() : mesh.cells.size();
  if (!mesh.node_tags.empty() && mesh.node_tags.size() != n) fail(name, "node tags do not match the nodes");
  if (!mesh.cell_tags.empty() && mesh.cell_tags.size() != m) fail(name, "cell tags do not match the cells");
  const std::vector<std::int64_t> node_tags = ids_or_positions(mesh.node_tags, n);
  const std::vector<std::int64_t> cell_tags = ids_or_positions(file_cells ? mesh.origin_tags : mesh.cell_tags, m);
  const auto [node_lo, node_hi] = std::minmax_element(node_tags.begin(), node_tags.end());
  const auto [cell_lo, cell_hi] = std::minmax_element(cell_tags.begin(), cell_tags.end());
  TextOut out(file);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  out << "$Entities\n" << (Dm::d == 3 ? "0 0 0 1" : "0 0 1 0") << "\n1 " << lo[0] << ' ' << lo[1] << ' ' << lo[2]
      << ' ' << hi[0] << ' ' << hi[1] << ' ' << hi[2] << " 0 0\n$EndEntities\n";
  out << "$Nodes\n1 " << n << ' ' << *node_lo << ' ' << *node_hi << '\n' << Dm::d << " 1 0 " << n << '\n';
  for (const std::int64_t tag : node_tags) out << tag << '\n';
  for (const auto& p : mesh.nodes) {
    if constexpr (Dm::d == 3) {
      out << p.x << ' ' << p.y << ' ' << p.z << '\n';
    } else {
      out << p.x << ' ' << p.y << " 0\n";
    }
  }
  if (!file_cells) {
    out << "$EndNodes\n$Elements\n1 " << m << ' ' << *cell_lo << ' ' << *cell_hi << '\n'
        << Dm::d << " 1 " << GmshCell<Mesh>::type << ' ' << m << '\n';
    for (std::size_t c = 0; c < m; ++c) {
      const auto& v = mesh.cells[c];
      out << cell_tags[c];
      for (const auto idx : v) out << ' ' << node_tags[static_cast<std::size_t>(idx)];
      out << '\n';
    }
  } else {
    // One block per element type present, in type order; the cells of a type in file order.
    std::size_t per_type[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (const std::uint8_t t : mesh.origin_types) ++per_type[t];
    std::vector<std::size_t> first_node(m + 1, 0);
    for (std::size_t f = 0; f < m; ++f)
      first_node[f + 1] = first_node[f] + static_cast<std::size_t>(file_cell_nodes(mesh.origin_types[f]));
    int blocks = 0;
    for (const std::size_t c : per_type) blocks += c > 0;
    out << "$EndNodes\n$Elements\n" << blocks << ' ' << m << ' ' << *cell_lo << ' ' << *cell_hi << '\n';
    for (int type = 2; type <= 7; ++type) {
      if (per_type[type] == 0) continue;
      out << Dm::d << " 1 " << type << ' ' << per_type[type] << '\n';
      for (std::size_t f = 0; f < m; ++f) {
        if (mesh.origin_types[f] != type) continue;
        out << cell_tags[f];
        for (std::size_t k = first_node[f]; k < first_node[f + 1]; ++k)
          out << ' ' << node_tags[static_cast<std::size_t>(mesh.origin_nodes[k])];
        out << '\n';
      }
    }
  }
  out << "$EndElements\n";
  for (const auto& f : point_data) write_msh_data(out, "NodeData", f, node_tags);
  for (const auto& f : cell_data) write_msh_data(out, "ElementData", f, cell_tags);
  for (const auto& f : cell_node_data) write_msh_data(out, "ElementNodeData", f, cell_tags, static_cast<int>(Dm::nv));
  out.close();
}

}  // namespace

// ---------------------------------------------------------------------------------------------

TetMesh read_mesh(const std::filesystem::path& file, MeshReadInfo* info, const MeshReadOptions& options) {
  return read<TetMesh>(file, info, options);
}

TriMesh read_tri_mesh(const std::filesystem::path& file, MeshReadInfo* info, const MeshReadOptions& options) {
  return read<TriMesh>(file, info, options);
}

AnyMesh read_any_mesh(const std::filesystem::path& file, MeshReadInfo* info, const MeshReadOptions& options) {
  const std::string name = file.string();
  const ParsedFile f(file, name);
  const int dim = detail::msh_dimension(f.msh);
  if (dim == 3) return read<TetMesh>(f, name, info, options);
  if (dim == 2) return read<TriMesh>(f, name, info, options);
  fail(name, "no tetrahedra or triangles (" + std::to_string(f.msh.other_elements) + " other elements ignored)");
}

int mesh_dimension(const std::filesystem::path& file) {
  const std::string name = file.string();
  const int dim = detail::msh_dimension(ParsedFile(file, name).msh);
  if (dim == 0) fail(name, "no tetrahedra or triangles");
  return dim;
}

// The cells the field refers to are those of the file's dimension (tetrahedra if there are
// any, else triangles), in the order read_mesh / read_tri_mesh give them.
std::vector<double> read_msh_field(const std::filesystem::path& file, const std::string& field_name, bool on_cells,
                                   std::int64_t step, int* components, const MeshReadOptions& options) {
  const std::string name = file.string();
  const ParsedFile f(file, name);
  const std::vector<ViewData> views = detail::msh_views(f.msh, true);
  if (options.fields_on_cell_nodes) {
    const auto per_vertex = [&]<class Mesh>(detail::Extracted<Mesh> ex) {
      std::vector<std::array<std::int32_t, detail::MeshDim<Mesh>::nv>> file_cells;
      finalize_for_cell_nodes(ex, name, file_cells);
      return detail::cell_node_values(name, ex, file_cells, views, field_name, step, components);
    };
    if (detail::msh_dimension(f.msh) == 2)
      return per_vertex(detail::extract_msh<TriMesh>(f.msh, name, options.corner_nodes));
    return per_vertex(detail::extract_msh<TetMesh>(f.msh, name, options.corner_nodes));
  }
  if (detail::msh_dimension(f.msh) == 2)
    return field_values(name, detail::extract_msh<TriMesh>(f.msh, name, options.corner_nodes), views, field_name,
                        on_cells, step, components);
  return field_values(name, detail::extract_msh<TetMesh>(f.msh, name, options.corner_nodes), views, field_name,
                      on_cells, step, components);
}

std::vector<FieldInfo> msh_fields(const std::filesystem::path& file) {
  const std::string name = file.string();
  const ParsedFile f(file, name);
  std::vector<FieldInfo> out;
  for (const detail::MshData& d : f.msh.data) {
    if (d.tags.empty()) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const FieldInfo& x) {
      return x.name == d.name && x.on_cells == d.on_elements && x.on_cell_nodes == d.on_element_nodes;
    });
    if (it == out.end())
      it = out.insert(out.end(), FieldInfo{d.name, d.on_elements, d.components, {}, d.on_element_nodes});
    if (std::find(it->steps.begin(), it->steps.end(), d.step) == it->steps.end()) it->steps.push_back(d.step);
  }
  for (auto& fi : out) std::sort(fi.steps.begin(), fi.steps.end());
  return out;
}

void write_vtu(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data,
               const std::vector<Field>& point_data, const VtuOptions& options) {
  vtu(file, mesh, cell_data, point_data, options);
}
void write_vtu(const std::filesystem::path& file, const TriMesh& mesh, const std::vector<Field>& cell_data,
               const std::vector<Field>& point_data, const VtuOptions& options) {
  vtu(file, mesh, cell_data, point_data, options);
}

void write_msh(const std::filesystem::path& file, const TetMesh& mesh, const std::vector<Field>& cell_data,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_node_data) {
  msh(file, mesh, cell_data, point_data, cell_node_data);
}
void write_msh(const std::filesystem::path& file, const TriMesh& mesh, const std::vector<Field>& cell_data,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_node_data) {
  msh(file, mesh, cell_data, point_data, cell_node_data);
}

namespace detail {

const GmshModule& gmsh_module() {
  static const GmshModule* const module = [] {
    std::vector<std::string> paths;
    if (const char* env = std::getenv("TETIA_GMSH_MODULE"); env != nullptr && *env != '\0') paths.emplace_back(env);
#ifdef TETIA_GMSH_MODULE_RELATIVE
    // Next to the shared library itself (the object holding this variable), wherever it is
    // installed: <its directory>/tetia/libtetia_gmsh.so.
    static const char anchor = 0;
    if (Dl_info info{}; ::dladdr(&anchor, &info) != 0 && info.dli_fname != nullptr && *info.dli_fname != '\0')
      paths.push_back((std::filesystem::path(info.dli_fname).parent_path() / TETIA_GMSH_MODULE_RELATIVE).string());
#endif
#ifdef TETIA_GMSH_MODULE_BUILD
    paths.emplace_back(TETIA_GMSH_MODULE_BUILD);
#endif
#ifdef TETIA_GMSH_MODULE_INSTALL
    paths.emplace_back(TETIA_GMSH_MODULE_INSTALL);
#endif
    std::string tried;
    for (const std::string& path : paths) {
      void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle == nullptr) {
        const char* why = ::dlerror();
        tried += (tried.empty() ? "" : "; ") + path + ": " + (why != nullptr ? why : "cannot load");
        continue;
      }
      using Entry = const GmshModule* (*)();
      const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "tetia_gmsh_module"));
      const GmshModule* m = entry != nullptr ? entry() : nullptr;
      if (m != nullptr && m->version == kGmshModuleVersion) return m;  // kept loaded for the process
      tried += (tried.empty() ? "" : "; ") + path + ": not a tetia Gmsh module of this version";
      ::dlclose(handle);
    }
    throw std::runtime_error("tetia: generating meshes needs the Gmsh module libtetia_gmsh.so (" +
                             (tried.empty() ? std::string("no path known") : tried) +
                             "); set TETIA_GMSH_MODULE to its path");
  }();
  return *module;
}

AnyMesh gmsh_read_any_mesh(const std::filesystem::path& file, MeshReadInfo* info) {
  return gmsh_module().read_any_mesh(file, info);
}

std::vector<double> gmsh_read_msh_field(const std::filesystem::path& file, const std::string& name, bool on_cells) {
  return gmsh_module().read_msh_field(file, name, on_cells);
}

}  // namespace detail

// The generators (Gmsh's OpenCASCADE shapes; see gmsh_module.cpp for how they mesh), through
// the module.
TetMesh generate_box(Vec3 lo, Vec3 hi, double h) { return detail::gmsh_module().generate_box(lo, hi, h); }
TetMesh generate_ball(Vec3 center, double radius, double h) {
  return detail::gmsh_module().generate_ball(center, radius, h);
}
TetMesh generate_torus(Vec3 center, double major_radius, double minor_radius, double h) {
  return detail::gmsh_module().generate_torus(center, major_radius, minor_radius, h);
}
TriMesh generate_rectangle(Vec2 lo, Vec2 hi, double h) { return detail::gmsh_module().generate_rectangle(lo, hi, h); }
TriMesh generate_disk(Vec2 center, double radius, double h) {
  return detail::gmsh_module().generate_disk(center, radius, h);
}
TriMesh generate_annulus(Vec2 center, double inner_radius, double outer_radius, double h) {
  return detail::gmsh_module().generate_annulus(center, inner_radius, outer_radius, h);
}

}  // namespace tetia
