// test_remap2d.cpp -- conservative remap between triangular meshes: P0 (constants reproduced,
// integrals conserved, both normalizations on partial overlaps), P1 Galerkin projection (linear
// fields reproduced, integrals conserved), the mixed mass matrix file, the quadrature rule, and
// convergence rates for sin(x) cos(y). The 2D counterpart of test_remap.cpp.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"
#include "support/remap_checks.hpp"

namespace {

using tetia::P0Normalization;
using tetia::Supermesh2;
using tetia::SupermeshOptions;
using tetia::TriMesh;
using tetia::Vec2;

TriMesh grid(int n, Vec2 origin = {0, 0}, double size = 1.0) {
  const double h = size / n;
  return tetia::make_structured_tri_mesh({n, n}, origin, {h, h});
}

/// A structured mesh of the unit square with its interior nodes moved at random by up to 0.2 h
/// along each axis: a general unstructured mesh of the same domain.
TriMesh jittered(int n, unsigned seed) {
  TriMesh m = grid(n);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.2 / n, 0.2 / n);
  for (Vec2& p : m.nodes) {
    if (!(p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1)) continue;
    p = p + Vec2{u(g), u(g)};
  }
  tetia::finalize(m, "jittered");
  EXPECT_EQ(m.reoriented_cells, 0u);
  return m;
}

Supermesh2 make_supermesh(const TriMesh& src, const TriMesh& tgt, bool keep) {
  SupermeshOptions o;
  o.keep_polyhedra = keep;
  o.threads = 2;
  return tetia::supermesh(src, tgt, o);
}

using tetia::testsupport::at_nodes;

double smooth(Vec2 p) { return std::sin(p.x) * std::cos(p.y); }
double linear(Vec2 p) { return 1.0 + 2.0 * p.x - 3.0 * p.y; }

// ---------------------------------------------------------------------------------------------
// P0

TEST(Remap2DP0, ConstantReproducedAndIntegralConservedOnTheSameDomain) {
  const TriMesh src = jittered(9, 1);
  const TriMesh tgt = jittered(11, 2);
  const Supermesh2 s = make_supermesh(src, tgt, false);
  tetia::testsupport::expect_p0_constant_and_conservation(s, src, tgt);
  // Gmsh meshes of a disk, both ways.
  const TriMesh a = tetia::generate_disk({1.0, 0.5}, 0.8, 0.1), b = tetia::generate_disk({1.0, 0.5}, 0.8, 0.13);
  const auto in_a = tetia::average_over_cells(a, smooth);
  const auto out_b = tetia::remap_p0(make_supermesh(a, b, false), in_a);
  const double ia = tetia::integral_p0(a, in_a), ib = tetia::integral_p0(b, out_b);
  // Not the same polygonal domain: the boundary chords differ, so compare over the overlap.
  const Supermesh2 ab = make_supermesh(a, b, false);
  double overlap = 0.0;
  for (const auto& p : ab.pieces) overlap += in_a[static_cast<std::size_t>(p.source)] * p.area;
  EXPECT_NEAR(ib, overlap, 1e-13 * std::abs(overlap));
  EXPECT_NEAR(ib, ia, 1e-2 * std::abs(ia));
}

TEST(Remap2DP0, PartialCoverageBothNormalizations) {
  const TriMesh src = grid(4, {0.3, 0.25}, 0.5);
  const TriMesh tgt = grid(5);
  const Supermesh2 s = make_supermesh(src, tgt, false);
  const auto cov = tetia::covered_areas(s);
  tetia::testsupport::expect_partial_coverage(s, src, tgt, cov, 0.25);
}

