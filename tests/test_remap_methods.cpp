// test_remap_methods.cpp -- the remap methods of tetia/remap_methods.hpp, in 3D and 2D alike
// (typed tests over the dimension): conservation for every method; linear reproduction where a
// method promises it; the bounds of lumped and bounded P1 checked at every node against bounds
// computed here from the pieces; boundedness of the limited reconstruction on steps and random
// data at every cell; second-order convergence of the reconstruction; discontinuous P1 as the
// identity on its own space.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/remap_methods.hpp"
#include "tetia/remap_operator.hpp"
#include "tetia/supermesh.hpp"

namespace {

using tetia::P0Normalization;
using tetia::P1Source;
using tetia::SupermeshOptions;

struct D3 {
  using Mesh = tetia::TetMesh;
  using Point = tetia::Vec3;
  using Result = tetia::Supermesh;
  static constexpr int nv = 4;
  static Mesh grid(int n, Point origin = {0, 0, 0}, double size = 1.0) {
    const double h = size / n;
    return tetia::make_kuhn_mesh({n, n, n}, origin, {h, h, h});
  }
  static bool interior(const Point& p) { return p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1; }
  static Point jitter(std::mt19937_64& g, double a) {
    std::uniform_real_distribution<double> u(-a, a);
    return {u(g), u(g), u(g)};
  }
  static const std::vector<double>& measures(const Mesh& m) { return m.volumes; }
  static double smooth(Point p) { return std::sin(p.x) * std::cos(p.y) * std::exp(p.z); }
  static double linear(Point p) { return 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z; }
  static double step(Point p) { return p.x + 0.3 * p.y + 0.2 * p.z > 0.61 ? 1.0 : 0.0; }
  static double measure(const tetia::SupermeshPiece& p) { return p.volume; }
  static int convergence_sizes(int i) { return i == 0 ? 4 : i == 1 ? 8 : 16; }
};

struct D2 {
  using Mesh = tetia::TriMesh;
  using Point = tetia::Vec2;
  using Result = tetia::Supermesh2;
  static constexpr int nv = 3;
  static Mesh grid(int n, Point origin = {0, 0}, double size = 1.0) {
    const double h = size / n;
    return tetia::make_structured_tri_mesh({n, n}, origin, {h, h});
  }
  static bool interior(const Point& p) { return p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1; }
  static Point jitter(std::mt19937_64& g, double a) {
    std::uniform_real_distribution<double> u(-a, a);
    return {u(g), u(g)};
  }
  static const std::vector<double>& measures(const Mesh& m) { return m.areas; }
  static double smooth(Point p) { return std::sin(p.x) * std::cos(p.y); }
  static double linear(Point p) { return 1.0 + 2.0 * p.x - 3.0 * p.y; }
  static double step(Point p) { return p.x + 0.3 * p.y > 0.61 ? 1.0 : 0.0; }
  static double measure(const tetia::SupermeshPiece2& p) { return p.area; }
  static int convergence_sizes(int i) { return i == 0 ? 8 : i == 1 ? 16 : 32; }
};

template <class D>
class RemapMethods : public ::testing::Test {
 public:
  using Mesh = typename D::Mesh;
  using Point = typename D::Point;

