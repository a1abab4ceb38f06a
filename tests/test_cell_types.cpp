// test_cell_types.cpp -- .msh files with hexahedra, prisms, pyramids (3D) and quadrilaterals
// (2D), read as simplices that conform across shared faces (src/mesh/split_cells.hpp): the
// mesh's volume is the cells' exactly, every interior face is matched (no hanging triangle), the
// file cells' tags and types are kept, element data reach every simplex of their cell, and the
// supermesh against a tetrahedral mesh of the same box totals the box (issue 16, part 3).
#include <gtest/gtest.h>
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cell_grids.hpp"
#include "support/error_of.hpp"
#include "support/gmsh_write.hpp"
#include "support/temp_dir.hpp"
#include "support/vtu_check.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace {

namespace fs = std::filesystem;

class CellTypes : public tetia::testsupport::TempDirTest {
 protected:
  CellTypes() : TempDirTest("cell_types") {}
};

using tetia::testsupport::error_of;
using tetia::testsupport::grid_msh;

void write(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

// The area of the faces without a neighbour: a conforming mesh's boundary surface (a face two
// cells share but split differently would count twice).
double boundary_area(const tetia::TetMesh& m) {
  double area = 0.0;
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    for (int k = 0; k < 4; ++k) {
      if (m.neighbors[c][k] >= 0) continue;
      const tetia::Tet t = m.cell(c);
      const tetia::Vec3 n = cross(t[(k + 2) % 4] - t[(k + 1) % 4], t[(k + 3) % 4] - t[(k + 1) % 4]);
      area += 0.5 * std::sqrt(dot(n, n));
    }
  return area;
}

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

// The supermesh per pair of file cells (file_cell_pairs) and P0 per file cell: each target
// hexahedron's or prism's pairs total its volume, every piece lies in exactly one pair and the
// pairs sum their pieces, a constant is reproduced per file cell and the integral is conserved;
// a mesh against itself pairs each file cell with itself only, and P0 gives back its values.
TEST_F(CellTypes, ResultsPerFileCell) {
  const fs::path p = path("mixed_pairs.msh");
  write(p, grid_msh(3, true, true));
  const tetia::TetMesh hex = tetia::read_mesh(p);
  const tetia::TetMesh tet = tetia::make_kuhn_mesh({4, 5, 3}, {0, 0, 0}, {0.75, 0.6, 1.0});
  const std::vector<double> measure = tetia::file_cell_measures(hex);
  ASSERT_EQ(measure.size(), 15u + 24u);
  for (std::size_t f = 0; f < measure.size(); ++f) EXPECT_EQ(measure[f], hex.origin_types[f] == 5 ? 1.0 : 0.5) << f;

  const tetia::Supermesh sm = tetia::supermesh(tet, hex);
  const tetia::FileCellPairs fp = tetia::file_cell_pairs(sm);
  ASSERT_EQ(fp.piece_pair.size(), sm.pieces.size());
  EXPECT_LT(fp.pairs.size(), sm.pieces.size());
  std::vector<double> covered(measure.size(), 0.0), from_pieces(fp.pairs.size(), 0.0);
  for (std::size_t i = 0; i < fp.pairs.size(); ++i) {
    const auto& q = fp.pairs[i];
    covered[static_cast<std::size_t>(q.target)] += q.volume;
    if (i > 0) {
      const auto& r = fp.pairs[i - 1];
      EXPECT_TRUE(r.target < q.target || (r.target == q.target && r.source < q.source)) << i;
    }
  }
  for (std::size_t k = 0; k < sm.pieces.size(); ++k) {
    const auto i = static_cast<std::size_t>(fp.piece_pair[k]);
    ASSERT_LT(i, fp.pairs.size());
    EXPECT_EQ(fp.pairs[i].source, sm.pieces[k].source);  // the source is not split
    EXPECT_EQ(static_cast<std::size_t>(fp.pairs[i].target), hex.file_cell(static_cast<std::size_t>(sm.pieces[k].target)));
    from_pieces[i] += sm.pieces[k].volume;
  }
  for (std::size_t i = 0; i < fp.pairs.size(); ++i) EXPECT_NEAR(from_pieces[i], fp.pairs[i].volume, 1e-15) << i;
  for (std::size_t f = 0; f < measure.size(); ++f) EXPECT_NEAR(covered[f], measure[f], 1e-13 * measure[f]) << f;

  // P0 per file cell: a constant, and the integral of a linear field.
  const auto per_file_cell = [&](const std::vector<double>& simplex_values) {
    return tetia::file_cell_average(hex, simplex_values);
  };
  const std::vector<double> three = per_file_cell(tetia::remap_p0(sm, std::vector<double>(tet.num_cells(), 3.0)));
  ASSERT_EQ(three.size(), measure.size());
  for (std::size_t f = 0; f < three.size(); ++f) EXPECT_NEAR(three[f], 3.0, 3e-13) << f;
  const std::vector<double> u = tetia::average_over_cells(tet, [](tetia::Vec3 x) { return x.x + 2 * x.y - x.z; });
  const std::vector<double> v = per_file_cell(tetia::remap_p0(sm, u));
  double source_integral = 0.0, target_integral = 0.0;
  for (std::size_t c = 0; c < u.size(); ++c) source_integral += u[c] * tet.volumes[c];
  for (std::size_t f = 0; f < v.size(); ++f) target_integral += v[f] * measure[f];
  EXPECT_NEAR(target_integral, source_integral, 1e-13 * std::abs(source_integral));
  EXPECT_EQ(tetia::spread_to_simplices(hex, v).size(), hex.num_cells());

  // The mesh against itself: each file cell with itself, and its values back.
  const tetia::Supermesh self = tetia::supermesh(hex, hex);
  const tetia::FileCellPairs sp = tetia::file_cell_pairs(self);
  ASSERT_EQ(sp.pairs.size(), measure.size());
  for (std::size_t f = 0; f < measure.size(); ++f) {
    EXPECT_EQ(static_cast<std::size_t>(sp.pairs[f].source), f);
    EXPECT_EQ(static_cast<std::size_t>(sp.pairs[f].target), f);
    EXPECT_NEAR(sp.pairs[f].volume, measure[f], 1e-15);
  }
  const std::vector<double> ten = tetia::read_msh_field(p, "ten", true);
  const std::vector<double> back = tetia::file_cell_average(hex, tetia::remap_p0(self, ten));
  for (std::size_t f = 0; f < back.size(); ++f)
    EXPECT_NEAR(back[f], 10.0 * double(hex.origin_tags[f]), 1e-12 * 10.0 * double(hex.origin_tags[f])) << f;
  // Sizes are checked.
  EXPECT_THROW((void)tetia::file_cell_average(hex, std::vector<double>(3)), std::invalid_argument);
  EXPECT_THROW((void)tetia::spread_to_simplices(hex, std::vector<double>(hex.num_cells())), std::invalid_argument);
}

// VTU and .msh output of a mesh with split cells: the file's cells, with their tags and types;
// VTK computes each one's volume from the node order written as positive and equal to the
// cell's (the wedge's order differs from Gmsh's). With VtuOptions::simplices, the simplices.
TEST_F(CellTypes, OutputsWriteTheFileCells) {
  const fs::path src = fs::path(__FILE__).parent_path().parent_path() / "fuzz" / "corpus" / "fuzz_msh_reader" /
                       "hex_prism_pyramid_22.msh";
  const tetia::TetMesh m = tetia::read_mesh(src);
  ASSERT_EQ(m.num_file_cells(), 4u);
  const std::vector<double> measure = tetia::file_cell_measures(m);
  EXPECT_EQ(measure, (std::vector<double>{1.0, 0.5, 0.5, 1.0 / 3.0}));
  const std::vector<double> p = tetia::file_cell_average(m, tetia::read_msh_field(src, "p", true));
  EXPECT_EQ(p, (std::vector<double>{1.5, 2.5, 3.5, 4.5}));
  for (const auto format : {tetia::VtuFormat::binary, tetia::VtuFormat::ascii}) {
    tetia::VtuOptions options;
    options.format = format;
    const fs::path file = path(format == tetia::VtuFormat::binary ? "cells.vtu" : "cells_ascii.vtu");
    tetia::write_vtu(file, m, {{"p", p}}, {}, options);
    const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(file);
    ASSERT_TRUE(v.ok) << v.error;
    EXPECT_EQ(v.cell_types, (std::vector<int>{12, 13, 13, 14}));
    ASSERT_NE(v.cell_array("cell_id"), nullptr);
    EXPECT_EQ(v.cell_array("cell_id")->values, (std::vector<double>{1, 2, 3, 4}));
    ASSERT_NE(v.cell_array("p"), nullptr);
    EXPECT_EQ(v.cell_array("p")->values, p);
    ASSERT_NE(v.cell_array("vtk:measure"), nullptr);
    const auto& vol = v.cell_array("vtk:measure")->values;
    ASSERT_EQ(vol.size(), 4u);
    for (std::size_t f = 0; f < 4; ++f) EXPECT_NEAR(vol[f], measure[f], 1e-12) << "cell " << f << " type " << v.cell_types[f];
  }
  tetia::VtuOptions simplices;
  simplices.simplices = true;
  const fs::path split = path("simplices.vtu");
  tetia::write_vtu(split, m, {{"q", std::vector<double>(m.num_cells(), 1.0)}}, {}, simplices);
  const tetia::testvtu::VtkView vs = tetia::testvtu::read_with_vtk(split);
  ASSERT_TRUE(vs.ok) << vs.error;
  EXPECT_EQ(vs.cells.size(), m.num_cells());
  for (const int t : vs.cell_types) EXPECT_EQ(t, 10);
  // Cell data per simplex for file cells (or the other way round) is refused, and so are file
  // cells without their nodes (a mesh built by hand), for both writers.
  EXPECT_THROW(tetia::write_vtu(path("bad.vtu"), m, {{"q", std::vector<double>(m.num_cells(), 1.0)}}), std::runtime_error);
  tetia::TetMesh no_nodes = m;
  no_nodes.origin_nodes.pop_back();
  EXPECT_NE(error_of([&] { tetia::write_vtu(path("bad.vtu"), no_nodes); }).find("file cell nodes: 24, expected 25"),
            std::string::npos);
  EXPECT_NE(error_of([&] { tetia::write_msh(path("bad.msh"), no_nodes); }).find("file cell nodes"), std::string::npos);

  // .msh: the file cells again, with their tags, read back to the same mesh.
  const fs::path again = path("again.msh");
  tetia::write_msh(again, m, {{"p", p}});
  const tetia::TetMesh r = tetia::read_mesh(again);
  EXPECT_EQ(r.origin_tags, m.origin_tags);
  EXPECT_EQ(r.origin_types, m.origin_types);
  EXPECT_EQ(r.node_tags, m.node_tags);
  EXPECT_EQ(r.origin_nodes, m.origin_nodes);
  EXPECT_EQ(r.cells, m.cells);
  EXPECT_EQ(tetia::file_cell_average(r, tetia::read_msh_field(again, "p", true)), p);
}

// Files Gmsh itself writes, in 2.2 and 4.1, ASCII and binary: two rectangles side by side, the
// first meshed with quadrilaterals (recombined) and the second with triangles, extruded in
// three recombined layers: hexahedra next to prisms, sharing quadrilateral faces. Read as
// conforming meshes (the boundary is the box's surface, every interior triangle matched) whose
// volume is the box's; the supermesh against a Kuhn mesh totals it, a constant is reproduced
// per file cell, and the VTU written has every cell positive in VTK's own eyes. The 2D variant:
// the rectangles alone, quadrilaterals and triangles.
TEST_F(CellTypes, GmshRecombinedAndExtrudedMeshes) {
  const auto generate = [&](int dim, double version, bool binary, int order = 1, bool incomplete = false) {
    tetia::testsupport::GmshScope scope;
    namespace occ = gmsh::model::occ;
    gmsh::model::add("recombined");
    const int quads = occ::addRectangle(0, 0, 0, 1, 2);
    const int triangles = occ::addRectangle(1, 0, 0, 1.5, 2);
    std::vector<std::pair<int, int>> out;
    std::vector<std::vector<std::pair<int, int>>> map;
    occ::fragment({{2, quads}}, {{2, triangles}}, out, map);
    if (dim == 3) {
      std::vector<std::pair<int, int>> extruded;
      occ::extrude({{2, quads}, {2, triangles}}, 0, 0, 0.9, extruded, {3}, {}, true);
    }
    occ::synchronize();
    gmsh::model::mesh::setRecombine(2, quads);
    gmsh::option::setNumber("Mesh.MeshSizeMax", 0.35);
    gmsh::model::mesh::generate(dim);
    if (order > 1) {
      gmsh::option::setNumber("Mesh.SecondOrderIncomplete", incomplete ? 1 : 0);
      gmsh::model::mesh::setOrder(order);
      gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 0);
    }
    gmsh::option::setNumber("Mesh.MshFileVersion", version);
    gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
    std::ostringstream name;
    name << "gmsh_" << dim << "d_" << version << (binary ? "_bin" : "_ascii") << "_order" << order
         << (incomplete ? "i" : "") << ".msh";
    const fs::path file = path(name.str());
    gmsh::write(file.string());
    return file;
  };
  for (const double version : {2.2, 4.1})
    for (const bool binary : {false, true}) {
      SCOPED_TRACE(testing::Message() << "version " << version << (binary ? " binary" : " ASCII"));
      const fs::path file3 = generate(3, version, binary);
      const tetia::TetMesh m = tetia::read_mesh(file3);
      std::size_t hexahedra = 0, prisms = 0;
      for (const auto t : m.origin_types) hexahedra += t == 5, prisms += t == 6;
      EXPECT_GT(hexahedra, 10u);
      EXPECT_GT(prisms, 10u);
      EXPECT_EQ(hexahedra + prisms, m.num_file_cells());
      EXPECT_EQ(m.reoriented_cells, 0u);
      EXPECT_NEAR(m.total_volume(), 2.5 * 2 * 0.9, 1e-13);
      EXPECT_NEAR(boundary_area(m), 2 * (2.5 * 2 + 2.5 * 0.9 + 2 * 0.9), 1e-12);
      const tetia::TetMesh kuhn = tetia::make_kuhn_mesh({5, 4, 3}, {0, 0, 0}, {0.5, 0.5, 0.3});
      const tetia::Supermesh sm = tetia::supermesh(kuhn, m);
      EXPECT_NEAR(sm.intersection_volume(), 4.5, 4.5e-13);
      const std::vector<double> one = tetia::file_cell_average(m, tetia::remap_p0(sm, std::vector<double>(kuhn.num_cells(), 1.0)));
      for (std::size_t f = 0; f < one.size(); ++f) EXPECT_NEAR(one[f], 1.0, 1e-12) << f;
      const fs::path vtu = path("gmsh_cells.vtu");
      tetia::write_vtu(vtu, m, {{"one", one}});
      const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
      ASSERT_TRUE(v.ok) << v.error;
      ASSERT_EQ(v.cells.size(), m.num_file_cells());
      const std::vector<double> measure = tetia::file_cell_measures(m);
      for (std::size_t f = 0; f < measure.size(); ++f)
        EXPECT_NEAR(v.cell_array("vtk:measure")->values[f], measure[f], 1e-12 * measure[f] + 1e-15) << f;

      const tetia::TriMesh q = tetia::read_tri_mesh(generate(2, version, binary));
      std::size_t quadrilaterals = 0;
      for (const auto t : q.origin_types) quadrilaterals += t == 3;
      EXPECT_GT(quadrilaterals, 10u);
      EXPECT_LT(quadrilaterals, q.num_file_cells());
      EXPECT_NEAR(q.total_area(), 5.0, 1e-13);
      std::size_t unmatched = 0;
      for (const auto& nb : q.neighbors)
        for (const auto x : nb) unmatched += x < 0;
      double perimeter = 0.0;
      for (std::size_t c = 0; c < q.num_cells(); ++c)
        for (int k = 0; k < 3; ++k)
          if (q.neighbors[c][k] < 0) {
            const tetia::Triangle t = q.cell(c);
            const tetia::Vec2 e = t[(k + 2) % 3] - t[(k + 1) % 3];
            perimeter += std::sqrt(e.x * e.x + e.y * e.y);
          }
      EXPECT_NEAR(perimeter, 9.0, 1e-12) << unmatched << " boundary edges";

      // Second order (hexahedra of 27 or 20 nodes, prisms of 18 or 15, quadrilaterals of 9 or
      // 8): refused, or with corner_nodes read by their corners as the same straight cells.
      for (const bool incomplete : {false, true}) {
        SCOPED_TRACE(incomplete ? "incomplete second order" : "complete second order");
        const fs::path file2 = generate(3, version, binary, 2, incomplete);
        EXPECT_NE(error_of([&] { (void)tetia::read_mesh(file2); }).find("higher-order cells are not supported"),
                  std::string::npos);
        tetia::MeshReadOptions corners;
        corners.corner_nodes = true;
        tetia::MeshReadInfo info;
        const tetia::TetMesh m2 = tetia::read_mesh(file2, &info, corners);
        EXPECT_EQ(info.straightened_cells, m.num_file_cells());
        EXPECT_EQ(m2.origin_types, m.origin_types);
        EXPECT_EQ(m2.num_cells(), m.num_cells());
        EXPECT_NEAR(m2.total_volume(), 4.5, 1e-13);
        const tetia::TriMesh q2 = tetia::read_tri_mesh(generate(2, version, binary, 2, incomplete), nullptr, corners);
        EXPECT_EQ(q2.origin_types, q.origin_types);
        EXPECT_NEAR(q2.total_area(), 5.0, 1e-13);
      }
    }
}

