// The remap operator built once (tetia/remap_operator.hpp): what it keeps, and its application:
// the linear methods (P0, lumped, discontinuous) by their matrix (apply_operator), the Galerkin
// P1 by the free function's loops (src/remap/assembly.hpp), bit for bit remap_p1, the bounded P1
// and the reconstruction by their free functions.
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

void check_order(int order, RemapMethod method) {
  if (order != 0 && order != 1)
    throw std::invalid_argument("tetia: Remap: order must be 0 or 1, not " + std::to_string(order));
  if ((method == RemapMethod::lumped || method == RemapMethod::bounded) && order != 1)
    throw std::invalid_argument("tetia: Remap: the lumped and bounded methods are P1: order must be 1");
  if (method == RemapMethod::linear_reconstruction && order != 0)
    throw std::invalid_argument("tetia: Remap: the linear reconstruction remaps cell averages: order must be 0");
}

// What the pieces must keep: the local mixed mass matrices for P1 and for the discontinuous
// methods; nothing else for cell averages and their reconstruction.
bool needs_mass(int order, RemapMethod method) { return order == 1 || method == RemapMethod::discontinuous; }

}  // namespace

template <class Mesh>
BasicRemap<Mesh>::BasicRemap(std::shared_ptr<const Mesh> source, std::shared_ptr<const Mesh> target,
                             const RemapOptions& options) {
  check_order(options.order, options.method);
  if (!source || !target) throw std::invalid_argument("tetia: Remap: a mesh is null");
  SupermeshOptions so = options.supermesh;
  so.keep_polyhedra = false;
  so.keep_mixed_mass = needs_mass(options.order, options.method);  // all that the method needs of the pieces
  supermesh_ = tetia::supermesh(std::move(source), std::move(target), so);
  order_ = options.order;
  method_ = options.method;
  prepare(options.normalization);
}

template <class Mesh>
BasicRemap<Mesh>::BasicRemap(Result supermesh, int order, P0Normalization normalization, RemapMethod method)
    : supermesh_(std::move(supermesh)), order_(order), method_(method) {
  check_order(order, method);
  check_meshes(supermesh_, "Remap");
  if (needs_mass(order, method)) check_mass_source<Mesh>(supermesh_, "Remap");
  prepare(normalization);
}

