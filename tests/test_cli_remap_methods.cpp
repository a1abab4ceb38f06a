// tests/test_cli_remap_methods.cpp -- `tetia remap`'s methods and coverage end to end (the
// executable named by TETIA_CLI_PATH): --bounded, --lumped, --discontinuous (both orders),
// --reconstruct linear, --normalize, --uncovered and the covered_fraction arrays, on meshes
// written here; values checked at every node or cell as VTK reads them from the output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "support/cell_grids.hpp"
#include "support/cli.hpp"
#include "support/json_text.hpp"
#include "support/vtu_check.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace {

namespace fs = std::filesystem;
using tetia::testcli::Result;
using tetia::testvtu::VtkView;
using tetia::testjson::json_number;
using tetia::testjson::json_string;



class CliRemapMethodsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "tetia_cli_methods_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
    ASSERT_TRUE(fs::exists(TETIA_CLI_PATH)) << "CLI not built: " << TETIA_CLI_PATH;
    // Two non-matching Kuhn meshes of the unit cube, and two structured triangle meshes of the
    // unit square.
    a_ = path("a.msh"), b_ = path("b.msh"), a2_ = path("a2.msh"), b2_ = path("b2.msh");
    tetia::write_msh(a_, tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3}));
    tetia::write_msh(b_, tetia::make_kuhn_mesh({4, 4, 4}, {0, 0, 0}, {0.25, 0.25, 0.25}));
    tetia::write_msh(a2_, tetia::make_structured_tri_mesh({5, 5}, {0, 0}, {0.2, 0.2}));
    tetia::write_msh(b2_, tetia::make_structured_tri_mesh({7, 7}, {0, 0}, {1.0 / 7, 1.0 / 7}));
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  Result run(const std::string& args) { return tetia::testcli::run(TETIA_CLI_PATH, args, dir_); }
  // Runs the remap with -o out.vtu (ASCII) and returns what VTK reads; the JSON into *json.
  VtkView remap_vtu(const std::string& args, std::string* json) {
    const Result r = run("remap " + args + " --ascii -o " + path("out.vtu"));
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    if (json != nullptr) *json = r.out;
    const VtkView v = tetia::testvtu::read_with_vtk(path("out.vtu"));
    EXPECT_TRUE(v.ok) << v.error;
    return v;
  }

  fs::path dir_;
  std::string a_, b_, a2_, b2_;
};

// The least and largest value of an array.
std::pair<double, double> range_of(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {*lo, *hi};
}

// Every method conserves the source integral over the overlap (here the whole source), both
// ways, in 3D and 2D; the JSON names the method.
TEST_F(CliRemapMethodsTest, EveryMethodIsConservativeBothWaysIn3DAnd2D) {
  const char* methods[][2] = {{"--order 0", "p0"},
                              {"--order 0 --reconstruct linear", "p0_linear"},
                              {"--order 0 --discontinuous", "p0_from_discontinuous"},
                              {"--order 1", "p1"},
                              {"--order 1 --lumped", "p1_lumped"},
                              {"--order 1 --bounded", "p1_bounded"},
                              {"--order 1 --discontinuous", "p1_discontinuous"}};
  for (const auto& [x, y] : {std::pair{a_, b_}, std::pair{b_, a_}, std::pair{a2_, b2_}, std::pair{b2_, a2_}})
    for (const auto& [flags, name] : methods) {
      SCOPED_TRACE(x + " -> " + y + " " + flags);
      const Result r = run("remap " + x + " " + y + " " + flags + " --expr \"exp(x)*(1 + y) + sin(3*z)\"");
      ASSERT_EQ(r.status, 0) << r.err;
      EXPECT_EQ(json_string(r.out, "method"), name);
      EXPECT_LE(json_number(r.out, "conservation_error"), 1e-13);
      EXPECT_NEAR(json_number(r.out, "overlap_integral"), json_number(r.out, "source_integral"),
                  1e-13 * std::abs(json_number(r.out, "source_integral")));
      EXPECT_EQ(json_number(r.out, "uncovered"), 0);
    }
}

