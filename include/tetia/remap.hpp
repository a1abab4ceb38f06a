// tetia/remap.hpp -- conservative transfer of fields between meshes on a supermesh.
//
// Contract: P0 (cell averages) is the L2 projection onto piecewise constants: target value =
// sum over pieces of (source value * piece volume) / target cell volume; it conserves the
// integral over the overlap and reproduces constants exactly where the target is covered.
// P1 (continuous, nodal) is the Galerkin L2 projection: M_t u_t = M_ts u_s with M_t the target
// mass matrix and M_ts the mixed mass matrix assembled exactly on the supermesh (products of
// linear functions integrated exactly on a tetrahedralization of each piece), solved by
// conjugate gradients. It needs the supermesh built with keep_polyhedra.
#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "tetia/supermesh.hpp"

namespace tetia {

std::vector<double> remap_p0(const Supermesh& s, std::span<const double> source_cell_values);

struct P1RemapReport {
  int iterations = 0;
  double residual = 0.0;
};

std::vector<double> remap_p1(const Supermesh& s, std::span<const double> source_node_values,
                             P1RemapReport* report = nullptr);

/// The mixed mass (coupling) matrix M_ts (rows: target nodes, columns: source nodes) in Matrix
/// Market coordinate format.
void write_mixed_mass_matrix(const Supermesh& s, const std::filesystem::path& file);

}  // namespace tetia