template <class Mesh>
void BasicRemap<Mesh>::prepare(P0Normalization normalization) {
  using Dm = detail::Dim<Mesh>;
  const Mesh& tgt = *supermesh_.target;
  normalization_ = normalization;
  if (order_ == 1) {
    if (method_ == RemapMethod::standard) solver_mass_ = consistent_mass(tgt, true);
    if (method_ == RemapMethod::lumped) {
      operator_ = p1_lumped_operator(supermesh_);
      if (normalization == P0Normalization::covered_volume) divide_rows(operator_, node_coverage());
    }
    if (method_ == RemapMethod::discontinuous) operator_ = p1_discontinuous_operator(supermesh_);
    operator_.makeCompressed();
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
  if (method_ == RemapMethod::standard) {  // W = diag(1 / d_T) M, one entry per pair of file cells
    operator_ = SparseMatrix(static_cast<Eigen::Index>(rows()), static_cast<Eigen::Index>(cols()));
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(pair_target_.size());
    for (std::size_t k = 0; k < pair_target_.size(); ++k) {
      const double den = denominator_[idx(pair_target_[k])];
      if (den > 0.0) trip.emplace_back(pair_target_[k], pair_source_[k], pair_measure_[k] / den);
    }
    operator_.setFromTriplets(trip.begin(), trip.end());
    operator_.makeCompressed();
    return;
  }
  if (method_ != RemapMethod::discontinuous) return;
  // Cell averages of a discontinuous source: its rows taken to the target's file cells (each
  // the measure-weighted average of its simplices' rows), then divided by the covered fraction.
  if (tgt.cell_origin.empty()) {
    operator_ = p0_from_discontinuous_operator(supermesh_, normalization);
  } else {
    const auto& measures = Dm::measures(tgt);
    const std::vector<double> file_measure = file_cell_measures(tgt);
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(tgt.num_cells());
    for (std::size_t c = 0; c < tgt.num_cells(); ++c) {
      const std::size_t f = tgt.file_cell(c);
      if (file_measure[f] > 0.0) trip.emplace_back(static_cast<int>(f), static_cast<int>(c), measures[c] / file_measure[f]);
    }
    SparseMatrix average(static_cast<Eigen::Index>(tgt.num_file_cells()), static_cast<Eigen::Index>(tgt.num_cells()));
    average.setFromTriplets(trip.begin(), trip.end());
    operator_ = average * p0_from_discontinuous_operator(supermesh_);
    if (normalization == P0Normalization::covered_volume) divide_rows(operator_, coverage());
  }
  operator_.makeCompressed();
}

template <class Mesh>
std::size_t BasicRemap<Mesh>::rows() const {
  if (order_ == 1 && method_ == RemapMethod::discontinuous) return supermesh_.target->num_cells() * detail::Dim<Mesh>::nv;
  return order_ == 0 ? supermesh_.target->num_file_cells() : supermesh_.target->num_nodes();
}

template <class Mesh>
std::size_t BasicRemap<Mesh>::cols() const {
  if (order_ == 0 && method_ == RemapMethod::discontinuous) return supermesh_.source->num_cells() * detail::Dim<Mesh>::nv;
  return order_ == 0 ? supermesh_.source->num_file_cells() : supermesh_.source->num_nodes();
}

template <class Mesh>
std::vector<double> BasicRemap<Mesh>::apply_component(std::span<const double> column, P1RemapReport* report) const {
  switch (method_) {
    case RemapMethod::lumped:
    case RemapMethod::discontinuous: return apply_operator(operator_, column);
    case RemapMethod::standard:
      if (order_ == 0) return apply_operator(operator_, column);
      break;
    case RemapMethod::bounded: return remap_p1_bounded(supermesh_, column, report);
    case RemapMethod::linear_reconstruction: {
      const Mesh& src = *supermesh_.source;
      const Mesh& tgt = *supermesh_.target;
      const std::vector<double> u = spread_to_simplices(src, std::vector<double>(column.begin(), column.end()));
      std::vector<double> v =
          file_cell_average(tgt, remap_p0_linear(supermesh_, u, P0Normalization::cell_volume, src.cell_origin));
      if (normalization_ == P0Normalization::covered_volume) {
        const std::vector<double> covered = coverage();
        for (std::size_t i = 0; i < v.size(); ++i) v[i] = covered[i] > 0.0 ? v[i] / covered[i] : 0.0;
      }
      return v;
    }
  }
  throw std::logic_error("tetia: Remap: apply_component is not for the Galerkin P1");
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
  if (method_ != RemapMethod::standard || order_ == 0) {
    std::vector<double> column(n_in);
    for (std::size_t c = 0; c < nc; ++c) {
      for (std::size_t i = 0; i < n_in; ++i) column[i] = field[i * nc + c];
      const std::vector<double> u = apply_component(column, report);
      for (std::size_t i = 0; i < n_out; ++i) out[i * nc + c] = u[i];
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
  if (method_ == RemapMethod::lumped || method_ == RemapMethod::discontinuous) return operator_;
  if (method_ == RemapMethod::bounded || method_ == RemapMethod::linear_reconstruction)
    throw std::logic_error("tetia: Remap: the bounded P1 and the linear reconstruction have no matrix (their "
                           "limiters depend on the field); use apply()");
  if (order_ == 1)
    throw std::logic_error(
        "tetia: Remap: order 1 has no sparse operator (M_t^-1 M_ts is dense); use mixed_mass() (M_ts) and "
        "target_mass() (M_t), or apply()");
  return operator_;
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

template <class Mesh>
std::vector<double> BasicRemap<Mesh>::node_coverage() const {
  if (order_ != 1 || method_ == RemapMethod::discontinuous)
    throw std::logic_error("tetia: Remap: node_coverage is for order 1 with a continuous result (nodes)");
  return p1_node_coverage(supermesh_);
}

template class BasicRemap<TetMesh>;
template class BasicRemap<TriMesh>;

}  // namespace tetia
