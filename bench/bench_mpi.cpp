// bench/bench_mpi.cpp -- strong scaling of the distributed supermesh (tetia/mpi.hpp) against
// the one-process supermesh with threads, for the table in docs/benchmarks.md.
//
//   bench_mpi [N] [serial]         under mpiexec -np P (OMP_NUM_THREADS=1 for pure MPI)
//
// Meshes: Kuhn meshes of N^3 cubes (6 N^3 tetrahedra; N = 55 gives 998,250), the source on the
// unit cube and the target the same shifted by (0.31, 0.17, 0.23) cubes, so that nothing
// matches. Every rank builds both whole meshes (the benchmark's own cost, not timed), takes its
// Morton part of each and frees them; peak memory ("peak_mib") is then measured from there
// (Linux's VmHWM, reset with /proc/self/clear_refs), so it is what the call costs. Prints one JSON line on rank 0: ranks, threads, cells, pieces, the
// distributed call's seconds (the slowest rank), the source cells sent (all ranks, copies
// counted) over the source's cells, bytes sent (all ranks) and per rank at most, the boxes each
// rank holds, and each rank's part sizes; with "serial", instead tetia::supermesh on the whole
// meshes in this one process (front search), for the same meshes.
#include <malloc.h>
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tetia/mesh.hpp"
#include "tetia/mpi.hpp"
#include "tetia/supermesh.hpp"

namespace {

/// The process's peak resident memory in MiB (VmHWM), or -1.
double peak_mib() {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return -1.0;
  char line[256];
  double kib = -1.0;
  while (std::fgets(line, sizeof line, f) != nullptr)
    if (std::strncmp(line, "VmHWM:", 6) == 0) kib = std::atof(line + 6);
  std::fclose(f);
  return kib / 1024.0;
}

/// Starts VmHWM afresh from the current resident size (Linux: clear_refs 5), so that the peak
/// read after a call is that call's (with what the process holds before it).
void reset_peak() {
  if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", f);
    std::fclose(f);
  }
}

double part_mib(const tetia::mpi::OwnedMeshPart& p) {
  return double(p.coordinates.size() * 8 + p.cells.size() * 4 + p.cell_ids.size() * 8 + p.node_ids.size() * 8) /
         (1024.0 * 1024.0);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int n = argc > 1 ? std::atoi(argv[1]) : 55;
  const bool serial = argc > 2 && std::string(argv[2]) == "serial";
  const double h = 1.0 / n;
  const int threads = omp_get_max_threads();
  if (serial) {
    const tetia::TetMesh source = tetia::make_kuhn_mesh({n, n, n}, {0, 0, 0}, {h, h, h});
    const tetia::TetMesh target = tetia::make_kuhn_mesh({n, n, n}, {0.31 * h, 0.17 * h, 0.23 * h}, {h, h, h});
    reset_peak();
    if (rank == 0) {
      const auto t0 = std::chrono::steady_clock::now();
      const tetia::Supermesh s = tetia::supermesh(source, target);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("{\"mode\": \"threads\", \"threads\": %d, \"cells\": %zu, \"pieces\": %zu, \"seconds\": %.3f, "
                  "\"peak_mib\": %.0f}\n",
                  threads, source.num_cells(), s.pieces.size(), seconds, peak_mib());
    }
    MPI_Finalize();
    return 0;
  }
  // The whole meshes only long enough to cut this rank's parts: the peak below is the call's.
  tetia::mpi::OwnedMeshPart s, t;
  std::size_t cells = 0;
  {
    const tetia::TetMesh source = tetia::make_kuhn_mesh({n, n, n}, {0, 0, 0}, {h, h, h});
    const tetia::TetMesh target = tetia::make_kuhn_mesh({n, n, n}, {0.31 * h, 0.17 * h, 0.23 * h}, {h, h, h});
    cells = source.num_cells();
    s = std::move(tetia::mpi::parts_of(source, tetia::mpi::morton_partition(source, ranks), ranks)[static_cast<std::size_t>(rank)]);
    t = std::move(tetia::mpi::parts_of(target, tetia::mpi::morton_partition(target, ranks), ranks)[static_cast<std::size_t>(rank)]);
  }
  malloc_trim(0);
  reset_peak();
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  const tetia::mpi::DistributedSupermesh d = tetia::mpi::supermesh(s.view(), t.view(), MPI_COMM_WORLD);
  const double mine = MPI_Wtime() - t0;
  double slowest = 0.0;
  MPI_Reduce(&mine, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  const unsigned long long local[4] = {d.pieces.size(), d.cells_sent, d.bytes_sent, d.cells_received};
  unsigned long long total[4] = {}, most[4] = {};
  MPI_Reduce(local, total, 4, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  MPI_Reduce(local, most, 4, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, MPI_COMM_WORLD);
  const double parts = part_mib(s) + part_mib(t);
  double parts_most = 0.0, peak_most = 0.0;
  const double peak = peak_mib();
  MPI_Reduce(&parts, &parts_most, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  MPI_Reduce(&peak, &peak_most, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  if (rank == 0)
    std::printf("{\"mode\": \"ranks\", \"ranks\": %d, \"threads\": %d, \"cells\": %zu, \"pieces\": %llu, "
                "\"seconds\": %.3f, \"cells_sent_per_source_cell\": %.4f, \"bytes_sent\": %llu, "
                "\"bytes_sent_most\": %llu, \"cells_received_most\": %llu, \"boxes\": %zu, "
                "\"part_mib_most\": %.1f, \"peak_mib_most\": %.0f}\n",
                ranks, threads, cells, total[0], slowest, double(total[1]) / double(cells),
                total[2], most[2], most[3], d.boxes_received, parts_most, peak_most);
  MPI_Finalize();
  return 0;
}
