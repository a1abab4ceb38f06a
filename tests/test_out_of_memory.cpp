// Out of memory inside the library's OpenMP regions: the supermesh's threads (their pieces,
// polyhedra, mixed mass matrices and a consumer's numbers grow as they are found) and the VTU
// writer's compression. An exception that left an OpenMP region would terminate the process; the
// library keeps it and throws it after the region, so the caller gets std::bad_alloc and can go
// on. This program's global operator new (tests/support/count_allocations.hpp) fails the n-th
// allocation on request; each path is run failing, in turn, a sample of the allocations an
// unarmed call makes, from the first to the last.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <new>
#include <string>

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

#include "support/count_allocations.hpp"  // the global operator new, counting and failing on request

namespace {
using tetia::testsupport::allocations;
auto& fail_at = tetia::testsupport::fail_allocation;
}  // namespace

namespace {

// Runs `call` once unarmed to count its allocations, then again failing the k-th for `samples`
// values of k spread over them: each run must either finish or throw std::bad_alloc (anything
// else, or a crash, fails the test), and some must throw. Returns the count.
long fail_each_allocation(const std::function<void()>& call, int samples = 60) {
  call();  // warm: OpenMP's threads, lazily built tables
  allocations = 0;
  call();
  const long total = allocations.load();
  EXPECT_GT(total, 0);
  int thrown = 0;
  for (int s = 0; s < samples; ++s) {
    const long k = 1 + total * s / samples;
    allocations = 0;
    fail_at = k;
    try {
      call();
    } catch (const std::bad_alloc&) {
      ++thrown;
    }
    fail_at = -1;
  }
  EXPECT_GT(thrown, samples / 2);
  call();  // and the library still works
  return total;
}

tetia::SupermeshOptions two_threads() {
  tetia::SupermeshOptions o;
  o.threads = 2;
  return o;
}

TEST(OutOfMemory, SupermeshThreadsThrowBadAlloc) {
  const tetia::TetMesh a = tetia::make_kuhn_mesh({4, 4, 4}, {0, 0, 0}, {0.25, 0.25, 0.25});
  const tetia::TetMesh b = tetia::make_kuhn_mesh({5, 5, 5}, {0.01, 0.02, 0.03}, {0.2, 0.2, 0.2});
  for (const bool polyhedra : {false, true})
    for (const bool mass : {false, true})
      for (const auto search : {tetia::CandidateSearch::front, tetia::CandidateSearch::rtree}) {
        tetia::SupermeshOptions o = two_threads();
        o.keep_polyhedra = polyhedra;
        o.keep_mixed_mass = mass;
        o.search = search;
        fail_each_allocation([&] { (void)tetia::supermesh(a, b, o); });
      }
  // Streamed P1 remap: a consumer's numbers in every thread.
  const std::vector<std::vector<double>> fields{std::vector<double>(a.num_nodes(), 1.0)};
  fail_each_allocation([&] { (void)tetia::remap_p1(a, b, fields, two_threads()); });
}

TEST(OutOfMemory, Supermesh2DThreadsThrowBadAlloc) {
  const tetia::TriMesh a = tetia::make_structured_tri_mesh({12, 12}, {0, 0}, {1.0 / 12, 1.0 / 12});
  const tetia::TriMesh b = tetia::make_structured_tri_mesh({13, 13}, {0.01, 0.02}, {1.0 / 13, 1.0 / 13});
  for (const bool polygons : {false, true}) {
    tetia::SupermeshOptions o = two_threads();
    o.keep_polyhedra = polygons;
    fail_each_allocation([&] { (void)tetia::supermesh(a, b, o); });
  }
}

TEST(OutOfMemory, CompressedVtuThrowsBadAlloc) {
  const tetia::TetMesh a = tetia::make_kuhn_mesh({12, 12, 12}, {0, 0, 0}, {1.0 / 12, 1.0 / 12, 1.0 / 12});
  const auto file = std::filesystem::temp_directory_path() / ("tetia_oom_" + std::to_string(::getpid()) + ".vtu");
  tetia::VtuOptions o;
  o.threads = 2;
  fail_each_allocation([&] { tetia::write_vtu(file, a, {}, {}, o); }, 40);
  std::filesystem::remove(file);
}

}  // namespace
