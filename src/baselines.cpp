// baselines.cpp -- the two floating-point methods the paper compares against (Section 5.2), for
// tetrahedra and (at the end) for triangles.
//
// Neither is robust, on purpose: they are the methods as usually written. What they do promise
// is to terminate, not to touch memory out of bounds, and to return a finite value >= 0 for any
// input (0 for non-finite or flat input). Both work in fixed-size arrays: no heap allocation.
#include "tetia/baselines.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace tetia::baselines {
namespace {

bool all_finite(const Tet& t) {
  for (const Vec3& p : t) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  }
  return true;
}

double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

// Face k of a tetrahedron is the one opposite vertex k. These vertex orders make every face
// counter-clockwise seen from outside when orient3d(t[0], t[1], t[2], t[3]) > 0.
constexpr int outward_face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// =============================================================================================
// Sutherland-Hodgman clipping of a closed polyhedron.
// =============================================================================================

// Capacities. In exact arithmetic every stage is a convex polytope with at most 8 facets, 12
// vertices and 18 edges, so a clip creates at most 7 points and a polygon has at most 7 corners.
// Rounding can make the mesh slightly non-convex (a plane may then cross it more often), hence
// the margins. Every write is still checked; a clip that would overflow makes the method give up
// and return 0, which is an accepted failure of a non-robust baseline, not undefined behaviour.
constexpr int kMaxVerts = 128;  // indices are stored as uint8_t
constexpr int kMaxPolys = 24;
constexpr int kMaxPolySize = 24;
constexpr int kMaxSegs = 64;

struct Poly {
  int n = 0;
  std::array<std::uint8_t, kMaxPolySize> v;  // left uninitialised: only v[0..n) is read
};

// Polygons of a closed, consistently outward-oriented mesh, as indices into a VertexPool.
struct Mesh {
  int num_polys = 0;
  std::array<Poly, kMaxPolys> polys;
};

// Vertices are only ever appended (a clip adds its crossing points and leaves the others alone,
// even those it cuts away), so all stages share one pool and nothing is copied. `live` lists the
// vertices the current mesh uses, so that each distance is computed once per clip and the early
// exits look at the current mesh only. The storage is deliberately left uninitialised: zeroing
// it on every call was a visible part of the cost.
struct VertexPool {
  int n = 0;
  int num_live = 0;
  union {
    Vec3 v[kMaxVerts];
  };
  union {
    std::uint8_t live[kMaxVerts];
  };
  VertexPool() {}
};

struct Plane {
  Vec3 n;
  double offset;  // kept side: dot(n, x) - offset >= 0
};

// The four inward planes of V, normal and offset computed from V's own vertices. All four are
// oriented from one sign, that of V's computed orientation, rather than face by face against the
// opposite vertex: for a nearly flat V the per-face tests can disagree, and one flipped plane
// keeps a slab of U instead of (almost) nothing. Returns false when V is flat as computed.
bool inward_planes(const Tet& V, std::array<Plane, 4>& planes) {
  const double orientation = orient3d(V[0], V[1], V[2], V[3]);
  if (!(orientation != 0.0) || !std::isfinite(orientation)) return false;
  // outward_face is counter-clockwise from outside for a right-handed tetrahedron, so its
  // normal points outward there; inward is the opposite, and the reverse for a left-handed one.
  const double sign = orientation > 0.0 ? -1.0 : 1.0;
  for (int k = 0; k < 4; ++k) {
    const Vec3 a = V[outward_face[k][0]];
    const Vec3 b = V[outward_face[k][1]];
    const Vec3 c = V[outward_face[k][2]];
    const Vec3 n = sign * cross(b - a, c - a);
    planes[k] = {n, dot(n, a)};
  }
  return true;
}

enum class ClipResult { kUnchanged, kClipped, kEmpty, kOverflow };

