// tests/support/remap_checks.hpp -- the remap checks test_remap.cpp (tetrahedra) and
// test_remap2d.cpp (triangles) share, as templates over the mesh: a P0 constant reproduced and
// a general field's integral conserved on meshes of one domain; the counts of fully, partly and
// not covered target cells of a partial overlap and both P0 normalizations there; a P1 linear
// field reproduced, a smooth field's integral conserved and the identity on identical meshes.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <random>
#include <vector>

#include "tetia/remap.hpp"

namespace tetia::testsupport {

inline const std::vector<double>& cell_measures(const TetMesh& m) { return m.volumes; }
inline const std::vector<double>& cell_measures(const TriMesh& m) { return m.areas; }

template <class Mesh, class F>
std::vector<double> at_nodes(const Mesh& m, const F& f) {
  std::vector<double> v(m.num_nodes());
  for (std::size_t i = 0; i < m.num_nodes(); ++i) v[i] = f(m.nodes[i]);
  return v;
}

/// Source and target mesh one domain: the constant 2.5 comes back on every cell (to 1e-13
/// relative) with both normalizations; a random field's integral is conserved to 1e-13 and its
/// averages stay within the source values' range.
template <class Result, class Mesh>
void expect_p0_constant_and_conservation(const Result& s, const Mesh& src, const Mesh& tgt) {
  const std::vector<double> c(src.num_cells(), 2.5);
  for (const auto norm : {P0Normalization::cell_volume, P0Normalization::covered_volume}) {
    const auto out = remap_p0(s, c, norm);
    ASSERT_EQ(out.size(), tgt.num_cells());
    for (const double v : out) EXPECT_NEAR(v, 2.5, 2.5 * 1e-13);
  }
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-1.0, 3.0);
  std::vector<double> in(src.num_cells());
  for (double& v : in) v = u(g);
  const auto out = remap_p0(s, in);
  const double si = integral_p0(src, in), ti = integral_p0(tgt, out);
  EXPECT_NEAR(ti, si, 1e-13 * std::abs(si));
  std::printf("  P0 random field: integral %.17g -> %.17g (relative %.3g)\n", si, ti, std::abs(ti - si) / std::abs(si));
  // Values are averages of source values: within their range.
  for (const double v : out) {
    EXPECT_GE(v, -1.0 - 1e-13);
    EXPECT_LE(v, 3.0 + 1e-13);
  }
}

/// A source covering part of the target (`cov`: covered measure per target cell, adding up to
/// `overlap`): some target cells are covered fully, some partly, some not at all. With
/// cell_volume a constant scales by the covered fraction and the integral is conserved; with
/// covered_volume the constant comes back on every touched cell and sum(u_t covered_t) is
/// conserved.
template <class Result, class Mesh>
void expect_partial_coverage(const Result& s, const Mesh& src, const Mesh& tgt, const std::vector<double>& cov,
                             double overlap) {
  const std::vector<double>& mt = cell_measures(tgt);
  double total = 0.0;
  for (const double v : cov) total += v;
  EXPECT_NEAR(total, overlap, 1e-15);
  std::size_t full = 0, partial = 0, none = 0;
  for (std::size_t t = 0; t < tgt.num_cells(); ++t) {
    if (cov[t] == 0.0) ++none;
    else if (std::abs(cov[t] - mt[t]) <= 1e-13 * mt[t]) ++full;
    else ++partial;
  }
  EXPECT_GT(full, 0u);
  EXPECT_GT(partial, 0u);
  EXPECT_GT(none, 0u);
  const std::vector<double> c(src.num_cells(), -1.5);
  const auto a = remap_p0(s, c);
  for (std::size_t t = 0; t < tgt.num_cells(); ++t) EXPECT_NEAR(a[t], -1.5 * cov[t] / mt[t], 1e-13);
  EXPECT_NEAR(integral_p0(tgt, a), integral_p0(src, c), 1e-14);
  const auto b = remap_p0(s, c, P0Normalization::covered_volume);
  double conserved = 0.0;
  for (std::size_t t = 0; t < tgt.num_cells(); ++t) {
    EXPECT_NEAR(b[t], cov[t] > 0.0 ? -1.5 : 0.0, 1e-13);
    conserved += b[t] * cov[t];
  }
  EXPECT_NEAR(conserved, integral_p0(src, c), 1e-14);
}

/// P1 on meshes of one domain (`s` from src to tgt, `same` from src to src, both built with
/// the mixed mass kept): the linear field comes back to 1e-10 at every node, the smooth field's
/// integral is conserved to 1e-12, and identical meshes give the identity to 1e-12.
template <class Result, class Mesh, class Linear, class Smooth>
void expect_p1_linear_conservation_identity(const Result& s, const Result& same, const Mesh& src, const Mesh& tgt,
                                            const Linear& linear, const Smooth& smooth) {
  P1RemapReport report;
  const auto out = remap_p1(s, at_nodes(src, linear), &report);
  ASSERT_EQ(out.size(), tgt.num_nodes());
  double worst = 0.0;
  for (std::size_t i = 0; i < tgt.num_nodes(); ++i) worst = std::max(worst, std::abs(out[i] - linear(tgt.nodes[i])));
  EXPECT_LT(worst, 1e-10);
  std::printf("  linear field: max nodal error %.3g, CG %d iterations, residual %.3g\n", worst, report.iterations,
              report.residual);
  // The integral of a smooth (non-linear) field.
  const auto in = at_nodes(src, smooth);
  const auto sm = remap_p1(s, in, &report);
  const double si = integral_p1(src, in), ti = integral_p1(tgt, sm);
  EXPECT_NEAR(ti, si, 1e-12 * std::abs(si));
  std::printf("  smooth field: integral %.17g -> %.17g (relative %.3g)\n", si, ti, std::abs(ti - si) / std::abs(si));
  // Identical meshes: the projection is the identity.
  const auto id = remap_p1(same, in);
  for (std::size_t i = 0; i < src.num_nodes(); ++i) EXPECT_NEAR(id[i], in[i], 1e-12);
}

}  // namespace tetia::testsupport
