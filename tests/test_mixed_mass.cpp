// test_mixed_mass.cpp -- SupermeshOptions::keep_mixed_mass: the supermesh keeps each piece's
// local mixed mass matrix instead of its polyhedron (polygon). Checked, in 3D and 2D, on
// identical, half-offset structured, jittered non-matching and Gmsh mesh pairs: the kept
// matrices are bit for bit what the remap computes from kept polyhedra (the same function,
// src/supermesh/mixed_mass.hpp, applied here to the kept shapes), the pieces are those of keep_polyhedra,
// 1 and 2 threads agree bit for bit, remap_p1 and the Matrix Market file are identical from
// either kept form (and through the CLI), and what is stored per piece is about 1/18 (3D) of
// a polyhedron.
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "../src/supermesh/mixed_mass.hpp"  // the per-piece computation the remap uses (internal)
#include "support/cli.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace {

namespace fs = std::filesystem;

using tetia::SupermeshOptions;
using tetia::TetMesh;
using tetia::TriMesh;
using tetia::Vec2;
using tetia::Vec3;

// --- meshes -----------------------------------------------------------------------------------

TetMesh kuhn(int n, Vec3 origin = {0, 0, 0}) {
  const double h = 1.0 / n;
  return tetia::make_kuhn_mesh({n, n, n}, origin, {h, h, h});
}

TetMesh jittered3(int n, unsigned seed) {
  TetMesh m = kuhn(n);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.2 / n, 0.2 / n);
  for (Vec3& p : m.nodes)
    if (p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1) p = p + Vec3{u(g), u(g), u(g)};
  tetia::finalize(m, "jittered");
  return m;
}

TriMesh grid(int n, Vec2 origin = {0, 0}) {
  const double h = 1.0 / n;
  return tetia::make_structured_tri_mesh({n, n}, origin, {h, h});
}

TriMesh jittered2(int n, unsigned seed) {
  TriMesh m = grid(n);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.2 / n, 0.2 / n);
  for (Vec2& p : m.nodes)
    if (p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1) p = p + Vec2{u(g), u(g)};
  tetia::finalize(m, "jittered");
  return m;
}

template <class Mesh>
struct Pair {
  std::string name;
  Mesh source, target;
};

std::vector<Pair<TetMesh>> pairs3() {
  std::vector<Pair<TetMesh>> p;
  p.push_back({"identical", kuhn(3), kuhn(3)});
  p.push_back({"half-offset", kuhn(3), kuhn(3, {0.5 / 3, 0.5 / 3, 0.5 / 3})});
  p.push_back({"jittered 3 x 4", jittered3(3, 1), jittered3(4, 2)});
  p.push_back({"kuhn 2 x jittered 5", kuhn(2), jittered3(5, 3)});
  p.push_back({"gmsh boxes", tetia::generate_box({0, 0, 0}, {1, 1, 1}, 0.35),
               tetia::generate_box({0.1, 0.05, 0}, {1.1, 1, 0.9}, 0.3)});
  return p;
}

std::vector<Pair<TriMesh>> pairs2() {
  std::vector<Pair<TriMesh>> p;
  p.push_back({"identical", grid(5), grid(5)});
  p.push_back({"half-offset", grid(5), grid(5, {0.1, 0.1})});
  p.push_back({"jittered 5 x 7", jittered2(5, 4), jittered2(7, 5)});
  p.push_back({"grid 3 x jittered 8", grid(3), jittered2(8, 6)});
  p.push_back({"gmsh rectangles", tetia::generate_rectangle({0, 0}, {1, 1}, 0.12),
               tetia::generate_rectangle({0.05, 0.1}, {1.05, 0.9}, 0.1)});
  return p;
}

// --- what differs between the dimensions ------------------------------------------------------

double measure(const tetia::SupermeshPiece& p) { return p.volume; }
double measure(const tetia::SupermeshPiece2& p) { return p.area; }
const std::vector<tetia::Polyhedron>& shapes(const tetia::Supermesh& s) { return s.polyhedra; }
const std::vector<tetia::Polygon>& shapes(const tetia::Supermesh2& s) { return s.polygons; }

template <class Mesh>
std::vector<double> linear_at_nodes(const Mesh& m) {
  std::vector<double> v(m.num_nodes());
  for (std::size_t i = 0; i < m.num_nodes(); ++i) {
    const auto& p = m.nodes[i];
    if constexpr (std::is_same_v<Mesh, TetMesh>) v[i] = 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z;
    else v[i] = 1.0 + 2.0 * p.x - 3.0 * p.y;
  }
  return v;
}