// Linear fields: reproduced by Galerkin, bounded (within its bounds, as a linear field is) and
// discontinuous P1, and by the discontinuous source's cell averages; the lumped projection and
// the reconstruction are not exact but much closer than P0 for the reconstruction.
TEST_F(CliRemapMethodsTest, LinearFieldsWhereTheMethodPromisesThem) {
  for (const auto& [x, y] : {std::pair{a_, b_}, std::pair{b_, a_}, std::pair{a2_, b2_}}) {
    SCOPED_TRACE(x + " -> " + y);
    const std::string common = "remap " + x + " " + y + " --expr \"1 + x + 2*y + 3*z\" ";
    for (const std::string flags : {"--order 1", "--order 1 --bounded", "--order 1 --discontinuous"}) {
      const Result r = run(common + flags);
      ASSERT_EQ(r.status, 0) << r.err;
      EXPECT_LE(json_number(r.out, "relative_l2_error"), 1e-12) << flags;
    }
    // Cell averages from a discontinuous source (the linear field's values at each source
    // cell's vertices): the exact cell averages of the field, cell by cell.
    const VtkView v = remap_vtu(x + " " + y + " --expr \"1 + x + 2*y + 3*z\" --order 0 --discontinuous", nullptr);
    const auto* field = v.cell_array("field");
    const auto* exact = v.cell_array("exact");
    ASSERT_TRUE(field != nullptr && exact != nullptr);
    for (std::size_t c = 0; c < field->values.size(); ++c)
      EXPECT_NEAR(field->values[c], exact->values[c], 1e-13) << "cell " << c;
    const Result p0 = run(common + "--order 0"), linear = run(common + "--order 0 --reconstruct linear");
    ASSERT_EQ(p0.status, 0) << p0.err;
    ASSERT_EQ(linear.status, 0) << linear.err;
    // The target's cell averages are the exact field's averages: relative_l2_error compares the
    // P0 values with the field itself, so both include the P0 representation error; the
    // reconstruction's values are the exact averages where its gradients are not limited.
    EXPECT_LT(json_number(linear.out, "relative_l2_error"), json_number(p0.out, "relative_l2_error"));
  }
}

// A step: Galerkin P1 over- and undershoots; --bounded and --lumped stay in [0, 1] at every
// node, the reconstruction at every cell, and they conserve.
TEST_F(CliRemapMethodsTest, BoundedLumpedAndLimitedStayWithinTheStep) {
  for (const auto& [x, y] : {std::pair{a_, b_}, std::pair{b_, a_}, std::pair{a2_, b2_}, std::pair{b2_, a2_}}) {
    SCOPED_TRACE(x + " -> " + y);
    const std::string common = x + " " + y + " --expr \"(x + 0.3*y > 0.55) ? 1 : 0\" ";
    std::string json;
    const VtkView galerkin = remap_vtu(common + "--order 1", &json);
    ASSERT_NE(galerkin.point_array("field"), nullptr);
    const auto [glo, ghi] = range_of(galerkin.point_array("field")->values);
    EXPECT_TRUE(glo < 0.0 || ghi > 1.0) << "the step does not make Galerkin P1 leave [0, 1]: the test sees nothing";
    for (const std::string flags : {"--order 1 --bounded", "--order 1 --lumped"}) {
      const VtkView v = remap_vtu(common + flags, &json);
      ASSERT_NE(v.point_array("field"), nullptr) << flags;
      const auto [lo, hi] = range_of(v.point_array("field")->values);
      // Bounded: exactly. Lumped: its operator's products (the value --save-operator's file
      // gives back), each an average of the values, within them to rounding.
      const double slack = flags == "--order 1 --bounded" ? 0.0 : 1e-14;
      EXPECT_GE(lo, -slack) << flags;
      EXPECT_LE(hi, 1.0 + slack) << flags;
      EXPECT_LE(json_number(json, "conservation_error"), 1e-13) << flags;
    }
    const VtkView v = remap_vtu(common + "--order 0 --reconstruct linear", &json);
    ASSERT_NE(v.cell_array("field"), nullptr);
    const auto [lo, hi] = range_of(v.cell_array("field")->values);
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 1.0 + 1e-15);
    EXPECT_LE(json_number(json, "conservation_error"), 1e-13);
  }
}

