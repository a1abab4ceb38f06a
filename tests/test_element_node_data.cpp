// test_element_node_data.cpp -- element-node data ($ElementNodeData: discontinuous fields, one
// value per node of each element) read with the mesh (MeshReadOptions::fields_on_cell_nodes,
// read_msh_field), listed (MeshReadInfo::cell_node_fields, msh_fields) and written (write_msh's
// cell_node_data), tetia/io.hpp.
//
// Why: a discontinuous P1 field comes in and goes out of `tetia remap` as element-node data.
// Its values belong to (element, node) pairs, while the mesh tetia returns is made of other
// cells: hexahedra split into tetrahedra, inverted cells reoriented (two vertices swapped). So
// every value must land on the simplex vertex that is the same node of the same element, never
// on a position. Checked here:
//  1. Round trips through write_msh and read_mesh / read_tri_mesh, bit for bit (values of every
//     bit pattern: subnormals, -0, the extremes), scalar and 3 components, 3D and 2D, next to
//     node and element data of the same name.
//  2. Literal files (.msh 4.1 and 2.2 ASCII; 4.1 and 2.2 binary built here, the offset of each
//     record known) of two hexahedra sharing a face with different values there (the field is
//     discontinuous) and an inverted tetrahedron, with scrambled node tags: every simplex vertex
//     gets its element's value at that node. The same for only tetrahedra (no split: the
//     reorientation alone), a quadrilateral and an inverted triangle in 2D, and a 10-node
//     tetrahedron read by its corners.
//  3. Gmsh's own files with element-node data (.msh 2.2 and 4.1, ASCII and binary), read as
//     written.
//  4. Errors, each naming the file and the field, and the element or the line / byte offset:
//     a wrong number of nodes, a missing element, a tag given twice, an unknown field (the
//     message lists the element-node fields there are), several time steps and none chosen, a
//     line of the wrong length, a non-finite value; and the writer's: split file cells, sizes.
#include <gtest/gtest.h>
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>
#include <variant>
#include <vector>

#include "support/error_of.hpp"
#include "support/gmsh_write.hpp"
#include "support/temp_dir.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/mesh_from_arrays.hpp"

namespace {

namespace fs = std::filesystem;
using tetia::Field;
using tetia::MeshReadInfo;
using tetia::MeshReadOptions;
using tetia::TetMesh;
using tetia::TriMesh;
using tetia::testsupport::error_of;

void write_bytes(const fs::path& p, std::string_view s) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(s.data(), static_cast<std::streamsize>(s.size()));
}

// Bit for bit (so -0 and 0 differ, as do NaNs of other payloads, though none are written).
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// Finite doubles of every kind: random bit patterns (every exponent, subnormals), and the edges.
std::vector<double> any_doubles(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double edges[] = {0.0, -0.0, std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::min(),
                          std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(), 0.1, 1.0 / 3.0};
  std::vector<double> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i < std::size(edges)) {
      out.push_back(edges[i]);
      continue;
    }
    double v = 0;
    do {
      const std::uint64_t bits = rng();
      std::memcpy(&v, &bits, sizeof v);
    } while (!std::isfinite(v));
    out.push_back(v);
  }
  return out;
}

MeshReadOptions cell_node_fields(std::vector<std::string> names) {
  MeshReadOptions o;
  o.fields = std::move(names);
  o.fields_on_cell_nodes = true;
  return o;
}

class ElementNodeDataTest : public tetia::testsupport::TempDirTest {
 protected:
  ElementNodeDataTest() : TempDirTest("element_node_data") {}

  fs::path write(const std::string& name, std::string_view bytes) const {
    write_bytes(path(name), bytes);
    return path(name);
  }
  std::string prefix(const fs::path& file) const { return "tetia: " + file.string() + ": "; }
};

// ---------------------------------------------------------------------------------------------
// 1. Round trips

