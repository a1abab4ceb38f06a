// src/kernel/barycentric_map.hpp -- the change of coordinates of Section 2 (internal to the library).
//
// BarycentricMap(r, 1 / det6) maps points to barycentric coordinates in tetrahedron r, with the
// exact snapping described below. Used by the kernel (src/kernel/frame.hpp) for the
// reference tetrahedron, and kept by callers that intersect one tetrahedron with many
// (src/kernel/one_to_many.hpp), so that a tetrahedron's map is built once. Inline, allocation-free.
#pragma once

#include <bit>
#include <cmath>

#include "tetia/geometry.hpp"

// SSE2 is part of x86-64; elsewhere the same computations run as scalar loops. Where the
// compiler targets AVX2 (the kernels' x86-64-v3 variant, kernel_variant.hpp), the map is made
// for the four faces, and map() takes the four coordinates of a point, in one 4-lane pass
// instead of two 2-lane ones: the same operations lane for lane, so the same bits.
#if defined(__SSE2__)
#include <emmintrin.h>
#define TETIA_KERNEL_SSE2 1
#else
#define TETIA_KERNEL_SSE2 0
#endif
#if TETIA_KERNEL_SSE2 && defined(__AVX2__)
#include <immintrin.h>
#define TETIA_KERNEL_AVX 1
#else
#define TETIA_KERNEL_AVX 0
#endif

