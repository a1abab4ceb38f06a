// tests/support/supermesh_checks.hpp -- the checks test_supermesh.cpp (tetrahedra) and
// test_supermesh2d.cpp (triangles) share: brute force over all cell pairs with the exact GMP
// reference, and "the supermesh finds exactly those pairs, each with the kernel's moments of its
// two cells, the same with both searches and with one or two threads, bit for bit". One
// template over the mesh type; MeshTraits says what is spelled differently (volume or area,
// Vec3 or Vec2).
#pragma once

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "tetia/exact.hpp"
#include "tetia/mesh.hpp"
#include "tetia/supermesh.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::testsupport {

template <class Mesh>
struct MeshTraits;

template <>
struct MeshTraits<TetMesh> {
  using Result = Supermesh;
  using Piece = SupermeshPiece;
  using Point = Vec3;
  static constexpr int d = 3;
  static constexpr const char* measure_word = "volume";
  static const std::vector<double>& measures(const TetMesh& m) { return m.volumes; }
  static double measure(const Piece& p) { return p.volume; }
  static double total(const Result& r) { return r.intersection_volume(); }
  static mpq_class exact(const Tet& a, const Tet& b) { return exact::intersection_volume(a, b); }
  static double coord(const Vec3& p, int k) { return p[k]; }
  static std::pair<double, Vec3> kernel(const Tet& a, const Tet& b) {
    const Moments m = intersection_moments(a, b);
    return {m.volume, m.first};
  }
};

template <>
struct MeshTraits<TriMesh> {
  using Result = Supermesh2;
  using Piece = SupermeshPiece2;
  using Point = Vec2;
  static constexpr int d = 2;
  static constexpr const char* measure_word = "area";
  static const std::vector<double>& measures(const TriMesh& m) { return m.areas; }
  static double measure(const Piece& p) { return p.area; }
  static double total(const Result& r) { return r.intersection_area(); }
  static mpq_class exact(const Triangle& a, const Triangle& b) { return exact::intersection_area(a, b); }
  static double coord(const Vec2& p, int k) { return k == 0 ? p.x : p.y; }
  static std::pair<double, Vec2> kernel(const Triangle& a, const Triangle& b) {
    const Moments2 m = intersection_moments(a, b);
    return {m.area, m.first};
  }
};

/// Two meshes as one, with separate nodes (two components, a non-conforming interface, or
/// overlapping cells if the caller wants).
template <class Mesh>
Mesh joined(Mesh a, const Mesh& b, const char* name = "joined") {
  const auto base = static_cast<std::int32_t>(a.nodes.size());
  a.nodes.insert(a.nodes.end(), b.nodes.begin(), b.nodes.end());
  for (auto c : b.cells) {
    for (auto& v : c) v += base;
    a.cells.push_back(c);
  }
  tetia::finalize(a, name);
  return a;
}

// The kernel resolves intersections above 1e-14 times the larger cell's measure (as in the
// kernel-vs-exact tests); below it, it may report a tiny positive measure where the exact one is
// zero, or zero where it is tiny, and the supermesh drops pieces of at most 1e-14 times the
// smaller cell's measure. Pairs above twice the resolution must be found; pairs of exact measure
// zero must not be (above the resolution).
inline constexpr double kResolution = 1e-14;

using PairList = std::vector<std::pair<std::int32_t, std::int32_t>>;  // (target, source)

struct BruteForce {
  PairList positive;  // exact measure > 0, sorted
  PairList required;  // exact measure above the resolution
  mpq_class total = 0;
};

/// Every pair with positive exact measure (cells whose boxes do not overlap in their interiors
/// cannot hold one).
template <class Mesh>
BruteForce brute_force(const Mesh& src, const Mesh& tgt) {
  using Tr = MeshTraits<Mesh>;
  struct Box {
    double lo[3], hi[3];
  };
  const auto box_of = [](const auto& cell) {
    Box b;
    for (int k = 0; k < Tr::d; ++k) {
      b.lo[k] = b.hi[k] = Tr::coord(cell[0], k);
      for (const auto& p : cell) {
        b.lo[k] = std::min(b.lo[k], Tr::coord(p, k));
        b.hi[k] = std::max(b.hi[k], Tr::coord(p, k));
      }
    }
    return b;
  };
  const auto overlap = [](const Box& a, const Box& b) {
    for (int k = 0; k < Tr::d; ++k)
      if (!(a.lo[k] < b.hi[k] && b.lo[k] < a.hi[k])) return false;
    return true;
  };
  std::vector<Box> sb(src.num_cells());
  for (std::size_t s = 0; s < src.num_cells(); ++s) sb[s] = box_of(src.cell(s));
  BruteForce bf;
  for (std::size_t t = 0; t < tgt.num_cells(); ++t) {
    const auto T = tgt.cell(t);
    const Box tb = box_of(T);
    for (std::size_t s = 0; s < src.num_cells(); ++s) {
      if (!overlap(sb[s], tb)) continue;
      const mpq_class v = Tr::exact(src.cell(s), T);
      if (sgn(v) <= 0) continue;
      const std::pair<std::int32_t, std::int32_t> key{static_cast<std::int32_t>(t), static_cast<std::int32_t>(s)};
      bf.positive.push_back(key);
      if (v.get_d() > 2 * kResolution * std::max(Tr::measures(src)[s], Tr::measures(tgt)[t])) bf.required.push_back(key);
      bf.total += v;
    }
  }
  return bf;
}

