// test_msh_reader.cpp -- tetia's strict .msh reader (src/io/msh_reader.hpp: bytes -> MshFile;
// src/io/msh_mesh.hpp: MshFile -> mesh and fields), behind read_any_mesh, read_mesh,
// read_tri_mesh, mesh_dimension and read_msh_field (tetia/io.hpp).
//
// Why: the strict reader replaced Gmsh's own (kept as tetia::detail::gmsh_read_any_mesh and
// gmsh_read_msh_field, src/io/gmsh_reader.hpp, the reference here), which crashes on corrupted
// files. So it must (1) read every file Gmsh writes as Gmsh does, and (2) refuse everything else
// with a message that says where, and (3) never crash or run away, whatever the bytes.
//
//  1. Agreement with Gmsh: models built and meshed by Gmsh (three volumes sharing faces, two
//     disjoint boxes, two rectangles in z = 0; physical groups on cells and facets, one entity
//     in two groups, one in none; node and element data, scalar and vector, two time steps,
//     partial, on facets only) written by Gmsh in every variant (.msh 2.2 and 4.1, ASCII and
//     binary, Mesh.SaveAll 0 and 1, Mesh.SaveParametric), alone and with the views appended
//     (gmsh::view::write, which writes the mesh again before each view). Both readers must give
//     the same nodes (exact doubles: ASCII files carry 16 digits, both parse the same text),
//     cells, MeshReadInfo, and the same values or the same error for each field query.
//  2. Literal files (2.2 and 4.1 ASCII texts, and binary files built here so that the offset of
//     each record is known): each malformed one must throw std::runtime_error "tetia: FILE: "
//     naming the line (ASCII) or byte offset (binary) and the node or element at fault; the
//     accepted oddities (a node given twice identically, a mesh given twice, CRLF, unknown and
//     unused element types) read as Gmsh reads them; every prefix of a valid file reads only if
//     it is a complete file and otherwise throws std::runtime_error; field errors name the
//     fields there are. Reading takes time linear in the size of the file, also for adversarial
//     tags and many field names (timed against a file of the same size).
//  3. Mutants of small files written by Gmsh (bytes overwritten, truncations, ranges
//     duplicated, tokens and binary words replaced by edge values; fixed seeds): each must read
//     or throw std::runtime_error naming the file, never crash or throw anything else.
//
// Where Gmsh 4.8 is no reference, the tests say so: it writes .msh 2.2 node data with tag -1
// when some cells are in no physical group (and cannot read that back: both readers must
// refuse it); it keeps only the last copy of a repeated .msh 2.2 mesh, but holds a repeated 4.1
// mesh more than once (two of the three copies of a mesh written with two views), so its count
// of ignored elements is no reference for files with views; it makes a second view for a field
// repeated under the same name (tetia lists a field once per name). And tetia's Gmsh path takes
// no time step (it reads a field's first step with values): fields of several time steps are
// compared at step 0.
//
// Gmsh is one process-wide state; these tests call it directly on the test's thread (as
// test_io.cpp does), never while a tetia I/O call runs, and clear it before and after. Files
// are small (at most a few hundred cells), so the suite takes seconds in a Release build.
#include <gtest/gtest.h>
#include <gmsh.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeinfo>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "support/error_of.hpp"
#include "support/gmsh_write.hpp"
#include "support/temp_dir.hpp"
#include "../src/io/gmsh_reader.hpp"
#include "../src/io/msh_reader.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace {

namespace fs = std::filesystem;
using tetia::AnyMesh;
using tetia::MeshReadInfo;
using tetia::TetMesh;
using tetia::TriMesh;

// ---------------------------------------------------------------------------------------------
// Helpers

std::string read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Removes the file first: on ext4, truncating a file and writing it again forces its blocks
// out on close (auto_da_alloc), milliseconds each time for the thousands of files written here.
void write_bytes(const fs::path& p, std::string_view s) {
  std::error_code ec;
  fs::remove(p, ec);
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(s.data(), static_cast<std::streamsize>(s.size()));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// `text` with its first occurrence of `from` replaced by `to`; fails the test if there is none.
std::string replaced(std::string text, std::string_view from, std::string_view to) {
  const auto at = text.find(from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "\"" << from << "\" not in the test file";
    return text;
  }
  return text.replace(at, from.size(), to);
}

std::string with_crlf(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '\n') out += '\r';
    out += c;
  }
  return out;
}

using tetia::testsupport::error_of;
using tetia::testsupport::GmshScope;

// What a field read gives: the values, or the error's message.
struct Outcome {
  std::vector<double> values;
  std::string error;
};
template <class F>
Outcome outcome_of(F&& f) {
  Outcome o;
  try {
    o.values = f();
  } catch (const std::runtime_error& e) {
    o.error = e.what();
  }
  return o;
}

// Meshes that keep the file's tags (TetMesh::node_tags, cell_tags).
template <class Mesh>
concept KeepsTags = requires(const Mesh& m) {
  m.node_tags;
  m.cell_tags;
};

template <class Mesh>
void expect_same_mesh(const Mesh& ours, const Mesh& gmsh) {
  EXPECT_EQ(ours.nodes, gmsh.nodes);  // exact doubles
  EXPECT_EQ(ours.cells, gmsh.cells);
  EXPECT_EQ(ours.neighbors, gmsh.neighbors);
  EXPECT_EQ(ours.reoriented_cells, gmsh.reoriented_cells);
  EXPECT_EQ(ours.flat_cells, gmsh.flat_cells);
  if constexpr (KeepsTags<Mesh>) {
    EXPECT_EQ(ours.node_tags, gmsh.node_tags);
    EXPECT_EQ(ours.cell_tags, gmsh.cell_tags);
  }
}

std::size_t num_cells(const AnyMesh& m) {
  return std::visit([](const auto& mesh) { return mesh.num_cells(); }, m);
}
std::size_t num_nodes(const AnyMesh& m) {
  return std::visit([](const auto& mesh) { return mesh.num_nodes(); }, m);
}

// A field query: read_msh_field(file, name, on_cells, step). Gmsh's reader (gmsh_read_msh_field)
// takes no step: it reads a field's first time step with values, so a query of a field with
// several steps names step 0 for ours.
struct Query {
  std::string name;
  bool on_cells;
  std::int64_t step;
  Query(std::string n, bool c, std::int64_t s = tetia::kOnlyStep) : name(std::move(n)), on_cells(c), step(s) {}
};

// read_any_mesh and Gmsh's reader agree on `file`: the same mesh (exact nodes, cells), the same
// MeshReadInfo (ignored_elements only if `compare_ignored`), and each query gives the same
// values or the same error. Both reads must succeed. Returns the number of cells read (0 if a
// read failed).
std::size_t expect_same_as_gmsh(const fs::path& file, const std::vector<Query>& queries = {},
                                bool compare_ignored = true) {
  SCOPED_TRACE(file.filename().string());
  MeshReadInfo ours_info, gmsh_info;
  std::optional<AnyMesh> ours, gmsh;
  try {
    ours = tetia::read_any_mesh(file, &ours_info);
  } catch (const std::runtime_error& e) {
    ADD_FAILURE() << "read_any_mesh: " << e.what();
  }
  try {
    gmsh = tetia::detail::gmsh_read_any_mesh(file, &gmsh_info);
  } catch (const std::runtime_error& e) {
    ADD_FAILURE() << "gmsh_read_any_mesh: " << e.what();
  }
  if (!ours || !gmsh) return 0;
  EXPECT_EQ(ours->index(), gmsh->index()) << "0: tetrahedra, 1: triangles";
  if (ours->index() != gmsh->index()) return 0;
  if (const auto* tets = std::get_if<TetMesh>(&*ours)) {
    expect_same_mesh(*tets, std::get<TetMesh>(*gmsh));
    EXPECT_EQ(tetia::read_mesh(file).cells, tets->cells);  // what read_any_mesh says it is
  } else {
    expect_same_mesh(std::get<TriMesh>(*ours), std::get<TriMesh>(*gmsh));
    EXPECT_EQ(tetia::read_tri_mesh(file).cells, std::get<TriMesh>(*ours).cells);
  }
  if (compare_ignored) {
    EXPECT_EQ(ours_info.ignored_elements, gmsh_info.ignored_elements);
  }
  EXPECT_EQ(ours_info.node_fields, gmsh_info.node_fields);
  EXPECT_EQ(ours_info.cell_fields, gmsh_info.cell_fields);
  EXPECT_EQ(tetia::mesh_dimension(file), ours->index() == 0 ? 3 : 2);
  for (const Query& q : queries) {
    SCOPED_TRACE("field " + q.name + (q.on_cells ? " (cells)" : " (nodes)"));
    const Outcome a = outcome_of([&] { return tetia::read_msh_field(file, q.name, q.on_cells, q.step); });
    const Outcome b = outcome_of([&] { return tetia::detail::gmsh_read_msh_field(file, q.name, q.on_cells); });
    EXPECT_EQ(a.error, b.error);
    EXPECT_EQ(a.values, b.values);  // exact doubles
  }
  return num_cells(*ours);
}

// MeshReadInfo::ignored_elements of `file` by each reader.
std::size_t ignored_by_us(const fs::path& file) {
  MeshReadInfo info;
  tetia::read_any_mesh(file, &info);
  return info.ignored_elements;
}
std::size_t ignored_by_gmsh(const fs::path& file) {
  MeshReadInfo info;
  tetia::detail::gmsh_read_any_mesh(file, &info);
  return info.ignored_elements;
}

// The models Gmsh meshes and writes for the agreement tests.
enum class Model {
  kFragmentedBoxes,  // two overlapping boxes fragmented: three volumes sharing faces
  kSeparateBoxes,    // two disjoint boxes: two volumes, no shared node
  kTwoRectangles,    // two rectangles in z = 0 sharing part of an edge, fragmented: 2D
};

struct GmshCase {
  const char* name;
  Model model;
  // Physical groups: the first cell entity, all cell entities (but kSeparateBoxes: the second
  // box is in no group, so that Mesh.SaveAll 0 drops its cells) and two facet entities.
  bool groups;
};

