// test_cell_types.cpp -- .msh files with hexahedra, prisms, pyramids (3D) and quadrilaterals
// (2D), read as simplices that conform across shared faces (src/mesh/split_cells.hpp): the
// mesh's volume is the cells' exactly, every interior face is matched (no hanging triangle), the
// file cells' tags and types are kept, element data reach every simplex of their cell, and the
// supermesh against a tetrahedral mesh of the same box totals the box (issue 16, part 3).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_dir.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/supermesh.hpp"

namespace {

namespace fs = std::filesystem;

class CellTypes : public tetia::testsupport::TempDirTest {
 protected:
  CellTypes() : TempDirTest("cell_types") {}
};

// An n x n x n grid of unit cubes as a .msh 2.2 file: node (i, j, k) has tag 1 + i + (n+1) j +
// (n+1)^2 k, scrambled by `perm` (a multiplier mod a prime above the node count, so that the
// smallest tag of a cell is not always its first corner). Cubes are hexahedra; with `mixed`,
// the columns with i + j odd are two prisms each instead (split along the diagonal from (i, j)
// to (i + 1, j + 1), the same in the whole column, as an extruded mesh has it: the prisms'
// triangles meet triangles, their quadrilaterals meet the hexahedra's).
std::string grid_msh(int n, bool mixed, bool with_data) {
  const int m = n + 1;
  const auto node = [&](int i, int j, int k) { return 1 + i + m * j + m * m * k; };
  const auto tag = [&](int v) { return 1 + (static_cast<long long>(v) * 7919) % 100003; };  // distinct for v < 100003
  // (std::ostringstream: g++ 12's -Wrestrict misreads chains of string concatenations.)
  std::ostringstream s, el, data;
  s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m * m * m << "\n";
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) s << tag(node(i, j, k)) << ' ' << i << ' ' << j << ' ' << k << '\n';
  s << "$EndNodes\n$Elements\n";
  int ne = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int c[8] = {node(i, j, k),     node(i + 1, j, k),     node(i + 1, j + 1, k),     node(i, j + 1, k),
                          node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
        if (mixed && (i + j) % 2 == 1) {
          // Two prisms: bottom triangles (0, 1, 2) and (0, 2, 3), counter-clockwise from above.
          for (const auto& p : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
            el << ++ne << " 6 2 1 1";
            for (const int v : {p[0], p[1], p[2], p[0] + 4, p[1] + 4, p[2] + 4}) el << ' ' << tag(c[v]);
            el << '\n';
            data << ne << ' ' << ne * 10 << '\n';
          }
        } else {
          el << ++ne << " 5 2 1 1";
          for (int v = 0; v < 8; ++v) el << ' ' << tag(c[v]);
          el << '\n';
          data << ne << ' ' << ne * 10 << '\n';
        }
      }
  s << ne << '\n' << el.str() << "$EndElements\n";
  if (with_data) s << "$ElementData\n1\n\"ten\"\n1\n0.0\n3\n0\n1\n" << ne << '\n' << data.str() << "$EndElementData\n";
  return s.str();
}

void write(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::size_t boundary_faces(const tetia::TetMesh& m) {
  std::size_t b = 0;
  for (const auto& nb : m.neighbors)
    for (const auto x : nb) b += x < 0;
  return b;
}

TEST_F(CellTypes, HexahedralGridIsConformingAndExact) {
  const fs::path p = path("hex.msh");
  write(p, grid_msh(3, false, true));
  tetia::MeshReadInfo info;
  const tetia::TetMesh m = tetia::read_mesh(p, &info);
  EXPECT_EQ(m.num_cells(), 27u * 6u);
  EXPECT_EQ(m.origin_tags.size(), 27u);
  EXPECT_EQ(m.cell_origin.size(), m.num_cells());
  EXPECT_TRUE(m.cell_tags.empty());
  for (const auto t : m.origin_types) EXPECT_EQ(t, 5);
  EXPECT_EQ(m.total_volume(), 27.0);
  EXPECT_EQ(m.reoriented_cells, 0u);
  EXPECT_EQ(m.flat_cells, 0u);
  EXPECT_EQ(boundary_faces(m), 6u * 9u * 2u);  // every interior triangle matched
  EXPECT_EQ(info.ignored_elements, 0u);
  // Element data of a hexahedron reach its six tetrahedra.
  const std::vector<double> v = tetia::read_msh_field(p, "ten", true);
  ASSERT_EQ(v.size(), m.num_cells());
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    EXPECT_EQ(v[c], 10.0 * double(m.origin_tags[static_cast<std::size_t>(m.cell_origin[c])]));
}

TEST_F(CellTypes, MixedHexahedraAndPrismsConform) {
  const fs::path p = path("mixed.msh");
  write(p, grid_msh(3, true, false));
  const tetia::TetMesh m = tetia::read_mesh(p);
  EXPECT_EQ(m.total_volume(), 27.0);
  EXPECT_EQ(m.reoriented_cells, 0u);
  EXPECT_EQ(boundary_faces(m), 6u * 9u * 2u);
  std::size_t prisms = 0;
  for (const auto t : m.origin_types) prisms += t == 6;
  EXPECT_EQ(prisms, 2u * 4u * 3u);
}

TEST_F(CellTypes, SupermeshAgainstTetrahedraTotalsTheBox) {
  const fs::path p = path("hex_sm.msh");
  write(p, grid_msh(3, true, false));
  const tetia::TetMesh hex = tetia::read_mesh(p);
  const tetia::TetMesh tet = tetia::make_kuhn_mesh({4, 5, 3}, {0, 0, 0}, {0.75, 0.6, 1.0});
  const tetia::Supermesh sm = tetia::supermesh(hex, tet);
  EXPECT_NEAR(sm.intersection_volume(), 27.0, 27.0 * 1e-13);
}

TEST_F(CellTypes, QuadrilateralsAsTriangles) {
  const fs::path p = path("quad.msh");
  // A 2 x 2 grid of unit squares, tags scrambled.
  std::ostringstream s;
  s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n";
  const int tags[9] = {17, 4, 9, 2, 30, 11, 6, 21, 13};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) s << tags[i + 3 * j] << ' ' << i << ' ' << j << " 0\n";
  s << "$EndNodes\n$Elements\n4\n";
  int e = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = i + 3 * j;
      s << ++e << " 3 2 1 1 " << tags[a] << ' ' << tags[a + 1] << ' ' << tags[a + 4] << ' ' << tags[a + 3] << '\n';
    }
  s << "$EndElements\n";
  write(p, s.str());
  const tetia::TriMesh m = tetia::read_tri_mesh(p);
  EXPECT_EQ(m.num_cells(), 8u);
  EXPECT_EQ(m.total_area(), 4.0);
  EXPECT_EQ(m.reoriented_cells, 0u);
  std::size_t boundary = 0;
  for (const auto& nb : m.neighbors)
    for (const auto x : nb) boundary += x < 0;
  EXPECT_EQ(boundary, 8u);
  EXPECT_EQ(m.origin_tags.size(), 4u);
}

}  // namespace
