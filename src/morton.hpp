// src/morton.hpp -- bit spreading for Morton codes (internal to the library; also used by
// bench/bench_supermesh.cpp to presort meshes).
#pragma once

#include <cstdint>

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

}  // namespace tetia::detail
