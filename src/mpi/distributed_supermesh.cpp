// The supermesh and P0 remap of two distributed tetrahedral meshes (tetia/mpi.hpp).
//
// The exchange. Rank r holds target cells T_r and source cells S_r (any partitions).
//  1. r sorts T_r along a Morton curve through the cell centroids, cuts it into at most
//     B = boxes_per_rank runs of consecutive cells and publishes one axis-aligned box per run
//     (the union of its cells' boxes): MPI_Allgather of the counts, MPI_Allgatherv of the
//     boxes, 48 bytes each, P * B in all on every rank.
//  2. For each of its source cells s, r finds (R-tree over all the boxes) the ranks q one of
//     whose boxes meets s's box, closed boxes, touching included, and sends s to each such q
//     once: its id (8 bytes), its four vertices (96 bytes) in its own vertex order and, for
//     remap_p0, its field values (8 bytes per component). MPI_Alltoall of the counts, then
//     MPI_Alltoallv of ids and of values.
//  3. q intersects the source cells it received with its own target cells (tetia::supermesh,
//     R-tree search: the received cells are a soup, without adjacency) and keeps the pieces.
// Why no piece is missed. Let s cap t have positive volume, t held by q. Then s's box and t's
// box overlap (each contains s cap t), t's box lies inside the box of t's run (a union of its
// cells' boxes), so s's box meets a box q published and r sends s to q, which tests the pair:
// the R-tree supermesh finds every pair with positive volume among the cells it is given (see
// src/supermesh.cpp). Conversely each pair is tested only on the rank of its target cell, so
// every piece appears once. Why bit for bit: a piece is the same kernel call on the same two
// cells, vertex for vertex (the cells travel as their coordinates, in the order given; finalize
// then orients the soup's cells as it orients the whole mesh), and front and R-tree searches
// return the same pieces, dropping the same sub-resolution ones.
// How much is sent, and why it is enough. Boxes: 48 B * B per rank to every rank, independent of
// the mesh sizes. Cells: each source cell goes to the ranks whose target region's run boxes it
// meets: for partitions into compact regions (Morton, graph partitioners) and meshes of similar
// resolution, the cells of the source region that overlaps q's target region plus a layer one
// cell thick around it (the boxes are slightly larger than the region), so about the rank's
// share of the source, which any algorithm that intersects s with t on one rank must bring
// there. More boxes per rank tighten the cover of non-convex regions. Nothing is sent twice to
// one rank.
#include "tetia/mpi.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/box.hpp>
#include <boost/geometry/geometries/point.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "../morton.hpp"
#include "tetia/mesh.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::mpi {

namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using BoostPoint = bg::model::point<double, 3, bg::cs::cartesian>;
using BoostBox = bg::model::box<BoostPoint>;

constexpr int kVertexDoubles = 12;
constexpr int kBoxDoubles = 6;

int rank_of(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int size_of(MPI_Comm comm) {
  int n = 0;
  MPI_Comm_size(comm, &n);
  return n;
}

/// The same outcome on every rank: if any rank's `error` is set, every rank throws (the lowest
/// failing rank its own std::invalid_argument, the others a std::runtime_error naming it).
void agree_on_errors(MPI_Comm comm, const std::string& error) {
  const int rank = rank_of(comm), size = size_of(comm);
  const int mine = error.empty() ? size : rank;
  int lowest = size;
  MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, comm);
  if (lowest == size) return;
  int length = rank == lowest ? static_cast<int>(error.size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, lowest, comm);
  std::string message = rank == lowest ? error : std::string(static_cast<std::size_t>(length), '\0');
  MPI_Bcast(message.data(), length, MPI_CHAR, lowest, comm);
  if (rank == lowest) throw std::invalid_argument(error);
  throw std::runtime_error("tetia: mpi: rank " + std::to_string(lowest) + ": " + message);
}