const GmshCase kGmshCases[] = {
    {"fragmented", Model::kFragmentedBoxes, true},         {"separate", Model::kSeparateBoxes, true},
    {"separate_nogroups", Model::kSeparateBoxes, false},   {"rectangles", Model::kTwoRectangles, true},
    {"rectangles_nogroups", Model::kTwoRectangles, false},
};

struct Variant {
  double version;           // Mesh.MshFileVersion
  bool binary;              // Mesh.Binary
  bool save_all;            // Mesh.SaveAll
  bool parametric = false;  // Mesh.SaveParametric
  std::string name() const {
    return std::string(version < 3 ? "v22" : "v41") + (binary ? "_bin" : "_ascii") + (save_all ? "_all" : "") +
           (parametric ? "_param" : "");
  }
};

// The fields each file written by write_with_gmsh carries, and the queries the agreement test
// makes: every field on its own kind (the two-step one at step 0), one on the wrong kind (an
// error naming the fields), and the fields that cannot be read as scalars on every node or cell
// (vector, partial, on facets only, absent: errors).
const std::vector<Query> kGmshQueries = {{"node scalar", false, 0}, {"cell scalar", true},   {"node scalar", true},
                                         {"cell vector", true},     {"node partial", false}, {"facet data", true},
                                         {"absent", false}};

// What msh_fields must list for such a file (in the order of the file).
void expect_gmsh_fields(const fs::path& file) {
  SCOPED_TRACE(file.filename().string());
  const std::vector<tetia::FieldInfo> fields = tetia::msh_fields(file);
  struct Expected {
    const char* name;
    bool on_cells;
    int components;
    std::vector<std::int64_t> steps;
  };
  const Expected expected[] = {{"node scalar", false, 1, {0, 1}},
                               {"cell scalar", true, 1, {0}},
                               {"cell vector", true, 3, {0}},
                               {"node partial", false, 1, {0}},
                               {"facet data", true, 1, {0}}};
  ASSERT_EQ(fields.size(), std::size(expected));
  for (std::size_t k = 0; k < fields.size(); ++k) {
    EXPECT_EQ(fields[k].name, expected[k].name);
    EXPECT_EQ(fields[k].on_cells, expected[k].on_cells) << expected[k].name;
    EXPECT_EQ(fields[k].components, expected[k].components) << expected[k].name;
    EXPECT_EQ(fields[k].steps, expected[k].steps) << expected[k].name;
  }
  MeshReadInfo info;
  const AnyMesh mesh = tetia::read_any_mesh(file, &info);
  EXPECT_EQ(info.node_fields, (std::vector<std::string>{"node scalar", "node partial"}));
  EXPECT_EQ(info.cell_fields, (std::vector<std::string>{"cell scalar", "cell vector", "facet data"}));
  // The steps of the two-step field: the default refuses to choose; each reads on its own.
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(file, "node scalar", false); }),
            "tetia: " + file.string() + ": field node scalar has 2 time steps (0, 1); choose one (--step)");
  const std::vector<double> step0 = tetia::read_msh_field(file, "node scalar", false, 0),
                            step1 = tetia::read_msh_field(file, "node scalar", false, 1);
  ASSERT_EQ(step0.size(), num_nodes(mesh));
  ASSERT_EQ(step1.size(), step0.size());
  for (std::size_t i = 0; i < step0.size(); ++i) EXPECT_NEAR(step1[i], -3.0 * step0[i], 1e-14) << i;
  EXPECT_NE(
      error_of([&] { tetia::read_msh_field(file, "node scalar", false, 2); }).find("has no time step 2 (steps: 0, 1)"),
      std::string::npos);
  // The vector field, with its components, where the scalar one on the same tags reads (in .msh
  // 2.2 with a cell entity in two physical groups Gmsh numbers the elements anew but writes the
  // data with the model's tags, which then name other elements: neither reads, see
  // kGmshQueries).
  int components = 0;
  const Outcome scalar = outcome_of([&] { return tetia::read_msh_field(file, "cell scalar", true); });
  const Outcome vector =
      outcome_of([&] { return tetia::read_msh_field(file, "cell vector", true, tetia::kOnlyStep, &components); });
  if (scalar.error.empty()) {
    EXPECT_EQ(vector.values.size(), 3 * num_cells(mesh)) << vector.error;
    EXPECT_EQ(components, 3);
  } else {
    EXPECT_NE(vector.error, "");
  }
}

// One variant of one model as Gmsh writes it: the mesh alone (gmsh::write), and the mesh
// followed by its views (gmsh::view::write, appended, which writes the mesh again before each
// view, as Gmsh always does).
struct Written {
  Variant variant;
  fs::path mesh_only, with_views;
};

// Builds `c` with Gmsh's OpenCASCADE kernel, meshes it coarsely and writes it once per variant
// as DIR/NAME_VARIANT_mesh.msh and DIR/NAME_VARIANT.msh with the views "node scalar" (NodeData
// at steps 0 and 1), "cell scalar" (ElementData), "cell vector" (3 components), "node partial"
// (every other node) and "facet data" (ElementData on the facets only).
std::vector<Written> write_with_gmsh(const GmshCase& c, const fs::path& dir, const std::vector<Variant>& variants) {
  GmshScope scope;
  namespace occ = gmsh::model::occ;
  gmsh::model::add("m");
  const int dim = c.model == Model::kTwoRectangles ? 2 : 3;
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> out_map;
  switch (c.model) {
    case Model::kFragmentedBoxes: {
      const int a = occ::addBox(0, 0, 0, 1, 1, 1);
      const int b = occ::addBox(0.5, 0.25, 0.25, 1, 0.5, 0.5);
      occ::fragment({{3, a}}, {{3, b}}, out, out_map);
      break;
    }
    case Model::kSeparateBoxes:
      occ::addBox(0, 0, 0, 1, 1, 1);
      occ::addBox(2, 0.1, 0.2, 0.7, 0.9, 0.8);
      break;
    case Model::kTwoRectangles: {
      const int a = occ::addRectangle(0, 0, 0, 1, 1);
      const int b = occ::addRectangle(1, 0.25, 0, 0.75, 1.5);
      occ::fragment({{2, a}}, {{2, b}}, out, out_map);
      break;
    }
  }
  occ::synchronize();
  gmsh::vectorpair top, facets;
  gmsh::model::getEntities(top, dim);
  gmsh::model::getEntities(facets, dim - 1);
  EXPECT_GE(top.size(), 2u);
  EXPECT_GE(facets.size(), 2u);
  if (c.groups) {
    std::vector<int> all;
    for (const auto& dt : top) all.push_back(dt.second);
    gmsh::model::addPhysicalGroup(dim, {all.front()}, 1);
    if (c.model != Model::kSeparateBoxes) {
      gmsh::model::addPhysicalGroup(dim, all, 2);  // the first entity is in two groups
      gmsh::model::setPhysicalName(dim, 2, "all cells");
    }
    gmsh::model::addPhysicalGroup(dim - 1, {facets[0].second, facets[1].second}, 3);
    gmsh::model::setPhysicalName(dim - 1, 3, "two facets");
  }
  const double h = dim == 3 ? 0.4 : 0.3;
  gmsh::option::setNumber("Mesh.MeshSizeMin", h);
  gmsh::option::setNumber("Mesh.MeshSizeMax", h);
  gmsh::model::mesh::generate(dim);

  std::vector<std::size_t> node_tags, cell_tags, cell_nodes, facet_tags, facet_nodes;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(node_tags, xyz, param, -1, -1, false, false);
  gmsh::model::mesh::getElementsByType(dim == 3 ? 4 : 2, cell_tags, cell_nodes, -1);
  gmsh::model::mesh::getElementsByType(dim == 3 ? 2 : 1, facet_tags, facet_nodes, -1);
  EXPECT_GT(cell_tags.size(), 10u);
  std::vector<double> step0, step1, cell_values, cell_vector, facet_values;
  std::vector<std::size_t> partial_tags;
  std::vector<double> partial_values;
  for (std::size_t i = 0; i < node_tags.size(); ++i) {
    // Not short decimals: ASCII files carry them with 16 digits, both readers parse that text.
    step0.push_back(xyz[3 * i] - 2.0 * xyz[3 * i + 1] + std::sin(0.1 * static_cast<double>(node_tags[i])));
    step1.push_back(-3.0 * step0.back());
    if (i % 2 == 0) {
      partial_tags.push_back(node_tags[i]);
      partial_values.push_back(1.0 / static_cast<double>(node_tags[i]));
    }
  }
  for (const std::size_t t : cell_tags) {
    cell_values.push_back(1e5 * std::cos(static_cast<double>(t)));
    cell_vector.insert(cell_vector.end(), {static_cast<double>(t), -0.5, 1e-300});
  }
  for (const std::size_t t : facet_tags) facet_values.push_back(static_cast<double>(t) / 3.0);
  std::vector<int> views;
  const auto add_view = [&](const char* name) { return views.emplace_back(gmsh::view::add(name)); };
  int v = add_view("node scalar");
  gmsh::view::addHomogeneousModelData(v, 0, "m", "NodeData", node_tags, step0, 0.0, 1);
  gmsh::view::addHomogeneousModelData(v, 1, "m", "NodeData", node_tags, step1, 1.0, 1);
  v = add_view("cell scalar");
  gmsh::view::addHomogeneousModelData(v, 0, "m", "ElementData", cell_tags, cell_values, 0.0, 1);
  v = add_view("cell vector");
  gmsh::view::addHomogeneousModelData(v, 0, "m", "ElementData", cell_tags, cell_vector, 0.0, 3);
  v = add_view("node partial");
  gmsh::view::addHomogeneousModelData(v, 0, "m", "NodeData", partial_tags, partial_values, 0.0, 1);
  v = add_view("facet data");
  gmsh::view::addHomogeneousModelData(v, 0, "m", "ElementData", facet_tags, facet_values, 0.0, 1);

  std::vector<Written> files;
  for (const Variant& var : variants) {
    gmsh::option::setNumber("Mesh.MshFileVersion", var.version);
    gmsh::option::setNumber("Mesh.Binary", var.binary ? 1 : 0);
    gmsh::option::setNumber("Mesh.SaveAll", var.save_all ? 1 : 0);
    gmsh::option::setNumber("Mesh.SaveParametric", var.parametric ? 1 : 0);
    const std::string stem = std::string(c.name) + "_" + var.name();
    Written w{var, dir / (stem + "_mesh.msh"), dir / (stem + ".msh")};
    gmsh::write(w.mesh_only.string());
    gmsh::write(w.with_views.string());
    for (const int view : views) gmsh::view::write(view, w.with_views.string(), true);
    EXPECT_TRUE(fs::exists(w.mesh_only) && fs::exists(w.with_views)) << stem;
    files.push_back(std::move(w));
  }
  return files;
}

