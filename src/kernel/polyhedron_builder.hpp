// src/kernel/polyhedron_builder.hpp -- PolyhedronBuilder: the kernel's result as a Polyhedron,
// facets oriented outward (orientation.hpp), corners back in the caller's coordinates by
// eq. (3), labels and barycentric coordinates relative to the caller's argument order.
// Part of the kernel: included by src/kernel/entry_points.hpp only.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>

#include "barycentric_map.hpp"  // BarycentricMap, TETIA_KERNEL_SSE2
#include "frame.hpp"
#include "kernel_result.hpp"
#include "lanes.hpp"
#include "moments.hpp"
#include "orientation.hpp"
#include "tetia/polyhedron.hpp"
#include "exact_fallback.hpp"

namespace tetia {

// Fills a Polyhedron from the kernel's result: facets oriented outward, original coordinates
// by eq. (3) (exact input vertices where a corner is one), labels and barycentric coordinates
// relative to the caller's argument order.
//
// A template on the kernel variant (entry_points.hpp) that uses it, only so that each variant's
// copy of these inline functions has its own name: the linker keeps one copy of an inline
// function, and the baseline's callers must never be given the copy compiled for AVX2.
template <class Variant>
struct PolyhedronBuilder {
  static void clear(Polyhedron& P) {
    P.num_corners_ = P.num_facets_ = 0;
    P.touched_v_ = 0;
    P.moments_ = {};
  }

  // Facet f (through corner 0, stored from it) walks its edge (second corner, third corner)
  // opposite to the way the facet g across that edge walks it, as oriented by dir[g]; g is
  // found from the labels (the plane both corners lie on besides f's). Returns false if g is
  // not found or is itself through corner 0 (labels that do not describe a simple polytope).
  static bool orient_from_neighbour(const detail::KernelResult& res, int f, std::int8_t (&dir)[8]) {
    const int b = res.facet_begin[f];
    const int u = res.facet_index[b + 1], v = res.facet_index[b + 2];
    const unsigned a = res.facet_label[f];
    int g_label = -1;
    for (const std::uint8_t l : res.corners[u].labels)
      if (l != a && ((res.on_plane[l] >> v) & 1u)) g_label = l;
    for (int g = 3; g < res.num_facets; ++g) {
      if (res.facet_label[g] != g_label) continue;
      const int gb = res.facet_begin[g], ge = res.facet_begin[g + 1];
      for (int k = gb; k < ge; ++k) {
        if (res.facet_index[k] != u) continue;
        const bool stored_uv = res.facet_index[k + 1 < ge ? k + 1 : gb] == v;  // else v -> u
        dir[f] = static_cast<std::int8_t>(stored_uv == (dir[g] > 0) ? -1 : 1);
        return true;
      }
      return false;
    }
    return false;
  }

  // Equal barycentric coordinates on V's vertices whose planes (bit p: plane 4 + p) the corner
  // is not on, 0 on those it is on: where no coordinates can be had (a reference or V flat to
  // the rounding of its coordinates, whose map is not finite), a point the labels allow.
  static detail::Quad admissible_midpoint(unsigned on_plane) {
    double b[4];
    const int free = 4 - std::popcount(on_plane & 0xFu);
    for (int p = 0; p < 4; ++p) b[p] = ((on_plane >> p) & 1u) || free == 0 ? 0.0 : 1.0 / free;
    return detail::load4(b);
  }