TEST_F(ElementNodeDataTest, RoundTripBitForBit3D) {
  const TetMesh m = tetia::make_kuhn_mesh({2, 2, 1}, {0.1, -0.3, 0.7}, {0.1, 0.2, 0.3});
  const std::size_t per_vertex = 4 * m.num_cells();
  const Field u{"u", any_doubles(per_vertex, 1), 1};
  const Field v{"velocity", any_doubles(3 * per_vertex, 2), 3};
  // Node and element data of the same name as an element-node field: other kinds, kept apart.
  const Field on_nodes{"u", std::vector<double>(m.num_nodes(), 2.5), 1};
  const Field on_cells{"u", std::vector<double>(m.num_cells(), -1.5), 1};
  const fs::path file = path("kuhn.msh");
  tetia::write_msh(file, m, {on_cells}, {on_nodes}, {u, v});

  MeshReadInfo info;
  const TetMesh back = tetia::read_mesh(file, &info, cell_node_fields({"velocity", "u"}));
  EXPECT_EQ(back.cells, m.cells);
  EXPECT_EQ(back.reoriented_cells, 0u);
  ASSERT_EQ(info.fields.size(), 2u);
  EXPECT_EQ(info.fields[0].name, "velocity");
  EXPECT_EQ(info.fields[0].components, 3);
  EXPECT_TRUE(same_bits(info.fields[0].values, v.values));
  EXPECT_EQ(info.fields[1].components, 1);
  EXPECT_TRUE(same_bits(info.fields[1].values, u.values));
  EXPECT_EQ(info.node_fields, std::vector<std::string>{"u"});
  EXPECT_EQ(info.cell_fields, std::vector<std::string>{"u"});
  EXPECT_EQ(info.cell_node_fields, (std::vector<std::string>{"u", "velocity"}));

  // The other kinds of the same name still read as they did.
  MeshReadOptions plain;
  plain.fields = {"u"};
  (void)tetia::read_mesh(file, &info, plain);
  EXPECT_EQ(info.fields[0].values, on_cells.values);

  // read_msh_field and read_any_mesh give the same.
  MeshReadOptions per_node;
  per_node.fields_on_cell_nodes = true;
  EXPECT_TRUE(same_bits(tetia::read_msh_field(file, "u", true, tetia::kOnlyStep, nullptr, per_node), u.values));
  int components = 0;
  EXPECT_TRUE(same_bits(tetia::read_msh_field(file, "velocity", false, 0, &components, per_node), v.values));
  EXPECT_EQ(components, 3);
  EXPECT_EQ(error_of([&] { tetia::read_msh_field(file, "velocity", true, tetia::kOnlyStep, nullptr, per_node); }),
            prefix(file) + "field velocity has 3 components; only scalar fields are read here");
  (void)tetia::read_any_mesh(file, &info, cell_node_fields({"u"}));
  EXPECT_TRUE(same_bits(info.fields[0].values, u.values));

  const std::vector<tetia::FieldInfo> listed = tetia::msh_fields(file);
  ASSERT_EQ(listed.size(), 4u);
  EXPECT_EQ(listed[0].name, "u");  // in file order: node, element, then element-node data
  EXPECT_FALSE(listed[0].on_cells || listed[0].on_cell_nodes);
  EXPECT_TRUE(listed[1].on_cells && !listed[1].on_cell_nodes);
  for (const int i : {2, 3}) {
    EXPECT_FALSE(listed[static_cast<std::size_t>(i)].on_cells);
    EXPECT_TRUE(listed[static_cast<std::size_t>(i)].on_cell_nodes);
    EXPECT_EQ(listed[static_cast<std::size_t>(i)].steps, std::vector<std::int64_t>{0});
  }
  EXPECT_EQ(listed[2].name, "u");
  EXPECT_EQ(listed[3].name, "velocity");
  EXPECT_EQ(listed[3].components, 3);
}

TEST_F(ElementNodeDataTest, RoundTripBitForBit2D) {
  const TriMesh m = tetia::make_structured_tri_mesh({3, 2}, {0.1, -0.3}, {0.1, 0.2});
  const std::size_t per_vertex = 3 * m.num_cells();
  const Field u{"u", any_doubles(per_vertex, 3), 1};
  const Field g{"grad", any_doubles(3 * per_vertex, 4), 3};
  const fs::path file = path("tri.msh");
  tetia::write_msh(file, m, {}, {}, {u, g});
  MeshReadInfo info;
  const TriMesh back = tetia::read_tri_mesh(file, &info, cell_node_fields({"u", "grad"}));
  EXPECT_EQ(back.cells, m.cells);
  ASSERT_EQ(info.fields.size(), 2u);
  EXPECT_TRUE(same_bits(info.fields[0].values, u.values));
  EXPECT_TRUE(same_bits(info.fields[1].values, g.values));
  EXPECT_EQ(info.fields[1].components, 3);
  EXPECT_EQ(info.cell_node_fields, (std::vector<std::string>{"u", "grad"}));
  const tetia::AnyMesh any = tetia::read_any_mesh(file, &info, cell_node_fields({"grad"}));
  EXPECT_TRUE(std::holds_alternative<TriMesh>(any));
  EXPECT_TRUE(same_bits(info.fields[0].values, g.values));
}

// ---------------------------------------------------------------------------------------------
// 2. Literal files

// Two unit cubes side by side (x in [0, 1] and [1, 2]: hexahedra with element tags 7 and 3,
// sharing the face x = 1) and, apart, a tetrahedron listed inverted (element 11), with node
// tags that follow no geometric order. Value j of element e at its node in position p (Gmsh's
// node order): 100 e + p + 1, and for the 3-component field "v" that times 1, -1, 0.5.
struct LiteralNode {
  int tag;
  double x, y, z;
};
const LiteralNode kNodes[] = {{1, 1, 1, 1},  {2, 0, 0, 0},  {3, 2, 0, 1},  {4, 1, 0, 0},  {5, 0, 1, 1},  {6, 2, 1, 0},
                              {7, 1, 1, 0},  {8, 0, 0, 1},  {9, 2, 0, 0},  {10, 0, 1, 0}, {11, 1, 0, 1}, {12, 2, 1, 1},
                              {13, 5, 0, 0}, {14, 6, 0, 0}, {15, 5, 1, 0}, {16, 5, 0, 1}};