// A target of 2 x 2 x 2 hexahedra on [0, 2]^3 and a source on [0, 0.8] x [0, 2]^2: the cells with
// x < 1 are 0.8 covered, the others not at all. covered_fraction per hexahedron, the JSON's
// counts, --normalize, and every --uncovered choice, checked cell by cell.
TEST_F(CliRemapMethodsTest, CoverageNormalizationAndUncoveredCells) {
  const std::string target = path("hex.msh"), source = path("part.msh");
  std::ofstream(target) << tetia::testsupport::grid_msh(2, false, true);  // "ten": 10 x the cell's tag
  const tetia::TetMesh part = tetia::make_kuhn_mesh({4, 10, 10}, {0, 0, 0}, {0.2, 0.2, 0.2});
  tetia::write_msh(source, part, {{"ten", std::vector<double>(part.num_cells(), 3.0)}});
  const auto centre_x = [](const VtkView& v, std::size_t c) {
    double x = 0.0;
    for (const long long p : v.cells[c]) x += v.points[static_cast<std::size_t>(p)][0];
    return x / static_cast<double>(v.cells[c].size());
  };
  std::string json;
  for (const std::string uncovered : {"flag", "nan", "zero", "keep"})
    for (const std::string normalize : {"full", "covered"}) {
      SCOPED_TRACE(uncovered + ", " + normalize);
      const VtkView v = remap_vtu(source + " " + target + " --field ten --order 0 --uncovered " + uncovered +
                                      " --normalize " + normalize,
                                  &json);
      ASSERT_EQ(v.cells.size(), 8u);
      const auto* fraction = v.cell_array("covered_fraction");
      const auto* value = v.cell_array("ten");
      const auto* id = v.cell_array("cell_id");
      ASSERT_TRUE(fraction != nullptr && value != nullptr && id != nullptr);
      for (std::size_t c = 0; c < 8; ++c) {
        const bool covered = centre_x(v, c) < 1.0;
        EXPECT_NEAR(fraction->values[c], covered ? 0.8 : 0.0, 1e-14) << "cell " << c;
        if (covered) {
          EXPECT_NEAR(value->values[c], normalize == "full" ? 2.4 : 3.0, 1e-13) << "cell " << c;
        } else if (uncovered == "nan") {
          EXPECT_TRUE(std::isnan(value->values[c])) << "cell " << c;
        } else if (uncovered == "keep") {
          EXPECT_EQ(value->values[c], 10.0 * id->values[c]) << "cell " << c;
        } else {
          EXPECT_EQ(value->values[c], 0.0) << "cell " << c;
        }
      }
      EXPECT_EQ(json_number(json, "uncovered"), 4);
      EXPECT_EQ(json_number(json, "partly_covered"), 4);
      EXPECT_NEAR(json_number(json, "least_fraction"), 0.0, 0.0);
      EXPECT_EQ(json_string(json, "uncovered_values"), uncovered);
      EXPECT_EQ(json.find(": nan"), std::string::npos) << json;
      EXPECT_EQ(json.find("NaN"), std::string::npos) << json;
    }
  // The default says so on stderr.
  const Result r = run("remap " + source + " " + target + " --field ten --order 0");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("4 target cells are not covered"), std::string::npos) << r.err;
  // P1: each node's coverage of its basis function, whose support is x within 1 of the node's:
  // none at x = 2, part of it at x = 0 and x = 1; the lumped value of 1 is that fraction.
  const VtkView p1 = remap_vtu(source + " " + target + " --expr 1 --order 1 --lumped --uncovered nan", &json);
  const auto* nodes = p1.point_array("node_covered_fraction");
  const auto* field = p1.point_array("field");
  ASSERT_TRUE(nodes != nullptr && field != nullptr);
  std::size_t uncovered_nodes = 0;
  for (std::size_t n = 0; n < p1.points.size(); ++n) {
    const double x = p1.points[n][0], f = nodes->values[n];
    if (x == 2.0) {
      ++uncovered_nodes;
      EXPECT_EQ(f, 0.0) << "node " << n;
      EXPECT_TRUE(std::isnan(field->values[n])) << "node " << n;
    } else {
      EXPECT_GT(f, 0.0) << "node " << n;
      EXPECT_LT(f, 1.0 - 1e-3) << "node " << n;
      EXPECT_NEAR(field->values[n], f, 1e-13) << "node " << n;
    }
  }
  EXPECT_EQ(uncovered_nodes, 9u);
  EXPECT_EQ(json_number(json, "uncovered"), 9);
  EXPECT_EQ(json_string(json, "of"), "nodes");
}

