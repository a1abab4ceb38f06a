// tests/test_cli_mesh.cpp -- `tetia supermesh`, `tetia remap` and `tetia demo` end to end: the
// executable named by TETIA_CLI_PATH on meshes written here (Kuhn meshes through write_msh) and,
// where ../shared is present, on the libsupermesh test meshes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <sstream>
#include <string>

#include "support/cli.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace {

namespace fs = std::filesystem;

using tetia::testcli::Result;
// The number after "key": in a one-line JSON object (null gives NaN).
double json_number(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const auto at = json.find(tag);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no key " << key << " in " << json;
    return std::nan("");
  }
  const char* p = json.c_str() + at + tag.size();
  if (std::string_view(p, 4) == "null") return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(p, &end);
  EXPECT_NE(end, p) << "no number for " << key << " in " << json;
  return v;
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

TEST_F(CliMeshTest, SupermeshWritesVtu) {
  const std::string vtu = (dir_ / "s.vtu").string();
  const Result r = run("supermesh " + a_ + " " + b_ + " -o " + vtu);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string text = tetia::testcli::read_file(vtu);
  EXPECT_NE(text.find("UnstructuredGrid"), std::string::npos);
  EXPECT_NE(text.find("Name=\"source\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"target\""), std::string::npos);
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

}  // namespace