struct LiteralElement {
  int tag, type;
  std::vector<int> nodes;
};
const std::vector<LiteralElement> kElements = {{7, 5, {2, 4, 7, 10, 8, 11, 1, 5}},
                                               {3, 5, {4, 9, 6, 7, 11, 3, 12, 1}},
                                               {11, 4, {13, 15, 14, 16}}};  // (13, 14, 15, 16) is positive
constexpr double kScale[3] = {1.0, -1.0, 0.5};

double literal_value(int element, std::size_t position, int component) {
  return (100.0 * element + static_cast<double>(position) + 1.0) * kScale[component];
}

// "$ElementNodeData" of field `name` (1 or 3 components) at `step` on `elements`, as text.
std::string ascii_element_node_data(const std::string& name, int components, int step,
                                    const std::vector<LiteralElement>& elements) {
  std::string s = "$ElementNodeData\n1\n\"" + name + "\"\n1\n0.0\n3\n" + std::to_string(step) + "\n" +
                  std::to_string(components) + "\n" + std::to_string(elements.size()) + "\n";
  for (const auto& e : elements) {
    s += std::to_string(e.tag) + " " + std::to_string(e.nodes.size());
    for (std::size_t p = 0; p < e.nodes.size(); ++p)
      for (int j = 0; j < components; ++j) {
        char buf[32];
        std::snprintf(buf, sizeof buf, " %.17g", literal_value(e.tag, p, j));
        s += buf;
      }
    s += "\n";
  }
  return s + "$EndElementNodeData\n";
}

std::string ascii41_mesh(const std::vector<LiteralElement>& elements) {
  std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 16 1 16\n3 1 0 16\n";
  for (const auto& n : kNodes) s += std::to_string(n.tag) + "\n";
  for (const auto& n : kNodes) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g %g %g\n", n.x, n.y, n.z);
    s += buf;
  }
  s += "$EndNodes\n$Elements\n" + std::to_string(elements.size()) + " " + std::to_string(elements.size()) + " 1 99\n";
  for (const auto& e : elements) {  // one block per element: blocks may repeat a type
    s += "3 1 " + std::to_string(e.type) + " 1\n" + std::to_string(e.tag);
    for (const int v : e.nodes) (s += ' ') += std::to_string(v);
    s += "\n";
  }
  return s + "$EndElements\n";
}

std::string ascii22_mesh(const std::vector<LiteralElement>& elements) {
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n16\n";
  for (const auto& n : kNodes) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d %g %g %g\n", n.tag, n.x, n.y, n.z);
    s += buf;
  }
  s += "$EndNodes\n$Elements\n" + std::to_string(elements.size()) + "\n";
  for (const auto& e : elements) {
    s += std::to_string(e.tag) + " " + std::to_string(e.type) + " 2 1 1";
    for (const int v : e.nodes) (s += ' ') += std::to_string(v);
    s += "\n";
  }
  return s + "$EndElements\n";
}

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

// The literal mesh and field "u" (scalar) in binary: 2.2 (int tags) or 4.1 (size_t tags, no
// $Entities); the data entries are int tag, int number of nodes, the doubles in both.
// entry_at receives the byte offset of each data entry.
std::string binary_file(bool v41, std::vector<std::size_t>& entry_at, int nodes_of_first = 8) {
  std::string s = v41 ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n2.2 1 8\n";
  put<std::int32_t>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n";
  if (v41) {
    for (const std::uint64_t v : {1, 16, 1, 16}) put(s, v);
    for (const std::int32_t v : {3, 1, 0}) put(s, v);
    put<std::uint64_t>(s, 16);
    for (const auto& n : kNodes) put(s, static_cast<std::uint64_t>(n.tag));
    for (const auto& n : kNodes)
      for (const double c : {n.x, n.y, n.z}) put(s, c);
  } else {
    s += "16\n";
    for (const auto& n : kNodes) {
      put<std::int32_t>(s, n.tag);
      for (const double c : {n.x, n.y, n.z}) put(s, c);
    }
  }
  s += "\n$EndNodes\n$Elements\n";
  if (v41) {
    for (const std::uint64_t v : {3, 3, 1, 11}) put(s, v);
    for (const auto& e : kElements) {
      for (const std::int32_t v : {3, 1, e.type}) put(s, v);
      put<std::uint64_t>(s, 1);
      put(s, static_cast<std::uint64_t>(e.tag));
      for (const int v : e.nodes) put(s, static_cast<std::uint64_t>(v));
    }
  } else {
    s += "3\n";
    for (const auto& e : kElements) {
      for (const std::int32_t v : {e.type, 1, 2}) put(s, v);
      for (const std::int32_t v : {e.tag, 1, 1}) put(s, v);
      for (const int v : e.nodes) put<std::int32_t>(s, v);
    }
  }
  s += "\n$EndElements\n$ElementNodeData\n1\n\"u\"\n1\n0.0\n3\n0\n1\n3\n";
  entry_at.clear();
  for (std::size_t i = 0; i < kElements.size(); ++i) {
    const auto& e = kElements[i];
    entry_at.push_back(s.size());
    put<std::int32_t>(s, e.tag);
    const int n = i == 0 ? nodes_of_first : static_cast<int>(e.nodes.size());
    put<std::int32_t>(s, n);
    // At most the element's nodes' values: a count too large for the file is what the reader must see.
    const int given = std::clamp(n, 0, static_cast<int>(e.nodes.size()));
    for (int p = 0; p < given; ++p) put(s, literal_value(e.tag, static_cast<std::size_t>(p), 0));
  }
  return s + "\n$EndElementNodeData\n";
}