// Discontinuous P1 out (VTU cell data of 4 values per tetrahedron, .msh element-node data) and
// back in as the source of --order 0 --discontinuous: the cell averages of a linear field.
TEST_F(CliRemapMethodsTest, DiscontinuousFieldsGoOutAndComeBackIn) {
  std::string json;
  const VtkView v = remap_vtu(a_ + " " + b_ + " --expr \"x + 2*y + 3*z\" --order 1 --discontinuous", &json);
  const auto* field = v.cell_array("field");
  ASSERT_NE(field, nullptr);
  ASSERT_EQ(field->values.size(), 4 * v.cells.size());
  for (std::size_t c = 0; c < v.cells.size(); ++c)
    for (std::size_t k = 0; k < 4; ++k) {
      const auto& p = v.points[static_cast<std::size_t>(v.cells[c][k])];
      EXPECT_NEAR(field->values[4 * c + k], p[0] + 2 * p[1] + 3 * p[2], 1e-12) << "cell " << c << ", vertex " << k;
    }
  const std::string dg = path("dg.msh");
  const Result out = run("remap " + a_ + " " + b_ + " --expr \"x + 2*y + 3*z\" --order 1 --discontinuous -o " + dg);
  ASSERT_EQ(out.status, 0) << out.err;
  const Result back = run("remap " + dg + " " + a_ + " --field field --order 0 --discontinuous");
  ASSERT_EQ(back.status, 0) << back.err;
  EXPECT_NEAR(json_number(back.out, "target_integral"), 3.0, 1e-12);  // the integral of x + 2y + 3z
  EXPECT_LE(json_number(back.out, "conservation_error"), 1e-13);
  // A split target: per simplex in VTU; refused in .msh.
  const std::string hex = path("hex.msh");
  std::ofstream(hex) << tetia::testsupport::grid_msh(2, true, false);
  const VtkView split = remap_vtu(a_ + " " + hex + " --expr x --order 1 --discontinuous", &json);
  ASSERT_NE(split.cell_array("field"), nullptr);
  EXPECT_EQ(split.cell_array("field")->values.size(), 4 * split.cells.size());
  const Result refused = run("remap " + a_ + " " + hex + " --expr x --order 1 --discontinuous -o " + path("s.msh"));
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("element-node data"), std::string::npos) << refused.err;
}

// Flags that name no method, and options a method does not have: exit status 2 before any work.
TEST_F(CliRemapMethodsTest, CombinationsThatMeanNothingAreUsageErrors) {
  const std::string m = a_ + " " + b_ + " --expr x ";
  const char* bad[][2] = {{"--order 0 --bounded", "--bounded is a P1 method"},
                          {"--order 0 --lumped", "--lumped is a P1 method"},
                          {"--order 1 --reconstruct linear", "give it with --order 0"},
                          {"--order 1 --bounded --lumped", "at most one"},
                          {"--order 0 --reconstruct linear --discontinuous", "exclude each other"},
                          {"--order 1 --normalize covered", "--normalize covered applies"},
                          {"--order 0 --uncovered keep", "needs --field"},
                          {"--order 0 --uncovered maybe", "--uncovered"},
                          {"--order 0 --reconstruct quadratic", "--reconstruct"}};
  for (const auto& [flags, message] : bad) {
    const Result r = run("remap " + m + flags);
    EXPECT_EQ(r.status, 2) << flags;
    EXPECT_NE(r.err.find(message), std::string::npos) << flags << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << flags;
  }
}

}  // namespace

