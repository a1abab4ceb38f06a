// src/kernel/rescale.hpp -- exact power-of-two rescaling of a kernel's input, so that
// coordinates anywhere in the double range are computed in the range the kernels are made for.
//
// Why: the kernels form products of up to three (3D) or two (2D) coordinate differences and
// compare them with error bounds; beyond about 2^+-300 (3D) or 2^+-500 (2D) those products
// overflow or underflow and the results are wrong (zero, empty, NaN or infinite). A power of
// two changes no significand: x 2^k is exact unless it leaves the normal range, so the scaled
// input has exactly the same geometry, and measures scale back by 2^(d k) (volume: d = 3,
// area: d = 2) and first moments by 2^((d + 1) k), each by one correctly rounded ldexp.
//
// Contract: scaled_exactly(c, n, k, out) writes c_i 2^k and says whether every one is exact
// (false when some coordinates leave the normal range: so small next to the largest that they
// lose bits as subnormals, or overflow; the caller's exact last resort then decides). The
// caller chooses k (from the cells' sizes: 2D, tri_kernel.hpp's solve). Allocation-free.
#pragma once

#include <cmath>

namespace tetia::detail {

// Internal linkage: each kernel variant compiles its own copy for its instruction set, which
// no other object file can bind to (src/kernel/entry_points.hpp, "Linkage").
namespace {

inline bool scaled_exactly(const double* c, int n, int k, double* out) {
  bool exact = true;
  for (int i = 0; i < n; ++i) {
    out[i] = std::ldexp(c[i], k);
    exact &= std::ldexp(out[i], -k) == c[i];
  }
  return exact;
}

}  // namespace

}  // namespace tetia::detail
