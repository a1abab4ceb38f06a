// src/remap/p1_loads.cpp -- P1 remap without keeping the supermesh (tetia/remap.hpp): the
// loads M_ts u_s summed by a PieceConsumer, the solve, and remap_p1 from two meshes.
//
// Bit for bit the kept path (src/remap/assembly.hpp, mixed_mass_times): the local mixed mass
// matrix comes from the same function on the same polyhedron (src/supermesh/mixed_mass.hpp), each
// target row of it is applied to the source values in the same order, and those sums are added
// to the loads in the same (target, source) order of the pieces.
#include <cstddef>
#include <stdexcept>
#include <string>

#include "../supermesh/dimension.hpp"
#include "../supermesh/mixed_mass.hpp"
#include "assembly.hpp"
#include "tetia/remap.hpp"

namespace tetia {

template <class Mesh, class Piece, class Shape>
BasicP1Loads<Mesh, Piece, Shape>::BasicP1Loads(const Mesh& source, const Mesh& target,
                                               std::vector<std::span<const double>> fields)
    : source_(source), target_(target), fields_(std::move(fields)) {
  for (const auto& f : fields_) detail::remap::check_size(f.size(), source.num_nodes(), "P1Loads", "source node");
  loads_.assign(fields_.size(), Eigen::VectorXd::Zero(static_cast<Eigen::Index>(target.num_nodes())));
}

template <class Mesh, class Piece, class Shape>
std::size_t BasicP1Loads<Mesh, Piece, Shape>::values_per_piece() const {
  return fields_.size() * detail::Dim<Mesh>::nv;
}

// Per field, row i of the piece's local matrix times the source values at its source cell's
// nodes (the sum mixed_mass_times forms for that row).
template <class Mesh, class Piece, class Shape>
void BasicP1Loads<Mesh, Piece, Shape>::compute(const Piece& piece, const Shape& shape, double* values) const {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  const auto s = static_cast<std::size_t>(piece.source);
  typename detail::Dim<Mesh>::LocalMass A;
  detail::piece_mixed_mass<Mesh>(source_.cell(s), shape, A);
  const auto& sn = source_.cells[s];
  for (std::size_t f = 0; f < fields_.size(); ++f) {
    double us[nv];
    for (std::size_t j = 0; j < nv; ++j) us[j] = fields_[f][static_cast<std::size_t>(sn[j])];
    for (std::size_t i = 0; i < nv; ++i) {
      double acc = 0.0;
      for (std::size_t j = 0; j < nv; ++j) acc += A[i * nv + j] * us[j];
      values[f * nv + i] = acc;
    }
  }
}

template <class Mesh, class Piece, class Shape>
void BasicP1Loads<Mesh, Piece, Shape>::consume(const Piece& piece, const double* values) {
  constexpr std::size_t nv = detail::Dim<Mesh>::nv;
  const auto& tn = target_.cells[static_cast<std::size_t>(piece.target)];
  for (std::size_t f = 0; f < fields_.size(); ++f)
    for (std::size_t i = 0; i < nv; ++i) loads_[f][tn[i]] += values[f * nv + i];
}

template class BasicP1Loads<TetMesh, SupermeshPiece, Polyhedron>;
template class BasicP1Loads<TriMesh, SupermeshPiece2, Polygon>;

namespace {

template <class Mesh>
std::vector<double> solve(const Mesh& target, const Eigen::VectorXd& load, P1RemapReport* report) {
  detail::remap::check_size(static_cast<std::size_t>(load.size()), target.num_nodes(), "solve_p1", "load");
  return detail::remap::solve_target_mass(detail::remap::consistent_mass(target, true), load, report);
}

template <class Loads, class Mesh>
std::vector<std::vector<double>> remap(const Mesh& source, const Mesh& target, std::span<const std::vector<double>> fields,
                                       const SupermeshOptions& options, std::vector<P1RemapReport>* reports) {
  Loads loads(source, target, std::vector<std::span<const double>>(fields.begin(), fields.end()));
  supermesh(source, target, loads, options);
  std::vector<std::vector<double>> out;
  if (reports) reports->assign(fields.size(), {});
  for (std::size_t f = 0; f < fields.size(); ++f)
    out.push_back(solve(target, loads.loads()[f], reports ? &(*reports)[f] : nullptr));
  return out;
}

}  // namespace

std::vector<double> solve_p1(const TetMesh& target, const Eigen::VectorXd& load, P1RemapReport* report) {
  return solve(target, load, report);
}
std::vector<double> solve_p1(const TriMesh& target, const Eigen::VectorXd& load, P1RemapReport* report) {
  return solve(target, load, report);
}

std::vector<std::vector<double>> remap_p1(const TetMesh& source, const TetMesh& target,
                                          std::span<const std::vector<double>> fields, const SupermeshOptions& options,
                                          std::vector<P1RemapReport>* reports) {
  return remap<P1Loads>(source, target, fields, options, reports);
}
std::vector<std::vector<double>> remap_p1(const TriMesh& source, const TriMesh& target,
                                          std::span<const std::vector<double>> fields, const SupermeshOptions& options,
                                          std::vector<P1RemapReport>* reports) {
  return remap<P1Loads2>(source, target, fields, options, reports);
}

}  // namespace tetia
