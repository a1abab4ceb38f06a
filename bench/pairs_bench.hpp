// bench/pairs_bench.hpp -- what bench_pairs (tetrahedra) and bench_tri_pairs (triangles) share:
// the timed loop over all pairs, the printout of the agreement check, and main's own flags.
//
// Each program keeps its workload, its benchmarks (which method is called per pair) and the
// per-pair sums of its agreement check. The printed text is as before this header, except that
// bench_pairs' totals are now aligned in one column.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace tetia::bench {

inline constexpr int kPassesPerBenchmark = 3;  // each iteration is one pass over all pairs

/// The workload, generated once before timing.
template <class Pair>
std::vector<Pair>& workload() {
  static std::vector<Pair> p;
  return p;
}

/// One benchmark iteration is one pass over all pairs, so items_per_second is pairs per second.
/// Every result is added into an accumulator kept alive with DoNotOptimize.
template <class Pair, class F>
void run_over_pairs(benchmark::State& state, F&& f) {
  const std::vector<Pair>& ps = workload<Pair>();
  for (auto _ : state) {
    double acc = 0.0;
    for (const Pair& p : ps) acc += f(p);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(ps.size()));
}

/// The agreement check's totals: sums[0] is tetia's fast path (names[0], e.g.
/// "intersection_volume"), then intersect, the clipper and PANG; max_abs_diff is the largest
/// per-pair difference between the fast path and the clipper.
struct Agreement {
  const char* measure;  // "volume" or "area"
  const char* names[4];
  double sums[4];
  double max_abs_diff;
  long nonempty;
  std::size_t pairs;
  std::uint64_t seed;

  /// Adds one pair: the fast path, intersect, the clipper and PANG, in that order.
  void add(double fast, double full, double clip, double pang) {
    sums[0] += fast;
    sums[1] += full;
    sums[2] += clip;
    sums[3] += pang;
    max_abs_diff = std::max(max_abs_diff, std::abs(fast - clip));
    if (fast > 0.0) ++nonempty;
  }
};

/// Prints the totals; returns false when the fast path and the clipper disagree by more than
/// 1e-9 relative in total.
inline bool report_agreement(const Agreement& a) {
  const auto rel = [](double x, double y) { return std::abs(x - y) / std::max(std::abs(x), std::abs(y)); };
  const double rel_clip = rel(a.sums[0], a.sums[2]);
  std::printf("pairs: %zu, seed %llu, non-empty intersections: %ld (%.2f%%)\n", a.pairs,
              static_cast<unsigned long long>(a.seed), a.nonempty,
              100.0 * static_cast<double>(a.nonempty) / static_cast<double>(a.pairs));
  const std::string head = std::string("total ") + a.measure + ": ";
  const int width = static_cast<int>(std::strlen(a.names[0]));
  std::printf("%s%s %.17g\n", head.c_str(), a.names[0], a.sums[0]);
  for (int k = 1; k < 4; ++k)
    std::printf("%*s%-*s %.17g (rel. diff %.3g)\n", static_cast<int>(head.size()), "", width, a.names[k], a.sums[k],
                rel(a.sums[0], a.sums[k]));
  std::printf("max |%s - %s| over pairs: %.3g\n", a.names[0], a.names[2], a.max_abs_diff);
  const bool ok = rel_clip <= 1e-9;
  std::printf("check %s vs %s total, 1e-9 relative: %s\n\n", a.names[0], a.names[2], ok ? "OK" : "FAILED");
  std::fflush(stdout);
  return ok;
}

/// main for both programs: their own flags --pairs=N (default 10^6) and --no-check are removed
/// before Google Benchmark sees the arguments; then the workload is made, checked unless
/// --no-check, and timed. Exit status 1 if the check failed, 2 for a bad --pairs.
template <class Pair>
int pairs_main(int argc, char** argv, std::vector<Pair> (*make)(std::size_t), bool (*check)()) {
  std::size_t n = 1000000;
  bool run_check = true;
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--pairs=", 8) == 0) {
      n = std::strtoull(argv[i] + 8, nullptr, 10);
    } else if (std::strcmp(argv[i], "--no-check") == 0) {
      run_check = false;
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
  workload<Pair>() = make(n);
  const bool ok = !run_check || check();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return ok ? 0 : 1;
}

}  // namespace tetia::bench
