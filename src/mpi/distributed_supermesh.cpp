// The supermesh and P0 remap of two distributed tetrahedral meshes (tetia/mpi.hpp), and the
// exchange that remap_p1 (distributed_p1.cpp) shares.
//
// The exchange. Rank r holds target cells T_r and source cells S_r (any partitions).
//  1. r sorts T_r along a Morton curve through the cell centroids, cuts it into at most
//     B = boxes_per_rank runs of consecutive cells and publishes one axis-aligned box per run
//     (the union of its cells' boxes): an all-to-all of the boxes, 48 bytes each, P * B in all
//     on every rank.
//  2. For each of its source cells s, r finds (R-tree over all the boxes) the ranks q one of
//     whose boxes meets s's box, closed boxes, touching included, and sends s to each such q
//     once: its id (8 bytes), its four vertices (96 bytes) in its own vertex order, its four
//     node ids (32 bytes) where every rank with source cells gave them, and for the remaps its
//     field values (8 bytes per value). MPI_Alltoall of the counts, then MPI_Alltoallv of ids
//     and of values.
//  3. q intersects the source cells it received with its own target cells (tetia::supermesh):
//     with node ids the received cells share their nodes again, a mesh with adjacency, and the
//     advancing front searches; without, they are a soup of four nodes each, and the R-tree.
//     It keeps the pieces, sorted by (target id, source id).
// Why no piece is missed. Let s cap t have positive volume, t held by q. Then s's box and t's
// box overlap (each contains s cap t), t's box lies inside the box of t's run (a union of its
// cells' boxes), so s's box meets a box q published and r sends s to q, which tests the pair:
// either search finds every pair with positive volume among the cells it is given (see
// src/supermesh/supermesh.cpp). Conversely each pair is tested only on the rank of its target cell, so
// every piece appears once. Why bit for bit: a piece is the same kernel call on the same two
// cells, vertex for vertex (the cells travel as their coordinates, in the order given; finalize
// then orients the received cells as it orients the whole mesh), and front and R-tree searches
// return the same pieces, dropping the same sub-resolution ones.
// How much is sent, and why it is enough. Boxes: 48 B * B per rank to every rank, independent of
// the mesh sizes. Cells: each source cell goes to the ranks whose target region's run boxes it
// meets: for partitions into compact regions (Morton, graph partitioners) and meshes of similar
// resolution, the cells of the source region that overlaps q's target region plus a layer a
// cell or two thick around it (the boxes are slightly larger than the region; two cube layers
// of a Kuhn mesh in docs/benchmarks.md), so about the rank's
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
#include <unordered_map>
#include <utility>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/box.hpp>
#include <boost/geometry/geometries/point.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "../morton.hpp"
#include "../permute.hpp"
#include "../supermesh/mixed_mass.hpp"
#include "exchange.hpp"
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

}  // namespace

namespace detail {

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

void check_part(const MeshPart& p, const char* what, bool need_node_ids) {
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
  if ((need_node_ids || !p.node_ids.empty()) && p.node_ids.size() != nodes)
    throw std::invalid_argument(name + std::to_string(nodes) + " nodes but " + std::to_string(p.node_ids.size()) +
                                " node ids");
  for (std::size_t n = 0; n < p.node_ids.size(); ++n)
    if (p.node_ids[n] < 0)
      throw std::invalid_argument(name + "node " + std::to_string(n) + ": negative id " + std::to_string(p.node_ids[n]));
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

}  // namespace detail

namespace {

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
  // (code, cell), sorted stably: the centroid's Morton code in the part's bounding box.
  std::vector<std::pair<std::uint64_t, std::size_t>> order(n);
  for (std::size_t c = 0; c < n; ++c) {
    const double* v = vertices.data() + kVertexDoubles * c;
    double centre[3];
    for (int d = 0; d < 3; ++d) centre[d] = 0.25 * (v[d] + v[3 + d] + v[6 + d] + v[9 + d]);
    order[c] = {tetia::detail::morton_code<3>(centre, all.data(), all.data() + 3), c};
  }
  tetia::detail::sort_by_key(order);
  const std::size_t runs = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, count)));
  std::vector<Box> boxes(runs, empty_box());
  for (std::size_t i = 0; i < n; ++i) extend(boxes[i * runs / n], vertices.data() + kVertexDoubles * order[i].second);
  return boxes;
}

}  // namespace