  /// The unit cube (square) meshed with its interior nodes moved at random by up to 0.2 h.
  static Mesh jittered(int n, unsigned seed) {
    Mesh m = D::grid(n);
    std::mt19937_64 g(seed);
    for (Point& p : m.nodes)
      if (D::interior(p)) p = p + D::jitter(g, 0.2 / n);
    tetia::finalize(m, "jittered");
    EXPECT_EQ(m.reoriented_cells, 0u);
    return m;
  }
  static typename D::Result make(const Mesh& src, const Mesh& tgt) {
    SupermeshOptions o;
    o.keep_mixed_mass = true;
    o.threads = 2;
    return tetia::supermesh(src, tgt, o);
  }
  template <class F>
  static std::vector<double> at_nodes(const Mesh& m, F f) {
    std::vector<double> v(m.num_nodes());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = f(m.nodes[i]);
    return v;
  }
  static Point centroid(const Mesh& m, std::size_t c) {
    const auto T = m.cell(c);
    Point p = T[0];
    for (int k = 1; k < D::nv; ++k) p = p + T[k];
    return (1.0 / D::nv) * p;
  }
  static std::vector<double> random_values(std::size_t n, unsigned seed) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(-1.0, 2.0);
    std::vector<double> v(n);
    for (double& x : v) x = u(g);
    return v;
  }
  /// Sum of the lumped target masses times the values: the P1 integral.
  static double integral(const Mesh& m, const std::vector<double>& u) { return tetia::integral_p1(m, u); }
  /// The local bounds computed here from the pieces and the covered measures: per target node,
  /// min and max of the source nodal values on the source cells of the pieces of the target
  /// cells around it; 0 added where one of those target cells is not fully covered; 0 and 0
  /// where none is covered at all.
  static tetia::P1Bounds expected_bounds(const typename D::Result& s, const std::vector<double>& u) {
    const Mesh& tgt = *s.target;
    const Mesh& src = *s.source;
    std::vector<double> lo(tgt.num_nodes(), std::numeric_limits<double>::infinity());
    std::vector<double> hi(tgt.num_nodes(), -std::numeric_limits<double>::infinity());
    std::vector<double> cov(tgt.num_cells(), 0.0);
    for (const auto& p : s.pieces) {
      cov[static_cast<std::size_t>(p.target)] += D::measure(p);
      for (const auto tn : tgt.cells[static_cast<std::size_t>(p.target)])
        for (const auto sn : src.cells[static_cast<std::size_t>(p.source)]) {
          lo[static_cast<std::size_t>(tn)] = std::min(lo[static_cast<std::size_t>(tn)], u[static_cast<std::size_t>(sn)]);
          hi[static_cast<std::size_t>(tn)] = std::max(hi[static_cast<std::size_t>(tn)], u[static_cast<std::size_t>(sn)]);
        }
    }
    std::vector<char> partial(tgt.num_nodes(), 0);
    for (std::size_t t = 0; t < tgt.num_cells(); ++t)
      if (cov[t] < D::measures(tgt)[t] * (1.0 - 1e-6))
        for (const auto tn : tgt.cells[t]) partial[static_cast<std::size_t>(tn)] = 1;
    for (std::size_t i = 0; i < lo.size(); ++i) {
      if (!(lo[i] <= hi[i])) {
        lo[i] = hi[i] = 0.0;
      } else if (partial[i]) {
        lo[i] = std::min(lo[i], 0.0);
        hi[i] = std::max(hi[i], 0.0);
      }
    }
    return {lo, hi};
  }
  static void expect_within(const std::vector<double>& u, const tetia::P1Bounds& b, double tol, const char* what) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double slack = tol * std::max({1.0, std::abs(b.lower[i]), std::abs(b.upper[i])});
      if (!(u[i] >= b.lower[i] - slack && u[i] <= b.upper[i] + slack)) {
        if (bad++ < 5)
          ADD_FAILURE() << what << ": node " << i << " value " << u[i] << " outside [" << b.lower[i] << ", "
                        << b.upper[i] << "]";
      }
    }
    EXPECT_EQ(bad, 0u) << what;
  }
  static double load_total(const typename D::Result& s, const std::vector<double>& u) {
    const Eigen::VectorXd b = tetia::mixed_mass_matrix(s) * Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
    return b.sum();
  }
};

using Dimensions = ::testing::Types<D3, D2>;
struct DimensionNames {
  template <class T>
  static std::string GetName(int) {
    return std::is_same_v<T, D3> ? "3D" : "2D";
  }
};
TYPED_TEST_SUITE(RemapMethods, Dimensions, DimensionNames);

// ---------------------------------------------------------------------------------------------
// Lumped and bounded P1