namespace tetia::detail {

// The change of coordinates of Section 2, eq. (1), one face at a time: coordinate k of a point
// u is the signed distance of u from the face opposite vertex k, (u - a_k) . n_k, divided by
// that of vertex k. Each face is translated to its own first vertex a_k before anything else,
// as Section 2 advises, so the normals n_k are accurate for the face's own size and a point far
// away (a big tetrahedron mapped into a tiny reference) keeps full relative accuracy; forming
// the determinants around u instead would cancel catastrophically there. A point equal to a
// vertex of the reference gets that vertex's coordinates exactly (1 and three exact zeros):
// shared vertices, shared faces and identical tetrahedra, the normal case on conforming meshes,
// are then decided exactly rather than by rounding.
//
// A coordinate whose computed value is within the rounding error bound of the determinant
// (Shewchuk's bound for orient3d, (7 + 56 eps) eps times the permanent, with this same
// evaluation order) has no reliable sign; it is set to exactly 0, which places the point on
// the face. The result is then the exact answer for an input perturbed by less than its own
// rounding, in the spirit of Corollary 2, and two tetrahedra that touch across a face up to an
// ulp give exactly zero instead of a slab of rounding-sized volume.
struct BarycentricMap {
  // The three vertices of face k (the face opposite vertex k), ascending.
  static constexpr int kMapFaceVerts[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

  // One entry per face k (opposite vertex k), as arrays over k.
  // 32-byte aligned: one AVX load per array where map() runs on four lanes.
  alignas(32) double vx[4], vy[4], vz[4];  // the vertices, for the exact snapping
  alignas(32) double ax[4], ay[4], az[4];  // anchor a_k: the face's first vertex
  alignas(32) double nx[4], ny[4], nz[4];  // normal n_k
  alignas(32) double px[4], py[4], pz[4];  // the terms of the normal in absolute value, for the permanent
  alignas(32) double scale[4];  // +-1 / det6 with the sign that makes coordinate k of vertex k positive
  alignas(16) double tiny[2];   // 2^-340 |det6|: a |det| below it is a coordinate below 2^-340

  static constexpr double kErrBound = (7.0 + 56.0 * 0x1p-53) * 0x1p-53;

  // inv_det6: 1 / det[r1 - r0, r2 - r0, r3 - r0] (Conditioning::inv_det6).
  //
  // always_inline, as map(): the type is shared by the kernel's variants (OneToMany holds one),
  // so an out-of-line copy would be one name for every variant's code, and the linker could
  // hand the baseline the AVX2 variant's (src/kernel/entry_points.hpp, "Linkage").
  [[gnu::always_inline]] BarycentricMap(const Tet& r, double inv_det6) {
    const double inv = inv_det6;
#if TETIA_KERNEL_AVX
    // The loop below for the four faces at once: the vertices' x, y and z as vectors over the
    // vertices, and each face's first, second and third vertex (kMapFaceVerts) picked from them
    // by a permutation: (r1, r0, r0, r0), (r2, r2, r1, r1), (r3, r3, r3, r2).
    const __m128d L[4] = {_mm_loadu_pd(&r[0].x), _mm_loadu_pd(&r[1].x), _mm_loadu_pd(&r[2].x), _mm_loadu_pd(&r[3].x)};
    const __m256d X = _mm256_set_m128d(_mm_unpacklo_pd(L[2], L[3]), _mm_unpacklo_pd(L[0], L[1]));
    const __m256d Y = _mm256_set_m128d(_mm_unpackhi_pd(L[2], L[3]), _mm_unpackhi_pd(L[0], L[1]));
    const __m256d Z = _mm256_set_m128d(_mm_loadh_pd(_mm_load_sd(&r[2].z), &r[3].z), _mm_loadh_pd(_mm_load_sd(&r[0].z), &r[1].z));
    constexpr int kFirst = 0x01, kSecond = 0x5A, kThird = 0xBF;  // lanes (1,0,0,0), (2,2,1,1), (3,3,3,2)
    const __m256d f0x = _mm256_permute4x64_pd(X, kFirst), f0y = _mm256_permute4x64_pd(Y, kFirst),
                  f0z = _mm256_permute4x64_pd(Z, kFirst);
    const __m256d d1x = _mm256_sub_pd(_mm256_permute4x64_pd(X, kSecond), f0x),
                  d1y = _mm256_sub_pd(_mm256_permute4x64_pd(Y, kSecond), f0y),
                  d1z = _mm256_sub_pd(_mm256_permute4x64_pd(Z, kSecond), f0z);
    const __m256d d2x = _mm256_sub_pd(_mm256_permute4x64_pd(X, kThird), f0x),
                  d2y = _mm256_sub_pd(_mm256_permute4x64_pd(Y, kThird), f0y),
                  d2z = _mm256_sub_pd(_mm256_permute4x64_pd(Z, kThird), f0z);
    const __m256d yz = _mm256_mul_pd(d1y, d2z), zy = _mm256_mul_pd(d1z, d2y), zx = _mm256_mul_pd(d1z, d2x),
                  xz = _mm256_mul_pd(d1x, d2z), xy = _mm256_mul_pd(d1x, d2y), yx = _mm256_mul_pd(d1y, d2x);
    const __m256d sign = _mm256_set1_pd(-0.0);
    _mm256_store_pd(ax, f0x);
    _mm256_store_pd(ay, f0y);
    _mm256_store_pd(az, f0z);
    _mm256_store_pd(nx, _mm256_sub_pd(yz, zy));
    _mm256_store_pd(ny, _mm256_sub_pd(zx, xz));
    _mm256_store_pd(nz, _mm256_sub_pd(xy, yx));
    _mm256_store_pd(px, _mm256_add_pd(_mm256_andnot_pd(sign, yz), _mm256_andnot_pd(sign, zy)));
    _mm256_store_pd(py, _mm256_add_pd(_mm256_andnot_pd(sign, zx), _mm256_andnot_pd(sign, xz)));
    _mm256_store_pd(pz, _mm256_add_pd(_mm256_andnot_pd(sign, xy), _mm256_andnot_pd(sign, yx)));
    _mm256_store_pd(vx, X);
    _mm256_store_pd(vy, Y);
    _mm256_store_pd(vz, Z);
    _mm256_store_pd(scale, _mm256_set_pd(inv, -inv, inv, -inv));  // scale[k] = (k % 2 == 0) ? -inv : inv
    tiny[0] = tiny[1] = 0x1p-340 / std::abs(inv);
#elif TETIA_KERNEL_SSE2
    // The loop below for faces (0, 1) and (2, 3) at once: first vertices (r1, r0), (r0, r0),
    // second (r2, r2), (r1, r1), third (r3, r3), (r3, r2) (kMapFaceVerts).
    // (x, y) of each vertex as one load; pairs of coordinates by unpacking.
    const __m128d L[4] = {_mm_loadu_pd(&r[0].x), _mm_loadu_pd(&r[1].x), _mm_loadu_pd(&r[2].x), _mm_loadu_pd(&r[3].x)};
    const auto zz = [&](int lo, int hi) { return _mm_loadh_pd(_mm_load_sd(&r[lo].z), &r[hi].z); };
    for (int h = 0; h < 2; ++h) {
      const int a0 = h == 0 ? 1 : 0, b0 = h == 0 ? 2 : 1, c0 = 3, c1 = h == 0 ? 3 : 2;
      const __m128d f0x = _mm_unpacklo_pd(L[a0], L[0]), f0y = _mm_unpackhi_pd(L[a0], L[0]), f0z = zz(a0, 0);
      const __m128d f1x = _mm_unpacklo_pd(L[b0], L[b0]), f1y = _mm_unpackhi_pd(L[b0], L[b0]), f1z = zz(b0, b0);
      const __m128d f2x = _mm_unpacklo_pd(L[c0], L[c1]), f2y = _mm_unpackhi_pd(L[c0], L[c1]), f2z = zz(c0, c1);
      const __m128d d1x = _mm_sub_pd(f1x, f0x), d1y = _mm_sub_pd(f1y, f0y), d1z = _mm_sub_pd(f1z, f0z);
      const __m128d d2x = _mm_sub_pd(f2x, f0x), d2y = _mm_sub_pd(f2y, f0y), d2z = _mm_sub_pd(f2z, f0z);
      const __m128d yz = _mm_mul_pd(d1y, d2z), zy = _mm_mul_pd(d1z, d2y), zx = _mm_mul_pd(d1z, d2x),
                    xz = _mm_mul_pd(d1x, d2z), xy = _mm_mul_pd(d1x, d2y), yx = _mm_mul_pd(d1y, d2x);
      const __m128d sign = _mm_set1_pd(-0.0);
      const int k = 2 * h;
      _mm_store_pd(ax + k, f0x);
      _mm_store_pd(ay + k, f0y);
      _mm_store_pd(az + k, f0z);
      _mm_store_pd(nx + k, _mm_sub_pd(yz, zy));
      _mm_store_pd(ny + k, _mm_sub_pd(zx, xz));
      _mm_store_pd(nz + k, _mm_sub_pd(xy, yx));
      _mm_store_pd(px + k, _mm_add_pd(_mm_andnot_pd(sign, yz), _mm_andnot_pd(sign, zy)));
      _mm_store_pd(py + k, _mm_add_pd(_mm_andnot_pd(sign, zx), _mm_andnot_pd(sign, xz)));
      _mm_store_pd(pz + k, _mm_add_pd(_mm_andnot_pd(sign, xy), _mm_andnot_pd(sign, yx)));
    }
    _mm_store_pd(vx, _mm_unpacklo_pd(L[0], L[1]));
    _mm_store_pd(vx + 2, _mm_unpacklo_pd(L[2], L[3]));
    _mm_store_pd(vy, _mm_unpackhi_pd(L[0], L[1]));
    _mm_store_pd(vy + 2, _mm_unpackhi_pd(L[2], L[3]));
    _mm_store_pd(vz, zz(0, 1));
    _mm_store_pd(vz + 2, zz(2, 3));
    const __m128d sc = _mm_set_pd(inv, -inv);  // scale[k] = (k % 2 == 0) ? -inv : inv
    _mm_store_pd(scale, sc);
    _mm_store_pd(scale + 2, sc);
    tiny[0] = tiny[1] = 0x1p-340 / std::abs(inv);
#else
    for (int k = 0; k < 4; ++k) {
      vx[k] = r[k].x, vy[k] = r[k].y, vz[k] = r[k].z;
      const Vec3 f0 = r[kMapFaceVerts[k][0]];
      const Vec3 d1 = r[kMapFaceVerts[k][1]] - f0, d2 = r[kMapFaceVerts[k][2]] - f0;
      ax[k] = f0.x, ay[k] = f0.y, az[k] = f0.z;
      const Vec3 n = cross(d1, d2);
      nx[k] = n.x, ny[k] = n.y, nz[k] = n.z;
      px[k] = std::abs(d1.y * d2.z) + std::abs(d1.z * d2.y);
      py[k] = std::abs(d1.z * d2.x) + std::abs(d1.x * d2.z);
      pz[k] = std::abs(d1.x * d2.y) + std::abs(d1.y * d2.x);
      // (r_k - f0) . n_k = orient3d(f0, f1, f2, r_k) = (-1)^(k+1) det6.
      scale[k] = (k % 2 == 0) ? -inv : inv;
    }
    tiny[0] = tiny[1] = 0x1p-340 / std::abs(inv);
#endif
  }

  // A coordinate below 2^-340 in magnitude is set to 0 as well: the kernel multiplies up to three
  // coordinates (eq. 5's numerator), whose products must not underflow (solve_with accepts only
  // tetrahedra whose sizes are within 2^250 of each other, so that this moves a vertex by at
  // most 2^-90 of the smaller one).
  //
  // Coordinate k: with w = u - a_k, det = w . n_k (evaluated as (w.x n.x + w.y n.y) + w.z n.z)
  // and the permanent |w.x| p.x + |w.y| p.y + |w.z| p.z, det * scale_k if |det| exceeds
  // kErrBound times the permanent, else exactly 0. Then u equal to vertex k (the last such k)
  // gets the unit coordinates of that vertex.
  [[gnu::always_inline]] void operator()(Vec3 u, double (&out)[4]) const {
    LargestDet unused{};
    map<false>(u, out, unused);
  }

  // The running maximum of |det| over coordinates (map<true>), two lanes with SSE2.
#if TETIA_KERNEL_SSE2
  using LargestDet = __m128d;
  static double largest(LargestDet m) { return _mm_cvtsd_f64(_mm_max_sd(m, _mm_unpackhi_pd(m, m))); }
#else
  using LargestDet = double;
  static double largest(LargestDet m) { return m; }
#endif

  // The same, and with kMax, largest_det = max(largest_det, the permanent of each coordinate's
  // determinant) (start from LargestDet{}, read with largest()): times |1 / det6| that bounds
  // the largest |coordinate| computed and, times kErrBound, the largest rounding error of one
  // (Shewchuk's bound): the magnitude the kernel's error estimate needs (solve.hpp), at the cost
  // of one max per two coordinates. The permanent, not |det|: where the reference is flattened,
  // a coordinate's rounding error is far above the coordinate itself (the map's conditioning),
  // and |det| left that out of the estimate (a pair off by 1.97e-12 of the smaller tetrahedron,
  // fuzz/regressions/fuzz_tet_kernel/found-2026-12-03.txt).
  template <bool kMax>
  [[gnu::always_inline]] void map(Vec3 u, double (&out)[4], LargestDet& largest_det) const {
    unsigned same = 0;  // bit k: u == vertex k
#if TETIA_KERNEL_AVX
    // The SSE2 branch below on four lanes: each lane's operations are that branch's, in its
    // order (compare predicates as _mm_cmpgt_pd's and _mm_cmpeq_pd's), and the running maximum
    // takes lanes (0, 1) then (2, 3) as it does.
    {
      const __m256d ux = _mm256_set1_pd(u.x), uy = _mm256_set1_pd(u.y), uz = _mm256_set1_pd(u.z);
      const __m256d sign = _mm256_set1_pd(-0.0), bound = _mm256_set1_pd(kErrBound);
      const __m256d wx = _mm256_sub_pd(ux, _mm256_load_pd(ax)), wy = _mm256_sub_pd(uy, _mm256_load_pd(ay)),
                    wz = _mm256_sub_pd(uz, _mm256_load_pd(az));
      const __m256d det = _mm256_add_pd(
          _mm256_add_pd(_mm256_mul_pd(wx, _mm256_load_pd(nx)), _mm256_mul_pd(wy, _mm256_load_pd(ny))),
          _mm256_mul_pd(wz, _mm256_load_pd(nz)));
      const __m256d perm =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_andnot_pd(sign, wx), _mm256_load_pd(px)),
                                      _mm256_mul_pd(_mm256_andnot_pd(sign, wy), _mm256_load_pd(py))),
                        _mm256_mul_pd(_mm256_andnot_pd(sign, wz), _mm256_load_pd(pz)));
      const __m256d abs_det = _mm256_andnot_pd(sign, det);
      if constexpr (kMax) {
        largest_det = _mm_max_pd(largest_det, _mm256_castpd256_pd128(perm));
        largest_det = _mm_max_pd(largest_det, _mm256_extractf128_pd(perm, 1));
      }
      const __m256d keep =
          _mm256_cmp_pd(abs_det, _mm256_max_pd(_mm256_mul_pd(bound, perm), _mm256_broadcast_sd(tiny)), _CMP_GT_OS);
      _mm256_storeu_pd(out, _mm256_and_pd(keep, _mm256_mul_pd(det, _mm256_load_pd(scale))));
      same = unsigned(_mm256_movemask_pd(_mm256_cmp_pd(ux, _mm256_load_pd(vx), _CMP_EQ_OQ)));  // x only, first
      if (same) {  // some vertex has u's x: compare the whole points
        const __m256d eq = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(ux, _mm256_load_pd(vx), _CMP_EQ_OQ), _mm256_cmp_pd(uy, _mm256_load_pd(vy), _CMP_EQ_OQ)),
            _mm256_cmp_pd(uz, _mm256_load_pd(vz), _CMP_EQ_OQ));
        same = unsigned(_mm256_movemask_pd(eq));
      }
    }