// Clips `in` by `plane` into `out` and closes the cut with new polygons; crossing points are
// appended to `pool` and `pool.live` becomes the vertex set of `out`. kUnchanged: nothing is
// outside, `out` untouched (use `in`); kEmpty: nothing strictly inside.
//
// Conventions that keep the mesh closed:
//  - A vertex at distance exactly 0 counts as inside and is itself the cut point: no duplicate
//    point is created next to it.
//  - The crossing point of an edge is computed once per edge (from its lower-index endpoint) and
//    shared by the two polygons that use the edge, so the cut segments meet at identical indices
//    and chain by index equality, never by comparing coordinates.
//  - Each polygon is walked from a kept vertex, so every excursion outside is an exit followed by
//    an entry; the segment exit -> entry is an edge of the clipped polygon whose twin is missing.
//    The cap is made of those segments reversed.
ClipResult clip(const Mesh& in, const Plane& plane, VertexPool& pool, Mesh& out) {
  // Distances of the vertices in use (those cut away earlier are not looked at).
  std::array<double, kMaxVerts> s;
  const int pool_before = pool.n;
  bool any_in = false, any_out = false;
  for (int i = 0; i < pool.num_live; ++i) {
    const int a = pool.live[i];
    const double d = dot(plane.n, pool.v[a]) - plane.offset;
    s[a] = d;
    any_in = any_in || d > 0.0;
    any_out = any_out || d < 0.0;
  }
  if (!any_out) return ClipResult::kUnchanged;
  if (!any_in) return ClipResult::kEmpty;  // at most a flat piece on the plane remains

  // The next live set: the kept vertices now, the crossing points as they are created. (A kept
  // vertex at distance 0 whose polygons all vanish stays listed; harmless.)
  int num_live = 0;
  for (int i = 0; i < pool.num_live; ++i) {
    if (s[pool.live[i]] >= 0.0) pool.live[num_live++] = pool.live[i];
  }
  pool.num_live = num_live;

  out.num_polys = 0;

  // Edge (a, b), a < b -> index of its crossing point.
  std::array<std::uint8_t, kMaxVerts> cut_a, cut_b;
  int num_cuts = 0;
  auto crossing = [&](int a, int b) -> int {
    if (a > b) std::swap(a, b);
    for (int i = 0; i < num_cuts; ++i) {
      if (cut_a[i] == a && cut_b[i] == b) return pool_before + i;
    }
    if (pool.n >= kMaxVerts) return -1;
    const double t = s[a] / (s[a] - s[b]);
    const Vec3 pa = pool.v[a], pb = pool.v[b];
    pool.v[pool.n] = pa + t * (pb - pa);
    cut_a[num_cuts] = static_cast<std::uint8_t>(a);
    cut_b[num_cuts] = static_cast<std::uint8_t>(b);
    ++num_cuts;
    pool.live[pool.num_live++] = static_cast<std::uint8_t>(pool.n);
    return pool.n++;
  };

  std::array<std::uint8_t, kMaxSegs> seg_from, seg_to;
  int num_segs = 0;

  for (int p = 0; p < in.num_polys; ++p) {
    const Poly& poly = in.polys[p];
    int start = 0;
    while (start < poly.n && s[poly.v[start]] < 0.0) ++start;
    if (start == poly.n) continue;  // entirely outside: dropped, and it crosses nothing
    if (out.num_polys >= kMaxPolys) return ClipResult::kOverflow;
    Poly& result = out.polys[out.num_polys];  // claimed only if it keeps 3 corners
    result.n = 0;
    int exit_point = -1;
    int ia = start;
    for (int e = 0; e < poly.n; ++e) {
      const int ib = ia + 1 == poly.n ? 0 : ia + 1;
      const int a = poly.v[ia], b = poly.v[ib];
      ia = ib;
      const double sa = s[a], sb = s[b];
      if (sa >= 0.0) {
        if (result.n >= kMaxPolySize) return ClipResult::kOverflow;
        result.v[result.n++] = static_cast<std::uint8_t>(a);
        if (sb >= 0.0) continue;
        // Leaving the kept side.
        if (sa == 0.0) {
          exit_point = a;
        } else {
          exit_point = crossing(a, b);
          if (exit_point < 0 || result.n >= kMaxPolySize) return ClipResult::kOverflow;
          result.v[result.n++] = static_cast<std::uint8_t>(exit_point);
        }
      } else if (sb >= 0.0) {
        // Coming back.
        int entry = b;
        if (sb > 0.0) {
          entry = crossing(a, b);
          if (entry < 0 || result.n >= kMaxPolySize) return ClipResult::kOverflow;
          result.v[result.n++] = static_cast<std::uint8_t>(entry);
        }
        // exit == entry: the polygon only touched the plane at one vertex; nothing to close.
        // exit_point < 0 only if a distance was NaN (overflowing input): skip, don't index.
        if (exit_point >= 0 && exit_point != entry) {
          if (num_segs >= kMaxSegs) return ClipResult::kOverflow;
          seg_from[num_segs] = static_cast<std::uint8_t>(exit_point);
          seg_to[num_segs] = static_cast<std::uint8_t>(entry);
          ++num_segs;
        }
      }
    }
    // Fewer than 3 corners: what is left lies on the plane. Its two directed edges (if any) are
    // twins of each other, so dropping it keeps the mesh closed.
    if (result.n >= 3) ++out.num_polys;
  }

  // Close the hole: chain the reversed segments (to -> from) into cycles. In exact arithmetic
  // there is one convex cycle; rounding or vertices on the plane can give several, or a vertex
  // visited twice. Any decomposition of the reversed segments into cycles gives the same flux,
  // so a greedy walk is enough. A chain that cannot be closed (impossible for a closed mesh) is
  // emitted as is.
  std::array<bool, kMaxSegs> used{};
  for (int first = 0; first < num_segs; ++first) {
    if (used[first]) continue;
    if (out.num_polys >= kMaxPolys) return ClipResult::kOverflow;
    Poly& cap = out.polys[out.num_polys];
    cap.n = 0;
    cap.v[cap.n++] = seg_to[first];
    int cur = first;
    while (true) {
      used[cur] = true;
      const int next_vertex = seg_from[cur];
      if (next_vertex == cap.v[0]) break;
      if (cap.n >= kMaxPolySize) return ClipResult::kOverflow;
      cap.v[cap.n++] = static_cast<std::uint8_t>(next_vertex);
      cur = -1;
      for (int j = 0; j < num_segs && cur < 0; ++j) {
        if (!used[j] && seg_to[j] == next_vertex) cur = j;
      }
      if (cur < 0) break;
    }
    if (cap.n >= 3) ++out.num_polys;
  }
  return ClipResult::kClipped;
}