TYPED_TEST(RemapMethods, LumpedAndBoundedConserveAndStayWithinTheLocalBounds) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  // The same domain, then a target shifted so that it is partly covered.
  for (const double shift : {0.0, 0.37}) {
    const auto src = T::jittered(D::nv == 4 ? 5 : 13, 1);
    auto tgt = T::jittered(D::nv == 4 ? 4 : 11, 2);
    for (auto& p : tgt.nodes) p.x += shift;
    tetia::finalize(tgt, "shifted");
    const auto s = T::make(src, tgt);
    for (int field = 0; field < 3; ++field) {
      const std::vector<double> u = field == 0   ? T::at_nodes(src, D::step)
                                    : field == 1 ? T::random_values(src.num_nodes(), 7)
                                                 : T::at_nodes(src, D::smooth);
      SCOPED_TRACE(::testing::Message() << "shift " << shift << " field " << field);
      const tetia::P1Bounds expected = T::expected_bounds(s, u);
      const tetia::P1Bounds got = tetia::p1_local_bounds(s, u);
      EXPECT_EQ(got.lower, expected.lower);
      EXPECT_EQ(got.upper, expected.upper);
      const double q = T::load_total(s, u);
      const auto lumped = tetia::remap_p1_lumped(s, u);
      const auto bounded = tetia::remap_p1_bounded(s, u);
      T::expect_within(lumped, expected, 0.0, "lumped");  // exactly: a step stays in [0, 1]
      T::expect_within(bounded, expected, 0.0, "bounded");
      EXPECT_NEAR(T::integral(tgt, lumped), q, 1e-14 * std::max(1.0, std::abs(q)));
      EXPECT_NEAR(T::integral(tgt, bounded), q, 1e-14 * std::max(1.0, std::abs(q)));
      if (shift == 0.0) {  // the same domain: the overlap integral is the source integral
        const double source_integral = T::integral(src, u);
        EXPECT_NEAR(q, source_integral, 1e-13 * std::max(1.0, std::abs(source_integral)));
      }
    }
  }
}

TYPED_TEST(RemapMethods, GalerkinOvershootsAStepWhereBoundedDoesNot) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = T::jittered(D::nv == 4 ? 8 : 24, 3);
  const auto tgt = T::jittered(D::nv == 4 ? 5 : 15, 4);
  const auto s = T::make(src, tgt);
  const auto u = T::at_nodes(src, D::step);
  const auto galerkin = tetia::remap_p1(s, u);
  const auto bounded = tetia::remap_p1_bounded(s, u);
  const auto [gmin, gmax] = std::minmax_element(galerkin.begin(), galerkin.end());
  const auto [bmin, bmax] = std::minmax_element(bounded.begin(), bounded.end());
  std::printf("  step: Galerkin in [%.4f, %.4f], bounded in [%.17g, %.17g]\n", *gmin, *gmax, *bmin, *bmax);
  EXPECT_LT(*gmin, -0.02);  // the case is one that needs the limiter
  EXPECT_GT(*gmax, 1.02);
  EXPECT_GE(*bmin, 0.0);
  EXPECT_LE(*bmax, 1.0);
}

TYPED_TEST(RemapMethods, BoundedReproducesLinearFieldsOnUnstructuredMeshes) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = T::jittered(D::nv == 4 ? 6 : 17, 5);
  const auto tgt = T::jittered(D::nv == 4 ? 5 : 12, 6);
  const auto s = T::make(src, tgt);
  const auto u = T::at_nodes(src, D::linear);
  const auto bounded = tetia::remap_p1_bounded(s, u);
  const auto exact = T::at_nodes(tgt, D::linear);
  double worst = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) worst = std::max(worst, std::abs(bounded[i] - exact[i]));
  EXPECT_LT(worst, 1e-10);
  // The lumped projection is first order: not exact for a linear field on a jittered mesh.
  const auto lumped = tetia::remap_p1_lumped(s, u);
  double lumped_worst = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) lumped_worst = std::max(lumped_worst, std::abs(lumped[i] - exact[i]));
  EXPECT_GT(lumped_worst, 1e-4);
}

