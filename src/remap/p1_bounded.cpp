// Lumped and bounded P1 remap (tetia/remap_methods.hpp): the lumped-mass projection, the local
// bounds of the source field around each target node, and the Galerkin solution limited by
// clip-and-assured-sum (CAAS: Bradley, Bosler and Guba, "Islet: interpolation semi-Lagrangian
// element-based transport", 2019, and its predecessors in the QLT papers; the method is
// described there, written here from that description).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "../compensated_sum.hpp"
#include "../supermesh/dimension.hpp"
#include "assembly.hpp"
#include "tetia/remap_methods.hpp"

namespace tetia {

namespace {

using namespace detail::remap;

// A node's support counts as fully covered when the source covers all but this fraction of its
// basis function's integral: above the rounding of the covered part (each piece to 1e-12 of the
// smaller cell, summed over a few cells), far below any overlap a mesh means. A node misjudged
// either way costs at most that fraction of its mass: its bounds lack 0 (the limiter may then
// lack that much room, which is then not conserved) or gain it.
constexpr double kCoveredFraction = 1.0 - 1e-12;

// What the three methods share: the loads b = M_ts u_s, the lumped mass m, the covered part of
// each basis function's integral (the row sums of M_ts), and the local bounds.
struct NodeSums {
  Eigen::VectorXd load;
  std::vector<double> mass, covered, lower, upper;
};

template <class Mesh>
NodeSums node_sums(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u, const char* who) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  const MassSource from = check_mass_source<Mesh>(s, who);
  check_size(u.size(), s.source->num_nodes(), who, "source node");
  const Mesh& tgt = *s.target;
  const Mesh& src = *s.source;
  NodeSums r;
  // The loads as mixed_mass_times forms them (the same products and sums in the same order, so
  // the same bits as remap_p1's), in the one pass over the pieces that also sums the rest.
  r.load = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tgt.num_nodes()));
  r.mass = lumped_mass(tgt);
  const std::size_t n = tgt.num_nodes();
  r.covered.assign(n, 0.0);
  r.lower.assign(n, std::numeric_limits<double>::infinity());
  r.upper.assign(n, -std::numeric_limits<double>::infinity());
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    const auto& sn = src.cells[idx(pc.source)];
    double lo = u[idx(sn[0])], hi = lo;
    for (std::size_t j = 1; j < nv; ++j) {
      lo = std::min(lo, u[idx(sn[j])]);
      hi = std::max(hi, u[idx(sn[j])]);
    }
    double us[nv];
    for (std::size_t j = 0; j < nv; ++j) us[j] = u[idx(sn[j])];
    const auto& tn = tgt.cells[idx(pc.target)];
    for (std::size_t i = 0; i < nv; ++i) {
      double row = 0.0, acc = 0.0;
      for (std::size_t j = 0; j < nv; ++j) {
        row += A[i * nv + j];
        acc += A[i * nv + j] * us[j];
      }
      const std::size_t node = idx(tn[i]);
      r.load[tn[i]] += acc;
      r.covered[node] += row;
      r.lower[node] = std::min(r.lower[node], lo);
      r.upper[node] = std::max(r.upper[node], hi);
    }
  });
  for (std::size_t i = 0; i < n; ++i) {
    if (!(r.lower[i] <= r.upper[i])) {  // nothing covers this node's support
      r.lower[i] = r.upper[i] = 0.0;
    } else if (!(r.covered[i] >= kCoveredFraction * r.mass[i])) {  // partly: the field is 0 outside
      r.lower[i] = std::min(r.lower[i], 0.0);
      r.upper[i] = std::max(r.upper[i], 0.0);
    }
  }
  return r;
}