// Every simplex vertex has its element's value at that node: the element is the simplex's file
// cell (found by its tag, or with `by_nodes` by its set of nodes: Gmsh renumbers the elements
// of the .msh 2.2 files it writes), the node found by its tag in the element's node list.
void expect_literal_values(const TetMesh& m, const Field& f, const std::vector<LiteralElement>& elements,
                           bool by_nodes = false) {
  const auto nc = static_cast<std::size_t>(f.components);
  ASSERT_EQ(f.values.size(), 4 * nc * m.num_cells());
  std::vector<std::size_t> first_node(m.num_file_cells() + 1, 0);  // in origin_nodes
  for (std::size_t i = 0; i < m.origin_types.size(); ++i)
    first_node[i + 1] = first_node[i] + static_cast<std::size_t>(tetia::file_cell_nodes(m.origin_types[i]));
  const auto node_set = [&](std::size_t c) {
    std::vector<std::int64_t> tags;
    if (m.cell_origin.empty()) {
      for (const auto v : m.cells[c]) tags.push_back(m.node_tags[static_cast<std::size_t>(v)]);
    } else {
      const std::size_t i = m.file_cell(c);
      for (std::size_t k = first_node[i]; k < first_node[i + 1]; ++k)
        tags.push_back(m.node_tags[static_cast<std::size_t>(m.origin_nodes[k])]);
    }
    std::sort(tags.begin(), tags.end());
    return tags;
  };
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const std::int64_t element = m.cell_origin.empty() ? m.cell_tags[c] : m.origin_tags[m.file_cell(c)];
    const auto e = std::find_if(elements.begin(), elements.end(), [&](const auto& x) {
      if (!by_nodes) return x.tag == element;
      std::vector<std::int64_t> nodes(x.nodes.begin(), x.nodes.end());
      std::sort(nodes.begin(), nodes.end());
      return nodes == node_set(c);
    });
    ASSERT_NE(e, elements.end());
    for (std::size_t k = 0; k < 4; ++k) {
      const std::int64_t node = m.node_tags[static_cast<std::size_t>(m.cells[c][k])];
      const auto p = static_cast<std::size_t>(std::find(e->nodes.begin(), e->nodes.end(), node) - e->nodes.begin());
      ASSERT_LT(p, e->nodes.size());
      for (std::size_t j = 0; j < nc; ++j)
        EXPECT_EQ(f.values[(c * 4 + k) * nc + j], literal_value(e->tag, p, static_cast<int>(j)))
            << f.name << ": cell " << c << " vertex " << k << " (node " << node << " of element " << element << ")";
    }
  }
}

TEST_F(ElementNodeDataTest, HexahedraSplitAndAnInvertedTetrahedronFollowTheNodes) {
  const std::string data = ascii_element_node_data("u", 1, 0, kElements) + ascii_element_node_data("v", 3, 0, kElements);
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"ascii41.msh", ascii41_mesh(kElements) + data},
                                   {"ascii22.msh", ascii22_mesh(kElements) + data}}) {
    SCOPED_TRACE(name);
    const fs::path file = write(name, text);
    MeshReadInfo info;
    const TetMesh m = tetia::read_mesh(file, &info, cell_node_fields({"u", "v"}));
    ASSERT_EQ(m.num_file_cells(), 3u);
    EXPECT_EQ(m.num_cells(), 13u);  // 6 + 6 + 1
    EXPECT_EQ(m.reoriented_cells, 1u);
    EXPECT_NEAR(m.total_volume(), 2.0 + 1.0 / 6.0, 1e-15);
    ASSERT_EQ(info.fields.size(), 2u);
    expect_literal_values(m, info.fields[0], kElements);
    expect_literal_values(m, info.fields[1], kElements);
    EXPECT_EQ(info.fields[1].components, 3);
    // Discontinuous: the shared face's nodes (tags 4, 7, 11, 1) have both elements' values.
    std::vector<double> at_node_4;
    for (std::size_t c = 0; c < m.num_cells(); ++c)
      for (std::size_t k = 0; k < 4; ++k)
        if (m.node_tags[static_cast<std::size_t>(m.cells[c][k])] == 4) at_node_4.push_back(info.fields[0].values[4 * c + k]);
    std::sort(at_node_4.begin(), at_node_4.end());
    at_node_4.erase(std::unique(at_node_4.begin(), at_node_4.end()), at_node_4.end());
    EXPECT_EQ(at_node_4, (std::vector<double>{301.0, 702.0}));
  }
  for (const bool v41 : {false, true}) {
    SCOPED_TRACE(v41 ? "binary 4.1" : "binary 2.2");
    std::vector<std::size_t> entry_at;
    const fs::path file = write(v41 ? "binary41.msh" : "binary22.msh", binary_file(v41, entry_at));
    MeshReadInfo info;
    const TetMesh m = tetia::read_mesh(file, &info, cell_node_fields({"u"}));
    EXPECT_EQ(m.num_cells(), 13u);
    EXPECT_EQ(m.reoriented_cells, 1u);
    expect_literal_values(m, info.fields[0], kElements);
    EXPECT_EQ(info.cell_node_fields, std::vector<std::string>{"u"});

    // Errors name the byte offset of the entry.
    const fs::path no_nodes = write("no_nodes.msh", binary_file(v41, entry_at, 0));
    EXPECT_EQ(error_of([&] { tetia::read_mesh(no_nodes, &info, cell_node_fields({"u"})); }),
              prefix(no_nodes) + "byte offset " + std::to_string(entry_at[0]) +
                  ": field u: element 7: 0 nodes (an element has at least 1)");
    const fs::path too_many = write("too_many.msh", binary_file(v41, entry_at, 1 << 30));
    EXPECT_NE(error_of([&] { tetia::read_mesh(too_many, &info, cell_node_fields({"u"})); })
                  .find("byte offset " + std::to_string(entry_at[0]) + ": the file declares 1073741824 values of an element"),
              std::string::npos);
    const fs::path four = write("four.msh", binary_file(v41, entry_at, 4));
    EXPECT_EQ(error_of([&] { tetia::read_mesh(four, &info, cell_node_fields({"u"})); }),
              prefix(four) + "field u: element 7 has 8 nodes, its data gives 4");
  }
}