void check_part(const MeshPart& p, const char* what) {
  const std::string name = std::string("tetia: mpi: ") + what + " part: ";
  if (p.coordinates.size() % 3 != 0)
    throw std::invalid_argument(name + "coordinates: " + std::to_string(p.coordinates.size()) +
                                " values, not a multiple of 3");
  if (p.cells.size() % 4 != 0)
    throw std::invalid_argument(name + "cells: " + std::to_string(p.cells.size()) + " node indices, not a multiple of 4");
  if (p.cell_ids.size() * 4 != p.cells.size())
    throw std::invalid_argument(name + std::to_string(p.cells.size() / 4) + " cells but " +
                                std::to_string(p.cell_ids.size()) + " cell ids");
  const std::size_t nodes = p.coordinates.size() / 3;
  for (std::size_t i = 0; i < p.coordinates.size(); ++i)
    if (!std::isfinite(p.coordinates[i]))
      throw std::invalid_argument(name + "node " + std::to_string(i / 3) + ": coordinate " + std::to_string(i % 3) +
                                  " is not finite");
  for (std::size_t c = 0; c < p.cell_ids.size(); ++c) {
    if (p.cell_ids[c] < 0)
      throw std::invalid_argument(name + "cell " + std::to_string(c) + ": negative id " + std::to_string(p.cell_ids[c]));
    for (int k = 0; k < 4; ++k) {
      const std::int32_t v = p.cells[4 * c + static_cast<std::size_t>(k)];
      if (v < 0 || static_cast<std::size_t>(v) >= nodes)
        throw std::invalid_argument(name + "cell " + std::to_string(c) + ": node index " + std::to_string(v) +
                                    " out of range (" + std::to_string(nodes) + " nodes)");
    }
  }
}

/// The part's cell c's four vertices, x y z each, in the cell's order.
void vertices_of(const MeshPart& p, std::size_t c, double* out) {
  for (std::size_t k = 0; k < 4; ++k) {
    const auto v = static_cast<std::size_t>(p.cells[4 * c + k]);
    std::copy_n(p.coordinates.data() + 3 * v, 3, out + 3 * k);
  }
}

/// A box as lo x y z, hi x y z.
using Box = std::array<double, kBoxDoubles>;

Box empty_box() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {inf, inf, inf, -inf, -inf, -inf};
}

void extend(Box& b, const double* vertices) {
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      b[static_cast<std::size_t>(d)] = std::min(b[static_cast<std::size_t>(d)], vertices[3 * k + d]);
      b[static_cast<std::size_t>(3 + d)] = std::max(b[static_cast<std::size_t>(3 + d)], vertices[3 * k + d]);
    }
}

BoostBox boost_box(const Box& b) { return {BoostPoint(b[0], b[1], b[2]), BoostPoint(b[3], b[4], b[5])}; }

/// Step 1: at most `count` boxes over runs of the target cells along a Morton curve.
std::vector<Box> target_boxes(const MeshPart& target, int count) {
  const std::size_t n = target.cell_ids.size();
  if (n == 0) return {};
  std::vector<double> vertices(kVertexDoubles * n);
  Box all = empty_box();
  for (std::size_t c = 0; c < n; ++c) {
    vertices_of(target, c, vertices.data() + kVertexDoubles * c);
    extend(all, vertices.data() + kVertexDoubles * c);
  }
  std::vector<std::uint64_t> code(n);
  for (std::size_t c = 0; c < n; ++c) {
    std::uint64_t key = 0;
    for (int d = 0; d < 3; ++d) {
      const double* v = vertices.data() + kVertexDoubles * c;
      const double centre = 0.25 * (v[d] + v[3 + d] + v[6 + d] + v[9 + d]);
      const double extent = all[static_cast<std::size_t>(3 + d)] - all[static_cast<std::size_t>(d)];
      const double unit = extent > 0.0 ? (centre - all[static_cast<std::size_t>(d)]) / extent : 0.0;
      const auto q = static_cast<std::uint64_t>(std::clamp(unit, 0.0, 1.0) * double((1u << 21) - 1));
      key |= detail::spread_bits<3>(q) << (2 - d);
    }
    code[c] = key;
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
  const std::size_t runs = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, count)));
  std::vector<Box> boxes(runs, empty_box());
  for (std::size_t i = 0; i < n; ++i) extend(boxes[i * runs / n], vertices.data() + kVertexDoubles * order[i]);
  return boxes;
}

