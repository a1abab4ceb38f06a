// Conservative remap on a supermesh: P0 by piece volumes, P1 by the Galerkin L2 projection
// with the mixed mass matrix integrated exactly on each piece's tetrahedralization.
#include "tetia/remap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

namespace tetia {

namespace {

using SpMat = Eigen::SparseMatrix<double>;  // column major
using Triplet = Eigen::Triplet<double>;

void check_meshes(const Supermesh& s, const char* who) {
  if (s.source == nullptr || s.target == nullptr)
    throw std::invalid_argument(std::string("tetia: ") + who + ": the supermesh has no source or target mesh");
}

void check_polyhedra(const Supermesh& s, const char* who) {
  check_meshes(s, who);
  if (s.polyhedra.size() != s.pieces.size())
    throw std::invalid_argument(std::string("tetia: ") + who +
                                ": the supermesh has no polyhedra; build it with "
                                "SupermeshOptions::keep_polyhedra = true");
}

void check_size(std::size_t got, std::size_t want, const char* who, const char* what) {
  if (got != want)
    throw std::invalid_argument(std::string("tetia: ") + who + ": " + std::to_string(got) + " " + what +
                                " values, the mesh has " + std::to_string(want));
}

std::size_t idx(std::int32_t i) { return static_cast<std::size_t>(i); }

// Barycentric coordinates of the corners of a piece in its source cell U: computed from the
// point, with the coordinates of U's planes the corner lies on (labels 0-3) set to exactly
// zero, negatives (rounding) clamped, scaled to sum to 1.
void source_bary(const Tet& U, const Polyhedron& P, std::array<std::array<double, 4>, Polyhedron::max_corners>& out) {
  const double det = orient3d(U[0], U[1], U[2], U[3]);
  for (int c = 0; c < P.num_corners(); ++c) {
    const Corner& k = P.corner(c);
    const Vec3 p = k.point;
    double b[4] = {orient3d(p, U[1], U[2], U[3]) / det, orient3d(U[0], p, U[2], U[3]) / det,
                   orient3d(U[0], U[1], p, U[3]) / det, orient3d(U[0], U[1], U[2], p) / det};
    for (const auto l : k.labels)
      if (l < 4) b[l] = 0.0;
    double sum = 0.0;
    for (double& x : b) {
      if (!(x > 0.0)) x = 0.0;
      sum += x;
    }
    auto& o = out[static_cast<std::size_t>(c)];
    for (int q = 0; q < 4; ++q) o[static_cast<std::size_t>(q)] = sum > 0.0 ? b[q] / sum : 0.25;
  }
}

// Local mixed mass matrix of one piece: A[i][j] = integral over the piece of (target basis i) x
// (source basis j), exact for the product of two linear functions on each tetrahedron of the
// fan from corner 0: |T|/20 (sum_v f_v g_v + (sum_v f_v)(sum_v g_v)).
void local_mixed(const Polyhedron& P, const std::array<std::array<double, 4>, Polyhedron::max_corners>& sb,
                 double (&A)[4][4]) {
  for (auto& row : A)
    for (double& x : row) x = 0.0;
  const Vec3 apex = P.corner(0).point;
  for (int f = 0; f < P.num_facets(); ++f) {
    const auto ids = P.facet(f);
    if (std::find(ids.begin(), ids.end(), std::uint8_t{0}) != ids.end()) continue;
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
      const int v[4] = {0, ids[0], ids[k], ids[k + 1]};
      const double w = orient3d(apex, P.corner(v[1]).point, P.corner(v[2]).point, P.corner(v[3]).point) / 120.0;
      double F[4] = {0, 0, 0, 0}, G[4] = {0, 0, 0, 0}, FG[4][4] = {};
      for (const int c : v) {
        const auto& f4 = P.corner(c).bary;
        const auto& g4 = sb[static_cast<std::size_t>(c)];
        for (int i = 0; i < 4; ++i) {
          F[i] += f4[static_cast<std::size_t>(i)];
          G[i] += g4[static_cast<std::size_t>(i)];
          for (int j = 0; j < 4; ++j) FG[i][j] += f4[static_cast<std::size_t>(i)] * g4[static_cast<std::size_t>(j)];
        }
      }
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) A[i][j] += w * (FG[i][j] + F[i] * G[j]);
    }
  }
}

