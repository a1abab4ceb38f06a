// The 2D kernel's entry points: the kernel itself is src/kernel/tri_kernel.hpp (Algorithm 1,
// PANG2, built like the 3D kernel), compiled here for the baseline and in
// src/kernel/tri_intersection_x86_64_v3.cpp for x86-64-v3; the public functions call the variant
// chosen at run time (src/kernel/kernel_variant.hpp). Also the Polygon's own methods.
#include "tetia/tri_intersection.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "kernel/kernel_variant.hpp"
#include "tetia/kernel_trace.hpp"

#define TETIA_KERNEL_VARIANT baseline
#include "kernel/tri_kernel.hpp"

namespace tetia {

TriIntersectionStats& TriIntersectionStats::operator+=(const TriIntersectionStats& o) {
  edge_inherited += o.edge_inherited;
  edge_paired += o.edge_paired;
  edge_straight_line += o.edge_straight_line;
  edge_computed += o.edge_computed;
  corner_coordinates += o.corner_coordinates;
  guardrail_clamps += o.guardrail_clamps;
  reference_swaps += o.reference_swaps;
  inconsistencies += o.inconsistencies;
  retries += o.retries;
  refined += o.refined;
  rescaled += o.rescaled;
  exact_fallbacks += o.exact_fallbacks;
  certified += o.certified;
  checked += o.checked;
  check_rejected += o.check_rejected;
  calls += o.calls;
  return *this;
}

std::vector<std::array<std::uint8_t, 3>> Polygon::triangle_corners() const {
  std::vector<std::array<std::uint8_t, 3>> out;
  if (num_corners_ < 3) return out;
  out.reserve(static_cast<std::size_t>(num_corners_ - 2));
  const Vec2 p0 = corners_[0].point;
  for (int k = 1; k + 1 < num_corners_; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (orient2d(p0, corners_[i].point, corners_[i + 1].point) > 0.0)
      out.push_back({0, static_cast<std::uint8_t>(k), static_cast<std::uint8_t>(k + 1)});
  }
  return out;
}

std::vector<Triangle> Polygon::triangles() const {
  std::vector<Triangle> out;
  for (const auto& t : triangle_corners()) out.push_back({corners_[t[0]].point, corners_[t[1]].point, corners_[t[2]].point});
  return out;
}

namespace detail {

TriClipTrace tri_clip_trace(const Triangle& A, const Triangle& B) {
  TriClipTrace t;
  detail2::Frame fr;
  Triangle scaled_a = A, scaled_b = B;
  int scale = 0;
  if (detail2::make_frame(A, B, fr) == detail2::FrameStatus::rescale) {  // as solve() scales
    scale = detail2::rescale_exponent(fr);
    if (!scaled_exactly(&A[0].x, 6, scale, &scaled_a[0].x) || !scaled_exactly(&B[0].x, 6, scale, &scaled_b[0].x))
      return t;
  }
  Triangle a, b;
  std::uint8_t perm[3];
  detail2::canonical_order(scaled_a, a, perm);
  detail2::canonical_order(scaled_b, b, perm);
  detail2::ClipEnclosure e;
  detail2::kernel_area_stands(a, b, 0.0, &e);
  t.enclosed = e.found;
  // Scaled back, the centre and the radius are rounded again (in the subnormal range, to a
  // multiple of 2^-1074): the radius grows by 2^-1074 for both.
  t.area = std::ldexp(e.area, -2 * scale);
  t.error = std::ldexp(e.error, -2 * scale) + (scale != 0 ? 0x1p-1074 : 0.0);
  t.relative = e.error / (0.5 * (e.det - e.det_error));
  t.fraction = e.fraction;
  return t;
}

}  // namespace detail

Polygon intersect(const Triangle& A, const Triangle& B, TriIntersectionStats* stats) {
  return detail::kernel_variant().tri_intersect(A, B, stats);
}

Moments2 intersection_moments(const Triangle& A, const Triangle& B) { return detail::kernel_variant().tri_moments(A, B); }

double intersection_area(const Triangle& A, const Triangle& B) { return detail::kernel_variant().tri_area(A, B); }

}  // namespace tetia