  // scale: the exponent the input was scaled by (solve_rescaled), undone here; 0 usually.
  static bool fill(Polyhedron& P, const detail::Frame& fr, detail::KernelResult& res, bool check, int scale) {
    using detail::RawCorner;
    std::int8_t dir[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    if (res.num_facets > 0) {
      // orient_facet_dirs' usual outcome without `check`: every facet's fan volume trusted, and
      // its sign the facet's direction. Otherwise (or with `check`) it decides.
      bool trusted = !check;
      if (trusted) {
        // With fans from corner 0, the facets through it (stored first) have no fan volume;
        // each takes the direction opposite to the facet across its edge from its second to its
        // third corner, an edge off corner 0: that facet does not contain corner 0 (two planes
        // of corner 0 meet in one edge of it), so its fan volume is there.
        const int skip = res.corner_apex ? 3 : 0;
        const double trust = 0x1p-40 * std::max(1.0, res.coordinate_scale);
        for (int f = skip; f < res.num_facets; ++f) {
          const double v = res.facet_volume6[f];
          trusted &= std::abs(v) > trust;
          dir[f] = static_cast<std::int8_t>(1 - 2 * int(!(v > 0.0)));  // v > 0.0 ? 1 : -1
        }
        for (int f = 0; f < skip && trusted; ++f) trusted = orient_from_neighbour(res, f, dir);
      }
      if (!trusted && !detail::orient_facet_dirs(res, check, dir)) return false;
    }
    // Outward in the reference frame; a negatively oriented reference maps outward to inward,
    // so the facets are then reversed once more.
    const bool flip_all = fr.det6 < 0.0;
    const Tet& r = *fr.ref;
    const Vec3 a1 = r[1] - r[0], a2 = r[2] - r[0], a3 = r[3] - r[0];
    P.num_corners_ = res.num_corners;
    const bool swapped = fr.swapped;
    const unsigned relabel = unsigned(swapped) << 2;  // (label + 4) % 8 when U was the reference
    const Tet* const sub_ref[2] = {fr.ref, fr.sub};
    const Tet& V = *sub_ref[swapped];  // the caller's V, chosen without a branch
    // V's map, built only for vertices of U inside V (in place, on first use).
    union MapStorage {
      MapStorage() {}
      detail::BarycentricMap map;
    } bary_v;
    bool have_bary_v = false;
    unsigned label_zero[8] = {0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu, 0xFu};  // see touched_v_ below
    for (int c = 0; c < res.num_corners; ++c) {
      const RawCorner& rc = res.corners[c];
      Corner& out = P.corners_[static_cast<std::size_t>(c)];
      // A vertex of X or Y is the input vertex itself; other corners by eq. (3). Chosen by
      // index rather than by a branch on the kind.
      const Vec3 mapped = r[0] + (rc.bary[1] * a1 + rc.bary[2] * a2 + rc.bary[3] * a3);
      const Vec3* const point[4] = {&(*fr.sub)[rc.index & 3], &mapped, &mapped, &r[rc.index & 3]};
      out.point = *point[rc.kind];
      // The labels relative to the caller's order, ascending (a sorting network).
      const auto min = [](unsigned x, unsigned y) { return y ^ ((x ^ y) & (0u - unsigned(x < y))); };
      const auto max = [](unsigned x, unsigned y) { return x ^ ((x ^ y) & (0u - unsigned(x < y))); };
      const unsigned k0 = rc.labels[0] ^ relabel, k1 = rc.labels[1] ^ relabel, k2 = rc.labels[2] ^ relabel;
      const unsigned l0 = min(min(k0, k1), k2), l2 = max(max(k0, k1), k2);
      const unsigned l1 = k0 ^ k1 ^ k2 ^ l0 ^ l2;  // the remaining one
      out.labels = {static_cast<std::uint8_t>(l0), static_cast<std::uint8_t>(l1), static_cast<std::uint8_t>(l2)};
      detail::Quad bary;  // V's barycentric coordinates of the corner
      if (!swapped) {
        // The kernel's coordinates sum to 1 up to the conditioning of the map; the reported
        // ones are scaled to sum to 1 (zeros stay exact zeros): they are P1 basis values.
        const double total = rc.bary[0] + rc.bary[1] + rc.bary[2] + rc.bary[3];
        if (total > 0.0 && total < INFINITY) [[likely]] {
          bary = detail::mul4(detail::load4(rc.bary), 1.0 / total);
        } else {  // nothing usable (a frame flat to rounding): the admissible midpoint
          bary = admissible_midpoint((1u << rc.labels[0] | 1u << rc.labels[1] | 1u << rc.labels[2]) >> 4);
        }
      } else {
        // The reference was U: V's coordinates come from the point itself, with the coordinates
        // of V's planes the corner lies on set to exactly zero, then clamped into the simplex
        // (the corner is on V by construction).
        // Where the guardrail moved the corner, its weights describe the point before the move
        // (in the issue that found it, a point on the line of an edge of U lying in a face of
        // V, 0.25 of V's diameter away): V's coordinates then come from the point, as for a
        // vertex of Y, so that point and coordinates describe one position.
        double b[4];
        if (rc.kind != detail::kVertexOfY && !rc.moved) {
          for (int p = 0; p < 4; ++p) b[p] = rc.weights[p];  // X is V: its weights are V's coordinates
        } else {
          if (!have_bary_v) {
            new (&bary_v.map) detail::BarycentricMap(V, 1.0 / orient3d(V[0], V[1], V[2], V[3]));
            have_bary_v = true;
          }
          bary_v.map(out.point, b);
        }
        const unsigned on_plane = ((1u << l0) | (1u << l1) | (1u << l2)) >> 4;  // labels 4 + p
        double sum = 0.0;
#if TETIA_KERNEL_SSE2
        {  // b[p] > 0 and p not a plane of the corner, else 0; as the loop below
          const __m128i off = _mm_set_epi64x(-std::int64_t((on_plane >> 1) & 1u), -std::int64_t(on_plane & 1u));
          const __m128i off2 = _mm_set_epi64x(-std::int64_t((on_plane >> 3) & 1u), -std::int64_t((on_plane >> 2) & 1u));
          const __m128d z = _mm_setzero_pd(), b01 = _mm_loadu_pd(b), b23 = _mm_loadu_pd(b + 2);
          _mm_storeu_pd(b, _mm_andnot_pd(_mm_castsi128_pd(off), _mm_and_pd(_mm_cmpgt_pd(b01, z), b01)));
          _mm_storeu_pd(b + 2, _mm_andnot_pd(_mm_castsi128_pd(off2), _mm_and_pd(_mm_cmpgt_pd(b23, z), b23)));
        }
        for (int p = 0; p < 4; ++p) sum += b[p];
#else
        for (int p = 0; p < 4; ++p) {
          b[p] = ((on_plane >> p) & 1u) || !(b[p] > 0.0) ? 0.0 : b[p];
          sum += b[p];
        }
#endif
        bary = sum > 0.0 && sum < INFINITY ? detail::div4(detail::load4(b), sum) : admissible_midpoint(on_plane);
      }
      // Which of V's barycentric coordinates are exactly zero, for every plane of the corner.
      detail::store4(out.bary.data(), bary);
      const unsigned zero = detail::zero_lanes(bary);
      for (int k = 0; k < 3; ++k) label_zero[rc.labels[k]] &= zero;
    }
    P.num_facets_ = res.num_facets;
    P.touched_v_ = 0;
    if constexpr (std::endian::native == std::endian::little) {
      // facet_begin[0..num_facets] as one 64-bit word and a byte; the entries after stay 0
      static_assert(Polyhedron::max_facets == 8);
      const unsigned nf = unsigned(res.num_facets);  // at most 8
      std::uint64_t w;
      std::memcpy(&w, res.facet_begin, 8);
      w &= ~std::uint64_t(0) >> ((8 * (7 - nf)) & 63u) | (0u - std::uint64_t(nf >= 7));
      std::memcpy(P.facet_begin_.data(), &w, 8);
      P.facet_begin_[8] = static_cast<std::uint8_t>(res.facet_begin[8] & (0u - unsigned(nf == 8)));
    } else {
      for (int f = 0; f <= res.num_facets; ++f) P.facet_begin_[static_cast<std::size_t>(f)] = res.facet_begin[f];
    }
    for (int f = 0; f < res.num_facets; ++f) {
      const unsigned kernel_label = res.facet_label[f], label = kernel_label ^ relabel;
      P.facet_label_[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(label);
      // A facet of V (label 4 + k), or a facet of U lying in a plane of V: every corner has
      // that coordinate exactly zero.
      const unsigned of_v = 0u - (label >> 2);
      P.touched_v_ |= (of_v & (1u << (label & 3u))) | (~of_v & label_zero[kernel_label]);
      // Stored in walking order; reversed where orient_facet_dirs says so, and once more for a
      // negatively oriented reference.
      const bool flip = (dir[f] < 0) != flip_all;
      const int b = res.facet_begin[f], e = res.facet_begin[f + 1];
      const unsigned len = unsigned(e - b);
      if (std::endian::native == std::endian::little && len <= 8 && b + 8 <= Polyhedron::max_facet_indices) {
        // The usual case (a facet has at most seven corners): the facet's indices as one
        // 64-bit word, reversed by a byte swap. The bytes past the facet are overwritten by the
        // next facet, or lie past the last one.
        std::uint64_t x;
        std::memcpy(&x, res.facet_index + b, 8);
        const std::uint64_t reversed = __builtin_bswap64(x) >> ((8 * (8 - len)) & 63u);
        const std::uint64_t keep = std::uint64_t(flip) - 1u;  // all ones unless flipped
        x = (x & keep) | (reversed & ~keep);
        std::memcpy(P.facet_index_.data() + b, &x, 8);
      } else {
        for (int k = b; k < e; ++k)
          P.facet_index_[static_cast<std::size_t>(k)] = res.facet_index[flip ? b + e - 1 - k : k];
      }
    }
    P.moments_ = detail::original_volume(fr, res) == 0.0 ? Moments{} : detail::original_moments(fr, res);  // as intersection_moments
    if (scale != 0) [[unlikely]] {
      for (int c = 0; c < P.num_corners_; ++c) {
        Vec3& q = P.corners_[static_cast<std::size_t>(c)].point;
        q = {std::ldexp(q.x, -scale), std::ldexp(q.y, -scale), std::ldexp(q.z, -scale)};
      }
      P.moments_ = unscaled(P.moments_, scale);
    }
    return true;
  }

  static void set_moments(Polyhedron& P, const Moments& m) { P.moments_ = m; }

  // Moments of the input scaled by 2^scale, brought back (one correctly rounded ldexp each).
  static Moments unscaled(const Moments& m, int scale) {
    return {std::ldexp(m.volume, -3 * scale),
            {std::ldexp(m.first.x, -4 * scale), std::ldexp(m.first.y, -4 * scale), std::ldexp(m.first.z, -4 * scale)}};
  }

  // The exact last resort's polyhedron (exact_fallback.hpp), already in the caller's numbering.
  static void fill_exact(Polyhedron& P, const detail::ExactPolyhedron& x) {
    P.num_corners_ = x.num_corners;
    P.num_facets_ = x.num_facets;
    for (int c = 0; c < x.num_corners; ++c) {
      Corner& out = P.corners_[static_cast<std::size_t>(c)];
      out.point = x.point[c];
      out.bary = {x.bary[c][0], x.bary[c][1], x.bary[c][2], x.bary[c][3]};
      out.labels = {x.labels[c][0], x.labels[c][1], x.labels[c][2]};
    }
    P.facet_begin_[0] = 0;
    P.touched_v_ = 0;
    for (int f = 0; f < x.num_facets; ++f) {
      const unsigned label = x.facet_label[f];
      P.facet_label_[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(label);
      P.facet_begin_[static_cast<std::size_t>(f) + 1] = x.facet_begin[f + 1];
      // A facet of V, or a facet of U whose corners all have V's coordinate k exactly 0.
      unsigned zero = 0xFu;
      for (int k = x.facet_begin[f]; k < x.facet_begin[f + 1]; ++k) {
        const int c = x.facet_index[k];
        P.facet_index_[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(c);
        for (int p = 0; p < 4; ++p)
          if (x.bary[c][p] != 0.0) zero &= ~(1u << p);
      }
      P.touched_v_ |= label >= 4 ? 1u << (label - 4) : zero;
    }
    P.moments_ = x.moments;
  }
};

}  // namespace tetia