namespace {

// Two arrays equal bit for bit (NaN equal to NaN).
void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool same = (std::isnan(a[i]) && std::isnan(b[i])) || a[i] == b[i];
    if (!same && bad++ < 5) ADD_FAILURE() << what << ": value " << i << ": " << a[i] << " against " << b[i];
  }
  EXPECT_EQ(bad, 0u) << what;
}

}  // namespace

// --save-operator W (Matrix Market and ESMF netCDF) then `tetia apply W`: the same values bit
// for bit as the remap that saved it, for every linear method, with --normalize and
// --uncovered, in 3D and 2D, with a target the source covers only partly.
TEST_F(CliRemapMethodsTest, SavedOperatorsApplyBitForBit) {
  // Sources with stored fields of every kind: cell data "c", node data "n" (2 components),
  // element-node data "e"; targets shifted out of the source's domain in part.
  struct Case {
    std::string source, target;
  };
  std::vector<Case> cases;
  {
    const tetia::TetMesh s = tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
    const tetia::TetMesh t = tetia::make_kuhn_mesh({4, 4, 4}, {0.3, 0, 0}, {0.25, 0.25, 0.25});
    const tetia::TriMesh s2 = tetia::make_structured_tri_mesh({5, 5}, {0, 0}, {0.2, 0.2});
    const tetia::TriMesh t2 = tetia::make_structured_tri_mesh({7, 7}, {0.3, 0.1}, {1.0 / 7, 1.0 / 7});
    const auto fields = [](const auto& m, const std::string& file) {
      std::vector<double> c(m.num_cells()), n(2 * m.num_nodes()), e(m.num_cells() * m.cells[0].size());
      for (std::size_t i = 0; i < c.size(); ++i) c[i] = std::sin(1.0 + static_cast<double>(i));
      for (std::size_t i = 0; i < n.size(); ++i) n[i] = std::cos(0.5 * static_cast<double>(i));
      for (std::size_t i = 0; i < e.size(); ++i) e[i] = std::sin(0.3 * static_cast<double>(i)) + 2.0;
      const int nc = 1;
      tetia::write_msh(file, m, {{"c", c, nc}}, {{"n", n, 2}}, {{"e", e, nc}});
    };
    fields(s, path("s3.msh"));
    fields(t, path("t3.msh"));  // the target's own values, for --uncovered keep
    fields(s2, path("s2.msh"));
    fields(t2, path("t2.msh"));
    cases = {{path("s3.msh"), path("t3.msh")}, {path("s2.msh"), path("t2.msh")}};
  }
  struct Method {
    const char* flags;
    const char* field;
    bool cells;  // result as cell data (else point data)
  };
  const Method methods[] = {{"--order 0", "c", true},
                            {"--order 0 --normalize covered", "c", true},
                            {"--order 0 --discontinuous", "e", true},
                            {"--order 0 --discontinuous --normalize covered", "e", true},
                            {"--order 1 --lumped", "n", false},
                            {"--order 1 --lumped --normalize covered", "n", false},
                            {"--order 1 --discontinuous", "n", true}};
  std::set<std::string> checked_with_vtk;
  for (const Case& c : cases)
    for (const Method& m : methods)
      for (const auto& [format, uncovered] : {std::pair<std::string, std::string>{".mtx", "flag"},
                                              {".nc", "nan"}, {".mtx", "keep"}}) {
          // keep needs the target's own field where the result goes: c and n are, e is not.
          const bool same_kind = std::string(m.field) == "c" ? m.cells : std::string(m.field) == "n" && !m.cells;
          if (uncovered == "keep" && !same_kind) continue;
          SCOPED_TRACE(c.source + " " + m.flags + " " + format + " --uncovered " + uncovered);
          const std::string w = path("w" + format);
          const std::string common = " --field " + std::string(m.field) + " --uncovered " + uncovered + " --ascii";
          const Result remap = run("remap " + c.source + " " + c.target + " " + m.flags + common + " --save-operator " +
                                   w + " -o " + path("remap.vtu"));
          ASSERT_EQ(remap.status, 0) << remap.err;
          const Result apply = run("apply " + w + " " + c.source + " " + c.target + common + " -o " + path("apply.vtu"));
          ASSERT_EQ(apply.status, 0) << apply.err;
          EXPECT_GT(json_number(remap.out, "uncovered"), 0);  // the shifted target is partly outside
          EXPECT_EQ(json_number(apply.out, "uncovered"), json_number(remap.out, "uncovered"));
          EXPECT_EQ(json_string(apply.out, "method"), json_string(remap.out, "method"));
          // The two files' values as written (shortest round-trip text), without VTK: it costs
          // a Python start per file, and the 31 comparisons took two minutes with it.
          bool in_remap = false, in_apply = false;
          const std::vector<double> x = tetia::testvtu::tetia_ascii_array(path("remap.vtu"), m.field, &in_remap);
          const std::vector<double> y = tetia::testvtu::tetia_ascii_array(path("apply.vtu"), m.field, &in_apply);
          ASSERT_TRUE(in_remap && in_apply);
          expect_same_bits(x, y, m.field);
          if (checked_with_vtk.insert(c.source + m.flags).second) {  // once per method and mesh: VTK reads the same
            const VtkView b = tetia::testvtu::read_with_vtk(path("apply.vtu"));
            ASSERT_TRUE(b.ok) << b.error;
            const auto* z = m.cells ? b.cell_array(m.field) : b.point_array(m.field);
            ASSERT_TRUE(z != nullptr);
            expect_same_bits(z->values, y, m.field);
          }
        }
}

