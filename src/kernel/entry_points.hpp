// src/kernel/entry_points.hpp -- the 3D kernel's entry points, compiled once for each
// instruction set the library dispatches to (src/kernel/kernel_variant.hpp): included by
// src/kernel/tet_intersection.cpp (the baseline x86-64 or any other target) and by
// src/kernel/tet_intersection_x86_64_v3.cpp (AVX2, BMI1/2, LZCNT, MOVBE, F16C; no FMA), each with
// TETIA_KERNEL_VARIANT naming the namespace its functions go into.
//
// Contract: each variant computes the same numbers bit for bit. The kernel's arithmetic is IEEE
// double with contraction off (-ffp-contract=off, and -mno-fma for the variant) and without
// reassociation, so an instruction set changes how the operations are encoded (three-operand
// VEX forms, BMI's bit operations, wider moves), never which roundings happen
// (tests/test_kernel_variants.cpp compares every entry point of every variant this CPU runs).
//
// Linkage: everything the kernel's headers define is internal (anonymous namespaces) or, where
// a type must be shared, inline code that is always inlined (BarycentricMap, which OneToMany
// holds) or templated on the variant (PolyhedronBuilder<Variant>, and PolygonBuilder<Variant>
// in tri_kernel.hpp); what this file defines lives in tetia::detail::TETIA_KERNEL_VARIANT. So no function the
// variant's object file defines can be bound by the linker to another object's call: a
// baseline caller never runs AVX2 code. The build checks it (cmake/check_variant_symbols.cmake:
// every code symbol the AVX2 object defines or exports carries its namespace's name).
#pragma once

#ifndef TETIA_KERNEL_VARIANT
#error "define TETIA_KERNEL_VARIANT (the variant's namespace) before including entry_points.hpp"
#endif

#include <cmath>

#include "exact_fallback.hpp"
#include "frame.hpp"
#include "kernel.hpp"
#include "kernel_result.hpp"
#include "kernel_variant.hpp"
#include "moments.hpp"
#include "one_to_many.hpp"
#include "polyhedron_builder.hpp"
#include "solve.hpp"
#include "tetia/tet_intersection.hpp"

