// src/kernel/lanes.hpp -- Quad, the four barycentric coordinates of a point, and the lane
// operations on it (SSE2 where available, scalar loops otherwise; the same arithmetic either
// way), with the lane tables of the SSE2 path.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <cstdint>

#include "barycentric_map.hpp"  // TETIA_KERNEL_SSE2 (SSE2 or scalar loops)
#include "tables.hpp"

namespace tetia::detail {

namespace {

// Four coordinates of a point, held in two SSE2 registers where available, in one AVX register
// in the x86-64-v3 variant (whole-vector loads and stores: a coordinate cleared in memory right
// before a vector load of the same point would stall the load). Every operation is the scalar
// one, lane by lane, so the three forms give the same bits.
#if TETIA_KERNEL_SSE2
// kKeepLanes[m]: all ones in the lanes not in m (m: 4-bit mask of lanes to clear); 32-byte
// aligned for the AVX load.
struct KeepLanes {
  alignas(32) std::uint64_t v[16][4];
};
constexpr KeepLanes make_keep_lanes() {
  KeepLanes k{};
  for (unsigned m = 0; m < 16; ++m)
    for (int p = 0; p < 4; ++p) k.v[m][p] = bit(m, p) ? 0u : ~std::uint64_t{0};
  return k;
}
constexpr KeepLanes kKeepLanes = make_keep_lanes();
// kFlipLanes[s]: for a sign mask s, -0.0 in the lanes of the pairs (y, x) of
// order_edge_by_pairs (in the order of kLines) whose y-bit in s is 0, else +0.0.
struct FlipLanes {
  alignas(16) double v[16][6];
};
constexpr FlipLanes make_flip_lanes() {
  FlipLanes t{};
  for (unsigned m = 0; m < 16; ++m)
    for (int L = 0; L < 6; ++L) t.v[m][L] = bit(kPairLanes.y[m], L) ? 0.0 : -0.0;
  return t;
}
constexpr FlipLanes kFlipLanes = make_flip_lanes();
#endif
#if TETIA_KERNEL_AVX
struct Quad {
  __m256d v;
};
inline Quad zero4() { return {_mm256_setzero_pd()}; }
inline Quad load4(const double* p) { return {_mm256_loadu_pd(p)}; }
inline void store4(double* p, const Quad& q) { _mm256_storeu_pd(p, q.v); }
// s + t (o - s)
inline Quad lerp(const Quad& s, const Quad& o, double t) {
  return {_mm256_add_pd(s.v, _mm256_mul_pd(_mm256_set1_pd(t), _mm256_sub_pd(o.v, s.v)))};
}
// The lanes in m set to +0.0.
inline Quad clear_lanes(const Quad& q, unsigned m) {
  return {_mm256_and_pd(q.v, _mm256_castsi256_pd(_mm256_load_si256(reinterpret_cast<const __m256i*>(kKeepLanes.v[m]))))};
}
// Bit p: lane p >= 0 (the predicate of _mm_cmpge_pd).
inline unsigned nonneg_lanes(const Quad& q) {
  return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(q.v, _mm256_setzero_pd(), _CMP_GE_OS)));
}
// Bit p: lane p == 0 (the predicate of _mm_cmpeq_pd).
inline unsigned zero_lanes(const Quad& q) {
  return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(q.v, _mm256_setzero_pd(), _CMP_EQ_OQ)));
}
inline Quad mul4(const Quad& q, double x) { return {_mm256_mul_pd(q.v, _mm256_set1_pd(x))}; }
inline Quad div4(const Quad& q, double x) { return {_mm256_div_pd(q.v, _mm256_set1_pd(x))}; }
inline Quad set4(double x) { return {_mm256_set1_pd(x)}; }
#elif TETIA_KERNEL_SSE2
struct Quad {
  __m128d lo, hi;
};
inline Quad zero4() { return {_mm_setzero_pd(), _mm_setzero_pd()}; }
inline Quad load4(const double* p) { return {_mm_loadu_pd(p), _mm_loadu_pd(p + 2)}; }
inline void store4(double* p, const Quad& q) {
  _mm_storeu_pd(p, q.lo);
  _mm_storeu_pd(p + 2, q.hi);
}
// s + t (o - s)
inline Quad lerp(const Quad& s, const Quad& o, double t) {
  const __m128d tt = _mm_set1_pd(t);
  return {_mm_add_pd(s.lo, _mm_mul_pd(tt, _mm_sub_pd(o.lo, s.lo))), _mm_add_pd(s.hi, _mm_mul_pd(tt, _mm_sub_pd(o.hi, s.hi)))};
}
// The lanes in m set to +0.0.
inline Quad clear_lanes(const Quad& q, unsigned m) {
  const std::uint64_t* k = kKeepLanes.v[m];
  return {_mm_and_pd(q.lo, _mm_castsi128_pd(_mm_load_si128(reinterpret_cast<const __m128i*>(k)))),
          _mm_and_pd(q.hi, _mm_castsi128_pd(_mm_load_si128(reinterpret_cast<const __m128i*>(k + 2))))};
}
// Bit p: lane p >= 0.
inline unsigned nonneg_lanes(const Quad& q) {
  const __m128d z = _mm_setzero_pd();
  return unsigned(_mm_movemask_pd(_mm_cmpge_pd(q.lo, z))) | unsigned(_mm_movemask_pd(_mm_cmpge_pd(q.hi, z))) << 2;
}
// Bit p: lane p == 0.
inline unsigned zero_lanes(const Quad& q) {
  const __m128d z = _mm_setzero_pd();
  return unsigned(_mm_movemask_pd(_mm_cmpeq_pd(q.lo, z))) | unsigned(_mm_movemask_pd(_mm_cmpeq_pd(q.hi, z))) << 2;
}
inline Quad mul4(const Quad& q, double x) {
  const __m128d xx = _mm_set1_pd(x);
  return {_mm_mul_pd(q.lo, xx), _mm_mul_pd(q.hi, xx)};
}
inline Quad div4(const Quad& q, double x) {
  const __m128d xx = _mm_set1_pd(x);
  return {_mm_div_pd(q.lo, xx), _mm_div_pd(q.hi, xx)};
}
inline Quad set4(double x) { return {_mm_set1_pd(x), _mm_set1_pd(x)}; }
#else
struct Quad {
  double v[4];
};
inline Quad zero4() { return {{0.0, 0.0, 0.0, 0.0}}; }
inline Quad load4(const double* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline void store4(double* p, const Quad& q) {
  for (int k = 0; k < 4; ++k) p[k] = q.v[k];
}
inline Quad lerp(const Quad& s, const Quad& o, double t) {
  Quad r;
  for (int k = 0; k < 4; ++k) r.v[k] = s.v[k] + t * (o.v[k] - s.v[k]);
  return r;
}
inline Quad clear_lanes(Quad q, unsigned m) {
  for (int k = 0; k < 4; ++k)
    if (bit(m, k)) q.v[k] = 0.0;
  return q;
}
inline unsigned nonneg_lanes(const Quad& q) {
  unsigned r = 0;
  for (int k = 0; k < 4; ++k) r |= unsigned(q.v[k] >= 0.0) << k;
  return r;
}
inline unsigned zero_lanes(const Quad& q) {
  unsigned r = 0;
  for (int k = 0; k < 4; ++k) r |= unsigned(q.v[k] == 0.0) << k;
  return r;
}
inline Quad mul4(Quad q, double x) {
  for (double& v : q.v) v *= x;
  return q;
}
inline Quad div4(Quad q, double x) {
  for (double& v : q.v) v /= x;
  return q;
}
inline Quad set4(double x) { return {{x, x, x, x}}; }
#endif

}  // namespace

}  // namespace tetia::detail