// ---------------------------------------------------------------------------------------------
// Discontinuous P1

TYPED_TEST(RemapMethods, DiscontinuousReproducesLinearFieldsAndConservesPerCell) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = T::jittered(D::nv == 4 ? 5 : 14, 7);
  const auto tgt = T::jittered(D::nv == 4 ? 4 : 9, 8);
  const auto s = T::make(src, tgt);
  const auto u = T::at_nodes(src, D::linear);
  const auto dg = tetia::remap_p1_discontinuous(s, u);
  ASSERT_EQ(dg.size(), tgt.num_cells() * D::nv);
  double worst = 0.0;
  for (std::size_t c = 0; c < tgt.num_cells(); ++c)
    for (int k = 0; k < D::nv; ++k)
      worst = std::max(worst, std::abs(dg[c * D::nv + static_cast<std::size_t>(k)] -
                                       D::linear(tgt.nodes[static_cast<std::size_t>(tgt.cells[c][static_cast<std::size_t>(k)])])));
  EXPECT_LT(worst, 1e-12);
  // The same from the source given as a discontinuous field.
  const auto dg2 = tetia::remap_p1_discontinuous(s, tetia::discontinuous_from_nodes(src, u), P1Source::discontinuous);
  for (std::size_t i = 0; i < dg.size(); ++i) EXPECT_NEAR(dg2[i], dg[i], 1e-13);
  // Conservation of a random field, per target cell: the cell's integral equals its loads' sum.
  const auto r = T::random_values(src.num_nodes(), 9);
  const auto dr = tetia::remap_p1_discontinuous(s, r);
  const double q = T::load_total(s, r);
  EXPECT_NEAR(tetia::integral_discontinuous(tgt, dr), q, 1e-14 * std::max(1.0, std::abs(q)));
  EXPECT_NEAR(q, T::integral(src, r), 1e-13 * std::max(1.0, std::abs(q)));
  // Per cell: the average of the cell's values is its P0 remap (both are the cell's integral
  // over its measure).
  const auto p0 = tetia::remap_p0_from_discontinuous(s, tetia::discontinuous_from_nodes(src, r));
  for (std::size_t c = 0; c < tgt.num_cells(); ++c) {
    double mean = 0.0;
    for (int k = 0; k < D::nv; ++k) mean += dr[c * D::nv + static_cast<std::size_t>(k)] / D::nv;
    EXPECT_NEAR(mean, p0[c], 1e-12);
  }
}

TYPED_TEST(RemapMethods, DiscontinuousIsTheIdentityOnItsOwnSpace) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto m = T::jittered(D::nv == 4 ? 3 : 7, 10);
  const auto s = T::make(m, m);
  const auto u = T::random_values(m.num_cells() * D::nv, 11);
  const auto out = tetia::remap_p1_discontinuous(s, u, P1Source::discontinuous);
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_NEAR(out[i], u[i], 1e-12) << i;
  // And cell averages of it are the cells' means.
  const auto p0 = tetia::remap_p0_from_discontinuous(s, u);
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    double mean = 0.0;
    for (int k = 0; k < D::nv; ++k) mean += u[c * D::nv + static_cast<std::size_t>(k)] / D::nv;
    EXPECT_NEAR(p0[c], mean, 1e-12);
  }
}

