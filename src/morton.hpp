// src/morton.hpp -- Morton codes of points in a box, and the order of cells by their codes
// (internal to the library: the supermesh's visiting and storage orders, the MPI partition and
// target boxes; also used by bench/bench_supermesh.cpp to presort meshes).
//
// Contract: morton_code<d>(centre, lo, hi) quantizes each coordinate of `centre` to 63 / d bits
// (21 in 3D, 31 in 2D) of its place in [lo, hi] (clamped; a flat axis gives 0) and interleaves
// them, axis 0 in the highest bit of each level. sort_by_key sorts (code, index) pairs by code,
// stably, in linear time. Callers compute the centres their own way (the centroid of a cell,
// summed in the order they document), so that each keeps its order bit for bit.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace tetia::detail {

// The low 63 / d bits of x, spread to every d-th bit (bit b to bit d * b): with the axes
// shifted by d - 1 - k and or-ed, the Morton code (axis 0 first at each level).
template <int d>
constexpr std::uint64_t spread_bits(std::uint64_t x) {
  if constexpr (d == 3) {
    x &= 0x1FFFFFu;
    x = (x | x << 32) & 0x1F00000000FFFFull;
    x = (x | x << 16) & 0x1F0000FF0000FFull;
    x = (x | x << 8) & 0x100F00F00F00F00Full;
    x = (x | x << 4) & 0x10C30C30C30C30C3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
  } else {
    x &= 0x7FFFFFFFu;
    x = (x | x << 16) & 0x0000FFFF0000FFFFull;
    x = (x | x << 8) & 0x00FF00FF00FF00FFull;
    x = (x | x << 4) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | x << 2) & 0x3333333333333333ull;
    x = (x | x << 1) & 0x5555555555555555ull;
  }
  return x;
}
static_assert(spread_bits<3>(0x1FFFFF) == 0x1249249249249249ull && spread_bits<3>(0b101) == 0b1000001);
static_assert(spread_bits<2>(0x7FFFFFFF) == 0x1555555555555555ull && spread_bits<2>(0b11) == 0b101);

template <int d>
std::uint64_t morton_code(const double* centre, const double* lo, const double* hi) {
  constexpr int bits = 63 / d;
  constexpr double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  std::uint64_t key = 0;
  for (int k = 0; k < d; ++k) {
    const double extent = hi[k] - lo[k];
    const double f = extent > 0.0 ? (centre[k] - lo[k]) / extent : 0.0;
    const auto q = static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * top);
    key |= spread_bits<d>(q) << (d - 1 - k);  // bit b of axis k at d * b + d - 1 - k
  }
  return key;
}

// Sorts (key, index) pairs by key, stably: pairs made in increasing index order come out as
// std::sort would sort them. LSD radix sort on 11-bit digits (six passes for 64 bits, a digit
// that all keys share is skipped), linear in the number of cells.
template <class Index>
void sort_by_key(std::vector<std::pair<std::uint64_t, Index>>& a) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  std::vector<std::pair<std::uint64_t, Index>> b(a.size());
  std::vector<std::size_t> count(kBuckets);
  for (int shift = 0; shift < 64; shift += kBits) {
    std::fill(count.begin(), count.end(), 0);
    for (const auto& x : a) ++count[(x.first >> shift) & (kBuckets - 1)];
    if (std::find(count.begin(), count.end(), a.size()) != count.end()) continue;
    std::size_t sum = 0;
    for (std::size_t& c : count) sum += std::exchange(c, sum);
    for (const auto& x : a) b[count[(x.first >> shift) & (kBuckets - 1)]++] = x;
    a.swap(b);
  }
}

}  // namespace tetia::detail