// Gmsh 4.8 writes .msh 2.2 node data of a model whose cells are not all in physical groups with
// node tag -1 for the nodes its view writer did not save, whatever Mesh.SaveAll: a file that
// Gmsh cannot read back either ("Could not read data in msh file").
bool gmsh_writes_tag_minus_one(const GmshCase& c, const Variant& v) {
  return c.model == Model::kSeparateBoxes && c.groups && v.version < 3;
}

// With Mesh.SaveAll 1, gmsh::write numbers the elements of all entities 1..N while the copy of
// the mesh view::write appends holds the elements of physical groups only, numbered anew: in
// .msh 2.2 (4.1 keeps the model's tags) the same element tag names different elements in the
// two copies. See Gmsh22SaveAllWithAppendedViews.
bool copies_disagree(const GmshCase& c, const Variant& v) { return c.groups && v.save_all && v.version < 3; }

class MshReaderTest : public tetia::testsupport::TempDirTest {
 protected:
  MshReaderTest() : TempDirTest("msh_reader") {}

  // Writes `bytes` as NAME and expects read_any_mesh to throw std::runtime_error whose message
  // starts with "tetia: FILE: " and contains each of `parts`. Returns the message.
  std::string expect_error(const std::string& name, const std::string& bytes, std::vector<std::string> parts) {
    SCOPED_TRACE(name);
    const fs::path file = path(name);
    write_bytes(file, bytes);
    const std::string msg = error_of([&] { tetia::read_any_mesh(file); });
    EXPECT_EQ(msg.rfind("tetia: " + file.string() + ": ", 0), 0u) << msg;
    for (const auto& part : parts)
      EXPECT_NE(msg.find(part), std::string::npos) << "expected \"" << part << "\" in: " << msg;
    return msg;
  }

  fs::path write(const std::string& name, const std::string& bytes) const {
    write_bytes(path(name), bytes);
    return path(name);
  }
};

// ---------------------------------------------------------------------------------------------
// 1. Agreement with Gmsh on the files Gmsh writes

// Every model, every variant: .msh 2.2 and 4.1, ASCII and binary, Mesh.SaveAll 0 and 1, and
// 4.1 with Mesh.SaveParametric; each written alone and with its views appended. Where the mesh
// is repeated (views appended), ignored_elements is not compared with Gmsh's: Gmsh 4.8 keeps
// only the last copy of a .msh 2.2 mesh but holds a 4.1 one more than once, so its count is no
// reference there (RepeatedMeshAddsNoIgnoredElements checks it). The 2.2 files Gmsh writes
// wrongly (gmsh_writes_tag_minus_one) must be refused by both readers; those whose copies
// disagree (copies_disagree) are left to Gmsh22SaveAllWithAppendedViews.
TEST_F(MshReaderTest, AgreesWithGmshOnEveryVariantGmshWrites) {
  std::vector<Variant> variants;
  for (const double version : {2.2, 4.1})
    for (const bool binary : {false, true})
      for (const bool save_all : {false, true}) variants.push_back({version, binary, save_all, false});
  variants.push_back({4.1, false, false, true});
  variants.push_back({4.1, true, false, true});
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t files = 0;
  for (const GmshCase& c : kGmshCases) {
    SCOPED_TRACE(c.name);
    const std::vector<Written> written = write_with_gmsh(c, dir_, variants);
    ASSERT_EQ(written.size(), variants.size());
    std::size_t all_cells = 0;
    std::vector<std::size_t> cells;
    for (const Written& w : written) {
      SCOPED_TRACE(w.variant.name());
      cells.push_back(expect_same_as_gmsh(w.mesh_only));
      all_cells = std::max(all_cells, cells.back());
      ++files;
      if (gmsh_writes_tag_minus_one(c, w.variant)) {
        // Both readers refuse it; ours names the line or byte offset and the field.
        EXPECT_THROW(tetia::detail::gmsh_read_any_mesh(w.with_views), std::runtime_error);
        const std::string msg = error_of([&] { tetia::read_any_mesh(w.with_views); });
        EXPECT_NE(msg.find("field node scalar: node: "), std::string::npos) << msg;
        EXPECT_NE(msg.find(w.variant.binary ? "negative tag -1" : "\"-1\" is not a non-negative integer"),
                  std::string::npos)
            << msg;
        continue;
      }
      if (copies_disagree(c, w.variant)) continue;  // Gmsh22SaveAllWithAppendedViews
      const std::size_t with_views = expect_same_as_gmsh(w.with_views, kGmshQueries, false);
      expect_gmsh_fields(w.with_views);
      ++files;
      EXPECT_GT(with_views, 0u);
      if (!w.variant.save_all) {
        EXPECT_EQ(with_views, cells.back());  // the same mesh, repeated
      }
    }
    // Not a vacuous agreement: every file has cells, and the variants differ where they must.
    for (std::size_t k = 0; k < variants.size(); ++k) {
      SCOPED_TRACE(variants[k].name());
      EXPECT_GT(cells[k], 0u);
      if (c.model == Model::kSeparateBoxes && c.groups && !variants[k].save_all) {
        EXPECT_LT(cells[k], all_cells) << "Mesh.SaveAll 0 drops the box in no physical group";
      } else {
        EXPECT_EQ(cells[k], all_cells);
      }
    }
  }
  std::printf("[ gmsh     ] %zu files written by Gmsh read by both readers in %.2f s\n", files, seconds_since(t0));
}

// .msh 2.2 with Mesh.SaveParametric: Gmsh writes the nodes as $ParametricNodes ("tag x y z dim
// entity u [v]") in place of $Nodes, and reads them back.
TEST_F(MshReaderTest, Gmsh22ParametricNodes) {
  for (const GmshCase& c : {kGmshCases[0], kGmshCases[3]}) {
    SCOPED_TRACE(c.name);
    for (const Written& w : write_with_gmsh(c, dir_, {{2.2, false, false, true}, {2.2, true, false, true}})) {
      ASSERT_NE(read_bytes(w.mesh_only).find("$ParametricNodes"), std::string::npos);
      expect_same_as_gmsh(w.mesh_only);
    }
  }
}

