// test_refined_clip.cpp -- the refinement's clipping and its derived error bound
// (src/kernel/refined_clip.hpp, clip_bound, thin_bound; src/kernel/separation.hpp), against GMP.
//
// The refinement clips the smaller tetrahedron S's frame by the bigger B's planes; a result
// stands only where its bound, derived from the computed surface (every face on its plane
// within computed residuals, every fan triangle certainly oriented alike, one ray crossing it
// once), is at most 2^-42 of S, or where an empty result is certain (one plane of B keeps at
// most that much of S, or a plane separates them). Here the clipping runs alone (clip_only) on
// every pair of every kernel test family, whether the kernel would refine it or not, so that the
// bound meets far more configurations than the refinement does: each certified volume must lie
// within its bound of the exact one, each certified empty result must be within 2^-42 of S of
// the exact volume (exactly 0 where a separating plane certified it), and what is not certified
// must stay rare.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "support/generators.hpp"
#include "tetia/exact.hpp"
#include "tetia/kernel_trace.hpp"
#include "tetia/tet_intersection.hpp"

namespace {

using namespace tetia;
using namespace tetia::testgen;

struct ClipTally {
  int pairs = 0, volumes = 0, empty = 0, separated = 0, uncertified = 0, failures = 0;
  double worst_ratio = 0.0;  // error over the bound, over the certified volumes
  double worst_error = 0.0;  // relative to S's exact volume, over everything certified
};

// The clipping alone on (S, B), S the smaller by exact volume.
void check_clip(const Tet& U, const Tet& V, ClipTally& t) {
  const mpq_class vu = exact::volume(U), vv = exact::volume(V);
  if (vu == 0 || vv == 0) return;
  ++t.pairs;
  const Tet& S = vu <= vv ? U : V;
  const Tet& B = vu <= vv ? V : U;
  const mpq_class small = std::min(vu, vv);
  const mpq_class ex = exact::intersection_volume(U, V);
  const detail::NearCoverTrace tr = detail::near_cover_trace(S, B);
  if (!tr.clip_certified) {
    ++t.uncertified;
    return;
  }
  const double err = mpq_class(abs(mpq_class(tr.clipped.volume) - ex) / small).get_d();
  t.worst_error = std::max(t.worst_error, err);
  std::string problem;
  if (tr.clipped.volume > 0.0) {
    ++t.volumes;
    t.worst_ratio = std::max(t.worst_ratio, err / tr.clip_bound);
    if (!(err <= tr.clip_bound && tr.clip_bound <= 0x1p-42))
      problem = "clipping error " + fmt(err) + " of S against its bound " + fmt(tr.clip_bound);
  } else {
    ++t.empty;
    t.separated += tr.clip_separated;
    if (tr.clip_separated && ex != 0) problem = "a separating plane certified, exact volume " + fmt(err) + " of S";
    if (!(err <= 0x1p-42)) problem = "certified empty, exact volume " + fmt(err) + " of S";
  }
  if (!problem.empty() && ++t.failures <= 3) ADD_FAILURE() << problem << "\n  " << fmt_pair(S, B);
}

TEST(RefinedClip, BoundHoldsOnEveryFamily) {
  ClipTally all;
  for (const Family& f : families()) {
    ClipTally t;
    for (const Case& c : f.make()) check_clip(c.U, c.V, t);
    std::printf("[ %-17s ] %5d pairs: %5d volumes (worst %.3g of the bound), %5d empty (%d by a separating "
                "plane), %d not certified; worst error %.3g of S\n",
                f.name, t.pairs, t.volumes, t.worst_ratio, t.empty, t.separated, t.uncertified, t.worst_error);
    EXPECT_EQ(t.failures, 0) << f.name;
    // What is not certified goes to the exact last resort: it must stay rare where the kernel
    // meets it (random pairs), and a minority even on the degenerate families (on 2026-12-06
    // at most 12 % but for Multiscale's 20 %, more than half of them size ratios beyond 2^50,
    // whose planes the refinement cannot resolve: exact by design; elsewhere touching at a
    // point inside an edge or face of the other, and near-duplicate corners).
    if (f.random) {
      EXPECT_LE(t.uncertified, t.pairs / 100) << f.name;
    }
    EXPECT_LE(t.uncertified, t.pairs / 4) << f.name;
    all.pairs += t.pairs;
    all.uncertified += t.uncertified;
    all.volumes += t.volumes;
  }
  EXPECT_GT(all.volumes, all.pairs / 4);
}

// Two wedges whose top and bottom edges cross at right angles a distance h apart: only the
// plane between the edges (an edge-edge axis, not a face) separates them. At h = 1e-3 and 1e-9
// the clipping empties and the separating plane certifies it. Touching (h = 0, the edges cross
// at a point inside both) no margin is left for the rounding; whatever is certified must still
// be 0.
TEST(RefinedClip, EmptyCertifiedByAnEdgePairPlane) {
  for (const double h : {1e-3, 1e-9, 0.0}) {
    const Tet U = {{{-1, 0, 0}, {1, 0, 0}, {0, 1, -1}, {0, -1, -1}}};
    const Tet V = {{{0, -1, h}, {0, 1, h}, {1, 0, 1 + h}, {-1, 0, 1 + h}}};
    // S a quarter of U's size (the clipping works in the smaller one's frame), scaled about a
    // point of U's top edge, so that the edges still cross.
    const Tet S = scale(U, 0.25);
    const detail::NearCoverTrace tr = detail::near_cover_trace(S, V);
    EXPECT_EQ(exact::intersection_volume(S, V), 0) << h;
    if (h > 0.0) {
      EXPECT_TRUE(tr.clip_certified) << h;
      EXPECT_TRUE(tr.clip_separated) << h;
    }
    if (tr.clip_certified) {
      EXPECT_EQ(tr.clipped.volume, 0.0) << h;
    }
    EXPECT_EQ(intersection_volume(S, V), 0.0) << h;
  }
}

// A tetrahedron 10^8 times smaller than B touching B's vertex from outside, beyond none of B's
// face planes (it straddles three of them): only a face plane of S through the shared vertex
// separates them, with no margin at that vertex, which projects to exactly 0 from itself. The
// kernel refines the pair (the size ratio), and the certificate must decide it without the
// exact last resort.
TEST(RefinedClip, TouchingAtASharedVertexCertified) {
  const Tet B = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const double eps : {1e-3, 1e-8}) {
    const Tet S = {{{0, 0, 0}, {-eps, -eps, eps}, {-eps, eps, -eps}, {eps, -eps, -eps}}};
    EXPECT_EQ(exact::intersection_volume(S, B), 0);
    const detail::NearCoverTrace tr = detail::near_cover_trace(S, B);
    EXPECT_TRUE(tr.clip_certified) << eps;
    EXPECT_TRUE(tr.clip_separated) << eps;
    IntersectionStats stats;
    EXPECT_EQ(intersect(S, B, &stats).volume(), 0.0) << eps;
    EXPECT_EQ(intersect(B, S, &stats).volume(), 0.0) << eps;
    EXPECT_EQ(stats.exact_fallbacks, 0) << eps;
  }
}

}  // namespace
