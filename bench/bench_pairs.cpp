// bench/bench_pairs.cpp -- pairs per second, one thread, over 10^6 random pairs of tetrahedra
// (four uniform points in the unit cube per tetrahedron, fixed seed; see random_pairs.hpp).
//
// Every benchmark iteration loops once over all pairs, so items_per_second is pairs per second.
// Methods: tetia::intersection_volume, tetia::intersect (full polyhedron, volume read back),
// tetia::intersection_moments, and the double-precision baselines clip_volume
// (Sutherland-Hodgman) and pang_volume (PANG-style).
//
// Usage: bench_pairs [--pairs=N] [--no-check] [Google Benchmark flags]
//   e.g. bench_pairs --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// --pairs=N changes the workload size (default 10^6); --no-check skips the agreement check
// (for profiling one method, e.g. under valgrind --tool=callgrind with --benchmark_filter).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pairs_bench.hpp"
#include "random_pairs.hpp"
#include "tetia/baselines.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

using tetia::bench::TetPair;
using tetia::bench::run_over_pairs;

constexpr int kIterations = tetia::bench::kPassesPerBenchmark;

void BM_intersection_volume(benchmark::State& state) {
  run_over_pairs<TetPair>(state, [](const TetPair& p) { return tetia::intersection_volume(p.U, p.V); });
}

void BM_intersect(benchmark::State& state) {
  run_over_pairs<TetPair>(state, [](const TetPair& p) {
    const tetia::Polyhedron poly = tetia::intersect(p.U, p.V);
    return poly.volume() + static_cast<double>(poly.num_corners());
  });
}

void BM_intersection_moments(benchmark::State& state) {
  run_over_pairs<TetPair>(state, [](const TetPair& p) {
    const tetia::Moments m = tetia::intersection_moments(p.U, p.V);
    return m.volume + m.first.x + m.first.y + m.first.z;
  });
}

void BM_clip(benchmark::State& state) {
  run_over_pairs<TetPair>(state, [](const TetPair& p) { return tetia::baselines::clip_volume(p.U, p.V); });
}

void BM_pang(benchmark::State& state) {
  run_over_pairs<TetPair>(state, [](const TetPair& p) { return tetia::baselines::pang_volume(p.U, p.V); });
}

BENCHMARK(BM_intersection_volume)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersect)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersection_moments)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_clip)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_pang)->Unit(benchmark::kMillisecond)->Iterations(kIterations);

// Outside timing: the methods must agree on the workload, or the speed figures mean nothing.
// Returns false when intersection_volume and clip_volume disagree by more than 1e-9 relative.
bool check_agreement() {
  const std::vector<TetPair>& ps = tetia::bench::workload<TetPair>();
  tetia::bench::Agreement a{"volume", {"intersection_volume", "intersect", "clip_volume", "pang_volume"},
                            {0.0, 0.0, 0.0, 0.0}, 0.0, 0, ps.size(), tetia::bench::kSeed};
  for (const TetPair& p : ps) {
    a.add(tetia::intersection_volume(p.U, p.V), tetia::intersect(p.U, p.V).volume(), tetia::baselines::clip_volume(p.U, p.V),
          tetia::baselines::pang_volume(p.U, p.V));
  }
  return tetia::bench::report_agreement(a);
}

std::vector<TetPair> make_pairs(std::size_t n) { return tetia::bench::random_pairs(n); }

}  // namespace

int main(int argc, char** argv) { return tetia::bench::pairs_main<TetPair>(argc, argv, make_pairs, check_agreement); }
