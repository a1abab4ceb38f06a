// src/kernel/orientation.hpp -- the facets oriented outward and consistently (each edge walked
// in opposite directions by its two facets): by the sign of a facet's fan volume where it is
// well above rounding, else propagated across shared edges from the labels.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernel_result.hpp"
#include "tables.hpp"

namespace tetia::detail {

namespace {

// Orients the facets outward (in the reference frame) and consistently: each edge is walked in
// opposite directions by its two facets. A facet whose fan, joined to the mean of the corners,
// has a volume well above rounding is oriented by the sign of that volume (computed anyway for
// the moments). The others, the flat facets of degenerate intersections, take the orientation
// the combinatorics impose, propagated breadth first across shared edges from the oriented
// ones; with `check`, that propagation runs over every facet and verifies that geometry and
// labels agree everywhere. Returns false if they do not (never seen in the tests). dir[f] is
// -1 for the facets whose stored order must be reversed, +1 for the others.
bool orient_facet_dirs(const KernelResult& r, bool check, std::int8_t (&dir)[8]) {
  const int F = r.num_facets;
  for (auto& d : dir) d = 0;
  int queue[8], head = 0, tail = 0;
  // In the reference frame every corner lies in Y (coordinates in [0, 1]); a corner computed
  // from X's coordinates is accurate to about the unit roundoff times their magnitude, and so
  // is a fan volume. Facets 2^12 times above that are trusted.
  const double trust = 0x1p-40 * std::max(1.0, r.coordinate_scale);
  for (int f = 0; f < F; ++f) {
    const double v = r.facet_volume6[f];
    if (std::abs(v) > trust) {
      dir[f] = v > 0.0 ? 1 : -1;
      queue[tail++] = f;
    }
  }
  const bool seeded = tail > 0;
  if (tail < F || check) {
    if (!seeded) {  // a tiny or flat polytope: orient combinatorially, then by the total
      dir[0] = 1;
      queue[tail++] = 0;
    }
    // succ[c][a]: the corner after c in the facet of plane a, as stored.
    u8 succ[KernelResult::kMaxCorners][8];
    int facet_of[8];
    for (int f = 0; f < F; ++f) {
      facet_of[r.facet_label[f]] = f;
      const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
      for (int k = b; k < e; ++k) succ[r.facet_index[k]][r.facet_label[f]] = r.facet_index[k + 1 < e ? k + 1 : b];
    }
    while (head < tail) {
      const int f = queue[head++];
      const int a = r.facet_label[f];
      const int b = r.facet_begin[f], e = r.facet_begin[f + 1];
      for (int k = b; k < e; ++k) {
        int u = r.facet_index[k], v = r.facet_index[k + 1 < e ? k + 1 : b];
        if (dir[f] < 0) std::swap(u, v);  // the edge u -> v as oriented in f
        // The neighbour across uv: the plane u and v share besides a.
        const std::uint32_t both = (1u << u) | (1u << v);
        int g_label = -1;
        for (const u8 l : r.corners[u].labels)
          if (l != a && (r.on_plane[l] & both) == both) g_label = l;
        if (g_label < 0) return false;
        const int g = facet_of[g_label];
        const std::int8_t want = succ[v][g_label] == u ? 1 : -1;  // g must walk v -> u
        if (dir[g] == 0) {
          dir[g] = want;
          queue[tail++] = g;
        } else if (dir[g] != want) {
          return false;
        }
      }
    }
    if (tail != F) return false;
    if (!seeded) {  // no facet was trusted: the sign of the whole decides
      double signed6 = 0.0;
      for (int f = 0; f < F; ++f) signed6 += dir[f] * r.facet_volume6[f];
      if (signed6 < 0.0)
        for (int f = 0; f < F; ++f) dir[f] = static_cast<std::int8_t>(-dir[f]);
    }
  }
  return true;
}

// orient_facet_dirs, applied to the stored facets (trace_kernel's; unused by the entry points,
// hence maybe_unused in a kernel variant's translation unit).
[[maybe_unused]] bool orient_facets(KernelResult& r, bool check) {
  std::int8_t dir[8];
  if (!orient_facet_dirs(r, check, dir)) return false;
  for (int f = 0; f < r.num_facets; ++f)
    if (dir[f] < 0) std::reverse(r.facet_index + r.facet_begin[f], r.facet_index + r.facet_begin[f + 1]);
  return true;
}

}  // namespace

}  // namespace tetia::detail
