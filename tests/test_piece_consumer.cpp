// test_piece_consumer.cpp -- a supermesh handed to a consumer instead of kept
// (supermesh(source, target, consumer, options), tetia/supermesh.hpp) and P1 remap through it
// (P1Loads, solve_p1, remap_p1 from two meshes, tetia/remap.hpp). Checked in 3D and 2D, with
// the front and the R-tree, on 1 and 2 threads: the consumer gets exactly the kept supermesh's
// pieces in its order, bit for bit (and those of a supermesh that keeps nothing, with the same
// candidates); compute() sees each piece's own polyhedron (polygon); the
// P1 loads and remapped fields are bit for bit those of remap_p1 on a supermesh kept with its
// mixed mass matrices; bad arguments are errors.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "support/error_of.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace {

using tetia::SupermeshOptions;
using tetia::TetMesh;
using tetia::TriMesh;
using tetia::Vec2;
using tetia::Vec3;

template <class Mesh>
struct Pair {
  std::string name;
  Mesh source, target;
};

std::vector<Pair<TetMesh>> pairs3() {
  std::vector<Pair<TetMesh>> p;
  p.push_back({"kuhn 3 x offset kuhn 4", tetia::make_kuhn_mesh({3, 3, 3}, {0, 0, 0}, {1.0 / 3, 1.0 / 3, 1.0 / 3}),
               tetia::make_kuhn_mesh({4, 4, 4}, {0.05, 0.1, -0.02}, {0.25, 0.25, 0.25})});
  p.push_back({"gmsh boxes", tetia::generate_box({0, 0, 0}, {1, 1, 1}, 0.3),
               tetia::generate_box({0.1, 0.05, 0}, {1.1, 1, 0.9}, 0.25)});
  return p;
}

std::vector<Pair<TriMesh>> pairs2() {
  std::vector<Pair<TriMesh>> p;
  p.push_back({"grid 5 x offset grid 7", tetia::make_structured_tri_mesh({5, 5}, {0, 0}, {0.2, 0.2}),
               tetia::make_structured_tri_mesh({7, 7}, {0.03, 0.05}, {1.0 / 7, 1.0 / 7})});
  p.push_back({"gmsh rectangles", tetia::generate_rectangle({0, 0}, {1, 1}, 0.12),
               tetia::generate_rectangle({0.05, 0.1}, {1.05, 0.9}, 0.1)});
  return p;
}

double measure(const tetia::SupermeshPiece& p) { return p.volume; }
double measure(const tetia::SupermeshPiece2& p) { return p.area; }
double measure(const tetia::Polyhedron& P) { return P.volume(); }
double measure(const tetia::Polygon& P) { return P.area(); }
const std::vector<tetia::Polyhedron>& shapes(const tetia::Supermesh& s) { return s.polyhedra; }
const std::vector<tetia::Polygon>& shapes(const tetia::Supermesh2& s) { return s.polygons; }

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
template <class Piece>
bool same_piece(const Piece& a, const Piece& b) {
  return a.source == b.source && a.target == b.target && same_bits(measure(a), measure(b)) && same_bits(a.first, b.first);
}

// Records what it is handed; with `values`, compute() keeps the polyhedron's (polygon's)
// measure and the piece's cell indices, so that consume() can check they belong together.
template <class Piece, class Shape>
struct Recorder final : tetia::BasicPieceConsumer<Piece, Shape> {
  bool with_values = false;
  std::vector<Piece> pieces;
  std::vector<double> shape_measures;
  bool ids_matched = true;
  std::size_t values_per_piece() const override { return with_values ? 3 : 0; }
  void compute(const Piece& piece, const Shape& shape, double* values) const override {
    values[0] = measure(shape);
    values[1] = piece.source;
    values[2] = piece.target;
  }
  void consume(const Piece& piece, const double* values) override {
    pieces.push_back(piece);
    if (with_values) {
      shape_measures.push_back(values[0]);
      ids_matched = ids_matched && values[1] == piece.source && values[2] == piece.target;
    } else {
      ids_matched = ids_matched && values == nullptr;
    }
  }
};