SpMat mixed_mass(const Supermesh& s) {
  const TetMesh& src = *s.source;
  const TetMesh& tgt = *s.target;
  std::vector<Triplet> trip;
  trip.reserve(s.pieces.size() * 16);
  std::array<std::array<double, 4>, Polyhedron::max_corners> sb{};
  double A[4][4];
  for (std::size_t k = 0; k < s.pieces.size(); ++k) {
    const SupermeshPiece& pc = s.pieces[k];
    const Polyhedron& P = s.polyhedra[k];
    if (P.empty()) continue;
    source_bary(src.cell(idx(pc.source)), P, sb);
    local_mixed(P, sb, A);
    const auto& tn = tgt.cells[idx(pc.target)];
    const auto& sn = src.cells[idx(pc.source)];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) trip.emplace_back(tn[static_cast<std::size_t>(i)], sn[static_cast<std::size_t>(j)], A[i][j]);
  }
  SpMat M(static_cast<Eigen::Index>(tgt.num_nodes()), static_cast<Eigen::Index>(src.num_nodes()));
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

// The consistent P1 mass matrix; a node in no cell (or only in flat ones) gets a unit diagonal,
// so that it solves to 0 (its right-hand side is 0) instead of breaking the solver.
SpMat mass_matrix(const TetMesh& m) {
  std::vector<Triplet> trip;
  trip.reserve(m.num_cells() * 16);
  std::vector<char> used(m.num_nodes(), 0);
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const double w = m.volumes[c] / 20.0;
    if (!(w > 0.0)) continue;
    const auto& v = m.cells[c];
    for (int i = 0; i < 4; ++i) {
      used[idx(v[static_cast<std::size_t>(i)])] = 1;
      for (int j = 0; j < 4; ++j) trip.emplace_back(v[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(j)], i == j ? 2.0 * w : w);
    }
  }
  for (std::size_t n = 0; n < m.num_nodes(); ++n)
    if (!used[n]) trip.emplace_back(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n), 1.0);
  SpMat M(static_cast<Eigen::Index>(m.num_nodes()), static_cast<Eigen::Index>(m.num_nodes()));
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

// A conical product Gauss rule on the reference tetrahedron (Duffy map of 4^3 Gauss-Legendre
// points): exact for polynomials of degree 5. Points as barycentric coordinates, weights
// summing to 1 (multiply by the cell volume).
struct Rule {
  std::array<std::array<double, 4>, 64> bary;
  std::array<double, 64> weight;
};

const Rule& rule() {
  static const Rule r = [] {
    Rule q{};
    const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    std::size_t n = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int c = 0; c < 4; ++c) {
          const double u = 0.5 * (1.0 + x[a]), v = 0.5 * (1.0 + x[b]), t = 0.5 * (1.0 + x[c]);
          const double x1 = u, x2 = v * (1.0 - u), x3 = t * (1.0 - u) * (1.0 - v);
          q.bary[n] = {1.0 - x1 - x2 - x3, x1, x2, x3};
          // Jacobian (1-u)^2 (1-v), Gauss weights on [0,1] (w/2 each), reference volume 1/6.
          q.weight[n] = 6.0 * (0.125 * w[a] * w[b] * w[c]) * (1.0 - u) * (1.0 - u) * (1.0 - v);
          ++n;
        }
    return q;
  }();
  return r;
}

Vec3 at(const Tet& T, const std::array<double, 4>& b) {
  return b[0] * T[0] + b[1] * T[1] + b[2] * T[2] + b[3] * T[3];
}

}  // namespace

std::vector<double> covered_volumes(const Supermesh& s) {
  check_meshes(s, "covered_volumes");
  std::vector<double> cov(s.target->num_cells(), 0.0);
  for (const auto& pc : s.pieces) cov[idx(pc.target)] += pc.volume;
  return cov;
}

std::vector<double> remap_p0(const Supermesh& s, std::span<const double> values, P0Normalization normalization) {
  check_meshes(s, "remap_p0");
  check_size(values.size(), s.source->num_cells(), "remap_p0", "source cell");
  const TetMesh& tgt = *s.target;
  std::vector<double> out(tgt.num_cells(), 0.0);
  // Pieces are sorted by target: one pass, each target's sum in source order.
  std::size_t k = 0;
  while (k < s.pieces.size()) {
    const std::int32_t t = s.pieces[k].target;
    double num = 0.0, cov = 0.0;
    for (; k < s.pieces.size() && s.pieces[k].target == t; ++k) {
      num += values[idx(s.pieces[k].source)] * s.pieces[k].volume;
      cov += s.pieces[k].volume;
    }
    const double den = normalization == P0Normalization::covered_volume ? cov : tgt.volumes[idx(t)];
    out[idx(t)] = den > 0.0 ? num / den : 0.0;
  }
  return out;
}