// A hybrid mesh as Gmsh makes it: hexahedra (a recombined square extruded in layers) under
// tetrahedra (an unstructured extrusion), with the pyramids Gmsh inserts between the hexahedra's
// quadrilaterals and the tetrahedra; in 2.2 and 4.1, ASCII and binary. Read conforming (the
// boundary is the box's surface), of exact volume, and written as VTK hexahedra, pyramids and
// tetrahedra of the right volumes.
TEST_F(CellTypes, GmshHybridMeshWithPyramids) {
  for (const double version : {2.2, 4.1})
    for (const bool binary : {false, true}) {
      SCOPED_TRACE(testing::Message() << "version " << version << (binary ? " binary" : " ASCII"));
      const fs::path file = path(std::string("hybrid_") + (version < 3 ? "22" : "41") + (binary ? "_bin" : "") + ".msh");
      {
        tetia::testsupport::GmshScope scope;
        namespace geo = gmsh::model::geo;
        gmsh::model::add("hybrid");
        const int p1 = geo::addPoint(0, 0, 0, 0.3), p2 = geo::addPoint(1, 0, 0, 0.3), p3 = geo::addPoint(1, 1, 0, 0.3),
                  p4 = geo::addPoint(0, 1, 0, 0.3);
        const int loop = geo::addCurveLoop({geo::addLine(p1, p2), geo::addLine(p2, p3), geo::addLine(p3, p4), geo::addLine(p4, p1)});
        const int square = geo::addPlaneSurface({loop});
        std::vector<std::pair<int, int>> layers, above;
        geo::extrude({{2, square}}, 0, 0, 1, layers, {3}, {}, true);  // layers[0]: the top surface
        geo::extrude({layers[0]}, 0, 0, 1, above);                        // meshed with tetrahedra
        geo::synchronize();
        gmsh::model::mesh::setRecombine(2, square);
        gmsh::model::mesh::generate(3);
        gmsh::option::setNumber("Mesh.MshFileVersion", version);
        gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
        gmsh::write(file.string());
      }
      const tetia::TetMesh m = tetia::read_mesh(file);
      std::size_t count[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (const auto t : m.origin_types) ++count[t];
      EXPECT_GT(count[5], 10u);  // hexahedra
      EXPECT_GT(count[7], 4u);   // pyramids
      EXPECT_GT(count[4], 100u);  // tetrahedra
      EXPECT_EQ(m.reoriented_cells, 0u);
      EXPECT_NEAR(m.total_volume(), 2.0, 1e-13);
      EXPECT_NEAR(boundary_area(m), 10.0, 1e-12);
      const tetia::Supermesh sm = tetia::supermesh(tetia::make_kuhn_mesh({3, 3, 5}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 0.4}), m);
      EXPECT_NEAR(sm.intersection_volume(), 2.0, 2e-13);
      const fs::path vtu = path("hybrid.vtu");
      tetia::write_vtu(vtu, m);
      const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
      ASSERT_TRUE(v.ok) << v.error;
      const std::vector<double> measure = tetia::file_cell_measures(m);
      ASSERT_EQ(v.cells.size(), measure.size());
      for (std::size_t f = 0; f < measure.size(); ++f)
        EXPECT_NEAR(v.cell_array("vtk:measure")->values[f], measure[f], 1e-12 * measure[f]) << f;
    }
}

