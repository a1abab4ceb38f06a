// The remap operator built once (tetia/remap_operator.hpp) and meshes from arrays
// (tetia/mesh_from_arrays.hpp): the operator gives what the free functions give (P1 bit for bit,
// P0 to rounding: it is its matrix applied, bit for bit), for both orders, dimensions and
// normalizations; its matrices are the ones in memory; meshes of hexahedra and prisms from arrays tile their
// domain, conform, and remap per file cell; bad arrays give errors naming the cell.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "support/error_of.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh_from_arrays.hpp"
#include "tetia/remap.hpp"
#include "tetia/remap_operator.hpp"

namespace {

using namespace tetia;

// The message of the exception `f` throws (std::invalid_argument, std::logic_error or finalize's
// std::runtime_error); fails the test if it throws nothing.
template <class F>
std::string message_of(F&& f) {
  return testsupport::error_of<std::exception>(std::forward<F>(f));
}

template <class Mesh>
std::shared_ptr<const Mesh> shared(Mesh m) {
  return std::make_shared<const Mesh>(std::move(m));
}

// A smooth field, per node or per cell (its value at the cell's first node: any values do).
double field(double x, double y, double z) { return std::sin(3 * x) + y * y - 0.5 * z + 2.0; }
double field(Vec3 p) { return field(p.x, p.y, p.z); }
double field(Vec2 p) { return field(p.x, p.y, 0.0); }

template <class Mesh>
std::vector<double> node_field(const Mesh& m, double shift = 0.0) {
  std::vector<double> v;
  for (const auto& p : m.nodes) v.push_back(field(p) + shift);
  return v;
}
template <class Mesh>
std::vector<double> cell_field(const Mesh& m, double shift = 0.0) {
  std::vector<double> v;
  for (const auto& c : m.cells) v.push_back(field(m.nodes[static_cast<std::size_t>(c[0])]) + shift);
  return v;
}

std::vector<double> times(const SparseMatrix& M, const std::vector<double>& u) {
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  const Eigen::VectorXd y = M * x;
  return std::vector<double>(y.data(), y.data() + y.size());
}

bool same_matrix(const SparseMatrix& a, const SparseMatrix& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
  for (Eigen::Index r = 0; r < a.outerSize(); ++r) {
    SparseMatrix::InnerIterator i(a, r), j(b, r);
    for (; i && j; ++i, ++j)
      if (i.col() != j.col() || i.value() != j.value()) return false;
    if (i || j) return false;
  }
  return true;
}

// Everything the operator promises, against the free functions on the same supermesh, for a
// source and a target mesh (overlapping partly, so that coverage and the normalizations differ).
template <class Mesh>
void expect_operator_matches(std::shared_ptr<const Mesh> src, std::shared_ptr<const Mesh> tgt) {
  using Op = BasicRemap<Mesh>;
  for (const auto norm : {P0Normalization::cell_volume, P0Normalization::covered_volume}) {
    RemapOptions o;
    o.normalization = norm;
    const Op r(src, tgt, o);
    EXPECT_EQ(r.rows(), tgt->num_cells());
    EXPECT_EQ(r.cols(), src->num_cells());
    const auto u = cell_field(*src), w = cell_field(*src, 7.0);
    // The operator's product: the free function to rounding, its matrix applied bit for bit.
    EXPECT_EQ(r.apply(u), tetia::apply_operator(r.matrix(), u));
    const auto free = remap_p0(r.supermesh(), u, norm);
    for (std::size_t i = 0; i < free.size(); ++i) EXPECT_NEAR(r.apply(u)[i], free[i], 1e-14 * (std::abs(free[i]) + 1.0));
    // Two components in rows: each as on its own.
    std::vector<double> uw;
    for (std::size_t i = 0; i < u.size(); ++i) uw.push_back(u[i]), uw.push_back(w[i]);
    const auto out = r.apply(uw, 2), a = r.apply(u), b = r.apply(w);
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(out[2 * i], a[i]);
      EXPECT_EQ(out[2 * i + 1], b[i]);
    }
    // The matrix applies the operator (to rounding: it divides each entry, apply the sum).
    const auto Mu = times(r.matrix(), u);
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(Mu[i], a[i], 1e-14 * (std::abs(a[i]) + 1.0));
    // mixed_mass = target_mass * matrix, and the coverage is its row sums over the measures.
    const SparseMatrix M = r.mixed_mass(), D = r.target_mass();
    const auto cov = r.coverage();
    const auto measures = file_cell_measures(*tgt);
    const auto ones = times(M, std::vector<double>(src->num_cells(), 1.0));
    std::size_t partly = 0;
    for (std::size_t t = 0; t < tgt->num_cells(); ++t) {
      EXPECT_NEAR(cov[t], ones[t] / measures[t], 1e-13);
      EXPECT_GE(cov[t], 0.0);
      EXPECT_LE(cov[t], 1.0 + 1e-13);
      partly += cov[t] > 1e-9 && cov[t] < 1 - 1e-9;
      const double d = D.coeff(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(t));
      EXPECT_EQ(d, norm == P0Normalization::cell_volume ? measures[t] : (ones[t] > 0 ? d : 0.0));
    }
    EXPECT_GT(partly, 0u);  // the overlap is partial: the test sees both normalizations differ
    EXPECT_THROW(r.apply(std::vector<double>(u.size() + 1, 0.0)), std::invalid_argument);
  }
  RemapOptions o;
  o.order = 1;
  const Op r(src, tgt, o);
  EXPECT_EQ(r.rows(), tgt->num_nodes());
  EXPECT_EQ(r.cols(), src->num_nodes());
  const auto u = node_field(*src);
  P1RemapReport rep_op, rep_free;
  EXPECT_EQ(r.apply(u, 1, &rep_op), remap_p1(r.supermesh(), u, &rep_free));  // bit for bit
  EXPECT_EQ(rep_op.iterations, rep_free.iterations);
  EXPECT_TRUE(same_matrix(r.mixed_mass(), mixed_mass_matrix(r.supermesh())));
  EXPECT_TRUE(same_matrix(r.target_mass(), mass_matrix(*tgt)));
  EXPECT_THROW(r.matrix(), std::logic_error);
  const std::string msg = message_of([&] { (void)r.matrix(); });
  EXPECT_NE(msg.find("dense"), std::string::npos) << msg;
  // The operator from a supermesh already built, and two threads applying it at once.
  SupermeshOptions so;
  so.keep_mixed_mass = true;
  const Op from(supermesh(src, tgt, so), 1);
  std::vector<double> x, y;
  std::thread t1([&] { x = from.apply(u); });
  std::thread t2([&] { y = r.apply(u); });
  t1.join();
  t2.join();
  EXPECT_EQ(x, y);
  EXPECT_THROW(Op(supermesh(src, tgt), 1), std::invalid_argument);  // nothing kept for P1
  o.order = 2;
  EXPECT_THROW(Op(src, tgt, o), std::invalid_argument);
}

