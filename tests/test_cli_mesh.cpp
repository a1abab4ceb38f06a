// tests/test_cli_mesh.cpp -- `tetia supermesh`, `tetia remap` and `tetia demo` end to end: the
// executable named by TETIA_CLI_PATH on meshes written here (Kuhn meshes and structured triangle
// meshes through write_msh) and, where ../shared is present, on the libsupermesh test meshes.
// 3D first, then 2D (the dimension detected from the files, mixed dimensions refused).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <sstream>
#include <string>

#include "support/cell_grids.hpp"
#include "support/cli.hpp"
#include "support/json_text.hpp"
#include "support/vtu_check.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace {

namespace fs = std::filesystem;

using tetia::testcli::Result;
using tetia::testjson::json_number;

// The JSON without its "seconds" (the one key that differs between runs).
std::string without_seconds(const std::string& json) {
  const auto at = json.find(", \"seconds\"");
  return at == std::string::npos ? json : json.substr(0, at);
}

class CliMeshTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "tetia_cli_mesh_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
    ASSERT_TRUE(fs::exists(TETIA_CLI_PATH)) << "CLI not built: " << TETIA_CLI_PATH;
    // Two non-matching meshes of the unit cube: 3x3x3 and 4x4x4 Kuhn cubes, the second with a
    // P0 field "rho" = 2 and a P1 field "phi" = x.
    a_ = (dir_ / "a.msh").string();
    b_ = (dir_ / "b.msh").string();
    const tetia::TetMesh a = tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
    const tetia::TetMesh b = tetia::make_kuhn_mesh({4, 4, 4}, {0, 0, 0}, {0.25, 0.25, 0.25});
    std::vector<double> rho(b.num_cells(), 2.0), phi(b.num_nodes());
    for (std::size_t n = 0; n < b.num_nodes(); ++n) phi[n] = b.nodes[n].x;
    tetia::write_msh(a_, a);
    tetia::write_msh(b_, b, {{"rho", rho}}, {{"phi", phi}});
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  Result run(const std::string& args) { return tetia::testcli::run(TETIA_CLI_PATH, args, dir_); }

  fs::path dir_;
  std::string a_, b_;
};

TEST_F(CliMeshTest, SupermeshPrintsTheSummary) {
  const Result r = run("supermesh " + a_ + " " + b_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json_number(r.out, "dimension"), 3);
  EXPECT_EQ(json_number(r.out, "source_cells"), 162);
  EXPECT_EQ(json_number(r.out, "target_cells"), 384);
  EXPECT_GT(json_number(r.out, "pairs"), 384);
  EXPECT_GE(json_number(r.out, "candidates"), json_number(r.out, "pairs"));
  EXPECT_NEAR(json_number(r.out, "intersection_volume"), 1.0, 1e-13);
  EXPECT_NEAR(json_number(r.out, "source_volume"), 1.0, 1e-13);
  EXPECT_GE(json_number(r.out, "seconds"), 0.0);
  const Result rt = run("supermesh --search rtree --threads 1 " + a_ + " " + b_);
  ASSERT_EQ(rt.status, 0) << rt.err;
  EXPECT_EQ(json_number(rt.out, "pairs"), json_number(r.out, "pairs"));
  EXPECT_EQ(json_number(rt.out, "intersection_volume"), json_number(r.out, "intersection_volume"));
}

// The supermesh VTU, binary and ASCII, as VTK reads it: tetrahedra only, Int64 piece, source
// and target (the files' tags), and simplex_volume summing to the intersection volume (a
// per-piece value repeated on each of its tetrahedra would not).
TEST_F(CliMeshTest, SupermeshWritesVtu) {
  for (const std::string flag : {"", " --ascii"}) {
    const std::string vtu = (dir_ / "s.vtu").string();
    const Result r = run("supermesh " + a_ + " " + b_ + " -o " + vtu + flag);
    ASSERT_EQ(r.status, 0) << r.err;
    const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
    ASSERT_TRUE(v.ok) << v.error;
    EXPECT_GT(v.cells.size(), json_number(r.out, "pairs") - 1);
    for (const int t : v.cell_types) EXPECT_EQ(t, 10);
    for (const char* name : {"piece", "source", "target"}) {
      ASSERT_NE(v.cell_array(name), nullptr) << name;
      EXPECT_EQ(v.cell_array(name)->type, "long_long") << name;
    }
    ASSERT_NE(v.cell_array("simplex_volume"), nullptr);
    double total = 0.0;
    for (const double x : v.cell_array("simplex_volume")->values) total += x;
    EXPECT_NEAR(total, json_number(r.out, "intersection_volume"), 1e-12);
    EXPECT_EQ(v.cell_array("piece")->values.back() + 1, json_number(r.out, "pairs"));
  }
}