namespace tetia::detail::TETIA_KERNEL_VARIANT {

struct Tag {};  // names this variant's PolyhedronBuilder
using Builder = PolyhedronBuilder<Tag>;

// The exact last resort's moments (finite input; non-finite is empty).
inline Moments exact_moments(const Tet& U, const Tet& V) {
  if (!finite(U) || !finite(V)) return {};
  ExactPolyhedron x;
  exact_polyhedron(U, V, x);
  return x.moments;
}

// The faces of t on which the polytope has a facet: labels 4-7 (planes of Y) when t was the
// reference, 0-3 (faces of X) when s was. Where int(s) crosses the interior of t's face k, a
// small ball around the crossing lies in s and half of it in t, so s n t has a facet on that
// face; without one, no path inside s crosses it. The labels are trusted only when the sign of
// the reference's det6, and so of its map, is certain (kSignCertainQuality).
inline unsigned faces_with_facets(const Frame& fr, const KernelResult& res, bool ok, double quality_s, double quality_t) {
  if (!ok || res.num_corners == 0 || !((fr.swapped ? quality_s : quality_t) > kSignCertainQuality)) return 0xFu;
  const int base = fr.swapped ? 0 : 4;
  unsigned faces = 0;
  for (int k = 0; k < 4; ++k) faces |= unsigned(res.on_plane[base + k] != 0) << k;
  return faces | OneToMany::kPlanesTested;
}

// tetia::intersect.
Polyhedron kernel_intersect(const Tet& U, const Tet& V, IntersectionStats* stats) {
  Polyhedron P;  // one object on every path, so that it is constructed in place (no copy)
  if (stats) ++stats->calls;
  Frame fr;
  KernelResult res;
  Tet scaled[2];
  int scale = 0;
  const Outcome outcome = solve<true, true>(U, V, fr, res, scaled, scale, stats);
  if (outcome == Outcome::empty) return P;
  if (outcome == Outcome::kernel) [[likely]] {
    if (Builder::fill(P, fr, res, stats != nullptr, scale)) return P;
    // The facets could not be oriented consistently (labels and geometry disagree): the exact
    // polytope's corners and facets, with the kernel's moments, which the other entry points
    // return (and which passed solve_with's tests).
    if (stats) ++stats->inconsistencies;
    const Moments m = scale == 0 ? original_moments(fr, res) : Builder::unscaled(original_moments(fr, res), scale);
    ExactPolyhedron x;
    exact_polyhedron(U, V, x);
    Builder::fill_exact(P, x);
    Builder::set_moments(P, m);
    if (stats) ++stats->exact_fallbacks;
    return P;
  }
  if (!finite(U) || !finite(V)) return P;
  if (stats) ++stats->exact_fallbacks;
  ExactPolyhedron x;
  exact_polyhedron(U, V, x);
  // Where the exact polytope is not simple (a degenerate intersection: a corner on four planes)
  // its corners cannot carry the three labels of a simple polytope; the kernel's polytope, if it
  // closed (the volume test is what rejected it), has them, with coincident corners: its
  // corners and facets then, with the exact moments.
  if (!x.simple && res.num_corners > 0 && Builder::fill(P, fr, res, stats != nullptr, scale)) {
    Builder::set_moments(P, x.moments);
    return P;
  }
  Builder::fill_exact(P, x);
  return P;
}

// tetia::intersection_volume.
double kernel_volume(const Tet& U, const Tet& V) {
  Frame fr;
  KernelResult res;
  Tet scaled[2];
  int scale = 0;
  switch (solve<false, false>(U, V, fr, res, scaled, scale, nullptr)) {
    case Outcome::empty:
      return 0.0;
    case Outcome::kernel: {
      const double v = original_volume(fr, res);
      return scale == 0 ? v : std::ldexp(v, -3 * scale);
    }
    default:
      return exact_moments(U, V).volume;
  }
}

// tetia::intersection_moments.
Moments kernel_moments(const Tet& U, const Tet& V) {
  Frame fr;
  KernelResult res;
  Tet scaled[2];
  int scale = 0;
  switch (solve<true, false>(U, V, fr, res, scaled, scale, nullptr)) {
    case Outcome::empty:
      return {};
    case Outcome::kernel:
      if (original_volume(fr, res) == 0.0) return {};  // +0 moments however the kernel summed zeros
      return scale == 0 ? original_moments(fr, res) : Builder::unscaled(original_moments(fr, res), scale);
    default:
      return exact_moments(U, V);
  }
}

// OneToMany::moments.
Moments one_to_many_moments(const OneToMany& s, const Tet& t, const Conditioning& ct, unsigned* t_faces) {
  Frame fr;
  KernelResult res;
  const auto make = [&](Frame& f, bool other) {
    return frame_from(s.source(), s.source_conditioning(), &s.map(), t, ct, f, other);
  };
  const Outcome outcome = solve_with<true, false>(make, fr, res, nullptr);
  if (outcome == Outcome::rescale || outcome == Outcome::exact) [[unlikely]] {
    // As the pairwise entry point, bit for bit (it scales, or computes exactly, likewise).
    if (t_faces) *t_faces = 0xFu;
    return kernel_moments(s.source(), t);
  }
  const bool ok = outcome == Outcome::kernel;
  if (t_faces) *t_faces = faces_with_facets(fr, res, ok, s.source_conditioning().quality, ct.quality);
  if (!ok || original_volume(fr, res) == 0.0) return {};  // +0 moments, as intersection_moments
  return original_moments(fr, res);
}

// OneToMany::intersect.
Moments one_to_many_intersect(const OneToMany& s, const Tet& t, const Conditioning& ct, Polyhedron& out,
                              unsigned* t_faces) {
  Frame fr;
  KernelResult res;
  const auto make = [&](Frame& f, bool other) {
    return frame_from(s.source(), s.source_conditioning(), &s.map(), t, ct, f, other);
  };
  const Outcome outcome = solve_with<true, true>(make, fr, res, nullptr);
  const bool ok = outcome == Outcome::kernel;
  if (t_faces) *t_faces = faces_with_facets(fr, res, ok, s.source_conditioning().quality, ct.quality);
  if (outcome == Outcome::empty || (ok && res.num_corners == 0)) return {};  // `out` untouched
  // The kernel's polytope as the pairwise entry point fills it; the rest (rescaled, exact, or
  // facets that do not orient) as the pairwise entry point computes it, bit for bit.
  if (!ok || !Builder::fill(out, fr, res, false, 0)) [[unlikely]]
    out = kernel_intersect(s.source(), t, nullptr);
  return out.moments();
}

// The 2D kernel's entry points, defined in this variant's compilation of tri_kernel.hpp.
double tri_area(const Triangle& A, const Triangle& B);
Moments2 tri_moments(const Triangle& A, const Triangle& B);
Polygon tri_intersect(const Triangle& A, const Triangle& B, TriIntersectionStats* stats);

extern const KernelVariant variant;
const KernelVariant variant = {TETIA_KERNEL_VARIANT_NAME, kernel_volume, kernel_moments, kernel_intersect,
                               one_to_many_moments, one_to_many_intersect, tri_area, tri_moments, tri_intersect};

}  // namespace tetia::detail::TETIA_KERNEL_VARIANT