// Collapsed cells as generators write them: a hexahedron with two nodes twice (a prism) next to
// a cube, sharing its face x = 1, and one with its top face in one node (a pyramid) on the
// cube's top; in 2D a quadrilateral with a node twice (a triangle). Read as conforming meshes:
// volume 1 + 1/2 + 1/3, and a boundary that is exactly the union's surface (every shared face
// matched), each collapsed cell one file cell.
TEST_F(CellTypes, CollapsedCellsAreReadByTheirVolume) {
  const fs::path p = path("collapsed.msh");
  write(p,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n11\n"
        "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n9 2 0 0\n10 2 0 1\n11 0.5 0.5 2\n"
        "$EndNodes\n$Elements\n3\n"
        "1 5 2 1 1 1 2 3 4 5 6 7 8\n"
        "2 5 2 1 1 2 9 3 3 6 10 7 7\n"
        "3 5 2 1 1 5 6 7 8 11 11 11 11\n"
        "$EndElements\n");
  const tetia::TetMesh m = tetia::read_mesh(p);
  EXPECT_EQ(m.num_file_cells(), 3u);
  EXPECT_EQ(m.reoriented_cells, 0u);
  EXPECT_EQ(m.flat_cells, 0u);
  const std::vector<double> measure = tetia::file_cell_measures(m);
  EXPECT_EQ(measure[0], 1.0);
  EXPECT_EQ(measure[1], 0.5);
  EXPECT_NEAR(measure[2], 1.0 / 3.0, 1e-16);
  EXPECT_NEAR(boundary_area(m), 6.0 + std::sqrt(2.0) + 2.0 * std::sqrt(1.25), 1e-13);
  const tetia::Supermesh sm = tetia::supermesh(m, tetia::make_kuhn_mesh({4, 2, 4}, {0, 0, 0}, {0.5, 0.5, 0.5}));
  EXPECT_NEAR(sm.intersection_volume(), 1.0 + 0.5 + 1.0 / 3.0, 1e-14);
  // Written as the file's (degenerate) hexahedra, which VTK measures right.
  const fs::path vtu = path("collapsed.vtu");
  tetia::write_vtu(vtu, m);
  const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
  ASSERT_TRUE(v.ok) << v.error;
  EXPECT_EQ(v.cell_types, (std::vector<int>{12, 12, 12}));
  for (std::size_t f = 0; f < 3; ++f) EXPECT_NEAR(v.cell_array("vtk:measure")->values[f], measure[f], 1e-15) << f;

  const fs::path q = path("collapsed_quad.msh");
  write(q,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n$EndNodes\n"
        "$Elements\n2\n1 3 2 1 1 1 2 3 4\n2 3 2 1 1 2 5 3 3\n$EndElements\n");
  const tetia::TriMesh t = tetia::read_tri_mesh(q);
  EXPECT_EQ(t.num_cells(), 3u);
  EXPECT_EQ(tetia::file_cell_measures(t), (std::vector<double>{1.0, 0.5}));
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
  // Written as quadrilaterals (VTK type 9) of positive area, and as .msh quadrilaterals.
  const fs::path vtu = path("quad.vtu");
  tetia::write_vtu(vtu, m, {{"one", std::vector<double>(4, 1.0)}});
  const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
  ASSERT_TRUE(v.ok) << v.error;
  EXPECT_EQ(v.cell_types, (std::vector<int>(4, 9)));
  ASSERT_NE(v.cell_array("vtk:measure"), nullptr);
  for (const double a : v.cell_array("vtk:measure")->values) EXPECT_NEAR(a, 1.0, 1e-14);
  EXPECT_EQ(v.cell_array("cell_id")->values, (std::vector<double>{1, 2, 3, 4}));
  const fs::path again = path("quad_again.msh");
  tetia::write_msh(again, m);
  const tetia::TriMesh r = tetia::read_tri_mesh(again);
  EXPECT_EQ(r.origin_nodes, m.origin_nodes);
  EXPECT_EQ(r.cells, m.cells);
  EXPECT_EQ(tetia::file_cell_measures(r), (std::vector<double>(4, 1.0)));
}

}  // namespace