// No split cells: the reorientation alone, on the cells of the file.
TEST_F(ElementNodeDataTest, InvertedTetrahedraWithoutSplitCells) {
  const std::vector<LiteralElement> tets = {{11, 4, {13, 15, 14, 16}}, {5, 4, {14, 13, 15, 5}}, {9, 4, {2, 4, 10, 8}}};
  for (const bool v41 : {false, true}) {
    const fs::path file =
        write("tets.msh", (v41 ? ascii41_mesh(tets) : ascii22_mesh(tets)) + ascii_element_node_data("v", 3, 0, tets));
    MeshReadInfo info;
    const TetMesh m = tetia::read_mesh(file, &info, cell_node_fields({"v"}));
    EXPECT_TRUE(m.cell_origin.empty());
    EXPECT_EQ(m.num_cells(), 3u);
    EXPECT_EQ(m.reoriented_cells, 2u);  // 11 and 5
    expect_literal_values(m, info.fields[0], tets);
  }
}

// 2D: a quadrilateral split into two triangles and an inverted triangle.
TEST_F(ElementNodeDataTest, QuadrilateralAndInvertedTriangle) {
  const std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 7 1 7\n2 1 0 7\n1\n2\n3\n4\n5\n6\n7\n"
      "1 1 0\n0 0 0\n0 1 0\n1 0 0\n3 0 0\n4 0 0\n3 1 0\n$EndNodes\n"
      "$Elements\n2 2 4 8\n2 1 3 1\n8 2 4 1 3\n2 1 2 1\n4 5 7 6\n$EndElements\n"  // triangle 4: clockwise
      "$ElementNodeData\n1\n\"w\"\n1\n0\n3\n0\n1\n2\n8 4 81 82 83 84\n4 3 41 42 43\n$EndElementNodeData\n";
  const fs::path file = write("quad.msh", text);
  MeshReadInfo info;
  const TriMesh m = tetia::read_tri_mesh(file, &info, cell_node_fields({"w"}));
  ASSERT_EQ(m.num_cells(), 3u);
  EXPECT_EQ(m.reoriented_cells, 1u);
  const std::vector<std::pair<std::int64_t, std::vector<std::int64_t>>> elements = {{8, {2, 4, 1, 3}}, {4, {5, 7, 6}}};
  const std::vector<double>& w = info.fields[0].values;
  ASSERT_EQ(w.size(), 9u);
  for (std::size_t c = 0; c < 3; ++c) {
    const std::int64_t element = m.origin_tags[m.file_cell(c)];
    const auto& nodes = element == 8 ? elements[0].second : elements[1].second;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int64_t node = m.node_tags[static_cast<std::size_t>(m.cells[c][k])];
      const auto p = std::find(nodes.begin(), nodes.end(), node) - nodes.begin();
      EXPECT_EQ(w[3 * c + k], static_cast<double>(10 * element + p + 1)) << "cell " << c << " vertex " << k;
    }
  }
}