// Gmsh writes a .msh 2.2 file with Mesh.SaveAll 1, physical groups and appended views (see
// copies_disagree), and reads it (the last copy of the mesh replaces the earlier ones in
// Gmsh's .msh 2.2 reader); ours should too.
TEST_F(MshReaderTest, Gmsh22SaveAllWithAppendedViews) {
  for (const GmshCase& c : {kGmshCases[0], kGmshCases[3]}) {
    SCOPED_TRACE(c.name);
    for (const Written& w : write_with_gmsh(c, dir_, {{2.2, false, true, false}, {2.2, true, true, false}})) {
      ASSERT_TRUE(copies_disagree(c, w.variant));
      expect_same_as_gmsh(w.with_views, kGmshQueries, false);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Small literal files: errors with their line or byte offset, and accepted oddities

// Two tetrahedra sharing a face, and a triangle; 17 lines, line numbers in the comments of the
// tests below refer to this text.
const std::string kTets22 =
    "$MeshFormat\n"        // 1
    "2.2 0 8\n"            // 2
    "$EndMeshFormat\n"     // 3
    "$Nodes\n"             // 4
    "5\n"                  // 5
    "1 0 0 0\n"            // 6
    "2 1 0 0\n"            // 7
    "3 0 1 0\n"            // 8
    "4 0 0 1\n"            // 9
    "5 1 1 1\n"            // 10
    "$EndNodes\n"          // 11
    "$Elements\n"          // 12
    "3\n"                  // 13
    "1 2 2 1 1 1 2 3\n"    // 14
    "2 4 2 1 1 1 2 3 4\n"  // 15
    "3 4 2 1 1 2 3 4 5\n"  // 16
    "$EndElements\n";      // 17

// The same mesh as .msh 4.1, with the entities Gmsh needs (one surface, one volume).
const std::string kTets41 =
    "$MeshFormat\n"        // 1
    "4.1 0 8\n"            // 2
    "$EndMeshFormat\n"     // 3
    "$Entities\n"          // 4
    "0 0 1 1\n"            // 5
    "1 0 0 0 1 1 1 0 0\n"  // 6
    "1 0 0 0 1 1 1 0 0\n"  // 7
    "$EndEntities\n"       // 8
    "$Nodes\n"             // 9
    "1 5 1 5\n"            // 10
    "3 1 0 5\n"            // 11
    "1\n"                  // 12
    "2\n"                  // 13
    "3\n"                  // 14
    "4\n"                  // 15
    "5\n"                  // 16
    "0 0 0\n"              // 17
    "1 0 0\n"              // 18
    "0 1 0\n"              // 19
    "0 0 1\n"              // 20
    "1 1 1\n"              // 21
    "$EndNodes\n"          // 22
    "$Elements\n"          // 23
    "2 3 1 3\n"            // 24
    "2 1 2 1\n"            // 25
    "1 1 2 3\n"            // 26
    "3 1 4 2\n"            // 27
    "2 1 2 3 4\n"          // 28
    "3 2 3 4 5\n"          // 29
    "$EndElements\n";      // 30

// A node field and a cell field, to append to either (tags as in both files).
const std::string kData =
    "$NodeData\n1\n\"temperature\"\n1\n0\n3\n0\n1\n5\n1 0.5\n2 1.5\n3 2.5\n4 3.5\n5 4.5\n$EndNodeData\n"
    "$ElementData\n1\n\"pressure\"\n1\n0\n3\n0\n1\n2\n3 -2\n2 -1\n$EndElementData\n";

TEST_F(MshReaderTest, LiteralFilesAgreeWithGmsh) {
  for (const auto& [name, text] : {std::pair{"tets22.msh", kTets22}, std::pair{"tets41.msh", kTets41}}) {
    const fs::path file = write(name, text + kData);
    EXPECT_EQ(expect_same_as_gmsh(file, {{"temperature", false}, {"pressure", true}}), 2u) << name;
    MeshReadInfo info;
    const TetMesh m = tetia::read_mesh(file, &info);
    EXPECT_EQ(info.ignored_elements, 1u);
    EXPECT_EQ(info.node_fields, std::vector<std::string>{"temperature"});
    EXPECT_EQ(info.cell_fields, std::vector<std::string>{"pressure"});
    EXPECT_DOUBLE_EQ(m.total_volume(), 1.0 / 6.0 + 1.0 / 3.0);
    EXPECT_EQ(tetia::read_msh_field(file, "temperature", false), (std::vector<double>{0.5, 1.5, 2.5, 3.5, 4.5}));
    EXPECT_EQ(tetia::read_msh_field(file, "pressure", true), (std::vector<double>{-1, -2}));
  }
}

TEST_F(MshReaderTest, DuplicateTags) {
  // A node tag given twice with other coordinates: both lines named.
  expect_error("node22.msh",
               replaced(replaced(kTets22, "$Nodes\n5\n", "$Nodes\n6\n"), "5 1 1 1\n", "5 1 1 1\n3 0 1 0.5\n"),
               {"node tag 3 given twice, differently (line 8 and line 11)"});
  expect_error("node41.msh", replaced(kTets41, "3\n4\n5\n", "3\n3\n5\n"),  // node "3" at line 15: (0, 0, 1)
               {"node tag 3 given twice, differently (line 14 and line 15)"});
  // An element tag given twice with other nodes.
  expect_error("element22.msh", replaced(kTets22, "3 4 2 1 1 2 3 4 5", "2 4 2 1 1 2 3 4 5"),
               {"element tag 2 given twice, differently (line 15 and line 16)"});
  expect_error("element41.msh", replaced(kTets41, "3 2 3 4 5", "2 2 3 4 5"),
               {"element tag 2 given twice, differently (line 28 and line 29)"});

  // The same node twice with the same coordinates: one node, as Gmsh reads it.
  const fs::path node = write(
      "same_node22.msh", replaced(replaced(kTets22, "$Nodes\n5\n", "$Nodes\n6\n"), "5 1 1 1\n", "5 1 1 1\n3 0 1 0\n"));
  EXPECT_EQ(expect_same_as_gmsh(node), 2u);
  EXPECT_EQ(tetia::read_mesh(node).num_nodes(), 5u);
  const fs::path node41 =
      write("same_node41.msh", replaced(replaced(replaced(kTets41, "1 5 1 5\n3 1 0 5\n", "1 6 1 5\n3 1 0 6\n"),
                                                 "4\n5\n0 0 0\n", "4\n5\n3\n0 0 0\n"),
                                        "1 1 1\n$EndNodes", "1 1 1\n0 1 0\n$EndNodes"));
  EXPECT_EQ(expect_same_as_gmsh(node41), 2u);
  EXPECT_EQ(tetia::read_mesh(node41).num_nodes(), 5u);
}

TEST_F(MshReaderTest, CountsThatDisagreeWithTheData) {
  // 2.2: a count smaller than the lines that follow: the next record is not the end marker.
  expect_error("nodes_small22.msh", replaced(kTets22, "$Nodes\n5\n", "$Nodes\n4\n"),
               {"line 10: expected $EndNodes after the counted data, found \"5 1 1 1\""});
  expect_error("elements_small22.msh", replaced(kTets22, "$Elements\n3\n", "$Elements\n2\n"),
               {"line 16: expected $EndElements after the counted data, found \"3 4 2 1 1 2 3 4 5\""});
  // Larger: the end marker is read as a record.
  expect_error("nodes_large22.msh", replaced(kTets22, "$Nodes\n5\n", "$Nodes\n6\n"),
               {"line 11: a node line (tag x y z): 4 numbers expected, found 1"});
  expect_error("elements_large22.msh", replaced(kTets22, "$Elements\n3\n", "$Elements\n4\n"), {"line 17: "});

  // 4.1: a block holding fewer nodes than follow; a header declaring fewer than the blocks hold.
  expect_error("nodes_small41.msh", replaced(kTets41, "1 5 1 5\n3 1 0 5\n", "1 4 1 5\n3 1 0 4\n"),
               {"line 16: a node's coordinates: 3 numbers expected, found 1"});
  expect_error("nodes_header41.msh", replaced(kTets41, "1 5 1 5\n", "1 4 1 5\n"),
               {"line 11: node blocks hold more nodes than the 4 the header declares"});
  expect_error("nodes_header_large41.msh", replaced(kTets41, "1 5 1 5\n", "1 6 1 5\n"),
               {"line 10: the $Nodes header declares 6 nodes, its blocks hold 5"});
  expect_error("elements_small41.msh", replaced(replaced(kTets41, "2 3 1 3\n", "2 2 1 3\n"), "3 1 4 2\n", "3 1 4 1\n"),
               {"line 29: expected $EndElements after the counted data, found \"3 2 3 4 5\""});
  expect_error("elements_blocks_small41.msh", replaced(kTets41, "3 1 4 2\n", "3 1 4 1\n"),
               {"line 24: the $Elements header declares 3 elements, its blocks hold 2"});
  expect_error("elements_header41.msh", replaced(kTets41, "2 3 1 3\n", "2 2 1 3\n"),
               {"line 27: element blocks hold more elements than the 2 the header declares"});

  // A count of 10^12: refused before anything is allocated for it.
  const std::string big = "1000000000000";
  expect_error("big_nodes22.msh", replaced(kTets22, "$Nodes\n5\n", "$Nodes\n" + big + "\n"),
               {"line 5: the file declares 1000000000000 nodes, more than its remaining"});
  expect_error("big_elements22.msh", replaced(kTets22, "$Elements\n3\n", "$Elements\n" + big + "\n"),
               {"line 13: the file declares 1000000000000 elements"});
  expect_error("big_nodes41.msh", replaced(kTets41, "1 5 1 5\n", "1 " + big + " 1 5\n"),
               {"line 10: the file declares 1000000000000 nodes"});
  expect_error("big_block41.msh", replaced(kTets41, "3 1 0 5\n", "3 1 0 " + big + "\n"), {"line 11: "});
  expect_error("big_elements41.msh", replaced(kTets41, "2 3 1 3\n", "2 " + big + " 1 3\n"),
               {"line 24: the file declares 1000000000000 elements"});
  expect_error("big_data.msh", replaced(kTets22 + kData, "0\n1\n5\n1 0.5", "0\n1\n" + big + "\n1 0.5"),
               {"line 26: the file declares 1000000000000 data entries"});
  // And 2^64, which is no number at all.
  expect_error("huge_nodes22.msh", replaced(kTets22, "$Nodes\n5\n", "$Nodes\n18446744073709551616\n"),
               {"line 5: the number of nodes: \"18446744073709551616\" is not a non-negative integer in range"});
}

TEST_F(MshReaderTest, BadNumbersAndTags) {
  // An element naming a node that no node has.
  expect_error("unknown_node22.msh", replaced(kTets22, "3 4 2 1 1 2 3 4 5", "3 4 2 1 1 2 3 4 9"),
               {"line 16: element 3: unknown node tag 9"});
  expect_error("unknown_node41.msh", replaced(kTets41, "3 2 3 4 5", "3 2 3 4 9"),
               {"line 29: element 3: unknown node tag 9"});
  // Coordinates out of range, infinite, not a number.
  for (const char* bad : {"1e400", "-1e400"})
    expect_error(std::string("coord_") + bad + ".msh",
                 replaced(kTets22, "4 0 0 1\n", std::string("4 0 0 ") + bad + "\n"),
                 {"line 9: node 4: coordinate: \"" + std::string(bad) + "\" is not a number in range"});
  for (const char* bad : {"inf", "-inf", "nan", "infinity", "-nan"}) {
    expect_error(std::string("coord22_") + bad + ".msh",
                 replaced(kTets22, "4 0 0 1\n", std::string("4 0 ") + bad + " 1\n"),
                 {"line 9: node 4: coordinate: \"" + std::string(bad) + "\" is not finite"});
    expect_error(std::string("coord41_") + bad + ".msh",
                 replaced(kTets41, "0 0 1\n1 1 1\n", std::string(bad) + " 0 1\n1 1 1\n"),
                 {"line 20: node 4: coordinate: \"" + std::string(bad) + "\" is not finite"});
  }
  expect_error("coord_text.msh", replaced(kTets22, "4 0 0 1\n", "4 0 0 1x\n"), {"line 9: node 4: coordinate: \"1x\""});
  // A field value that is not finite.
  expect_error("value_nan.msh", replaced(kTets22 + kData, "3 2.5", "3 nan"),
               {"line 29: field temperature: the value at node 3: \"nan\" is not finite"});
  // Tag 0, negative tags.
  expect_error("node_tag0_22.msh", replaced(kTets22, "1 0 0 0\n", "0 0 0 0\n"),
               {"line 6: node: tag 0 (tags start at 1)"});
  expect_error("node_tag0_41.msh", replaced(kTets41, "$Nodes\n1 5 1 5\n3 1 0 5\n1\n", "$Nodes\n1 5 1 5\n3 1 0 5\n0\n"),
               {"line 12: node: tag 0 (tags start at 1)"});
  expect_error("element_tag0.msh", replaced(kTets22, "2 4 2 1 1 1 2 3 4", "0 4 2 1 1 1 2 3 4"),
               {"line 15: element: tag 0 (tags start at 1)"});
  expect_error("element_node0.msh", replaced(kTets41, "2 1 2 3 4", "2 1 2 0 4"), {"line 28: element 2: node: tag 0"});
  expect_error("node_tag_neg22.msh", replaced(kTets22, "1 0 0 0\n", "-1 0 0 0\n"),
               {"line 6: node: \"-1\" is not a non-negative integer in range"});
  expect_error("node_tag_neg41.msh",
               replaced(kTets41, "$Nodes\n1 5 1 5\n3 1 0 5\n1\n", "$Nodes\n1 5 1 5\n3 1 0 5\n-1\n"),
               {"line 12: node: \"-1\" is not a non-negative integer"});
  expect_error("element_tag_neg.msh", replaced(kTets22, "2 4 2 1 1 1 2 3 4", "-2 4 2 1 1 1 2 3 4"),
               {"line 15: element: \"-2\" is not a non-negative integer"});
  expect_error("element_node_neg.msh", replaced(kTets22, "2 4 2 1 1 1 2 3 4", "2 4 2 1 1 1 2 -3 4"),
               {"line 15: element 2: node: \"-3\" is not a non-negative integer"});
  // A tetrahedron line with a node missing.
  expect_error("short_element.msh", replaced(kTets22, "2 4 2 1 1 1 2 3 4", "2 4 2 1 1 1 2 3"),
               {"line 15: element 2: type 4 has 4 nodes, the line gives 3"});
}

TEST_F(MshReaderTest, BadStructure) {
  for (const char* version : {"3.0", "4.0", "4", "1.0", "22"})
    expect_error(std::string("version_") + version + ".msh",
                 replaced(kTets22, "2.2 0 8", std::string(version) + " 0 8"),
                 {"line 2: version " + std::string(version) + " is not supported"});
  expect_error("data_size.msh", replaced(kTets22, "2.2 0 8", "2.2 0 4"), {"line 2: data size must be 8"});
  expect_error("file_type.msh", replaced(kTets22, "2.2 0 8", "2.2 2 8"), {"line 2: file type must be 0 (ASCII) or 1"});
  expect_error("no_header.msh", kTets22.substr(kTets22.find("$Nodes")), {"line 1: not a Gmsh mesh file"});
  // $Nodes without $EndNodes: followed by the next section, or by the end of the file.
  expect_error("no_end_nodes22.msh", replaced(kTets22, "$EndNodes\n", ""),
               {"line 11: expected $EndNodes after the counted data, found \"$Elements\""});
  expect_error("no_end_nodes41.msh", replaced(kTets41, "$EndNodes\n", ""),
               {"line 22: expected $EndNodes after the counted data, found \"$Elements\""});
  expect_error("eof_in_nodes.msh", kTets22.substr(0, kTets22.find("$EndNodes")),
               {"line 11: unexpected end of file (expected $EndNodes)"});
  expect_error("no_end_elements.msh", replaced(kTets41, "$EndElements\n", ""),
               {"unexpected end of file (expected $EndElements)"});
  expect_error("end_without_section.msh", kTets22 + "$EndNodeData\n",
               {"line 18: \"$EndNodeData\" without its section"});
  expect_error("unknown_section_open.msh", kTets22 + "$Comments\nno end\n",
               {"line 18: section $Comments has no $EndComments"});
  expect_error("no_elements.msh", kTets22.substr(0, kTets22.find("$Elements")), {"line 12: no $Elements section"});
  expect_error("garbage_between.msh", replaced(kTets22, "$Elements\n", "hello\n$Elements\n"),
               {"line 12: expected a section ($Name), found \"hello\""});
  // An unknown section is skipped, even one holding what looks like other sections.
  const fs::path comment =
      write("comment.msh", replaced(kTets22, "$Elements\n", "$Comments\n$Nodes\n1\n$EndComments\n$Elements\n"));
  EXPECT_EQ(tetia::read_mesh(comment).num_cells(), 2u);
}

// Binary files built here, so that the offset of each record is known.
struct BinNode {
  std::int64_t tag;
  double x, y, z;
};
struct BinElement {
  int type;
  std::int64_t tag;
  std::vector<std::int64_t> nodes;
};
struct Binary {
  std::string bytes;
  std::size_t byte_order = 0;    // offset of the integer 1 after the format line
  std::size_t nodes_header = 0;  // 2.2: the count line; 4.1: the four size_t of $Nodes
  std::vector<std::size_t> node_at, coord_at, element_at, block_at;  // coord_at: of each node's x
};

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

int element_dim(int type) {
  switch (type) {
    case 15:
      return 0;
    case 1:
      return 1;
    case 2:
    case 3:
    case 9:
      return 2;
    default:
      return 3;
  }
}

// Consecutive elements of one type form one block (int tags in 2.2: physical 1, elementary 1).
std::vector<std::pair<std::size_t, std::size_t>> blocks_of(const std::vector<BinElement>& elements) {
  std::vector<std::pair<std::size_t, std::size_t>> blocks;  // [first, last)
  for (std::size_t i = 0; i < elements.size(); ++i)
    if (blocks.empty() || elements[i].type != elements[blocks.back().first].type)
      blocks.emplace_back(i, i + 1);
    else
      blocks.back().second = i + 1;
  return blocks;
}

Binary binary22(const std::vector<BinNode>& nodes, const std::vector<BinElement>& elements) {
  Binary b;
  std::string& s = b.bytes;
  s = "$MeshFormat\n2.2 1 8\n";
  b.byte_order = s.size();
  put<std::int32_t>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n";
  b.nodes_header = s.size();
  s += std::to_string(nodes.size()) + "\n";
  for (const auto& n : nodes) {
    b.node_at.push_back(s.size());
    put(s, static_cast<std::int32_t>(n.tag));
    b.coord_at.push_back(s.size());
    for (const double c : {n.x, n.y, n.z}) put(s, c);
  }
  s += "\n$EndNodes\n$Elements\n" + std::to_string(elements.size()) + "\n";
  for (const auto& [first, last] : blocks_of(elements)) {
    b.block_at.push_back(s.size());
    put<std::int32_t>(s, elements[first].type);
    put(s, static_cast<std::int32_t>(last - first));
    put<std::int32_t>(s, 2);
    for (std::size_t i = first; i < last; ++i) {
      b.element_at.push_back(s.size());
      put(s, static_cast<std::int32_t>(elements[i].tag));
      put<std::int32_t>(s, 1);
      put<std::int32_t>(s, 1);
      for (const auto v : elements[i].nodes) put(s, static_cast<std::int32_t>(v));
    }
  }
  s += "\n$EndElements\n";
  return b;
}

// .msh 4.1 binary with $Entities (one surface and one volume, tag 1); nodes in one block on
// the volume.
Binary binary41(const std::vector<BinNode>& nodes, const std::vector<BinElement>& elements) {
  Binary b;
  std::string& s = b.bytes;
  s = "$MeshFormat\n4.1 1 8\n";
  b.byte_order = s.size();
  put<std::int32_t>(s, 1);
  s += "\n$EndMeshFormat\n$Entities\n";
  for (const std::uint64_t count : {0, 0, 1, 1}) put(s, count);
  for (int entity = 0; entity < 2; ++entity) {
    put<std::int32_t>(s, 1);
    for (const double c : {0.0, 0.0, 0.0, 1.0, 1.0, 1.0}) put(s, c);
    put<std::uint64_t>(s, 0);  // physical tags
    put<std::uint64_t>(s, 0);  // bounding entities
  }
  s += "\n$EndEntities\n$Nodes\n";
  b.nodes_header = s.size();
  const auto tag = [](std::int64_t t) { return static_cast<std::uint64_t>(t); };
  put<std::uint64_t>(s, 1);
  put<std::uint64_t>(s, nodes.size());
  put<std::uint64_t>(s, 1);
  put<std::uint64_t>(s, nodes.size());
  for (const std::int32_t v : {3, 1, 0}) put(s, v);
  put<std::uint64_t>(s, nodes.size());
  for (const auto& n : nodes) {
    b.node_at.push_back(s.size());
    put(s, tag(n.tag));
  }
  for (const auto& n : nodes) {
    b.coord_at.push_back(s.size());
    for (const double c : {n.x, n.y, n.z}) put(s, c);
  }
  s += "\n$EndNodes\n$Elements\n";
  const auto blocks = blocks_of(elements);
  put<std::uint64_t>(s, blocks.size());
  put<std::uint64_t>(s, elements.size());
  put<std::uint64_t>(s, 1);
  put<std::uint64_t>(s, elements.size());
  for (const auto& [first, last] : blocks) {
    b.block_at.push_back(s.size());
    put<std::int32_t>(s, element_dim(elements[first].type));
    put<std::int32_t>(s, 1);
    put<std::int32_t>(s, elements[first].type);
    put<std::uint64_t>(s, last - first);
    for (std::size_t i = first; i < last; ++i) {
      b.element_at.push_back(s.size());
      put(s, tag(elements[i].tag));
      for (const auto v : elements[i].nodes) put(s, tag(v));
    }
  }
  s += "\n$EndElements\n";
  return b;
}

// The mesh of kTets22 (a triangle, then two tetrahedra).
const std::vector<BinNode> kBinNodes = {{1, 0, 0, 0}, {2, 1, 0, 0}, {3, 0, 1, 0}, {4, 0, 0, 1}, {5, 1, 1, 1}};
const std::vector<BinElement> kBinElements = {{2, 1, {1, 2, 3}}, {4, 2, {1, 2, 3, 4}}, {4, 3, {2, 3, 4, 5}}};

using BinaryWriter = Binary (*)(const std::vector<BinNode>&, const std::vector<BinElement>&);
const std::pair<const char*, BinaryWriter> kBinaryWriters[] = {{"bin22", binary22}, {"bin41", binary41}};

TEST_F(MshReaderTest, BinaryFilesAgreeWithGmsh) {
  for (const auto& [name, make] : kBinaryWriters) {
    const fs::path file = write(std::string(name) + ".msh", make(kBinNodes, kBinElements).bytes);
    EXPECT_EQ(expect_same_as_gmsh(file), 2u) << name;
    MeshReadInfo info;
    EXPECT_DOUBLE_EQ(tetia::read_mesh(file, &info).total_volume(), 0.5);
    EXPECT_EQ(info.ignored_elements, 1u);
  }
}

TEST_F(MshReaderTest, BinaryErrorsNameTheByteOffset) {
  const auto at = [](std::size_t offset) { return "byte offset " + std::to_string(offset) + ": "; };
  for (const auto& [name, make] : kBinaryWriters) {
    SCOPED_TRACE(name);
    const std::string n = name;
    const Binary good = make(kBinNodes, kBinElements);

    // Big-endian: the integer 1 with its bytes reversed.
    std::string big_endian = good.bytes;
    big_endian.replace(good.byte_order, 4, std::string("\0\0\0\1", 4));
    expect_error(n + "_big_endian.msh", big_endian, {at(good.byte_order) + "a big-endian binary file (not supported)"});
    std::string no_mark = good.bytes;
    no_mark.replace(good.byte_order, 4, std::string("\2\0\0\0", 4));
    expect_error(n + "_no_mark.msh", no_mark, {at(good.byte_order) + "no byte-order mark"});

    auto nodes = kBinNodes;
    nodes[3].z = std::numeric_limits<double>::infinity();
    expect_error(n + "_inf.msh", make(nodes, kBinElements).bytes,
                 {at(good.coord_at[3] + 16) + "node 4: coordinate: not finite"});
    nodes = kBinNodes;
    nodes[1].x = std::nan("");
    const Binary with_nan = make(nodes, kBinElements);
    expect_error(n + "_nan.msh", with_nan.bytes, {at(good.coord_at[1]) + "node 2: coordinate: not finite"});

    nodes = kBinNodes;
    nodes[2].tag = 0;
    expect_error(n + "_tag0.msh", make(nodes, kBinElements).bytes,
                 {at(good.node_at[2]) + "node: tag 0 (tags start at 1)"});
    if (n == "bin22") {  // int tags; 4.1's are size_t
      nodes[2].tag = -3;
      expect_error(n + "_negative.msh", make(nodes, kBinElements).bytes,
                   {at(good.node_at[2]) + "node: negative tag -3"});
    }

    nodes = kBinNodes;
    nodes[3].tag = 3;  // at other coordinates than node 3
    expect_error(n + "_duplicate_node.msh", make(nodes, kBinElements).bytes,
                 {"node tag 3 given twice, differently (byte offset " + std::to_string(good.node_at[2]) +
                  " and byte offset " + std::to_string(good.node_at[3]) + ")"});

    auto elements = kBinElements;
    elements[2].nodes[3] = 9;
    expect_error(n + "_unknown_node.msh", make(kBinNodes, elements).bytes,
                 {at(good.element_at[2]) + "element 3: unknown node tag 9"});
    elements = kBinElements;
    elements[2].tag = 2;
    expect_error(n + "_duplicate_element.msh", make(kBinNodes, elements).bytes,
                 {"element tag 2 given twice, differently (byte offset " + std::to_string(good.element_at[1]) +
                  " and byte offset " + std::to_string(good.element_at[2]) + ")"});
    elements = kBinElements;
    elements[0].type = 99;  // a binary file gives no size: not readable on
    expect_error(n + "_unknown_type.msh", make(kBinNodes, elements).bytes,
                 {at(good.block_at[0]) + "element type 99 is unknown"});

    // A count of 10^12.
    std::string big = good.bytes;
    if (n == "bin22") {
      big = replaced(big, "$Nodes\n5\n", "$Nodes\n1000000000000\n");
    } else {
      const std::uint64_t count = 1000000000000;
      std::memcpy(big.data() + good.nodes_header + 8, &count, 8);
    }
    expect_error(n + "_big_count.msh", big, {at(good.nodes_header) + "the file declares 1000000000000 nodes"});
  }
}

TEST_F(MshReaderTest, AcceptedOddities) {
  // The same mesh twice in one file (as Gmsh writes a mesh again before each view it appends):
  // read as Gmsh merges it, the same mesh as once.
  const TetMesh once = tetia::read_mesh(write("once.msh", kTets22));
  const std::string bin22 = binary22(kBinNodes, kBinElements).bytes, bin41 = binary41(kBinNodes, kBinElements).bytes;
  const std::pair<std::string, std::string> twice[] = {{"twice22.msh", kTets22 + kTets22},
                                                       {"twice41.msh", kTets41 + kTets41},
                                                       {"twice_data.msh", kTets22 + kData + kTets22 + kData},
                                                       {"twice_bin22.msh", bin22 + bin22},
                                                       {"twice_bin41.msh", bin41 + bin41}};
  for (const auto& [name, text] : twice) {
    SCOPED_TRACE(name);
    const fs::path file = write(name, text);
    if (name == "twice_data.msh") {
      // Gmsh makes a second view of the same name for the repeated data; MeshReadInfo lists a
      // field once per name and kind.
      MeshReadInfo info;
      tetia::read_mesh(file, &info);
      EXPECT_EQ(info.node_fields, std::vector<std::string>{"temperature"});
      EXPECT_EQ(info.cell_fields, std::vector<std::string>{"pressure"});
    } else {
      EXPECT_EQ(expect_same_as_gmsh(file, {}, false), 2u);  // ignored: RepeatedMeshAddsNoIgnoredElements
    }
    const TetMesh m = tetia::read_mesh(file);
    EXPECT_EQ(m.nodes, once.nodes);
    EXPECT_EQ(m.cells, once.cells);
    const tetia::detail::MshFile parsed = tetia::detail::parse_msh(text, name);
    EXPECT_EQ(parsed.formats.size(), 2u);
    // 2.x: the last copy is the mesh (as Gmsh's 2.2 reader has it); 4.1: both read, duplicates
    // resolved when assembled.
    EXPECT_EQ(parsed.node_tags.size(), name.find("41") != std::string::npos ? 10u : 5u);
  }
  // The data given twice at one time step: two values for each node (tetia/io.hpp: an error).
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(path("twice_data.msh"), "temperature", false); }),
            "tetia: " + path("twice_data.msh").string() + ": field temperature: node tag 1 has two values");

  // CRLF line endings (with data: quoted names lose their \r too); error lines counted alike.
  struct Crlf {
    std::string name, text, from, to, line;
  };
  for (const Crlf& c : {Crlf{"crlf22.msh", kTets22 + kData, "2 1 0 0", "2 1 0 x", "line 7: "},
                        Crlf{"crlf41.msh", kTets41 + kData, "1 0 0\n0 1 0", "1 0 x\n0 1 0", "line 18: "}}) {
    SCOPED_TRACE(c.name);
    const fs::path file = write(c.name, with_crlf(c.text));
    MeshReadInfo info;
    const TetMesh m = tetia::read_mesh(file, &info);
    EXPECT_EQ(m.nodes, once.nodes);
    EXPECT_EQ(m.cells, once.cells);
    EXPECT_EQ(info.node_fields, std::vector<std::string>{"temperature"});
    EXPECT_EQ(info.cell_fields, std::vector<std::string>{"pressure"});
    EXPECT_EQ(tetia::read_msh_field(file, "pressure", true), (std::vector<double>{-1, -2}));
    EXPECT_EQ(expect_same_as_gmsh(file, {{"temperature", false}, {"pressure", true}}), 2u);
    expect_error("bad_" + c.name, with_crlf(replaced(c.text, c.from, c.to)), {c.line});
  }

  // Element types that are not kept: unknown ones (ASCII: the line says how long it is),
  // quadrilaterals in a 3D mesh, points, lines: counted. (Hexahedra, prisms and pyramids are
  // read: test_cell_types.cpp.)
  const std::string extra22 =
      "4 99 2 1 1 1 2 3 4 5 1 2\n"   // unknown type 99
      "5 3 2 1 1 1 2 5 3\n"          // quadrilateral
      "6 15 2 1 1 5\n"               // point
      "7 1 2 1 1 1 2\n"              // line
      "8 15 2 1 1 4\n"               // point
      "9 1 2 1 1 4 5\n";             // line
  MeshReadInfo info;
  const fs::path others = write("others22.msh", replaced(replaced(kTets22, "$Elements\n3\n", "$Elements\n9\n"),
                                                         "$EndElements", extra22 + "$EndElements"));
  EXPECT_EQ(tetia::read_mesh(others, &info).cells, once.cells);
  EXPECT_EQ(info.ignored_elements, 7u);  // the triangle, and the six above
  const fs::path others41 = write("others41.msh", replaced(replaced(kTets41, "2 3 1 3\n", "4 5 1 9\n"), "$EndElements",
                                                           "3 1 99 1\n4 1 2 3 4 5\n2 1 3 1\n5 1 2 5 3\n$EndElements"));
  EXPECT_EQ(tetia::read_mesh(others41, &info).cells, once.cells);
  EXPECT_EQ(info.ignored_elements, 3u);
  // Only such elements: no cells, the count in the message.
  const std::string lines_only = kTets22.substr(0, kTets22.find("$Elements")) +
                                 "$Elements\n2\n1 1 2 1 1 1 2\n2 15 2 1 1 5\n$EndElements\n";
  expect_error("only_lines.msh", lines_only, {"no tetrahedra or triangles (2 other elements ignored)"});
  EXPECT_NE(error_of([&] { tetia::read_mesh(path("only_lines.msh")); }).find("no tetrahedra (2 other elements ignored)"),
            std::string::npos);
  // A collapsed hexahedron (nodes given twice) is read by its pieces with volume
  // (test_cell_types.cpp checks what they fill).
  const std::string collapsed = kTets22.substr(0, kTets22.find("$Elements")) +
                                "$Elements\n1\n7 5 2 1 1 1 2 3 4 5 1 2 3\n$EndElements\n";
  std::ofstream(path("collapsed_hex.msh")) << collapsed;
  const TetMesh collapsed_mesh = tetia::read_mesh(path("collapsed_hex.msh"));
  EXPECT_EQ(collapsed_mesh.origin_tags, (std::vector<std::int64_t>{7}));
  EXPECT_GT(collapsed_mesh.num_cells(), 0u);

  // Higher-order tetrahedra (10 nodes) and triangles (6 nodes): named as not supported.
  const std::string nodes10 =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
      "5 .5 0 0\n6 .5 .5 0\n7 0 .5 0\n8 0 0 .5\n9 0 .5 .5\n10 .5 0 .5\n$EndNodes\n";
  const std::pair<std::string, std::string> tet10[] = {
      {"tet10_22.msh", nodes10 + "$Elements\n1\n1 11 2 0 1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n"},
      {"tet10_41.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n"
       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 1 2 3 4 1 2\n$EndElements\n"}};
  for (const auto& [name, text] : tet10) {
    SCOPED_TRACE(name);
    const fs::path file = write(name, text);
    EXPECT_EQ(tetia::mesh_dimension(file), 3);
    EXPECT_NE(error_of([&] { tetia::read_mesh(file); }).find("higher-order cells are not supported"),
              std::string::npos);
    expect_error(name, text, {"higher-order cells are not supported"});
  }
  const std::string tri6 = nodes10 + "$Elements\n1\n1 9 2 0 1 1 2 3 5 6 7\n$EndElements\n";
  EXPECT_EQ(tetia::mesh_dimension(write("tri6.msh", tri6)), 2);
  expect_error("tri6.msh", tri6, {"higher-order cells are not supported"});
}

// A mesh repeated in a file (as Gmsh writes it again before each view it appends) is one mesh:
// its copies add no ignored elements. MeshReadInfo::ignored_elements is "elements other than
// 4-node tetrahedra" (or 3-node triangles): the file with views must report what the mesh alone
// reports. (Gmsh's reader agrees for .msh 2.2, where it keeps the last copy.)
TEST_F(MshReaderTest, RepeatedMeshAddsNoIgnoredElements) {
  const std::string bin22 = binary22(kBinNodes, kBinElements).bytes, bin41 = binary41(kBinNodes, kBinElements).bytes;
  const std::pair<std::string, std::string> literal[] = {{"twice22.msh", kTets22 + kTets22},
                                                         {"twice41.msh", kTets41 + kTets41},
                                                         {"twice_bin22.msh", bin22 + bin22},
                                                         {"twice_bin41.msh", bin41 + bin41}};
  for (const auto& [name, text] : literal) {
    const fs::path file = write(name, text);
    EXPECT_EQ(ignored_by_us(file), 1u) << name << ": the triangle, once";
    if (name.find("22") != std::string::npos) {
      EXPECT_EQ(ignored_by_gmsh(file), 1u) << name;
    }
  }
  for (const GmshCase& c : {kGmshCases[0], kGmshCases[2], kGmshCases[3]}) {
    SCOPED_TRACE(c.name);
    for (const Written& w : write_with_gmsh(c, dir_, {{2.2, false, false, false}, {4.1, true, false, false}})) {
      const std::size_t alone = ignored_by_us(w.mesh_only);
      EXPECT_EQ(alone, ignored_by_gmsh(w.mesh_only)) << w.variant.name();
      EXPECT_EQ(ignored_by_us(w.with_views), alone)
          << w.variant.name() << ": the mesh written again with each of the 5 views (Gmsh's reader says "
          << ignored_by_gmsh(w.with_views) << ")";
    }
  }
}

// Every prefix of a valid file (ASCII and binary, 2.2 and 4.1) reads only if it ends between
// sections, after the mesh (for files without data: only the whole file, with or without its
// final newline), and otherwise throws std::runtime_error "tetia: FILE: " with the line
// (ASCII) or, once past the binary header, the byte offset.
TEST_F(MshReaderTest, EveryPrefixReadsOrThrows) {
  struct Whole {
    std::string name, text;
    std::size_t byte_order;  // binary: where the header's integer 1 is; ASCII: 0
  };
  const Binary b22 = binary22(kBinNodes, kBinElements), b41 = binary41(kBinNodes, kBinElements);
  const Whole files[] = {{"ascii22", kTets22, 0},
                         {"ascii41", kTets41, 0},
                         {"ascii22_data", kTets22 + kData, 0},
                         {"bin22", b22.bytes, b22.byte_order},
                         {"bin41", b41.bytes, b41.byte_order}};
  for (const Whole& w : files) {
    SCOPED_TRACE(w.name);
    const bool binary = w.byte_order > 0;
    const fs::path file = path(w.name + ".msh");
    const std::string prefix_of_error = "tetia: " + file.string() + ": ";
    std::size_t read_ok = 0;
    for (std::size_t len = 0; len <= w.text.size(); ++len) {
      const std::string_view p = std::string_view(w.text).substr(0, len);
      write_bytes(file, p);
      std::string msg;
      try {
        tetia::read_any_mesh(file);
        ++read_ok;
      } catch (const std::runtime_error& e) {
        msg = e.what();
      }
      std::string_view stripped = p;
      while (!stripped.empty() && stripped.back() == '\n') stripped.remove_suffix(1);
      const bool complete = stripped.find("$EndElements") != std::string_view::npos &&
                            (stripped.ends_with("$EndElements") || stripped.ends_with("$EndNodeData") ||
                             stripped.ends_with("$EndElementData"));
      EXPECT_EQ(msg.empty(), complete) << "prefix of " << len << " bytes: " << msg;
      if (msg.empty()) continue;
      EXPECT_EQ(msg.rfind(prefix_of_error, 0), 0u) << msg;
      if (binary && len + 1 >= w.byte_order) {  // the format line read (its newline may be cut)
        EXPECT_NE(msg.find(": byte offset "), std::string::npos) << len << ": " << msg;
      } else {
        EXPECT_NE(msg.find(": line "), std::string::npos) << len << ": " << msg;
      }
    }
    EXPECT_GE(read_ok, 2u);  // the whole file, and without its final newline
  }
}

// Field errors name every field of the kind asked for, and a tag given twice in one block.
TEST_F(MshReaderTest, FieldErrors) {
  const std::string two = "$ElementData\n1\n\"press\"\n1\n0\n3\n0\n1\n2\n2 7\n3 8\n$EndElementData\n";
  const fs::path file = write("fields.msh", kTets22 + kData + two);
  EXPECT_EQ(tetia::read_msh_field(file, "press", true), (std::vector<double>{7, 8}));
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(file, "x", true); }),
            "tetia: " + file.string() + ": no cell field named x (cell fields: pressure, press)");
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(file, "x", false); }),
            "tetia: " + file.string() + ": no node field named x (node fields: temperature)");
  const fs::path twice = write("tag_twice.msh", replaced(kTets22 + kData, "3 -2\n2 -1\n", "3 -2\n3 -1\n"));
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(twice, "pressure", true); }),
            "tetia: " + twice.string() + ": field pressure: element tag 3 has two values");
}