// The lumped values b_i / m_i, each an average of the source values over its support, so
// within its local bounds but for the rounding of the quotient (a 1 that comes out as
// 1 + 2^-52 where the support is covered): clamped to them, which moves a value by that
// rounding only, so that the bounds hold exactly.
std::vector<double> lumped_values(const NodeSums& r) {
  std::vector<double> out(r.mass.size(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (r.mass[i] > 0.0) out[i] = std::clamp(r.load[static_cast<Eigen::Index>(i)] / r.mass[i], r.lower[i], r.upper[i]);
  return out;
}

template <class Mesh>
std::vector<double> lumped(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u) {
  return lumped_values(node_sums<Mesh>(s, u, "remap_p1_lumped"));
}

template <class Mesh>
P1Bounds bounds(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u) {
  NodeSums r = node_sums<Mesh>(s, u, "p1_local_bounds");
  return {std::move(r.lower), std::move(r.upper)};
}

template <class Mesh>
std::vector<double> bounded(const typename detail::Dim<Mesh>::Result& s, std::span<const double> u,
                            P1RemapReport* report) {
  const NodeSums r = node_sums<Mesh>(s, u, "remap_p1_bounded");
  const std::vector<double> high = solve_target_mass(consistent_mass(*s.target, true), r.load, report);
  const std::size_t n = high.size();
  // The Galerkin values clipped to the local bounds; the target mass Q is the loads' sum (the
  // source integral over the overlap), which the lumped solution carries to rounding, so the
  // correction below has the room it needs but for rounding.
  const std::vector<double>& lo = r.lower;
  const std::vector<double>& hi = r.upper;
  std::vector<double> y(n);
  detail::CompensatedSum target_mass, clipped_mass;
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = r.mass[i] > 0.0 ? std::clamp(high[i], lo[i], hi[i]) : 0.0;
    target_mass.add(r.load[static_cast<Eigen::Index>(i)]);
    clipped_mass.add(r.mass[i] * y[i]);
  }
  // CAAS: the mass the clipping moved goes back to the nodes with room on the side that takes
  // it, in proportion to m_i times that room; y_i then moves at most to its bound.
  const double excess = target_mass.value() - clipped_mass.value();
  if (excess != 0.0) {
    detail::CompensatedSum room;
    for (std::size_t i = 0; i < n; ++i) room.add(r.mass[i] * (excess > 0.0 ? hi[i] - y[i] : y[i] - lo[i]));
    const double total_room = room.value();
    if (total_room > 0.0) {
      const double share = std::min(1.0, std::abs(excess) / total_room);  // above 1 only by rounding
      for (std::size_t i = 0; i < n; ++i) {
        if (!(r.mass[i] > 0.0)) continue;
        y[i] = excess > 0.0 ? std::min(hi[i], y[i] + share * (hi[i] - y[i]))
                            : std::max(lo[i], y[i] - share * (y[i] - lo[i]));
      }
    }
  }
  return y;
}

// Coverage fractions from the covered part of each basis function's integral.
template <class Mesh>
std::vector<double> coverage_of_nodes(const Mesh& target, std::span<const double> covered) {
  check_size(covered.size(), target.num_nodes(), "p1_node_coverage", "target node");
  std::vector<double> out = lumped_mass(target);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = out[i] > 0.0 ? covered[i] / out[i] : 0.0;
  return out;
}

// The row sums of M_ts as node_sums forms them (each piece's row summed in column order, the
// rows added in piece order): the same bits as the loads of a field of ones.
template <class Mesh>
std::vector<double> node_coverage(const typename detail::Dim<Mesh>::Result& s) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  const MassSource from = check_mass_source<Mesh>(s, "p1_node_coverage");
  const Mesh& tgt = *s.target;
  std::vector<double> covered(tgt.num_nodes(), 0.0);
  for_each_piece_mass<Mesh>(s, from, [&](const auto& pc, const auto& A) {
    const auto& tn = tgt.cells[idx(pc.target)];
    for (std::size_t i = 0; i < nv; ++i) {
      double row = 0.0;
      for (std::size_t j = 0; j < nv; ++j) row += A[i * nv + j];
      covered[idx(tn[i])] += row;
    }
  });
  return coverage_of_nodes(tgt, covered);
}

// Coverage fractions from the covered measure of each target cell.
template <class Mesh>
std::vector<double> coverage_of_cells(const Mesh& target, std::span<const double> covered) {
  check_size(covered.size(), target.num_cells(), "cell_coverage", "target cell");
  const auto& measures = detail::Dim<Mesh>::measures(target);
  std::vector<double> out(covered.begin(), covered.end());
  for (std::size_t c = 0; c < out.size(); ++c) out[c] = measures[c] > 0.0 ? out[c] / measures[c] : 0.0;
  return out;
}

template <class Mesh>
std::vector<double> cell_coverage(const typename detail::Dim<Mesh>::Result& s) {
  check_meshes(s, "cell_coverage");
  return coverage_of_cells(*s.target, covered_measures<Mesh>(s));
}

}  // namespace

std::vector<double> p1_node_coverage(const Supermesh& s) { return node_coverage<TetMesh>(s); }
std::vector<double> p1_node_coverage(const Supermesh2& s) { return node_coverage<TriMesh>(s); }
std::vector<double> p1_node_coverage(const TetMesh& t, std::span<const double> c) { return coverage_of_nodes(t, c); }
std::vector<double> p1_node_coverage(const TriMesh& t, std::span<const double> c) { return coverage_of_nodes(t, c); }
std::vector<double> cell_coverage(const Supermesh& s) { return cell_coverage<TetMesh>(s); }
std::vector<double> cell_coverage(const Supermesh2& s) { return cell_coverage<TriMesh>(s); }
std::vector<double> cell_coverage(const TetMesh& t, std::span<const double> c) { return coverage_of_cells(t, c); }
std::vector<double> cell_coverage(const TriMesh& t, std::span<const double> c) { return coverage_of_cells(t, c); }
std::vector<double> lumped_mass(const TetMesh& m) { return detail::remap::lumped_mass(m); }
std::vector<double> lumped_mass(const TriMesh& m) { return detail::remap::lumped_mass(m); }

std::vector<double> remap_p1_lumped(const Supermesh& s, std::span<const double> u) { return lumped<TetMesh>(s, u); }
std::vector<double> remap_p1_lumped(const Supermesh2& s, std::span<const double> u) { return lumped<TriMesh>(s, u); }
P1Bounds p1_local_bounds(const Supermesh& s, std::span<const double> u) { return bounds<TetMesh>(s, u); }
P1Bounds p1_local_bounds(const Supermesh2& s, std::span<const double> u) { return bounds<TriMesh>(s, u); }
std::vector<double> remap_p1_bounded(const Supermesh& s, std::span<const double> u, P1RemapReport* report) {
  return bounded<TetMesh>(s, u, report);
}
std::vector<double> remap_p1_bounded(const Supermesh2& s, std::span<const double> u, P1RemapReport* report) {
  return bounded<TriMesh>(s, u, report);
}

}  // namespace tetia
