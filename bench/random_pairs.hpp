// bench/random_pairs.hpp -- the benchmark workload: pairs of tetrahedra, each vertex uniform in
// the unit cube [0,1)^3, from std::mt19937_64 with a fixed seed. The same generator (and seed)
// is used by bench_pairs and bench_cgal, so the first N pairs are the same in both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "tetia/geometry.hpp"

namespace tetia::bench {

inline constexpr std::uint64_t kSeed = 20240601;

struct TetPair {
  Tet U, V;
};

inline std::vector<TetPair> random_pairs(std::size_t n, std::uint64_t seed = kSeed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<TetPair> pairs(n);
  for (TetPair& p : pairs) {
    for (Tet* t : {&p.U, &p.V}) {
      for (Vec3& v : *t) {
        v.x = uni(rng);
        v.y = uni(rng);
        v.z = uni(rng);
      }
    }
  }
  return pairs;
}

}  // namespace tetia::bench