TEST(RemapOperator, MatchesTheFreeFunctions3D) {
  const auto src = shared(generate_box({0, 0, 0}, {1, 1, 1}, 0.3));
  const auto tgt = shared(generate_box({0.25, 0.1, -0.2}, {1.3, 0.9, 0.8}, 0.25));
  expect_operator_matches<TetMesh>(src, tgt);
}

TEST(RemapOperator, MatchesTheFreeFunctions2D) {
  const auto src = shared(generate_rectangle({0, 0}, {1, 1}, 0.1));
  const auto tgt = shared(generate_rectangle({0.25, 0.1}, {1.3, 0.9}, 0.08));
  expect_operator_matches<TriMesh>(src, tgt);
}

// An n^3 grid of unit cubes as arrays: hexahedra, or with `mixed` two prisms in the columns with
// i + j odd (as tests/support/cell_grids.hpp, whose file the reader splits the same way).
struct Grid {
  std::vector<double> xyz;
  std::vector<std::int64_t> hexahedra, prisms;
};
Grid grid(int n, bool mixed) {
  Grid g;
  const int m = n + 1;
  const auto node = [&](int i, int j, int k) { return static_cast<std::int64_t>(i + m * j + m * m * k); };
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) g.xyz.insert(g.xyz.end(), {double(i), double(j), double(k)});
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::int64_t c[8] = {node(i, j, k),     node(i + 1, j, k),     node(i + 1, j + 1, k),
                                   node(i, j + 1, k), node(i, j, k + 1),     node(i + 1, j, k + 1),
                                   node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
        if (mixed && (i + j) % 2 == 1) {
          for (const auto& p : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}})
            for (const int v : {p[0], p[1], p[2], p[0] + 4, p[1] + 4, p[2] + 4}) g.prisms.push_back(c[v]);
        } else {
          g.hexahedra.insert(g.hexahedra.end(), c, c + 8);
        }
      }
  return g;
}

