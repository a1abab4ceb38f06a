// src/remap/assembly.hpp -- the sparse pieces the remap is built from (internal to the library):
// the mixed mass matrix M_ts from the pieces' local matrices, its product with a field without
// forming it, a mesh's consistent mass matrix M_t, and the conjugate gradient solve of
// M_t u_t = b that P1 remap ends with. Shared by the free functions (src/remap.cpp) and the
// operator built once (src/remap/remap_operator.cpp), so that both give the same numbers bit
// for bit.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "../supermesh/dimension.hpp"
#include "../supermesh/mixed_mass.hpp"
#include "tetia/remap.hpp"

namespace tetia::detail::remap {

using SpMat = Eigen::SparseMatrix<double>;  // column major
using Triplet = Eigen::Triplet<double>;

template <class Result>
void check_meshes(const Result& s, const char* who) {
  if (s.source == nullptr || s.target == nullptr)
    throw std::invalid_argument(std::string("tetia: ") + who + ": the supermesh has no source or target mesh");
}

// Where the local mixed mass matrices come from: kept by the supermesh (keep_mixed_mass), else
// computed from its kept polyhedra / polygons (keep_polyhedra), the same numbers bit for bit.
enum class MassSource { local_mass, shapes };

template <class Mesh>
MassSource check_mass_source(const typename detail::Dim<Mesh>::Result& s, const char* who) {
  using Dm = detail::Dim<Mesh>;
  check_meshes(s, who);
  if (Dm::local_mass(s).size() == s.pieces.size()) return MassSource::local_mass;
  if (Dm::shapes(s).size() == s.pieces.size()) return MassSource::shapes;
  throw std::invalid_argument(std::string("tetia: ") + who + ": the supermesh has no local mixed mass matrices and no " +
                              (Dm::d == 3 ? "polyhedra" : "polygons") +
                              "; build it with SupermeshOptions::keep_mixed_mass = true (or keep_polyhedra = true)");
}

inline void check_size(std::size_t got, std::size_t want, const char* who, const char* what) {
  if (got != want)
    throw std::invalid_argument(std::string("tetia: ") + who + ": " + std::to_string(got) + " " + what +
                                " values, the mesh has " + std::to_string(want));
}

inline std::size_t idx(std::int32_t i) { return static_cast<std::size_t>(i); }

// Calls f(piece, A) for each piece in (target, source) order, A its local mixed mass matrix
// (row-major, nv x nv: target cell's basis i times source cell's basis j): kept by the
// supermesh, or computed here from the kept shape (src/supermesh/mixed_mass.hpp), the same values
// either way. Pieces without a shape (never one of positive volume) are skipped.
template <class Mesh, class F>
void for_each_piece_mass(const typename detail::Dim<Mesh>::Result& s, MassSource from, F&& f) {
  using Dm = detail::Dim<Mesh>;
  const Mesh& src = *s.source;
  const auto& shapes = Dm::shapes(s);
  const auto& kept = Dm::local_mass(s);
  typename Dm::LocalMass local{};
  for (std::size_t k = 0; k < s.pieces.size(); ++k) {
    const auto& pc = s.pieces[k];
    if (from == MassSource::shapes) {
      const auto& P = shapes[k];
      if (P.empty()) continue;  // never for a piece of positive volume
      detail::piece_mixed_mass<Mesh>(src.cell(idx(pc.source)), P, local);
    }
    f(pc, from == MassSource::local_mass ? kept[k] : local);
  }
}

// The same with the target and source cells' nodes: f(target cell's nodes, source cell's nodes, A).
template <class Mesh, class F>
void for_each_local_mass(const typename detail::Dim<Mesh>::Result& s, MassSource from, F&& f) {
  const Mesh& src = *s.source;
  const Mesh& tgt = *s.target;
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    f(tgt.cells[idx(pc.target)], src.cells[idx(pc.source)], A);
  });
}

// M_ts from the pieces' local mixed mass matrices; the triplets come in the same order whatever
// their source, so the sums are too.
template <class Mesh>
SpMat mixed_mass(const typename detail::Dim<Mesh>::Result& s, MassSource from) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  std::vector<Triplet> trip;
  trip.reserve(s.pieces.size() * nv * nv);
  for_each_local_mass<Mesh>(s, from, [&](const auto& tn, const auto& sn, const auto& A) {
    for (std::size_t i = 0; i < nv; ++i)
      for (std::size_t j = 0; j < nv; ++j) trip.emplace_back(tn[i], sn[j], A[i * nv + j]);
  });
  SpMat M(static_cast<Eigen::Index>(s.target->num_nodes()), static_cast<Eigen::Index>(s.source->num_nodes()));
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