// Numbers as C reads them (strtod, sscanf: what Gmsh's reader uses), including a leading '+',
// which some writers print (printf "%+.16e"): the same mesh as Gmsh reads.
TEST_F(MshReaderTest, NumbersWithALeadingPlusAsGmshReadsThem) {
  const fs::path file = write(
      "plus.msh", replaced(replaced(kTets22, "4 0 0 1\n", "4 +0 0 +1.0e+00\n"), "5 1 1 1\n", "5 1 +1 1\n") + kData);
  EXPECT_EQ(expect_same_as_gmsh(file, {{"temperature", false}}), 2u);
  const fs::path value = write("plus_value.msh", replaced(kTets22 + kData, "3 2.5", "3 +2.5"));
  EXPECT_EQ(expect_same_as_gmsh(value, {{"temperature", false}}), 2u);
}

// Time linear in the size of the file (msh_reader.hpp's contract), whatever the tags and names:
// each case is timed against a file of about the same size that differs only where it matters
// (the best of `runs`), and must not take more than 10 times as long (a quadratic cost here is
// 20-100 times).
template <class F>
double best_time_of(F&& f, int runs = 2) {
  double best = 1e300;
  for (int k = 0; k < runs; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, seconds_since(t0));
  }
  return best;
}

// Sparse node tags that are all multiples of the bucket count the reader's hash index of tags
// gets (a std::unordered_map reserved for n tags): every tag lands in one bucket, and each
// insertion and lookup walks all the tags before it. The reference: the same file with the tags
// (i + 1) (B + 1) instead of (i + 1) B, B the bucket count (spread over the buckets, as sparse).
TEST_F(MshReaderTest, AdversarialNodeTagsReadInLinearTime) {
  constexpr std::size_t n = 12000;
  std::unordered_map<std::size_t, std::int32_t> probe;
  probe.reserve(n);
  const std::size_t buckets = probe.bucket_count();
  const auto file_with = [&](std::size_t step) {
    const auto tag = [&](std::size_t i) { return std::to_string((i + 1) * step); };
    std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + std::to_string(n) + "\n";
    for (std::size_t i = 0; i < n; ++i)  // nodes on a helix: the tetrahedra of the chain are not flat
      s += tag(i) + " " + std::to_string(std::cos(0.7 * static_cast<double>(i))) + " " +
           std::to_string(std::sin(0.7 * static_cast<double>(i))) + " " + std::to_string(0.1 * static_cast<double>(i)) +
           "\n";
    s += "$EndNodes\n$Elements\n" + std::to_string(n - 3) + "\n";
    for (std::size_t i = 0; i + 3 < n; ++i)
      s += std::to_string(i + 1) + " 4 2 1 1 " + tag(i) + " " + tag(i + 1) + " " + tag(i + 2) + " " + tag(i + 3) + "\n";
    return s + "$EndElements\n";
  };
  const fs::path colliding = write("colliding.msh", file_with(buckets)),
                 spread = write("spread.msh", file_with(buckets + 1));
  EXPECT_EQ(num_cells(tetia::read_any_mesh(spread)), n - 3);
  const double t_spread = best_time_of([&] { tetia::read_any_mesh(spread); });
  const double t_colliding = best_time_of([&] { EXPECT_EQ(num_cells(tetia::read_any_mesh(colliding)), n - 3); }, 1);
  std::printf("[ timing   ] %zu nodes: tags spread over the buckets %.3f s, in one bucket %.3f s\n", n, t_spread,
              t_colliding);
  EXPECT_LT(t_colliding, 10 * t_spread + 0.05);
}

