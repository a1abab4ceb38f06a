// src/kernel/facets.hpp -- the facets of X ∩ Y from the corners' labels alone (what the paper
// leaves to the implementer; see ERRATA.md): every corner lies on exactly three of the eight
// planes, and by Theorem 6 the labels are those of a simple polytope, so each plane's corners
// form one cycle. build_facets_walk is the walk as stated, build_facets the fast one (with the
// fan volumes and moments computed on the way, as fan_moments in moments.hpp computes them
// after the walk).
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "barycentric_map.hpp"  // TETIA_KERNEL_SSE2
#include "kernel_result.hpp"
#include "tables.hpp"

namespace tetia::detail {

namespace {

// --- facets from labels ---------------------------------------------------------------------

// The facets of the polytope whose corners carry the labels: the corners on plane a form one
// cycle in which consecutive corners share a second label (the edge between them lies on both
// planes). With the corners of each plane as a bit mask, the neighbour of corner c across the
// pair {a, b} is the other bit of on_plane[a] & on_plane[b]. Returns false if the labels do not
// describe a closed simple polytope (each pair of planes shared by no corner or by two).
// This is the walk as stated; build_facets below follows the same cycles faster and falls
// back to it when a pair of planes is not shared by exactly two corners.
template <bool kVolume>
bool build_facets_walk(KernelResult& r) {
  const int n = r.num_corners;
  r.num_facets = 0;
  r.facet_begin[0] = 0;
  if (n == 0) return true;
  if (n < 4) return false;
  // With kVolume, each facet's fan is joined to the mean of the corners while it is walked
  // (see fan_moments for why absolute values per facet).
  double o[3] = {0.0, 0.0, 0.0}, vol6 = 0.0;
  if constexpr (kVolume) {
    for (int c = 0; c < n; ++c)
      for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
    const double inv = 1.0 / n;
    for (double& x : o) x *= inv;
  }
  int used = 0;
  for (int a = 0; a < 8; ++a) {
    const std::uint32_t here = r.on_plane[a];
    if (!here) continue;
    const int start = std::countr_zero(here);
    const u8* l = r.corners[start].labels;
    int prev_label = l[0] == a ? l[1] : l[0];
    int cur = start, prev = -1;
    std::uint32_t visited = 0;
    double fv = 0.0, ax = 0.0, ay = 0.0, az = 0.0, bx = 0.0, by = 0.0, bz = 0.0;
    do {
      const std::uint32_t cb = 1u << cur;
      if (visited & cb) return false;
      visited |= cb;
      r.facet_index[used++] = static_cast<u8>(cur);
      if constexpr (kVolume) {
        const double* p = r.corners[cur].bary;
        const double cx = p[1] - o[0], cy = p[2] - o[1], cz = p[3] - o[2];
        if (prev < 0) {
          ax = cx, ay = cy, az = cz;
        } else if (prev != start) {
          fv += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        }
        bx = cx, by = cy, bz = cz;
        prev = cur;
      }
      const u8* cl = r.corners[cur].labels;
      const int next_label = cl[0] + cl[1] + cl[2] - a - prev_label;  // labels are distinct
      const std::uint32_t pair = here & r.on_plane[next_label] & ~cb;
      if (pair == 0 || (pair & (pair - 1)) != 0) return false;  // exactly one neighbour
      prev_label = next_label;
      cur = std::countr_zero(pair);
    } while (cur != start);
    // All the plane's corners on one cycle of at least three.
    if (visited != here || r.facet_begin[r.num_facets] + 3 > used) return false;
    r.facet_label[r.num_facets] = static_cast<u8>(a);
    r.facet_begin[++r.num_facets] = static_cast<u8>(used);
    vol6 += std::abs(fv);
  }
  if constexpr (kVolume) r.ref_volume = vol6 / 6.0;
  // Euler's formula for a simple polytope: F = V/2 + 2.
  return 2 * r.num_facets == n + 4;
}

// build_facets_walk, with each corner's neighbours found once instead of at every step. Corner
// c with labels l0 < l1 < l2 has three edges; nb[k] is the other corner on the edge that does
// not lie on l_k. When every such neighbour is unique and no two corners carry the same three
// labels, each plane's corners and edges form cycles of at least three corners (two neighbours
// per corner on the plane, distinct, symmetric), so a walk cannot revisit a corner before it
// closes and needs no test for it. Otherwise the label walk above decides (and fails). On
// facet a the walk enters c from one of its two neighbours on a and leaves to the other: the
// next corner is (xor of c's two neighbours on a) xor the previous one. The first step from
// the start corner goes where the label walk goes (across the planes a and the label of start
// that is neither a nor the first other one), so the cycles and their directions are the same;
// without kCornerApex (below) so are the fan volumes, operation for operation, and with
// kMoments the walk also computes what reference_moments computes after the label walk (the
// same triangles in the same order).
enum FacetMode { kFacetsOnly, kFacetsVolume, kFacetsMoments };
template <bool kMoments>
void reference_moments(KernelResult& r);

template <FacetMode kMode>
bool facets_by_label_walk(KernelResult& r) {
  if constexpr (kMode == kFacetsMoments) {
    if (!build_facets_walk<false>(r)) return false;
    reference_moments<true>(r);
    return true;
  } else {
    return build_facets_walk<kMode == kFacetsVolume>(r);
  }
}

// What build_facets measures on its way for the a posteriori error estimate
// (error_estimate.hpp), with kMeasure: the sum of the fans' triangle areas, twice (original
// units: `points`, the corners relative to the reference's vertex 0), over every facet, and the
// sum of the permanents of the fans' triple products, relative to corner 0 (their apex), over
// the facets not through corner 0 (the others contribute exactly 0). The triangles are those of
// the volume's fans.
struct FacetMeasures {
  double surface2 = 0.0;
  double permanents = 0.0;
};

// build_facets' options.
// kCornerApex: the fans are joined to corner 0 instead of the mean of the corners. Corner 0 lies
// on the polytope, so every pyramid still has non-negative volume, and the three facets through
// it contribute exactly nothing: they are walked without geometry, which saves about half the
// walk. Their fan volumes are stored as 0; PolyhedronBuilder::fill orients them from a
// neighbouring facet instead (KernelResult::corner_apex tells it so). Every entry point uses it,
// so intersect(U, V).volume() and intersection_volume(U, V) stay the same number.
// kStore: the facets' corner indices, labels and fan volumes are stored (a Polyhedron reads
// them; the volume and the moments alone do not).
// kMeasure: a second walk over a result the first built, which changes nothing in it: `measures`
// receives FacetMeasures' sums, from `points`, along the fans the first walk computed the volume
// on (the facets through corner 0 walked one after the other, as with kStore, for their areas).
// False where the fast walk cannot run (the first one then took the label walk).
template <FacetMode kMode, bool kCornerApex = false, bool kStore = true, bool kMeasure = false>
bool build_facets(KernelResult& r, [[maybe_unused]] const Vec3* points = nullptr,
                  [[maybe_unused]] FacetMeasures* measures = nullptr) {
  constexpr bool kVolume = kMode != kFacetsOnly, kMoments = kMode == kFacetsMoments;
  static_assert(kVolume || !kCornerApex);
  static_assert(kStore || kCornerApex);
  static_assert(!kMeasure || (kCornerApex && !kStore && !kMoments));
  constexpr bool kWrite = !kMeasure;  // the result is written (not a measuring walk)
  if constexpr (kWrite) r.corner_apex = false;
  const int n = r.num_corners;
  if (n == 0) {  // nothing found (X and Y apart): as the label walk leaves it, without the call
    if constexpr (kWrite) r.set_empty();
    return kWrite;
  }
  if (n < 4) {
    if constexpr (kMeasure) return false;
    return facets_by_label_walk<kMode>(r);
  }
  u8 nb[KernelResult::kMaxCorners][2];  // nb[c][0], nb[c][1]: across the edges off l0, off l1
  u8 across[KernelResult::kMaxCorners][8];  // [c][a]: xor of c's two neighbours on facet a
  unsigned bad = 0;
  double o[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < n; ++c) {
    const u8* l = r.corners[c].labels;
    const std::uint32_t self = ~(1u << c), p0 = r.on_plane[l[0]], p1 = r.on_plane[l[1]], p2 = r.on_plane[l[2]];
    const std::uint32_t m0 = p1 & p2 & self, m1 = p0 & p2 & self, m2 = p0 & p1 & self;
    const int n0 = std::countr_zero(m0 | 0x80000000u), n1 = std::countr_zero(m1 | 0x80000000u),
              n2 = std::countr_zero(m2 | 0x80000000u);
    // Exactly one bit each (m equals its lowest bit; an empty m gets n = 31 and differs from
    // bit 31), and no other corner on all three planes.
    bad |= (m0 ^ (1u << n0)) | (m1 ^ (1u << n1)) | (m2 ^ (1u << n2)) | (m2 & p2);
    nb[c][0] = static_cast<u8>(n0);
    nb[c][1] = static_cast<u8>(n1);
    across[c][l[0]] = static_cast<u8>(n1 ^ n2);
    across[c][l[1]] = static_cast<u8>(n0 ^ n2);
    across[c][l[2]] = static_cast<u8>(n0 ^ n1);
    if constexpr (kVolume && !kCornerApex)
      for (int k = 0; k < 3; ++k) o[k] += r.corners[c].bary[k + 1];
  }
  if (bad) {
    if constexpr (kMeasure) return false;
    return facets_by_label_walk<kMode>(r);
  }
  if constexpr (kCornerApex) {
    for (int k = 0; k < 3; ++k) o[k] = r.corners[0].bary[k + 1];
  } else if constexpr (kVolume) {
    const double inv = 1.0 / n;
    for (double& x : o) x *= inv;
  }
  // A corner relative to the mean of the corners.
  const auto rel = [&](int c, double& x, double& y, double& z) {
    const double* p = r.corners[c].bary;
    x = p[1] - o[0], y = p[2] - o[1], z = p[3] - o[2];
  };
  if constexpr (kWrite) {
    r.num_facets = 0;
    r.facet_begin[0] = 0;
  }
  double vol6 = 0.0, m[3] = {0.0, 0.0, 0.0};
  [[maybe_unused]] int used = 0;  // facet indices stored (with kStore)
  unsigned planes = 0;  // bit a: some corner lies on plane a
#if TETIA_KERNEL_SSE2
  {
    const __m128i z = _mm_setzero_si128();
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r.on_plane));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(r.on_plane + 4));
    planes = ~(unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(lo, z)))) |
               unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(hi, z)))) << 4) &
             0xFFu;
  }