// M_ts u_s without forming M_ts: each piece adds its local matrix times the source values at
// its source cell's nodes to its target cell's nodes. P1 remap needs only this product; the
// matrix itself (16 triplets a piece, then a sort) cost more time and memory than the
// supermesh at 10^6 cells. Pieces are visited in their (target, source) order, so the sums do
// not depend on the number of threads that built the supermesh.
template <class Mesh>
Eigen::VectorXd mixed_mass_times(const typename detail::Dim<Mesh>::Result& s, MassSource from,
                                 std::span<const double> u) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(s.target->num_nodes()));
  for_each_local_mass<Mesh>(s, from, [&](const auto& tn, const auto& sn, const auto& A) {
    double us[nv];
    for (std::size_t j = 0; j < nv; ++j) us[j] = u[idx(sn[j])];
    for (std::size_t i = 0; i < nv; ++i) {
      double acc = 0.0;
      for (std::size_t j = 0; j < nv; ++j) acc += A[i * nv + j] * us[j];
      b[tn[i]] += acc;
    }
  });
  return b;
}

// Per target cell, the measure the source covers: the sum of its pieces' measures, in piece
// order (covered_volumes, the P0 denominators, the cell coverage).
template <class Mesh>
std::vector<double> covered_measures(const typename detail::Dim<Mesh>::Result& s) {
  std::vector<double> cov(s.target->num_cells(), 0.0);
  for (const auto& pc : s.pieces) cov[idx(pc.target)] += detail::Dim<Mesh>::measure(pc);
  return cov;
}

// The integral of each basis function of a mesh: sum over its cells of |T| / nv (the row sums
// of the consistent mass matrix, the lumped mass).
template <class Mesh>
std::vector<double> lumped_mass(const Mesh& m) {
  using Dm = detail::Dim<Mesh>;
  std::vector<double> out(m.num_nodes(), 0.0);
  const auto& measures = Dm::measures(m);
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    for (const auto v : m.cells[c]) out[idx(v)] += measures[c] * (1.0 / Dm::nv);
  return out;
}

// An operator's rows divided by by[row] (lumped masses, covered fractions); a row with
// by[row] = 0 is emptied: nothing covers it.
inline void divide_rows(SparseMatrix& w, const std::vector<double>& by) {
  for (Eigen::Index r = 0; r < w.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(w, r); it; ++it) {
      const double d = by[static_cast<std::size_t>(r)];
      it.valueRef() = d > 0.0 ? it.value() / d : 0.0;
    }
  w.prune([&](Eigen::Index r, Eigen::Index, double) { return by[static_cast<std::size_t>(r)] > 0.0; });
}

// P0's division of each target cell's integral by its measure (cell_volume) or its covered
// measure (covered_volume); 0 where that is 0.
template <class Mesh>
void divide_by_p0_denominator(const Mesh& target, std::vector<double>& integrals, const std::vector<double>& covered,
                              P0Normalization normalization) {
  const auto& measures = detail::Dim<Mesh>::measures(target);
  for (std::size_t t = 0; t < integrals.size(); ++t) {
    const double den = normalization == P0Normalization::covered_volume ? covered[t] : measures[t];
    integrals[t] = den > 0.0 ? integrals[t] / den : 0.0;
  }
}

template <class Mesh>
SpMat consistent_mass(const Mesh& m, bool unit_for_unused) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  constexpr double factor = (Dm::d + 1) * (Dm::d + 2);
  const auto& measures = Dm::measures(m);
  std::vector<Triplet> trip;
  trip.reserve(m.num_cells() * nv * nv);
  std::vector<char> used(m.num_nodes(), 0);
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const double w = measures[c] / factor;
    if (!(w > 0.0)) continue;
    const auto& v = m.cells[c];
    for (std::size_t i = 0; i < nv; ++i) {
      used[idx(v[i])] = 1;
      for (std::size_t j = 0; j < nv; ++j) trip.emplace_back(v[i], v[j], i == j ? 2.0 * w : w);
    }
  }
  for (std::size_t n = 0; n < m.num_nodes() && unit_for_unused; ++n)
    if (!used[n]) trip.emplace_back(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n), 1.0);
  SpMat M(static_cast<Eigen::Index>(m.num_nodes()), static_cast<Eigen::Index>(m.num_nodes()));
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

// Solves M_t u = b by conjugate gradients (Jacobi preconditioned, tolerance 1e-14 relative),
// from the lumped-mass solution b_i / sum_j (M_t)_ij. `Mt` is consistent_mass(target, true).
inline std::vector<double> solve_target_mass(const SpMat& Mt, const Eigen::VectorXd& b, P1RemapReport* report) {
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

}  // namespace tetia::detail::remap