// Many fields: 15000 $NodeData sections of distinct names (empty ones, the smallest there
// are), against as many of one name: read_any_mesh with its MeshReadInfo, and read_msh_field of
// a name that is not there (whose error lists the fields of the file).
TEST_F(MshReaderTest, ManyFieldNamesReadInLinearTime) {
  constexpr int n = 15000;
  const auto file_with = [&](bool distinct) {
    std::string s = kTets22;
    for (int i = 0; i < n; ++i)
      s += "$NodeData\n1\n\"f" + (distinct ? std::to_string(i + 100000) : std::string("100000")) +
           "\"\n1\n0\n3\n0\n1\n0\n$EndNodeData\n";
    return s;
  };
  const fs::path distinct = write("distinct.msh", file_with(true)), same = write("same.msh", file_with(false));
  const auto read = [](const fs::path& f) {
    MeshReadInfo info;
    tetia::read_any_mesh(f, &info);
  };
  const double t_same = best_time_of([&] { read(same); });
  const double t_distinct = best_time_of([&] { read(distinct); }, 1);
  const double t_field = best_time_of([&] { (void)error_of([&] { tetia::read_msh_field(distinct, "x", false); }); }, 1);
  std::printf("[ timing   ] %d data sections: one name %.3f s, distinct names %.3f s, read_msh_field %.3f s\n", n,
              t_same, t_distinct, t_field);
  EXPECT_LT(t_distinct, 10 * t_same + 0.05);
  EXPECT_LT(t_field, 10 * t_same + 0.05) << "read_msh_field";
}

