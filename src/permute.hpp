// src/permute.hpp -- an array (or arrays kept in step) put in a new order in place (internal to
// the library: the MPI exchange's pieces).
//
// Contract: permute_to(place, swap) moves the element at k to position place[k], for every k,
// where `place` is a permutation of 0 .. n-1, by following its cycles: swap(i, j) exchanges the
// elements at i and j (of every array permuted together). n - (number of cycles) swaps; no
// storage beyond `place`, which ends as the identity.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace tetia::detail {

template <class Index, class Swap>
void permute_to(std::vector<Index>& place, Swap&& swap) {
  for (std::size_t k = 0; k < place.size(); ++k)
    while (static_cast<std::size_t>(place[k]) != k) {
      const auto j = static_cast<std::size_t>(place[k]);
      swap(k, j);
      std::swap(place[k], place[j]);
    }
}

}  // namespace tetia::detail
