// test_tri_vs_exact.cpp -- the 2D kernel's area against the exact GMP reference.
//
// For every pair of every family (tests/support/generators2d.hpp): >= 10^4 random pairs and
// >= 10^4 degenerate pairs built so that the degeneracy is exact in doubles.
//
//  - error |a - exact| / min(|A|, |B|) <= 1e-12 (max(|A|, |B|) for slivers and tiny-in-big),
//    for intersect(A, B).area(), the fast path intersection_area(A, B) and
//    intersection_moments(A, B).area;
//  - the three are the same number: intersection_area(A, B) == intersect(A, B).area() ==
//    intersection_moments(A, B).area, bit for bit (one code path), and intersect's first
//    moments equal intersection_moments' first moments;
//  - no vanishing: exact > 1e-14 max(|A|, |B|) (above the resolution of the arithmetic, see
//    kResolution) implies a non-empty polygon of positive area (for tiny-in-big, built without
//    perturbation, exact > 1e-14 min(|A|, |B|) already does); exact = 0 implies an area
//    <= 1e-15 norm; touching from outside along a shared or collinear edge (and, on the exact
//    lattice, every pair of exact area 0) gives exactly 0 and an empty polygon;
//  - stats.inconsistencies == stats.retries on every call (the only inconsistency allowed is a
//    retry that succeeded, as in 3D); area never negative or NaN;
//  - the reference itself is cross-checked where the answer is known by construction
//    (identical triangles: |A|; a tiny triangle strictly inside a big one: |tiny|; touching
//    from outside: 0).
//
// A failure prints the pair with 17 digits and as hex floats (paste-able), the areas and the
// stats. Each family prints its worst error per sub-family and records it with RecordProperty.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "support/generators2d.hpp"
#include "tetia/exact.hpp"
#include "tetia/tri_intersection.hpp"

