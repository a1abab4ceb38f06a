// bench/kernel_paths.cpp -- which way the 3D kernel takes on a workload: the double result
// certified by its error estimate, refined in the smaller tetrahedron's frame
// (IntersectionStats::refined), computed exactly (exact_fallbacks), rescaled, retried. The
// fallback rates in docs/architecture.md ("Accuracy relative to the smaller tetrahedron").
//
//   Part "random": the benchmark pairs of bench_pairs (random_pairs.hpp), --pairs=N (10^6).
//   Part "pyramid": every pair of cells of libsupermesh's pyramid (33,901 cells) and cube
//     (41,063 cells) meshes (../shared/extdata, skipped if absent) whose bounding boxes overlap:
//     a superset of the pairs the supermesh's front tests.
//
// Usage: kernel_paths [--pairs=N] [--extdata=DIR]
// Prints one line per part; exits 1 if the volumes of intersect() with statistics and
// intersection_volume() differ for any pair (the bitwise contract).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "random_pairs.hpp"
#include "tetia/io.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

struct Tally {
  tetia::IntersectionStats stats;
  long long pairs = 0, nonempty = 0, mismatches = 0;

  void add(const tetia::Tet& U, const tetia::Tet& V) {
    const tetia::Polyhedron P = tetia::intersect(U, V, &stats);
    if (P.volume() != tetia::intersection_volume(U, V)) ++mismatches;
    ++pairs;
    nonempty += P.volume() > 0.0;
  }

  void print(const char* name) const {
    const auto pct = [&](long long n) { return 100.0 * double(n) / double(std::max(pairs, 1LL)); };
    std::printf("%-8s %lld pairs (%lld non-empty): refined %lld (%.4f %%), exact %lld (%.4f %%), rescaled %lld, "
                "retries %lld, entry points disagree %lld\n",
                name, pairs, nonempty, (long long)stats.refined, pct(stats.refined), (long long)stats.exact_fallbacks,
                pct(stats.exact_fallbacks), (long long)stats.rescaled, (long long)stats.retries, mismatches);
  }
};

struct Box {
  tetia::Vec3 lo, hi;
};

Box box_of(const tetia::Tet& t) {
  Box b{t[0], t[0]};
  for (const tetia::Vec3& p : t) {
    b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
    b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
  }
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 1000000;
  std::filesystem::path extdata = std::filesystem::path(TETIA_SHARED_DIR) / "extdata";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--pairs=", 0) == 0) n = std::strtoull(a.c_str() + 8, nullptr, 10);
    else if (a.rfind("--extdata=", 0) == 0) extdata = a.substr(10);
    else {
      std::fprintf(stderr, "kernel_paths: unknown option %s\nusage: kernel_paths [--pairs=N] [--extdata=DIR]\n", a.c_str());
      return 2;
    }
  }
  bool ok = true;
  {
    Tally t;
    for (const auto& p : tetia::bench::random_pairs(n)) t.add(p.U, p.V);
    t.print("random");
    ok &= t.mismatches == 0;
  }
  const auto pyramid = extdata / "lsm_pyramid_0_05.msh", cube = extdata / "lsm_cube_0_05.msh";
  if (!std::filesystem::exists(pyramid) || !std::filesystem::exists(cube)) {
    std::printf("pyramid  skipped (%s not found)\n", extdata.string().c_str());
    return ok ? 0 : 1;
  }
  const tetia::TetMesh S = tetia::read_mesh(pyramid), T = tetia::read_mesh(cube);
  // Target boxes sorted by their lower x; for each source cell, the targets whose box overlaps.
  std::vector<Box> tb(T.num_cells());
  std::vector<std::size_t> order(T.num_cells());
  for (std::size_t j = 0; j < T.num_cells(); ++j) tb[j] = box_of(T.cell(j)), order[j] = j;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tb[a].lo.x < tb[b].lo.x; });
  double max_width = 0.0;
  for (const Box& b : tb) max_width = std::max(max_width, b.hi.x - b.lo.x);
  std::vector<double> lo_x(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) lo_x[k] = tb[order[k]].lo.x;
  Tally t;
  for (std::size_t i = 0; i < S.num_cells(); ++i) {
    const tetia::Tet U = S.cell(i);
    const Box b = box_of(U);
    const auto first = std::lower_bound(lo_x.begin(), lo_x.end(), b.lo.x - max_width) - lo_x.begin();
    for (auto k = std::size_t(first); k < order.size() && lo_x[k] <= b.hi.x; ++k) {
      const Box& c = tb[order[k]];
      if (c.hi.x < b.lo.x || c.lo.y > b.hi.y || c.hi.y < b.lo.y || c.lo.z > b.hi.z || c.hi.z < b.lo.z) continue;
      t.add(U, T.cell(order[k]));
    }
  }
  t.print("pyramid");
  ok &= t.mismatches == 0;
  return ok ? 0 : 1;
}