// Divergence theorem: the volume enclosed by a closed outward-oriented mesh is the sum over its
// polygons of the fan triangles' triple products, divided by 6. The triple products are taken
// relative to a vertex of the mesh, not the origin: a small intersection far from the origin
// would otherwise be the difference of large, nearly equal terms.
double mesh_volume(const Mesh& m, const VertexPool& pool) {
  if (m.num_polys == 0) return 0.0;
  const Vec3 origin = pool.v[m.polys[0].v[0]];
  double sum = 0.0;
  for (int p = 0; p < m.num_polys; ++p) {
    const Poly& poly = m.polys[p];
    const Vec3 q0 = pool.v[poly.v[0]] - origin;
    Vec3 qi = pool.v[poly.v[1]] - origin;
    for (int i = 2; i < poly.n; ++i) {
      const Vec3 qj = pool.v[poly.v[i]] - origin;
      sum += dot(q0, cross(qi, qj));
      qi = qj;
    }
  }
  return sum / 6.0;
}

// =============================================================================================
// PANG-style: independent points, then their convex hull.
// =============================================================================================

constexpr int kMaxPangPoints = 4 + 4 + 24 + 24;

// Closed barycentric inside test of p in t, tolerance free: p is inside when replacing any vertex
// by p does not flip the orientation.
bool inside(Vec3 p, const Tet& t, double orientation) {
  for (int k = 0; k < 4; ++k) {
    Tet r = t;
    r[k] = p;
    const double o = orient3d(r[0], r[1], r[2], r[3]);
    if (orientation > 0.0 ? o < 0.0 : o > 0.0) return false;
  }
  return true;
}

// Intersection of the segment pq with the closed triangle abc, if any, into x. The plane test
// and the inside test are both sign tests of orientations (no tolerance); a segment lying in the
// triangle's plane is reported as not intersecting (its points come from other pairs, or not at
// all: this method makes no promise there).
bool segment_triangle(Vec3 p, Vec3 q, Vec3 a, Vec3 b, Vec3 c, Vec3& x) {
  const double sp = orient3d(a, b, c, p);
  const double sq = orient3d(a, b, c, q);
  if ((sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0)) return false;
  if (sp == 0.0 && sq == 0.0) return false;
  const double o1 = orient3d(p, q, a, b);
  const double o2 = orient3d(p, q, b, c);
  const double o3 = orient3d(p, q, c, a);
  const bool all_nonneg = o1 >= 0.0 && o2 >= 0.0 && o3 >= 0.0;
  const bool all_nonpos = o1 <= 0.0 && o2 <= 0.0 && o3 <= 0.0;
  if (!all_nonneg && !all_nonpos) return false;
  const double t = sp / (sp - sq);
  x = p + t * (q - p);
  return true;
}

