// The remap operator built once (tetia/remap_operator.hpp): what it keeps, and its application
// by the same loops as the free functions (src/remap.cpp, src/remap/assembly.hpp), so that the
// two agree bit for bit.
#include "tetia/remap_operator.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "../supermesh/dimension.hpp"
#include "assembly.hpp"
#include "tetia/file_cells.hpp"

namespace tetia {

namespace {

using namespace detail::remap;

void check_order(int order) {
  if (order != 0 && order != 1)
    throw std::invalid_argument("tetia: Remap: order must be 0 or 1, not " + std::to_string(order));
}

}  // namespace

template <class Mesh>
BasicRemap<Mesh>::BasicRemap(std::shared_ptr<const Mesh> source, std::shared_ptr<const Mesh> target,
                             const RemapOptions& options) {
  check_order(options.order);
  if (!source || !target) throw std::invalid_argument("tetia: Remap: a mesh is null");
  SupermeshOptions so = options.supermesh;
  so.keep_polyhedra = false;
  so.keep_mixed_mass = options.order == 1;  // all that P1 needs of the pieces
  supermesh_ = tetia::supermesh(std::move(source), std::move(target), so);
  order_ = options.order;
  prepare(options.normalization);
}

template <class Mesh>
BasicRemap<Mesh>::BasicRemap(Result supermesh, int order, P0Normalization normalization)
    : supermesh_(std::move(supermesh)), order_(order) {
  check_order(order);
  check_meshes(supermesh_, "Remap");
  if (order == 1) check_mass_source<Mesh>(supermesh_, "Remap");
  prepare(normalization);
}

template <class Mesh>
void BasicRemap<Mesh>::prepare(P0Normalization normalization) {
  using Dm = detail::Dim<Mesh>;
  const Mesh& tgt = *supermesh_.target;
  if (order_ == 1) {
    solver_mass_ = consistent_mass(tgt, true);
    return;
  }
  const auto pairs = file_cell_pairs(supermesh_);
  pair_target_.reserve(pairs.pairs.size());
  pair_source_.reserve(pairs.pairs.size());
  pair_measure_.reserve(pairs.pairs.size());
  for (const auto& p : pairs.pairs) {
    pair_target_.push_back(p.target);
    pair_source_.push_back(p.source);
    pair_measure_.push_back(Dm::measure(p));
  }
  if (normalization == P0Normalization::covered_volume) {
    // Each target's covered measure summed in its pairs' order, as remap_p0 sums it.
    denominator_.assign(tgt.num_file_cells(), 0.0);
    std::size_t k = 0;
    while (k < pair_target_.size()) {
      const std::int32_t t = pair_target_[k];
      double cov = 0.0;
      for (; k < pair_target_.size() && pair_target_[k] == t; ++k) cov += pair_measure_[k];
      denominator_[idx(t)] = cov;
    }
  } else {
    denominator_ = file_cell_measures(tgt);
  }
}

template <class Mesh>
std::size_t BasicRemap<Mesh>::rows() const {
  return order_ == 0 ? supermesh_.target->num_file_cells() : supermesh_.target->num_nodes();
}

template <class Mesh>
std::size_t BasicRemap<Mesh>::cols() const {
  return order_ == 0 ? supermesh_.source->num_file_cells() : supermesh_.source->num_nodes();
}

template <class Mesh>
std::vector<double> BasicRemap<Mesh>::apply(std::span<const double> field, int components,
                                            P1RemapReport* report) const {
  if (components < 1) throw std::invalid_argument("tetia: Remap: components must be at least 1");
  const auto nc = static_cast<std::size_t>(components);
  const std::size_t n_in = cols(), n_out = rows();
  if (field.size() != n_in * nc)
    throw std::invalid_argument("tetia: Remap: " + std::to_string(field.size()) + " values for " +
                                std::to_string(n_in) + (order_ == 0 ? " source cells" : " source nodes") + " x " +
                                std::to_string(components) + " components");
  std::vector<double> out(n_out * nc, 0.0);
  if (order_ == 0) {
    // Pairs are sorted by target: one pass, each target's sum in source order (remap_p0's loop).
    const std::size_t np = pair_target_.size();
    std::vector<double> num(nc);
    std::size_t k = 0;
    while (k < np) {
      const std::int32_t t = pair_target_[k];
      std::fill(num.begin(), num.end(), 0.0);
      for (; k < np && pair_target_[k] == t; ++k) {
        const double m = pair_measure_[k];
        const double* u = field.data() + idx(pair_source_[k]) * nc;
        for (std::size_t c = 0; c < nc; ++c) num[c] += u[c] * m;
      }
      const double den = denominator_[idx(t)];
      for (std::size_t c = 0; c < nc; ++c) out[idx(t) * nc + c] = den > 0.0 ? num[c] / den : 0.0;
    }
    return out;
  }
  const MassSource from = check_mass_source<Mesh>(supermesh_, "Remap");
  std::vector<double> column(n_in);
  for (std::size_t c = 0; c < nc; ++c) {
    for (std::size_t i = 0; i < n_in; ++i) column[i] = field[i * nc + c];
    const Eigen::VectorXd b = mixed_mass_times<Mesh>(supermesh_, from, column);
    const std::vector<double> u = solve_target_mass(solver_mass_, b, report);
    for (std::size_t i = 0; i < n_out; ++i) out[i * nc + c] = u[i];
  }
  return out;
}

template <class Mesh>
SparseMatrix BasicRemap<Mesh>::mixed_mass() const {
  if (order_ == 1) return SparseMatrix(detail::remap::mixed_mass<Mesh>(supermesh_, check_mass_source<Mesh>(supermesh_, "Remap")));
  SparseMatrix M(static_cast<Eigen::Index>(rows()), static_cast<Eigen::Index>(cols()));
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(pair_target_.size());
  for (std::size_t k = 0; k < pair_target_.size(); ++k) trip.emplace_back(pair_target_[k], pair_source_[k], pair_measure_[k]);
  M.setFromTriplets(trip.begin(), trip.end());  // one entry per pair: nothing is summed
  return M;
}

template <class Mesh>
SparseMatrix BasicRemap<Mesh>::target_mass() const {
  if (order_ == 1) return SparseMatrix(consistent_mass(*supermesh_.target, false));
  SparseMatrix M(static_cast<Eigen::Index>(rows()), static_cast<Eigen::Index>(rows()));
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(denominator_.size());
  for (std::size_t t = 0; t < denominator_.size(); ++t)
    if (denominator_[t] != 0.0) trip.emplace_back(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(t), denominator_[t]);
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

template <class Mesh>
SparseMatrix BasicRemap<Mesh>::matrix() const {
  if (order_ == 1)
    throw std::logic_error(
        "tetia: Remap: order 1 has no sparse operator (M_t^-1 M_ts is dense); use mixed_mass() (M_ts) and "
        "target_mass() (M_t), or apply()");
  SparseMatrix M(static_cast<Eigen::Index>(rows()), static_cast<Eigen::Index>(cols()));
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(pair_target_.size());
  for (std::size_t k = 0; k < pair_target_.size(); ++k) {
    const double den = denominator_[idx(pair_target_[k])];
    if (den > 0.0) trip.emplace_back(pair_target_[k], pair_source_[k], pair_measure_[k] / den);
  }
  M.setFromTriplets(trip.begin(), trip.end());
  return M;
}

template <class Mesh>
std::vector<double> BasicRemap<Mesh>::coverage() const {
  using Dm = detail::Dim<Mesh>;
  const Mesh& tgt = *supermesh_.target;
  const std::vector<double> measures = file_cell_measures(tgt);
  std::vector<double> covered(measures.size(), 0.0);
  if (order_ == 0) {
    for (std::size_t k = 0; k < pair_target_.size(); ++k) covered[idx(pair_target_[k])] += pair_measure_[k];
  } else {
    for (const auto& p : supermesh_.pieces) covered[tgt.file_cell(idx(p.target))] += Dm::measure(p);
  }
  for (std::size_t t = 0; t < covered.size(); ++t) covered[t] = measures[t] > 0.0 ? covered[t] / measures[t] : 0.0;
  return covered;
}

template class BasicRemap<TetMesh>;
template class BasicRemap<TriMesh>;

}  // namespace tetia