template <class Mesh, class Piece, class Shape>
void check_pieces(const Pair<Mesh>& pair) {
  for (const auto search : {tetia::CandidateSearch::front, tetia::CandidateSearch::rtree})
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(pair.name + (search == tetia::CandidateSearch::front ? ", front" : ", rtree") + ", threads " +
                   std::to_string(threads));
      SupermeshOptions o;
      o.search = search;
      o.threads = threads;
      SupermeshOptions kept = o;
      kept.keep_polyhedra = true;
      const auto s = tetia::supermesh(pair.source, pair.target, kept);
      ASSERT_GT(s.pieces.size(), 0u);
      // The full kernel (for the shapes) finds the pieces of the fast one, bit for bit, with the
      // same candidates (its facets guide the front as the fast path's do).
      const auto plain = tetia::supermesh(pair.source, pair.target, o);
      ASSERT_EQ(plain.pieces.size(), s.pieces.size());
      EXPECT_EQ(plain.candidates, s.candidates);
      for (std::size_t k = 0; k < s.pieces.size(); ++k) ASSERT_TRUE(same_piece(plain.pieces[k], s.pieces[k])) << k;
      for (const bool with_values : {false, true}) {
        Recorder<Piece, Shape> r;
        r.with_values = with_values;
        const tetia::SupermeshSummary sum = tetia::supermesh(pair.source, pair.target, r, o);
        EXPECT_EQ(sum.pieces, s.pieces.size());
        EXPECT_EQ(sum.candidates, s.candidates);
        ASSERT_EQ(r.pieces.size(), s.pieces.size());
        EXPECT_TRUE(r.ids_matched);
        for (std::size_t k = 0; k < s.pieces.size(); ++k) {
          ASSERT_TRUE(same_piece(r.pieces[k], s.pieces[k])) << "piece " << k;
          if (with_values) {
            ASSERT_TRUE(same_bits(r.shape_measures[k], measure(shapes(s)[k]))) << "piece " << k;
          }
        }
      }
    }
}

TEST(PieceConsumer, HandedTheKeptSupermeshsPiecesInItsOrder3D) {
  for (const auto& p : pairs3()) check_pieces<TetMesh, tetia::SupermeshPiece, tetia::Polyhedron>(p);
}

TEST(PieceConsumer, HandedTheKeptSupermeshsPiecesInItsOrder2D) {
  for (const auto& p : pairs2()) check_pieces<TriMesh, tetia::SupermeshPiece2, tetia::Polygon>(p);
}

template <class Mesh>
std::vector<std::vector<double>> fields_of(const Mesh& m) {
  std::vector<std::vector<double>> f(2, std::vector<double>(m.num_nodes()));
  for (std::size_t i = 0; i < m.num_nodes(); ++i) {
    const auto& p = m.nodes[i];
    if constexpr (std::is_same_v<Mesh, TetMesh>) {
      f[0][i] = 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z;
      f[1][i] = std::sin(3.0 * p.x) * std::cos(2.0 * p.y) * std::exp(p.z);
    } else {
      f[0][i] = 1.0 + 2.0 * p.x - 3.0 * p.y;
      f[1][i] = std::sin(3.0 * p.x) * std::cos(2.0 * p.y);
    }
  }
  return f;
}