// A 10-node tetrahedron read by its corners: the corners' values (Gmsh lists the corners first).
TEST_F(ElementNodeDataTest, HigherOrderCellByItsCorners) {
  std::string nodes = "$Nodes\n1 10 1 10\n3 1 0 10\n";
  for (int t = 1; t <= 10; ++t) nodes += std::to_string(t) + "\n";
  nodes += "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n$EndNodes\n";
  // Corners listed inverted (1 3 2 4), so that the read mesh swaps two of them.
  const std::string mesh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n" + nodes +
                           "$Elements\n1 1 1 1\n3 1 11 1\n1 1 3 2 4 7 6 5 8 9 10\n$EndElements\n";
  const std::string data_head = "$ElementNodeData\n1\n\"q\"\n1\n0\n3\n0\n1\n1\n";
  const fs::path file =
      write("tet10.msh", mesh + data_head + "1 10 10 30 20 40 70 60 50 80 90 100\n$EndElementNodeData\n");
  MeshReadOptions options = cell_node_fields({"q"});
  options.corner_nodes = true;
  MeshReadInfo info;
  const TetMesh m = tetia::read_mesh(file, &info, options);
  EXPECT_EQ(info.straightened_cells, 1u);
  ASSERT_EQ(m.num_cells(), 1u);
  EXPECT_EQ(m.reoriented_cells, 1u);
  for (std::size_t k = 0; k < 4; ++k)  // node tag t has value 10 t
    EXPECT_EQ(info.fields[0].values[k], 10.0 * static_cast<double>(m.node_tags[static_cast<std::size_t>(m.cells[0][k])]));
  const fs::path corners_only = write("tet10_four.msh", mesh + data_head + "1 4 10 30 20 40\n$EndElementNodeData\n");
  EXPECT_EQ(error_of([&] { tetia::read_mesh(corners_only, &info, options); }),
            prefix(corners_only) + "field q: element 1 has 10 nodes, its data gives 4");
}

// ---------------------------------------------------------------------------------------------
// 3. Gmsh's files