// Hexahedra and prisms (a 3x3x3 box, 39 file cells, 162 tetrahedra) against a Kuhn mesh of the
// same box: every result is per cell of the files. The JSON counts file cells and their pairs
// (and the simplices apart), the supermesh VTU's piece ids are the pairs, P0 gives one value per
// hexahedron or prism and conserves the integral, the VTU has the file's cells, the P0 matrix
// has a row per file cell, and P1 onto the hexahedral mesh reproduces a linear field.
TEST_F(CliMeshTest, ResultsPerFileCellOfHexahedraAndPrisms) {
  const std::string hex = (dir_ / "hex.msh").string(), tet = (dir_ / "tet.msh").string();
  std::ofstream(hex) << tetia::testsupport::grid_msh(3, true, true);
  tetia::write_msh(tet, tetia::make_kuhn_mesh({4, 4, 4}, {0, 0, 0}, {0.75, 0.75, 0.75}));
  const std::string sm_vtu = (dir_ / "sm.vtu").string();
  const Result sm = run("supermesh " + hex + " " + tet + " -o " + sm_vtu);
  ASSERT_EQ(sm.status, 0) << sm.err;
  EXPECT_EQ(json_number(sm.out, "source_cells"), 39);
  EXPECT_EQ(json_number(sm.out, "source_simplices"), 162);
  EXPECT_EQ(json_number(sm.out, "target_cells"), 384);
  EXPECT_EQ(json_number(sm.out, "target_simplices"), 384);
  EXPECT_LT(json_number(sm.out, "pairs"), json_number(sm.out, "simplex_pairs"));
  EXPECT_NEAR(json_number(sm.out, "intersection_volume"), 27.0, 27e-13);
  {
    const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(sm_vtu);
    ASSERT_TRUE(v.ok) << v.error;
    ASSERT_NE(v.cell_array("piece"), nullptr);
    const auto& piece = v.cell_array("piece")->values;
    EXPECT_EQ(*std::max_element(piece.begin(), piece.end()) + 1, json_number(sm.out, "pairs"));
  }
  // P0 onto the hexahedra and prisms: one value per file cell.
  const std::string r_vtu = (dir_ / "r.vtu").string(), mtx = (dir_ / "m.mtx").string();
  const Result r = run("remap " + tet + " " + hex + " --order 0 --expr \"x+2*y-z\" -o " + r_vtu + " --matrix " + mtx);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json_number(r.out, "target_cells"), 39);
  EXPECT_LT(json_number(r.out, "conservation_error"), 1e-13);
  {
    const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(r_vtu);
    ASSERT_TRUE(v.ok) << v.error;
    ASSERT_EQ(v.cells.size(), 39u);
    int hexahedra = 0, wedges = 0;
    for (const int t : v.cell_types) hexahedra += t == 12, wedges += t == 13;
    EXPECT_EQ(hexahedra, 15);
    EXPECT_EQ(wedges, 24);
    ASSERT_NE(v.cell_array("field"), nullptr);
    ASSERT_NE(v.cell_array("exact"), nullptr);
    EXPECT_EQ(v.cell_array("field")->values.size(), 39u);
    double integral = 0.0;
    for (std::size_t f = 0; f < 39; ++f) integral += v.cell_array("field")->values[f] * v.cell_array("vtk:measure")->values[f];
    EXPECT_NEAR(integral, json_number(r.out, "target_integral"), 1e-12);
  }
  {
    std::ifstream in(mtx);
    std::string line;
    while (std::getline(in, line) && line[0] == '%') {
    }
    std::istringstream header(line);
    long rows = 0, cols = 0, entries = 0;
    header >> rows >> cols >> entries;
    EXPECT_EQ(rows, 39);
    EXPECT_EQ(cols, 384);
    EXPECT_EQ(entries, static_cast<long>(json_number(r.out, "pairs")));
  }
  // The same as .msh: the file's cells with their tags, the field per cell, read back alike.
  const std::string r_msh = (dir_ / "r.msh").string();
  const Result rm = run("remap " + tet + " " + hex + " --order 0 --expr \"x+2*y-z\" -o " + r_msh);
  ASSERT_EQ(rm.status, 0) << rm.err;
  {
    const tetia::TetMesh written = tetia::read_mesh(r_msh), original = tetia::read_mesh(hex);
    EXPECT_EQ(written.origin_tags, original.origin_tags);
    EXPECT_EQ(written.origin_types, original.origin_types);
    EXPECT_EQ(written.node_tags, original.node_tags);
    const std::vector<double> field = tetia::file_cell_average(written, tetia::read_msh_field(r_msh, "field", true));
    const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(r_vtu);
    ASSERT_TRUE(v.ok) << v.error;
    EXPECT_EQ(field, v.cell_array("field")->values);
  }
  const std::string sm_msh = (dir_ / "sm.msh").string();
  ASSERT_EQ(run("supermesh " + hex + " " + tet + " -o " + sm_msh).status, 0);
  {
    const tetia::TetMesh pieces = tetia::read_mesh(sm_msh);
    const std::vector<double> piece = tetia::read_msh_field(sm_msh, "piece", true);
    EXPECT_EQ(*std::max_element(piece.begin(), piece.end()) + 1, json_number(sm.out, "pairs"));
    const std::vector<double> volume = tetia::read_msh_field(sm_msh, "simplex_volume", true);
    double total = 0.0;
    for (const double x : volume) total += x;
    EXPECT_NEAR(total, 27.0, 27e-13);
    EXPECT_EQ(volume.size(), pieces.num_cells());
  }
  // P0 from the hexahedra's element data: conservative.
  const Result back = run("remap " + hex + " " + tet + " --order 0 --field ten");
  ASSERT_EQ(back.status, 0) << back.err;
  EXPECT_EQ(json_number(back.out, "source_cells"), 39);
  EXPECT_LT(json_number(back.out, "conservation_error"), 1e-13);
  // P1 onto the hexahedral mesh: a linear field reproduced.
  const Result p1 = run("remap " + tet + " " + hex + " --order 1 --expr \"x+2*y-z\" -o " + r_vtu);
  ASSERT_EQ(p1.status, 0) << p1.err;
  EXPECT_LT(json_number(p1.out, "relative_l2_error"), 1e-10);
  const tetia::testvtu::VtkView v1 = tetia::testvtu::read_with_vtk(r_vtu);
  ASSERT_TRUE(v1.ok) << v1.error;
  EXPECT_EQ(v1.cells.size(), 39u);
}

