// fuzz/kernel_contract.hpp -- the kernels' contract for any finite input, as one function per
// dimension that returns an empty string when it holds and a description otherwise. Shared by
// the fuzz targets, fuzz_replay and tests/test_fuzz_regressions.cpp, so that what the fuzzer
// flags and what the regression test accepts cannot drift apart.
//
// A message is one or more violations joined by "; ", each "kind: details". The kind (see
// message_kind) is a fixed token, so that findings can be deduplicated by it. Kinds, for
// v = intersection_volume(U, V) (2D: "area" for "volume", intersection_area(A, B)):
//
//   input-nonfinite          a coordinate is not finite (outside the contract; the decoder and
//                            parse_line never produce one)
//   volume-nonfinite         v is NaN, or infinite although the exact intersection is finite
//   (v infinite where the exact intersection rounds to infinity too is what the contract asks.)
//   volume-negative          v < 0
//   volume-nonzero-for-flat  the smaller exact volume rounds to 0, but v != 0
//   volume-exceeds-min       v > min(|U|, |V|) (1 + 1e-12), |.| the exact volumes rounded to the
//                            nearest double
//   mismatch[ENTRY]          entry point ENTRY does not return v bit for bit (3D: V and U
//                            swapped, intersect with and without stats, intersection_moments,
//                            the supermesh's OneToMany, moments and full; 2D: the same but
//                            OneToMany, and a reordering of the vertices, which
//                            tri_intersection.hpp promises to give the same polygon bit for bit)
//   one-to-many-moments      OneToMany's first moments (either path) differ from
//                            intersection_moments' (its header promises the same bits)
//   moments-nonfinite        a first moment of intersection_moments or of intersect is NaN, or
//                            infinite although the exact one is certainly below DBL_MAX / 4
//                            (|first| <= exact intersection x largest |coordinate|)
//   (an infinite first moment where that bound does not rule out that the exact one overflows
//   is accepted: the moments are the exact ones rounded, to within the rounding of a
//   rescaled result)
//   corner-nonfinite         a corner of intersect(U, V) has a non-finite point or bary
//   stats-inconsistencies    3D: intersect(U, V, &stats) counted label or sign contradictions
//                            other than first attempts redone with the other reference (retries)
//                            and second attempts whose pair went to the exact last resort
//                            (labels that close with neither reference: tet_intersection.hpp
//                            lists them among what is computed exactly; both tetrahedra flat to
//                            rounding, fuzz/regressions/fuzz_tet_kernel/found-2026-12-06b.txt)
//   vanished                 v == 0 although the exact intersection is at least 2^-1054 (a
//                            double with at least 20 significant bits, not rounding noise) and
//                            more than 1e-14 of the larger volume (the resolution the kernel
//                            tests use), for two inputs of quality above 1e-10 (so that neither
//                            is flat as computed, which the contract allows to give 0)
//   vanished-overflow        the same, but the exact intersection exceeds DBL_MAX
//   inaccurate-smaller       |v - exact| > 1e-12 min(|U|, |V|) + 64 * 2^-1074 where the
//                            smaller cell's quality is at least 2^-40 (not flat to the rounding
//                            of its own coordinates): the accuracy the headers promise
//   inaccurate               |v - exact| > 1e-6 max(|U|, |V|) + 64 * 2^-1074 for two inputs of
//                            quality above 1e-3 with finite volumes: a loose sanity bound (the
//                            kernel tests hold 1e-12), so that only plainly wrong results count
//   clip-check-enclosure     2D: the check of the kernel's result (src/kernel/tri_clip_check.hpp,
//                            run alone: tri_clip_trace) found an enclosure that does not hold,
//                            |area - exact| > error (a derived bound: it must hold for every
//                            input it is found for)
//
// The quality of a tetrahedron is |6 vol| / s^(3/2), s the sum of its squared edge lengths (the
// kernel's conditioning, src/kernel/one_to_many.hpp), of a triangle |2 area| / s, here both
// evaluated exactly. All exact values come from GMP (tetia/exact.hpp), independent of the
// kernels and of the scale of the input: subnormal and 1e300 coordinates are judged alike. The
// exact intersection (tens of microseconds) is computed only when a check needs it.
//
// OneToMany is internal to the library: its header is included by relative path; the fuzz build
// compiles the kernel sources directly, the tests link the tetia library that defines it.
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "../src/kernel/one_to_many.hpp"
#include "decode.hpp"
#include "tetia/exact.hpp"
#include "tetia/kernel_trace.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::fuzz {

