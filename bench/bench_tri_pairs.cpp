// bench/bench_tri_pairs.cpp -- pairs per second, one thread, over 10^6 random pairs of triangles
// (three uniform points in the unit square [0,1)^2 per triangle, std::mt19937_64 with a fixed
// seed): the 2D counterpart of bench_pairs.
//
// Every benchmark iteration loops once over all pairs, so items_per_second is pairs per second.
// Methods: tetia::intersection_area, tetia::intersect (full polygon: corners, labels,
// barycentric coordinates; area and corner count read back), tetia::intersection_moments, and
// the double-precision baselines clip_area (Sutherland-Hodgman) and pang_area (PANG-style).
//
// Usage: bench_tri_pairs [--pairs=N] [--no-check] [Google Benchmark flags]
//   e.g. bench_tri_pairs --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// --pairs=N changes the workload size (default 10^6); --no-check skips the agreement check.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "pairs_bench.hpp"

#include "tetia/baselines.hpp"
#include "tetia/tri_intersection.hpp"

namespace {

constexpr std::uint64_t kSeed = 20240602;

struct TriPair {
  tetia::Triangle A, B;
};

std::vector<TriPair> make_pairs(std::size_t n) {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<TriPair> pairs(n);
  for (TriPair& p : pairs) {
    for (tetia::Triangle* t : {&p.A, &p.B}) {
      for (tetia::Vec2& v : *t) {
        v.x = uni(rng);
        v.y = uni(rng);
      }
    }
  }
  return pairs;
}

using tetia::bench::run_over_pairs;

constexpr int kIterations = tetia::bench::kPassesPerBenchmark;

void BM_intersection_area(benchmark::State& state) {
  run_over_pairs<TriPair>(state, [](const TriPair& p) { return tetia::intersection_area(p.A, p.B); });
}

void BM_intersect(benchmark::State& state) {
  run_over_pairs<TriPair>(state, [](const TriPair& p) {
    const tetia::Polygon poly = tetia::intersect(p.A, p.B);
    return poly.area() + static_cast<double>(poly.num_corners());
  });
}

void BM_intersection_moments(benchmark::State& state) {
  run_over_pairs<TriPair>(state, [](const TriPair& p) {
    const tetia::Moments2 m = tetia::intersection_moments(p.A, p.B);
    return m.area + m.first.x + m.first.y;
  });
}

void BM_clip_area(benchmark::State& state) {
  run_over_pairs<TriPair>(state, [](const TriPair& p) { return tetia::baselines::clip_area(p.A, p.B); });
}

void BM_pang_area(benchmark::State& state) {
  run_over_pairs<TriPair>(state, [](const TriPair& p) { return tetia::baselines::pang_area(p.A, p.B); });
}

BENCHMARK(BM_intersection_area)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersect)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_intersection_moments)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_clip_area)->Unit(benchmark::kMillisecond)->Iterations(kIterations);
BENCHMARK(BM_pang_area)->Unit(benchmark::kMillisecond)->Iterations(kIterations);

// Outside timing: the methods must agree on the workload, or the speed figures mean nothing.
// Returns false when intersection_area and clip_area disagree by more than 1e-9 relative in
// total.
bool check_agreement() {
  const std::vector<TriPair>& ps = tetia::bench::workload<TriPair>();
  tetia::bench::Agreement a{"area", {"intersection_area", "intersect", "clip_area", "pang_area"},
                            {0.0, 0.0, 0.0, 0.0}, 0.0, 0, ps.size(), kSeed};
  for (const TriPair& p : ps) {
    a.add(tetia::intersection_area(p.A, p.B), tetia::intersect(p.A, p.B).area(), tetia::baselines::clip_area(p.A, p.B),
          tetia::baselines::pang_area(p.A, p.B));
  }
  return tetia::bench::report_agreement(a);
}

}  // namespace

int main(int argc, char** argv) { return tetia::bench::pairs_main<TriPair>(argc, argv, make_pairs, check_agreement); }