template <class Result>
PairList pairs_of(const Result& sm) {
  PairList p;
  for (const auto& pc : sm.pieces) p.emplace_back(pc.target, pc.source);
  return p;
}

inline double measure_of(const SupermeshPiece& p) { return p.volume; }
inline double measure_of(const SupermeshPiece2& p) { return p.area; }

/// Same pairs, measures and first moments, bit for bit.
template <class Piece>
bool bitwise_equal(const std::vector<Piece>& a, const std::vector<Piece>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].source != b[i].source || a[i].target != b[i].target) return false;
    const double ma = measure_of(a[i]), mb = measure_of(b[i]);
    if (std::memcmp(&ma, &mb, sizeof(double)) != 0) return false;
    if (std::memcmp(&a[i].first, &b[i].first, sizeof(a[i].first)) != 0) return false;
  }
  return true;
}

inline std::string describe(const PairList& list, const char* what) {
  std::string s = std::to_string(list.size()) + " " + what;
  for (std::size_t i = 0; i < std::min<std::size_t>(list.size(), 5); ++i)
    s += " (" + std::to_string(list[i].first) + ", " + std::to_string(list[i].second) + ")";
  return s;
}

template <class Mesh>
typename MeshTraits<Mesh>::Result run(const Mesh& src, const Mesh& tgt, CandidateSearch search, int threads,
                                      bool keep = false) {
  SupermeshOptions o;
  o.search = search;
  o.threads = threads;
  o.keep_polyhedra = keep;
  return supermesh(src, tgt, o);
}

/// The supermesh, both searches, one and two threads, against brute force with exact measures.
/// Returns the front's result.
template <class Mesh>
typename MeshTraits<Mesh>::Result check_against_brute_force(const Mesh& src, const Mesh& tgt,
                                                            const std::string& name) {
  using Tr = MeshTraits<Mesh>;
  SCOPED_TRACE(name);
  const BruteForce bf = brute_force(src, tgt);
  const auto front1 = run(src, tgt, CandidateSearch::front, 1);
  const auto front2 = run(src, tgt, CandidateSearch::front, 2);
  const auto rtree2 = run(src, tgt, CandidateSearch::rtree, 2);
  const PairList got = pairs_of(front1);
  EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
  // Every pair above the resolution is found; every pair found is positive or sub-resolution.
  PairList missing, extra;
  std::set_difference(bf.required.begin(), bf.required.end(), got.begin(), got.end(), std::back_inserter(missing));
  const auto& ms = Tr::measures(src);
  const auto& mt = Tr::measures(tgt);
  for (const auto& pc : front1.pieces) {
    const std::pair<std::int32_t, std::int32_t> key{pc.target, pc.source};
    if (std::binary_search(bf.positive.begin(), bf.positive.end(), key)) continue;
    const double res = kResolution * std::max(ms[static_cast<std::size_t>(pc.source)], mt[static_cast<std::size_t>(pc.target)]);
    if (Tr::measure(pc) > res) extra.push_back(key);
  }
  EXPECT_TRUE(missing.empty()) << describe(missing, "missing (target, source)");
  EXPECT_TRUE(extra.empty()) << describe(extra, (std::string("found with exact ") + Tr::measure_word + " 0 (target, source)").c_str());
  // Each piece is the kernel's intersection_moments of its two cells, bit for bit (the
  // supermesh prepares each source cell once; that must not change the numbers).
  std::size_t not_the_kernel = 0;
  for (const auto& pc : front1.pieces) {
    const auto [m, first] =
        Tr::kernel(src.cell(static_cast<std::size_t>(pc.source)), tgt.cell(static_cast<std::size_t>(pc.target)));
    const double got_m = Tr::measure(pc);
    not_the_kernel += std::memcmp(&m, &got_m, sizeof(double)) != 0 || std::memcmp(&first, &pc.first, sizeof(first)) != 0;
  }
  EXPECT_EQ(not_the_kernel, 0u) << "pieces whose moments differ from intersection_moments of their cells";
  EXPECT_TRUE(bitwise_equal(front1.pieces, front2.pieces)) << "1 thread vs 2 threads";
  EXPECT_TRUE(bitwise_equal(front1.pieces, rtree2.pieces)) << "front vs rtree";
  EXPECT_EQ(front1.candidates, front2.candidates);
  const double exact_total = bf.total.get_d();
  EXPECT_NEAR(Tr::total(front1), exact_total, 1e-13 * std::max(1.0, exact_total));
  for (const auto& pc : front1.pieces)
    EXPECT_GT(Tr::measure(pc), kResolution * std::min(ms[static_cast<std::size_t>(pc.source)],
                                                      mt[static_cast<std::size_t>(pc.target)]));
  std::printf("  %-40s %4zu x %4zu cells: %5zu pairs (%5zu exact > 0, %5zu above resolution), candidates: "
              "front %5zu, rtree %5zu\n",
              name.c_str(), src.num_cells(), tgt.num_cells(), front1.pieces.size(), bf.positive.size(),
              bf.required.size(), front1.candidates, rtree2.candidates);
  return front1;
}

}  // namespace tetia::testsupport
