// tetia/file_cells.hpp -- results per cell of the user's file, for meshes whose hexahedra,
// prisms and pyramids (quadrilaterals in 2D) were split into simplices (TetMesh::cell_origin).
//
// Contract. A file cell is a cell of the file the mesh came from: a split cell's simplices
// together, or a simplex that was not split (every cell, for a mesh without split cells).
// - file_cell_measures: each file cell's volume (area), the compensated sum of its simplices'.
// - file_cell_average: per file cell, the average of per-simplex values (`components` values
//   per simplex, in a row) weighted by `weights` (one per simplex; empty: the simplex volumes),
//   with compensated sums; a value the same on all of a file cell's simplices is returned
//   exactly, and a file cell whose weights sum to 0 gets the plain mean. For values
//   that are averages over the simplices (P0 fields) and volume weights this is the average
//   over the file cell.
// - spread_to_simplices: the other way, each simplex taking its file cell's values.
// Without split cells, file_cell_average and spread_to_simplices return their input and
// file_cell_measures the cell measures. Sizes that do not match throw std::invalid_argument.
#pragma once

#include <vector>

#include "tetia/mesh.hpp"

namespace tetia {

std::vector<double> file_cell_measures(const TetMesh& mesh);
std::vector<double> file_cell_measures(const TriMesh& mesh);

std::vector<double> file_cell_average(const TetMesh& mesh, const std::vector<double>& simplex_values,
                                      int components = 1, const std::vector<double>& weights = {});
std::vector<double> file_cell_average(const TriMesh& mesh, const std::vector<double>& simplex_values,
                                      int components = 1, const std::vector<double>& weights = {});

std::vector<double> spread_to_simplices(const TetMesh& mesh, const std::vector<double>& file_cell_values,
                                        int components = 1);
std::vector<double> spread_to_simplices(const TriMesh& mesh, const std::vector<double>& file_cell_values,
                                        int components = 1);

}  // namespace tetia
