// Algorithm 2 of McCoid & Gander, "A provably robust algorithm for tetrahedron-tetrahedron
// intersections in floating-point arithmetic" (ACM TOMS, submitted), with the errata of
// shared/paper/ERRATA.md. Section numbers, lemmas and equations below refer to that paper.
//
// Notation (as in the paper): V is mapped to the reference tetrahedron Y, U to X. Every vertex
// x_i of X has barycentric coordinates C[i][p], p = 0..3 standing for (w, x, y, z); coordinate p
// is the barycentric coordinate of V's vertex p, and P_p = {p = 0} is the face of V opposite its
// vertex p. Signs are binary: sign(v) = 1 for v >= 0, 0 for v < 0 (Section 1); a zero is
// treated as "inside by an infinitesimal", which is what makes touching configurations
// consistent instead of special.
//
// The shape of the result is decided from signs only; a coordinate is evaluated only when a
// sign cannot be inherited, paired or forced, and a corner's coordinates only when it lies on Y.
// Every sign that two parts of the algorithm could compute separately is computed once and
// shared, which is what Theorem 6 needs: the corners then carry the labels of a simple
// polytope, and the facets follow from the labels.
//
// Implementation: the four binary signs of a point are kept as a 4-bit mask (bit p = sign of
// coordinate p), so inheritance and the sign tests of lines 8 and 18 are bit operations. Nothing
// here allocates (but the exact last resort); all arrays are sized by the worst case.
//
// The kernel is one translation unit, this file, so that everything inlined stays inlined; it
// is split into headers by the steps of Algorithm 2 (all in src/kernel/):
//   tables.hpp              constant index tables (edges, faces, lines; edge orders, triples)
//   kernel_result.hpp       RawCorner, KernelResult: what the kernel produces
//   lanes.hpp               Quad and its SSE2 or scalar lane operations
//   frame.hpp               Section 2, line 1: conditioning, choice of the reference, X
//   barycentric_map.hpp     Section 2, eq. (1): the map to barycentric coordinates
//   kernel.hpp              class Kernel: state, binary signs of X's vertices, run
//   algorithm2.hpp          run_steps: the steps in order; Sections 3.1 and 3.4
//   edge_signs.hpp          Section 3.2, lines 7-17: edges of X against planes of Y
//   face_signs.hpp          Section 3.3, line 18: faces of X against lines of Y
//   nonconvex_repair.hpp    the non-convex case of Theorem 6's proof (Fig. 6): a twisted
//                           cross-section, its edge signs decided again with exact minors
//   minor_sign.hpp          the exact sign of a 2x2 minor where its products tie
//   corner_coordinates.hpp  eqs. (2), (4), (5) and the guardrail of Section 4.1.1
//   facets.hpp              the facets from the corners' labels
//   orientation.hpp         the facets oriented outward
//   moments.hpp             volume and first moments; eq. (3) back to the caller's frame
//   fan.hpp                 the pyramids over one facet (shared with refined_clip.hpp)
//   error_estimate.hpp      the double result's error relative to the smaller tetrahedron
//   solve.hpp               one pair from start to end, with the repair (other reference),
//                           the tests that certify the result, and the rescaling
//   polyhedron_builder.hpp  the result as a Polyhedron
//   one_to_many.hpp         one tetrahedron against many (the supermesh)
//   tet_intersection.cpp    the entry points (this file)
// and, shared with the 2D kernel (src/tri_intersection.cpp), what makes every finite input
// work (docs/architecture.md, "Every finite input"):
//   rescale.hpp             exact power-of-two scaling of extreme sizes
//   exact_fallback.hpp      the exact last resort (GMP; implemented in src/exact.cpp)
//   refined_clip.hpp        results the kernel's estimate does not certify to 1e-12 of the
//                           smaller tetrahedron, recomputed in that tetrahedron's frame (3D)
//   exact_sign.hpp          exact orient2d signs and values in double arithmetic (2D), and
//                           the error-free products minor_sign.hpp uses
#include "tetia/tet_intersection.hpp"

#include <algorithm>
#include <bit>
#include <new>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tetia/kernel_trace.hpp"

#include "algorithm2.hpp"
#include "barycentric_map.hpp"  // BarycentricMap, TETIA_KERNEL_SSE2 (SSE2 or scalar loops)
#include "facets.hpp"
#include "frame.hpp"
#include "kernel.hpp"
#include "kernel_result.hpp"
#include "moments.hpp"
#include "one_to_many.hpp"
#include "orientation.hpp"
#include "polyhedron_builder.hpp"
#include "solve.hpp"

