// Conservative remap on a supermesh: P0 by piece volumes, P1 by the Galerkin L2 projection
// with the mixed mass matrix integrated exactly on each piece's simplices (tetrahedra of a
// polyhedron, triangles of a polygon's fan).
//
// One implementation for both dimensions: templates over the mesh type (src/supermesh/dimension.hpp).
// The products of two linear functions on a simplex of dimension d integrate to
// |S| / ((d + 1)(d + 2)) (sum_v f_v g_v + (sum_v f_v)(sum_v g_v)): 1/20 in 3D, 1/12 in 2D; the
// consistent mass matrix is the case f = g = basis functions. A piece's local mixed mass matrix
// is computed in src/supermesh/mixed_mass.hpp (shared with the supermesh, which can keep it instead of
// the polyhedron: SupermeshOptions::keep_mixed_mass); the quadrature rule is written per
// dimension here.
#include "tetia/remap.hpp"
#include "tetia/remap_methods.hpp"

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

#include "compensated_sum.hpp"
#include "supermesh/dimension.hpp"
#include "remap/assembly.hpp"

namespace tetia {

namespace {

using namespace detail::remap;

// Conical product Gauss rules (Duffy map of 4 Gauss-Legendre points per axis) on the reference
// simplex: 4^3 = 64 points on the tetrahedron, exact for degree 5 (the Jacobian (1-u)^2 (1-v)
// takes two of the 7 degrees in u), 4^2 = 16 points on the triangle, exact for degree 6 (the
// Jacobian (1-u) takes one). Points as barycentric coordinates, weights summing to 1 (multiply
// by the cell's measure).
template <int D>
struct Rule {
  static constexpr std::size_t n = D == 3 ? 64 : 16;
  std::array<std::array<double, D + 1>, n> bary;
  std::array<double, n> weight;
};

template <int D>
const Rule<D>& rule() {
  static const Rule<D> r = [] {
    Rule<D> q{};
    const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    std::size_t n = 0;
    if constexpr (D == 3) {
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
    } else {
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double u = 0.5 * (1.0 + x[a]), v = 0.5 * (1.0 + x[b]);
          const double x1 = u, x2 = v * (1.0 - u);
          q.bary[n] = {1.0 - x1 - x2, x1, x2};
          // Jacobian (1-u), Gauss weights on [0,1] (w/2 each), reference area 1/2.
          q.weight[n] = 2.0 * (0.25 * w[a] * w[b]) * (1.0 - u);
          ++n;
        }
    }
    return q;
  }();
  return r;
}

template <class Cell, std::size_t N>
auto at(const Cell& T, const std::array<double, N>& b) {
  auto p = b[0] * T[0];
  for (std::size_t k = 1; k < N; ++k) p = p + b[k] * T[k];
  return p;
}

template <class Mesh>
std::vector<double> covered(const typename detail::Dim<Mesh>::Result& s, const char* who) {
  check_meshes(s, who);
  return covered_measures<Mesh>(s);
}

template <class Mesh>
std::vector<double> p0(const typename detail::Dim<Mesh>::Result& s, std::span<const double> values,
                       P0Normalization normalization) {
  using Dm = detail::Dim<Mesh>;
  check_meshes(s, "remap_p0");
  check_size(values.size(), s.source->num_cells(), "remap_p0", "source cell");
  const Mesh& tgt = *s.target;
  std::vector<double> out(tgt.num_cells(), 0.0);
  // Pieces are sorted by target: one pass, each target's sum in source order.
  std::size_t k = 0;
  while (k < s.pieces.size()) {
    const std::int32_t t = s.pieces[k].target;
    double num = 0.0, cov = 0.0;
    for (; k < s.pieces.size() && s.pieces[k].target == t; ++k) {
      const double m = Dm::measure(s.pieces[k]);
      num += values[idx(s.pieces[k].source)] * m;
      cov += m;
    }
    const double den = normalization == P0Normalization::covered_volume ? cov : Dm::measures(tgt)[idx(t)];
    out[idx(t)] = den > 0.0 ? num / den : 0.0;
  }
  return out;
}

template <class Mesh>
std::vector<double> p1(const typename detail::Dim<Mesh>::Result& s, std::span<const double> values,
                       P1RemapReport* report) {
  const MassSource from = check_mass_source<Mesh>(s, "remap_p1");
  check_size(values.size(), s.source->num_nodes(), "remap_p1", "source node");
  const Eigen::VectorXd b = mixed_mass_times<Mesh>(s, from, values);
  return solve_target_mass(consistent_mass(*s.target, true), b, report);
}

template <class Mesh>
void write_mixed(const typename detail::Dim<Mesh>::Result& s, const std::filesystem::path& file) {
  const MassSource from = check_mass_source<Mesh>(s, "write_mixed_mass_matrix");
  const Eigen::SparseMatrix<double, Eigen::RowMajor> M = mixed_mass<Mesh>(s, from);
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

template <class Mesh>
double int_p0(const Mesh& mesh, std::span<const double> values) {
  check_size(values.size(), mesh.num_cells(), "integral_p0", "cell");
  const auto& measures = detail::Dim<Mesh>::measures(mesh);
  detail::CompensatedSum sum;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) sum.add(values[c] * measures[c]);
  return sum.value();
}

template <class Mesh>
double int_p1(const Mesh& mesh, std::span<const double> values) {
  using Dm = detail::Dim<Mesh>;
  check_size(values.size(), mesh.num_nodes(), "integral_p1", "node");
  const auto& measures = Dm::measures(mesh);
  detail::CompensatedSum sum;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cells[c];
    double nodal = values[idx(v[0])];
    for (std::size_t k = 1; k < Dm::nv; ++k) nodal += values[idx(v[k])];
    sum.add((1.0 / Dm::nv) * measures[c] * nodal);
  }
  return sum.value();
}

