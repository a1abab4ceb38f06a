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
// The kernel is one translation unit, this file, so that everything inlined stays inlined (one
// more, tet_intersection_x86_64_v3.cpp, compiles its entry points for AVX2); it is split into
// headers by the steps of Algorithm 2 (all in src/kernel/):
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
//   entry_points.hpp        the entry points, compiled once per instruction set: here (the
//                           baseline) and in tet_intersection_x86_64_v3.cpp (AVX2)
//   kernel_variant.hpp      the choice among those compilations at run time
//   tet_intersection.cpp    this file: the baseline's compilation, the choice, and what is
//                           computed once per tetrahedron or for the tests
// and, shared with the 2D kernel (src/kernel/tri_kernel.hpp), what makes every finite input
// work (docs/architecture.md, "Every finite input"):
//   rescale.hpp             exact power-of-two scaling of extreme sizes
//   exact_fallback.hpp      the exact last resort (GMP; implemented in src/exact.cpp)
//   refined_clip.hpp        results the kernel's estimate does not certify to 1e-12 of the
//                           smaller tetrahedron, recomputed in that tetrahedron's frame (3D)
//   exact_sign.hpp          exact orient2d signs and values in double arithmetic (2D), and
//                           the error-free products minor_sign.hpp uses
#include "tetia/tet_intersection.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <string_view>

#if defined(TETIA_KERNEL_X86_64_V3)
#include <cpuid.h>
#endif

#include "tetia/kernel_trace.hpp"

#define TETIA_KERNEL_VARIANT baseline
#define TETIA_KERNEL_VARIANT_NAME "baseline"
#include "entry_points.hpp"

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

namespace {

#if defined(TETIA_KERNEL_X86_64_V3)
// Whether this CPU runs what the x86-64-v3 variant is compiled for (CMakeLists.txt:
// -march=x86-64-v3 -mno-fma): the x86-64-v2 and -v3 levels of the x86-64 psABI but FMA, from
// CPUID, and the operating system saving the SSE and AVX registers' state (OSXSAVE, then XCR0
// bits 1 and 2). CPUID directly: the compilers' __builtin_cpu_supports does not name every one.
bool cpu_runs_x86_64_v3() {
  unsigned a, b, c, d;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
  const auto bit = [](unsigned reg, int k) { return ((reg >> k) & 1u) != 0; };
  const bool leaf1 = bit(c, 0) /* SSE3 */ && bit(c, 9) /* SSSE3 */ && bit(c, 13) /* CMPXCHG16B */ &&
                     bit(c, 19) /* SSE4.1 */ && bit(c, 20) /* SSE4.2 */ && bit(c, 22) /* MOVBE */ &&
                     bit(c, 23) /* POPCNT */ && bit(c, 27) /* OSXSAVE */ && bit(c, 28) /* AVX */ &&
                     bit(c, 29) /* F16C */;
  if (!leaf1) return false;
  unsigned xcr0_lo, xcr0_hi;
  __asm__("xgetbv" : "=a"(xcr0_lo), "=d"(xcr0_hi) : "c"(0u));
  if ((xcr0_lo & 0x6u) != 0x6u) return false;  // XMM and YMM state
  if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return false;
  if (!(bit(b, 3) /* BMI1 */ && bit(b, 5) /* AVX2 */ && bit(b, 8) /* BMI2 */)) return false;
  if (!__get_cpuid(0x80000001u, &a, &b, &c, &d)) return false;
  return bit(c, 0) /* LAHF/SAHF */ && bit(c, 5) /* LZCNT */;
}
#endif

// The variants this CPU runs, the baseline first, into `out`; returns how many. No allocation:
// the choice may be made within a kernel call (one that comes before the library's
// initializer), which must not allocate either.
constexpr int kMaxVariants = 2;
int runnable_variants(const KernelVariant* (&out)[kMaxVariants]) {
  int n = 0;
  out[n++] = &baseline::variant;
#if defined(TETIA_KERNEL_X86_64_V3)
  if (cpu_runs_x86_64_v3()) out[n++] = &x86_64_v3::variant;
#endif
  return n;
}

const KernelVariant& choose_variant() {
  const KernelVariant* runnable[kMaxVariants];
  const int n = runnable_variants(runnable);
  if (const char* asked = std::getenv("TETIA_KERNEL_VARIANT"))
    for (int k = 0; k < n; ++k)
      if (std::string_view(asked) == runnable[k]->name) return *runnable[k];
  return *runnable[n - 1];  // the last is the fastest this CPU runs
}

}  // namespace

std::vector<const KernelVariant*> kernel_variants() {
  const KernelVariant* runnable[kMaxVariants];
  const int n = runnable_variants(runnable);
  return {runnable, runnable + n};
}

std::atomic<const KernelVariant*> chosen_kernel_variant{nullptr};

const KernelVariant& choose_kernel_variant() {
  // Every thread that gets here chooses the same (CPUID and the environment), so a race only
  // stores the same pointer twice; the tables themselves are constants.
  const KernelVariant& v = choose_variant();
  chosen_kernel_variant.store(&v, std::memory_order_relaxed);
  return v;
}

namespace {
// Chosen when the library is loaded (dynamic initialization), so that the entry points find it
// set; a call from another library's initializer that runs first chooses on the spot.
[[maybe_unused]] const bool chosen_at_load = (choose_kernel_variant(), true);
}  // namespace

Conditioning conditioning(const Tet& t) {
  Conditioning c, unused;  // both lanes compute t: lane for lane what a pair computes
  shape_qualities(t, t, c, unused);
  return c;
}

void conditioning(const Tet& a, const Tet& b, Conditioning& ca, Conditioning& cb) { shape_qualities(a, b, ca, cb); }

OneToMany::OneToMany(const Tet& s)
    : s_(s), cs_(conditioning(s)), map_(s, cs_.inv_det6), variant_(&kernel_variant()) {}

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
  if (res.num_corners > 0 && !res.x_inside && a_posteriori_worthwhile(fr, res))
    e.estimate = std::min(e.estimate, a_posteriori_estimate(fr, res));
  e.snapped = has_zero_coordinate(fr.C);
  return e;
}

NearCoverTrace near_cover_trace(const Tet& S, const Tet& B) {
  NearCoverTrace t;
  const Vec3 e1 = B[1] - B[0], e2 = B[2] - B[0], e3 = B[3] - B[0];
  const double det6_B = dot(cross(e1, e2), e3);  // its sign only
  NearCoverReport report;
  t.certified = refined_moments<true>(S, B, det6_B, t.moments, &report);
  t.tried = report.tried;
  t.decided = report.decided;
  t.bound = report.bound;
  NearCoverReport clip_report;
  t.clip_certified = refined_moments<true>(S, B, det6_B, t.clipped, &clip_report, true);
  t.clip_bound = clip_report.clip_bound;
  t.clip_separated = clip_report.separated;
  return t;
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
  return detail::kernel_variant().intersect(U, V, stats);
}

double intersection_volume(const Tet& U, const Tet& V) { return detail::kernel_variant().volume(U, V); }

Moments intersection_moments(const Tet& U, const Tet& V) { return detail::kernel_variant().moments(U, V); }

}  // namespace tetia
