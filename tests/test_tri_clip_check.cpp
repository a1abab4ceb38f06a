// test_tri_clip_check.cpp -- the check of the 2D kernel's result (src/kernel/tri_clip_check.hpp)
// against the exact GMP area.
//
// The kernel's result (for the pairs the certified formula leaves) stands only where the
// clipping of the smaller triangle's frame by the other's lines, whose error bound is derived
// (exact combinatorics, vertices from their own two lines, the slabs of the lines' values),
// puts it within 2^-42 of the smaller triangle of the exact area; elsewhere the exact last
// resort decides. Here the check runs alone (tri_clip_trace) on every pair of every 2D test
// family and on pairs made for it (touching, shared vertices, size ratios to 1e16, needles,
// near-identical, nudged across a line, tiny triangles at a vertex or an edge of a big one):
//  - every enclosure holds: |area - exact| <= error, compared exactly;
//  - it accepts (error at most 2^-42 of the smaller triangle) all but a few pairs: what it does
//    not accept goes exact, which costs time, not accuracy;
// and through the public entry points, every result the kernel decided (neither the formula
// nor the exact last resort) is within 2^-42 of the smaller triangle of the exact area.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/generators2d.hpp"
#include "tetia/exact.hpp"
#include "tetia/kernel_trace.hpp"
#include "tetia/tri_intersection.hpp"