namespace tetia {

IntersectionStats& IntersectionStats::operator+=(const IntersectionStats& o) {
  edge_inherited += o.edge_inherited;
  edge_paired += o.edge_paired;
  edge_straight_line += o.edge_straight_line;
  edge_computed += o.edge_computed;
  face_inherited += o.face_inherited;
  face_paired += o.face_paired;
  face_computed += o.face_computed;
  nonconvex_lines += o.nonconvex_lines;
  corner_coordinates += o.corner_coordinates;
  guardrail_clamps += o.guardrail_clamps;
  reference_swaps += o.reference_swaps;
  inconsistencies += o.inconsistencies;
  retries += o.retries;
  rescaled += o.rescaled;
  refined += o.refined;
  exact_fallbacks += o.exact_fallbacks;
  calls += o.calls;
  return *this;
}

namespace detail {

Conditioning conditioning(const Tet& t) {
  Conditioning c, unused;  // both lanes compute t: lane for lane what a pair computes
  shape_qualities(t, t, c, unused);
  return c;
}

void conditioning(const Tet& a, const Tet& b, Conditioning& ca, Conditioning& cb) { shape_qualities(a, b, ca, cb); }

OneToMany::OneToMany(const Tet& s) : s_(s), cs_(conditioning(s)), map_(s, cs_.inv_det6) {}

// The exact last resort's moments (finite input; non-finite is empty).
Moments exact_moments(const Tet& U, const Tet& V) {
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
unsigned faces_with_facets(const Frame& fr, const KernelResult& res, bool ok, double quality_s, double quality_t) {
  if (!ok || res.num_corners == 0 || !((fr.swapped ? quality_s : quality_t) > kSignCertainQuality)) return 0xFu;
  const int base = fr.swapped ? 0 : 4;
  unsigned faces = 0;
  for (int k = 0; k < 4; ++k) faces |= unsigned(res.on_plane[base + k] != 0) << k;
  return faces | OneToMany::kPlanesTested;
}

Moments OneToMany::moments(const Tet& t, const Conditioning& ct, unsigned* t_faces) const {
  Frame fr;
  KernelResult res;
  const auto make = [&](Frame& f, bool other) { return frame_from(s_, cs_, &map_, t, ct, f, other); };
  const Outcome outcome = solve_with<true, false>(make, fr, res, nullptr);
  if (outcome == Outcome::rescale || outcome == Outcome::exact) [[unlikely]] {
    // As the pairwise entry point, bit for bit (it scales, or computes exactly, likewise).
    if (t_faces) *t_faces = 0xFu;
    return intersection_moments(s_, t);
  }
  const bool ok = outcome == Outcome::kernel;
  if (t_faces) *t_faces = faces_with_facets(fr, res, ok, cs_.quality, ct.quality);
  if (!ok || original_volume(fr, res) == 0.0) return {};  // +0 moments, as intersection_moments
  return original_moments(fr, res);
}

Moments OneToMany::intersect(const Tet& t, const Conditioning& ct, Polyhedron& out, unsigned* t_faces) const {
  Frame fr;
  KernelResult res;
  const auto make = [&](Frame& f, bool other) { return frame_from(s_, cs_, &map_, t, ct, f, other); };
  const Outcome outcome = solve_with<true, true>(make, fr, res, nullptr);
  const bool ok = outcome == Outcome::kernel;
  if (t_faces) *t_faces = faces_with_facets(fr, res, ok, cs_.quality, ct.quality);
  if (outcome == Outcome::empty || (ok && res.num_corners == 0)) return {};  // `out` untouched
  // The kernel's polytope as the pairwise entry point fills it; the rest (rescaled, exact, or
  // facets that do not orient) as the pairwise entry point computes it, bit for bit.
  if (!ok || !PolyhedronBuilder::fill(out, fr, res, false, 0)) [[unlikely]]
    out = tetia::intersect(s_, t);
  return out.moments();
}

KernelEstimate kernel_estimate(const Tet& U, const Tet& V) {
  KernelEstimate e;
  Frame fr;
  KernelResult res;
  if (make_frame(U, V, fr) != FrameStatus::ok || fr.flat_to_rounding) return e;
  if (!run_kernel<false, false>(fr.C, res, nullptr)) return e;
  e.ran = true;
  e.x_inside = res.x_inside;
  e.empty = res.num_corners == 0;
  e.volume = original_volume(fr, res);
  e.a_priori = a_priori_estimate(fr);
  e.estimate = e.a_priori;
  if (res.num_corners > 0 && !res.x_inside) e.estimate = std::min(e.estimate, a_posteriori_estimate(fr, res));
  e.snapped = has_zero_coordinate(fr.C);
  return e;
}

void trace_kernel(const double (&C)[4][4], KernelTrace& t, IntersectionStats* stats) {
  Kernel<true, true> k(C, stats);
  KernelResult res;
  const bool ran = k.run(res);
  for (int i = 0; i < 4; ++i)
    for (int p = 0; p < 4; ++p) res.coordinate_scale = std::max(res.coordinate_scale, std::abs(C[i][p]));
  k.export_signs(t);
  t.num_corners = res.num_corners;
  for (int c = 0; c < res.num_corners; ++c)
    for (int x = 0; x < 4; ++x) {
      if (x < 3) t.labels[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].labels[x];
      t.bary[static_cast<std::size_t>(c)][static_cast<std::size_t>(x)] = res.corners[c].bary[x];
    }
  t.consistent = ran && build_facets<kFacetsOnly>(res);
  if (t.consistent) reference_moments<true>(res);
  t.consistent = t.consistent && (res.num_facets == 0 || orient_facets(res, true));
  t.num_facets = res.num_facets;
  t.volume = res.ref_volume;
}

}  // namespace detail

Polyhedron intersect(const Tet& U, const Tet& V, IntersectionStats* stats) {
  using detail::Outcome;
  Polyhedron P;  // one object on every path, so that it is constructed in place (no copy)
  if (stats) ++stats->calls;
  detail::Frame fr;
  detail::KernelResult res;
  Tet scaled[2];
  int scale = 0;
  const Outcome outcome = detail::solve<true, true>(U, V, fr, res, scaled, scale, stats);
  if (outcome == Outcome::empty) return P;
  if (outcome == Outcome::kernel) [[likely]] {
    if (PolyhedronBuilder::fill(P, fr, res, stats != nullptr, scale)) return P;
    // The facets could not be oriented consistently (labels and geometry disagree): the exact
    // polytope's corners and facets, with the kernel's moments, which the other entry points
    // return (and which passed solve_with's tests).
    if (stats) ++stats->inconsistencies;
    const Moments m = scale == 0 ? detail::original_moments(fr, res)
                                 : PolyhedronBuilder::unscaled(detail::original_moments(fr, res), scale);
    detail::ExactPolyhedron x;
    detail::exact_polyhedron(U, V, x);
    PolyhedronBuilder::fill_exact(P, x);
    PolyhedronBuilder::set_moments(P, m);
    if (stats) ++stats->exact_fallbacks;
    return P;
  }
  if (!detail::finite(U) || !detail::finite(V)) return P;
  if (stats) ++stats->exact_fallbacks;
  detail::ExactPolyhedron x;
  detail::exact_polyhedron(U, V, x);
  // Where the exact polytope is not simple (a degenerate intersection: a corner on four planes)
  // its corners cannot carry the three labels of a simple polytope; the kernel's polytope, if it
  // closed (the volume test is what rejected it), has them, with coincident corners: its
  // corners and facets then, with the exact moments.
  if (!x.simple && res.num_corners > 0 && PolyhedronBuilder::fill(P, fr, res, stats != nullptr, scale)) {
    PolyhedronBuilder::set_moments(P, x.moments);
    return P;
  }
  PolyhedronBuilder::fill_exact(P, x);
  return P;
}

double intersection_volume(const Tet& U, const Tet& V) {
  using detail::Outcome;
  detail::Frame fr;
  detail::KernelResult res;
  Tet scaled[2];
  int scale = 0;
  switch (detail::solve<false, false>(U, V, fr, res, scaled, scale, nullptr)) {
    case Outcome::empty:
      return 0.0;
    case Outcome::kernel: {
      const double v = detail::original_volume(fr, res);
      return scale == 0 ? v : std::ldexp(v, -3 * scale);
    }
    default:
      return detail::exact_moments(U, V).volume;
  }
}

Moments intersection_moments(const Tet& U, const Tet& V) {
  using detail::Outcome;
  detail::Frame fr;
  detail::KernelResult res;
  Tet scaled[2];
  int scale = 0;
  switch (detail::solve<true, false>(U, V, fr, res, scaled, scale, nullptr)) {
    case Outcome::empty:
      return {};
    case Outcome::kernel:
      if (detail::original_volume(fr, res) == 0.0) return {};  // +0 moments however the kernel summed zeros
      return scale == 0 ? detail::original_moments(fr, res)
                        : PolyhedronBuilder::unscaled(detail::original_moments(fr, res), scale);
    default:
      return detail::exact_moments(U, V);
  }
}

}  // namespace tetia