/// The kind of a contract message: its first violation's token (the text before ':').
inline std::string message_kind(std::string_view message) {
  return std::string(message.substr(0, message.find(':')));
}

/// The kinds of all the violations in a message, in order.
inline std::vector<std::string> message_kinds(std::string_view message) {
  std::vector<std::string> kinds;
  while (!message.empty()) {
    kinds.push_back(message_kind(message));
    const std::size_t next = message.find("; ");
    message = next == std::string_view::npos ? std::string_view() : message.substr(next + 2);
  }
  return kinds;
}

namespace detail {

inline std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// Built by appending: g++ 12 warns (-Wrestrict, a false positive) on "(" + std::string&&.
inline std::string str(const Vec3& p) {
  std::string s = "(";
  s += num(p.x);
  s += ", ";
  s += num(p.y);
  s += ", ";
  s += num(p.z);
  return s += ")";
}
inline std::string str(const Vec2& p) {
  std::string s = "(";
  s += num(p.x);
  s += ", ";
  s += num(p.y);
  return s += ")";
}
template <std::size_t K>
std::string str(const std::array<double, K>& a) {
  std::string s = "(";
  for (std::size_t i = 0; i < K; ++i) {
    if (i) s += ", ";
    s += num(a[i]);
  }
  return s += ")";
}

inline bool finite(const Vec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}
inline bool finite(const Vec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }
template <std::size_t K>
bool finite(const std::array<double, K>& a) {
  return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
}

inline bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

/// q rounded to the nearest double, ties to even; +-inf beyond the largest double. (mpq's
/// get_d truncates, and the contract's bounds are on round-to-nearest values.)
inline double round_to_double(const mpq_class& q_signed) {
  const int sign = sgn(q_signed);
  if (sign == 0) return 0.0;
  const mpq_class q = abs(q_signed);
  // floor(log2 q) is bits(num) - bits(den) or one less.
  long e = static_cast<long>(mpz_sizeinbase(q.get_num_mpz_t(), 2)) -
           static_cast<long>(mpz_sizeinbase(q.get_den_mpz_t(), 2));
  mpq_class p = 1;
  if (e >= 0)
    mpq_mul_2exp(p.get_mpq_t(), p.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
  else
    mpq_div_2exp(p.get_mpq_t(), p.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
  if (q < p) --e;
  if (e > 1023) return sign * std::numeric_limits<double>::infinity();
  // The spacing of the doubles around q is 2^s; below 2^-1022 it stays 2^-1074.
  const long s = std::max(e, -1022L) - 52;
  mpq_class t = q;
  if (s >= 0)
    mpq_div_2exp(t.get_mpq_t(), t.get_mpq_t(), static_cast<mp_bitcnt_t>(s));
  else
    mpq_mul_2exp(t.get_mpq_t(), t.get_mpq_t(), static_cast<mp_bitcnt_t>(-s));
  mpz_class m;
  mpz_fdiv_q(m.get_mpz_t(), t.get_num_mpz_t(), t.get_den_mpz_t());
  const int half = cmp(mpq_class(2 * (t - m)), 1);
  if (half > 0 || (half == 0 && mpz_odd_p(m.get_mpz_t()))) ++m;
  // m <= 2^53 is exact in a double, and ldexp rounds nothing (or overflows to inf, correctly).
  return sign * std::ldexp(m.get_d(), static_cast<int>(s));
}

template <class Point>
mpq_class squared_distance(const Point& a, const Point& b) {
  const mpq_class dx = mpq_class(a.x) - mpq_class(b.x), dy = mpq_class(a.y) - mpq_class(b.y);
  mpq_class s = dx * dx + dy * dy;
  if constexpr (std::is_same_v<Point, Vec3>) {
    const mpq_class dz = mpq_class(a.z) - mpq_class(b.z);
    s += dz * dz;
  }
  return s;
}

/// Whether quality(t) >= sqrt(threshold_sq), exactly, given t's exact measure: for a
/// tetrahedron 36 vol^2 >= threshold_sq s^3, for a triangle 4 area^2 >= threshold_sq s^2.
template <class Shape>
bool quality_at_least(const Shape& t, const mpq_class& measure, const mpq_class& threshold_sq) {
  mpq_class s = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    for (std::size_t j = i + 1; j < t.size(); ++j) s += squared_distance(t[i], t[j]);
  if (sgn(s) == 0) return false;
  if constexpr (std::is_same_v<Shape, Tet>)
    return 36 * measure * measure >= threshold_sq * s * s * s;
  else
    return 4 * measure * measure >= threshold_sq * s * s;
}

// Thresholds of the "vanished" and "inaccurate" checks (see the header comment), squared.
inline const mpq_class& vanish_quality_sq() {
  static const mpq_class q(1, mpz_class("100000000000000000000"));  // (1e-10)^2
  return q;
}
inline const mpq_class& flat_quality_sq() {  // (2^-40)^2
  static const mpq_class q(1, mpz_class(1) << 80);
  return q;
}
inline const mpq_class& accuracy_quality_sq() {
  static const mpq_class q(1, 1000000);  // (1e-3)^2
  return q;
}

/// What the entry points returned for one pair: everything the contract is checked on.
template <class Point>
struct Observed {
  double v = 0.0;                                       ///< the primary entry point
  std::vector<std::pair<std::string, double>> entries;  ///< the others, each must equal v
  std::vector<std::pair<std::string, Point>> first_moments;
  std::string corner_problem;  ///< the first non-finite corner
  std::int64_t inconsistencies = 0;
  std::int64_t retries = 0;
  std::int64_t exact_fallbacks = 0;
};

/// The contract for a pair X, Y of tetrahedra or triangles, given what the kernel returned.
/// exact_intersection computes the exact intersection; it is called at most once, and only when
/// a check needs it.
template <class Shape, class Point, class ExactIntersection>
std::string judge(const Shape& X, const Shape& Y, const std::string& measure,
                  const Observed<Point>& o, ExactIntersection&& exact_intersection) {
  std::string report;
  const auto add = [&](const std::string& kind, const std::string& details) {
    report += (report.empty() ? "" : "; ") + kind + ": " + details;
  };
  const auto exact_measure = [](const Shape& t) {
    if constexpr (std::is_same_v<Shape, Tet>)
      return exact::volume(t);
    else
      return exact::area(t);
  };
  const mpq_class ex = exact_measure(X), ey = exact_measure(Y);
  const double vx = round_to_double(ex), vy = round_to_double(ey);
  const double vmin = std::min(vx, vy), v = o.v;
  const std::string exact_measures =
      " (the exact " + measure + "s are " + num(vx) + " and " + num(vy) + ")";
  std::optional<mpq_class> exact_cache;
  const auto exact = [&]() -> const mpq_class& {
    if (!exact_cache) exact_cache = exact_intersection();
    return *exact_cache;
  };

  if (std::isnan(v) || (std::isinf(v) && std::isfinite(round_to_double(exact()))))
    add(measure + "-nonfinite", measure + " = " + num(v));
  else if (v < 0)
    add(measure + "-negative", measure + " = " + num(v));
  if (vmin == 0.0) {
    if (v != 0.0)
      add(measure + "-nonzero-for-flat",
          measure + " = " + num(v) + ", but the smaller exact " + measure + " rounds to 0");
  } else if (v > vmin * (1 + 1e-12)) {
    add(measure + "-exceeds-min", measure + " = " + num(v) + " > the smaller exact " + measure +
                                      " " + num(vmin) + " (ratio " + num(v / vmin) + ")");
  }

  for (const auto& [name, value] : o.entries)
    if (!same_bits(value, v))
      add("mismatch[" + name + "]", name + " = " + num(value) + " but " + measure + " = " + num(v) +
                                        " (difference " + num(value - v) + ")");

  for (const auto& [name, first] : o.first_moments) {
    if (finite(first)) continue;
    // |first moment| <= exact intersection * the largest |coordinate| of the input. NaN is
    // wrong whatever the bound; an infinity only where the exact moment may not fit.
    bool nan = std::isnan(first.x) || std::isnan(first.y);
    double largest = 0.0;
    for (const Shape* t : {&X, &Y})
      for (const Point& p : *t) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
    if constexpr (std::is_same_v<Point, Vec3>) {
      nan = nan || std::isnan(first.z);
      for (const Shape* t : {&X, &Y})
        for (const Point& p : *t) largest = std::max(largest, std::abs(p.z));
    }
    const double bound = round_to_double(exact()) * largest;
    const bool fits = bound <= std::numeric_limits<double>::max() / 4;
    if (nan || fits)
      add("moments-nonfinite", name + " = " + str(first) + ", exact " + measure +
                                   " x largest |coordinate| = " + num(bound));
  }
  if (!o.corner_problem.empty()) add("corner-nonfinite", o.corner_problem);
  // 3D only: the 2D kernel counts a first attempt whose labels did not close as a retry alone,
  // and its statistics path can flag a contradiction in an attempt whose result is right
  // (fuzz/regressions/fuzz_tri_kernel has one); those are diagnostics of the 2D kernel, not
  // part of its contract, which the checks above cover.
  if constexpr (std::is_same_v<Point, Vec3>)
    if (o.inconsistencies > o.retries + o.exact_fallbacks)
      add("stats-inconsistencies", "intersect with stats counted " + std::to_string(o.inconsistencies) +
                                       " inconsistencies, " + std::to_string(o.retries) + " retries and " +
                                       std::to_string(o.exact_fallbacks) + " exact results");

  // Against the exact intersection: only for inputs shaped well enough for the checks to be fair.
  const bool vanish_shaped =
      quality_at_least(X, ex, vanish_quality_sq()) && quality_at_least(Y, ey, vanish_quality_sq());
  if (v == 0.0 && vanish_shaped) {
    static const mpq_class resolution(1, mpz_class("100000000000000"));  // 1e-14
    const double ed = round_to_double(exact());
    if (ed >= 0x1p-1054 && exact() > resolution * std::max(ex, ey)) {
      if (std::isinf(ed))
        add("vanished-overflow",
            measure + " = 0, but the exact intersection exceeds DBL_MAX" + exact_measures);
      else
        add("vanished",
            measure + " = 0, but the exact intersection is " + num(ed) + exact_measures);
      return report;
    }
  }
  {
    // Within 1e-12 of the smaller cell whenever that one is not flat to the rounding of its own
    // coordinates (quality at least 2^-40, the 3D kernel's kFlatQuality; the 2D kernel promises
    // it for every triangle, and is held to it alike).
    const bool x_smaller = ex <= ey;
    if (std::isfinite(v) && std::isfinite(vmin) &&
        quality_at_least(x_smaller ? X : Y, x_smaller ? ex : ey, flat_quality_sq())) {
      const double ed = round_to_double(exact());
      const double tol = 1e-12 * vmin + 64 * std::numeric_limits<double>::denorm_min();
      if (std::isfinite(ed) && std::abs(v - ed) > tol)
        add("inaccurate-smaller", measure + " = " + num(v) + ", exact " + num(ed) + ", error " +
                                      num(std::abs(v - ed)) + " > 1e-12 of the smaller" + exact_measures);
    }
  }
  if (vanish_shaped && std::isfinite(v) && std::isfinite(vx) && std::isfinite(vy) &&
      quality_at_least(X, ex, accuracy_quality_sq()) &&
      quality_at_least(Y, ey, accuracy_quality_sq())) {
    const double ed = round_to_double(exact());
    const double tol = 1e-6 * std::max(vx, vy) + 64 * std::numeric_limits<double>::denorm_min();
    if (std::isfinite(ed) && std::abs(v - ed) > tol)
      add("inaccurate", measure + " = " + num(v) + ", exact " + num(ed) + ", error " +
                            num(std::abs(v - ed)) + " > " + num(tol) + exact_measures);
  }
  return report;
}

template <class Shape>
std::string nonfinite_input(const Shape& X, const Shape& Y) {
  for (const Shape* t : {&X, &Y})
    for (const auto& p : *t)
      if (!finite(p)) return "input-nonfinite: vertex " + str(p) + " (outside the contract)";
  return {};
}

template <class PolytopeCorners>
std::string corner_problem(const PolytopeCorners& corners, const char* call) {
  for (std::size_t i = 0; i < corners.size(); ++i)
    if (!finite(corners[i].point) || !finite(corners[i].bary))
      return std::string(call) + " corner " + std::to_string(i) + ": point " +
             str(corners[i].point) + ", bary " + str(corners[i].bary);
  return {};
}

}  // namespace detail

/// The 3D contract for U and V (any finite coordinates, any orientation). Empty when it holds.
inline std::string check_tet_contract(const Tet& U, const Tet& V) {
  if (std::string bad = detail::nonfinite_input(U, V); !bad.empty()) return bad;
  IntersectionStats stats;
  const Polyhedron P = intersect(U, V);
  const Polyhedron P_stats = intersect(U, V, &stats);
  const Moments M = intersection_moments(U, V);
  const tetia::detail::OneToMany one(U);
  const Moments M_one = one.moments(V, tetia::detail::conditioning(V));
  Polyhedron P_one;  // the supermesh's full path, where shapes are needed
  const Moments M_one_full = one.intersect(V, tetia::detail::conditioning(V), P_one);
  detail::Observed<Vec3> o;
  o.v = intersection_volume(U, V);
  o.entries = {
      {"intersection_volume(V, U)", intersection_volume(V, U)},
      {"intersect(U, V).volume()", P.volume()},
      {"intersect(U, V, &stats).volume()", P_stats.volume()},
      {"intersect(V, U).volume()", intersect(V, U).volume()},
      {"intersection_moments(U, V).volume", M.volume},
      {"OneToMany(U).moments(V, conditioning(V)).volume", M_one.volume},
      {"OneToMany(U).intersect(V, conditioning(V), P).volume", M_one_full.volume},
  };
  o.first_moments = {{"intersection_moments(U, V).first", M.first},
                     {"intersect(U, V).moments().first", P.moments().first}};
  o.corner_problem = detail::corner_problem(P.corners(), "intersect(U, V)");
  o.inconsistencies = stats.inconsistencies;
  o.retries = stats.retries;
  o.exact_fallbacks = stats.exact_fallbacks;
  std::string report =
      detail::judge(U, V, "volume", o, [&] { return exact::intersection_volume(U, V); });
  const auto same = [](const Vec3& a, const Vec3& b) {
    using detail::same_bits;
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
  };
  if (!same(M_one.first, M.first)) {
    report += (report.empty() ? "" : "; ") + std::string("one-to-many-moments: OneToMany first ") +
              detail::str(M_one.first) + ", intersection_moments first " + detail::str(M.first);
  }
  if (!same(M_one_full.first, M.first)) {
    report += (report.empty() ? "" : "; ") + std::string("one-to-many-moments: OneToMany::intersect first ") +
              detail::str(M_one_full.first) + ", intersection_moments first " + detail::str(M.first);
  }
  return report;
}

/// The 2D contract for A and B (any finite coordinates, any orientation). Empty when it holds.
inline std::string check_tri_contract(const Triangle& A, const Triangle& B) {
  if (std::string bad = detail::nonfinite_input(A, B); !bad.empty()) return bad;
  TriIntersectionStats stats;
  const Polygon P = intersect(A, B);
  const Polygon P_stats = intersect(A, B, &stats);
  const Moments2 M = intersection_moments(A, B);
  detail::Observed<Vec2> o;
  o.v = intersection_area(A, B);
  o.entries = {
      {"intersection_area(B, A)", intersection_area(B, A)},
      {"intersect(A, B).area()", P.area()},
      {"intersect(A, B, &stats).area()", P_stats.area()},
      {"intersect(B, A).area()", intersect(B, A).area()},
      {"intersection_moments(A, B).area", M.area},
      {"intersection_area(A[1 2 0], B[2 1 0])",
       intersection_area(Triangle{A[1], A[2], A[0]}, Triangle{B[2], B[1], B[0]})},
  };
  o.first_moments = {{"intersection_moments(A, B).first", M.first},
                     {"intersect(A, B).moments().first", P.moments().first}};
  o.corner_problem = detail::corner_problem(P.corners(), "intersect(A, B)");
  o.inconsistencies = stats.inconsistencies;
  o.retries = stats.retries;
  std::optional<mpq_class> exact_area;
  std::string report = detail::judge(A, B, "area", o, [&] {
    if (!exact_area) exact_area = exact::intersection_area(A, B);
    return *exact_area;
  });
  const tetia::detail::TriClipTrace clip = tetia::detail::tri_clip_trace(A, B);
  if (clip.enclosed) {
    if (!exact_area) exact_area = exact::intersection_area(A, B);
    const mpq_class off = abs(mpq_class(clip.area) - *exact_area);
    if (!(std::isfinite(clip.error) && off <= mpq_class(clip.error)))
      report += (report.empty() ? "" : "; ") + std::string("clip-check-enclosure: area ") + detail::num(clip.area) +
                " with error " + detail::num(clip.error) + ", exact " + detail::num(exact_area->get_d());
  }
  return report;
}

/// The contract for a decoded or parsed pair.
inline std::string check_contract(const TetCoords& c) {
  Tet U, V;
  split(c, U, V);
  return check_tet_contract(U, V);
}
inline std::string check_contract(const TriCoords& c) {
  Triangle A, B;
  split(c, A, B);
  return check_tri_contract(A, B);
}

}  // namespace tetia::fuzz
