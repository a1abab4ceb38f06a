// Second-order conservative remap of cell averages (tetia/remap_methods.hpp, remap_p0_linear):
// a limited least-squares gradient per source cell (or group of cells), integrated exactly on
// each piece with its first moments.
//
// The gradient of cell S minimizes sum_n w_n (g . d_n - (u_n - u_S))^2 over its face neighbours
// n, d_n = c_n - c_S the centroid difference and w_n = 1 / |d_n|^2 (each neighbour's equation
// scaled to a directional derivative, so that near and far neighbours weigh alike). Where the
// face neighbours do not span the space (a corner cell with one neighbour, say), the cells that
// share a vertex with S take their place. Barth-Jespersen's limiter then scales g by the largest
// phi in [0, 1] that keeps u_S + phi g . (x_v - c_S) within [min, max] of the averages of S and
// its vertex neighbours (the cells that share a vertex with S) at every vertex x_v of S; since the reconstruction is linear on S, it is then
// within those bounds everywhere on S, and so is every piece's average of it.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "../supermesh/dimension.hpp"
#include "assembly.hpp"
#include "tetia/remap_methods.hpp"

namespace tetia {

namespace {

using namespace detail::remap;

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

template <class Mesh>
Vec<detail::Dim<Mesh>::d> to_vec(const typename detail::Dim<Mesh>::Point& p) {
  using Dm = detail::Dim<Mesh>;
  Vec<Dm::d> v;
  for (int k = 0; k < Dm::d; ++k) v[k] = Dm::coord(p, k);
  return v;
}

// Compressed lists: members of each group, neighbours of each group.
struct Lists {
  std::vector<std::size_t> start;
  std::vector<std::int32_t> items;
  std::span<const std::int32_t> of(std::size_t i) const {
    return {items.data() + start[i], items.data() + start[i + 1]};
  }
};

Lists compress(std::vector<std::pair<std::int32_t, std::int32_t>>& pairs, std::size_t n) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Lists l;
  l.start.assign(n + 1, 0);
  for (const auto& [a, b] : pairs) ++l.start[idx(a) + 1];
  for (std::size_t i = 0; i < n; ++i) l.start[i + 1] += l.start[i];
  l.items.reserve(pairs.size());
  for (const auto& [a, b] : pairs) l.items.push_back(b);
  return l;
}

template <class Mesh>
std::vector<double> linear(const typename detail::Dim<Mesh>::Result& s, std::span<const double> values,
                           P0Normalization normalization, std::span<const std::int32_t> groups) {
  using Dm = detail::Dim<Mesh>;
  constexpr int D = Dm::d;
  const char* who = "remap_p0_linear";
  check_meshes(s, who);
  const Mesh& src = *s.source;
  const Mesh& tgt = *s.target;
  const std::size_t nc = src.num_cells();
  check_size(values.size(), nc, who, "source cell");
  if (!groups.empty()) check_size(groups.size(), nc, who, "group");
  std::size_t ng = groups.empty() ? nc : 0;
  for (const auto g : groups) {
    if (g < 0) throw std::invalid_argument("tetia: remap_p0_linear: a group index is negative");
    ng = std::max(ng, idx(g) + 1);
  }
  auto group_of = [&](std::size_t c) { return groups.empty() ? c : idx(groups[c]); };

  // Each group's measure, centroid and average.
  const auto& measures = Dm::measures(src);
  std::vector<double> vol(ng, 0.0), avg(ng, 0.0);
  std::vector<Vec<D>> centroid(ng, Vec<D>::Zero());
  std::vector<std::pair<std::int32_t, std::int32_t>> member_pairs;
  member_pairs.reserve(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::size_t g = group_of(c);
    member_pairs.emplace_back(static_cast<std::int32_t>(g), static_cast<std::int32_t>(c));
    const auto T = src.cell(c);
    Vec<D> mid = Vec<D>::Zero();
    for (int k = 0; k < Dm::nv; ++k) mid += to_vec<Mesh>(T[k]);
    mid *= 1.0 / Dm::nv;
    vol[g] += measures[c];
    avg[g] += measures[c] * values[c];
    centroid[g] += measures[c] * mid;
  }
  const Lists members = compress(member_pairs, ng);
  for (std::size_t g = 0; g < ng; ++g) {
    if (vol[g] > 0.0) {
      avg[g] /= vol[g];
      centroid[g] /= vol[g];
    } else if (!members.of(g).empty()) {  // flat cells only: no pieces come from them
      avg[g] = values[idx(members.of(g)[0])];
      centroid[g] = to_vec<Mesh>(src.cell(idx(members.of(g)[0]))[0]);
    }
  }

  // Face neighbours of each group (the gradient's stencil) and vertex neighbours (the
  // limiter's bounds, and the gradient's stencil where the face neighbours do not span).
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (std::size_t c = 0; c < nc; ++c)
    for (const auto n : src.neighbors[c])
      if (n >= 0 && group_of(idx(n)) != group_of(c))
        pairs.emplace_back(static_cast<std::int32_t>(group_of(c)), static_cast<std::int32_t>(group_of(idx(n))));
  const Lists faces = compress(pairs, ng);
  pairs.clear();
  {
    std::vector<std::pair<std::int32_t, std::int32_t>> node_groups;
    node_groups.reserve(nc * Dm::nv);
    for (std::size_t c = 0; c < nc; ++c)
      for (const auto v : src.cells[c]) node_groups.emplace_back(v, static_cast<std::int32_t>(group_of(c)));
    const Lists around = compress(node_groups, src.num_nodes());
    for (std::size_t c = 0; c < nc; ++c)
      for (const auto v : src.cells[c])
        for (const auto g : around.of(idx(v)))
          if (idx(g) != group_of(c)) pairs.emplace_back(static_cast<std::int32_t>(group_of(c)), g);
  }
  const Lists vertices = compress(pairs, ng);
  pairs = {};

  // The gradient by least squares over a stencil; false where it does not span the space.
  auto least_squares = [&](std::size_t g, std::span<const std::int32_t> stencil, Vec<D>& grad) {
    Eigen::Matrix<double, D, D> N = Eigen::Matrix<double, D, D>::Zero();
    Vec<D> rhs = Vec<D>::Zero();
    for (const auto n : stencil) {
      const Vec<D> d = centroid[idx(n)] - centroid[g];
      // The direction and distance from d scaled to its largest coordinate: d's squared norm
      // would overflow or underflow at extreme scales.
      const double scale = d.cwiseAbs().maxCoeff();
      if (!(scale > 0.0) || !std::isfinite(scale)) continue;
      const Vec<D> e = (d / scale).normalized();
      const double dist = scale * (d / scale).norm();
      N += e * e.transpose();
      rhs += e * ((avg[idx(n)] - avg[g]) / dist);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eig(N, Eigen::EigenvaluesOnly);
    const auto lambda = eig.eigenvalues();
    if (!(lambda[0] > 1e-10 * lambda[D - 1])) return false;
    grad = N.ldlt().solve(rhs);
    return grad.allFinite();
  };

  std::vector<Vec<D>> gradient(ng, Vec<D>::Zero());
  for (std::size_t g = 0; g < ng; ++g) {
    if (!(vol[g] > 0.0)) continue;
    Vec<D> grad;
    if (!least_squares(g, faces.of(g), grad) && !least_squares(g, vertices.of(g), grad)) continue;
    // Barth-Jespersen, bounded by the averages of the cell and its vertex neighbours (the
    // cells around each of its vertices: an interior vertex lies within their centroids, so
    // that a linear field is not clipped there).
    double lo = avg[g], hi = avg[g];
    for (const auto n : vertices.of(g)) {
      lo = std::min(lo, avg[idx(n)]);
      hi = std::max(hi, avg[idx(n)]);
    }
    double phi = 1.0;
    for (const auto c : members.of(g)) {
      const auto T = src.cell(idx(c));
      for (int k = 0; k < Dm::nv; ++k) {
        const double delta = grad.dot(to_vec<Mesh>(T[k]) - centroid[g]);
        if (delta > 0.0) phi = std::min(phi, (hi - avg[g]) / delta);
        else if (delta < 0.0) phi = std::min(phi, (lo - avg[g]) / delta);
      }
    }
    phi = std::max(phi, 0.0);
    const Vec<D> limited = phi * grad;
    if (limited.allFinite()) gradient[g] = limited;
  }

  // Each piece's integral of its source group's reconstruction, summed per target cell in the
  // pieces' order.
  std::vector<double> num(tgt.num_cells(), 0.0), cov(tgt.num_cells(), 0.0);
  for (const auto& pc : s.pieces) {
    const std::size_t g = group_of(idx(pc.source));
    const double m = Dm::measure(pc);
    const Vec<D> first = to_vec<Mesh>(pc.first);
    const double integral = avg[g] * m + gradient[g].dot(first - m * centroid[g]);
    num[idx(pc.target)] += integral;
    cov[idx(pc.target)] += m;
  }
  divide_by_p0_denominator(tgt, num, cov, normalization);
  return num;
}

}  // namespace

std::vector<double> remap_p0_linear(const Supermesh& s, std::span<const double> values, P0Normalization n,
                                    std::span<const std::int32_t> groups) {
  return linear<TetMesh>(s, values, n, groups);
}
std::vector<double> remap_p0_linear(const Supermesh2& s, std::span<const double> values, P0Normalization n,
                                    std::span<const std::int32_t> groups) {
  return linear<TriMesh>(s, values, n, groups);
}

}  // namespace tetia