namespace detail {

Exchanged exchange_and_intersect(const MeshPart& source, std::span<const double> values, int doubles,
                                 std::span<const std::int64_t> extra, int ids, const MeshPart& target, MPI_Comm comm,
                                 const DistributedOptions& options, bool keep_mixed_mass, bool need_node_ids) {
  const double t0 = MPI_Wtime();
  const int self = rank_of(comm);
  const auto ranks = static_cast<std::size_t>(size_of(comm));
  const auto per_value = static_cast<std::size_t>(doubles);
  Exchanged out;

  // The parts, checked, and the target mesh built, before anything is sent.
  std::string error;
  try {
    check_part(source, "source", need_node_ids);
    check_part(target, "target", need_node_ids);
    if (values.size() != source.cell_ids.size() * per_value ||
        extra.size() != source.cell_ids.size() * static_cast<std::size_t>(ids))
      throw std::invalid_argument("tetia: mpi: " + std::to_string(values.size()) + " source values for " +
                                  std::to_string(source.cell_ids.size()) + " source cells");
    if (!target.cell_ids.empty()) {
      TetMesh t;
      for (std::size_t n = 0; n < target.coordinates.size(); n += 3)
        t.nodes.push_back({target.coordinates[n], target.coordinates[n + 1], target.coordinates[n + 2]});
      for (std::size_t c = 0; c < target.cell_ids.size(); ++c)
        t.cells.push_back({target.cells[4 * c], target.cells[4 * c + 1], target.cells[4 * c + 2], target.cells[4 * c + 3]});
      finalize(t, "tetia: mpi: rank " + std::to_string(self) + ": target part");
      out.target = std::make_shared<const TetMesh>(std::move(t));
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree_on_errors(comm, error);
  // Where the source's node ids are known, its cells travel with them (the caller's extra ids
  // are those ids where it needs them, as remap_p1), so that the receiving rank rebuilds the
  // cells' adjacency and searches with the advancing front instead of an R-tree.
  // Every rank must agree (a rank parses what the others send): ids travel where every rank
  // with source cells has given them.
  const int have_ids = need_node_ids || source.cell_ids.empty() || !source.node_ids.empty() ? 1 : 0;
  int all_have_ids = 0;
  MPI_Allreduce(&have_ids, &all_have_ids, 1, MPI_INT, MPI_MIN, comm);
  const bool with_node_ids = all_have_ids == 1;
  std::vector<std::int64_t> node_extra;
  if (with_node_ids && ids == 0) {
    node_extra.reserve(source.cells.size());
    for (const std::int32_t v : source.cells) node_extra.push_back(source.node_ids[static_cast<std::size_t>(v)]);
    extra = node_extra;
    ids = 4;
  }
  const auto per_extra = static_cast<std::size_t>(ids);

  // 1. Target boxes from every rank.
  const std::vector<Box> mine = target_boxes(target, options.boxes_per_rank);
  std::vector<std::vector<double>> box_send(ranks);
  for (std::size_t q = 0; q < ranks; ++q)
    for (const Box& b : mine) box_send[q].insert(box_send[q].end(), b.begin(), b.end());
  std::vector<int> box_from;
  const std::vector<double> all_boxes = all_to_all(comm, box_send, "target boxes", &box_from);
  out.stats.boxes_received = all_boxes.size() / kBoxDoubles;
  out.stats.bytes_sent += mine.size() * kBoxDoubles * sizeof(double) * (ranks - 1);
  std::vector<std::pair<BoostBox, int>> entries;
  for (std::size_t q = 0, offset = 0; q < ranks; ++q)
    for (int b = 0; b < box_from[q] / kBoxDoubles; ++b, offset += kBoxDoubles) {
      Box box;
      std::copy_n(all_boxes.data() + offset, kBoxDoubles, box.begin());
      entries.emplace_back(boost_box(box), static_cast<int>(q));
    }
  const bgi::rtree<std::pair<BoostBox, int>, bgi::quadratic<16>> tree(entries.begin(), entries.end());

  // 2. Each source cell to the ranks whose boxes its box meets, once each: its id, then its
  // vertices and values, then its extra ids.
  const std::size_t per_cell = kVertexDoubles + per_value;
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
    for (const auto& hit : hits) {
      const auto r = static_cast<std::size_t>(hit.second);
      if (last_cell[r] == c) continue;
      last_cell[r] = c;
      ids_to[r].push_back(source.cell_ids[c]);
      ids_to[r].insert(ids_to[r].end(), extra.begin() + static_cast<std::ptrdiff_t>(c * per_extra),
                       extra.begin() + static_cast<std::ptrdiff_t>((c + 1) * per_extra));
      data_to[r].insert(data_to[r].end(), v.begin(), v.end());
      data_to[r].insert(data_to[r].end(), values.begin() + static_cast<std::ptrdiff_t>(c * per_value),
                        values.begin() + static_cast<std::ptrdiff_t>((c + 1) * per_value));
    }
  }
  for (std::size_t q = 0; q < ranks; ++q)
    if (static_cast<int>(q) != self) {
      out.stats.cells_sent += data_to[q].size() / per_cell;
      out.stats.bytes_sent += ids_to[q].size() * sizeof(std::int64_t) + data_to[q].size() * sizeof(double);
    }
  const std::vector<std::int64_t> received_ids = all_to_all(comm, ids_to, "source cells");
  ids_to.clear();
  const std::vector<double> received_data = all_to_all(comm, data_to, "source cells");
  data_to.clear();
  const std::size_t received = received_data.size() / per_cell;
  out.stats.cells_received = received;
  out.source_ids.reserve(received);
  out.source_extra.reserve(received * per_extra);
  for (std::size_t c = 0; c < received; ++c) {
    out.source_ids.push_back(received_ids[c * (1 + per_extra)]);
    out.source_extra.insert(out.source_extra.end(), received_ids.begin() + static_cast<std::ptrdiff_t>(c * (1 + per_extra) + 1),
                            received_ids.begin() + static_cast<std::ptrdiff_t>((c + 1) * (1 + per_extra)));
  }
  out.source_values.reserve(received * per_value);
  for (std::size_t c = 0; c < received; ++c) {
    const double* p = received_data.data() + c * per_cell;
    out.source_values.insert(out.source_values.end(), p + kVertexDoubles, p + per_cell);
  }

  // 3. The received cells (a soup: four nodes of their own each) against the rank's targets.
  error.clear();
  try {
    if (received > 0 && out.target) {
      // The received cells: sharing their nodes by id where the ids came along (a mesh with
      // adjacency: the front search), else a soup of four nodes each (the R-tree search).
      TetMesh received_mesh;
      received_mesh.cells.reserve(received);
      std::unordered_map<std::int64_t, std::int32_t> node_of;
      for (std::size_t c = 0; c < received; ++c) {
        const double* p = received_data.data() + c * per_cell;
        std::array<std::int32_t, 4> cell{};
        for (std::size_t k = 0; k < 4; ++k) {
          const Vec3 x{p[3 * k], p[3 * k + 1], p[3 * k + 2]};
          auto index = static_cast<std::int32_t>(received_mesh.nodes.size());
          if (with_node_ids) {
            const std::int64_t id = out.source_extra[4 * c + k];
            const auto [it, fresh] = node_of.try_emplace(id, index);
            if (!fresh) {
              index = it->second;
              const Vec3& y = received_mesh.nodes[static_cast<std::size_t>(index)];
              if (x.x != y.x || x.y != y.y || x.z != y.z)
                throw std::invalid_argument("tetia: mpi: source node id " + std::to_string(id) +
                                            " has two different positions (in the parts of two ranks, or two cells)");
            }
          }
          if (index == static_cast<std::int32_t>(received_mesh.nodes.size())) received_mesh.nodes.push_back(x);
          cell[k] = index;
        }
        received_mesh.cells.push_back(cell);
      }
      finalize(received_mesh, "tetia: mpi: rank " + std::to_string(self) + ": received source cells");
      SupermeshOptions so;
      so.search = with_node_ids ? CandidateSearch::front : CandidateSearch::rtree;
      so.threads = options.threads;
      // The pieces (and their local mixed mass matrices, computed as keep_mixed_mass computes
      // them) handed straight into `out` by a consumer: no kept supermesh to copy them from.
      // Then in (target id, source id) order, in place.
      struct Into final : PieceConsumer {
        const TetMesh& source;
        bool with_mass;
        Exchanged& out;
        Into(const TetMesh& s, bool m, Exchanged& o) : source(s), with_mass(m), out(o) {}
        std::size_t values_per_piece() const override { return with_mass ? 16 : 0; }
        void compute(const SupermeshPiece& p, const Polyhedron& P, double* values) const override {
          std::array<double, 16> A;
          tetia::detail::piece_mixed_mass<TetMesh>(source.cell(static_cast<std::size_t>(p.source)), P, A);
          std::copy(A.begin(), A.end(), values);
        }
        void consume(const SupermeshPiece& p, const double* values) override {
          out.pieces.push_back(p);
          if (with_mass) std::copy(values, values + 16, out.local_mass.emplace_back().begin());
        }
      } into(received_mesh, keep_mixed_mass, out);
      out.stats.candidates = tetia::supermesh(received_mesh, *out.target, into, so).candidates;
      const std::size_t n = out.pieces.size();
      std::vector<std::size_t> order(n);  // order[k]: the piece that goes to position k
      std::iota(order.begin(), order.end(), std::size_t{0});
      const auto key = [&](std::size_t k) {
        return std::pair{target.cell_ids[static_cast<std::size_t>(out.pieces[k].target)],
                         out.source_ids[static_cast<std::size_t>(out.pieces[k].source)]};
      };
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
      std::vector<std::size_t> place(n);  // where the piece now at k goes
      for (std::size_t k = 0; k < n; ++k) place[order[k]] = k;
      order = {};
      tetia::detail::permute_to(place, [&](std::size_t i, std::size_t j) {
        std::swap(out.pieces[i], out.pieces[j]);
        if (keep_mixed_mass) std::swap(out.local_mass[i], out.local_mass[j]);
      });
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree_on_errors(comm, error);
  out.stats.seconds = MPI_Wtime() - t0;
  return out;
}

/// The pieces with global ids.
std::vector<DistributedPiece> global_pieces(const Exchanged& x, const MeshPart& target) {
  std::vector<DistributedPiece> out;
  out.reserve(x.pieces.size());
  for (const SupermeshPiece& p : x.pieces)
    out.push_back({x.source_ids[static_cast<std::size_t>(p.source)], target.cell_ids[static_cast<std::size_t>(p.target)],
                   p.volume, p.first});
  return out;
}

}  // namespace detail

DistributedSupermesh supermesh(const MeshPart& source, const MeshPart& target, MPI_Comm comm,
                               const DistributedOptions& options) {
  detail::Exchanged x =
      detail::exchange_and_intersect(source, {}, 0, {}, 0, target, comm, options, options.keep_mixed_mass, false);
  DistributedSupermesh out = std::move(x.stats);
  out.pieces = detail::global_pieces(x, target);
  out.local_mass = std::move(x.local_mass);
  return out;
}

std::vector<double> remap_p0(const MeshPart& source, std::span<const double> source_values, const MeshPart& target,
                             MPI_Comm comm, int components, P0Normalization normalization,
                             const DistributedOptions& options, DistributedSupermesh* pieces) {
  if (components < 1) throw std::invalid_argument("tetia: mpi: remap_p0: components must be at least 1");
  detail::Exchanged x = detail::exchange_and_intersect(source, source_values, components, {}, 0, target, comm,
                                                       options, false, false);
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
    pieces->pieces = detail::global_pieces(x, target);
  }
  return out;
}

}  // namespace tetia::mpi