// ---------------------------------------------------------------------------------------------
// 3. Mutants of files written by Gmsh: read or std::runtime_error, never a crash

// A small mesh (one box, coarse) with a node and a cell view, written by Gmsh.
std::string gmsh_small_file(const fs::path& file, double version, bool binary, bool two_d) {
  GmshScope scope;
  gmsh::model::add("m");
  if (two_d) {
    gmsh::model::occ::addRectangle(0, 0, 0, 1, 0.5);
  } else {
    gmsh::model::occ::addBox(0, 0, 0, 1, 0.5, 0.5);
  }
  gmsh::model::occ::synchronize();
  gmsh::model::addPhysicalGroup(two_d ? 2 : 3, {1}, 7);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.5);
  gmsh::option::setNumber("Mesh.MeshSizeMax", 0.5);
  gmsh::model::mesh::generate(two_d ? 2 : 3);
  std::vector<std::size_t> node_tags, cell_tags, cell_nodes;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(node_tags, xyz, param, -1, -1, false, false);
  gmsh::model::mesh::getElementsByType(two_d ? 2 : 4, cell_tags, cell_nodes, -1);
  std::vector<double> on_nodes(node_tags.size()), on_cells(cell_tags.size());
  for (std::size_t i = 0; i < on_nodes.size(); ++i) on_nodes[i] = xyz[3 * i] + 0.25;
  for (std::size_t i = 0; i < on_cells.size(); ++i) on_cells[i] = static_cast<double>(i) - 0.5;
  gmsh::option::setNumber("Mesh.MshFileVersion", version);
  gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
  gmsh::write(file.string());
  const int a = gmsh::view::add("u");
  gmsh::view::addHomogeneousModelData(a, 0, "m", "NodeData", node_tags, on_nodes, 0.0, 1);
  gmsh::view::write(a, file.string(), true);
  const int b = gmsh::view::add("c");
  gmsh::view::addHomogeneousModelData(b, 0, "m", "ElementData", cell_tags, on_cells, 0.0, 1);
  gmsh::view::write(b, file.string(), true);
  return read_bytes(file);
}

