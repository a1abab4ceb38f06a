// src/supermesh/file_cell_pairs.cpp -- file_cell_pairs (tetia/supermesh.hpp): the supermesh's
// pieces summed per pair of file cells.
//
// The pieces come sorted by (target cell, source cell), and a mesh's split file cells own
// consecutive cells in increasing order (src/io/msh_mesh.cpp), so the pieces of one target file
// cell are consecutive: each such run is sorted by source file cell (stably, so the sums run in
// the pieces' order and the result is the same for any number of threads) and merged.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "../compensated_sum.hpp"
#include "tetia/supermesh.hpp"

namespace tetia {
namespace {

double& measure_of(SupermeshPiece& p) { return p.volume; }
double& measure_of(SupermeshPiece2& p) { return p.area; }
double measure_of(const SupermeshPiece& p) { return p.volume; }
double measure_of(const SupermeshPiece2& p) { return p.area; }
double& coordinate(Vec3& p, int a) { return p[a]; }
double& coordinate(Vec2& p, int a) { return a == 0 ? p.x : p.y; }
double coordinate(const Vec3& p, int a) { return p[a]; }
double coordinate(const Vec2& p, int a) { return a == 0 ? p.x : p.y; }

template <class Pairs, class Result>
Pairs pairs_of(const Result& s) {
  using Piece = typename decltype(s.pieces)::value_type;
  using Point = decltype(Piece::first);
  constexpr int d = std::is_same_v<Point, Vec3> ? 3 : 2;
  Pairs out;
  const auto& pieces = s.pieces;
  if (s.source->cell_origin.empty() && s.target->cell_origin.empty()) {  // nothing split: the pieces
    out.pairs = pieces;
    out.piece_pair.resize(pieces.size());
    std::iota(out.piece_pair.begin(), out.piece_pair.end(), std::int32_t{0});
    return out;
  }
  out.piece_pair.assign(pieces.size(), -1);
  std::vector<std::size_t> run;
  for (std::size_t begin = 0; begin < pieces.size();) {
    const std::size_t target = s.target->file_cell(static_cast<std::size_t>(pieces[begin].target));
    std::size_t end = begin + 1;
    while (end < pieces.size() && s.target->file_cell(static_cast<std::size_t>(pieces[end].target)) == target) ++end;
    if (end < pieces.size() && s.target->file_cell(static_cast<std::size_t>(pieces[end].target)) < target)
      throw std::logic_error("tetia: file_cell_pairs: the target's file cells are not in cell order");
    run.resize(end - begin);
    std::iota(run.begin(), run.end(), begin);
    const auto source_of = [&](std::size_t k) { return s.source->file_cell(static_cast<std::size_t>(pieces[k].source)); };
    std::stable_sort(run.begin(), run.end(), [&](std::size_t a, std::size_t b) { return source_of(a) < source_of(b); });
    for (std::size_t i = 0; i < run.size();) {
      const std::size_t source = source_of(run[i]);
      detail::CompensatedSum m, first[d];
      std::size_t j = i;
      for (; j < run.size() && source_of(run[j]) == source; ++j) {
        const Piece& p = pieces[run[j]];
        m.add(measure_of(p));
        for (int a = 0; a < d; ++a) first[a].add(coordinate(p.first, a));
        out.piece_pair[run[j]] = static_cast<std::int32_t>(out.pairs.size());
      }
      Piece sum;
      sum.source = static_cast<std::int32_t>(source);
      sum.target = static_cast<std::int32_t>(target);
      measure_of(sum) = m.value();
      for (int a = 0; a < d; ++a) coordinate(sum.first, a) = first[a].value();
      out.pairs.push_back(sum);
      i = j;
    }
    begin = end;
  }
  return out;
}

}  // namespace

FileCellPairs file_cell_pairs(const Supermesh& s) { return pairs_of<FileCellPairs>(s); }
FileCellPairs2 file_cell_pairs(const Supermesh2& s) { return pairs_of<FileCellPairs2>(s); }

}  // namespace tetia
