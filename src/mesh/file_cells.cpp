// src/mesh/file_cells.cpp -- results per file cell (tetia/file_cells.hpp), for both dimensions.
#include "tetia/file_cells.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "../compensated_sum.hpp"
#include "mesh_dim.hpp"

namespace tetia {
namespace {


void check_size(const char* what, std::size_t got, std::size_t expected) {
  if (got != expected)
    throw std::invalid_argument(std::string("tetia: ") + what + ": " + std::to_string(got) + " values, expected " +
                                std::to_string(expected));
}

template <class Mesh>
std::vector<double> measures_of(const Mesh& m) {
  if (m.cell_origin.empty()) return detail::MeshDim<Mesh>::measures(m);
  std::vector<detail::CompensatedSum> sums(m.num_file_cells());
  for (std::size_t c = 0; c < m.num_cells(); ++c) sums[m.file_cell(c)].add(detail::MeshDim<Mesh>::measures(m)[c]);
  std::vector<double> out(sums.size());
  for (std::size_t f = 0; f < sums.size(); ++f) out[f] = sums[f].value();
  return out;
}

template <class Mesh>
std::vector<double> average_of(const Mesh& m, const std::vector<double>& values, int components,
                               const std::vector<double>& weights) {
  if (components < 1) throw std::invalid_argument("tetia: file_cell_average: components must be at least 1");
  const auto nc = static_cast<std::size_t>(components);
  check_size("file_cell_average: simplex values", values.size(), m.num_cells() * nc);
  if (!weights.empty()) check_size("file_cell_average: weights", weights.size(), m.num_cells());
  if (m.cell_origin.empty()) return values;
  const std::vector<double>& w = weights.empty() ? detail::MeshDim<Mesh>::measures(m) : weights;
  const std::size_t n = m.num_file_cells();
  std::vector<detail::CompensatedSum> weighted(n * nc), plain(n * nc), total(n);
  std::vector<std::size_t> count(n, 0);
  // A value that is the same on all of a file cell's simplices is its average exactly (the
  // quotient of the sums could be off by an ulp).
  std::vector<double> first(n * nc, 0.0);
  std::vector<char> uniform(n * nc, 1);
  for (std::size_t c = 0; c < m.num_cells(); ++c) {
    const std::size_t f = m.file_cell(c);
    total[f].add(w[c]);
    for (std::size_t k = 0; k < nc; ++k) {
      const double x = values[c * nc + k];
      weighted[f * nc + k].add(w[c] * x);
      plain[f * nc + k].add(x);
      if (count[f] == 0) first[f * nc + k] = x;
      else if (!(x == first[f * nc + k])) uniform[f * nc + k] = 0;
    }
    ++count[f];
  }
  std::vector<double> out(n * nc, 0.0);
  for (std::size_t f = 0; f < n; ++f) {
    const double t = total[f].value();
    for (std::size_t k = 0; k < nc; ++k) {
      const std::size_t i = f * nc + k;
      out[i] = count[f] == 0 ? 0.0
               : uniform[i]  ? first[i]
               : t != 0.0    ? weighted[i].value() / t
                             : plain[i].value() / static_cast<double>(count[f]);
    }
  }
  return out;
}

template <class Mesh>
std::vector<double> spread_of(const Mesh& m, const std::vector<double>& values, int components) {
  if (components < 1) throw std::invalid_argument("tetia: spread_to_simplices: components must be at least 1");
  const auto nc = static_cast<std::size_t>(components);
  check_size("spread_to_simplices: file cell values", values.size(), m.num_file_cells() * nc);
  if (m.cell_origin.empty()) return values;
  std::vector<double> out(m.num_cells() * nc);
  for (std::size_t c = 0; c < m.num_cells(); ++c)
    std::copy_n(&values[m.file_cell(c) * nc], nc, &out[c * nc]);
  return out;
}

}  // namespace

std::vector<double> file_cell_measures(const TetMesh& mesh) { return measures_of(mesh); }
std::vector<double> file_cell_measures(const TriMesh& mesh) { return measures_of(mesh); }
std::vector<double> file_cell_average(const TetMesh& mesh, const std::vector<double>& simplex_values, int components,
                                      const std::vector<double>& weights) {
  return average_of(mesh, simplex_values, components, weights);
}
std::vector<double> file_cell_average(const TriMesh& mesh, const std::vector<double>& simplex_values, int components,
                                      const std::vector<double>& weights) {
  return average_of(mesh, simplex_values, components, weights);
}
std::vector<double> spread_to_simplices(const TetMesh& mesh, const std::vector<double>& file_cell_values,
                                        int components) {
  return spread_of(mesh, file_cell_values, components);
}
std::vector<double> spread_to_simplices(const TriMesh& mesh, const std::vector<double>& file_cell_values,
                                        int components) {
  return spread_of(mesh, file_cell_values, components);
}

}  // namespace tetia
