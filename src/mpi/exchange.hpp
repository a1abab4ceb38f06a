// src/mpi/exchange.hpp -- what the distributed supermesh and remaps share (internal): the
// collective error rule, all-to-all exchanges of vectors, and the exchange of donor cells with
// the local supermesh (implemented in distributed_supermesh.cpp).
#pragma once

#include <mpi.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "tetia/mesh.hpp"
#include "tetia/mpi.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::mpi::detail {

inline int rank_of(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

inline int size_of(MPI_Comm comm) {
  int n = 0;
  MPI_Comm_size(comm, &n);
  return n;
}

/// The same outcome on every rank: if any rank's `error` is set, every rank throws (the lowest
/// failing rank its own std::invalid_argument, the others a std::runtime_error naming it).
void agree_on_errors(MPI_Comm comm, const std::string& error);

/// MPI counts are int: a message this large is refused with a clear error rather than wrapped.
inline int count_of(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error(std::string("tetia: mpi: ") + what + ": " + std::to_string(n) +
                            " values in one message, more than MPI's int counts allow");
  return static_cast<int>(n);
}

/// Exclusive prefix sums of the counts (checked against int).
inline std::vector<int> displacements(const std::vector<int>& counts, const char* what) {
  std::vector<int> d(counts.size(), 0);
  std::size_t sum = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    d[i] = count_of(sum, what);
    sum += static_cast<std::size_t>(counts[i]);
  }
  count_of(sum, what);
  return d;
}

template <class T>
MPI_Datatype datatype();
template <>
inline MPI_Datatype datatype<double>() {
  return MPI_DOUBLE;
}
template <>
inline MPI_Datatype datatype<std::int64_t>() {
  return MPI_INT64_T;
}
template <>
inline MPI_Datatype datatype<int>() {
  return MPI_INT;
}

/// send[q] to rank q, for every q (MPI_Alltoall of the counts, MPI_Alltoallv of the values):
/// what every rank sent this one, rank after rank; `from` (if given) gets the count per rank.
template <class T>
std::vector<T> all_to_all(MPI_Comm comm, const std::vector<std::vector<T>>& send, const char* what,
                          std::vector<int>* from = nullptr) {
  const std::size_t ranks = send.size();
  std::vector<int> send_counts(ranks), recv_counts(ranks);
  std::vector<T> flat;
  for (std::size_t q = 0; q < ranks; ++q) {
    send_counts[q] = count_of(send[q].size(), what);
    flat.insert(flat.end(), send[q].begin(), send[q].end());
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  const std::vector<int> send_offsets = displacements(send_counts, what);
  const std::vector<int> recv_offsets = displacements(recv_counts, what);
  std::vector<T> received(static_cast<std::size_t>(recv_offsets.back() + recv_counts.back()));
  MPI_Alltoallv(flat.data(), send_counts.data(), send_offsets.data(), datatype<T>(), received.data(),
                recv_counts.data(), recv_offsets.data(), datatype<T>(), comm);
  if (from != nullptr) *from = std::move(recv_counts);
  return received;
}

/// Throws std::invalid_argument naming the part unless its arrays agree (sizes, node indices in
/// range, finite coordinates, ids >= 0; node ids too if `need_node_ids`).
void check_part(const MeshPart& p, const char* what, bool need_node_ids);

/// What the exchange and the local supermesh leave on a rank.
struct Exchanged {
  std::vector<std::int64_t> source_ids;   ///< received source cells' ids
  std::vector<double> source_values;      ///< `doubles` values per received cell
  std::vector<std::int64_t> source_extra; ///< `extra` ids per received cell
  std::shared_ptr<const TetMesh> target;  ///< the rank's target cells, finalized (null if none)
  /// Pieces (source: received cell, target: local cell), sorted by (target id, source id), and
  /// their local mixed mass matrices if asked for (aligned with them).
  std::vector<SupermeshPiece> pieces;
  std::vector<std::array<double, 16>> local_mass;
  DistributedSupermesh stats;
};

/// The exchange of tetia/mpi.hpp (steps 1-3 of distributed_supermesh.cpp): each source cell c
/// travels with values[doubles * c ...] and extra[ids * c ...].
Exchanged exchange_and_intersect(const MeshPart& source, std::span<const double> values, int doubles,
                                 std::span<const std::int64_t> extra, int ids, const MeshPart& target, MPI_Comm comm,
                                 const DistributedOptions& options, bool keep_mixed_mass, bool need_node_ids);

/// The pieces with global ids (source: the received cell's id, target: the local cell's).
std::vector<DistributedPiece> global_pieces(const Exchanged& x, const MeshPart& target);

}  // namespace tetia::mpi::detail