// One mutant of `src`: 1 to 8 bytes overwritten, a truncation, a range duplicated, a token
// (ASCII: a run of non-blanks) replaced by an edge value, or an aligned 4- or 8-byte word
// replaced by an edge integer. Appends what was done to `what`.
std::string mutate(const std::string& src, std::mt19937_64& rng, std::string& what) {
  std::string m = src;
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  static const char kAlphabet[] = "0123456789-+.eE \n\r\t$";
  static const char* const kTokens[] = {"0",
                                        "-1",
                                        "1",
                                        "2",
                                        "3",
                                        "4",
                                        "9",
                                        "99",
                                        "1e400",
                                        "nan",
                                        "inf",
                                        "-0",
                                        "1000000000000",
                                        "18446744073709551615",
                                        "18446744073709551616",
                                        "2147483648",
                                        "4.1",
                                        "2.2",
                                        "$EndNodes",
                                        "$Nodes",
                                        "$EndElements",
                                        "",
                                        "\"",
                                        "1 1 1 1 1 1 1 1"};
  static const std::int64_t kWords[] = {0,
                                        1,
                                        2,
                                        3,
                                        4,
                                        -1,
                                        99,
                                        1000000000000,
                                        std::numeric_limits<std::int32_t>::max(),
                                        std::numeric_limits<std::int32_t>::min(),
                                        std::int64_t{1} << 32,
                                        std::numeric_limits<std::int64_t>::max(),
                                        std::numeric_limits<std::int64_t>::min()};
  switch (pick(6)) {
    case 0:
    case 1: {  // overwrite 1-8 bytes
      const std::size_t k = 1 + pick(8);
      what += "overwrite";
      for (std::size_t i = 0; i < k; ++i) {
        const std::size_t at = pick(m.size());
        const char c = pick(2) == 0 ? static_cast<char>(rng() & 0xff) : kAlphabet[pick(sizeof kAlphabet - 1)];
        m[at] = c;
        what += " " + std::to_string(at) + "=" + std::to_string(static_cast<unsigned char>(c));
      }
      break;
    }
    case 2: {  // truncate
      const std::size_t len = pick(m.size());
      m.resize(len);
      what += "truncate " + std::to_string(len);
      break;
    }
    case 3: {  // duplicate a range (at most 1/4 of the file), right after itself or elsewhere
      const std::size_t from = pick(m.size());
      const std::size_t len = 1 + pick(std::min(m.size() - from, 1 + m.size() / 4));
      const std::size_t to = pick(2) == 0 ? from + len : pick(m.size() + 1);
      m.insert(to, src.substr(from, len));
      what += "duplicate " + std::to_string(from) + "+" + std::to_string(len) + " at " + std::to_string(to);
      break;
    }
    case 4: {  // a token replaced
      std::size_t at = pick(m.size());
      while (at > 0 && !std::isspace(static_cast<unsigned char>(m[at - 1]))) --at;
      std::size_t end = at;
      while (end < m.size() && !std::isspace(static_cast<unsigned char>(m[end]))) ++end;
      const char* token = kTokens[pick(std::size(kTokens))];
      m.replace(at, end - at, token);
      what += "token " + std::to_string(at) + "=\"" + token + "\"";
      break;
    }
    default: {  // an aligned word replaced
      const std::size_t size = pick(2) == 0 ? 4 : 8;
      if (m.size() < size) break;
      const std::size_t at = pick(m.size() - size + 1) / 4 * 4;
      const std::int64_t v = kWords[pick(std::size(kWords))];
      if (size == 4) {
        const auto w = static_cast<std::int32_t>(v);
        std::memcpy(m.data() + at, &w, 4);
      } else {
        std::memcpy(m.data() + at, &v, 8);
      }
      what += "word " + std::to_string(at) + "=" + std::to_string(v) + " (" + std::to_string(size) + " bytes)";
      break;
    }
  }
  return m;
}

template <class Mesh>
void expect_valid(const Mesh& m, const std::string& what) {
  ASSERT_FALSE(m.cells.empty()) << what;
  ASSERT_EQ(m.neighbors.size(), m.cells.size()) << what;
  for (const auto& c : m.cells)
    for (const auto v : c) ASSERT_TRUE(v >= 0 && static_cast<std::size_t>(v) < m.nodes.size()) << what;
}

TEST_F(MshReaderTest, MutantsReadOrThrowRuntimeError) {
  struct Source {
    const char* name;
    double version;
    bool binary, two_d;
  };
  const Source sources[] = {{"bin22", 2.2, true, false},
                            {"bin41", 4.1, true, false},
                            {"ascii22", 2.2, false, false},
                            {"ascii41", 4.1, false, false},
                            {"bin41_2d", 4.1, true, true}};
  // TETIA_MUTANTS=N runs N per source instead (a longer search, e.g. under ASan).
  const char* env = std::getenv("TETIA_MUTANTS");
  const int kMutants = env != nullptr && std::atoi(env) > 0 ? std::atoi(env) : 3000;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t s = 0; s < std::size(sources); ++s) {
    const Source& src = sources[s];
    SCOPED_TRACE(src.name);
    const std::string bytes =
        gmsh_small_file(path(std::string(src.name) + "_src.msh"), src.version, src.binary, src.two_d);
    ASSERT_GT(bytes.size(), 500u);
    EXPECT_GT(expect_same_as_gmsh(path(std::string(src.name) + "_src.msh"), {{"u", false}, {"c", true}}, false), 0u);
    std::mt19937_64 rng(20240531 + s);
    const fs::path file = path(std::string(src.name) + "_mutant.msh");
    const std::string prefix = "tetia: " + file.string() + ": ";
    std::size_t read_ok = 0, rejected = 0, failures = 0;
    std::string what;
    // Runs one call on the mutant: true if it returned; false if it threw std::runtime_error
    // naming the file; anything else thrown fails the test (the first few reported).
    const auto guard = [&](const char* call, const auto& f) {
      try {
        f();
        return true;
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()).rfind(prefix, 0) != 0 && ++failures <= 5)
          ADD_FAILURE() << what << ": " << call << ": the message does not name the file: " << e.what();
      } catch (const std::exception& e) {
        if (++failures <= 5) ADD_FAILURE() << what << ": " << call << ": " << typeid(e).name() << ": " << e.what();
      }
      return false;
    };
    for (int i = 0; i < kMutants; ++i) {
      what = "mutant " + std::to_string(i) + ": ";
      const std::string m = mutate(bytes, rng, what);
      write_bytes(file, m);
      std::optional<AnyMesh> mesh;
      MeshReadInfo info;
      if (guard("read_any_mesh", [&] { mesh = tetia::read_any_mesh(file, &info); })) {
        std::visit([&](const auto& mm) { expect_valid(mm, what); }, *mesh);
        ++read_ok;
      } else {
        ++rejected;
      }
      // The other entry points on the same bytes, whether the mesh read or not.
      guard("mesh_dimension", [&] { tetia::mesh_dimension(file); });
      for (const Query& q : {Query{"u", false}, Query{"c", true}}) {
        std::vector<double> v;
        if (guard("read_msh_field", [&] { v = tetia::read_msh_field(file, q.name, q.on_cells); }) && mesh) {
          EXPECT_EQ(v.size(), q.on_cells ? num_cells(*mesh) : num_nodes(*mesh)) << what;
        }
      }
    }
    std::printf("[ mutants  ] %s (%zu bytes): %d mutants, %zu read, %zu rejected\n", src.name, bytes.size(), kMutants,
                read_ok, rejected);
    EXPECT_EQ(read_ok + rejected, static_cast<std::size_t>(kMutants));
    EXPECT_GT(rejected, static_cast<std::size_t>(kMutants) / 4);
  }
  std::printf("[ mutants  ] %.2f s\n", seconds_since(t0));
}

}  // namespace