namespace {

using namespace tetia;
using namespace tetia::testgen2d;

constexpr double kAccepted = 0x1p-42;

struct Tally {
  long pairs = 0, enclosed = 0, accepted = 0, kernel = 0, checked = 0, failures = 0;
  double worst_ratio = 0.0;   // |area - exact| / error over the enclosures
  double worst_kernel = 0.0;  // the kernel's decided results: error / smaller area
};

void check(const Triangle& A, const Triangle& B, Tally& t) {
  const mpq_class ea = abs(exact::area(A)), eb = abs(exact::area(B));
  if (sgn(ea) == 0 || sgn(eb) == 0) return;
  ++t.pairs;
  const mpq_class ex = exact::intersection_area(A, B);
  const mpq_class smaller = std::min(ea, eb);
  const detail::TriClipTrace tr = detail::tri_clip_trace(A, B);
  std::string fail;
  if (tr.enclosed) {
    ++t.enclosed;
    const mpq_class off = abs(mpq_class(tr.area) - ex);
    if (!(off <= mpq_class(tr.error)))
      fail = "enclosure off: |area - exact| = " + fmt(off.get_d()) + " > error " + fmt(tr.error);
    if (tr.error > 0.0) t.worst_ratio = std::max(t.worst_ratio, mpq_class(off / mpq_class(tr.error)).get_d());
    if (tr.relative <= kAccepted) ++t.accepted;
  }
  TriIntersectionStats st;
  const double area = intersect(A, B, &st).area();
  // The counters: a pair the formula decided is not checked; a rejected check went exact.
  if (st.certified != 0 && st.checked != 0) fail += "checked although the formula decided; ";
  if (st.check_rejected > st.checked || st.check_rejected > st.exact_fallbacks)
    fail += "check_rejected " + std::to_string(st.check_rejected) + " not among the checks and exact fallbacks; ";
  if (st.certified == 0 && st.exact_fallbacks == 0) {
    ++t.kernel;
    t.checked += st.checked;
    const double rel = mpq_class(abs(mpq_class(area) - ex) / smaller).get_d();
    t.worst_kernel = std::max(t.worst_kernel, rel);
    if (!(rel <= kAccepted)) fail += (fail.empty() ? "" : "; ") + std::string("kernel result off by ") + fmt(rel);
  }
  if (!fail.empty() && ++t.failures <= 3)
    ADD_FAILURE() << fail << "\n  pair " << fmt_pair(A, B) << "\n  hex " << hex_pair(A, B);
}

void report(const char* name, const Tally& t) {
  std::printf("[ clipcheck] %-18s %6ld pairs, %6ld enclosed, %6ld accepted (%.3f %%), worst |area - exact| / error "
              "%.3g; neither formula nor exact %6ld (%ld checked), worst %.3g of the smaller\n",
              name, t.pairs, t.enclosed, t.accepted, t.pairs ? 100.0 * double(t.accepted) / double(t.pairs) : 0.0,
              t.worst_ratio, t.kernel, t.checked, t.worst_kernel);
  EXPECT_EQ(t.failures, 0) << name;
}

TEST(TriClipCheck, EveryFamily) {
  for (const Family& fam : families()) {
    Tally t;
    for (const Case& c : fam.make()) check(c.A, c.B, t);
    report(fam.name, t);
    // What the check does not accept goes exact: rare on every family.
    EXPECT_GE(t.accepted, t.pairs * 97 / 100) << fam.name;
  }
}

// Pairs made for the check: a small triangle at a vertex or on an edge of a big one (sizes 1e1
// to 1e16 apart, touching, across or inside), sharing a vertex, nudged across a line by 1 to
// 2^40 ulps; needles against fat triangles; near-identical pairs.
TEST(TriClipCheck, MadeForIt) {
  Rng g(0x7e7a2d11);
  Tally at_vertex, on_edge, shared, nudged, needles, near_identical;
  for (int i = 0; i < 2000; ++i) {
    const Triangle big0 = {Vec2{0.0, 0.0}, Vec2{1.0, 0.0}, Vec2{urand(g, 0.1, 0.9), urand(g, 0.3, 1.0)}};
    const double ratio = std::pow(10.0, urand(g, 1.0, 16.0));
    Triangle small0;
    for (auto& p : small0) p = {urand(g, -1.0, 1.0) / ratio, urand(g, -1.0, 1.0) / ratio};
    const double theta = urand(g, 0.0, 6.283185307179586);
    const Vec2 shift = {urand(g, -4.0, 4.0), urand(g, -4.0, 4.0)};
    const auto place = [&](const Triangle& t) { return translate(rotate(t, {0.0, 0.0}, theta), shift); };
    // At big's vertex 0 (the vertex itself rotated and shifted like big).
    if (!flat(small0)) check(place(big0), place(small0), at_vertex);
    // On big's edge 0-1, at a random point of it.
    const Vec2 at = {urand(g, 0.05, 0.95), 0.0};
    const Triangle on = translate(small0, at);
    if (!flat(on)) check(place(big0), place(on), on_edge);
    // Sharing big's vertex 0 exactly, in the caller's coordinates.
    const Triangle B = place(big0);
    Triangle s = place(small0);
    s[0] = B[0];
    if (!flat(s)) check(B, s, shared);
    // A vertex of the small one on big's edge line, nudged by about 2^k ulps.
    Triangle n = place(on);
    const int k = irand(g, 0, 40);
    n[1] = B[0] + urand(g, 0.05, 0.95) * (B[1] - B[0]);
    n[1].x += (coin(g) ? 1.0 : -1.0) * std::ldexp(std::abs(n[1].x) + 0x1p-60, k - 52);
    if (!flat(n)) check(B, n, nudged);
  }
  for (int i = 0; i < 2000; ++i) {
    const double aspect = std::pow(10.0, urand(g, 2.0, 12.0));
    const auto [needle, fat] = needle_and_fat(g, aspect);
    const double theta = urand(g, 0.0, 6.283185307179586);
    const Triangle A = rotate(needle, {0.1, 0.0}, theta), B = rotate(fat, {0.1, 0.0}, theta);
    if (!flat(A) && !flat(B)) check(A, B, needles);
    Triangle C, D;
    for (auto& p : C) p = {urand(g, 0.0, 1.0), urand(g, 0.0, 1.0)};
    const double nudge = std::pow(10.0, -urand(g, 9.0, 16.0));
    for (int k = 0; k < 3; ++k)
      D[static_cast<std::size_t>(k)] = C[static_cast<std::size_t>(k)] + Vec2{urand(g, -nudge, nudge), urand(g, -nudge, nudge)};
    const double phi = urand(g, 0.0, 6.283185307179586);
    const Vec2 to = {urand(g, -8.0, 8.0), urand(g, -8.0, 8.0)};
    const Triangle C1 = translate(rotate(C, {0.0, 0.0}, phi), to), D1 = translate(rotate(D, {0.0, 0.0}, phi), to);
    if (!flat(C1) && !flat(D1)) check(C1, D1, near_identical);
  }
  for (const auto& [name, t] : {std::pair<const char*, const Tally&>{"at a vertex", at_vertex}, {"on an edge", on_edge},
                                {"shared vertex", shared}, {"nudged", nudged}, {"needles", needles},
                                {"near-identical", near_identical}}) {
    report(name, t);
    EXPECT_GE(t.accepted, t.pairs * 97 / 100) << name;
  }
}

}  // namespace