/// MPI counts are int: a message this large is refused with a clear error rather than wrapped.
int count_of(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error(std::string("tetia: mpi: ") + what + ": " + std::to_string(n) +
                            " values in one message, more than MPI's int counts allow");
  return static_cast<int>(n);
}

/// Displacements of the counts (exclusive prefix sums).
std::vector<int> displacements(const std::vector<int>& counts, const char* what) {
  std::vector<int> d(counts.size(), 0);
  std::size_t sum = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    d[i] = count_of(sum, what);
    sum += static_cast<std::size_t>(counts[i]);
  }
  count_of(sum, what);
  return d;
}

}  // namespace

namespace detail_mpi {

/// What the exchange and the local supermesh leave on a rank: the received source cells (ids,
/// values) and the pieces with local indices (source: received cell, target: local cell).
struct Exchanged {
  std::vector<std::int64_t> source_ids;
  std::vector<double> source_values;  ///< components per received cell
  std::shared_ptr<const TetMesh> target;  ///< the rank's target cells, finalized (null if none)
  std::vector<SupermeshPiece> pieces;    ///< sorted by (target id, source id)
  DistributedSupermesh stats;
};

Exchanged exchange_and_intersect(const MeshPart& source, std::span<const double> values, int components,
                                 const MeshPart& target, MPI_Comm comm, const DistributedOptions& options) {
  const double t0 = MPI_Wtime();
  const int size = size_of(comm);
  const auto ranks = static_cast<std::size_t>(size);
  Exchanged out;

  // The parts, checked and the target mesh built before anything is sent.
  std::string error;
  try {
    check_part(source, "source");
    check_part(target, "target");
    if (values.size() != source.cell_ids.size() * static_cast<std::size_t>(components))
      throw std::invalid_argument("tetia: mpi: remap_p0: " + std::to_string(values.size()) + " source values for " +
                                  std::to_string(source.cell_ids.size()) + " source cells of " +
                                  std::to_string(components) + " components");
    if (!target.cell_ids.empty()) {
      TetMesh t;
      for (std::size_t i = 0; i < target.coordinates.size(); i += 3)
        t.nodes.push_back({target.coordinates[i], target.coordinates[i + 1], target.coordinates[i + 2]});
      for (std::size_t c = 0; c < target.cell_ids.size(); ++c)
        t.cells.push_back({target.cells[4 * c], target.cells[4 * c + 1], target.cells[4 * c + 2], target.cells[4 * c + 3]});
      finalize(t, "tetia: mpi: rank " + std::to_string(rank_of(comm)) + ": target part");
      out.target = std::make_shared<const TetMesh>(std::move(t));
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree_on_errors(comm, error);

  // 1. Target boxes from every rank.
  const std::vector<Box> mine = target_boxes(target, options.boxes_per_rank);
  const int my_count = static_cast<int>(mine.size());
  std::vector<int> box_counts(ranks);
  MPI_Allgather(&my_count, 1, MPI_INT, box_counts.data(), 1, MPI_INT, comm);
  std::vector<int> box_doubles(ranks);
  for (std::size_t q = 0; q < ranks; ++q) box_doubles[q] = box_counts[q] * kBoxDoubles;
  const std::vector<int> box_offsets = displacements(box_doubles, "target boxes");
  std::vector<double> all_boxes(static_cast<std::size_t>(box_offsets.back() + box_doubles.back()));
  MPI_Allgatherv(mine.empty() ? nullptr : mine.front().data(), my_count * kBoxDoubles, MPI_DOUBLE, all_boxes.data(),
                 box_doubles.data(), box_offsets.data(), MPI_DOUBLE, comm);
  out.stats.boxes_received = all_boxes.size() / kBoxDoubles;
  out.stats.bytes_sent += static_cast<std::size_t>(my_count) * kBoxDoubles * sizeof(double) * (ranks - 1);

  std::vector<std::pair<BoostBox, int>> entries;
  for (std::size_t q = 0; q < ranks; ++q)
    for (int b = 0; b < box_counts[q]; ++b) {
      Box box;
      std::copy_n(all_boxes.data() + box_offsets[q] + kBoxDoubles * b, kBoxDoubles, box.begin());
      entries.emplace_back(boost_box(box), static_cast<int>(q));
    }
  const bgi::rtree<std::pair<BoostBox, int>, bgi::quadratic<16>> tree(entries.begin(), entries.end());

  // 2. Each source cell to the ranks whose boxes its box meets, once each.
  const std::size_t per_cell = kVertexDoubles + static_cast<std::size_t>(components);
  std::vector<std::vector<std::int64_t>> ids_to(ranks);
  std::vector<std::vector<double>> data_to(ranks);
  std::vector<std::size_t> last_cell(ranks, std::numeric_limits<std::size_t>::max());
  std::vector<std::pair<BoostBox, int>> hits;
  std::array<double, kVertexDoubles> v{};
  for (std::size_t c = 0; c < source.cell_ids.size(); ++c) {
    vertices_of(source, c, v.data());
    Box box = empty_box();
    extend(box, v.data());
    hits.clear();
    tree.query(bgi::intersects(boost_box(box)), std::back_inserter(hits));
    for (const auto& [b, q] : hits) {
      const auto r = static_cast<std::size_t>(q);
      if (last_cell[r] == c) continue;
      last_cell[r] = c;
      ids_to[r].push_back(source.cell_ids[c]);
      data_to[r].insert(data_to[r].end(), v.begin(), v.end());
      data_to[r].insert(data_to[r].end(), values.begin() + static_cast<std::ptrdiff_t>(c * static_cast<std::size_t>(components)),
                        values.begin() + static_cast<std::ptrdiff_t>((c + 1) * static_cast<std::size_t>(components)));
    }
  }
  const int self = rank_of(comm);
  std::vector<int> send_cells(ranks), recv_cells(ranks);
  for (std::size_t q = 0; q < ranks; ++q) send_cells[q] = count_of(ids_to[q].size(), "source cells");
  MPI_Alltoall(send_cells.data(), 1, MPI_INT, recv_cells.data(), 1, MPI_INT, comm);
  std::vector<int> send_data(ranks), recv_data(ranks);
  std::vector<std::int64_t> send_ids;
  std::vector<double> send_values;
  for (std::size_t q = 0; q < ranks; ++q) {
    send_data[q] = count_of(data_to[q].size(), "source cells");
    recv_data[q] = count_of(static_cast<std::size_t>(recv_cells[q]) * per_cell, "source cells");
    send_ids.insert(send_ids.end(), ids_to[q].begin(), ids_to[q].end());
    send_values.insert(send_values.end(), data_to[q].begin(), data_to[q].end());
    if (static_cast<int>(q) != self) {
      out.stats.cells_sent += ids_to[q].size();
      out.stats.bytes_sent += ids_to[q].size() * sizeof(std::int64_t) + data_to[q].size() * sizeof(double);
    }
  }
  ids_to.clear();
  data_to.clear();
  const std::vector<int> send_cell_offsets = displacements(send_cells, "source cells");
  const std::vector<int> recv_cell_offsets = displacements(recv_cells, "source cells");
  const std::vector<int> send_data_offsets = displacements(send_data, "source cells");
  const std::vector<int> recv_data_offsets = displacements(recv_data, "source cells");
  const std::size_t received = static_cast<std::size_t>(recv_cell_offsets.back() + recv_cells.back());
  out.source_ids.resize(received);
  std::vector<double> received_data(received * per_cell);
  MPI_Alltoallv(send_ids.data(), send_cells.data(), send_cell_offsets.data(), MPI_INT64_T, out.source_ids.data(),
                recv_cells.data(), recv_cell_offsets.data(), MPI_INT64_T, comm);
  MPI_Alltoallv(send_values.data(), send_data.data(), send_data_offsets.data(), MPI_DOUBLE, received_data.data(),
                recv_data.data(), recv_data_offsets.data(), MPI_DOUBLE, comm);
  out.stats.cells_received = received;

  // 3. The received cells (a soup: four nodes of their own each) against the rank's targets.
  error.clear();
  try {
    if (received > 0 && out.target) {
      TetMesh soup;
      soup.nodes.reserve(4 * received);
      soup.cells.reserve(received);
      out.source_values.reserve(received * static_cast<std::size_t>(components));
      for (std::size_t c = 0; c < received; ++c) {
        const double* p = received_data.data() + c * per_cell;
        for (int k = 0; k < 4; ++k) soup.nodes.push_back({p[3 * k], p[3 * k + 1], p[3 * k + 2]});
        const auto base = static_cast<std::int32_t>(4 * c);
        soup.cells.push_back({base, base + 1, base + 2, base + 3});
        out.source_values.insert(out.source_values.end(), p + kVertexDoubles, p + per_cell);
      }
      finalize(soup, "tetia: mpi: rank " + std::to_string(self) + ": received source cells");
      SupermeshOptions so;
      so.search = CandidateSearch::rtree;
      so.threads = options.threads;
      Supermesh s = tetia::supermesh(std::make_shared<const TetMesh>(std::move(soup)), out.target, so);
      out.pieces = std::move(s.pieces);
      std::sort(out.pieces.begin(), out.pieces.end(), [&](const SupermeshPiece& a, const SupermeshPiece& b) {
        const std::int64_t ta = target.cell_ids[static_cast<std::size_t>(a.target)];
        const std::int64_t tb = target.cell_ids[static_cast<std::size_t>(b.target)];
        if (ta != tb) return ta < tb;
        return out.source_ids[static_cast<std::size_t>(a.source)] < out.source_ids[static_cast<std::size_t>(b.source)];
      });
    } else {
      for (std::size_t c = 0; c < received; ++c) {
        const double* p = received_data.data() + c * per_cell;
        out.source_values.insert(out.source_values.end(), p + kVertexDoubles, p + per_cell);
      }
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree_on_errors(comm, error);
  out.stats.seconds = MPI_Wtime() - t0;
  return out;
}

}  // namespace detail_mpi

DistributedSupermesh supermesh(const MeshPart& source, const MeshPart& target, MPI_Comm comm,
                               const DistributedOptions& options) {
  detail_mpi::Exchanged x = detail_mpi::exchange_and_intersect(source, {}, 0, target, comm, options);
  DistributedSupermesh out = std::move(x.stats);
  out.pieces.reserve(x.pieces.size());
  for (const SupermeshPiece& p : x.pieces)
    out.pieces.push_back({x.source_ids[static_cast<std::size_t>(p.source)],
                          target.cell_ids[static_cast<std::size_t>(p.target)], p.volume, p.first});
  return out;
}

std::vector<double> remap_p0(const MeshPart& source, std::span<const double> source_values, const MeshPart& target,
                             MPI_Comm comm, int components, P0Normalization normalization,
                             const DistributedOptions& options, DistributedSupermesh* pieces) {
  if (components < 1) throw std::invalid_argument("tetia: mpi: remap_p0: components must be at least 1");
  detail_mpi::Exchanged x =
      detail_mpi::exchange_and_intersect(source, source_values, components, target, comm, options);
  const auto k = static_cast<std::size_t>(components);
  std::vector<double> out(target.cell_ids.size() * k, 0.0);
  // As tetia::remap_p0: per target cell, the pieces in source order, then one division.
  std::size_t i = 0;
  std::vector<double> num(k);
  while (i < x.pieces.size()) {
    const std::int32_t t = x.pieces[i].target;
    std::fill(num.begin(), num.end(), 0.0);
    double covered = 0.0;
    for (; i < x.pieces.size() && x.pieces[i].target == t; ++i) {
      const double m = x.pieces[i].volume;
      const double* u = x.source_values.data() + static_cast<std::size_t>(x.pieces[i].source) * k;
      for (std::size_t c = 0; c < k; ++c) num[c] += u[c] * m;
      covered += m;
    }
    const double den =
        normalization == P0Normalization::covered_volume ? covered : x.target->volumes[static_cast<std::size_t>(t)];
    for (std::size_t c = 0; c < k; ++c) out[static_cast<std::size_t>(t) * k + c] = den > 0.0 ? num[c] / den : 0.0;
  }
  if (pieces != nullptr) {
    *pieces = std::move(x.stats);
    pieces->pieces.clear();
    for (const SupermeshPiece& p : x.pieces)
      pieces->pieces.push_back({x.source_ids[static_cast<std::size_t>(p.source)],
                                target.cell_ids[static_cast<std::size_t>(p.target)], p.volume, p.first});
  }
  return out;
}

}  // namespace tetia::mpi