// Collects the points of X inside Y and of X's edges through Y's faces.
void collect(const Tet& X, const Tet& Y, double orientation_y, std::array<Vec3, kMaxPangPoints>& pts,
             int& n) {
  for (const Vec3& p : X) {
    if (inside(p, Y, orientation_y)) pts[n++] = p;
  }
  for (const auto& e : tet_edges) {
    for (const auto& f : outward_face) {
      Vec3 x;
      if (segment_triangle(X[e[0]], X[e[1]], Y[f[0]], Y[f[1]], Y[f[2]], x)) pts[n++] = x;
    }
  }
}

// A candidate facet: three point indices and twice their triangle's area.
struct Triple {
  float area2;
  std::uint8_t i, j, k;
};
constexpr int kMaxTriples = kMaxPangPoints * (kMaxPangPoints - 1) * (kMaxPangPoints - 2) / 6;

// Volume of the convex hull of pts[0..n) (n <= 56), in doubles.
//
// Brute force, which is plenty for so few points: a triple of points spans a hull facet when no
// point lies beyond its plane on both sides (with a tolerance relative to the extent of the
// point set). All points within the tolerance of that plane form the facet; it is ordered by
// angle and contributes the pyramid from the centroid of all points. Triples inside an already
// found facet are skipped, which also keeps a facet from being counted twice.
//
// Triples are tried in order of decreasing area, so that every facet is first found through its
// best-conditioned triple. Otherwise a triple using a very short edge (two vertices 1e-7 apart,
// common near a corner of the intersection) gives a plane tilted by rounding enough to push the
// facet's other points out of the tolerance, and the hull gains spurious sliver facets.
double hull_volume(std::array<Vec3, kMaxPangPoints>& pts, int n) {
  if (n < 4) return 0.0;
  Vec3 lo = pts[0], hi = pts[0];
  for (int i = 1; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], pts[i][k]);
      hi[k] = std::max(hi[k], pts[i][k]);
    }
  }
  const double extent = norm(hi - lo);
  if (!(extent > 0.0) || !std::isfinite(extent)) return 0.0;
  // Near-duplicates (the same vertex found by two edge-face pairs) would make facets of
  // zero-area slivers: merge them.
  const double dup_tol = 1e-13 * extent;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    bool dup = false;
    for (int j = 0; j < m && !dup; ++j) {
      const Vec3 d = pts[i] - pts[j];
      dup = dot(d, d) <= dup_tol * dup_tol;
    }
    if (!dup) pts[m++] = pts[i];
  }
  n = m;
  if (n < 4) return 0.0;

  // Static, not on the stack: up to 27720 entries; per thread, so calls may run in parallel.
  thread_local std::array<Triple, kMaxTriples> triples;
  int num_triples = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k = j + 1; k < n; ++k) {
        const Vec3 eij = pts[j] - pts[i], eik = pts[k] - pts[i];
        const double len = norm(cross(eij, eik));
        // A nearly collinear triple defines no plane worth testing. The test is on the shape
        // (the sine of the angle at i), not the size: a tiny facet is still a facet.
        if (!(len > 1e-8 * norm(eij) * norm(eik))) continue;
        triples[num_triples++] = {static_cast<float>(len), static_cast<std::uint8_t>(i),
                                  static_cast<std::uint8_t>(j), static_cast<std::uint8_t>(k)};
      }
    }
  }
  std::sort(triples.begin(), triples.begin() + num_triples,
            [](const Triple& a, const Triple& b) { return a.area2 > b.area2; });

  Vec3 center{};
  for (int i = 0; i < n; ++i) center = center + pts[i];
  center = (1.0 / n) * center;

  const double plane_tol = 1e-12 * extent;
  std::array<std::uint64_t, 2 * kMaxPangPoints> facets{};  // a hull of n points: <= 2n - 4
  int num_facets = 0;
  double volume6 = 0.0;
  for (int t = 0; t < num_triples; ++t) {
    const int i = triples[t].i, j = triples[t].j, k = triples[t].k;
    const std::uint64_t triple =
        (std::uint64_t{1} << i) | (std::uint64_t{1} << j) | (std::uint64_t{1} << k);
    bool known = false;
    for (int f = 0; f < num_facets && !known; ++f) known = (facets[f] & triple) == triple;
    if (known) continue;
    const Vec3 u = pts[j] - pts[i];
    Vec3 normal = cross(u, pts[k] - pts[i]);
    normal = (1.0 / norm(normal)) * normal;
    bool above = false, below = false;
    std::uint64_t on = triple;
    for (int q = 0; q < n; ++q) {
      const double dist = dot(normal, pts[q] - pts[i]);
      if (dist > plane_tol) {
        above = true;
      } else if (dist < -plane_tol) {
        below = true;
      } else {
        on |= std::uint64_t{1} << q;
      }
    }
    if (!above && !below) return 0.0;  // all points coplanar
    if (above && below) continue;       // not a supporting plane
    if (num_facets >= static_cast<int>(facets.size())) return 0.0;  // impossible for n <= 56
    facets[num_facets++] = on;

    // Order the facet's points by angle around their centroid, in a basis of the plane.
    std::array<int, kMaxPangPoints> idx;
    std::array<double, kMaxPangPoints> angle;
    int c = 0;
    Vec3 fc{};
    for (int q = 0; q < n; ++q) {
      if ((on >> q) & 1u) {
        idx[c++] = q;
        fc = fc + pts[q];
      }
    }
    fc = (1.0 / c) * fc;
    const Vec3 w = cross(normal, u);
    for (int q = 0; q < c; ++q) {
      const Vec3 d = pts[idx[q]] - fc;
      const double a = std::atan2(dot(d, w), dot(d, u));
      angle[idx[q]] = std::isnan(a) ? 0.0 : a;  // NaN would break std::sort's ordering
    }
    std::sort(idx.begin(), idx.begin() + c, [&](int a, int b) { return angle[a] < angle[b]; });
    double facet6 = 0.0;
    const Vec3 q0 = pts[idx[0]] - center;
    for (int q = 1; q + 1 < c; ++q) {
      facet6 += dot(q0, cross(pts[idx[q]] - center, pts[idx[q + 1]] - center));
    }
    volume6 += std::abs(facet6);
  }
  return volume6 / 6.0;
}

}  // namespace

