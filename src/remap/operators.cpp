// The linear remaps as sparse operators (tetia/remap_methods.hpp): cell averages, cell averages
// of a discontinuous source, lumped P1 and discontinuous P1, each W with W u the remap of u.
// Assembled from the pieces in their (target, source) order, so each row's entries come
// together and the matrices do not depend on the number of threads that built the supermesh.
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

#include "../supermesh/dimension.hpp"
#include "assembly.hpp"
#include "tetia/remap_methods.hpp"

namespace tetia {

namespace {

using namespace detail::remap;
using Triplets = std::vector<Eigen::Triplet<double, std::int64_t>>;

SparseMatrix from_triplets(std::size_t rows, std::size_t cols, const Triplets& t) {
  SparseMatrix m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  m.setFromTriplets(t.begin(), t.end());
  m.makeCompressed();
  return m;
}

// Each target cell's P0 denominator: its measure or its covered measure (0: the row stays
// empty, the cell's value 0 as remap_p0 gives it).
template <class Mesh>
std::vector<double> p0_denominators(const typename detail::Dim<Mesh>::Result& s, P0Normalization n) {
  if (n == P0Normalization::cell_volume) return detail::Dim<Mesh>::measures(*s.target);
  return covered_measures<Mesh>(s);
}

template <class Mesh>
SparseMatrix p0_op(const typename detail::Dim<Mesh>::Result& s, P0Normalization n) {
  check_meshes(s, "p0_operator");
  const std::vector<double> den = p0_denominators<Mesh>(s, n);
  Triplets t;
  t.reserve(s.pieces.size());
  for (const auto& pc : s.pieces)
    if (den[idx(pc.target)] > 0.0) t.emplace_back(pc.target, pc.source, detail::Dim<Mesh>::measure(pc) / den[idx(pc.target)]);
  return from_triplets(s.target->num_cells(), s.source->num_cells(), t);
}

template <class Mesh>
SparseMatrix p0_from_dg_op(const typename detail::Dim<Mesh>::Result& s, P0Normalization n) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  const MassSource from = check_mass_source<Mesh>(s, "p0_from_discontinuous_operator");
  const std::vector<double> den = p0_denominators<Mesh>(s, n);
  Triplets t;
  t.reserve(s.pieces.size() * nv);
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    const double d = den[idx(pc.target)];
    if (!(d > 0.0)) return;
    // The piece's integral of source basis function j: column j's sum (the target's basis
    // functions sum to 1), as remap_p0_from_discontinuous forms it.
    for (std::size_t j = 0; j < nv; ++j) {
      double column = 0.0;
      for (std::size_t i = 0; i < nv; ++i) column += A[i * nv + j];
      t.emplace_back(pc.target, static_cast<std::int64_t>(idx(pc.source) * nv + j), column / d);
    }
  });
  return from_triplets(s.target->num_cells(), s.source->num_cells() * nv, t);
}

template <class Mesh>
SparseMatrix lumped_op(const typename detail::Dim<Mesh>::Result& s) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const MassSource from = check_mass_source<Mesh>(s, "p1_lumped_operator");
  const Mesh& tgt = *s.target;
  const Mesh& src = *s.source;
  Triplets t;
  t.reserve(s.pieces.size() * nv * nv);
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    const auto& tn = tgt.cells[idx(pc.target)];
    const auto& sn = src.cells[idx(pc.source)];
    for (std::size_t i = 0; i < nv; ++i)
      for (std::size_t j = 0; j < nv; ++j) t.emplace_back(tn[i], sn[j], A[i * nv + j]);
  });
  SparseMatrix w = from_triplets(tgt.num_nodes(), src.num_nodes(), t);  // M_ts
  divide_rows(w, lumped_mass(tgt));  // by the lumped masses m_i
  return w;
}

