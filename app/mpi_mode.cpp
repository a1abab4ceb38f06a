// The command line under mpiexec (app/mpi_mode.hpp). Without MPI in the build (no
// TETIA_WITH_MPI) every function is the one-process case.
#include "mpi_mode.hpp"

#include <cstdlib>
#include <stdexcept>

#ifdef TETIA_WITH_MPI
#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "tetia/mpi.hpp"
#endif

namespace tetia::app {

void check_partition(const std::string& kind) {
  if (kind != "morton" && kind != "reversed" && kind != "random")
    throw std::invalid_argument("tetia: --partition must be morton, reversed or random, not " + kind);
}

Supermesh2 parallel_supermesh(std::shared_ptr<const TriMesh> source, std::shared_ptr<const TriMesh> target,
                              const SupermeshOptions& options, const std::string& partition) {
  check_partition(partition);
  return supermesh(std::move(source), std::move(target), options);
}

#ifndef TETIA_WITH_MPI

std::optional<int> mpi_start(int&, char**&) { return std::nullopt; }
int mpi_finish(int status) { return status; }
int mpi_ranks() { return 1; }

Supermesh parallel_supermesh(std::shared_ptr<const TetMesh> source, std::shared_ptr<const TetMesh> target,
                             const SupermeshOptions& options, const std::string& partition) {
  check_partition(partition);
  return supermesh(std::move(source), std::move(target), options);
}

#else

namespace {

bool started = false;

// What rank 0 broadcasts to the others: stop (with the exit status), or a supermesh.
enum Command : int { stop = 0, distributed_supermesh = 1 };

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

using Part = mpi::OwnedMeshPart;

template <class T>
void send_vector(const std::vector<T>& v, int to, MPI_Datatype type) {
  const auto n = static_cast<long long>(v.size());
  MPI_Send(&n, 1, MPI_LONG_LONG, to, 0, MPI_COMM_WORLD);
  MPI_Send(v.data(), static_cast<int>(v.size()), type, to, 0, MPI_COMM_WORLD);
}

template <class T>
std::vector<T> receive_vector(int from, MPI_Datatype type) {
  long long n = 0;
  MPI_Recv(&n, 1, MPI_LONG_LONG, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::vector<T> v(static_cast<std::size_t>(n));
  MPI_Recv(v.data(), static_cast<int>(n), type, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return v;
}

void send_part(const Part& p, int to) {
  send_vector(p.coordinates, to, MPI_DOUBLE);
  send_vector(p.cells, to, MPI_INT32_T);
  send_vector(p.cell_ids, to, MPI_INT64_T);
  send_vector(p.node_ids, to, MPI_INT64_T);
}

Part receive_part(int from) {
  Part p;
  p.coordinates = receive_vector<double>(from, MPI_DOUBLE);
  p.cells = receive_vector<std::int32_t>(from, MPI_INT32_T);
  p.cell_ids = receive_vector<std::int64_t>(from, MPI_INT64_T);
  p.node_ids = receive_vector<std::int64_t>(from, MPI_INT64_T);
  return p;
}

/// Pieces (ids, volume, moments, local mass if kept) as doubles, 6 or 22 per piece.
std::vector<double> pack(const mpi::DistributedSupermesh& d, bool with_mass) {
  std::vector<double> out;
  for (std::size_t k = 0; k < d.pieces.size(); ++k) {
    const auto& p = d.pieces[k];
    out.insert(out.end(), {static_cast<double>(p.source), static_cast<double>(p.target), p.volume, p.first.x,
                           p.first.y, p.first.z});
    if (with_mass) out.insert(out.end(), d.local_mass[k].begin(), d.local_mass[k].end());
  }
  return out;
}

/// Which rank gets each cell.
std::vector<int> owners(const TetMesh& m, int ranks, const std::string& kind, bool target) {
  const std::size_t n = m.num_cells();
  std::vector<int> owner(n, 0);
  if (kind == "random") {
    std::mt19937 rng(target ? 2u : 1u);
    for (int& o : owner) o = static_cast<int>(rng() % static_cast<unsigned>(ranks));
    return owner;
  }
  owner = mpi::morton_partition(m, ranks);
  if (target && kind == "reversed")
    for (int& o : owner) o = ranks - 1 - o;
  return owner;
}

/// Every rank's side of a distributed supermesh: its parts in, its pieces out (to rank 0).
mpi::DistributedSupermesh take_part(const Part& source, const Part& target, const mpi::DistributedOptions& options) {
  return mpi::supermesh(source.view(), target.view(), MPI_COMM_WORLD, options);
}

/// A rank other than 0: serves rank 0's commands until told to stop; returns the exit status.
int serve() {
  for (;;) {
    std::array<int, 3> command{};  // command, and: status (stop) or keep_mixed_mass, threads
    MPI_Bcast(command.data(), 3, MPI_INT, 0, MPI_COMM_WORLD);
    if (command[0] == stop) return command[1];
    const Part source = receive_part(0), target = receive_part(0);
    mpi::DistributedOptions options;
    options.keep_mixed_mass = command[1] != 0;
    options.threads = command[2];
    try {
      const mpi::DistributedSupermesh d = take_part(source, target, options);
      send_vector(pack(d, options.keep_mixed_mass), 0, MPI_DOUBLE);
      const auto candidates = static_cast<long long>(d.candidates);
      MPI_Send(&candidates, 1, MPI_LONG_LONG, 0, 0, MPI_COMM_WORLD);
    } catch (const std::exception&) {
      // Collective: rank 0 has the same error (tetia/mpi.hpp) and reports it.
    }
  }
}

}  // namespace

std::optional<int> mpi_start(int& argc, char**& argv) {
  const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
                        std::getenv("PMIX_RANK") != nullptr;
  if (!launched) return std::nullopt;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started = true;
  if (world_rank() == 0) return std::nullopt;
  const int status = serve();
  MPI_Finalize();
  return status;
}

int mpi_finish(int status) {
  if (!started) return status;
  const std::array<int, 3> command{stop, status, 0};
  std::array<int, 3> sent = command;
  MPI_Bcast(sent.data(), 3, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return status;
}

int mpi_ranks() {
  if (!started) return 1;
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

Supermesh parallel_supermesh(std::shared_ptr<const TetMesh> source, std::shared_ptr<const TetMesh> target,
                             const SupermeshOptions& options, const std::string& partition) {
  check_partition(partition);
  const int ranks = mpi_ranks();
  if (ranks == 1) return supermesh(std::move(source), std::move(target), options);
  const auto t0 = std::chrono::steady_clock::now();
  if (options.progress) options.progress(0, source->num_cells());
  std::vector<Part> s = mpi::parts_of(*source, owners(*source, ranks, partition, false), ranks);
  std::vector<Part> t = mpi::parts_of(*target, owners(*target, ranks, partition, true), ranks);
  const bool with_mass = options.keep_mixed_mass || options.keep_polyhedra;
  std::array<int, 3> command{distributed_supermesh, with_mass ? 1 : 0, options.threads};
  MPI_Bcast(command.data(), 3, MPI_INT, 0, MPI_COMM_WORLD);
  for (int q = 1; q < ranks; ++q) {
    send_part(s[static_cast<std::size_t>(q)], q);
    send_part(t[static_cast<std::size_t>(q)], q);
    s[static_cast<std::size_t>(q)] = Part{};
    t[static_cast<std::size_t>(q)] = Part{};
  }
  mpi::DistributedOptions distributed;
  distributed.keep_mixed_mass = with_mass;
  distributed.threads = options.threads;
  const mpi::DistributedSupermesh own = take_part(s[0], t[0], distributed);
  // Gather: rank 0's pieces, then every other rank's.
  Supermesh out;
  out.source = std::move(source);
  out.target = std::move(target);
  out.candidates = own.candidates;
  std::vector<double> all = pack(own, with_mass);
  for (int q = 1; q < ranks; ++q) {
    const std::vector<double> theirs = receive_vector<double>(q, MPI_DOUBLE);
    all.insert(all.end(), theirs.begin(), theirs.end());
    long long candidates = 0;
    MPI_Recv(&candidates, 1, MPI_LONG_LONG, q, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    out.candidates += static_cast<std::size_t>(candidates);
  }
  const std::size_t stride = with_mass ? 22 : 6;
  const std::size_t count = all.size() / stride;
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto key = [&](std::size_t k) { return std::pair{all[stride * k + 1], all[stride * k]}; };  // exact ids
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  out.pieces.reserve(count);
  for (const std::size_t k : order) {
    const double* p = all.data() + stride * k;
    out.pieces.push_back({static_cast<std::int32_t>(p[0]), static_cast<std::int32_t>(p[1]), p[2], {p[3], p[4], p[5]}});
    if (with_mass) {
      std::array<double, 16> m;
      std::copy_n(p + 6, 16, m.begin());
      out.local_mass.push_back(m);
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (options.progress) options.progress(out.source->num_cells(), out.source->num_cells());
  return out;
}

#endif

}  // namespace tetia::app