// Contract: the volume of U ∩ V by clipping U with V's four planes in doubles; >= 0 and finite,
// 0 for non-finite input, for a U or V that is flat as computed, and (rarely, by design of a
// non-robust method) when rounding makes the mesh too irregular for the fixed capacities.
// U's faces are oriented outward from one computed orientation sign (not face by face), so the
// initial mesh is consistent even for a nearly flat U.
double clip_volume(const Tet& U_in, const Tet& V) {
  if (!all_finite(U_in) || !all_finite(V)) return 0.0;
  Tet U = U_in;
  const double orient_u = orient3d(U[0], U[1], U[2], U[3]);
  if (!(orient_u != 0.0) || !std::isfinite(orient_u)) return 0.0;
  if (orient_u < 0.0) std::swap(U[0], U[1]);  // outward faces need a right-handed U
  std::array<Plane, 4> planes;
  if (!inward_planes(V, planes)) return 0.0;

  VertexPool pool;
  pool.n = 4;
  pool.num_live = 4;
  for (int i = 0; i < 4; ++i) {
    pool.v[i] = U[i];
    pool.live[i] = static_cast<std::uint8_t>(i);
  }
  std::array<Mesh, 2> meshes;
  Mesh* cur = &meshes[0];
  Mesh* next = &meshes[1];
  cur->num_polys = 4;
  for (int f = 0; f < 4; ++f) {
    cur->polys[f].n = 3;
    for (int i = 0; i < 3; ++i) cur->polys[f].v[i] = static_cast<std::uint8_t>(outward_face[f][i]);
  }
  for (int k = 0; k < 4; ++k) {
    switch (clip(*cur, planes[k], pool, *next)) {
      case ClipResult::kUnchanged:
        break;
      case ClipResult::kClipped:
        std::swap(cur, next);
        break;
      case ClipResult::kEmpty:
      case ClipResult::kOverflow:
        return 0.0;
    }
  }
  const double v = mesh_volume(*cur, pool);
  // Huge finite coordinates can overflow in the products (inf, or inf - inf = NaN).
  return std::isfinite(v) && v > 0.0 ? v : 0.0;
}