template <class Mesh, class F>
std::vector<double> averages(const Mesh& mesh, const F& f) {
  const auto& q = rule<detail::Dim<Mesh>::d>();
  std::vector<double> out(mesh.num_cells(), 0.0);
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const auto T = mesh.cell(c);
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) s += q.weight[k] * f(at(T, q.bary[k]));
    out[c] = s;
  }
  return out;
}

template <class Mesh, class F>
double err_p0(const Mesh& mesh, std::span<const double> values, const F& f) {
  check_size(values.size(), mesh.num_cells(), "l2_error_p0", "cell");
  const auto& q = rule<detail::Dim<Mesh>::d>();
  const auto& measures = detail::Dim<Mesh>::measures(mesh);
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const auto T = mesh.cell(c);
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) {
      const double e = values[c] - f(at(T, q.bary[k]));
      s += q.weight[k] * e * e;
    }
    sum += s * measures[c];
  }
  return std::sqrt(sum);
}

// The L2 error of a piecewise linear field given by its values at each cell's vertices:
// vertex_value(c, k) for vertex k of cell c (a continuous field's node values, or a
// discontinuous one's own per cell).
template <class Mesh, class VertexValue, class F>
double err_linear(const Mesh& mesh, const VertexValue& vertex_value, const F& f) {
  using Dm = detail::Dim<Mesh>;
  const auto& q = rule<Dm::d>();
  const auto& measures = Dm::measures(mesh);
  double sum = 0.0;
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    const auto T = mesh.cell(c);
    double s = 0.0;
    for (std::size_t k = 0; k < q.weight.size(); ++k) {
      const auto& b = q.bary[k];
      double uh = b[0] * vertex_value(c, 0);
      for (std::size_t j = 1; j < Dm::nv; ++j) uh += b[j] * vertex_value(c, j);
      const double e = uh - f(at(T, b));
      s += q.weight[k] * e * e;
    }
    sum += s * measures[c];
  }
  return std::sqrt(sum);
}

template <class Mesh, class F>
double err_p1(const Mesh& mesh, std::span<const double> values, const F& f) {
  check_size(values.size(), mesh.num_nodes(), "l2_error_p1", "node");
  return err_linear(mesh, [&](std::size_t c, std::size_t k) { return values[idx(mesh.cells[c][k])]; }, f);
}

