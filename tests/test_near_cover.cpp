// test_near_cover.cpp -- the refinement's near-cover formula (src/kernel/refined_clip.hpp): where
// every plane of B cuts at most a thin part off the smaller tetrahedron S, S n B's volume is S's
// less the parts cut off, each in closed form, with an error bound derived (not calibrated).
//
// Against GMP, on the pairs it is made for and beside them:
//  - near-identical tetrahedra (V = U moved by up to 1e-15 .. 1e-6, U turned by up to 1e-13 ..
//    1e-7 rad), of three shapes (random, well shaped, slivers of height 1e-3), scaled by 2^-40,
//    1 and 2^40 and translated by up to 2^20;
//  - a small S just across a face of a bigger B (size ratios 1 to 1e12, depths 0 to 1e-4 of S);
//  - S with a face exactly in a plane of B (dyadic coordinates), inside B otherwise.
// Every result the formula accepts must be within its own bound of the exact volume (a bound
// the formula computes; the test fails on a single pair beyond it) and within 1e-12 of S; its
// first moments must agree with the clipping's; and the kernel's entry points must agree with
// the exact volume to 1e-12 of the smaller tetrahedron on every pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "support/generators.hpp"
#include "tetia/exact.hpp"
#include "tetia/kernel_trace.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

using namespace tetia;
using namespace tetia::testgen;

struct Tally {
  int pairs = 0, tried = 0, decided = 0, failures = 0;
  double worst_error = 0.0;  // relative to S's exact volume, over the pairs decided
  double worst_ratio = 0.0;  // error over the formula's bound
  double worst_kernel = 0.0; // intersection_volume against exact, relative to the smaller
  // The clipping alone (clip_only): results certified with a volume, certified empty, not certified.
  int clip_volume = 0, clip_empty = 0, clip_uncertified = 0;
  double worst_clip_ratio = 0.0;  // the clipping's error over its bound
};

// The pair as text ready to paste ("Tet U = {...}; Tet V = {...};"), by a stream: g++ 12 at -O3
// reports a false -Wrestrict in fmt_pair's string concatenations as they are inlined here.
std::string pair_text(const Tet& a, const Tet& b) {
  std::ostringstream o;
  o.precision(17);
  const char* name = "U";
  for (const Tet* t : {&a, &b}) {
    o << "Tet " << name << " = {";
    for (std::size_t i = 0; i < 4; ++i)
      o << (i ? ", {" : "{") << (*t)[i].x << ", " << (*t)[i].y << ", " << (*t)[i].z << "}";
    o << "}; ";
    name = "V";
  }
  return o.str();
}

double max_coordinate(const Tet& t) {
  double m = 0.0;
  for (const Vec3& p : t) m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return m;
}

// The clipping alone, against GMP: a certified volume within its derived bound (clip_bound,
// relative to S's exact volume) and within 2^-42 of S; a certified empty result with an exact
// volume within 2^-42 of S.
void check_clip(const detail::NearCoverTrace& tr, const mpq_class& ex, const mpq_class& small, const Tet& S,
                const Tet& B, Tally& t) {
  if (!tr.clip_certified) {
    ++t.clip_uncertified;
    return;
  }
  const double err = mpq_class(abs(mpq_class(tr.clipped.volume) - ex) / small).get_d();
  if (tr.clipped.volume > 0.0) {
    ++t.clip_volume;
    t.worst_clip_ratio = std::max(t.worst_clip_ratio, err / tr.clip_bound);
    if (!(err <= tr.clip_bound && tr.clip_bound <= 0x1p-42) && ++t.failures <= 3)
      ADD_FAILURE() << "clipping error " << fmt(err) << " against its bound " << fmt(tr.clip_bound) << "\n  "
                    << pair_text(S, B);
  } else {
    ++t.clip_empty;
    if (!(err <= 0x1p-42) && ++t.failures <= 3)
      ADD_FAILURE() << "clipping certified empty, exact " << fmt(err) << " of S\n  " << pair_text(S, B);
  }
}

// One pair: the formula (S the smaller by its exact volume) and the kernel against GMP.
void check(const Tet& U, const Tet& V, Tally& t) {
  ++t.pairs;
  const mpq_class vu = exact::volume(U), vv = exact::volume(V);
  const Tet& S = vu <= vv ? U : V;
  const Tet& B = vu <= vv ? V : U;
  const mpq_class small = std::min(vu, vv);
  const mpq_class ex = exact::intersection_volume(U, V);
  const detail::NearCoverTrace tr = detail::near_cover_trace(S, B);
  t.tried += tr.tried;
  if (tr.decided) {
    ++t.decided;
    EXPECT_TRUE(tr.certified);
    const double err = mpq_class(abs(mpq_class(tr.moments.volume) - ex) / small).get_d();
    t.worst_error = std::max(t.worst_error, err);
    t.worst_ratio = std::max(t.worst_ratio, err / tr.bound);
    const bool ok = err <= tr.bound && err <= 1e-12;
    if (!ok && ++t.failures <= 3)
      ADD_FAILURE() << "near-cover error " << fmt(err) << " against its bound " << fmt(tr.bound) << "\n  "
                    << pair_text(S, B);
    // First moments: the clipping's are accurate to a few ulps of S (where it certifies its
    // volume); the formula leaves out the overlaps of the parts cut off, which its acceptance
    // keeps below 2^-44 of S.
    const double scale = small.get_d() * max_coordinate(S) * 1e-12;
    const Vec3 d = tr.moments.first - tr.clipped.first;
    if (tr.clip_certified && !(std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) <= scale) && ++t.failures <= 3)
      ADD_FAILURE() << "first moments differ by " << fmt(std::sqrt(dot(d, d))) << "\n  " << pair_text(S, B);
  }
  check_clip(tr, ex, small, S, B, t);
  // The kernel as users call it, with the formula where the refinement reaches it.
  const double v = intersection_volume(U, V);
  const double err = mpq_class(abs(mpq_class(v) - ex) / small).get_d();
  t.worst_kernel = std::max(t.worst_kernel, err);
  if (!(err <= 1e-12) && ++t.failures <= 3) ADD_FAILURE() << "kernel error " << fmt(err) << "\n  " << pair_text(U, V);
  EXPECT_EQ(intersection_moments(V, U).volume, v);
  EXPECT_EQ(intersect(U, V).volume(), v);
}