TEST(Remap2DP0, RejectsWrongSizes) {
  const TriMesh m = grid(2);
  const Supermesh2 s = make_supermesh(m, m, false);
  const std::vector<double> wrong(m.num_cells() + 1, 1.0);
  EXPECT_THROW(tetia::remap_p0(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p1(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::integral_p0(m, wrong), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// P1

TEST(Remap2DP1, LinearFieldReproducedAndIntegralConserved) {
  const TriMesh src = jittered(7, 3);
  const TriMesh tgt = jittered(9, 4);
  const Supermesh2 s = make_supermesh(src, tgt, true);
  tetia::testsupport::expect_p1_linear_conservation_identity(s, make_supermesh(src, src, true), src, tgt, linear,
                                                              smooth);
  // Gmsh meshes of one rectangle (non-matching, unstructured).
  const TriMesh a = tetia::generate_rectangle({0, 0}, {2, 1}, 0.1), b = tetia::generate_rectangle({0, 0}, {2, 1}, 0.13);
  const auto lb = tetia::remap_p1(make_supermesh(a, b, true), at_nodes(a, linear));
  double worst = 0.0;
  for (std::size_t i = 0; i < b.num_nodes(); ++i) worst = std::max(worst, std::abs(lb[i] - linear(b.nodes[i])));
  EXPECT_LT(worst, 1e-10);
}

TEST(Remap2DP1, PartialCoverageConservesTheIntegralOverTheOverlap) {
  const TriMesh src = grid(5, {0.2, 0.3}, 0.6);
  const TriMesh tgt = jittered(8, 5);
  const Supermesh2 s = make_supermesh(src, tgt, true);
  const auto in = at_nodes(src, smooth);
  const auto out = tetia::remap_p1(s, in);
  const double si = tetia::integral_p1(src, in), ti = tetia::integral_p1(tgt, out);
  EXPECT_NEAR(ti, si, 1e-12 * std::abs(si));
}

TEST(Remap2DP1, TargetNodesInNoCell) {
  const TriMesh src = jittered(5, 14);
  TriMesh tgt = jittered(6, 15);
  tgt.nodes.push_back({0.5, 0.5});
  tetia::finalize(tgt, "with an unused node");
  const auto out = tetia::remap_p1(make_supermesh(src, tgt, true), at_nodes(src, linear));
  for (std::size_t i = 0; i + 1 < tgt.num_nodes(); ++i) EXPECT_NEAR(out[i], linear(tgt.nodes[i]), 1e-10);
  EXPECT_EQ(out.back(), 0.0);
}

TEST(Remap2DP1, NeedsPolygons) {
  const TriMesh m = grid(2);
  const Supermesh2 s = make_supermesh(m, m, false);
  try {
    tetia::remap_p1(s, at_nodes(m, linear));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no polygons"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("keep_polyhedra"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tetia::write_mixed_mass_matrix(s, std::filesystem::temp_directory_path() / "tetia_never2d.mtx"),
               std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// The mixed mass matrix file.

TEST(MixedMassMatrix2D, MatrixMarketFileIsWrittenAndParsable) {
  const TriMesh src = jittered(4, 8);
  const TriMesh tgt = jittered(5, 9);
  const Supermesh2 s = make_supermesh(src, tgt, true);
  const auto file = std::filesystem::temp_directory_path() /
                    ("tetia_mixed_mass_2d_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".mtx");
  tetia::write_mixed_mass_matrix(s, file);
  std::ifstream in(file);
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "%%MatrixMarket matrix coordinate real general");
  while (in.peek() == '%') std::getline(in, line);
  long rows = 0, cols = 0, nnz = 0;
  in >> rows >> cols >> nnz;
  EXPECT_EQ(rows, static_cast<long>(tgt.num_nodes()));
  EXPECT_EQ(cols, static_cast<long>(src.num_nodes()));
  std::vector<double> row_sum(static_cast<std::size_t>(rows), 0.0), col_sum(static_cast<std::size_t>(cols), 0.0);
  double total = 0.0;
  long count = 0, i = 0, j = 0;
  double v = 0.0;
  while (in >> i >> j >> v) {
    ASSERT_GE(i, 1);
    ASSERT_LE(i, rows);
    ASSERT_GE(j, 1);
    ASSERT_LE(j, cols);
    row_sum[static_cast<std::size_t>(i - 1)] += v;
    col_sum[static_cast<std::size_t>(j - 1)] += v;
    total += v;
    ++count;
  }
  EXPECT_TRUE(in.eof());
  EXPECT_EQ(count, nnz);
  // The domains coincide: the entries add up to the area, row sums are the integrals of the
  // target basis functions (lumped target mass, area / 3 per vertex) and column sums those of
  // the source ones.
  EXPECT_NEAR(total, 1.0, 1e-13);
  const auto lumped = [](const TriMesh& m) {
    std::vector<double> l(m.num_nodes(), 0.0);
    for (std::size_t c = 0; c < m.num_cells(); ++c)
      for (const auto n : m.cells[c]) l[static_cast<std::size_t>(n)] += m.areas[c] / 3;
    return l;
  };
  const auto lt = lumped(tgt), ls = lumped(src);
  for (std::size_t r = 0; r < row_sum.size(); ++r) EXPECT_NEAR(row_sum[r], lt[r], 1e-14);
  for (std::size_t c = 0; c < col_sum.size(); ++c) EXPECT_NEAR(col_sum[c], ls[c], 1e-14);
  std::filesystem::remove(file);
}

// ---------------------------------------------------------------------------------------------
// Convergence: sin(x) cos(y) on the unit square, from a structured source mesh 1.5 times finer
// than a jittered target, refined three times. L2 errors against the function on the target.

TEST(Remap2DConvergence, P0FirstOrderP1SecondOrder) {
  for (const int order : {0, 1}) {
    std::printf("  %-4s %8s %8s %12s %6s\n", "", "source", "target", "L2 error", "rate");
    double prev = 0.0;
    std::vector<double> rates;
    for (const int n : {8, 16, 32, 64}) {
      const TriMesh src = grid(3 * n / 2);
      const TriMesh tgt = jittered(n, order == 0 ? 11 : 12);
      const Supermesh2 s = make_supermesh(src, tgt, order == 1);
      double e = 0.0;
      if (order == 0) {
        e = tetia::l2_error_p0(tgt, tetia::remap_p0(s, tetia::average_over_cells(src, smooth)), smooth);
      } else {
        e = tetia::l2_error_p1(tgt, tetia::remap_p1(s, at_nodes(src, smooth)), smooth);
      }
      const double rate = prev > 0.0 ? std::log2(prev / e) : 0.0;
      if (prev > 0.0) rates.push_back(rate);
      std::printf("  P%-3d %8zu %8zu %12.4e %6.2f\n", order, src.num_cells(), tgt.num_cells(), e, rate);
      prev = e;
    }
    for (const double r : rates) {
      EXPECT_GT(r, order == 0 ? 0.85 : 1.8);
      EXPECT_LT(r, order == 0 ? 1.2 : 2.3);
    }
  }
}

TEST(Remap2DHelpers, IntegralsAndQuadrature) {
  const TriMesh m = jittered(5, 13);
  // The rule is exact for degree 6: the averages of x^2 y^3 and x^3 y^3 over the square.
  const auto a5 = tetia::average_over_cells(m, [](Vec2 p) { return p.x * p.x * p.y * p.y * p.y; });
  EXPECT_NEAR(tetia::integral_p0(m, a5), 1.0 / 12.0, 1e-15);
  const auto a6 = tetia::average_over_cells(m, [](Vec2 p) { return p.x * p.x * p.x * p.y * p.y * p.y; });
  EXPECT_NEAR(tetia::integral_p0(m, a6), 1.0 / 16.0, 1e-15);
  // On a single triangle, a degree-6 monomial against its exact integral: over the reference
  // triangle, x^a y^b integrates to a! b! / (a + b + 2)!.
  TriMesh ref;
  ref.nodes = {{0, 0}, {1, 0}, {0, 1}};
  ref.cells = {{0, 1, 2}};
  tetia::finalize(ref);
  const auto x2y4 = tetia::average_over_cells(ref, [](Vec2 p) { return p.x * p.x * std::pow(p.y, 4); });
  EXPECT_NEAR(x2y4[0] * 0.5, 2.0 * 24.0 / 40320.0, 1e-17);
  const auto lin = at_nodes(m, linear);
  EXPECT_NEAR(tetia::integral_p1(m, lin), 1.0 + 1.0 - 1.5, 1e-14);
  EXPECT_NEAR(tetia::l2_error_p1(m, lin, linear), 0.0, 1e-14);
  // The L2 distance from 1/2 to x on the unit square: sqrt(1/12).
  const std::vector<double> half(m.num_cells(), 0.5);
  EXPECT_NEAR(tetia::l2_error_p0(m, half, [](Vec2 p) { return p.x; }), std::sqrt(1.0 / 12.0), 1e-14);
}

}  // namespace
