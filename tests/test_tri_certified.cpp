// test_tri_certified.cpp -- the 2D kernel's certified formula (src/kernel/tri_certified_moments.hpp)
// through the public entry points: where it decides (TriIntersectionStats::certified), its
// result must keep its contract against the exact GMP area, whatever the input.
//
//  - a certified area is within 2^-47 of the smaller triangle's area from the exact area (the
//    derived bound; the kernel's own results are held to 1e-12 elsewhere), and at least 2^-30
//    of it less that;
//  - "certainly apart" (certified, area 0) means an exact area of 0;
//  - the result is the same bits in every vertex order and argument order, from every entry
//    point (area, moments, polygon), and the polygon is not empty; the polygon (built from the
//    formula's parts) has consecutive corners on a common line, coordinates exactly 0 on B's
//    edges, and barycentric coordinates that give its points;
//  - on random pairs the formula decides nearly every pair whose boxes overlap (if it stopped
//    deciding, the kernel would still give right answers, and nothing else would notice).
//
// Families: every family of tests/support/generators2d.hpp, and pairs made for the formula's
// decisions: vertices nudged by 1 to 2^40 ulps across an edge line of the other triangle
// (orientations near their error bounds), shallow crossings (edges 1e-3 to 1e-12 rad from
// parallel), near-identical triangles, needles (aspect 1e2 to 1e8) against fat triangles, size ratios 1e1 to 1e6, all
// rotated and translated.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/generators2d.hpp"
#include "tetia/exact.hpp"
#include "tetia/mesh.hpp"
#include "tetia/tri_intersection.hpp"