template <class Mesh>
SparseMatrix dg_op(const typename detail::Dim<Mesh>::Result& s, P1Source kind) {
  using Dm = detail::Dim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  const MassSource from = check_mass_source<Mesh>(s, "p1_discontinuous_operator");
  const Mesh& tgt = *s.target;
  const Mesh& src = *s.source;
  const auto& measures = Dm::measures(tgt);
  constexpr double factor = (Dm::d + 1) * (Dm::d + 2);
  // Per target cell: its block of the cell-local mixed mass matrix (rows: the cell's vertices,
  // columns: source values), then the closed-form inverse of the cell's mass matrix applied:
  // row i -> (d + 1)(d + 2) / |T| (row i - sum of the rows / (d + 2)).
  struct Entry {
    std::int64_t col;
    double row[nv];
  };
  std::vector<Entry> block;
  Triplets t;
  t.reserve(s.pieces.size() * nv * nv);
  std::int64_t current = -1;
  const auto flush = [&] {
    if (current < 0 || block.empty()) return;
    std::sort(block.begin(), block.end(), [](const Entry& a, const Entry& b) { return a.col < b.col; });
    const double m = measures[static_cast<std::size_t>(current)];
    if (m > 0.0) {
      const double scale = factor / m;
      for (std::size_t e = 0; e < block.size();) {
        double r[nv] = {};
        std::size_t f = e;
        for (; f < block.size() && block[f].col == block[e].col; ++f)
          for (std::size_t i = 0; i < nv; ++i) r[i] += block[f].row[i];
        double sum = 0.0;
        for (std::size_t i = 0; i < nv; ++i) sum += r[i];
        for (std::size_t i = 0; i < nv; ++i)
          t.emplace_back(current * static_cast<std::int64_t>(nv) + static_cast<std::int64_t>(i), block[e].col,
                         scale * (r[i] - sum * (1.0 / (nv + 1))));
        e = f;
      }
    }
    block.clear();
  };
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    if (pc.target != current) {
      flush();
      current = pc.target;
    }
    const auto& sn = src.cells[idx(pc.source)];
    for (std::size_t j = 0; j < nv; ++j) {
      Entry e{kind == P1Source::continuous ? std::int64_t{sn[j]}
                                           : static_cast<std::int64_t>(idx(pc.source) * nv + j),
              {}};
      for (std::size_t i = 0; i < nv; ++i) e.row[i] = A[i * nv + j];
      block.push_back(e);
    }
  });
  flush();
  const std::size_t cols = kind == P1Source::continuous ? src.num_nodes() : src.num_cells() * nv;
  return from_triplets(tgt.num_cells() * nv, cols, t);
}

}  // namespace

std::vector<double> apply_operator(const SparseMatrix& w, std::span<const double> u) {
  check_size(u.size(), static_cast<std::size_t>(w.cols()), "apply_operator", "field");
  std::vector<double> out(static_cast<std::size_t>(w.rows()), 0.0);
  for (Eigen::Index r = 0; r < w.outerSize(); ++r) {
    double sum = 0.0;
    for (SparseMatrix::InnerIterator it(w, r); it; ++it) sum += it.value() * u[static_cast<std::size_t>(it.col())];
    out[static_cast<std::size_t>(r)] = sum;
  }
  return out;
}

SparseMatrix p0_operator(const Supermesh& s, P0Normalization n) { return p0_op<TetMesh>(s, n); }
SparseMatrix p0_operator(const Supermesh2& s, P0Normalization n) { return p0_op<TriMesh>(s, n); }
SparseMatrix p0_from_discontinuous_operator(const Supermesh& s, P0Normalization n) { return p0_from_dg_op<TetMesh>(s, n); }
SparseMatrix p0_from_discontinuous_operator(const Supermesh2& s, P0Normalization n) {
  return p0_from_dg_op<TriMesh>(s, n);
}
SparseMatrix p1_lumped_operator(const Supermesh& s) { return lumped_op<TetMesh>(s); }
SparseMatrix p1_lumped_operator(const Supermesh2& s) { return lumped_op<TriMesh>(s); }
SparseMatrix p1_discontinuous_operator(const Supermesh& s, P1Source kind) { return dg_op<TetMesh>(s, kind); }
SparseMatrix p1_discontinuous_operator(const Supermesh2& s, P1Source kind) { return dg_op<TriMesh>(s, kind); }

}  // namespace tetia