TYPED_TEST(RemapMethods, SizesThatDoNotMatchThrow) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto m = T::jittered(2, 12);
  const auto s = T::make(m, m);
  const std::vector<double> wrong(3, 0.0);
  EXPECT_THROW(tetia::remap_p1_lumped(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p1_bounded(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p1_discontinuous(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p1_discontinuous(s, wrong, P1Source::discontinuous), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p0_from_discontinuous(s, wrong), std::invalid_argument);
  EXPECT_THROW(tetia::remap_p0_linear(s, wrong), std::invalid_argument);
  const std::vector<double> cells(m.num_cells(), 1.0);
  const std::vector<std::int32_t> negative(m.num_cells(), -1);
  EXPECT_THROW(tetia::remap_p0_linear(s, cells, P0Normalization::cell_volume, negative), std::invalid_argument);
  SupermeshOptions plain;
  const auto bare = tetia::supermesh(m, m, plain);
  EXPECT_THROW(tetia::remap_p1_bounded(bare, std::vector<double>(m.num_nodes(), 1.0)), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Linear reconstruction of cell averages

TYPED_TEST(RemapMethods, LinearReconstructionConservesAndIsBounded) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = T::jittered(D::nv == 4 ? 7 : 19, 13);
  const auto tgt = T::jittered(D::nv == 4 ? 5 : 12, 14);
  const auto s = T::make(src, tgt);
  for (int field = 0; field < 3; ++field) {
    SCOPED_TRACE(field);
    std::vector<double> u(src.num_cells());
    if (field == 2) u = T::random_values(src.num_cells(), 15);
    else
      for (std::size_t c = 0; c < u.size(); ++c) u[c] = (field == 0 ? D::step : D::smooth)(T::centroid(src, c));
    const auto out = tetia::remap_p0_linear(s, u);
    const double in_integral = tetia::integral_p0(src, u);
    EXPECT_NEAR(tetia::integral_p0(tgt, out), in_integral, 1e-13 * std::max(1.0, std::abs(in_integral)));
    // Bounded by the source's extremes at every target cell; for the step, by 0 and 1.
    const auto [lo, hi] = std::minmax_element(u.begin(), u.end());
    for (std::size_t c = 0; c < out.size(); ++c) {
      EXPECT_GE(out[c], *lo - 1e-14) << c;
      EXPECT_LE(out[c], *hi + 1e-14) << c;
    }
  }
}

TYPED_TEST(RemapMethods, LinearReconstructionOfALinearFieldIsExactAwayFromTheBoundary) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = D::grid(D::nv == 4 ? 6 : 16);
  const auto tgt = T::jittered(D::nv == 4 ? 5 : 11, 16);
  const auto s = T::make(src, tgt);
  std::vector<double> u(src.num_cells());
  for (std::size_t c = 0; c < u.size(); ++c) u[c] = D::linear(T::centroid(src, c));
  const auto out = tetia::remap_p0_linear(s, u);
  // Target cells whose sources are all interior (no vertex on the boundary): exact.
  std::vector<char> boundary_cell(src.num_cells(), 0);
  for (std::size_t c = 0; c < src.num_cells(); ++c)
    for (const auto v : src.cells[c]) boundary_cell[c] |= !D::interior(src.nodes[static_cast<std::size_t>(v)]);
  std::vector<char> touches_boundary(tgt.num_cells(), 0);
  for (const auto& p : s.pieces)
    touches_boundary[static_cast<std::size_t>(p.target)] |= boundary_cell[static_cast<std::size_t>(p.source)];
  std::size_t checked = 0;
  for (std::size_t c = 0; c < tgt.num_cells(); ++c) {
    if (touches_boundary[c]) continue;
    ++checked;
    EXPECT_NEAR(out[c], D::linear(T::centroid(tgt, c)), 1e-12) << c;
  }
  EXPECT_GT(checked, 0u);
}

TYPED_TEST(RemapMethods, LinearReconstructionConvergesAtSecondOrder) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  // The error in the target's cell averages (discrete L2: sqrt(sum |T| (u_T - avg_T f)^2)),
  // against plain P0 remap of the same averages: over all cells, and over the interior (target
  // cells none of whose source cells has a vertex on the boundary). The limiter keeps the
  // reconstruction within the neighbours' averages, which at a boundary vertex (outside its
  // neighbours' centroids) clips even a linear field: first order in a layer of cells one
  // deep, so the whole domain tends to 1.5 and the interior to 2.
  double prev[2][2] = {{0, 0}, {0, 0}};
  std::vector<double> rates[2][2];
  std::printf("  %-7s %8s %8s %12s %6s %12s %6s\n", "", "source", "target", "L2 all", "rate", "L2 inside", "rate");
  for (int level = 0; level < 3; ++level) {
    const int n = D::convergence_sizes(level);
    const auto src = T::jittered(3 * n / 2, 17);
    const auto tgt = T::jittered(n, 18);
    const auto s = T::make(src, tgt);
    const auto in = tetia::average_over_cells(src, D::smooth);
    const auto exact = tetia::average_over_cells(tgt, D::smooth);
    std::vector<char> boundary_source(src.num_cells(), 0), near_boundary(tgt.num_cells(), 0);
    for (std::size_t c = 0; c < src.num_cells(); ++c)
      for (const auto v : src.cells[c]) boundary_source[c] |= !D::interior(src.nodes[static_cast<std::size_t>(v)]);
    for (const auto& p : s.pieces)
      near_boundary[static_cast<std::size_t>(p.target)] |= boundary_source[static_cast<std::size_t>(p.source)];
    const std::vector<double> outs[2] = {tetia::remap_p0(s, in), tetia::remap_p0_linear(s, in)};
    for (int m = 0; m < 2; ++m) {
      double e[2] = {0.0, 0.0};
      for (std::size_t c = 0; c < exact.size(); ++c) {
        const double term = D::measures(tgt)[c] * std::pow(outs[m][c] - exact[c], 2);
        e[0] += term;
        if (!near_boundary[c]) e[1] += term;
      }
      double rate[2];
      for (int r = 0; r < 2; ++r) {
        e[r] = std::sqrt(e[r]);
        rate[r] = prev[m][r] > 0.0 ? std::log2(prev[m][r] / e[r]) : 0.0;
        if (prev[m][r] > 0.0) rates[m][r].push_back(rate[r]);
        prev[m][r] = e[r];
      }
      std::printf("  %-7s %8zu %8zu %12.4e %6.2f %12.4e %6.2f\n", m == 0 ? "P0" : "linear", src.num_cells(),
                  tgt.num_cells(), e[0], rate[0], e[1], rate[1]);
    }
  }
  // Measured (3D; 2D): all cells 1.51, 1.56; 1.61, 1.20. Inside 1.22, 1.59; 1.92, 1.86 (the 3D
  // interior is a few cells deep at the coarse levels). Plain P0 is first order.
  for (const double r : rates[0][0]) EXPECT_LT(r, 1.4);
  for (const double r : rates[1][0]) EXPECT_GT(r, 1.1);
  EXPECT_GT(rates[1][1].back(), 1.5);
  EXPECT_LT(prev[1][0] * 5.0, prev[0][0]);  // the finest level: linear well below plain P0
}

TYPED_TEST(RemapMethods, LinearReconstructionByGroupsKeepsGroupsWhole) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  // Groups of consecutive simplices (as a split hexahedron's): the result is the same as for a
  // source whose values are equal within each group, and conservative.
  const auto src = T::jittered(D::nv == 4 ? 4 : 10, 19);
  const auto tgt = T::jittered(D::nv == 4 ? 3 : 7, 20);
  const auto s = T::make(src, tgt);
  const std::size_t per = D::nv == 4 ? 6 : 2;
  std::vector<std::int32_t> groups(src.num_cells());
  std::vector<double> u(src.num_cells());
  for (std::size_t c = 0; c < groups.size(); ++c) {
    groups[c] = static_cast<std::int32_t>(c / per);
    u[c] = D::smooth(T::centroid(src, c - c % per));
  }
  const auto out = tetia::remap_p0_linear(s, u, P0Normalization::cell_volume, groups);
  EXPECT_NEAR(tetia::integral_p0(tgt, out), tetia::integral_p0(src, u), 1e-13);
  const auto [lo, hi] = std::minmax_element(u.begin(), u.end());
  for (const double v : out) {
    EXPECT_GE(v, *lo - 1e-14);
    EXPECT_LE(v, *hi + 1e-14);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Operators and coverage

namespace {
std::vector<double> times(const tetia::SparseMatrix& w, const std::vector<double>& u) {
  const Eigen::VectorXd r = w * Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  return {r.data(), r.data() + r.size()};
}
void expect_close(const std::vector<double>& got, const std::vector<double>& want, double tol, const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  double scale = 0.0;
  for (const double w : want) scale = std::max(scale, std::abs(w));
  std::size_t bad = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    if (!(std::abs(got[i] - want[i]) <= tol * std::max(1.0, scale)) && bad++ < 5)
      ADD_FAILURE() << what << ": entry " << i << ": " << got[i] << " against " << want[i];
  EXPECT_EQ(bad, 0u) << what;
}
}  // namespace

// Each linear method's operator applied to random fields gives the method's values (to
// rounding), on a target the source covers only partly (shifted by 0.37), both normalizations.
TYPED_TEST(RemapMethods, OperatorsApplyTheirMethods) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  const auto src = T::jittered(D::nv == 4 ? 4 : 11, 21);
  auto tgt = T::jittered(D::nv == 4 ? 3 : 8, 22);
  for (auto& p : tgt.nodes) p.x += 0.37;
  tetia::finalize(tgt, "shifted");
  const auto s = T::make(src, tgt);
  const auto cells = T::random_values(src.num_cells(), 23);
  const auto nodes = T::random_values(src.num_nodes(), 24);
  const auto dg = T::random_values(src.num_cells() * D::nv, 25);
  for (const auto n : {tetia::P0Normalization::cell_volume, tetia::P0Normalization::covered_volume}) {
    expect_close(times(tetia::p0_operator(s, n), cells), tetia::remap_p0(s, cells, n), 1e-14, "p0");
    expect_close(times(tetia::p0_from_discontinuous_operator(s, n), dg), tetia::remap_p0_from_discontinuous(s, dg, n),
                 1e-14, "p0 from discontinuous");
  }
  expect_close(times(tetia::p1_lumped_operator(s), nodes), tetia::remap_p1_lumped(s, nodes), 1e-14, "lumped");
  expect_close(times(tetia::p1_discontinuous_operator(s), nodes), tetia::remap_p1_discontinuous(s, nodes), 1e-12,
               "discontinuous");
  expect_close(times(tetia::p1_discontinuous_operator(s, P1Source::discontinuous), dg),
               tetia::remap_p1_discontinuous(s, dg, P1Source::discontinuous), 1e-12, "discontinuous from discontinuous");
  // Coverage: the cells' against the covered measures computed here; the nodes' is the lumped
  // value of a field of ones, and 1 where the node's cells are all covered.
  const auto cov = tetia::cell_coverage(s);
  std::vector<double> covered(tgt.num_cells(), 0.0);
  for (const auto& p : s.pieces) covered[static_cast<std::size_t>(p.target)] += D::measure(p);
  bool some_partly = false, some_full = false;
  for (std::size_t c = 0; c < tgt.num_cells(); ++c) {
    EXPECT_EQ(cov[c], covered[c] / D::measures(tgt)[c]);
    some_partly |= cov[c] > 0.01 && cov[c] < 0.99;
    some_full |= cov[c] > 1.0 - 1e-12;
  }
  EXPECT_TRUE(some_partly && some_full);
  const auto node_cov = tetia::p1_node_coverage(s);
  const auto ones = tetia::remap_p1_lumped(s, std::vector<double>(src.num_nodes(), 1.0));
  std::vector<char> all_covered(tgt.num_nodes(), 1);
  for (std::size_t c = 0; c < tgt.num_cells(); ++c)
    if (cov[c] < 1.0 - 1e-12)
      for (const auto v : tgt.cells[c]) all_covered[static_cast<std::size_t>(v)] = 0;
  for (std::size_t i = 0; i < node_cov.size(); ++i) {
    EXPECT_NEAR(node_cov[i], ones[i], 1e-15) << i;
    if (all_covered[i]) {
      EXPECT_NEAR(node_cov[i], 1.0, 1e-13) << i;
    }
    EXPECT_GE(node_cov[i], 0.0);
    EXPECT_LE(node_cov[i], 1.0 + 1e-13);
  }
}

// The operator built once (tetia::Remap, RemapOptions::method) gives each method's values: the
// bounded P1 and the reconstruction bit for bit the free functions on its supermesh, the linear
// methods their matrix applied (apply_operator) bit for bit and the free functions to rounding;
// rows and columns as the methods have them; node_coverage for nodal results.
TYPED_TEST(RemapMethods, OperatorBuiltOnceHasEveryMethod) {
  using D = TypeParam;
  using T = RemapMethods<D>;
  using Mesh = typename D::Mesh;
  auto src = std::make_shared<const Mesh>(T::jittered(D::nv == 4 ? 4 : 11, 31));
  Mesh shifted = T::jittered(D::nv == 4 ? 3 : 8, 32);
  for (auto& p : shifted.nodes) p.x += 0.2;
  tetia::finalize(shifted, "shifted");
  auto tgt = std::make_shared<const Mesh>(shifted);
  const auto nodes = T::random_values(src->num_nodes(), 33);
  const auto cells = T::random_values(src->num_cells(), 34);
  const auto dg = T::random_values(src->num_cells() * D::nv, 35);
  const auto make = [&](int order, tetia::RemapMethod m) {
    tetia::RemapOptions o;
    o.order = order;
    o.method = m;
    return tetia::BasicRemap<Mesh>(src, tgt, o);
  };
  const auto close = [](const std::vector<double>& a, const std::vector<double>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-13 * (1.0 + std::abs(b[i]))) << i;
  };
  {
    const auto r = make(1, tetia::RemapMethod::bounded);
    EXPECT_EQ(r.apply(nodes), tetia::remap_p1_bounded(r.supermesh(), nodes));
    EXPECT_THROW((void)r.matrix(), std::logic_error);
    EXPECT_EQ(r.node_coverage(), tetia::p1_node_coverage(r.supermesh()));
  }
  {
    const auto r = make(0, tetia::RemapMethod::linear_reconstruction);
    EXPECT_EQ(r.apply(cells), tetia::remap_p0_linear(r.supermesh(), cells));
  }
  {
    const auto r = make(1, tetia::RemapMethod::lumped);
    EXPECT_EQ(r.apply(nodes), tetia::apply_operator(r.matrix(), nodes));
    close(r.apply(nodes), tetia::remap_p1_lumped(r.supermesh(), nodes));
  }
  {
    const auto r = make(1, tetia::RemapMethod::discontinuous);
    EXPECT_EQ(r.rows(), tgt->num_cells() * D::nv);
    EXPECT_EQ(r.apply(nodes), tetia::apply_operator(r.matrix(), nodes));
    close(r.apply(nodes), tetia::remap_p1_discontinuous(r.supermesh(), nodes));
    EXPECT_THROW((void)r.node_coverage(), std::logic_error);
  }
  {
    const auto r = make(0, tetia::RemapMethod::discontinuous);
    EXPECT_EQ(r.cols(), src->num_cells() * D::nv);
    close(r.apply(dg), tetia::remap_p0_from_discontinuous(r.supermesh(), dg));
  }
  EXPECT_THROW(make(0, tetia::RemapMethod::lumped), std::invalid_argument);
  EXPECT_THROW(make(0, tetia::RemapMethod::bounded), std::invalid_argument);
  EXPECT_THROW(make(1, tetia::RemapMethod::linear_reconstruction), std::invalid_argument);
}