#else
  for (int a = 0; a < 8; ++a) planes |= unsigned(r.on_plane[a] != 0) << a;
#endif
  [[maybe_unused]] double surface2 = 0.0, permanents = 0.0;  // kMeasure
  // Twice the area of the triangle (from, b, c), given e_b = b - from; e_c = c - from (kMeasure).
  [[maybe_unused]] const auto twice_area = [](Vec3 e_b, Vec3 e_c) {
    const Vec3 t = cross(e_b, e_c);
    return std::sqrt(dot(t, t));
  };
  if constexpr (kCornerApex && !kStore && !kMeasure) {
    // The facets through corner 0 (its three labels): no geometry, only the check that each is
    // one cycle. The three walks run side by side, from corner 0 to its neighbours on each
    // (as below); a walk that is back at corner 0 stays there. One loop instead of three: one
    // data-dependent exit, and three independent chains of loads instead of one after another.
    const u8* l = r.corners[0].labels;
    const int a0 = l[0], a1 = l[1], a2 = l[2];
    unsigned p0 = nb[0][1], p1 = nb[0][0], p2 = nb[0][0];  // the first steps, as below
    unsigned c0 = across[p0][a0], c1 = across[p1][a1], c2 = across[p2][a2];
    std::uint32_t v0 = 1u | (1u << p0), v1 = 1u | (1u << p1), v2 = v1;
    while ((c0 | c1 | c2) != 0) {
      v0 |= 1u << c0;  // bit 0 for a walk already back: set from the start
      v1 |= 1u << c1;
      v2 |= 1u << c2;
      const unsigned n0 = (across[c0][a0] ^ p0) & (0u - unsigned(c0 != 0));
      const unsigned n1 = (across[c1][a1] ^ p1) & (0u - unsigned(c1 != 0));
      const unsigned n2 = (across[c2][a2] ^ p2) & (0u - unsigned(c2 != 0));
      p0 = c0, p1 = c1, p2 = c2;
      c0 = n0, c1 = n1, c2 = n2;
    }
    if ((v0 ^ r.on_plane[a0]) | (v1 ^ r.on_plane[a1]) | (v2 ^ r.on_plane[a2])) return false;
    r.num_facets = std::popcount(planes);
    planes &= ~((1u << a0) | (1u << a1) | (1u << a2));
    r.corner_apex = true;
  } else if constexpr (kCornerApex) {
    // The same facets one walk after the other: stored in their order (kStore; a Polyhedron
    // reads them), and measured (kMeasure). Corner 0 is the lowest corner on each, so it is
    // where the walk starts.
    const u8* l = r.corners[0].labels;
    const unsigned apex_planes = (1u << l[0]) | (1u << l[1]) | (1u << l[2]);
    for (unsigned rest = apex_planes; rest; rest &= rest - 1) {
      const int a = std::countr_zero(rest);
      const int first = nb[0][l[0] == a ? 1 : 0];
      if constexpr (kStore) {
        r.facet_index[used++] = 0;
        r.facet_index[used++] = static_cast<u8>(first);
      }
      std::uint32_t visited = 1u | (1u << first);
      int prev = first, cur = across[first][a];  // across[first][a] ^ 0
      [[maybe_unused]] Vec3 prev_edge{};
      if constexpr (kMeasure) prev_edge = points[first] - points[0];
      while (cur != 0) {
        visited |= 1u << cur;
        if constexpr (kStore) r.facet_index[used++] = static_cast<u8>(cur);
        if constexpr (kMeasure) {
          const Vec3 edge = points[cur] - points[0];
          surface2 += twice_area(prev_edge, edge);
          prev_edge = edge;
        }
        const int next = across[cur][a] ^ prev;
        prev = cur;
        cur = next;
      }
      if (visited != r.on_plane[a]) return false;
      if constexpr (kStore) {
        r.facet_volume6[r.num_facets] = 0.0;
        r.facet_label[r.num_facets] = static_cast<u8>(a);
        r.facet_begin[++r.num_facets] = static_cast<u8>(used);
      }
    }
    planes &= ~apex_planes;
    if constexpr (kWrite) r.corner_apex = true;
  }
  for (; planes; planes &= planes - 1) {
    const int a = std::countr_zero(planes);
    const std::uint32_t here = r.on_plane[a];
    const int start = std::countr_zero(here);
    const int first = nb[start][r.corners[start].labels[0] == a ? 1 : 0];
    if constexpr (kStore) {
      r.facet_index[used++] = static_cast<u8>(start);
      r.facet_index[used++] = static_cast<u8>(first);
    }
    std::uint32_t visited = (1u << start) | (1u << first);
    double fv = 0.0, ax = 0.0, ay = 0.0, az = 0.0, bx = 0.0, by = 0.0, bz = 0.0, fm[3] = {0.0, 0.0, 0.0};
    // For the moments: o + (start's coordinates), the same for every triangle of the fan, and
    // the previous corner's coordinates, kept in registers (the index stores are of a char
    // type and would otherwise force them to be loaded again at every step).
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, q0 = 0.0, q1 = 0.0, q2 = 0.0;
    if constexpr (kVolume) {
      rel(start, ax, ay, az);
      rel(first, bx, by, bz);
    }
    if constexpr (kMoments) {
      const double* p0 = r.corners[start].bary;
      const double* p1 = r.corners[first].bary;
      s0 = o[0] + p0[1], s1 = o[1] + p0[2], s2 = o[2] + p0[3];
      q0 = p1[1], q1 = p1[2], q2 = p1[3];
    }
    [[maybe_unused]] Vec3 prev_edge{};
    if constexpr (kMeasure) prev_edge = points[first] - points[start];
    int prev = first, cur = across[first][a] ^ start;
    while (cur != start) {
      visited |= 1u << cur;
      if constexpr (kStore) r.facet_index[used++] = static_cast<u8>(cur);
      if constexpr (kVolume) {
        const double* p2 = r.corners[cur].bary;
        const double px = p2[1], py = p2[2], pz = p2[3];
        const double cx = px - o[0], cy = py - o[1], cz = pz - o[2];  // rel(cur)
        const double d = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        fv += d;
        if constexpr (kMeasure) {
          permanents += std::abs(ax) * (std::abs(by * cz) + std::abs(bz * cy)) +
                        std::abs(ay) * (std::abs(bx * cz) + std::abs(bz * cx)) +
                        std::abs(az) * (std::abs(bx * cy) + std::abs(by * cx));
          const Vec3 edge = points[cur] - points[start];
          surface2 += twice_area(prev_edge, edge);
          prev_edge = edge;
        }
        if constexpr (kMoments) {  // d * (o + p0 + p1 + p2), in that order
          fm[0] += d * (s0 + q0 + px);
          fm[1] += d * (s1 + q1 + py);
          fm[2] += d * (s2 + q2 + pz);
          q0 = px, q1 = py, q2 = pz;
        }
        bx = cx, by = cy, bz = cz;
      }
      const int next = across[cur][a] ^ prev;
      prev = cur;
      cur = next;
    }
    // All the plane's corners on one cycle (of at least three, see above).
    if (visited != here) return false;
    if constexpr (kMoments) {  // as fan_moments
      if constexpr (kStore) r.facet_volume6[r.num_facets] = fv;
      const double sgn = 1.0 - 2.0 * double(fv < 0.0);  // fv < 0.0 ? -1.0 : 1.0, without a branch
      vol6 += sgn * fv;
      for (int c = 0; c < 3; ++c) m[c] += sgn * fm[c];
    } else {
      vol6 += std::abs(fv);
    }
    if constexpr (kStore) {
      r.facet_label[r.num_facets] = static_cast<u8>(a);
      r.facet_begin[++r.num_facets] = static_cast<u8>(used);
    }
  }
  if constexpr (kMeasure) {
    measures->surface2 = surface2;
    measures->permanents = permanents;
    return true;
  }
  if constexpr (kVolume) r.ref_volume = vol6 / 6.0;
  if constexpr (kMoments)
    for (int c = 0; c < 3; ++c) r.ref_first[c] = m[c] / 24.0;
  // Euler's formula for a simple polytope: F = V/2 + 2.
  return 2 * r.num_facets == n + 4;
}

}  // namespace

}  // namespace tetia::detail
