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
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "random_pairs.hpp"
#include "tetia/baselines.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

using tetia::bench::TetPair;

std::vector<TetPair>& pairs() {
  static std::vector<TetPair> p;
  return p;
}

constexpr int kIterations = 3;  // each iteration is one pass over all pairs

template <class F>
void run_over_pairs(benchmark::State& state, F&& f) {
  const std::vector<TetPair>& ps = pairs();
  for (auto _ : state) {
    double acc = 0.0;
    for (const TetPair& p : ps) acc += f(p);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(ps.size()));
}

void BM_intersection_volume(benchmark::State& state) {
  run_over_pairs(state, [](const TetPair& p) { return tetia::intersection_volume(p.U, p.V); });
}

void BM_intersect(benchmark::State& state) {
  run_over_pairs(state, [](const TetPair& p) {
    const tetia::Polyhedron poly = tetia::intersect(p.U, p.V);
    return poly.volume() + static_cast<double>(poly.num_corners());
  });
}

void BM_intersection_moments(benchmark::State& state) {
  run_over_pairs(state, [](const TetPair& p) {
    const tetia::Moments m = tetia::intersection_moments(p.U, p.V);
    return m.volume + m.first.x + m.first.y + m.first.z;
  });
}

void BM_clip(benchmark::State& state) {
  run_over_pairs(state, [](const TetPair& p) { return tetia::baselines::clip_volume(p.U, p.V); });
}

void BM_pang(benchmark::State& state) {
  run_over_pairs(state, [](const TetPair& p) { return tetia::baselines::pang_volume(p.U, p.V); });
}

BENCHMARK(BM_intersection_volume)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersect)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersection_moments)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_clip)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_pang)->Unit(benchmark::kMillisecond)->Iterations(kIterations);

// Outside timing: the methods must agree on the workload, or the speed figures mean nothing.
// Returns false when intersection_volume and clip_volume disagree by more than 1e-9 relative.
bool check_agreement() {
  const std::vector<TetPair>& ps = pairs();
  double sum_vol = 0.0, sum_intersect = 0.0, sum_clip = 0.0, sum_pang = 0.0;
  double max_abs_diff = 0.0;
  long nonempty = 0;
  for (const TetPair& p : ps) {
    const double v = tetia::intersection_volume(p.U, p.V);
    const double c = tetia::baselines::clip_volume(p.U, p.V);
    sum_vol += v;
    sum_intersect += tetia::intersect(p.U, p.V).volume();
    sum_clip += c;
    sum_pang += tetia::baselines::pang_volume(p.U, p.V);
    max_abs_diff = std::max(max_abs_diff, std::abs(v - c));
    if (v > 0.0) ++nonempty;
  }
  const auto rel = [](double a, double b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
  };
  const double rel_clip = rel(sum_vol, sum_clip);
  std::printf("pairs: %zu, seed %llu, non-empty intersections: %ld (%.2f%%)\n", ps.size(),
              static_cast<unsigned long long>(tetia::bench::kSeed), nonempty,
              100.0 * static_cast<double>(nonempty) / static_cast<double>(ps.size()));
  std::printf("total volume: intersection_volume %.17g\n", sum_vol);
  std::printf("              intersect          %.17g (rel. diff %.3g)\n", sum_intersect,
              rel(sum_vol, sum_intersect));
  std::printf("              clip_volume        %.17g (rel. diff %.3g)\n", sum_clip, rel_clip);
  std::printf("              pang_volume        %.17g (rel. diff %.3g)\n", sum_pang,
              rel(sum_vol, sum_pang));
  std::printf("max |intersection_volume - clip_volume| over pairs: %.3g\n", max_abs_diff);
  const bool ok = rel_clip <= 1e-9;
  std::printf("check intersection_volume vs clip_volume total, 1e-9 relative: %s\n\n",
              ok ? "OK" : "FAILED");
  std::fflush(stdout);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 1000000;
  bool check = true;
  // Our own flag, removed before Google Benchmark sees the arguments.
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--pairs=", 8) == 0) {
      n = std::strtoull(argv[i] + 8, nullptr, 10);
    } else if (std::strcmp(argv[i], "--no-check") == 0) {
      check = false;
    } else {
      argv[out++] = argv[i];
    }
  }
  argc = out;
  if (n == 0) {
    std::fprintf(stderr, "--pairs must be positive\n");
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  pairs() = tetia::bench::random_pairs(n);
  const bool ok = !check || check_agreement();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return ok ? 0 : 1;
}
