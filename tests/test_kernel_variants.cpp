// The kernels' compilations for different instruction sets (src/kernel/kernel_variant.hpp)
// compute the same numbers bit for bit: every entry point of every variant this CPU runs,
// against the baseline's, on every test family of each kernel (random, degenerate, slivers, size
// ratios, scales, far from the origin) and on 10^5 more random pairs, including the statistics
// and the whole polyhedron or polygon (points, barycentric coordinates, labels, facets).
// Where the build has it (tests/CMakeLists.txt, TETIA_TEST_PORTABLE_KERNEL), the kernels' portable
// scalar code, the other side of every SSE2 branch, is one more variant compared here.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../src/kernel/kernel_variant.hpp"  // the variants (internal)
#include "../src/kernel/one_to_many.hpp"     // OneToMany, conditioning (internal)
#include "support/generators.hpp"
#include "support/generators2d.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

#if defined(TETIA_TEST_PORTABLE_KERNEL)
namespace tetia::detail::portable {
extern const KernelVariant variant;  // src/kernel/tet_intersection_portable.cpp
}
#endif

namespace tetia {
namespace {

using detail::KernelVariant;

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool same_moments(const Moments& a, const Moments& b) {
  return same_bits(a.volume, b.volume) && same_bits(a.first.x, b.first.x) && same_bits(a.first.y, b.first.y) &&
         same_bits(a.first.z, b.first.z);
}

// Everything a Polyhedron reports, compared bit for bit; "" where the same, else what differs.
std::string polyhedron_difference(const Polyhedron& a, const Polyhedron& b) {
  if (!same_moments(a.moments(), b.moments())) return "moments";
  if (a.num_corners() != b.num_corners() || a.num_facets() != b.num_facets()) return "counts";
  if (a.touched_faces_of_v() != b.touched_faces_of_v()) return "touched faces";
  for (int c = 0; c < a.num_corners(); ++c) {
    const Corner &x = a.corner(c), &y = b.corner(c);
    if (!same_bits(x.point.x, y.point.x) || !same_bits(x.point.y, y.point.y) || !same_bits(x.point.z, y.point.z))
      return "point of corner " + std::to_string(c);
    for (int p = 0; p < 4; ++p)
      if (!same_bits(x.bary[static_cast<std::size_t>(p)], y.bary[static_cast<std::size_t>(p)]))
        return "bary of corner " + std::to_string(c);
    if (x.labels != y.labels) return "labels of corner " + std::to_string(c);
  }
  for (int f = 0; f < a.num_facets(); ++f) {
    if (a.facet_label(f) != b.facet_label(f)) return "label of facet " + std::to_string(f);
    const auto fa = a.facet(f), fb = b.facet(f);
    if (fa.size() != fb.size() || !std::equal(fa.begin(), fa.end(), fb.begin())) return "facet " + std::to_string(f);
  }
  return "";
}

bool same_stats(const IntersectionStats& a, const IntersectionStats& b) {
  return a.edge_inherited == b.edge_inherited && a.edge_paired == b.edge_paired &&
         a.edge_straight_line == b.edge_straight_line && a.edge_computed == b.edge_computed &&
         a.face_inherited == b.face_inherited && a.face_paired == b.face_paired &&
         a.face_computed == b.face_computed && a.nonconvex_lines == b.nonconvex_lines &&
         a.corner_coordinates == b.corner_coordinates && a.guardrail_clamps == b.guardrail_clamps &&
         a.reference_swaps == b.reference_swaps && a.inconsistencies == b.inconsistencies &&
         a.retries == b.retries && a.rescaled == b.rescaled && a.refined == b.refined &&
         a.exact_fallbacks == b.exact_fallbacks && a.calls == b.calls;
}

// Every entry point of `v` against the baseline's on (U, V), in both argument orders; "" where
// all agree, else the first that does not.
std::string variant_difference(const KernelVariant& base, const KernelVariant& v, const Tet& U, const Tet& V) {
  for (int order = 0; order < 2; ++order) {
    const Tet& A = order == 0 ? U : V;
    const Tet& B = order == 0 ? V : U;
    const std::string which = order == 0 ? " (U, V)" : " (V, U)";
    const double vol = base.volume(A, B), vol_v = v.volume(A, B);
    if (!same_bits(vol, vol_v)) return "intersection_volume" + which;
    if (!same_moments(base.moments(A, B), v.moments(A, B))) return "intersection_moments" + which;
    IntersectionStats sb, sv;
    const Polyhedron pb = base.intersect(A, B, &sb), pv = v.intersect(A, B, &sv);
    if (const std::string d = polyhedron_difference(pb, pv); !d.empty()) return "intersect with statistics" + which + ": " + d;
    if (!same_stats(sb, sv)) return "statistics" + which;
    if (const std::string d = polyhedron_difference(base.intersect(A, B, nullptr), v.intersect(A, B, nullptr));
        !d.empty())
      return "intersect" + which + ": " + d;
    const detail::OneToMany many(A);
    const detail::Conditioning cb = detail::conditioning(B);
    unsigned faces_b = 0, faces_v = 0;
    if (!same_moments(base.one_to_many_moments(many, B, cb, &faces_b), v.one_to_many_moments(many, B, cb, &faces_v)) ||
        faces_b != faces_v)
      return "OneToMany::moments" + which;
    Polyhedron ob, ov;
    faces_b = faces_v = 0;
    const Moments mb = base.one_to_many_intersect(many, B, cb, ob, &faces_b);
    const Moments mv = v.one_to_many_intersect(many, B, cb, ov, &faces_v);
    if (!same_moments(mb, mv) || faces_b != faces_v) return "OneToMany::intersect" + which;
    if (mb.volume != 0.0)
      if (const std::string d = polyhedron_difference(ob, ov); !d.empty()) return "OneToMany::intersect" + which + ": " + d;
  }
  return "";
}

bool same_moments(const Moments2& a, const Moments2& b) {
  return same_bits(a.area, b.area) && same_bits(a.first.x, b.first.x) && same_bits(a.first.y, b.first.y);
}

std::string polygon_difference(const Polygon& a, const Polygon& b) {
  if (!same_moments(a.moments(), b.moments())) return "moments";
  if (a.num_corners() != b.num_corners()) return "counts";
  if (a.touched_edges_of_b() != b.touched_edges_of_b()) return "touched edges";
  for (int c = 0; c < a.num_corners(); ++c) {
    const PolygonCorner &x = a.corner(c), &y = b.corner(c);
    if (!same_bits(x.point.x, y.point.x) || !same_bits(x.point.y, y.point.y)) return "point of corner " + std::to_string(c);
    for (int p = 0; p < 3; ++p)
      if (!same_bits(x.bary[static_cast<std::size_t>(p)], y.bary[static_cast<std::size_t>(p)]))
        return "bary of corner " + std::to_string(c);
    if (x.labels != y.labels) return "labels of corner " + std::to_string(c);
  }
  return "";
}

bool same_stats(const TriIntersectionStats& a, const TriIntersectionStats& b) {
  return a.edge_inherited == b.edge_inherited && a.edge_paired == b.edge_paired &&
         a.edge_straight_line == b.edge_straight_line && a.edge_computed == b.edge_computed &&
         a.corner_coordinates == b.corner_coordinates && a.guardrail_clamps == b.guardrail_clamps &&
         a.reference_swaps == b.reference_swaps && a.inconsistencies == b.inconsistencies &&
         a.retries == b.retries && a.refined == b.refined && a.rescaled == b.rescaled &&
         a.exact_fallbacks == b.exact_fallbacks && a.calls == b.calls;
}

// The 2D kernel's entry points, as variant_difference.
std::string variant_difference(const KernelVariant& base, const KernelVariant& v, const Triangle& A0,
                               const Triangle& B0) {
  for (int order = 0; order < 2; ++order) {
    const Triangle& A = order == 0 ? A0 : B0;
    const Triangle& B = order == 0 ? B0 : A0;
    const std::string which = order == 0 ? " (A, B)" : " (B, A)";
    if (!same_bits(base.tri_area(A, B), v.tri_area(A, B))) return "intersection_area" + which;
    if (!same_moments(base.tri_moments(A, B), v.tri_moments(A, B))) return "intersection_moments" + which;
    TriIntersectionStats sb, sv;
    if (const std::string d = polygon_difference(base.tri_intersect(A, B, &sb), v.tri_intersect(A, B, &sv)); !d.empty())
      return "intersect with statistics" + which + ": " + d;
    if (!same_stats(sb, sv)) return "statistics" + which;
    if (const std::string d = polygon_difference(base.tri_intersect(A, B, nullptr), v.tri_intersect(A, B, nullptr));
        !d.empty())
      return "intersect" + which + ": " + d;
  }
  return "";
}

std::vector<const KernelVariant*> others() {
  std::vector<const KernelVariant*> v = detail::kernel_variants();
  v.erase(v.begin());  // the baseline
#if defined(TETIA_TEST_PORTABLE_KERNEL)
  v.push_back(&detail::portable::variant);
#endif
  return v;
}

TEST(KernelVariants, BaselineFirstAndTheChosenOneRunsHere) {
  const std::vector<const KernelVariant*> all = detail::kernel_variants();
  ASSERT_FALSE(all.empty());
  EXPECT_STREQ(all.front()->name, "baseline");
  bool listed = false;
  for (const KernelVariant* v : all) listed |= v == &detail::kernel_variant();
  EXPECT_TRUE(listed) << "the chosen variant is one this CPU runs";
  // The public entry points are the chosen variant's.
  const Tet U = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  const Tet V = {Vec3{0.1, 0.1, 0.1}, Vec3{1.1, 0.2, 0.1}, Vec3{0.2, 1.1, 0.1}, Vec3{0.1, 0.2, 1.3}};
  EXPECT_TRUE(same_bits(intersection_volume(U, V), detail::kernel_variant().volume(U, V)));
}

// The choice: the variant TETIA_KERNEL_VARIANT names where this CPU runs it, else the last
// (fastest) one. tests/CMakeLists.txt runs this test once more with TETIA_KERNEL_VARIANT=baseline.
TEST(KernelVariants, TheEnvironmentOrTheFastestIsChosen) {
  const std::vector<const KernelVariant*> all = detail::kernel_variants();
  const KernelVariant* expected = all.back();
  if (const char* asked = std::getenv("TETIA_KERNEL_VARIANT"))
    for (const KernelVariant* v : all)
      if (std::string(asked) == v->name) expected = v;
  EXPECT_EQ(&detail::kernel_variant(), expected) << "chosen " << detail::kernel_variant().name << ", expected "
                                                 << expected->name;
}

TEST(KernelVariants, EveryFamilyBitForBit) {
  const std::vector<const KernelVariant*> variants = others();
  if (variants.empty()) GTEST_SKIP() << "this CPU runs only the baseline (no x86-64-v3, or not built for it)";
  const KernelVariant& base = *detail::kernel_variants().front();
  for (const KernelVariant* v : variants)
    for (const testgen::Family& family : testgen::families()) {
      int differing = 0;
      const std::vector<testgen::Case> cases = family.make();
      for (const testgen::Case& c : cases) {
        const std::string d = variant_difference(base, *v, c.U, c.V);
        if (!d.empty() && ++differing <= 3)
          ADD_FAILURE() << v->name << " differs from the baseline in " << d << " on " << family.name << "/"
                        << c.kind << ": " << testgen::fmt_pair(c.U, c.V);
      }
      EXPECT_EQ(differing, 0) << v->name << ", family " << family.name << " (" << cases.size() << " pairs)";
    }
}

TEST(KernelVariants, EveryFamilyBitForBit2D) {
  const std::vector<const KernelVariant*> variants = others();
  if (variants.empty()) GTEST_SKIP() << "this CPU runs only the baseline (no x86-64-v3, or not built for it)";
  const KernelVariant& base = *detail::kernel_variants().front();
  for (const KernelVariant* v : variants)
    for (const testgen2d::Family& family : testgen2d::families()) {
      int differing = 0;
      const std::vector<testgen2d::Case> cases = family.make();
      for (const testgen2d::Case& c : cases) {
        const std::string d = variant_difference(base, *v, c.A, c.B);
        if (!d.empty() && ++differing <= 3)
          ADD_FAILURE() << v->name << " differs from the baseline in " << d << " on " << family.name << "/"
                        << c.kind << ": " << testgen2d::fmt_pair(c.A, c.B);
      }
      EXPECT_EQ(differing, 0) << v->name << ", family " << family.name << " (" << cases.size() << " pairs)";
    }
}

// As bench/'s random pairs: two tetrahedra with vertices uniform in the unit cube (most overlap).
TEST(KernelVariants, RandomPairsBitForBit) {
  const std::vector<const KernelVariant*> variants = others();
  if (variants.empty()) GTEST_SKIP() << "this CPU runs only the baseline (no x86-64-v3, or not built for it)";
  const KernelVariant& base = *detail::kernel_variants().front();
  std::mt19937_64 rng(0x7e7a7a71);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto tet = [&] {
    Tet t;
    for (Vec3& p : t) p = {u(rng), u(rng), u(rng)};
    return t;
  };
  for (const KernelVariant* v : variants) {
    int differing = 0;
    for (int n = 0; n < 100000; ++n) {
      const Tet U = tet(), V = tet();
      const std::string d = variant_difference(base, *v, U, V);
      if (!d.empty() && ++differing <= 3)
        ADD_FAILURE() << v->name << " differs from the baseline in " << d << ": " << testgen::fmt_pair(U, V);
    }
    EXPECT_EQ(differing, 0) << v->name;
  }
}

TEST(KernelVariants, RandomPairsBitForBit2D) {
  const std::vector<const KernelVariant*> variants = others();
  if (variants.empty()) GTEST_SKIP() << "this CPU runs only the baseline (no x86-64-v3, or not built for it)";
  const KernelVariant& base = *detail::kernel_variants().front();
  std::mt19937_64 rng(0x7e7a7a72);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto triangle = [&] {
    Triangle t;
    for (Vec2& p : t) p = {u(rng), u(rng)};
    return t;
  };
  for (const KernelVariant* v : variants) {
    int differing = 0;
    for (int n = 0; n < 100000; ++n) {
      const Triangle A = triangle(), B = triangle();
      const std::string d = variant_difference(base, *v, A, B);
      if (!d.empty() && ++differing <= 3)
        ADD_FAILURE() << v->name << " differs from the baseline in " << d << ": " << testgen2d::fmt_pair(A, B);
    }
    EXPECT_EQ(differing, 0) << v->name;
  }
}

}  // namespace
}  // namespace tetia