TEST(MeshFromArrays, HexahedraAndPrismsTileAndConform) {
  const Grid g = grid(3, true);
  const CellBlock blocks[] = {{5, g.hexahedra}, {6, g.prisms}};
  const TetMesh m = make_tet_mesh(g.xyz, blocks);
  const std::size_t hexes = g.hexahedra.size() / 8, prisms = g.prisms.size() / 6;
  ASSERT_EQ(m.num_file_cells(), hexes + prisms);
  EXPECT_EQ(m.num_cells(), 6 * hexes + 3 * prisms);
  EXPECT_EQ(m.reoriented_cells, 0u);
  const auto measures = file_cell_measures(m);
  for (std::size_t f = 0; f < measures.size(); ++f) EXPECT_NEAR(measures[f], f < hexes ? 1.0 : 0.5, 1e-15) << f;
  EXPECT_NEAR(m.total_volume(), 27.0, 1e-13);
  // Conforming: the only open faces are the boundary's, two triangles per unit square.
  std::size_t open = 0;
  for (const auto& nb : m.neighbors)
    for (const auto c : nb) open += c < 0;
  EXPECT_EQ(open, 2u * 6u * 9u);
  // File cells in the order given, with their types and nodes (the first hexahedron's).
  EXPECT_EQ(m.origin_types.front(), 5);
  EXPECT_EQ(m.origin_types.back(), 6);
  for (int k = 0; k < 8; ++k) EXPECT_EQ(m.origin_nodes[static_cast<std::size_t>(k)], g.hexahedra[static_cast<std::size_t>(k)]);
  // Remapped per file cell: the operator's rows and columns are the file cells.
  const auto tets = shared(generate_box({0.2, 0.1, 0.3}, {2.9, 2.8, 2.7}, 0.6));
  const Remap r(shared(m), tets);
  EXPECT_EQ(r.cols(), hexes + prisms);
  const auto out = r.apply(std::vector<double>(hexes + prisms, 3.0));
  for (const double v : out) EXPECT_NEAR(v, 3.0, 3e-13);
  const Remap back(tets, shared(m));
  EXPECT_EQ(back.rows(), hexes + prisms);
  const auto cov = back.coverage();
  double covered = 0.0;
  for (std::size_t f = 0; f < cov.size(); ++f) covered += cov[f] * measures[f];
  EXPECT_NEAR(covered, tets->total_volume(), 1e-12);
}

TEST(MeshFromArrays, TrianglesAndQuadrilateralsIn2DAnd3DPoints) {
  // Two unit squares, one a quadrilateral, one two triangles; points with z = 5 and without.
  const std::vector<double> xy = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1};
  std::vector<double> xyz;
  for (std::size_t i = 0; i < xy.size(); i += 2) xyz.insert(xyz.end(), {xy[i], xy[i + 1], 5.0});
  const std::vector<std::int64_t> quad = {0, 1, 4, 3}, tris = {1, 2, 5, 1, 5, 4};
  const CellBlock blocks[] = {{3, quad}, {2, tris}};
  for (int dim : {2, 3}) {
    const TriMesh m = make_tri_mesh(dim == 2 ? xy : xyz, dim, blocks);
    EXPECT_EQ(m.num_file_cells(), 3u);
    EXPECT_EQ(m.num_cells(), 4u);
    EXPECT_EQ(file_cell_measures(m), (std::vector<double>{1.0, 0.5, 0.5}));
  }
  xyz[2] = 5.5;  // node 0 off the plane
  EXPECT_NE(message_of([&] { (void)make_tri_mesh(xyz, 3, blocks); }).find("plane"), std::string::npos);
}