#elif TETIA_KERNEL_SSE2
    const __m128d ux = _mm_set1_pd(u.x), uy = _mm_set1_pd(u.y), uz = _mm_set1_pd(u.z);
    const __m128d sign = _mm_set1_pd(-0.0), bound = _mm_set1_pd(kErrBound);
    for (int h = 0; h < 4; h += 2) {
      const __m128d wx = _mm_sub_pd(ux, _mm_load_pd(ax + h)), wy = _mm_sub_pd(uy, _mm_load_pd(ay + h)),
                    wz = _mm_sub_pd(uz, _mm_load_pd(az + h));
      const __m128d det = _mm_add_pd(_mm_add_pd(_mm_mul_pd(wx, _mm_load_pd(nx + h)), _mm_mul_pd(wy, _mm_load_pd(ny + h))),
                                     _mm_mul_pd(wz, _mm_load_pd(nz + h)));
      const __m128d perm =
          _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_andnot_pd(sign, wx), _mm_load_pd(px + h)),
                                _mm_mul_pd(_mm_andnot_pd(sign, wy), _mm_load_pd(py + h))),
                     _mm_mul_pd(_mm_andnot_pd(sign, wz), _mm_load_pd(pz + h)));
      const __m128d abs_det = _mm_andnot_pd(sign, det);
      if constexpr (kMax) largest_det = _mm_max_pd(largest_det, perm);
      const __m128d keep = _mm_cmpgt_pd(abs_det, _mm_max_pd(_mm_mul_pd(bound, perm), _mm_load_pd(tiny)));
      _mm_storeu_pd(out + h, _mm_and_pd(keep, _mm_mul_pd(det, _mm_load_pd(scale + h))));
      same |= unsigned(_mm_movemask_pd(_mm_cmpeq_pd(ux, _mm_load_pd(vx + h)))) << h;  // x only, first
    }
    if (same) {  // some vertex has u's x: compare the whole points
      same = 0;
      for (int h = 0; h < 4; h += 2) {
        const __m128d eq = _mm_and_pd(_mm_and_pd(_mm_cmpeq_pd(ux, _mm_load_pd(vx + h)), _mm_cmpeq_pd(uy, _mm_load_pd(vy + h))),
                                      _mm_cmpeq_pd(uz, _mm_load_pd(vz + h)));
        same |= unsigned(_mm_movemask_pd(eq)) << h;
      }
    }
#else
    for (int k = 0; k < 4; ++k) {
      const double wx = u.x - ax[k], wy = u.y - ay[k], wz = u.z - az[k];
      const double det = wx * nx[k] + wy * ny[k] + wz * nz[k];
      const double permanent = std::abs(wx) * px[k] + std::abs(wy) * py[k] + std::abs(wz) * pz[k];
      if constexpr (kMax) largest_det = std::max(largest_det, permanent);
      out[k] = std::abs(det) > std::max(kErrBound * permanent, tiny[0]) ? det * scale[k] : 0.0;
      same |= unsigned(u.x == vx[k] && u.y == vy[k] && u.z == vz[k]) << k;
    }
#endif
    if (same) {
      const int k = std::bit_width(same) - 1;
      for (int q = 0; q < 4; ++q) out[q] = q == k ? 1.0 : 0.0;
    }
  }
};

}  // namespace tetia::detail