template <class Mesh, class Loads>
void check_p1(const Pair<Mesh>& pair) {
  const auto fields = fields_of(pair.source);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(pair.name + ", threads " + std::to_string(threads));
    SupermeshOptions o;
    o.threads = threads;
    SupermeshOptions kept = o;
    kept.keep_mixed_mass = true;
    const auto s = tetia::supermesh(pair.source, pair.target, kept);
    std::vector<tetia::P1RemapReport> reports;
    const auto streamed = tetia::remap_p1(pair.source, pair.target, fields, o, &reports);
    ASSERT_EQ(streamed.size(), fields.size());
    ASSERT_EQ(reports.size(), fields.size());
    for (std::size_t f = 0; f < fields.size(); ++f) {
      tetia::P1RemapReport r;
      const auto direct = tetia::remap_p1(s, fields[f], &r);
      ASSERT_EQ(streamed[f].size(), direct.size());
      EXPECT_EQ(std::memcmp(streamed[f].data(), direct.data(), direct.size() * sizeof(double)), 0) << "field " << f;
      EXPECT_EQ(reports[f].iterations, r.iterations);
      EXPECT_TRUE(same_bits(reports[f].residual, r.residual));
    }
    // The loads themselves: each row sum of M_ts times a constant 1 is the overlap of that
    // target basis function's support, so their total is the intersection measure.
    Loads loads(pair.source, pair.target, {fields[0]});
    tetia::supermesh(pair.source, pair.target, loads, o);
    const auto M = tetia::mixed_mass_matrix(s);
    Eigen::VectorXd u(static_cast<Eigen::Index>(fields[0].size()));
    for (std::size_t i = 0; i < fields[0].size(); ++i) u[static_cast<Eigen::Index>(i)] = fields[0][i];
    const Eigen::VectorXd b = M * u;  // the same sums in another order: equal to rounding
    ASSERT_EQ(loads.loads().size(), 1u);
    ASSERT_EQ(loads.loads()[0].size(), b.size());
    EXPECT_LE((loads.loads()[0] - b).cwiseAbs().maxCoeff(), 1e-13 * b.cwiseAbs().maxCoeff());
  }
}

TEST(P1Loads, RemapFromTheMeshesIsBitForBitTheKeptOnes3D) {
  for (const auto& p : pairs3()) check_p1<TetMesh, tetia::P1Loads>(p);
}

TEST(P1Loads, RemapFromTheMeshesIsBitForBitTheKeptOnes2D) {
  for (const auto& p : pairs2()) check_p1<TriMesh, tetia::P1Loads2>(p);
}

// A consumer whose compute() throws on one piece: the exception leaves supermesh(), on any
// number of threads (an exception must not escape the OpenMP region the pieces are found in).
struct Throwing final : tetia::PieceConsumer {
  std::size_t values_per_piece() const override { return 1; }
  void compute(const tetia::SupermeshPiece& piece, const tetia::Polyhedron&, double* values) const override {
    if (piece.source == 7) throw std::runtime_error("no piece of source cell 7");
    values[0] = 1.0;
  }
  void consume(const tetia::SupermeshPiece&, const double*) override { ++consumed; }
  int consumed = 0;
};

TEST(PieceConsumer, AnExceptionInComputeLeavesTheSupermesh) {
  const auto p = pairs3().front();
  for (const int threads : {1, 2}) {
    Throwing t;
    SupermeshOptions o;
    o.threads = threads;
    EXPECT_EQ(tetia::testsupport::error_of([&] { tetia::supermesh(p.source, p.target, t, o); }),
              "no piece of source cell 7");
    EXPECT_EQ(t.consumed, 0);
  }
}

TEST(PieceConsumer, BadArgumentsAreErrors) {
  const auto p = pairs3().front();
  Recorder<tetia::SupermeshPiece, tetia::Polyhedron> r;
  SupermeshOptions o;
  o.keep_polyhedra = true;
  EXPECT_NE(tetia::testsupport::error_of<std::invalid_argument>([&] { tetia::supermesh(p.source, p.target, r, o); })
                .find("keep_polyhedra"),
            std::string::npos);
  o.keep_polyhedra = false;
  o.keep_mixed_mass = true;
  EXPECT_NE(tetia::testsupport::error_of<std::invalid_argument>([&] { tetia::supermesh(p.source, p.target, r, o); })
                .find("keep_mixed_mass"),
            std::string::npos);
  const std::vector<double> short_field(p.source.num_nodes() - 1, 1.0);
  const std::string e = tetia::testsupport::error_of<std::invalid_argument>(
      [&] { tetia::P1Loads(p.source, p.target, {short_field}); });
  EXPECT_NE(e.find("source node"), std::string::npos) << e;
  EXPECT_THROW(tetia::solve_p1(p.target, Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