// The literal mesh and "u", "v" written by Gmsh (gmsh::view::addModelData, "ElementNodeData"),
// appended to its mesh, in every variant (Gmsh 4.8 renumbers the elements of a .msh 2.2 file, in
// its mesh and its data alike).
TEST_F(ElementNodeDataTest, FilesWrittenByGmsh) {
  tetia::testsupport::GmshScope scope;
  gmsh::model::add("m");
  const int volume = gmsh::model::addDiscreteEntity(3);
  std::vector<std::size_t> node_tags;
  std::vector<double> xyz;
  for (const auto& n : kNodes) {
    node_tags.push_back(static_cast<std::size_t>(n.tag));
    xyz.insert(xyz.end(), {n.x, n.y, n.z});
  }
  gmsh::model::mesh::addNodes(3, volume, node_tags, xyz);
  std::vector<std::size_t> element_tags;
  std::vector<std::vector<double>> u, v;
  for (const auto& e : kElements) {
    std::vector<std::size_t> nodes(e.nodes.begin(), e.nodes.end());
    gmsh::model::mesh::addElementsByType(volume, e.type, {static_cast<std::size_t>(e.tag)}, nodes);
    element_tags.push_back(static_cast<std::size_t>(e.tag));
    u.emplace_back();
    v.emplace_back();
    for (std::size_t p = 0; p < e.nodes.size(); ++p) {
      u.back().push_back(literal_value(e.tag, p, 0));
      for (int j = 0; j < 3; ++j) v.back().push_back(literal_value(e.tag, p, j));
    }
  }
  const int view_u = gmsh::view::add("u");
  gmsh::view::addModelData(view_u, 0, "m", "ElementNodeData", element_tags, u, 0.0, 1);
  const int view_v = gmsh::view::add("v");
  gmsh::view::addModelData(view_v, 0, "m", "ElementNodeData", element_tags, v, 0.0, 3);
  for (const double version : {2.2, 4.1})
    for (const bool binary : {false, true}) {
      const std::string name = std::string(version == 2.2 ? "v22" : "v41") + (binary ? "_binary" : "_ascii");
      SCOPED_TRACE(name);
      const fs::path file = path(name + ".msh");
      gmsh::option::setNumber("Mesh.MshFileVersion", version);
      gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
      gmsh::write(file.string());
      gmsh::view::write(view_u, file.string(), true);
      gmsh::view::write(view_v, file.string(), true);
      MeshReadInfo info;
      const TetMesh m = tetia::read_mesh(file, &info, cell_node_fields({"u", "v"}));
      EXPECT_EQ(m.num_cells(), 13u);
      ASSERT_EQ(info.fields.size(), 2u);
      expect_literal_values(m, info.fields[0], kElements, version == 2.2);
      expect_literal_values(m, info.fields[1], kElements, version == 2.2);
      EXPECT_EQ(info.cell_node_fields, (std::vector<std::string>{"u", "v"}));
      const auto listed = tetia::msh_fields(file);
      ASSERT_EQ(listed.size(), 2u);
      EXPECT_TRUE(listed[0].on_cell_nodes && !listed[0].on_cells);
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Errors

TEST_F(ElementNodeDataTest, ReadErrorsNameTheFieldAndTheElement) {
  const std::string mesh = ascii41_mesh(kElements);
  const auto read_u = [&](const fs::path& file, std::int64_t step = tetia::kOnlyStep) {
    MeshReadOptions options = cell_node_fields({"u"});
    options.step = step;
    MeshReadInfo info;
    (void)tetia::read_mesh(file, &info, options);
    return info.fields.empty() ? std::vector<double>{} : info.fields[0].values;
  };
  const std::string good = ascii_element_node_data("u", 1, 0, kElements);

  auto wrong_count = kElements;
  wrong_count[1].nodes.resize(4);  // hexahedron 3 given 4 nodes' values
  const fs::path count = write("count.msh", mesh + ascii_element_node_data("u", 1, 0, wrong_count));
  EXPECT_EQ(error_of([&] { read_u(count); }), prefix(count) + "field u: element 3 has 8 nodes, its data gives 4");

  const fs::path missing =
      write("missing.msh", mesh + ascii_element_node_data("u", 1, 0, {kElements[0], kElements[2]}));
  EXPECT_EQ(error_of([&] { read_u(missing); }), prefix(missing) + "field u has no value for element 3");

  const fs::path twice = write("twice.msh", mesh + good + ascii_element_node_data("u", 1, 0, {kElements[1]}));
  EXPECT_EQ(error_of([&] { read_u(twice); }), prefix(twice) + "field u: element tag 3 has two values");

  // Entries on elements that are not cells (a boundary triangle) are ignored, of any length.
  const fs::path other = write("other.msh", mesh + good + ascii_element_node_data("u", 1, 0, {{99, 2, {1, 2}}}));
  EXPECT_EQ(read_u(other).size(), 4u * 13u);

  const fs::path unknown = write("unknown.msh", mesh + good + ascii_element_node_data("v", 3, 0, kElements));
  MeshReadInfo info;
  EXPECT_EQ(error_of([&] { (void)tetia::read_mesh(unknown, &info, cell_node_fields({"w"})); }),
            prefix(unknown) + "no cell-node field named w (cell-node fields: u, v)");
  EXPECT_EQ(error_of([&] { (void)tetia::read_mesh(write("none.msh", mesh), &info, cell_node_fields({"u"})); }),
            prefix(path("none.msh")) + "no cell-node field named u (cell-node fields: none)");
  // Element data of that name is no element-node data.
  const fs::path element_data =
      write("element_data.msh", mesh + "$ElementData\n1\n\"u\"\n1\n0\n3\n0\n1\n3\n7 1\n3 2\n11 3\n$EndElementData\n");
  EXPECT_EQ(error_of([&] { read_u(element_data); }),
            prefix(element_data) + "no cell-node field named u (cell-node fields: none)");

  const fs::path steps = write("steps.msh", mesh + good + ascii_element_node_data("u", 1, 1, kElements));
  EXPECT_EQ(error_of([&] { read_u(steps); }), prefix(steps) + "field u has 2 time steps (0, 1); choose one (--step)");
  EXPECT_EQ(read_u(steps, 0), read_u(write("step0.msh", mesh + good)));
  EXPECT_EQ(error_of([&] { read_u(steps, 2); }), prefix(steps) + "field u has no time step 2 (steps: 0, 1)");
  EXPECT_EQ(tetia::msh_fields(steps).at(0).steps, (std::vector<std::int64_t>{0, 1}));

  // The parser's errors: the line, the field, the element.
  const auto line_of = [&](const std::string& text, std::string_view what) {
    const std::size_t at = text.find(what);
    return "line " + std::to_string(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n') + 1);
  };
  std::string text = mesh + good;
  const std::string short_line = text.replace(text.find(" 708\n"), 5, "\n");
  const fs::path short_file = write("short.msh", short_line);
  EXPECT_EQ(error_of([&] { read_u(short_file); }),
            prefix(short_file) + line_of(short_line, "7 8 701") +
                ": field u: element 7: 8 nodes of 1 component need 8 values, the line gives 7");
  text = mesh + good;
  const std::string long_line = text.replace(text.find(" 708\n"), 5, " 708 709 710\n");
  const fs::path long_file = write("long.msh", long_line);
  EXPECT_EQ(error_of([&] { read_u(long_file); }),
            prefix(long_file) + line_of(long_line, "7 8 701") +
                ": field u: element 7: 8 nodes of 1 component need 8 values, the line gives 10");
  text = mesh + good;
  const std::string with_nan = text.replace(text.find(" 703 "), 5, " nan ");
  const fs::path nan_file = write("nan.msh", with_nan);
  EXPECT_EQ(error_of([&] { read_u(nan_file); }),
            prefix(nan_file) + line_of(with_nan, "7 8 701") + ": field u: the value at element 7: \"nan\" is not finite");
  text = mesh + good;
  const std::string zero = text.replace(text.find("7 8 701"), 3, "7 0");
  const fs::path zero_file = write("zero.msh", zero);
  EXPECT_EQ(error_of([&] { read_u(zero_file); }),
            prefix(zero_file) + line_of(zero, "7 0 701") + ": field u: element 7: 0 nodes (an element has at least 1)");
  text = mesh + good;
  const std::size_t entry = text.find("7 8 701");
  const std::string lone_tag = text.replace(entry, text.find('\n', entry) - entry, "7");
  const fs::path lone = write("lone.msh", lone_tag);
  const auto lone_line = std::count(lone_tag.begin(), lone_tag.begin() + static_cast<std::ptrdiff_t>(entry), '\n') + 1;
  EXPECT_EQ(error_of([&] { read_u(lone); }), prefix(lone) + "line " + std::to_string(lone_line) +
                                                 ": a data line needs the tag, the number of nodes and the values");

  // Fields need a MeshReadInfo to come back in.
  EXPECT_THROW((void)tetia::read_mesh(count, nullptr, cell_node_fields({"u"})), std::invalid_argument);
}

// Whatever the bytes of the data section, reading gives a mesh and the field or throws
// std::runtime_error naming the file: every prefix of the literal files (ASCII 4.1, binary 2.2
// and 4.1), and mutants of their data sections (bytes overwritten, a fixed seed).
TEST_F(ElementNodeDataTest, EveryPrefixAndMutantReadsOrThrows) {
  std::vector<std::size_t> entry_at;
  const std::string files[] = {ascii41_mesh(kElements) + ascii_element_node_data("u", 1, 0, kElements),
                               binary_file(false, entry_at), binary_file(true, entry_at)};
  const fs::path file = path("prefix.msh");
  const auto read_or_throw = [&](std::string_view bytes, const std::string& what) {
    write_bytes(file, bytes);
    MeshReadInfo info;
    try {
      (void)tetia::read_mesh(file, &info, cell_node_fields({"u"}));
      EXPECT_EQ(info.fields.at(0).values.size(), 4u * 13u) << what;
      return true;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string_view(e.what()).rfind(prefix(file), 0), 0u) << what << ": " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": " << typeid(e).name() << ": " << e.what();
    }
    return false;
  };
  std::mt19937_64 rng(20240611);
  for (std::size_t f = 0; f < std::size(files); ++f) {
    const std::string& bytes = files[f];
    const std::size_t data_at = bytes.find("$ElementNodeData");
    ASSERT_NE(data_at, std::string::npos);
    // (Up to the last newline: without it the file is complete.)
    for (std::size_t n = data_at; n + 1 < bytes.size(); ++n)
      EXPECT_FALSE(read_or_throw(std::string_view(bytes).substr(0, n), "prefix " + std::to_string(n)));
    EXPECT_TRUE(read_or_throw(bytes, "whole file"));
    for (int m = 0; m < 1500; ++m) {
      std::string mutant = bytes;
      const int changes = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < changes; ++k) {
        const std::size_t at = data_at + rng() % (bytes.size() - data_at);
        const char pool[] = "0123456789 -+.e\nnan\x7f\xff";
        mutant[at] = rng() % 2 == 0 ? pool[rng() % (sizeof pool - 1)] : static_cast<char>(rng());
      }
      read_or_throw(mutant, "file " + std::to_string(f) + " mutant " + std::to_string(m));
    }
  }
}

// A file with element-node data reads as before where it is not asked for.
TEST_F(ElementNodeDataTest, MeshAloneAndOtherFieldsReadAsBefore) {
  const fs::path file = write("mixed.msh", ascii41_mesh(kElements) + ascii_element_node_data("u", 1, 0, kElements) +
                                               "$ElementData\n1\n\"p\"\n1\n0\n3\n0\n1\n3\n7 1\n3 2\n11 3\n$EndElementData\n");
  MeshReadInfo info;
  const TetMesh m = tetia::read_mesh(file, &info);
  EXPECT_EQ(m.num_cells(), 13u);
  EXPECT_EQ(info.cell_node_fields, std::vector<std::string>{"u"});
  EXPECT_EQ(info.cell_fields, std::vector<std::string>{"p"});
  EXPECT_TRUE(info.node_fields.empty());
  MeshReadOptions options;
  options.fields = {"p"};
  (void)tetia::read_mesh(file, &info, options);
  EXPECT_EQ(info.fields[0].values.size(), 13u);
  EXPECT_EQ(tetia::read_msh_field(file, "p", true).size(), 13u);
}

TEST_F(ElementNodeDataTest, WriteErrors) {
  const TetMesh m = tetia::make_kuhn_mesh({1, 1, 1}, {0, 0, 0}, {1, 1, 1});
  const fs::path file = path("out.msh");
  EXPECT_EQ(error_of([&] { tetia::write_msh(file, m, {}, {}, {{"u", std::vector<double>(6 * 3)}}); }),
            prefix(file) + "field u has 18 values, expected 24");
  EXPECT_EQ(error_of([&] { tetia::write_msh(file, m, {}, {}, {{"u", std::vector<double>(24 * 2), 3}}); }),
            prefix(file) + "field u has 48 values, expected 72");
  EXPECT_FALSE(fs::exists(file));
  // Split file cells: the simplices are not the file's cells.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  const std::vector<std::int64_t> hex = {0, 1, 2, 3, 4, 5, 6, 7};
  const tetia::CellBlock block{5, hex};
  const TetMesh split = tetia::make_tet_mesh(xyz, {&block, 1}, "hex");
  ASSERT_FALSE(split.cell_origin.empty());
  const std::string message = error_of<std::invalid_argument>(
      [&] { tetia::write_msh(file, split, {}, {}, {{"u", std::vector<double>(4 * split.num_cells())}}); });
  EXPECT_EQ(message.rfind(prefix(file) + "element-node data needs a simplicial mesh", 0), 0u) << message;
  EXPECT_FALSE(fs::exists(file));
  tetia::write_msh(file, split);  // without element-node data it is written as before
  EXPECT_EQ(tetia::read_mesh(file).num_file_cells(), 1u);

  const TriMesh t = tetia::make_structured_tri_mesh({1, 1}, {0, 0}, {1, 1});
  EXPECT_EQ(error_of([&] { tetia::write_msh(file, t, {}, {}, {{"u", std::vector<double>(5)}}); }),
            prefix(file) + "field u has 5 values, expected 6");
}

}  // namespace
