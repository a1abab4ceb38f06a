// src/kernel/minor_sign.hpp -- the exact sign of a 2x2 minor a b - c d of doubles, for the
// kernel's one comparison along an edge (eq. 2, edge_signs.hpp), where the computed minor
// fl(fl(a b) - fl(c d)) is 0 although a b != c d.
//
// Why only there. Rounding is monotone: a b > c d implies fl(a b) >= fl(c d), and the difference
// of two doubles is 0 only when they are equal (gradual underflow). So the computed minor has
// the exact sign or is 0, and it is wrongly 0 exactly when the two products round to the same
// double. Where that double is 0 both products are 0 (no product of nonzero coordinates
// underflows, below), and the minor is exactly 0. Otherwise the products are p + e_p and p + e_q
// with the same p, and e_p - e_q, rounded, has the sign of a b - c d.
//
// Contract: tie_difference(a, b, c, d), for finite doubles with fl(a b) == fl(c d) != 0,
// returns a double with the exact sign of a b - c d (0 only where it is exactly 0), provided
// |a|, |b|, |c|, |d| < 2^996 (Dekker's split cannot overflow) and |a b|, |c d| >= 2^-968 (the
// products' rounding errors are representable). The kernel's coordinates satisfy both: nonzero
// ones are at least 2^-340 (barycentric_map.hpp snaps smaller ones to 0), and they stay far
// below 2^996 (sizes are rescaled into [2^-250, 2^250], solve.hpp; coordinates are ratios of
// such sizes over the reference's quality). No fused multiply-add is assumed (the kernels build
// with -ffp-contract=off).
#pragma once

#include "exact_sign.hpp"  // exact_sign_impl::two_product (Dekker)

namespace tetia::detail {

// Internal linkage: each kernel variant compiles its own copy for its instruction set, which
// no other object file can bind to (src/kernel/entry_points.hpp, "Linkage").
namespace {

inline double tie_difference(double a, double b, double c, double d) {
  double p, e_p, q, e_q;
  exact_sign_impl::two_product(a, b, p, e_p);
  exact_sign_impl::two_product(c, d, q, e_q);
  return e_p - e_q;  // p == q: a b - c d = e_p - e_q exactly, and its rounding keeps the sign
}

// The computed minor a b - c d, or where it is 0 with nonzero products, tie_difference: a
// double whose sign is the exact sign of a b - c d (same contract).
inline double minor_with_exact_sign(double a, double b, double c, double d) {
  const double p = a * b, q = c * d;
  const double m = p - q;
  if (m == 0.0 && p != 0.0) [[unlikely]]
    return tie_difference(a, b, c, d);
  return m;
}

}  // namespace

}  // namespace tetia::detail
