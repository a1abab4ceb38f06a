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
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

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

std::vector<TriPair>& pairs() {
  static std::vector<TriPair> p;
  return p;
}

constexpr int kIterations = 3;  // each iteration is one pass over all pairs

template <class F>
void run_over_pairs(benchmark::State& state, F&& f) {
  const std::vector<TriPair>& ps = pairs();
  for (auto _ : state) {
    double acc = 0.0;
    for (const TriPair& p : ps) acc += f(p);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(ps.size()));
}

void BM_intersection_area(benchmark::State& state) {
  run_over_pairs(state, [](const TriPair& p) { return tetia::intersection_area(p.A, p.B); });
}

void BM_intersect(benchmark::State& state) {
  run_over_pairs(state, [](const TriPair& p) {
    const tetia::Polygon poly = tetia::intersect(p.A, p.B);
    return poly.area() + static_cast<double>(poly.num_corners());
  });
}

void BM_intersection_moments(benchmark::State& state) {
  run_over_pairs(state, [](const TriPair& p) {
    const tetia::Moments2 m = tetia::intersection_moments(p.A, p.B);
    return m.area + m.first.x + m.first.y;
  });
}

void BM_clip_area(benchmark::State& state) {
  run_over_pairs(state, [](const TriPair& p) { return tetia::baselines::clip_area(p.A, p.B); });
}

void BM_pang_area(benchmark::State& state) {
  run_over_pairs(state, [](const TriPair& p) { return tetia::baselines::pang_area(p.A, p.B); });
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
  const std::vector<TriPair>& ps = pairs();
  double sum_area = 0.0, sum_intersect = 0.0, sum_clip = 0.0, sum_pang = 0.0;
  double max_abs_diff = 0.0;
  long nonempty = 0;
  for (const TriPair& p : ps) {
    const double a = tetia::intersection_area(p.A, p.B);
    const double c = tetia::baselines::clip_area(p.A, p.B);
    sum_area += a;
    sum_intersect += tetia::intersect(p.A, p.B).area();
    sum_clip += c;
    sum_pang += tetia::baselines::pang_area(p.A, p.B);
    max_abs_diff = std::max(max_abs_diff, std::abs(a - c));
    if (a > 0.0) ++nonempty;
  }
  const auto rel = [](double a, double b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
  };
  const double rel_clip = rel(sum_area, sum_clip);
  std::printf("pairs: %zu, seed %llu, non-empty intersections: %ld (%.2f%%)\n", ps.size(),
              static_cast<unsigned long long>(kSeed), nonempty,
              100.0 * static_cast<double>(nonempty) / static_cast<double>(ps.size()));
  std::printf("total area: intersection_area %.17g\n", sum_area);
  std::printf("            intersect         %.17g (rel. diff %.3g)\n", sum_intersect,
              rel(sum_area, sum_intersect));
  std::printf("            clip_area         %.17g (rel. diff %.3g)\n", sum_clip, rel_clip);
  std::printf("            pang_area         %.17g (rel. diff %.3g)\n", sum_pang,
              rel(sum_area, sum_pang));
  std::printf("max |intersection_area - clip_area| over pairs: %.3g\n", max_abs_diff);
  const bool ok = rel_clip <= 1e-9;
  std::printf("check intersection_area vs clip_area total, 1e-9 relative: %s\n\n",
              ok ? "OK" : "FAILED");
  std::fflush(stdout);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 1000000;
  bool check = true;
  // Our own flags, removed before Google Benchmark sees the arguments.
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
  pairs() = make_pairs(n);
  const bool ok = !check || check_agreement();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return ok ? 0 : 1;
}
