// bench/bench_cgal.cpp -- what a CGAL user would do for the same workload as bench_pairs.
//
// CGAL 5.5 has no construction for the intersection of two Tetrahedron_3 (the header
// Intersections_3/Tetrahedron_3_Tetrahedron_3.h defines do_intersect only). So each
// tetrahedron is made a closed triangle mesh (CGAL::Surface_mesh, CGAL::make_tetrahedron,
// outward oriented) and:
//   - BM_cgal_clip_epeck: PMP::clip(U, V, clip_volume(true)) (= corefine_and_compute_intersection)
//     with Exact_predicates_exact_constructions_kernel, then PMP::volume, to_double;
//   - BM_cgal_clip_epick: the same with Exact_predicates_inexact_constructions_kernel;
//   - BM_cgal_nef: Nef_polyhedron_3 intersection (EPECK), converted back to a
//     Surface_mesh for PMP::volume.
// Mesh construction is inside the timed loop (it is part of what a user pays per pair).
// The pairs are the first N of bench_pairs' workload (same generator and seed).
//
// Build with -ffp-contract=off (the project's global flags): CGAL's interval filters rely on
// every operation being rounded once; a fused multiply-add breaks that, and CGAL's clipping has
// been reported to hang under -march=native without -ffp-contract=off (not reproduced on this
// sample; see docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/convert_nef_polyhedron_to_polygon_mesh.h>
#include <CGAL/boost/graph/generators.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "random_pairs.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using tetia::bench::TetPair;
using EPECK = CGAL::Exact_predicates_exact_constructions_kernel;
using EPICK = CGAL::Exact_predicates_inexact_constructions_kernel;

constexpr std::size_t kClipPairs = 2000;
constexpr std::size_t kNefPairs = 200;

const std::vector<TetPair>& pairs() {
  static const std::vector<TetPair> p = tetia::bench::random_pairs(kClipPairs);
  return p;
}

template <class K>
CGAL::Surface_mesh<typename K::Point_3> tet_mesh(const tetia::Tet& t) {
  using P = typename K::Point_3;
  P p[4];
  for (int i = 0; i < 4; ++i) p[i] = P(t[i].x, t[i].y, t[i].z);
  // make_tetrahedron gives an outward-oriented surface for a positively oriented vertex order.
  if (CGAL::orientation(p[0], p[1], p[2], p[3]) == CGAL::NEGATIVE) std::swap(p[1], p[2]);
  CGAL::Surface_mesh<P> m;
  CGAL::make_tetrahedron(p[0], p[1], p[2], p[3], m);
  return m;
}

// Volume of U ∩ V by corefinement clipping. Returns NaN when CGAL reports failure.
template <class K>
double clip_volume(const tetia::Tet& U, const tetia::Tet& V) {
  auto u = tet_mesh<K>(U);
  auto v = tet_mesh<K>(V);
  if (!PMP::clip(u, v, CGAL::parameters::clip_volume(true))) return std::nan("");
  if (u.is_empty()) return 0.0;
  return CGAL::to_double(PMP::volume(u));
}

double nef_volume(const tetia::Tet& U, const tetia::Tet& V) {
  using Nef = CGAL::Nef_polyhedron_3<EPECK>;
  auto u = tet_mesh<EPECK>(U);
  auto v = tet_mesh<EPECK>(V);
  Nef nu(u), nv(v);
  Nef w = nu * nv;
  if (w.is_empty()) return 0.0;
  CGAL::Surface_mesh<EPECK::Point_3> out;
  CGAL::convert_nef_polyhedron_to_polygon_mesh(w, out, /*triangulate_all_faces=*/true);
  if (out.is_empty()) return 0.0;  // lower-dimensional intersection
  return CGAL::to_double(PMP::volume(out));
}

template <class F>
void run(benchmark::State& state, std::size_t n, F&& f) {
  const auto& ps = pairs();
  n = std::min(n, ps.size());
  for (auto _ : state) {
    double acc = 0.0;
    for (std::size_t i = 0; i < n; ++i) acc += f(ps[i].U, ps[i].V);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}

void BM_tetia_intersection_volume(benchmark::State& state) {
  run(state, kClipPairs, [](const tetia::Tet& U, const tetia::Tet& V) {
    return tetia::intersection_volume(U, V);
  });
}
void BM_cgal_clip_epeck(benchmark::State& state) {
  run(state, kClipPairs, clip_volume<EPECK>);
}
void BM_cgal_clip_epick(benchmark::State& state) {
  run(state, kClipPairs, clip_volume<EPICK>);
}
void BM_cgal_nef(benchmark::State& state) { run(state, kNefPairs, nef_volume); }

BENCHMARK(BM_tetia_intersection_volume)->Unit(benchmark::kMillisecond)->Iterations(50);
BENCHMARK(BM_cgal_clip_epeck)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_cgal_clip_epick)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_cgal_nef)->Unit(benchmark::kMillisecond)->Iterations(1);

// Outside timing: does CGAL compute the same volumes as tetia on the sample?
void check(const char* name, std::size_t n, double (*f)(const tetia::Tet&, const tetia::Tet&)) {
  const auto& ps = pairs();
  n = std::min(n, ps.size());
  double sum_t = 0.0, sum_c = 0.0, max_diff = 0.0;
  long failures = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = tetia::intersection_volume(ps[i].U, ps[i].V);
    double c = 0.0;
    try {
      c = f(ps[i].U, ps[i].V);
    } catch (const std::exception&) {
      c = std::nan("");
    }
    if (!std::isfinite(c)) {
      ++failures;
      continue;
    }
    sum_t += t;
    sum_c += c;
    max_diff = std::max(max_diff, std::abs(t - c));
  }
  std::printf("%-16s %zu pairs: total volume %.17g vs tetia %.17g, max |diff| %.3g, failures %ld\n",
              name, n, sum_c, sum_t, max_diff, failures);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  {  // make_tetrahedron's orientation convention, checked once.
    auto m = tet_mesh<EPECK>(pairs()[0].U);
    std::printf("tetrahedron mesh outward oriented: %s\n",
                PMP::is_outward_oriented(m) ? "yes" : "NO");
  }
  check("clip EPECK", kClipPairs, clip_volume<EPECK>);
  check("clip EPICK", kClipPairs, clip_volume<EPICK>);
  check("Nef EPECK", kNefPairs, nef_volume);
  std::fflush(stdout);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