std::vector<double> remap_p1(const Supermesh& s, std::span<const double> values, P1RemapReport* report) {
  check_polyhedra(s, "remap_p1");
  check_size(values.size(), s.source->num_nodes(), "remap_p1", "source node");
  const SpMat Mts = mixed_mass(s);
  const SpMat Mt = mass_matrix(*s.target);
  const Eigen::Map<const Eigen::VectorXd> us(values.data(), static_cast<Eigen::Index>(values.size()));
  const Eigen::VectorXd b = Mts * us;
  // Initial guess: the lumped-mass solution.
  Eigen::VectorXd lumped = Mt * Eigen::VectorXd::Ones(Mt.cols());
  Eigen::VectorXd guess(b.size());
  for (Eigen::Index i = 0; i < b.size(); ++i) guess[i] = lumped[i] > 0.0 ? b[i] / lumped[i] : 0.0;
  Eigen::ConjugateGradient<SpMat, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg;
  cg.setTolerance(1e-14);
  cg.setMaxIterations(std::max<Eigen::Index>(1000, 4 * Mt.rows()));
  cg.compute(Mt);
  const Eigen::VectorXd u = cg.solveWithGuess(b, guess);
  if (report) {
    report->iterations = static_cast<int>(cg.iterations());
    report->residual = cg.error();
  }
  return std::vector<double>(u.data(), u.data() + u.size());
}

void write_mixed_mass_matrix(const Supermesh& s, const std::filesystem::path& file) {
  check_polyhedra(s, "write_mixed_mass_matrix");
  const Eigen::SparseMatrix<double, Eigen::RowMajor> M = mixed_mass(s);
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.c_str(), "w"), &std::fclose);
  if (!f) throw std::runtime_error("tetia: " + file.string() + ": cannot open for writing");
  std::fprintf(f.get(), "%%%%MatrixMarket matrix coordinate real general\n");
  std::fprintf(f.get(),
               "%% tetia mixed mass matrix M_ts: entry (i, j) = integral over the supermesh of target "
               "P1 basis i times source P1 basis j; rows: %lld target nodes, columns: %lld source nodes\n",
               static_cast<long long>(M.rows()), static_cast<long long>(M.cols()));
  std::fprintf(f.get(), "%lld %lld %lld\n", static_cast<long long>(M.rows()), static_cast<long long>(M.cols()),
               static_cast<long long>(M.nonZeros()));
  for (Eigen::Index r = 0; r < M.outerSize(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(M, r); it; ++it)
      std::fprintf(f.get(), "%lld %lld %.17g\n", static_cast<long long>(it.row() + 1),
                   static_cast<long long>(it.col() + 1), it.value());
  if (std::ferror(f.get())) throw std::runtime_error("tetia: " + file.string() + ": write error");
}

double integral_p0(const TetMesh& mesh, std::span<const double> values) {
  check_size(values.size(), mesh.num_cells(), "integral_p0", "cell");
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) sum += values[c] * mesh.volumes[c];
  return sum;
}

double integral_p1(const TetMesh& mesh, std::span<const double> values) {
  check_size(values.size(), mesh.num_nodes(), "integral_p1", "node");
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cells[c];
    sum += 0.25 * mesh.volumes[c] * (values[idx(v[0])] + values[idx(v[1])] + values[idx(v[2])] + values[idx(v[3])]);
  }
  return sum;
}

std::vector<double> average_over_cells(const TetMesh& mesh, const std::function<double(Vec3)>& f) {
  const Rule& q = rule();
  std::vector<double> out(mesh.num_cells(), 0.0);
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const Tet T = mesh.cell(c);
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) s += q.weight[k] * f(at(T, q.bary[k]));
    out[c] = s;
  }
  return out;
}

double l2_error_p0(const TetMesh& mesh, std::span<const double> values, const std::function<double(Vec3)>& f) {
  check_size(values.size(), mesh.num_cells(), "l2_error_p0", "cell");
  const Rule& q = rule();
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const Tet T = mesh.cell(c);
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) {
      const double e = values[c] - f(at(T, q.bary[k]));
      s += q.weight[k] * e * e;
    }
    sum += s * mesh.volumes[c];
  }
  return std::sqrt(sum);
}

double l2_error_p1(const TetMesh& mesh, std::span<const double> values, const std::function<double(Vec3)>& f) {
  check_size(values.size(), mesh.num_nodes(), "l2_error_p1", "node");
  const Rule& q = rule();
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const Tet T = mesh.cell(c);
    const auto& v = mesh.cells[c];
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) {
      const auto& b = q.bary[k];
      const double uh = b[0] * values[idx(v[0])] + b[1] * values[idx(v[1])] + b[2] * values[idx(v[2])] +
                        b[3] * values[idx(v[3])];
      const double e = uh - f(at(T, b));
      s += q.weight[k] * e * e;
    }
    sum += s * mesh.volumes[c];
  }
  return std::sqrt(sum);
}

}  // namespace tetia