namespace {

using namespace tetia;
using namespace tetia::testgen2d;

constexpr double kAccepted = 0x1p-47;

struct Tally {
  long pairs = 0, certified = 0, apart = 0, failures = 0;
  double worst = 0.0;  // largest |area - exact| / min(|A|, |B|) among certified results
};

// One pair: the contract where the formula decided.
void check(const Triangle& A, const Triangle& B, Tally& t, const char* what) {
  ++t.pairs;
  TriIntersectionStats st;
  const Polygon P = intersect(A, B, &st);
  if (st.certified == 0) return;
  const double area = intersection_area(A, B);
  const Moments2 mo = intersection_moments(A, B);
  const mpq_class ex = exact::intersection_area(A, B);
  const mpq_class smaller = std::min(abs(exact::area(A)), abs(exact::area(B)));
  std::string fail;
  if (!(area == P.area()) || !(mo.area == area) || !(mo.first == P.moments().first))
    fail = "entry points disagree";
  if (area == 0.0) {
    ++t.apart;
    if (sgn(ex) != 0) fail = "certainly apart, but the exact area is " + fmt(ex.get_d());
    if (!P.empty()) fail = "certainly apart, but the polygon has corners";
  } else {
    ++t.certified;
    const mpq_class err = abs(mpq_class(area) - ex);
    const double rel = mpq_class(err / smaller).get_d();
    t.worst = std::max(t.worst, rel);
    if (!(rel <= kAccepted)) fail = "error " + fmt(rel) + " of the smaller triangle, above 2^-47";
    if (!(mpq_class(area) >= smaller * (0x1p-30 - kAccepted))) fail = "certified area below 2^-30 of the smaller";
    if (P.empty()) fail = "certified area, empty polygon";
  }
  // The polygon built from the formula's parts: consecutive corners share a label, a label of
  // B's edge p means barycentric coordinate p exactly 0, and the coordinates give the point.
  {
    double bmax = 0.0;
    for (const Vec2& q : B) bmax = std::max({bmax, std::abs(q.x), std::abs(q.y)});
    const double dB = diameter(B);
    const int n = P.num_corners();
    for (int k = 0; k < n; ++k) {
      const PolygonCorner& c = P.corner(k);
      const PolygonCorner& d = P.corner((k + 1) % n);
      if (c.labels[0] != d.labels[0] && c.labels[0] != d.labels[1] && c.labels[1] != d.labels[0] &&
          c.labels[1] != d.labels[1])
        fail = "consecutive corners share no label";
      for (const std::uint8_t l : c.labels)
        if (l >= 3 && c.bary[l - 3] != 0.0) fail = "on B's edge, but its coordinate is not 0";
      const Vec2 q = c.bary[0] * B[0] + c.bary[1] * B[1] + c.bary[2] * B[2];
      if (!(std::abs(c.bary[0] + c.bary[1] + c.bary[2] - 1.0) <= 1e-12) ||
          !(std::hypot(q.x - c.point.x, q.y - c.point.y) <= 1e-12 * dB + 16 * 0x1p-53 * bmax))
        fail = "barycentric coordinates do not give the point";
    }
  }
  // Every vertex order and both argument orders: the same bits.
  for (const auto& pa : kPerms3)
    for (const auto& pb : kPerms3) {
      const Triangle a = permute(A, pa), b = permute(B, pb);
      const Moments2 m1 = intersection_moments(a, b), m2 = intersection_moments(b, a);
      if (!(m1.area == mo.area && m1.first == mo.first && m2.area == mo.area && m2.first == mo.first) &&
          !(mo.area == 0.0 && m1.area == 0.0 && m2.area == 0.0))
        fail = "not the same bits in another vertex or argument order";
    }
  if (!fail.empty()) {
    if (++t.failures <= 3)
      ADD_FAILURE() << what << ": " << fail << "\n  " << fmt_pair(A, B) << "\n  " << hex_pair(A, B)
                    << "\n  area " << fmt(area) << ", exact " << fmt(ex.get_d());
  }
}

// Whether the closed bounding boxes of A and B meet: the pairs that reach the formula (the
// entry points answer disjoint boxes before it).
bool boxes_overlap(const Triangle& A, const Triangle& B) {
  return std::max({A[0].x, A[1].x, A[2].x}) >= std::min({B[0].x, B[1].x, B[2].x}) &&
         std::max({B[0].x, B[1].x, B[2].x}) >= std::min({A[0].x, A[1].x, A[2].x}) &&
         std::max({A[0].y, A[1].y, A[2].y}) >= std::min({B[0].y, B[1].y, B[2].y}) &&
         std::max({B[0].y, B[1].y, B[2].y}) >= std::min({A[0].y, A[1].y, A[2].y});
}

void report(const char* name, const Tally& t) {
  std::printf("[ certified] %-22s %6ld pairs: %6ld certified (worst %.3g of the smaller), %6ld apart\n", name,
              t.pairs, t.certified, t.worst, t.apart);
  EXPECT_EQ(t.failures, 0) << name;
}

Triangle rigid(Rng& g, const Triangle& t, double s) {
  const double theta = urand(g, 0.0, 6.283185307179586);
  const Vec2 shift = {urand(g, -8.0, 8.0), urand(g, -8.0, 8.0)};
  return translate(scale(rotate(t, {0.0, 0.0}, theta), s), shift);
}

TEST(TriCertified, EveryFamilyKeepsTheContract) {
  for (const Family& fam : families()) {
    Tally t;
    for (const Case& c : fam.make()) check(c.A, c.B, t, fam.name);
    report(fam.name, t);
  }
}

TEST(TriCertified, DecidesNearlyEveryRandomPair) {
  Rng g(0x7e7a2d01);
  Tally t;
  long overlapping = 0;
  for (int i = 0; i < 20000; ++i) {
    Triangle A, B;
    for (auto& p : A) p = {urand(g, 0.0, 1.0), urand(g, 0.0, 1.0)};
    for (auto& p : B) p = {urand(g, 0.0, 1.0), urand(g, 0.0, 1.0)};
    overlapping += boxes_overlap(A, B);
    check(A, B, t, "random");
  }
  report("random", t);
  std::printf("[ certified] random: %ld of %ld pairs whose boxes overlap decided\n", t.certified + t.apart, overlapping);
  // All but 8 of the benchmark's 810,282 pairs whose boxes overlap are decided (96 % by the first
  // try alone); the rest: orientations within their bounds, small overlaps.
  EXPECT_GE(t.certified + t.apart, overlapping * 99 / 100);
}

// A vertex of B on an edge line of A (rotated, so not exactly), moved by about 1 to 2^40 ulps of
// its abscissa: orientations near and beyond their error bounds.
TEST(TriCertified, NudgedAcrossAnEdgeLine) {
  Rng g(0x7e7a2d02);
  Tally t;
  for (int i = 0; i < 3000; ++i) {
    const Triangle A0 = {Vec2{0.0, 0.0}, Vec2{1.0, 0.0}, Vec2{urand(g, 0.1, 0.9), urand(g, 0.5, 1.0)}};
    const double s = urand(g, 0.1, 0.9);
    Vec2 v = {s, 0.0};  // on A's edge 0-1 before the rotation
    Triangle B0 = {v, Vec2{urand(g, -0.5, 1.5), urand(g, -1.0, -0.2)}, Vec2{urand(g, -0.5, 1.5), urand(g, -1.0, 0.5)}};
    const double theta = urand(g, 0.0, 6.283185307179586);
    const Triangle A = rotate(A0, {0.3, 0.2}, theta);
    Triangle B = rotate(B0, {0.3, 0.2}, theta);
    // About 2^k ulps of the coordinate, k from 0 to 40, either way.
    const int k = irand(g, 0, 40);
    const double step = std::ldexp(std::abs(B[0].x) + 0x1p-60, k - 52);
    B[0].x += coin(g) ? step : -step;
    if (flat(A) || flat(B)) continue;
    check(A, B, t, "nudged");
  }
  report("nudged", t);
}

// Edges of A and B at 1e-3 to 1e-12 rad from parallel, crossing inside both.
TEST(TriCertified, ShallowCrossings) {
  Rng g(0x7e7a2d03);
  Tally t;
  for (int i = 0; i < 3000; ++i) {
    const double angle = std::pow(10.0, -urand(g, 3.0, 12.0));
    const Triangle A0 = {Vec2{0.0, 0.0}, Vec2{1.0, 0.0}, Vec2{urand(g, 0.2, 0.8), urand(g, 0.3, 1.0)}};
    const double c = std::cos(angle), sn = std::sin(angle);
    const Vec2 p = {urand(g, 0.1, 0.5), 0.0};
    const Triangle B0 = {p - 0.4 * Vec2{c, sn}, p + 0.6 * Vec2{c, sn}, Vec2{urand(g, 0.0, 1.0), urand(g, -1.0, 1.0)}};
    if (flat(A0) || flat(B0)) continue;
    check(rigid(g, A0, 1.0), rigid(g, B0, 1.0), t, "shallow");  // two rigid motions: not aligned
    const double theta = urand(g, 0.0, 6.283185307179586);
    check(rotate(A0, {0.0, 0.0}, theta), rotate(B0, {0.0, 0.0}, theta), t, "shallow");
  }
  report("shallow", t);
}

// Near-identical triangles: B = A with each coordinate moved by up to 1e-9 to 1e-15 and turned
// by 1e-7 to 1e-15 rad about its centroid (the peers' near-degenerate pairs are 1e-12 and
// 1e-10): every edge crosses its counterpart at a shallow angle.
TEST(TriCertified, NearIdentical) {
  Rng g(0x7e7a2d05);
  Tally t;
  for (int i = 0; i < 3000; ++i) {
    Triangle A, B;
    for (auto& p : A) p = {urand(g, 0.0, 1.0), urand(g, 0.0, 1.0)};
    const double nudge = std::pow(10.0, -urand(g, 9.0, 15.0)), angle = std::pow(10.0, -urand(g, 7.0, 15.0));
    const Vec2 c = (1.0 / 3.0) * (A[0] + A[1] + A[2]);
    for (int k = 0; k < 3; ++k) {
      const Vec2 p = A[static_cast<std::size_t>(k)] + Vec2{urand(g, -nudge, nudge), urand(g, -nudge, nudge)};
      B[static_cast<std::size_t>(k)] = rotate(p, c, coin(g) ? angle : -angle);
    }
    if (flat(A) || flat(B)) continue;
    check(A, B, t, "near-identical");
  }
  report("near-identical", t);
  // 2,988 measured (2,350 with the first try alone, 2,772 with the second): the rest have an
  // orientation within its error bound even when accurate.
  EXPECT_GT(t.certified, 2900);
}

// Needles against fat triangles, and triangles of sizes 1e1 to 1e6 apart, overlapping.
TEST(TriCertified, NeedlesAndSizeRatios) {
  Rng g(0x7e7a2d04);
  Tally needles, ratios;
  for (int i = 0; i < 3000; ++i) {
    const double aspect = std::pow(10.0, urand(g, 2.0, 8.0));
    const auto [needle, fat] = needle_and_fat(g, aspect);
    const double theta = urand(g, 0.0, 6.283185307179586);
    const Triangle A = rotate(needle, {0.1, 0.0}, theta), B = rotate(fat, {0.1, 0.0}, theta);
    if (!flat(A) && !flat(B)) check(A, B, needles, "needle");
    // The same rigid motion for both (a separate one would move them apart).
    const double ratio = std::pow(10.0, urand(g, 1.0, 6.0));
    const Vec2 at = {urand(g, -0.3, 0.3), urand(g, -0.3, 0.3)};
    const double phi = urand(g, 0.0, 6.283185307179586);
    const Vec2 shift = {urand(g, -8.0, 8.0), urand(g, -8.0, 8.0)};
    const Triangle big = translate(rotate(fat, {0.0, 0.0}, phi), shift);
    const Triangle small = translate(rotate(translate(scale(fat, 1.0 / ratio), at), {0.0, 0.0}, phi), shift);
    if (!flat(big) && !flat(small)) check(big, small, ratios, "size ratio");
  }
  report("needles", needles);
  report("size ratios", ratios);
  // The later tries' accurate det(S) decides nearly every needle (3,000 measured; 228 with
  // Shewchuk's bound on the plain det, which grows with the aspect ratio).
  EXPECT_GT(needles.certified, 2900);
}

// Cells of axis-aligned structured grids (rectangles split along either diagonal): right
// triangles with two vertices of one abscissa, and, where both grids have one spacing, equal
// determinants. Both used to go to the kernel. Against a second grid moved by a fraction of a
// cell (no shared vertex, no collinear edge) every pair must be decided: equal abscissas and
// equal determinants are tie-broken lexicographically, which depends on the point sets only.
TEST(TriCertified, StructuredGrids) {
  Rng g(0x7e7a2d06);
  Tally t;
  long tried = 0;
  const auto cell = [](double h, Vec2 o, int i, int j, int half, bool other_diagonal) {
    const Vec2 p00 = o + Vec2{i * h, j * h}, p10 = o + Vec2{(i + 1) * h, j * h};
    const Vec2 p01 = o + Vec2{i * h, (j + 1) * h}, p11 = o + Vec2{(i + 1) * h, (j + 1) * h};
    if (!other_diagonal) return half == 0 ? Triangle{p00, p10, p11} : Triangle{p00, p11, p01};
    return half == 0 ? Triangle{p00, p10, p01} : Triangle{p10, p11, p01};
  };
  for (const double ratio : {1.0, 1.0 / 1.375, 0.5, 2.0}) {
    for (int trial = 0; trial < 40; ++trial) {
      const double h = 0.125, k = h * ratio;
      const Vec2 shift = {urand(g, 0.05, 0.95) * k, urand(g, 0.05, 0.95) * k};
      const bool da = coin(g), db = coin(g);
      const int i = irand(g, 0, 7), j = irand(g, 0, 7);
      for (int half = 0; half < 2; ++half) {
        const Triangle A = cell(h, {0.0, 0.0}, i, j, half, da);
        // Every cell of the second grid whose box meets A's.
        const int lo_i = static_cast<int>(std::floor((i * h - shift.x) / k)) - 1, hi_i = static_cast<int>(std::ceil(((i + 1) * h - shift.x) / k)) + 1;
        const int lo_j = static_cast<int>(std::floor((j * h - shift.y) / k)) - 1, hi_j = static_cast<int>(std::ceil(((j + 1) * h - shift.y) / k)) + 1;
        for (int bi = lo_i; bi <= hi_i; ++bi)
          for (int bj = lo_j; bj <= hi_j; ++bj)
            for (int bh = 0; bh < 2; ++bh) {
              const Triangle B = cell(k, shift, bi, bj, bh, db);
              tried += boxes_overlap(A, B);
              check(A, B, t, "structured");
            }
      }
    }
  }
  report("structured grids", t);
  std::printf("[ certified] structured grids: %ld of %ld pairs whose boxes overlap decided\n", t.certified + t.apart, tried);
  EXPECT_EQ(t.certified + t.apart, tried);
}

// The cells of a mesh against the same mesh: pairs with a vertex in common. Neighbours only
// touch and must be decided (certainly apart, the closed separation); a cell against itself
// overlaps with every vertex in common and goes to the kernel. A structured mesh, and the same
// with its interior nodes moved at random (unstructured, still conforming), rotated so that no
// edge is axis-aligned in the second case.
TEST(TriCertified, MeshNeighboursTouch) {
  Rng g(0x7e7a2d07);
  for (int variant = 0; variant < 2; ++variant) {
    const int n = 8;
    TriMesh m = make_structured_tri_mesh({n, n}, {0.0, 0.0}, {1.0 / n, 1.0 / n});
    if (variant == 1) {
      const double theta = urand(g, 0.1, 1.4);
      for (std::size_t i = 0; i < m.nodes.size(); ++i) {
        Vec2& p = m.nodes[i];
        const bool boundary = p.x == 0.0 || p.y == 0.0 || p.x == 1.0 || p.y == 1.0;
        if (!boundary) p = p + Vec2{urand(g, -0.3, 0.3) / n, urand(g, -0.3, 0.3) / n};
        p = rotate(p, {0.5, 0.5}, theta);
      }
    }
    Tally t;
    long neighbours = 0, decided = 0;
    for (std::size_t a = 0; a < m.cells.size(); ++a)
      for (std::size_t b = 0; b < m.cells.size(); ++b) {
        const Triangle A = m.cell(a), B = m.cell(b);
        bool common = false;
        for (const Vec2& p : A)
          for (const Vec2& q : B) common |= p.x == q.x && p.y == q.y;
        if (!common) continue;
        TriIntersectionStats st;
        const double area = intersect(A, B, &st).area();
        if (a == b) {
          EXPECT_EQ(st.certified, 0) << "a cell against itself overlaps: the kernel's";
          continue;
        }
        ++neighbours;
        decided += st.certified == 1 && area == 0.0;
        check(A, B, t, variant == 0 ? "structured neighbours" : "moved neighbours");
      }
    report(variant == 0 ? "structured neighbours" : "moved neighbours", t);
    std::printf("[ certified] %s: %ld of %ld neighbours decided apart\n", variant == 0 ? "structured" : "moved", decided, neighbours);
    EXPECT_EQ(decided, neighbours);
  }
}

}  // namespace
