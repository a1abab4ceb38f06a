// src/kernel/fan.hpp -- the volume and first moments of the pyramids over one facet of a convex
// polytope, its corners fanned from the first and each triangle joined to a point o inside
// (internal; used by the kernel's moments.hpp and by refined_clip.hpp).
//
// Contract: corner(k), k = 0..n-1, gives the facet's k-th corner as four coordinates, of which
// entries 1..3 are used (barycentric coordinates in a reference tetrahedron: (x, y, z)). Adds to
// fv six times the signed volume of the pyramids, and with kMoments to fm, per triangle
// (p0, p1, p2), its six-fold volume d times (o + p0 + p1 + p2) (24 times its first moments).
// Always inlined, so that each caller computes exactly what it computed with this loop written
// out (the same operations in the same order: the bitwise contract of the entry points).
#pragma once

namespace tetia::detail {

// Internal linkage: each kernel variant compiles its own copy for its instruction set, which
// no other object file can bind to (src/kernel/entry_points.hpp, "Linkage").
namespace {

// record(d) receives each triangle's six-fold volume as it is added (by default nothing: the
// refinement's clipping keeps them for its error bound, refined_clip.hpp).
struct NoRecord {
  void operator()(double) const {}
};

template <bool kMoments, class Corner, class Record = NoRecord>
[[gnu::always_inline]] inline void fan_pyramids(const double (&o)[3], int n, const Corner& corner, double& fv,
                                                double (&fm)[3], const Record& record = Record{}) {
  const double* p0 = corner(0);
  const double ax = p0[1] - o[0], ay = p0[2] - o[1], az = p0[3] - o[2];
  for (int k = 1; k + 1 < n; ++k) {
    const double* p1 = corner(k);
    const double* p2 = corner(k + 1);
    const double bx = p1[1] - o[0], by = p1[2] - o[1], bz = p1[3] - o[2];
    const double cx = p2[1] - o[0], cy = p2[2] - o[1], cz = p2[3] - o[2];
    const double d = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    record(d);
    fv += d;
    if constexpr (kMoments)
      for (int c = 0; c < 3; ++c) fm[c] += d * (o[c] + p0[c + 1] + p1[c + 1] + p2[c + 1]);
  }
}

}  // namespace

}  // namespace tetia::detail