// What has no operator, and an operator applied to meshes it was not saved for: exit status 2
// with a message that says why.
TEST_F(CliRemapMethodsTest, OperatorsThatCannotBeSavedOrApplied) {
  const std::string w = path("w.mtx");
  for (const std::string flags : {"--order 1", "--order 1 --bounded", "--order 0 --reconstruct linear"}) {
    const Result r = run("remap " + a_ + " " + b_ + " --expr x " + flags + " --save-operator " + w);
    EXPECT_EQ(r.status, 2) << flags;
    EXPECT_NE(r.err.find("--save-operator"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(w)) << flags;
  }
  const Result bad_name = run("remap " + a_ + " " + b_ + " --expr x --save-operator " + path("w.txt"));
  EXPECT_EQ(bad_name.status, 2);
  // Saved for a -> b, applied to b -> a.
  for (const auto& [file, n] : {std::pair{a_, 3}, std::pair{b_, 4}}) {
    const tetia::TetMesh m = tetia::make_kuhn_mesh({n, n, n}, {0, 0, 0}, {1.0 / n, 1.0 / n, 1.0 / n});
    tetia::write_msh(file, m, {{"x", std::vector<double>(m.num_cells(), 1.0)}});
  }
  ASSERT_EQ(run("remap " + b_ + " " + a_ + " --field x --save-operator " + w).status, 0);
  const Result wrong = run("apply " + w + " " + a_ + " " + b_ + " --field x");
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.err.find("not the meshes it was saved for"), std::string::npos) << wrong.err;
  // --uncovered keep with a target field of other components: refused, naming both files.
  {
    const tetia::TetMesh m = tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
    const std::string three = path("three.msh");
    tetia::write_msh(three, m, {{"x", std::vector<double>(3 * m.num_cells(), 1.0), 3}});
    const Result keep = run("apply " + w + " " + b_ + " " + three + " --field x --uncovered keep");
    EXPECT_EQ(keep.status, 2);
    EXPECT_NE(keep.err.find("has 1 components in " + b_ + " but 3 in " + three), std::string::npos) << keep.err;
  }
  // A damaged file: the line is named.
  std::string text = tetia::testcli::read_file(w);
  text.replace(text.rfind('\n', text.size() - 2) + 1, std::string::npos, "1 1 nan\n");
  std::ofstream(w) << text;
  const Result damaged = run("apply " + w + " " + b_ + " " + a_ + " --field x");
  EXPECT_EQ(damaged.status, 2);
  EXPECT_NE(damaged.err.find(w + ":"), std::string::npos) << damaged.err;
  EXPECT_TRUE(damaged.out.empty());
}