void report(const char* name, const Tally& t) {
  std::printf("[ %-9s ] %d pairs, formula tried %d, decided %d: worst error %.3g of S (%.3g of its bound); "
              "kernel worst %.3g; clipping alone: %d volumes (worst %.3g of its bound), %d empty, %d not certified\n",
              name, t.pairs, t.tried, t.decided, t.worst_error, t.worst_ratio, t.worst_kernel, t.clip_volume,
              t.worst_clip_ratio, t.clip_empty, t.clip_uncertified);
  EXPECT_EQ(t.failures, 0);
}

Tet moved(Rng& g, const Tet& t, double nudge, double angle) {
  std::uniform_real_distribution<double> u(-nudge, nudge);
  Tet m;
  for (std::size_t i = 0; i < 4; ++i) m[i] = {t[i].x + u(g), t[i].y + u(g), t[i].z + u(g)};
  const Vec3 c = 0.25 * (((t[0] + t[1]) + t[2]) + t[3]);
  return angle == 0.0 ? m : rotate(m, c, random_unit(g), angle);
}

TEST(NearCover, NearIdenticalTetrahedra) {
  Rng g(0x0c0ffee);
  Tally t;
  for (int shape = 0; shape < 3; ++shape)
    for (const double nudge : {0.0, 1e-15, 1e-12, 1e-9, 1e-6})
      for (const double angle : {0.0, 1e-13, 1e-10, 1e-7})
        for (const int e : {-40, 0, 40})
          for (int n = 0; n < 12; ++n) {
            Tet U0 = shape == 0 ? unit_random_tet(g) : shape == 1 ? fat_tet(g) : sliver(g, 1e-3);
            if (flat(U0)) continue;
            const Vec3 shift{std::ldexp(urand(g, -1, 1), 20), urand(g, -1, 1), 0.0};
            U0 = translate(scale(U0, std::ldexp(1.0, e)), n % 2 == 0 ? Vec3{} : std::ldexp(1.0, e) * shift);
            const Tet V = moved(g, U0, std::ldexp(nudge, e), 0.0);
            const Tet U = moved(g, U0, 0.0, angle);
            if (flat(U) || flat(V)) continue;
            check(U, V, t);
          }
  report("near-id.", t);
  EXPECT_GT(t.decided, t.pairs / 4);
}

TEST(NearCover, SmallTetrahedronAcrossAFace) {
  Rng g(0xfacade);
  Tally t;
  for (const double ratio : {1.0, 1e3, 1e6, 1e9, 1e12})
    for (const double depth : {0.0, 1e-12, 1e-8, 1e-4})
      for (int n = 0; n < 25; ++n) {
        const Tet B = scale(fat_tet(g), 4.0 * ratio);
        const int f = irand(g, 0, 3);
        const Vec3 a = B[static_cast<std::size_t>((f + 1) % 4)], b = B[static_cast<std::size_t>((f + 2) % 4)],
                   c = B[static_cast<std::size_t>((f + 3) % 4)], o = B[static_cast<std::size_t>(f)];
        Vec3 normal = cross(b - a, c - a);
        normal = (1.0 / std::sqrt(dot(normal, normal))) * normal;
        if (dot(normal, o - a) < 0.0) normal = -1.0 * normal;  // into B
        const Vec3 centre = (1.0 / 3.0) * ((a + b) + c);
        Tet S = fat_tet(g);
        double lowest = INFINITY;
        for (const Vec3& p : S) lowest = std::min(lowest, dot(p, normal));
        S = translate(S, centre + (-lowest - depth) * normal);
        if (flat(S)) continue;
        check(S, B, t);
      }
  report("across", t);
  EXPECT_GT(t.decided, 100);
}

TEST(NearCover, FaceInAPlaneOfTheOther) {
  Rng g(0xd1ad1c);
  Tally t;
  const Tet B = scale(kRefTet, 8.0);
  for (int n = 0; n < 400; ++n) {
    // S's face in z = 0 (a face of B), its fourth vertex above; dyadic coordinates, inside B.
    Tet S;
    for (int i = 0; i < 3; ++i)
      S[static_cast<std::size_t>(i)] = {std::ldexp(double(irand(g, 1, 24)), -3), std::ldexp(double(irand(g, 1, 24)), -3), 0.0};
    S[3] = {std::ldexp(double(irand(g, 1, 24)), -3), std::ldexp(double(irand(g, 1, 24)), -3),
            std::ldexp(double(irand(g, 1, 16)), -4 - irand(g, 0, 20))};
    if (flat(S)) continue;
    check(S, B, t);
  }
  report("in-plane", t);
}

}  // namespace