template <class Mesh, class F>
double err_discontinuous(const Mesh& mesh, std::span<const double> values, const F& f) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  check_size(values.size(), mesh.num_cells() * nv, "l2_error_discontinuous", "cell-vertex");
  return err_linear(mesh, [&](std::size_t c, std::size_t k) { return values[c * nv + k]; }, f);
}

}  // namespace

// 3D

std::vector<double> covered_volumes(const Supermesh& s) { return covered<TetMesh>(s, "covered_volumes"); }

std::vector<double> remap_p0(const Supermesh& s, std::span<const double> values, P0Normalization normalization) {
  return p0<TetMesh>(s, values, normalization);
}

std::vector<double> remap_p1(const Supermesh& s, std::span<const double> values, P1RemapReport* report) {
  return p1<TetMesh>(s, values, report);
}

void write_mixed_mass_matrix(const Supermesh& s, const std::filesystem::path& file) { write_mixed<TetMesh>(s, file); }

SparseMatrix mixed_mass_matrix(const Supermesh& s) {
  return SparseMatrix(mixed_mass<TetMesh>(s, check_mass_source<TetMesh>(s, "mixed_mass_matrix")));
}
SparseMatrix mass_matrix(const TetMesh& mesh) { return SparseMatrix(consistent_mass(mesh, false)); }

double integral_p0(const TetMesh& mesh, std::span<const double> values) { return int_p0(mesh, values); }
double integral_p1(const TetMesh& mesh, std::span<const double> values) { return int_p1(mesh, values); }

std::vector<double> average_over_cells(const TetMesh& mesh, const std::function<double(Vec3)>& f) {
  return averages(mesh, f);
}

double l2_error_p0(const TetMesh& mesh, std::span<const double> values, const std::function<double(Vec3)>& f) {
  return err_p0(mesh, values, f);
}

double l2_error_p1(const TetMesh& mesh, std::span<const double> values, const std::function<double(Vec3)>& f) {
  return err_p1(mesh, values, f);
}

double l2_error_discontinuous(const TetMesh& mesh, std::span<const double> values, const std::function<double(Vec3)>& f) {
  return err_discontinuous(mesh, values, f);
}

// 2D

std::vector<double> covered_areas(const Supermesh2& s) { return covered<TriMesh>(s, "covered_areas"); }

std::vector<double> remap_p0(const Supermesh2& s, std::span<const double> values, P0Normalization normalization) {
  return p0<TriMesh>(s, values, normalization);
}

std::vector<double> remap_p1(const Supermesh2& s, std::span<const double> values, P1RemapReport* report) {
  return p1<TriMesh>(s, values, report);
}

void write_mixed_mass_matrix(const Supermesh2& s, const std::filesystem::path& file) { write_mixed<TriMesh>(s, file); }

SparseMatrix mixed_mass_matrix(const Supermesh2& s) {
  return SparseMatrix(mixed_mass<TriMesh>(s, check_mass_source<TriMesh>(s, "mixed_mass_matrix")));
}
SparseMatrix mass_matrix(const TriMesh& mesh) { return SparseMatrix(consistent_mass(mesh, false)); }

double integral_p0(const TriMesh& mesh, std::span<const double> values) { return int_p0(mesh, values); }
double integral_p1(const TriMesh& mesh, std::span<const double> values) { return int_p1(mesh, values); }

std::vector<double> average_over_cells(const TriMesh& mesh, const std::function<double(Vec2)>& f) {
  return averages(mesh, f);
}

double l2_error_p0(const TriMesh& mesh, std::span<const double> values, const std::function<double(Vec2)>& f) {
  return err_p0(mesh, values, f);
}

double l2_error_p1(const TriMesh& mesh, std::span<const double> values, const std::function<double(Vec2)>& f) {
  return err_p1(mesh, values, f);
}

double l2_error_discontinuous(const TriMesh& mesh, std::span<const double> values, const std::function<double(Vec2)>& f) {
  return err_discontinuous(mesh, values, f);
}

}  // namespace tetia