// The netCDF library is loaded only for ESMF files (app/netcdf_library.hpp): where it cannot be
// loaded, --save-operator W.nc and apply W.nc end with status 2 and a message naming the file and
// the library, and write nothing; Matrix Market files do not need it.
TEST_F(CliRemapMethodsTest, EsmfFilesWithoutTheNetcdfLibraryFailCleanly) {
  const tetia::TetMesh m = tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  const std::string source = path("with_x.msh");
  tetia::write_msh(source, m, {{"x", std::vector<double>(m.num_cells(), 1.0)}});
  const std::string args = " " + source + " " + b_ + " --field x";
  ASSERT_EQ(run("remap" + args + " --save-operator " + path("saved.nc")).status, 0);
  ::setenv("TETIA_NETCDF_LIBRARY", "/nonexistent/libnetcdf.so", 1);
  const Result save = run("remap" + args + " --save-operator " + path("w.nc") + " -o " + path("o.vtu"));
  const Result apply = run("apply " + path("saved.nc") + args);
  const Result mtx = run("remap" + args + " --save-operator " + path("w.mtx"));
  ::unsetenv("TETIA_NETCDF_LIBRARY");
  for (const Result* r : {&save, &apply}) {
    EXPECT_EQ(r->status, 2) << r->err;
    EXPECT_NE(r->err.find("ESMF weight files need the netCDF library (/nonexistent/libnetcdf.so)"), std::string::npos)
        << r->err;
    EXPECT_TRUE(r->out.empty()) << r->out;
  }
  EXPECT_NE(save.err.find(path("w.nc")), std::string::npos) << save.err;
  EXPECT_NE(apply.err.find(path("saved.nc")), std::string::npos) << apply.err;
  EXPECT_FALSE(fs::exists(path("w.nc")));
  EXPECT_EQ(mtx.status, 0) << mtx.err;
}

// The operator reader's fuzz seeds and findings (fuzz/corpus/fuzz_operator_mtx/,
// fuzz/regressions/fuzz_operator_mtx/) through `tetia apply`: each is applied (status 0) or
// refused with a message naming the file (status 2); never a crash.
TEST_F(CliRemapMethodsTest, OperatorFuzzInputsApplyOrFailCleanly) {
  const fs::path fuzz = fs::path(__FILE__).parent_path().parent_path() / "fuzz";
  // One cube of 6 tetrahedra and 8 nodes: the seeds need not fit it; one that is read but does
  // not fit is refused like a damaged one (status 2, the file named).
  tetia::TetMesh m = tetia::make_kuhn_mesh({1, 1, 1}, {0, 0, 0}, {1, 1, 1});
  tetia::write_msh(path("m.msh"), m, {{"x", std::vector<double>(m.num_cells(), 1.0)}},
                   {{"x", std::vector<double>(m.num_nodes(), 1.0)}});
  int seeds = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fuzz / kind / "fuzz_operator_mtx";
    if (!fs::exists(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string file = path("op.mtx");
      fs::copy_file(entry.path(), file, fs::copy_options::overwrite_existing);
      const Result r = run("apply " + file + " " + path("m.msh") + " " + path("m.msh") + " --field x");
      SCOPED_TRACE(entry.path().string());
      EXPECT_TRUE(r.status == 0 || r.status == 2) << r.status << " " << r.err;
      if (r.status == 2) {
        EXPECT_EQ(r.err.rfind("tetia: " + file, 0), 0u) << r.err;
      }
      seeds += kind == std::string("corpus");
    }
  }
  EXPECT_GE(seeds, 3);
}