TEST_F(CliMeshTest, RemapP0OfAStoredFieldIsConservative) {
  const Result r = run("remap " + b_ + " " + a_ + " --field rho --order 0 -o " + (dir_ / "r.vtu").string() +
                       " --matrix " + (dir_ / "m.mtx").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(json_number(r.out, "source_integral"), 2.0, 1e-12);
  EXPECT_LE(json_number(r.out, "conservation_error"), 1e-13);
  EXPECT_NE(tetia::testcli::read_file(dir_ / "m.mtx").find("%%MatrixMarket matrix coordinate real general"), std::string::npos);
  EXPECT_NE(tetia::testcli::read_file(dir_ / "r.vtu").find("Name=\"rho\""), std::string::npos);
}

TEST_F(CliMeshTest, RemapP1ReproducesALinearExpression) {
  const Result r = run("remap " + a_ + " " + b_ + " --expr \"x + 2*y - z\" --order 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LE(json_number(r.out, "relative_l2_error"), 1e-10);
  EXPECT_LE(json_number(r.out, "conservation_error"), 1e-12);
  const Result f = run("remap " + b_ + " " + a_ + " --field phi --order 1");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_NEAR(json_number(f.out, "target_integral"), 0.5, 1e-12);
}

TEST_F(CliMeshTest, RemapP1WithoutMatrixKeepsNoSupermeshAndPrintsTheSameNumbers) {
  // Without --matrix, P1 sums its loads from pieces handed over (tetia::P1Loads) instead of a
  // kept supermesh; with it, from the kept pieces' matrices. Every number printed and written
  // must be the same, counts of file cell pairs included (hexahedra and prisms split).
  const std::string hex = (dir_ / "hex.msh").string(), tet = (dir_ / "tet.msh").string();
  std::ofstream(hex) << tetia::testsupport::grid_msh(3, true, true);
  tetia::write_msh(tet, tetia::make_kuhn_mesh({4, 4, 4}, {0, 0, 0}, {0.75, 0.75, 0.75}));
  for (const auto& [src, tgt] : {std::pair{hex, tet}, std::pair{tet, hex}, std::pair{b_, a_}})
    for (const std::string field : {"--expr \"sin(x)*y + z\"", "--field phi"}) {
      if (field == "--field phi" && src != b_) continue;
      SCOPED_TRACE(src + " -> " + tgt + ", " + field);
      const std::string common = "remap " + src + " " + tgt + " " + field + " --order 1 -o ";
      const Result streamed = run(common + (dir_ / "streamed.vtu").string());
      const Result kept = run(common + (dir_ / "kept.vtu").string() + " --matrix " + (dir_ / "m.mtx").string());
      ASSERT_EQ(streamed.status, 0) << streamed.err;
      ASSERT_EQ(kept.status, 0) << kept.err;
      EXPECT_EQ(without_seconds(streamed.out), without_seconds(kept.out));
      EXPECT_GT(json_number(streamed.out, "pairs"), 0);
      EXPECT_EQ(tetia::testcli::read_file(dir_ / "streamed.vtu"), tetia::testcli::read_file(dir_ / "kept.vtu"));
    }
}

TEST_F(CliMeshTest, BadInputGivesAClearErrorAndStatus2) {
  Result r = run("supermesh " + (dir_ / "missing.msh").string() + " " + b_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tetia: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.msh"), std::string::npos) << r.err;
  r = run("remap " + a_ + " " + b_ + " --expr \"sin(x\" --order 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--expr"), std::string::npos) << r.err;
  r = run("remap " + a_ + " " + b_ + " --field nosuchfield --order 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("nosuchfield"), std::string::npos) << r.err;
  r = run("remap " + a_ + " " + b_ + " --order 0");
  EXPECT_EQ(r.status, 2);
}

// Issue 16's habits: a broken file names its line and tag; an output path that cannot be
// written fails before the work (the missing directory is reported, not the meshes); --threads
// is validated; a summary that would not be finite is an error, never "nan" in the JSON.
TEST_F(CliMeshTest, ErrorsComeEarlyNameTheLineAndNeverPrintNan) {
  const std::string dup = (dir_ / "dup.msh").string();
  std::ofstream(dup) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                        "3 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n";
  Result r = run("supermesh " + dup + " " + b_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(dup + ": node tag 3 given twice, differently (line 8 and line 9)"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");

  const std::string nowhere = (dir_ / "no" / "such" / "dir" / "s.vtu").string();
  r = run("supermesh " + (dir_ / "missing.msh").string() + " " + b_ + " -o " + nowhere);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(nowhere + ": cannot write (-o)"), std::string::npos) << r.err;  // before the meshes are read
  r = run("remap " + a_ + " " + b_ + " --expr x --order 1 --matrix " + nowhere);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(nowhere + ": cannot write (--matrix)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "no"));

  for (const char* bad : {"-3", "100000", "two"}) {
    r = run(std::string("supermesh ") + a_ + " " + b_ + " --threads " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
  }

  // Coordinates of 1e300: every number is finite in the file, the volume (1e900 / 6) is beyond
  // double's range: reading says so, naming the cell.
  const std::string huge = (dir_ / "huge.msh").string();
  std::ofstream(huge) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1e300 0 0\n3 0 1e300 0\n"
                         "4 0 0 1e300\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n";
  for (const std::string& cmd : {"supermesh " + huge + " " + huge, "remap " + huge + " " + huge + " --expr x --order 1"}) {
    r = run(cmd);
    EXPECT_EQ(r.status, 2) << cmd;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("cell 0: its volume is beyond the range of double precision"), std::string::npos) << r.err;
  }
}

// Fields as users have them: a vector field (every component remapped; linear components are
// reproduced by P1), several fields in one run (each output named like its input), and time
// steps (--step chooses; several steps and none chosen is an error naming them).
TEST_F(CliMeshTest, VectorFieldsSeveralFieldsAndTimeSteps) {
  const tetia::TetMesh b = tetia::read_mesh(b_);
  std::vector<double> velocity, pressure(b.num_nodes());
  for (std::size_t n = 0; n < b.num_nodes(); ++n) {
    const tetia::Vec3 p = b.nodes[n];
    velocity.insert(velocity.end(), {p.x + 1.0, 2.0 * p.y - p.z, 3.0});
    pressure[n] = 1.0 - p.x;
  }
  const std::string src = (dir_ / "fields.msh").string();
  tetia::write_msh(src, b, {}, {{"velocity", velocity, 3}, {"p", pressure}});
  EXPECT_EQ(tetia::msh_fields(src).size(), 2u);
  const std::string vtu = (dir_ / "out.vtu").string();
  Result r = run("remap " + src + " " + a_ + " --field velocity --field p --order 1 -o " + vtu);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"fields\": [{\"name\": \"velocity\", \"components\": 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("{\"name\": \"p\", \"components\": 1"), std::string::npos) << r.out;
  const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
  ASSERT_TRUE(v.ok) << v.error;
  const tetia::TetMesh a = tetia::read_mesh(a_);
  ASSERT_NE(v.point_array("velocity"), nullptr);
  ASSERT_NE(v.point_array("p"), nullptr);
  const auto& u = v.point_array("velocity")->values;
  ASSERT_EQ(u.size(), 3 * a.num_nodes());
  double worst = 0.0;
  for (std::size_t n = 0; n < a.num_nodes(); ++n) {
    const tetia::Vec3 p = a.nodes[n];
    worst = std::max({worst, std::abs(u[3 * n] - (p.x + 1.0)), std::abs(u[3 * n + 1] - (2.0 * p.y - p.z)),
                      std::abs(u[3 * n + 2] - 3.0), std::abs(v.point_array("p")->values[n] - (1.0 - p.x))});
  }
  EXPECT_LT(worst, 1e-10);

  // Two time steps of one field: a file written with step 0, and step 1 appended by hand.
  const std::string steps = (dir_ / "steps.msh").string();
  std::vector<double> rho(b.num_cells(), 2.0);
  tetia::write_msh(steps, b, {{"rho", rho}});
  {
    std::ofstream out(steps, std::ios::app);
    out << "$ElementData\n1\n\"rho\"\n1\n1.5\n3\n1\n1\n" << b.num_cells() << "\n";
    for (std::size_t c = 0; c < b.num_cells(); ++c) out << c + 1 << " 5\n";
    out << "$EndElementData\n";
  }
  r = run("remap " + steps + " " + a_ + " --field rho --order 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("field rho has 2 time steps (0, 1); choose one (--step)"), std::string::npos) << r.err;
  r = run("remap " + steps + " " + a_ + " --field rho --order 0 --step 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(json_number(r.out, "target_integral"), 5.0, 1e-12);
  r = run("remap " + steps + " " + a_ + " --field rho --order 0 --step 7");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("has no time step 7 (steps: 0, 1)"), std::string::npos) << r.err;
  r = run("remap " + steps + " " + a_ + " --field rho --field rho --order 0 --step 0");
  EXPECT_EQ(r.status, 2);
}

// The progress line: named phases, a bar and a rate for the intersection, shown with
// --progress (here without the one-second delay), never with --quiet, and not by default when
// stderr is not a terminal (as here); the JSON on stdout is the same either way.
TEST_F(CliMeshTest, ProgressLineOnRequestOnly) {
  const Result plain = run("supermesh " + a_ + " " + b_);
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.err, "");
  ::setenv("TETIA_PROGRESS_DELAY", "0", 1);  // inherited by the commands run below
  const Result shown = run("supermesh " + a_ + " " + b_ + " --progress");
  ASSERT_EQ(shown.status, 0) << shown.err;
  EXPECT_NE(shown.err.find("tetia: reading " + a_), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("tetia: intersection ["), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("100%"), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("cells/s"), std::string::npos) << shown.err;
  EXPECT_EQ(json_number(shown.out, "pairs"), json_number(plain.out, "pairs"));
  const Result solve = run("remap " + a_ + " " + b_ + " --expr x --order 1 --progress");
  ASSERT_EQ(solve.status, 0) << solve.err;
  EXPECT_NE(solve.err.find("tetia: solve"), std::string::npos) << solve.err;
  const Result quiet = run("supermesh " + a_ + " " + b_ + " --quiet");
  EXPECT_EQ(quiet.status, 0);
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(run("supermesh " + a_ + " " + b_ + " --quiet --progress").status, 2);
  ::unsetenv("TETIA_PROGRESS_DELAY");
}

// Second-order tetrahedra: refused by default (the message names the option), read by their
// corner nodes with --corner-nodes, which the JSON and stderr report.
TEST_F(CliMeshTest, SecondOrderCellsOnlyWithCornerNodes) {
  const std::string t10 = (dir_ / "t10.msh").string();
  std::ofstream(t10) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                        "5 .5 0 0\n6 .5 .5 0\n7 0 .5 0\n8 0 0 .5\n9 0 .5 .5\n10 .5 0 .5\n$EndNodes\n"
                        "$Elements\n1\n1 11 2 0 1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
  Result r = run("supermesh " + t10 + " " + a_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("higher-order cells are not supported"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--corner-nodes"), std::string::npos) << r.err;
  r = run("supermesh " + t10 + " " + a_ + " --corner-nodes --progress");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"straightened_cells\": [1, 0]"), std::string::npos) << r.out;
  EXPECT_NEAR(json_number(r.out, "intersection_volume"), 1.0 / 6.0, 1e-15);
  EXPECT_NE(r.err.find("1 higher-order cells read by their corner nodes: their geometry was made straight"),
            std::string::npos)
      << r.err;
}

TEST_F(CliMeshTest, SharedLibsupermeshCubes) {
  const fs::path shared = fs::path(TETIA_SHARED_DIR) / "extdata";
  if (!fs::exists(shared / "lsm_cube.1.msh")) GTEST_SKIP() << "needs ../shared/extdata (absent)";
  const Result r = run("supermesh " + (shared / "lsm_cube.1.msh").string() + " " + (shared / "lsm_cube.2.msh").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(json_number(r.out, "intersection_volume"), 1.0, 1e-13);  // the README's known answer
}

TEST_F(CliMeshTest, DemoRunsAndWritesVtu) {
  const fs::path out = dir_ / "demo";
  const Result r = run("demo --size 0.35 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("box/box"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ball/box"), std::string::npos) << r.out;
  int vtu = 0;
  for (const auto& e : fs::directory_iterator(out)) vtu += e.path().extension() == ".vtu";
  EXPECT_EQ(vtu, 8);
}

// ---------------------------------------------------------------------------------------------
// 2D: triangular meshes

class CliMesh2DTest : public CliMeshTest {
 protected:
  void SetUp() override {
    CliMeshTest::SetUp();
    // Two non-matching meshes of the unit square: 5x5 and 7x7 structured triangle meshes, the
    // second with a P0 field "rho" = 2 and a P1 field "phi" = x.
    a2_ = (dir_ / "a2.msh").string();
    b2_ = (dir_ / "b2.msh").string();
    const tetia::TriMesh a = tetia::make_structured_tri_mesh({5, 5}, {0, 0}, {0.2, 0.2});
    const tetia::TriMesh b = tetia::make_structured_tri_mesh({7, 7}, {0, 0}, {1.0 / 7, 1.0 / 7});
    std::vector<double> rho(b.num_cells(), 2.0), phi(b.num_nodes());
    for (std::size_t n = 0; n < b.num_nodes(); ++n) phi[n] = b.nodes[n].x;
    tetia::write_msh(a2_, a);
    tetia::write_msh(b2_, b, {{"rho", rho}}, {{"phi", phi}});
  }

  std::string a2_, b2_;
};

// Quadrilaterals (a 4 x 4 grid of the unit square, tags scrambled) as the target of a 2D remap:
// one value per quadrilateral, the VTU of quadrilaterals (VTK type 9), conservation, and P1
// onto the quadrilaterals' nodes reproducing a linear field.
TEST_F(CliMesh2DTest, ResultsPerQuadrilateral) {
  const std::string quads = (dir_ / "quads.msh").string();
  {
    std::ofstream q(quads);
    const int n = 4, m = n + 1;
    const auto tag = [&](int i, int j) { return 1 + ((i + m * j) * 7) % (m * m); };  // 7 is prime to 25
    q << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m * m << "\n";
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) q << tag(i, j) << ' ' << double(i) / n << ' ' << double(j) / n << " 0\n";
    q << "$EndNodes\n$Elements\n" << n * n << "\n";
    for (int j = 0, e = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        q << ++e << " 3 2 1 1 " << tag(i, j) << ' ' << tag(i + 1, j) << ' ' << tag(i + 1, j + 1) << ' ' << tag(i, j + 1) << '\n';
    q << "$EndElements\n";
  }
  const std::string vtu = (dir_ / "q.vtu").string();
  const Result r = run("remap " + a2_ + " " + quads + " --order 0 --expr \"x-3*y\" -o " + vtu);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json_number(r.out, "target_cells"), 16);
  EXPECT_EQ(json_number(r.out, "target_simplices"), 32);
  EXPECT_LT(json_number(r.out, "conservation_error"), 1e-13);
  const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
  ASSERT_TRUE(v.ok) << v.error;
  EXPECT_EQ(v.cell_types, std::vector<int>(16, 9));
  ASSERT_NE(v.cell_array("field"), nullptr);
  EXPECT_EQ(v.cell_array("field")->values.size(), 16u);
  const Result p1 = run("remap " + a2_ + " " + quads + " --order 1 --expr \"x-3*y\"");
  ASSERT_EQ(p1.status, 0) << p1.err;
  EXPECT_LT(json_number(p1.out, "relative_l2_error"), 1e-10);
}

TEST_F(CliMesh2DTest, SupermeshDetectsTheDimensionAndPrintsAreas) {
  const Result r = run("supermesh " + a2_ + " " + b2_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json_number(r.out, "dimension"), 2);
  EXPECT_EQ(json_number(r.out, "source_cells"), 50);
  EXPECT_EQ(json_number(r.out, "target_cells"), 98);
  EXPECT_GT(json_number(r.out, "pairs"), 98);
  EXPECT_GE(json_number(r.out, "candidates"), json_number(r.out, "pairs"));
  EXPECT_NEAR(json_number(r.out, "intersection_area"), 1.0, 1e-13);
  EXPECT_NEAR(json_number(r.out, "source_area"), 1.0, 1e-13);
  EXPECT_NEAR(json_number(r.out, "target_area"), 1.0, 1e-13);
  EXPECT_EQ(r.out.find("volume"), std::string::npos) << r.out;
  const Result rt = run("supermesh --search rtree --threads 1 " + a2_ + " " + b2_);
  ASSERT_EQ(rt.status, 0) << rt.err;
  EXPECT_EQ(json_number(rt.out, "pairs"), json_number(r.out, "pairs"));
  EXPECT_EQ(json_number(rt.out, "intersection_area"), json_number(r.out, "intersection_area"));
  // -o: the pieces' triangles, as VTK reads them.
  const std::string vtu = (dir_ / "s2.vtu").string();
  const Result o = run("supermesh " + a2_ + " " + b2_ + " -o " + vtu);
  ASSERT_EQ(o.status, 0) << o.err;
  const tetia::testvtu::VtkView v = tetia::testvtu::read_with_vtk(vtu);
  ASSERT_TRUE(v.ok) << v.error;
  EXPECT_GT(v.cells.size(), 98u);
  for (const int t : v.cell_types) EXPECT_EQ(t, 5);  // VTK_TRIANGLE
  for (const auto& p : v.points) EXPECT_EQ(p[2], 0.0);
  ASSERT_NE(v.cell_array("simplex_area"), nullptr);
  double total = 0.0;
  for (const double x : v.cell_array("simplex_area")->values) total += x;
  EXPECT_NEAR(total, json_number(o.out, "intersection_area"), 1e-12);
}

TEST_F(CliMesh2DTest, RemapP0OfAStoredFieldIsConservative) {
  const Result r = run("remap " + b2_ + " " + a2_ + " --field rho --order 0 -o " + (dir_ / "r2.vtu").string() +
                       " --matrix " + (dir_ / "m2.mtx").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json_number(r.out, "dimension"), 2);
  EXPECT_NEAR(json_number(r.out, "source_integral"), 2.0, 1e-12);
  EXPECT_NEAR(json_number(r.out, "target_integral"), 2.0, 1e-12);
  EXPECT_LE(json_number(r.out, "conservation_error"), 1e-13);
  EXPECT_NEAR(json_number(r.out, "intersection_area"), 1.0, 1e-13);
  EXPECT_NE(tetia::testcli::read_file(dir_ / "m2.mtx").find("area of target cell t"), std::string::npos);
  EXPECT_NE(tetia::testcli::read_file(dir_ / "r2.vtu").find("Name=\"rho\""), std::string::npos);
}

TEST_F(CliMesh2DTest, RemapP1ReproducesALinearExpressionInXAndY) {
  // z is 0 in 2D: "+ 5*z" changes nothing.
  const Result r = run("remap " + a2_ + " " + b2_ + " --expr \"x + 2*y + 5*z\" --order 1 --matrix " +
                       (dir_ / "p1.mtx").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LE(json_number(r.out, "relative_l2_error"), 1e-10);
  EXPECT_LE(json_number(r.out, "conservation_error"), 1e-12);
  EXPECT_NEAR(json_number(r.out, "target_integral"), 1.5, 1e-12);
  EXPECT_GT(json_number(r.out, "cg_iterations"), 0);
  EXPECT_NE(tetia::testcli::read_file(dir_ / "p1.mtx").find("rows: 64 target nodes, columns: 36 source nodes"),
            std::string::npos);
  const Result f = run("remap " + b2_ + " " + a2_ + " --field phi --order 1");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_NEAR(json_number(f.out, "target_integral"), 0.5, 1e-12);
  // P0 of a smooth expression: errors reported.
  const Result e = run("remap " + a2_ + " " + b2_ + " --expr \"sin(x)*cos(y)\" --order 0");
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_GT(json_number(e.out, "l2_error"), 0.0);
  EXPECT_LT(json_number(e.out, "relative_l2_error"), 0.2);
}

TEST_F(CliMesh2DTest, RemapP1WithoutMatrixPrintsTheSameNumbers) {
  // As in 3D: the loads from pieces handed over, or from a kept supermesh (--matrix).
  for (const auto& [src, tgt] : {std::pair{a2_, b2_}, std::pair{b2_, a2_}}) {
    SCOPED_TRACE(src + " -> " + tgt);
    const std::string common = "remap " + src + " " + tgt + " --expr \"sin(x)*y\" --order 1 -o ";
    const Result streamed = run(common + (dir_ / "streamed.vtu").string());
    const Result kept = run(common + (dir_ / "kept.vtu").string() + " --matrix " + (dir_ / "m.mtx").string());
    ASSERT_EQ(streamed.status, 0) << streamed.err;
    ASSERT_EQ(kept.status, 0) << kept.err;
    EXPECT_EQ(without_seconds(streamed.out), without_seconds(kept.out));
    EXPECT_EQ(tetia::testcli::read_file(dir_ / "streamed.vtu"), tetia::testcli::read_file(dir_ / "kept.vtu"));
  }
}

TEST_F(CliMesh2DTest, MixedDimensionsAndFilesWithoutCellsAreErrors) {
  Result r = run("supermesh " + a2_ + " " + b_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tetia: " + a2_ + " is a 2D mesh (triangles) but " + b_ + " is a 3D mesh (tetrahedra)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("same dimension"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  r = run("remap " + b_ + " " + a2_ + " --expr x --order 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("same dimension"), std::string::npos) << r.err;
  // Only lines: neither dimension.
  const fs::path lines = dir_ / "lines.msh";
  std::ofstream(lines) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n"
                          "$Elements\n1\n1 1 2 0 1 1 2\n$EndElements\n";
  r = run("supermesh " + lines.string() + " " + a2_);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("tetia: " + lines.string() + ": no tetrahedra or triangles"), std::string::npos) << r.err;
  r = run("remap " + a2_ + " " + b2_ + " --field nosuchfield --order 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no node field named nosuchfield"), std::string::npos) << r.err;
}

TEST_F(CliMesh2DTest, HelpDocumentsTheAreaKeys) {
  const Result r = run("supermesh --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("intersection_area"), std::string::npos) << r.out;
  const Result m = run("remap --help");
  EXPECT_NE(m.out.find("source_area"), std::string::npos) << m.out;
}

TEST_F(CliMesh2DTest, Demo2DRunsAndWritesVtu) {
  const fs::path out = dir_ / "demo2";
  const Result r = run("demo --dim 2 --size 0.15 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"rect/rect", "disk/rect", "ring/rect"}) EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
  int vtu = 0;
  for (const auto& e : fs::directory_iterator(out)) vtu += e.path().extension() == ".vtu";
  EXPECT_EQ(vtu, 12);
  EXPECT_EQ(run("demo --dim 4").status, 2);
}

}  // namespace