// Contract: the volume of the convex hull of the independently computed candidate points, in
// doubles; >= 0 and finite, 0 for non-finite or flat input and for fewer than 4 distinct or
// coplanar points.
double pang_volume(const Tet& U, const Tet& V) {
  if (!all_finite(U) || !all_finite(V)) return 0.0;
  const double orient_u = orient3d(U[0], U[1], U[2], U[3]);
  const double orient_v = orient3d(V[0], V[1], V[2], V[3]);
  if (!(orient_u != 0.0) || !(orient_v != 0.0)) return 0.0;
  std::array<Vec3, kMaxPangPoints> pts;
  int n = 0;
  collect(U, V, orient_v, pts, n);
  collect(V, U, orient_u, pts, n);
  const double v = hull_volume(pts, n);
  return std::isfinite(v) && v > 0.0 ? v : 0.0;
}

// =============================================================================================
// 2D: triangles.
// =============================================================================================

namespace {

bool all_finite(const Triangle& t) {
  for (const Vec2& p : t) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  }
  return true;
}

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Capacity of a clipped polygon. A clip outputs each kept corner and one point per crossing
// edge, so at most twice the corners it gets: 3, 6, 12, 24 after three clips, whatever the
// rounding. (In exact arithmetic a convex polygon gains at most one corner per clip: 6.) With
// this bound no write can overflow, so no check is needed in the loop.
constexpr int kMaxClipCorners = 24;

// Twice the signed area of poly[0..n), fan from corner 0 (not from the origin: a small polygon
// far from the origin would otherwise be the difference of large, nearly equal terms).
double shoelace2(const Vec2* poly, int n) {
  double sum = 0.0;
  const Vec2 o = poly[0];
  Vec2 prev = poly[1] - o;
  for (int i = 2; i < n; ++i) {
    const Vec2 cur = poly[i] - o;
    sum += cross2(prev, cur);
    prev = cur;
  }
  return sum;
}

constexpr int kMaxPang2Points = 3 + 3 + 9;

// Closed inside test of p in t, tolerance free: p is inside when no edge has it strictly on the
// side away from the opposite vertex. `orientation` is orient2d of t.
bool inside(Vec2 p, const Triangle& t, double orientation) {
  for (int k = 0; k < 3; ++k) {
    const double o = orient2d(t[static_cast<std::size_t>((k + 1) % 3)],
                              t[static_cast<std::size_t>((k + 2) % 3)], p);
    if (orientation > 0.0 ? o < 0.0 : o > 0.0) return false;
  }
  return true;
}

// Intersection point of the closed segments pq and ab, if they cross, into x. Collinear
// overlapping segments are reported as not intersecting (their endpoints come from the inside
// tests, or not at all: this method makes no promise there).
bool segment_segment(Vec2 p, Vec2 q, Vec2 a, Vec2 b, Vec2& x) {
  const double sp = orient2d(a, b, p);
  const double sq = orient2d(a, b, q);
  if ((sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0)) return false;
  if (sp == 0.0 && sq == 0.0) return false;
  const double sa = orient2d(p, q, a);
  const double sb = orient2d(p, q, b);
  if ((sa > 0.0 && sb > 0.0) || (sa < 0.0 && sb < 0.0)) return false;
  const double t = sp / (sp - sq);
  x = p + t * (q - p);
  return true;
}