namespace {

using namespace tetia;
using namespace tetia::testgen2d;

constexpr double kTol = 1e-12;      // relative area error
constexpr double kZeroTol = 1e-15;  // exact zero: kernel area <= kZeroTol * norm
// No vanishing is required of intersections above the resolution of double arithmetic: a pair
// nudged by an ulp can overlap by 1e-17 of its area, or 1e-50, which no floating-point method
// resolves. Below kResolution * max(|A|, |B|) either answer (empty, or a sliver) is within the
// error bound already checked; above it the polygon must be non-empty with positive area.
constexpr double kResolution = 1e-14;
constexpr int kMaxReported = 3;  // failures printed in full per kind of failed check

struct Worst {
  double err = 0.0;
  std::size_t index = 0;
  int pairs = 0;
};

void run_family(const char* name) {
  const Family& fam = family(name);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Case> cases = fam.make();
  std::map<std::string, Worst> worst;     // per sub-family
  std::map<std::string, int> categories;  // failed checks per sub-family and kind of check
  Worst overall;
  int failures = 0, nonempty = 0, exact_zero = 0, sub_resolution = 0, max_corners = 0;
  TriIntersectionStats total;

  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    TriIntersectionStats st;
    const Polygon P = intersect(c.A, c.B, &st);
    total += st;
    const double a = P.area();
    const double afast = intersection_area(c.A, c.B);
    const Moments2 mo = intersection_moments(c.A, c.B);
    const mpq_class ex = exact::intersection_area(c.A, c.B);
    const double exd = exact::intersection_area_double(c.A, c.B);  // correctly rounded
    const mpq_class exA = exact::area(c.A), exB = exact::area(c.B);
    const double areaA = exA.get_d(), areaB = exB.get_d();
    const double norm = c.norm == Norm::Min ? std::min(areaA, areaB) : std::max(areaA, areaB);
    const double err = mpq_class(abs(mpq_class(a) - ex)).get_d() / norm;
    const double err_fast = mpq_class(abs(mpq_class(afast) - ex)).get_d() / norm;
    const double e = std::max(err, err_fast);
    if (sgn(ex) > 0) ++nonempty;
    else ++exact_zero;
    max_corners = std::max(max_corners, P.num_corners());

    Worst& w = worst[c.kind];
    ++w.pairs;
    ++overall.pairs;
    if (!(e <= w.err)) w.err = e, w.index = i;
    if (!(e <= overall.err)) overall.err = e, overall.index = i;

    std::string what;
    bool report = false;  // print in full: among the first kMaxReported of one of its checks
    auto fail = [&](const std::string& category, const std::string& detail = "") {
      what += (what.empty() ? "" : "; ") + category + (detail.empty() ? "" : " (" + detail + ")");
      report |= ++categories[std::string(c.kind) + ": " + category] <= kMaxReported;
    };
    if (sgn(exA) == 0 || sgn(exB) == 0) fail("TEST SETUP: the generator produced a flat triangle");
    if (!(a >= 0.0) || !(afast >= 0.0) || !(mo.area >= 0.0)) fail("negative or NaN area");
    if (!(err <= kTol)) fail("intersect() error > 1e-12", fmt(err));
    if (!(err_fast <= kTol)) fail("intersection_area() error > 1e-12", fmt(err_fast));
    if (!(afast == a)) fail("intersection_area() != intersect().area()", fmt(afast) + " vs " + fmt(a));
    if (!(mo.area == a)) fail("intersection_moments().area != intersect().area()", fmt(mo.area) + " vs " + fmt(a));
    if (!(mo.first == P.moments().first))
      fail("intersection_moments().first != intersect().moments().first",
           fmt(mo.first) + " vs " + fmt(P.moments().first));
    if (P.empty() && a != 0.0) fail("empty polygon with nonzero area", fmt(a));
    if (st.inconsistencies != st.retries) fail("stats.inconsistencies != stats.retries (a contradiction, or labels that closed with neither reference)");
    // No vanishing above the resolution of the arithmetic (see kResolution).
    const bool real = exd > kResolution * std::max(areaA, areaB);
    if (real && P.empty()) fail("vanished: exact > 1e-14 max(|A|,|B|) but the polygon is empty");
    if (real && !(a > 0.0)) fail("vanished: exact > 1e-14 max(|A|,|B|) but intersect() area 0");
    if (real && !(afast > 0.0)) fail("vanished: exact > 1e-14 max(|A|,|B|) but intersection_area() 0");
    if (sgn(ex) > 0 && !real) ++sub_resolution;
    // A tiny triangle's overlap with a big one is built exactly (no perturbation), so it must
    // not vanish even when it is far below the big one's resolution: 1e-14 of the tiny area.
    if (std::string(fam.name) == "TinyInBig" && exd > kResolution * std::min(areaA, areaB) &&
        (P.empty() || !(a > 0.0)))
      fail("vanished: tiny-in-big, exact > 1e-14 min(|A|,|B|) but the polygon is empty or area 0");
    if (sgn(ex) == 0 && !(a <= kZeroTol * norm)) fail("exact 0 but area > 1e-15 norm", fmt(a));
    if (c.exact_zero) {
      if (sgn(ex) != 0) fail("REFERENCE: touching from outside but exact area > 0", fmt(exd));
      if (a != 0.0 || afast != 0.0) fail("exact 0 by construction: area not exactly zero");
      // polygon.hpp: touching gives an empty polygon, not a zero-area one.
      if (!P.empty())
        fail("exact 0 by construction: polygon not empty",
             std::to_string(P.num_corners()) + " corners, area " + fmt(a));
    }
    // Cross-checks of the reference where the answer is known by construction.
    if (std::string(fam.name) == "IdenticalPermuted" && ex != exA)
      fail("REFERENCE: identical triangles but exact != |A|");
    if (std::string(fam.name) == "TinyInBig" && std::string(c.kind) == "inside" &&
        ex != std::min(exA, exB))
      fail("REFERENCE: tiny strictly inside big but exact != |tiny|");

    if (!what.empty()) {
      ++failures;
      if (report) {
        ADD_FAILURE() << fam.name << "/" << c.kind << " pair #" << i << ": " << what << "\n  "
                      << fmt_pair(c.A, c.B) << "\n  as hex floats:\n  " << hex_pair(c.A, c.B)
                      << "\n  intersect " << fmt(a) << " (corners " << P.num_corners()
                      << "), fast " << fmt(afast) << ", moments " << fmt(mo.area) << ", exact "
                      << fmt(exd) << ", |A| " << fmt(areaA) << ", |B| " << fmt(areaB)
                      << "\n  stats: " << fmt_stats(st);
      }
    }
  }

  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ family   ] %s: %d pairs (%d with exact area > 0, of which %d below the "
              "resolution; %d exact 0), worst error %.3g, at most %d corners, %d failures, "
              "%.1f s\n",
              fam.name, overall.pairs, nonempty, sub_resolution, exact_zero, overall.err,
              max_corners, failures, secs);
  for (const auto& [kind, w] : worst)
    std::printf("[   kind   ]   %-22s %6d pairs, worst error %.3g (pair #%zu)\n", kind.c_str(),
                w.pairs, w.err, w.index);
  if (overall.pairs > 0) {
    const Case& c = cases[overall.index];
    std::printf("[  worst   ]   %s\n", fmt_pair(c.A, c.B).c_str());
  }
  std::printf("[  stats   ]   %s\n", fmt_stats(total).c_str());
  for (const auto& [what, n] : categories)
    std::printf("[ failed   ]   %5d x %s\n", n, what.c_str());
  ::testing::Test::RecordProperty("pairs", overall.pairs);
  ::testing::Test::RecordProperty("worst_error", fmt(overall.err));
  ::testing::Test::RecordProperty("failures", failures);
  EXPECT_EQ(failures, 0) << fam.name << ": " << failures << " of " << cases.size()
                         << " pairs failed (the first " << kMaxReported
                         << " of each kind of failed check shown)";
  EXPECT_EQ(total.inconsistencies, total.retries);
}

// The issue's counts: at least 10^4 random and 10^4 degenerate pairs.
TEST(TriVsExact, Counts) {
  std::size_t random = 0, degenerate = 0;
  for (const Family& f : families()) {
    const std::size_t n = f.make().size();
    std::printf("[  counts  ] %-18s %6zu\n", f.name, n);
    (f.random ? random : degenerate) += n;
  }
  std::printf("[  counts  ] random %zu, degenerate %zu\n", random, degenerate);
  EXPECT_GE(random, 10000u);
  EXPECT_GE(degenerate, 10000u);
}

TEST(TriVsExact, Random) { run_family("Random"); }
TEST(TriVsExact, IdenticalPermuted) { run_family("IdenticalPermuted"); }
TEST(TriVsExact, SharedEdges) { run_family("SharedEdges"); }
TEST(TriVsExact, CollinearEdges) { run_family("CollinearEdges"); }
TEST(TriVsExact, VertexOnBoundary) { run_family("VertexOnBoundary"); }
TEST(TriVsExact, Perturbed) { run_family("Perturbed"); }
TEST(TriVsExact, Rotated) { run_family("Rotated"); }
TEST(TriVsExact, FarFromOrigin) { run_family("FarFromOrigin"); }
TEST(TriVsExact, Slivers) { run_family("Slivers"); }
TEST(TriVsExact, TinyInBig) { run_family("TinyInBig"); }
TEST(TriVsExact, Lattice) { run_family("Lattice"); }
TEST(TriVsExact, Adversarial) { run_family("Adversarial"); }

}  // namespace
