// Discontinuous P1 remap (tetia/remap_methods.hpp): the L2 projection onto discontinuous P1 on
// the target, cell by cell, from a continuous or discontinuous P1 source; cell averages from a
// discontinuous source; and the helpers for discontinuous fields.
#include <vector>

#include "../compensated_sum.hpp"
#include "../supermesh/dimension.hpp"
#include "assembly.hpp"
#include "tetia/remap_methods.hpp"

namespace tetia {

namespace {

using namespace detail::remap;

// The source value of basis function j of a piece's source cell.
template <class Mesh>
double source_value(const Mesh& src, std::span<const double> u, P1Source kind, std::size_t cell, std::size_t j) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  return kind == P1Source::continuous ? u[idx(src.cells[cell][j])] : u[cell * nv + j];
}

template <class Mesh>
void check_source(const Mesh& src, std::span<const double> u, P1Source kind, const char* who) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  if (kind == P1Source::continuous) check_size(u.size(), src.num_nodes(), who, "source node");
  else check_size(u.size(), src.num_cells() * nv, who, "source cell-vertex");
}

template <class Mesh>
std::vector<double> discontinuous(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u, P1Source kind) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const char* who = "remap_p1_discontinuous";
  const MassSource from = check_mass_source<Mesh>(s, who);
  const Mesh& src = *s.source;
  const Mesh& tgt = *s.target;
  check_source(src, u, kind, who);
  // The loads per target cell and vertex, summed in the pieces' (target, source) order.
  std::vector<double> out(tgt.num_cells() * nv, 0.0);
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    double us[nv];
    for (std::size_t j = 0; j < nv; ++j) us[j] = source_value(src, u, kind, idx(pc.source), j);
    double* b = &out[idx(pc.target) * nv];
    for (std::size_t i = 0; i < nv; ++i) {
      double acc = 0.0;
      for (std::size_t j = 0; j < nv; ++j) acc += A[i * nv + j] * us[j];
      b[i] += acc;
    }
  });
  // The cell's mass matrix |T| / ((d + 1)(d + 2)) (I + J) inverted in closed form:
  // (I + J)^-1 = I - J / (nv + 1), nv + 1 = d + 2.
  const auto& measures = Dm::measures(tgt);
  constexpr double factor = (Dm::d + 1) * (Dm::d + 2);
  for (std::size_t t = 0; t < tgt.num_cells(); ++t) {
    double* b = &out[t * nv];
    if (!(measures[t] > 0.0)) {
      for (std::size_t i = 0; i < nv; ++i) b[i] = 0.0;
      continue;
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < nv; ++i) sum += b[i];
    const double scale = factor / measures[t];
    for (std::size_t i = 0; i < nv; ++i) b[i] = scale * (b[i] - sum * (1.0 / (nv + 1)));
  }
  return out;
}

template <class Mesh>
std::vector<double> p0_from_discontinuous(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u,
                                          P0Normalization normalization) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const char* who = "remap_p0_from_discontinuous";
  const MassSource from = check_mass_source<Mesh>(s, who);
  const Mesh& src = *s.source;
  const Mesh& tgt = *s.target;
  check_source(src, u, P1Source::discontinuous, who);
  std::vector<double> num(tgt.num_cells(), 0.0), cov(tgt.num_cells(), 0.0);
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    // The piece's integral of source basis function j is column j's sum (the target's basis
    // functions sum to 1).
    double acc = 0.0;
    for (std::size_t j = 0; j < nv; ++j) {
      double column = 0.0;
      for (std::size_t i = 0; i < nv; ++i) column += A[i * nv + j];
      acc += column * u[idx(pc.source) * nv + j];
    }
    num[idx(pc.target)] += acc;
    cov[idx(pc.target)] += Dm::measure(pc);
  });
  divide_by_p0_denominator(tgt, num, cov, normalization);
  return num;
}

template <class Mesh>
std::vector<double> from_nodes(const Mesh& m, std::span<const double> u) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  check_size(u.size(), m.num_nodes(), "discontinuous_from_nodes", "node");
  std::vector<double> out(m.num_cells() * nv);
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    for (std::size_t i = 0; i < nv; ++i) out[c * nv + i] = u[idx(m.cells[c][i])];
  return out;
}

template <class Mesh>
double integral_dg(const Mesh& m, std::span<const double> u) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  check_size(u.size(), m.num_cells() * nv, "integral_discontinuous", "cell-vertex");
  const auto& measures = Dm::measures(m);
  detail::CompensatedSum sum;
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    double nodal = u[c * nv];
    for (std::size_t i = 1; i < nv; ++i) nodal += u[c * nv + i];
    sum.add((1.0 / nv) * measures[c] * nodal);
  }
  return sum.value();
}

}  // namespace

std::vector<double> remap_p1_discontinuous(const Supermesh& s, std::span<const double> u, P1Source kind) {
  return discontinuous<TetMesh>(s, u, kind);
}
std::vector<double> remap_p1_discontinuous(const Supermesh2& s, std::span<const double> u, P1Source kind) {
  return discontinuous<TriMesh>(s, u, kind);
}
std::vector<double> remap_p0_from_discontinuous(const Supermesh& s, std::span<const double> u, P0Normalization n) {
  return p0_from_discontinuous<TetMesh>(s, u, n);
}
std::vector<double> remap_p0_from_discontinuous(const Supermesh2& s, std::span<const double> u, P0Normalization n) {
  return p0_from_discontinuous<TriMesh>(s, u, n);
}
std::vector<double> discontinuous_from_nodes(const TetMesh& m, std::span<const double> u) { return from_nodes(m, u); }
std::vector<double> discontinuous_from_nodes(const TriMesh& m, std::span<const double> u) { return from_nodes(m, u); }
double integral_discontinuous(const TetMesh& m, std::span<const double> u) { return integral_dg(m, u); }
double integral_discontinuous(const TriMesh& m, std::span<const double> u) { return integral_dg(m, u); }

}  // namespace tetia