template <class Mesh>
std::vector<double> smooth_at_nodes(const Mesh& m) {
  std::vector<double> v(m.num_nodes());
  for (std::size_t i = 0; i < m.num_nodes(); ++i) {
    const auto& p = m.nodes[i];
    if constexpr (std::is_same_v<Mesh, TetMesh>) v[i] = std::sin(3 * p.x) * std::cos(2 * p.y) * std::exp(p.z);
    else v[i] = std::sin(3 * p.x) * std::cos(2 * p.y);
  }
  return v;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

template <class Piece>
bool same_piece(const Piece& a, const Piece& b) {
  return std::memcmp(&a, &b, sizeof(Piece)) == 0;
}

template <class Mesh>
auto build(const Mesh& src, const Mesh& tgt, bool polyhedra, bool mass, int threads) {
  SupermeshOptions o;
  o.keep_polyhedra = polyhedra;
  o.keep_mixed_mass = mass;
  o.threads = threads;
  return tetia::supermesh(src, tgt, o);
}

fs::path temp_file(const std::string& stem) {
  return fs::temp_directory_path() /
         (stem + "_" + std::to_string(::getpid()) + "_" +
          std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".mtx");
}

// Everything the feature promises, on one mesh pair.
template <class Mesh>
void check_pair(const Pair<Mesh>& pr) {
  using Dm = tetia::detail::Dim<Mesh>;
  SCOPED_TRACE(pr.name);
  const Mesh& src = pr.source;
  const Mesh& tgt = pr.target;
  const auto poly = build(src, tgt, true, false, 2);   // today's P1 path
  const auto mass1 = build(src, tgt, false, true, 1);  // the new one, 1 and 2 threads
  const auto mass2 = build(src, tgt, false, true, 2);
  const auto both = build(src, tgt, true, true, 2);
  ASSERT_GT(poly.pieces.size(), 0u);

  // What is kept.
  EXPECT_TRUE(shapes(mass1).empty());
  EXPECT_TRUE(poly.local_mass.empty());
  ASSERT_EQ(mass1.local_mass.size(), mass1.pieces.size());
  ASSERT_EQ(both.local_mass.size(), both.pieces.size());
  ASSERT_EQ(shapes(both).size(), both.pieces.size());

  // The same pieces as keep_polyhedra (the same kernel call), in the same order, bit for bit,
  // and the same candidates.
  ASSERT_EQ(mass1.pieces.size(), poly.pieces.size());
  for (std::size_t k = 0; k < poly.pieces.size(); ++k)
    ASSERT_TRUE(same_piece(mass1.pieces[k], poly.pieces[k])) << "piece " << k;
  EXPECT_EQ(mass1.candidates, poly.candidates);

  // 1 vs 2 threads, and with the polyhedra kept as well: bit for bit.
  EXPECT_TRUE(same_bits(mass1.pieces, mass2.pieces));
  EXPECT_TRUE(same_bits(mass1.local_mass, mass2.local_mass));
  EXPECT_EQ(mass1.candidates, mass2.candidates);
  EXPECT_TRUE(same_bits(mass1.local_mass, both.local_mass));

  // Each kept matrix is what the remap computes from the kept polyhedron (polygon), bit for
  // bit; its entries add up to the piece's volume (area), the integral of 1 = sum of bases.
  typename Dm::LocalMass A{};
  for (std::size_t k = 0; k < poly.pieces.size(); ++k) {
    const auto& pc = poly.pieces[k];
    tetia::detail::piece_mixed_mass<Mesh>(src.cell(static_cast<std::size_t>(pc.source)), shapes(poly)[k], A);
    ASSERT_EQ(std::memcmp(A.data(), mass1.local_mass[k].data(), sizeof A), 0) << "piece " << k;
    double sum = 0.0;
    for (const double a : A) sum += a;
    const double cell = Dm::measures(src)[static_cast<std::size_t>(pc.source)];
    EXPECT_NEAR(sum, measure(pc), 1e-12 * measure(pc) + 1e-14 * cell) << "piece " << k;
  }

  // remap_p1: identical results from either kept form (and local_mass preferred when both).
  for (const auto& in : {linear_at_nodes(src), smooth_at_nodes(src)}) {
    tetia::P1RemapReport rp, rm, rb;
    const auto up = tetia::remap_p1(poly, in, &rp);
    const auto um = tetia::remap_p1(mass1, in, &rm);
    const auto ub = tetia::remap_p1(both, in, &rb);
    EXPECT_TRUE(same_bits(up, um));
    EXPECT_TRUE(same_bits(up, ub));
    EXPECT_EQ(rp.iterations, rm.iterations);
    EXPECT_EQ(std::memcmp(&rp.residual, &rm.residual, sizeof(double)), 0);
  }

  // The Matrix Market file: byte for byte the same.
  const fs::path fp = temp_file("tetia_mm_poly"), fm = temp_file("tetia_mm_mass");
  tetia::write_mixed_mass_matrix(poly, fp);
  tetia::write_mixed_mass_matrix(mass2, fm);
  const std::string tp = tetia::testcli::read_file(fp), tm = tetia::testcli::read_file(fm);
  EXPECT_GT(tp.size(), 100u);
  EXPECT_TRUE(tp == tm) << fp << " and " << fm << " differ";
  fs::remove(fp);
  fs::remove(fm);
}

// --- 3D ---------------------------------------------------------------------------------------

TEST(KeepMixedMass, MatchesThePolyhedraPathBitForBit3D) {
  for (const auto& pr : pairs3()) check_pair(pr);
}

TEST(KeepMixedMass, MatchesThePolyhedraPathBitForBit2D) {
  for (const auto& pr : pairs2()) check_pair(pr);
}

// The R-tree search gives the same pieces, hence the same kept matrices.
TEST(KeepMixedMass, FrontAndRtreeKeepTheSameMatrices) {
  const TetMesh a = jittered3(3, 11), b = jittered3(4, 12);
  SupermeshOptions o;
  o.keep_mixed_mass = true;
  o.threads = 2;
  const auto front = tetia::supermesh(a, b, o);
  o.search = tetia::CandidateSearch::rtree;
  const auto rtree = tetia::supermesh(a, b, o);
  EXPECT_TRUE(same_bits(front.pieces, rtree.pieces));
  EXPECT_TRUE(same_bits(front.local_mass, rtree.local_mass));
  const TriMesh c = jittered2(6, 13), d = jittered2(9, 14);
  o.search = tetia::CandidateSearch::front;
  const auto front2 = tetia::supermesh(c, d, o);
  o.search = tetia::CandidateSearch::rtree;
  const auto rtree2 = tetia::supermesh(c, d, o);
  EXPECT_TRUE(same_bits(front2.pieces, rtree2.pieces));
  EXPECT_TRUE(same_bits(front2.local_mass, rtree2.local_mass));
}

// The matrices in memory (tetia::mixed_mass_matrix, tetia::mass_matrix): M_t symmetric with the
// lumped masses as row sums, M_ts the same from kept matrices and from polyhedra, and solving
// M_t u_t = M_ts u_s directly (Eigen's LDL^T) gives what remap_p1 gives by CG; in 3D and 2D.
template <class Mesh>
void check_in_memory(const Mesh& a, const Mesh& b) {
  const auto mass = build(a, b, false, true, 2), poly = build(a, b, true, false, 1);
  const tetia::SparseMatrix mts = tetia::mixed_mass_matrix(mass), mt = tetia::mass_matrix(b);
  EXPECT_TRUE((mts - tetia::mixed_mass_matrix(poly)).norm() == 0.0);
  EXPECT_EQ(mts.rows(), static_cast<Eigen::Index>(b.num_nodes()));
  EXPECT_EQ(mts.cols(), static_cast<Eigen::Index>(a.num_nodes()));
  EXPECT_EQ((mt - tetia::SparseMatrix(mt.transpose())).norm(), 0.0);
  double total = 0.0;
  for (Eigen::Index r = 0; r < mt.rows(); ++r) total += mt.row(r).sum();
  double measure = 0.0;
  if constexpr (std::is_same_v<Mesh, TetMesh>) measure = b.total_volume();
  else measure = b.total_area();
  EXPECT_NEAR(total, measure, 1e-14);
  Eigen::VectorXd us(static_cast<Eigen::Index>(a.num_nodes()));
  for (std::size_t n = 0; n < a.num_nodes(); ++n) us[static_cast<Eigen::Index>(n)] = std::sin(3.0 * a.nodes[n].x) + a.nodes[n].y;
  const Eigen::SparseMatrix<double> mt_col = mt;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(mt_col);
  ASSERT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd ut = solver.solve(mts * us);
  const std::vector<double> cg = tetia::remap_p1(mass, std::vector<double>(us.data(), us.data() + us.size()));
  double worst = 0.0;
  for (std::size_t n = 0; n < cg.size(); ++n) worst = std::max(worst, std::abs(cg[n] - ut[static_cast<Eigen::Index>(n)]));
  EXPECT_LT(worst, 1e-9);
}

TEST(KeepMixedMass, MatricesInMemory) {
  check_in_memory(jittered3(3, 21), jittered3(4, 22));
  check_in_memory(jittered2(6, 23), jittered2(9, 24));
}

// Neither option: the error names both.
TEST(KeepMixedMass, WithoutEitherOptionTheErrorNamesBoth) {
  const TetMesh m = kuhn(2);
  const auto s = build(m, m, false, false, 1);
  for (int dim = 3; dim >= 2; --dim) {
    try {
      if (dim == 3) {
        tetia::remap_p1(s, linear_at_nodes(m));
      } else {
        const TriMesh t = grid(2);
        tetia::remap_p1(build(t, t, false, false, 1), linear_at_nodes(t));
      }
      FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
      const std::string w = e.what();
      EXPECT_NE(w.find("keep_mixed_mass"), std::string::npos) << w;
      EXPECT_NE(w.find("keep_polyhedra"), std::string::npos) << w;
    }
  }
  EXPECT_THROW(tetia::write_mixed_mass_matrix(s, temp_file("tetia_never_mm")), std::invalid_argument);
  EXPECT_THROW((void)tetia::mixed_mass_matrix(s), std::invalid_argument);
}

// Memory: what is stored per piece.
TEST(KeepMixedMass, StoredBytesPerPiece) {
  using M3 = decltype(tetia::Supermesh::local_mass)::value_type;
  using M2 = decltype(tetia::Supermesh2::local_mass)::value_type;
  static_assert(sizeof(M3) == 16 * sizeof(double));
  static_assert(sizeof(M2) == 9 * sizeof(double));
  const std::size_t piece3 = sizeof(tetia::SupermeshPiece), piece2 = sizeof(tetia::SupermeshPiece2);
  const std::size_t with_mass3 = piece3 + sizeof(M3), with_poly3 = piece3 + sizeof(tetia::Polyhedron);
  const std::size_t with_mass2 = piece2 + sizeof(M2), with_poly2 = piece2 + sizeof(tetia::Polygon);
  std::printf("bytes per piece in the result: 3D %zu (keep_mixed_mass) vs %zu (keep_polyhedra), "
              "2D %zu vs %zu; no shapes: %zu, %zu\n",
              with_mass3, with_poly3, with_mass2, with_poly2, piece3, piece2);
  EXPECT_EQ(with_mass3, 168u);
  EXPECT_EQ(with_mass2, 104u);
  EXPECT_GT(with_poly3, 5 * with_mass3);
  EXPECT_GT(with_poly2, 3 * with_mass2);
  // And nothing else grows: a supermesh with only the matrices holds no shapes at all.
  const TetMesh a = kuhn(2), b = kuhn(3);
  const auto s = build(a, b, false, true, 1);
  EXPECT_EQ(s.polyhedra.capacity(), 0u);
  EXPECT_EQ(s.local_mass.size(), s.pieces.size());
}

// The CLI: `tetia remap --order 1 --matrix` (which now keeps only the matrices) writes the
// file the library writes from kept polyhedra, byte for byte, in 3D and 2D.
template <class Mesh>
void cli_matrix_matches(const Mesh& a, const Mesh& b, const std::string& expr) {
  std::string templ = (fs::temp_directory_path() / "tetia_mixed_mass_cli_XXXXXX").string();
  ASSERT_NE(::mkdtemp(templ.data()), nullptr);
  const fs::path dir = templ;
  ASSERT_TRUE(fs::exists(TETIA_CLI_PATH)) << "CLI not built: " << TETIA_CLI_PATH;
  tetia::write_msh(dir / "a.msh", a);
  tetia::write_msh(dir / "b.msh", b);
  const auto cli = tetia::testcli::run(TETIA_CLI_PATH,
                                       "remap " + tetia::testcli::shell_quote((dir / "a.msh").string()) + " " +
                                           tetia::testcli::shell_quote((dir / "b.msh").string()) + " --expr '" + expr +
                                           "' --order 1 --matrix " +
                                           tetia::testcli::shell_quote((dir / "cli.mtx").string()),
                                       dir);
  ASSERT_EQ(cli.status, 0) << cli.err;
  // The same meshes as the CLI sees them: read back from the files.
  Mesh ra, rb;
  if constexpr (std::is_same_v<Mesh, TetMesh>) {
    ra = tetia::read_mesh(dir / "a.msh");
    rb = tetia::read_mesh(dir / "b.msh");
  } else {
    ra = tetia::read_tri_mesh(dir / "a.msh");
    rb = tetia::read_tri_mesh(dir / "b.msh");
  }
  tetia::write_mixed_mass_matrix(build(ra, rb, true, false, 1), dir / "lib.mtx");
  const std::string c = tetia::testcli::read_file(dir / "cli.mtx"), l = tetia::testcli::read_file(dir / "lib.mtx");
  EXPECT_GT(c.size(), 100u);
  EXPECT_TRUE(c == l) << "the CLI's matrix differs from the library's (kept polyhedra)";
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST(KeepMixedMass, CliMatrixIsTheLibrarysFromPolyhedra) {
  cli_matrix_matches(jittered3(3, 21), jittered3(4, 22), "x + 2*y - z");
  cli_matrix_matches(jittered2(5, 23), jittered2(7, 24), "x*y");
}

}  // namespace