// Coordinates near the top of double's range: a measure that double holds is computed although
// the determinant's products overflow (found by fuzz/fuzz_mesh_from_arrays: it was infinite);
// one beyond the range is an error naming the cell.
TEST(MeshFromArrays, MeasuresNearTheTopOfTheRange) {
  const std::vector<std::int64_t> tet = {0, 1, 2, 3}, tri = {0, 1, 2};
  const CellBlock tets[] = {{4, tet}}, tris[] = {{2, tri}};
  const double a = 1e103;  // volume a^3 / 6 = 1.67e308 < DBL_MAX, a^3 is not
  const TetMesh m = make_tet_mesh(std::vector<double>{0, 0, 0, a, 0, 0, 0, a, 0, 0, 0, a}, tets);
  EXPECT_NEAR(m.volumes[0], 1e308 / 6.0 * 10.0, 1e-15 * 1.7e308);
  const double b = 1.5e154;  // area b^2 / 2 = 1.125e308, b^2 overflows
  const TriMesh t = make_tri_mesh(std::vector<double>{0, 0, b, 0, 0, b}, 2, tris);
  EXPECT_NEAR(t.areas[0], 1.125e308, 1e-15 * 1.2e308);
  const double c = 1e104;
  EXPECT_EQ(message_of([&] { (void)make_tet_mesh(std::vector<double>{0, 0, 0, c, 0, 0, 0, c, 0, 0, 0, c}, tets, "big"); }),
            "tetia: big: cell 0: its volume is beyond the range of double precision (coordinates too large)");
}

TEST(MeshFromArrays, BadArraysNameTheCell) {
  const Grid g = grid(2, false);
  std::vector<std::int64_t> hexes = g.hexahedra;
  hexes[8 * 5 + 3] = 27;  // cell 5: a node that is not there (27 nodes: 0..26)
  const CellBlock bad[] = {{5, hexes}};
  EXPECT_EQ(message_of([&] { (void)make_tet_mesh(g.xyz, bad, "grid"); }),
            "tetia: grid: cell 5 (hexahedron): node index 27 out of range (27 nodes)");
  const std::vector<std::int64_t> short_block(g.hexahedra.begin(), g.hexahedra.begin() + 7);
  const CellBlock partial[] = {{5, short_block}};
  EXPECT_NE(message_of([&] { (void)make_tet_mesh(g.xyz, partial); }).find("not a multiple of 8"),
            std::string::npos);
  const std::vector<std::int64_t> tri = {0, 1, 2};
  const CellBlock wrong_dim[] = {{2, tri}};
  EXPECT_NE(message_of([&] { (void)make_tet_mesh(g.xyz, wrong_dim); }).find("not a cell of a 3D mesh"),
            std::string::npos);
  const std::vector<std::int64_t> flat = {0, 1, 1, 0, 3, 3, 3, 3};  // three distinct nodes
  const CellBlock collapsed[] = {{5, g.hexahedra}, {5, flat}};
  EXPECT_EQ(message_of([&] { (void)make_tet_mesh(g.xyz, collapsed, "grid"); }),
            "tetia: grid: cell 8 (hexahedron): its repeated nodes leave it no volume");
  std::vector<double> xyz = g.xyz;
  xyz[3 * 4 + 1] = std::nan("");
  const CellBlock good[] = {{5, g.hexahedra}};
  EXPECT_EQ(message_of([&] { (void)make_tet_mesh(xyz, good, "grid"); }),
            "tetia: grid: node 4: coordinate 1 is not finite");
  EXPECT_NE(message_of([&] { (void)make_tet_mesh(g.xyz, {}); }).find("no cells"), std::string::npos);
}

}  // namespace
