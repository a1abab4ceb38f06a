// test_remap.cpp -- conservative remap on a supermesh: P0 (constants reproduced, integrals
// conserved, both normalizations on partial overlaps), P1 Galerkin projection (linear fields
// reproduced, integrals conserved), the mixed mass matrix file, and convergence rates.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"
#include "support/remap_checks.hpp"

namespace {

using tetia::CandidateSearch;
using tetia::P0Normalization;
using tetia::Supermesh;
using tetia::SupermeshOptions;
using tetia::TetMesh;
using tetia::Vec3;

TetMesh kuhn(int n, Vec3 origin = {0, 0, 0}, double size = 1.0) {
  const double h = size / n;
  return tetia::make_kuhn_mesh({n, n, n}, origin, {h, h, h});
}

/// A Kuhn mesh of the unit cube with its interior nodes moved at random by up to 0.2 h along
/// each axis: a general unstructured mesh of the same domain.
TetMesh jittered(int n, unsigned seed) {
  TetMesh m = kuhn(n);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.2 / n, 0.2 / n);
  for (Vec3& p : m.nodes) {
    const bool interior = p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1;
    if (!interior) continue;
    p = p + Vec3{u(g), u(g), u(g)};
  }
  tetia::finalize(m, "jittered");
  EXPECT_EQ(m.reoriented_cells, 0u);
  return m;
}

Supermesh make_supermesh(const TetMesh& src, const TetMesh& tgt, bool keep) {
  SupermeshOptions o;
  o.keep_polyhedra = keep;
  o.threads = 2;
  return tetia::supermesh(src, tgt, o);
}

using tetia::testsupport::at_nodes;

double smooth(Vec3 p) { return std::sin(p.x) * std::cos(p.y) * std::exp(p.z); }
double linear(Vec3 p) { return 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z; }

// ---------------------------------------------------------------------------------------------
// P0

TEST(RemapP0, ConstantReproducedAndIntegralConservedOnTheSameDomain) {
  const TetMesh src = jittered(4, 1);
  const TetMesh tgt = jittered(5, 2);
  const Supermesh s = make_supermesh(src, tgt, false);
  tetia::testsupport::expect_p0_constant_and_conservation(s, src, tgt);
}

TEST(RemapP0, PartialCoverageBothNormalizations) {
  // The source covers part of the target (a smaller, offset box); the target also has cells
  // the source does not reach.
  const TetMesh src = kuhn(4, {0.3, 0.25, 0.2}, 0.5);
  const TetMesh tgt = kuhn(5);
  const Supermesh s = make_supermesh(src, tgt, false);
  const auto cov = tetia::covered_volumes(s);
  tetia::testsupport::expect_partial_coverage(s, src, tgt, cov, 0.125);
}