// Area of the convex hull of pts[0..n) (Andrew's monotone chain; collinear and repeated points
// are dropped by the strict turn test).
double hull_area(std::array<Vec2, kMaxPang2Points>& pts, int n) {
  if (n < 3) return 0.0;
  std::sort(pts.begin(), pts.begin() + n,
            [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::array<Vec2, 2 * kMaxPang2Points> hull;
  int h = 0;
  for (int i = 0; i < n; ++i) {  // lower hull
    while (h >= 2 && orient2d(hull[h - 2], hull[h - 1], pts[i]) <= 0.0) --h;
    hull[h++] = pts[i];
  }
  const int lower = h + 1;
  for (int i = n - 2; i >= 0; --i) {  // upper hull
    while (h >= lower && orient2d(hull[h - 2], hull[h - 1], pts[i]) <= 0.0) --h;
    hull[h++] = pts[i];
  }
  --h;  // the last point is the first again
  if (h < 3) return 0.0;
  return 0.5 * std::abs(shoelace2(hull.data(), h));
}

}  // namespace

// Contract: the area of A ∩ B by clipping A with B's three lines in doubles; >= 0 and finite,
// 0 for non-finite input and for an A or B that is flat as computed.
double clip_area(const Triangle& A, const Triangle& B) {
  if (!all_finite(A) || !all_finite(B)) return 0.0;
  const double oa = orient2d(A[0], A[1], A[2]);
  const double ob = orient2d(B[0], B[1], B[2]);
  if (!(oa != 0.0) || !(ob != 0.0) || !std::isfinite(oa) || !std::isfinite(ob)) return 0.0;

  std::array<Vec2, kMaxClipCorners> buf[2];
  Vec2* in = buf[0].data();
  Vec2* out = buf[1].data();
  in[0] = A[0];
  in[1] = A[1];
  in[2] = A[2];
  int n = 3;
  std::array<double, kMaxClipCorners> f;
  for (int k = 0; k < 3; ++k) {
    // Line k of B (opposite vertex k), from its own first vertex b1; the edge vector is turned
    // so that B[k]'s side is positive for either orientation of B.
    const Vec2 b1 = B[static_cast<std::size_t>((k + 1) % 3)];
    const Vec2 b2 = B[static_cast<std::size_t>((k + 2) % 3)];
    const Vec2 e = ob > 0.0 ? b2 - b1 : b1 - b2;
    bool any_in = false, any_out = false;
    for (int i = 0; i < n; ++i) {
      const double d = e.x * (in[i].y - b1.y) - e.y * (in[i].x - b1.x);
      f[static_cast<std::size_t>(i)] = d;
      any_in = any_in || d > 0.0;
      any_out = any_out || d < 0.0;
    }
    if (!any_out) continue;       // nothing cut: keep the polygon as it is
    if (!any_in) return 0.0;      // at most a segment or a point on the line is left
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const int j = i + 1 == n ? 0 : i + 1;
      const double fi = f[static_cast<std::size_t>(i)], fj = f[static_cast<std::size_t>(j)];
      if (fi >= 0.0) out[m++] = in[i];
      if ((fi > 0.0 && fj < 0.0) || (fi < 0.0 && fj > 0.0)) {
        const double t = fi / (fi - fj);
        out[m++] = in[i] + t * (in[j] - in[i]);
      }
    }
    std::swap(in, out);
    n = m;
  }
  if (n < 3) return 0.0;
  const double a = 0.5 * std::abs(shoelace2(in, n));
  // Huge finite coordinates can overflow in the products (inf, or inf - inf = NaN).
  return std::isfinite(a) ? a : 0.0;
}

// Contract: the area of the convex hull of the independently computed candidate points, in
// doubles; >= 0 and finite, 0 for non-finite or flat input and for fewer than 3 points.
double pang_area(const Triangle& A, const Triangle& B) {
  if (!all_finite(A) || !all_finite(B)) return 0.0;
  const double oa = orient2d(A[0], A[1], A[2]);
  const double ob = orient2d(B[0], B[1], B[2]);
  if (!(oa != 0.0) || !(ob != 0.0) || !std::isfinite(oa) || !std::isfinite(ob)) return 0.0;
  std::array<Vec2, kMaxPang2Points> pts;
  int n = 0;
  for (const Vec2& p : A) {
    if (inside(p, B, ob)) pts[static_cast<std::size_t>(n++)] = p;
  }
  for (const Vec2& p : B) {
    if (inside(p, A, oa)) pts[static_cast<std::size_t>(n++)] = p;
  }
  for (int i = 0; i < 3; ++i) {
    const Vec2 p = A[static_cast<std::size_t>((i + 1) % 3)], q = A[static_cast<std::size_t>((i + 2) % 3)];
    for (int j = 0; j < 3; ++j) {
      Vec2 x;
      if (segment_segment(p, q, B[static_cast<std::size_t>((j + 1) % 3)],
                          B[static_cast<std::size_t>((j + 2) % 3)], x)) {
        pts[static_cast<std::size_t>(n++)] = x;
      }
    }
  }
  const double a = hull_area(pts, n);
  return std::isfinite(a) && a > 0.0 ? a : 0.0;
}

}  // namespace tetia::baselines