TEST(RemapP0, RejectsWrongSizes) {
  const TetMesh m = kuhn(2);
  const Supermesh s = make_supermesh(m, m, false);
  const std::vector<double> wrong(m.num_cells() + 1, 1.0);
  EXPECT_THROW(tetia::remap_p0(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p1(s, wrong), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// P1

TEST(RemapP1, LinearFieldReproducedAndIntegralConserved) {
  const TetMesh src = jittered(3, 3);
  const TetMesh tgt = jittered(4, 4);
  const Supermesh s = make_supermesh(src, tgt, true);
  tetia::testsupport::expect_p1_linear_conservation_identity(s, make_supermesh(src, src, true), src, tgt, linear,
                                                              smooth);
}

TEST(RemapP1, PartialCoverageConservesTheIntegralOverTheOverlap) {
  const TetMesh src = kuhn(3, {0.2, 0.3, 0.1}, 0.6);
  const TetMesh tgt = jittered(4, 5);
  const Supermesh s = make_supermesh(src, tgt, true);
  const auto in = at_nodes(src, smooth);
  const auto out = tetia::remap_p1(s, in);
  const double si = tetia::integral_p1(src, in), ti = tetia::integral_p1(tgt, out);
  EXPECT_NEAR(ti, si, 1e-12 * std::abs(si));
}

TEST(RemapP1, TargetNodesInNoCell) {
  // A target mesh with a node no cell uses: it gets 0, the rest is unaffected.
  const TetMesh src = jittered(3, 14);
  TetMesh tgt = jittered(3, 15);
  tgt.nodes.push_back({0.5, 0.5, 0.5});
  tetia::finalize(tgt, "with an unused node");
  const Supermesh s = make_supermesh(src, tgt, true);
  const auto out = tetia::remap_p1(s, at_nodes(src, linear));
  for (std::size_t i = 0; i + 1 < tgt.num_nodes(); ++i) EXPECT_NEAR(out[i], linear(tgt.nodes[i]), 1e-10);
  EXPECT_EQ(out.back(), 0.0);
}

TEST(RemapP1, NeedsPolyhedra) {
  const TetMesh m = kuhn(2);
  const Supermesh s = make_supermesh(m, m, false);
  const auto in = at_nodes(m, linear);
  try {
    tetia::remap_p1(s, in);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keep_polyhedra"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tetia::write_mixed_mass_matrix(s, std::filesystem::temp_directory_path() / "tetia_never.mtx"),
               std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// The mixed mass matrix file.

TEST(MixedMassMatrix, MatrixMarketFileIsWrittenAndParsable) {
  const TetMesh src = jittered(2, 8);
  const TetMesh tgt = jittered(3, 9);
  const Supermesh s = make_supermesh(src, tgt, true);
  const auto file = std::filesystem::temp_directory_path() /
                    ("tetia_mixed_mass_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".mtx");
  tetia::write_mixed_mass_matrix(s, file);
  std::ifstream in(file);
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "%%MatrixMarket matrix coordinate real general");
  int comments = 0;
  while (in.peek() == '%') {
    std::getline(in, line);
    ++comments;
  }
  EXPECT_GE(comments, 1);
  long rows = 0, cols = 0, nnz = 0;
  in >> rows >> cols >> nnz;
  EXPECT_EQ(rows, static_cast<long>(tgt.num_nodes()));
  EXPECT_EQ(cols, static_cast<long>(src.num_nodes()));
  ASSERT_GT(nnz, 0);
  std::vector<double> row_sum(static_cast<std::size_t>(rows), 0.0), col_sum(static_cast<std::size_t>(cols), 0.0);
  double total = 0.0;
  long count = 0;
  long i = 0, j = 0;
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
  // The domains coincide: the entries add up to the volume, row sums are the integrals of the
  // target basis functions (lumped target mass) and column sums those of the source ones.
  EXPECT_NEAR(total, 1.0, 1e-13);
  const auto lumped = [](const TetMesh& m) {
    std::vector<double> l(m.num_nodes(), 0.0);
    for (std::size_t c = 0; c < m.num_cells(); ++c)
      for (const auto n : m.cells[c]) l[static_cast<std::size_t>(n)] += m.volumes[c] / 4;
    return l;
  };
  const auto lt = lumped(tgt), ls = lumped(src);
  for (std::size_t r = 0; r < row_sum.size(); ++r) EXPECT_NEAR(row_sum[r], lt[r], 1e-14);
  for (std::size_t c = 0; c < col_sum.size(); ++c) EXPECT_NEAR(col_sum[c], ls[c], 1e-14);
  std::filesystem::remove(file);
}

// ---------------------------------------------------------------------------------------------
// Convergence: sin(x) cos(y) exp(z) on the unit cube, from a source mesh to a target mesh 1.5
// times coarser, refined twice. L2 errors against the function on the target.

TEST(RemapConvergence, P0FirstOrderP1SecondOrder) {
  std::printf("  %-4s %8s %8s %12s %6s\n", "", "source", "target", "L2 error", "rate");
  double prev = 0.0;
  std::vector<double> rates;
  for (const int n : {2, 4, 8}) {
    const TetMesh src = kuhn(3 * n / 2);
    const TetMesh tgt = jittered(n, 11);
    const Supermesh s = make_supermesh(src, tgt, false);
    const auto out = tetia::remap_p0(s, tetia::average_over_cells(src, smooth));
    const double e = tetia::l2_error_p0(tgt, out, smooth);
    const double rate = prev > 0.0 ? std::log2(prev / e) : 0.0;
    if (prev > 0.0) rates.push_back(rate);
    std::printf("  %-4s %8zu %8zu %12.4e %6.2f\n", "P0", src.num_cells(), tgt.num_cells(), e, rate);
    prev = e;
  }
  for (const double r : rates) {
    EXPECT_GT(r, 0.8);
    EXPECT_LT(r, 1.3);
  }
  prev = 0.0;
  rates.clear();
  for (const int n : {2, 4, 8}) {
    const TetMesh src = kuhn(3 * n / 2);
    const TetMesh tgt = jittered(n, 12);
    const Supermesh s = make_supermesh(src, tgt, true);
    const auto out = tetia::remap_p1(s, at_nodes(src, smooth));
    const double e = tetia::l2_error_p1(tgt, out, smooth);
    const double rate = prev > 0.0 ? std::log2(prev / e) : 0.0;
    if (prev > 0.0) rates.push_back(rate);
    std::printf("  %-4s %8zu %8zu %12.4e %6.2f\n", "P1", src.num_cells(), tgt.num_cells(), e, rate);
    prev = e;
  }
  for (const double r : rates) {
    EXPECT_GT(r, 1.7);
    EXPECT_LT(r, 2.4);
  }
}

TEST(RemapHelpers, IntegralsAndQuadrature) {
  const TetMesh m = jittered(3, 13);
  // Quadrature exact for degree 5: the average of x^2 y^3 over the cube is 1/3 * 1/4.
  const auto avg = tetia::average_over_cells(m, [](Vec3 p) { return p.x * p.x * p.y * p.y * p.y; });
  EXPECT_NEAR(tetia::integral_p0(m, avg), 1.0 / 12.0, 1e-15);
  // P1 integral of a linear field is exact; its L2 error against itself is zero.
  const auto lin = at_nodes(m, linear);
  EXPECT_NEAR(tetia::integral_p1(m, lin), 1.0 + 1.0 - 1.5 + 0.25, 1e-14);
  EXPECT_NEAR(tetia::l2_error_p1(m, lin, linear), 0.0, 1e-14);
  // The L2 distance from a constant to x on the unit cube: sqrt(integral (x - 1/2)^2) = sqrt(1/12).
  const std::vector<double> half(m.num_cells(), 0.5);
  EXPECT_NEAR(tetia::l2_error_p0(m, half, [](Vec3 p) { return p.x; }), std::sqrt(1.0 / 12.0), 1e-14);
}

}  // namespace
