// exact.cpp -- the exact reference: intersection volume of two tetrahedra (and, at the end, the
// intersection area of two triangles) in rational arithmetic.
//
// Method (deliberately unrelated to the kernel's logic, so that it can judge it):
//  1. Every double is m * 2^e with an integer m, so after multiplying all 24 coordinates by one
//     common power of two they are integers. Working in integers (GMP mpz) instead of rationals
//     avoids a gcd after every operation; the power of two is put back at the very end. (They
//     are also translated so that U's vertex 0 is the origin: smaller numbers, same volume.)
//  2. The intersection is {x : n_f . x >= d_f, f = 0..7}, with the four face planes of U and the
//     four of V, each through three vertices (exact integer normal = cross product) and oriented
//     towards the fourth vertex.
//  3. Every triple of planes with independent normals meets in one point, solved by Cramer's rule
//     in homogeneous integer coordinates (X, Y, Z, W), W > 0. A point satisfying all eight
//     inequalities is a vertex of the intersection polytope (and every vertex is such a point).
//  4. The volume is a sum of pyramids from one vertex (the apex) over the facets not containing
//     it. The facet on plane f is the convex hull of the vertices lying on f; those are ordered
//     by exact orientation tests and measured with the shoelace formula in a coordinate plane.
//
// Performance: about 40 us per random pair (roughly 10^3 multiplications of a few hundred bits
// each, and one gcd per facet); pairs separated by a face plane return after a few dozen. The
// mpz buffers live in a thread-local workspace so that repeated calls do not reallocate them.
//
// Non-finite coordinates have no rational value: they throw std::domain_error (validate input at
// the boundary, as the CLI does).
#include "tetia/exact.hpp"

#include "kernel/exact_fallback.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace tetia::exact {
namespace {

constexpr int kPlanes = 8;
constexpr int kMaxPoints = 56;  // C(8, 3): at most one point per triple of planes

// All the big integers one call needs. Kept per thread and reused: mpz_class keeps its limbs
// between assignments, so after the first few calls nothing is allocated any more.
struct Workspace {
  mpz_class vert[2][4][3];           // integer coordinates of U (0) and V (1)
  mpz_class n[kPlanes][3];           // inward normals: faces 0-3 of U, 4-7 of V
  mpz_class d[kPlanes];              // offsets: n . x >= d inside
  mpz_class c[kPlanes][kPlanes][3];  // c[j][k] = n_j x n_k for j < k
  mpz_class pt[kMaxPoints][4];       // distinct feasible points (X, Y, Z, W), W > 0
  mpz_class h[kPlanes];              // n_f . P0 - d_f * W0 for the apex P0
  mpz_class prefix[kMaxPoints + 1], suffix[kMaxPoints + 1];  // products of a facet's W
  mpz_class t0, t1, t2, e1[3], e2[3], area;
  mpq_class term, total;
};

Workspace& workspace() {
  thread_local Workspace w;
  return w;
}

// x = m * 2^e with m odd (or x = 0: m = 0, e = 0).
struct Dyadic {
  std::int64_t m = 0;
  long e = 0;
};

Dyadic decompose(double x) {
  if (x == 0.0) return {};
  int e = 0;
  const double f = std::frexp(x, &e);  // x = f * 2^e, 0.5 <= |f| < 1, subnormals included
  std::int64_t m = static_cast<std::int64_t>(std::ldexp(f, 53));  // exact: 53-bit integer
  const int tz = std::countr_zero(static_cast<std::uint64_t>(m < 0 ? -m : m));
  m /= std::int64_t{1} << tz;  // exact: m is a multiple of 2^tz
  return {m, static_cast<long>(e) - 53 + tz};
}

// Writes the coordinates of U and V, scaled by a common power of two 2^-emin so that they are
// integers and translated by U's vertex 0, into w.vert and returns emin: the true coordinates
// are vert * 2^emin + U[0].
long scale_to_integers(const Tet& U, const Tet& V, Workspace& w) {
  Dyadic dy[2][4][3];
  long emin = 0;
  bool any = false;
  for (int t = 0; t < 2; ++t) {
    const Tet& T = t == 0 ? U : V;
    for (int i = 0; i < 4; ++i) {
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(T[i][k])) {
          throw std::domain_error("tetia::exact: non-finite coordinate");
        }
        dy[t][i][k] = decompose(T[i][k]);
        if (dy[t][i][k].m != 0 && (!any || dy[t][i][k].e < emin)) {
          emin = dy[t][i][k].e;
          any = true;
        }
      }
    }
  }
  for (int t = 0; t < 2; ++t) {
    for (int i = 0; i < 4; ++i) {
      for (int k = 0; k < 3; ++k) {
        mpz_class& z = w.vert[t][i][k];
        z = static_cast<long>(dy[t][i][k].m);
        if (dy[t][i][k].m != 0) {
          mpz_mul_2exp(z.get_mpz_t(), z.get_mpz_t(),
                       static_cast<mp_bitcnt_t>(dy[t][i][k].e - emin));
        }
      }
    }
  }
  // Volumes do not change under translation, and with U's vertex 0 at the origin the three face
  // planes of U through it have offset 0 and the other numbers get smaller: cheaper products.
  for (int k = 0; k < 3; ++k) {
    const mpz_class origin = w.vert[0][0][k];
    for (int t = 0; t < 2; ++t) {
      for (int i = 0; i < 4; ++i) w.vert[t][i][k] -= origin;
    }
  }
  return emin;
}

// r = a x b. r must not alias a or b.
void cross(const mpz_class* a, const mpz_class* b, mpz_class* r) {
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    mpz_mul(r[k].get_mpz_t(), a[k1].get_mpz_t(), b[k2].get_mpz_t());
    mpz_submul(r[k].get_mpz_t(), a[k2].get_mpz_t(), b[k1].get_mpz_t());
  }
}

// r = a . b.
void dot(const mpz_class* a, const mpz_class* b, mpz_class& r) {
  mpz_mul(r.get_mpz_t(), a[0].get_mpz_t(), b[0].get_mpz_t());
  mpz_addmul(r.get_mpz_t(), a[1].get_mpz_t(), b[1].get_mpz_t());
  mpz_addmul(r.get_mpz_t(), a[2].get_mpz_t(), b[2].get_mpz_t());
}

// The four inward face planes of the tetrahedron v into n[0..3], d[0..3] (face k is opposite
// vertex k). Returns false when the tetrahedron is flat (its exact determinant is zero).
bool build_planes(const mpz_class (*v)[3], mpz_class (*n)[3], mpz_class* d, Workspace& w) {
  for (int k = 0; k < 4; ++k) {
    const int a = k == 0 ? 1 : 0;
    const int b = k <= 1 ? 2 : 1;
    const int c = k <= 2 ? 3 : 2;
    for (int i = 0; i < 3; ++i) {
      w.e1[i] = v[b][i] - v[a][i];
      w.e2[i] = v[c][i] - v[a][i];
    }
    cross(w.e1, w.e2, n[k]);
    dot(n[k], v[a], d[k]);
    dot(n[k], v[k], w.t0);
    w.t0 -= d[k];  // +-6 times the volume: the same magnitude for every face
    const int side = sgn(w.t0);
    if (side == 0) return false;
    if (side < 0) {
      for (int i = 0; i < 3; ++i) mpz_neg(n[k][i].get_mpz_t(), n[k][i].get_mpz_t());
      mpz_neg(d[k].get_mpz_t(), d[k].get_mpz_t());
    }
  }
  return true;
}

// Sign of the orientation of the projected homogeneous points (u, v, w) a, b, c:
// det [[ua, va, wa], [ub, vb, wb], [uc, vc, wc]]. All W are positive, so this is the sign of
// the orientation of the affine points.
int orient2d(const mpz_class* a, const mpz_class* b, const mpz_class* c, int iu, int iv,
             Workspace& w) {
  // w.t0 = ua (vb wc - vc wb) - va (ub wc - uc wb) + wa (ub vc - uc vb)
  mpz_mul(w.t1.get_mpz_t(), b[iv].get_mpz_t(), c[3].get_mpz_t());
  mpz_submul(w.t1.get_mpz_t(), c[iv].get_mpz_t(), b[3].get_mpz_t());
  mpz_mul(w.t0.get_mpz_t(), a[iu].get_mpz_t(), w.t1.get_mpz_t());
  mpz_mul(w.t1.get_mpz_t(), b[iu].get_mpz_t(), c[3].get_mpz_t());
  mpz_submul(w.t1.get_mpz_t(), c[iu].get_mpz_t(), b[3].get_mpz_t());
  mpz_submul(w.t0.get_mpz_t(), a[iv].get_mpz_t(), w.t1.get_mpz_t());
  mpz_mul(w.t1.get_mpz_t(), b[iu].get_mpz_t(), c[iv].get_mpz_t());
  mpz_submul(w.t1.get_mpz_t(), c[iu].get_mpz_t(), b[iv].get_mpz_t());
  mpz_addmul(w.t0.get_mpz_t(), a[3].get_mpz_t(), w.t1.get_mpz_t());
  return sgn(w.t0);
}

// Correct rounding of a positive rational to the nearest double, ties to even, including the
// subnormal range. (mpq_get_d truncates towards zero, which would make exact results off by an
// ulp in half the cases.)
double round_to_double(const mpq_class& q) {
  if (sgn(q) == 0) return 0.0;
  const bool negative = sgn(q) < 0;
  mpz_class num = abs(q.get_num());
  const mpz_class& den = q.get_den();
  // Choose s so that quo = floor(num * 2^s / den) lies in [2^53, 2^55).
  const long s = 54 - (static_cast<long>(mpz_sizeinbase(num.get_mpz_t(), 2)) -
                       static_cast<long>(mpz_sizeinbase(den.get_mpz_t(), 2)));
  mpz_class scaled_den = den;
  if (s >= 0) {
    mpz_mul_2exp(num.get_mpz_t(), num.get_mpz_t(), static_cast<mp_bitcnt_t>(s));
  } else {
    mpz_mul_2exp(scaled_den.get_mpz_t(), scaled_den.get_mpz_t(), static_cast<mp_bitcnt_t>(-s));
  }
  mpz_class quo, rem;
  mpz_tdiv_qr(quo.get_mpz_t(), rem.get_mpz_t(), num.get_mpz_t(), scaled_den.get_mpz_t());
  // q = (quo + rem/den') * 2^-s with 2^53 <= quo < 2^55, so q lies in [2^top, 2^(top+1)).
  const long bits = static_cast<long>(mpz_sizeinbase(quo.get_mpz_t(), 2));
  const long top = bits - 1 - s;
  // Precision available at that exponent: 53 for normal numbers, fewer for subnormals.
  long precision = 53;
  if (top < -1022) precision = 53 - (-1022 - top);
  const long drop = bits - precision;  // >= 1 because bits >= 54 and precision <= 53
  mpz_class kept;
  mpz_fdiv_q_2exp(kept.get_mpz_t(), quo.get_mpz_t(), static_cast<mp_bitcnt_t>(drop));
  const bool half = mpz_tstbit(quo.get_mpz_t(), static_cast<mp_bitcnt_t>(drop - 1)) != 0;
  const bool below_half_nonzero =
      sgn(rem) != 0 || (drop >= 2 && mpz_scan1(quo.get_mpz_t(), 0) < static_cast<mp_bitcnt_t>(drop - 1));
  if (half && (below_half_nonzero || mpz_odd_p(kept.get_mpz_t()))) ++kept;
  // kept < 2^54 fits a double exactly; ldexp by a power of two is exact (or overflows to inf).
  const double r = std::ldexp(kept.get_d(), static_cast<int>(drop - s));
  return negative ? -r : r;
}

}  // namespace

// Contract: |det[t1 - t0, t2 - t0, t3 - t0]| / 6, exactly. Throws std::domain_error on a
// non-finite coordinate (GMP itself would raise SIGFPE).
mpq_class volume(const Tet& t) {
  for (const Vec3& p : t) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw std::domain_error("tetia::exact: non-finite coordinate");
    }
  }
  mpq_class e[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) e[i][k] = mpq_class(t[i + 1][k]) - mpq_class(t[0][k]);
  }
  mpq_class det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                  e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                  e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  return abs(det) / 6;
}

namespace {

// Steps 1-3 for U and V: the planes, and the distinct feasible points into w.pt[0..np) with
// their incidence masks (bit f: on plane f); emin as scale_to_integers. Returns np, 0 when the
// intersection has no interior for a reason found on the way (a flat tetrahedron, a separating
// face plane). Shared by intersection_volume and the kernel's last resort (exact_polyhedron).
int feasible_points(const Tet& U, const Tet& V, Workspace& w, long& emin, std::array<std::uint8_t, kMaxPoints>& mask) {
  emin = scale_to_integers(U, V, w);
  if (!build_planes(w.vert[0], &w.n[0], &w.d[0], w) ||
      !build_planes(w.vert[1], &w.n[4], &w.d[4], w)) {
    return 0;  // a flat tetrahedron: the intersection has no interior
  }

  // Shortcut (exact, and only a shortcut): if a face plane of one tetrahedron has the whole
  // other one on its closed outer side, the intersection is at most flat.
  for (int f = 0; f < kPlanes; ++f) {
    const auto& other = w.vert[f < 4 ? 1 : 0];
    bool separating = true;
    for (int i = 0; i < 4 && separating; ++i) {
      dot(w.n[f], other[i], w.t0);
      separating = cmp(w.t0, w.d[f]) <= 0;
    }
    if (separating) return 0;
  }

  for (int j = 0; j < kPlanes; ++j) {
    for (int k = j + 1; k < kPlanes; ++k) cross(w.n[j], w.n[k], w.c[j][k]);
  }

  // Step 3: the distinct feasible points. Two equal points lie on exactly the same planes, and a
  // point is determined by any three independent planes through it (which its generating triple
  // is), so points with the same incidence mask are equal and vice versa: deduplicating by mask
  // is exact and needs no comparison of coordinates.
  std::array<std::int8_t, 256> index_of_mask;
  index_of_mask.fill(-1);
  mask.fill(0);
  int np = 0;
  for (int i = 0; i < kPlanes; ++i) {
    for (int j = i + 1; j < kPlanes; ++j) {
      for (int k = j + 1; k < kPlanes; ++k) {
        mpz_class* P = w.pt[np];
        mpz_class& W = P[3];
        if (k < 4 || i >= 4) {
          // Three faces of one tetrahedron meet at the vertex they share (the one whose index
          // is the missing face): known exactly, and with W = 1 the tests below are cheaper.
          const int t = i >= 4 ? 1 : 0;
          const int vertex = 0 + 1 + 2 + 3 - (i + j + k - 12 * t);
          for (int x = 0; x < 3; ++x) P[x] = w.vert[t][vertex][x];
          W = 1;
        } else {
          dot(w.n[i], w.c[j][k], W);
          const int sdet = sgn(W);
          if (sdet == 0) continue;  // dependent normals: no single point
          // Cramer: P = d_i (n_j x n_k) + d_j (n_k x n_i) + d_k (n_i x n_j), over det.
          for (int x = 0; x < 3; ++x) {
            mpz_mul(P[x].get_mpz_t(), w.d[i].get_mpz_t(), w.c[j][k][x].get_mpz_t());
            mpz_submul(P[x].get_mpz_t(), w.d[j].get_mpz_t(), w.c[i][k][x].get_mpz_t());
            mpz_addmul(P[x].get_mpz_t(), w.d[k].get_mpz_t(), w.c[i][j][x].get_mpz_t());
          }
          if (sdet < 0) {
            for (int x = 0; x < 4; ++x) mpz_neg(P[x].get_mpz_t(), P[x].get_mpz_t());
          }
        }
        unsigned m = (1u << i) | (1u << j) | (1u << k);
        bool feasible = true;
        for (int f = 0; f < kPlanes && feasible; ++f) {
          if (f == i || f == j || f == k) continue;
          dot(w.n[f], P, w.t0);
          mpz_submul(w.t0.get_mpz_t(), w.d[f].get_mpz_t(), W.get_mpz_t());
          const int s = sgn(w.t0);
          if (s < 0) feasible = false;
          if (s == 0) m |= 1u << f;
        }
        if (!feasible || index_of_mask[m] >= 0) continue;
        index_of_mask[m] = static_cast<std::int8_t>(np);
        mask[np] = static_cast<std::uint8_t>(m);
        ++np;
      }
    }
  }
  return np;
}

}  // namespace

// Contract: the exact volume of U ∩ V for closed U, V in any vertex order; 0 when they touch or
// are disjoint or either is flat. Throws std::domain_error on a non-finite coordinate.
// Reentrant: the workspace is per thread.
mpq_class intersection_volume(const Tet& U, const Tet& V) {
  Workspace& w = workspace();
  long emin = 0;
  std::array<std::uint8_t, kMaxPoints> mask;
  const int np = feasible_points(U, V, w, emin, mask);
  if (np < 4) return 0;  // at most a triangle: no interior

  // Step 4: pyramids from the apex P0 = pt[0]. h_f = W0 * (n_f . p0 - d_f) >= 0 is W0 times the
  // apex's (unnormalised) distance to plane f; zero exactly for the planes through the apex,
  // whose facets contribute nothing. If the polytope is flat, every plane holding three
  // non-collinear vertices holds the apex too, so the sum is 0 with no special case.
  const mpz_class* P0 = w.pt[0];
  for (int f = 0; f < kPlanes; ++f) {
    dot(w.n[f], P0, w.h[f]);
    mpz_submul(w.h[f].get_mpz_t(), w.d[f].get_mpz_t(), P0[3].get_mpz_t());
  }
  w.total = 0;
  std::array<std::uint64_t, kPlanes> done_facets{};
  int num_done = 0;
  for (int f = 0; f < kPlanes; ++f) {
    if ((mask[0] >> f) & 1u) continue;
    std::array<int, kMaxPoints> on{};
    int k = 0;
    std::uint64_t set = 0;
    for (int p = 0; p < np; ++p) {
      if ((mask[p] >> f) & 1u) {
        on[k++] = p;
        set |= std::uint64_t{1} << p;
      }
    }
    if (k < 3) continue;  // an edge or a vertex touches the plane: no facet
    // A face of U and a face of V on the same plane with the same orientation hold the same
    // vertices; count that facet once. (Opposite orientations make the polytope flat, handled
    // above.)
    bool duplicate = false;
    for (int q = 0; q < num_done; ++q) duplicate = duplicate || done_facets[q] == set;
    if (duplicate) continue;
    done_facets[num_done++] = set;

    // Project along the axis where the normal is largest (any nonzero component would do).
    int axis = 0;
    for (int x = 1; x < 3; ++x) {
      if (mpz_cmpabs(w.n[f][x].get_mpz_t(), w.n[f][axis].get_mpz_t()) > 0) axis = x;
    }
    const int iu = (axis + 1) % 3, iv = (axis + 2) % 3;

    // The vertices on the facet are extreme points of a convex polygon, hence in strictly convex
    // position (three collinear points cannot all be extreme). Seen from the extreme point
    // on[0], the others span an angle below pi, so "orient(on[0], a, b) > 0" is a strict total
    // order on them: insertion sort by it yields the polygon in counter-clockwise order.
    const mpz_class* Q0 = w.pt[on[0]];
    for (int a = 2; a < k; ++a) {
      for (int b = a; b > 1 && orient2d(Q0, w.pt[on[b]], w.pt[on[b - 1]], iu, iv, w) > 0; --b) {
        std::swap(on[b], on[b - 1]);
      }
    }

    // Shoelace: twice the signed projected area is S = sum over edges (a, b) of
    // (u_a v_b - u_b v_a) / (w_a w_b). Every term is put over D = prod of the facet's w (the
    // product of the other k - 2 weights comes from prefix and suffix products), so that the
    // facet costs one gcd, not one per edge: the gcds dominated the running time.
    mpz_set_ui(w.prefix[0].get_mpz_t(), 1);
    for (int a = 0; a < k; ++a) {
      mpz_mul(w.prefix[a + 1].get_mpz_t(), w.prefix[a].get_mpz_t(), w.pt[on[a]][3].get_mpz_t());
    }
    mpz_set_ui(w.suffix[k].get_mpz_t(), 1);
    for (int a = k - 1; a >= 0; --a) {
      mpz_mul(w.suffix[a].get_mpz_t(), w.pt[on[a]][3].get_mpz_t(), w.suffix[a + 1].get_mpz_t());
    }
    mpz_set_ui(w.area.get_mpz_t(), 0);
    for (int a = 0; a < k; ++a) {
      const mpz_class* A = w.pt[on[a]];
      const mpz_class* B = w.pt[on[(a + 1) % k]];
      mpz_mul(w.t1.get_mpz_t(), A[iu].get_mpz_t(), B[iv].get_mpz_t());
      mpz_submul(w.t1.get_mpz_t(), B[iu].get_mpz_t(), A[iv].get_mpz_t());
      if (a + 1 < k) {  // the others: w_0 .. w_{a-1} and w_{a+2} .. w_{k-1}
        mpz_mul(w.t2.get_mpz_t(), w.prefix[a].get_mpz_t(), w.suffix[a + 2].get_mpz_t());
      } else {          // closing edge (k-1, 0): the others are w_1 .. w_{k-2}
        mpz_divexact(w.t2.get_mpz_t(), w.prefix[k - 1].get_mpz_t(), w.pt[on[0]][3].get_mpz_t());
      }
      mpz_addmul(w.area.get_mpz_t(), w.t1.get_mpz_t(), w.t2.get_mpz_t());
    }
    // Pyramid: the true area is |S| |n| / (2 |n_axis|) and the height h_f / (W0 |n|), so
    // 6 * volume = |S| * h_f / (W0 |n_axis|), with |S| = |area| / D. W0 is divided out once at
    // the end.
    mpz_abs(w.t1.get_mpz_t(), w.area.get_mpz_t());
    mpz_mul(w.t1.get_mpz_t(), w.t1.get_mpz_t(), w.h[f].get_mpz_t());
    mpz_abs(w.t2.get_mpz_t(), w.n[f][axis].get_mpz_t());
    mpz_mul(w.t2.get_mpz_t(), w.t2.get_mpz_t(), w.prefix[k].get_mpz_t());
    mpq_set_num(w.term.get_mpq_t(), w.t1.get_mpz_t());
    mpq_set_den(w.term.get_mpq_t(), w.t2.get_mpz_t());
    w.term.canonicalize();
    w.total += w.term;
  }

  mpq_class result = w.total;
  mpz_mul_ui(w.t1.get_mpz_t(), P0[3].get_mpz_t(), 6);
  mpq_set_z(w.term.get_mpq_t(), w.t1.get_mpz_t());
  result /= w.term;
  // Undo the scaling: a volume scales with the cube of the length unit.
  if (emin >= 0) {
    mpq_mul_2exp(result.get_mpq_t(), result.get_mpq_t(), static_cast<mp_bitcnt_t>(3 * emin));
  } else {
    mpq_div_2exp(result.get_mpq_t(), result.get_mpq_t(), static_cast<mp_bitcnt_t>(-3 * emin));
  }
  return result;
}

// Contract: intersection_volume(U, V) correctly rounded to the nearest double (ties to even),
// subnormals included. Not mpq_class::get_d, which truncates towards zero.
double intersection_volume_double(const Tet& U, const Tet& V) {
  return round_to_double(intersection_volume(U, V));
}

}  // namespace tetia::exact

namespace tetia::detail {

// The exact polytope of feasible_points as a Polyhedron's data (exact_fallback.hpp).
void exact_polyhedron(const Tet& U, const Tet& V, ExactPolyhedron& out) {
  using namespace exact;
  out.num_corners = out.num_facets = 0;
  out.simple = true;
  out.facet_begin[0] = 0;
  out.moments = {};
  Workspace& w = workspace();
  long emin = 0;
  std::array<std::uint8_t, kMaxPoints> mask;
  const int np = feasible_points(U, V, w, emin, mask);
  if (np < 4) return;
  if (np > Polyhedron::max_corners) throw std::logic_error("exact_polyhedron: too many corners");
  // The points in original coordinates: x = (X / W) 2^emin + U[0] (scale_to_integers).
  const auto unscale = [emin](mpq_class q) {
    if (emin >= 0) mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(emin));
    else mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-emin));
    return q;
  };
  std::vector<std::array<mpq_class, 3>> q(static_cast<std::size_t>(np));
  for (int p = 0; p < np; ++p)
    for (int k = 0; k < 3; ++k) {
      mpq_class x(w.pt[p][k], w.pt[p][3]);
      x.canonicalize();
      q[static_cast<std::size_t>(p)][static_cast<std::size_t>(k)] = unscale(x) + mpq_class(U[0][k]);
    }
  // Facets: the points on each plane, counter-clockwise in the projection along the normal's
  // largest component (as intersection_volume orders them), reversed where that axis and the
  // outward normal -n_f point opposite ways. A plane whose points are those of an earlier plane
  // (a face of U and one of V coinciding with the same orientation) is that facet: shadowed.
  unsigned shadowed = 0;
  std::array<std::uint64_t, kPlanes> sets{};
  int used = 0;
  for (int f = 0; f < kPlanes; ++f) {
    std::array<int, kMaxPoints> on{};
    int k = 0;
    std::uint64_t set = 0;
    for (int p = 0; p < np; ++p)
      if ((mask[static_cast<std::size_t>(p)] >> f) & 1u) {
        on[static_cast<std::size_t>(k++)] = p;
        set |= std::uint64_t{1} << p;
      }
    sets[static_cast<std::size_t>(f)] = set;
    if (k < 3) continue;
    bool duplicate = false;
    for (int g = 0; g < f; ++g) duplicate = duplicate || sets[static_cast<std::size_t>(g)] == set;
    if (duplicate) {
      shadowed |= 1u << f;
      continue;
    }
    int axis = 0;
    for (int x = 1; x < 3; ++x)
      if (mpz_cmpabs(w.n[f][x].get_mpz_t(), w.n[f][axis].get_mpz_t()) > 0) axis = x;
    const int iu = (axis + 1) % 3, iv = (axis + 2) % 3;
    const mpz_class* Q0 = w.pt[on[0]];
    for (int a = 2; a < k; ++a)
      for (int b = a; b > 1 && orient2d(Q0, w.pt[on[static_cast<std::size_t>(b)]], w.pt[on[static_cast<std::size_t>(b - 1)]], iu, iv, w) > 0; --b)
        std::swap(on[static_cast<std::size_t>(b)], on[static_cast<std::size_t>(b - 1)]);
    if (sgn(w.n[f][axis]) > 0) std::reverse(on.begin() + 1, on.begin() + k);
    if (used + k > Polyhedron::max_facet_indices || out.num_facets == Polyhedron::max_facets)
      throw std::logic_error("exact_polyhedron: too many facets");
    for (int a = 0; a < k; ++a) out.facet_index[used++] = static_cast<std::uint8_t>(on[static_cast<std::size_t>(a)]);
    out.facet_label[out.num_facets] = static_cast<std::uint8_t>(f);
    out.facet_begin[++out.num_facets] = static_cast<std::uint8_t>(used);
  }
  // Volume and first moments: tetrahedra from point 0 over the fans of the facets not through it.
  mpq_class volume = 0, first[3] = {0, 0, 0};
  const auto& p0 = q[0];
  for (int fi = 0; fi < out.num_facets; ++fi) {
    const int f = out.facet_label[fi];
    if ((mask[0] >> f) & 1u) continue;
    const int b = out.facet_begin[fi], e = out.facet_begin[fi + 1];
    const auto& a0 = q[out.facet_index[b]];
    for (int t = b + 1; t + 1 < e; ++t) {
      const auto& a1 = q[out.facet_index[t]];
      const auto& a2 = q[out.facet_index[t + 1]];
      mpq_class d[3][3];
      for (int x = 0; x < 3; ++x) {
        d[0][x] = a0[static_cast<std::size_t>(x)] - p0[static_cast<std::size_t>(x)];
        d[1][x] = a1[static_cast<std::size_t>(x)] - p0[static_cast<std::size_t>(x)];
        d[2][x] = a2[static_cast<std::size_t>(x)] - p0[static_cast<std::size_t>(x)];
      }
      const mpq_class det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                            d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                            d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
      const mpq_class v = abs(det) / 6;
      volume += v;
      for (int x = 0; x < 3; ++x)
        first[x] += v * (p0[static_cast<std::size_t>(x)] + a0[static_cast<std::size_t>(x)] + a1[static_cast<std::size_t>(x)] +
                         a2[static_cast<std::size_t>(x)]) / 4;
    }
  }
  if (sgn(volume) == 0) {  // flat: no interior
    out.num_facets = 0;
    out.facet_begin[0] = 0;
    return;
  }
  out.moments.volume = round_to_double(volume);
  out.moments.first = {round_to_double(first[0]), round_to_double(first[1]), round_to_double(first[2])};
  // Corners: the points, their labels, and their barycentric coordinates in V, coordinate k
  // being (n . P - d W) / (W (n . v_k - d)) for V's face k (plane 4 + k) and vertex v_k.
  for (int p = 0; p < np; ++p) {
    const unsigned m = mask[static_cast<std::size_t>(p)] & ~shadowed;
    int n = 0;
    for (int f = 0; f < kPlanes && n < 3; ++f)
      if ((m >> f) & 1u) out.labels[p][n++] = static_cast<std::uint8_t>(f);
    out.simple = out.simple && n == 3 && std::popcount(m) == 3;
    for (int k = 0; k < 3; ++k) out.point[p][k] = round_to_double(q[static_cast<std::size_t>(p)][static_cast<std::size_t>(k)]);
    for (int k = 0; k < 4; ++k) {
      dot(w.n[4 + k], w.pt[p], w.t0);
      mpz_submul(w.t0.get_mpz_t(), w.d[4 + k].get_mpz_t(), w.pt[p][3].get_mpz_t());
      dot(w.n[4 + k], w.vert[1][k], w.t1);
      w.t1 -= w.d[4 + k];
      w.t1 *= w.pt[p][3];
      mpq_class coordinate(w.t0, w.t1);
      coordinate.canonicalize();
      out.bary[p][k] = round_to_double(coordinate);
    }
  }
  out.num_corners = np;
}

}  // namespace tetia::detail

namespace tetia::exact {

// =============================================================================================
// 2D: the intersection area of two triangles.
//
// Method (again unrelated to the kernel's: no barycentric coordinates, no pairing of signs; the
// lines each corner lies on are tracked only for the kernel's exact last resort,
// exact_polygon below): Sutherland-Hodgman clipping of A by the three closed half-planes of B, every number a
// rational. Clipping a convex polygon by a half-plane in exact arithmetic yields exactly the
// intersection (a vertex on the line is kept once and creates no crossing point; a crossing
// point P + t (Q - P) with t = f(P) / (f(P) - f(Q)) lies exactly on the line), so after three
// clips the polygon is exactly A ∩ B, possibly with repeated or collinear corners, which the
// shoelace formula does not mind. A flat intersection (touching along an edge or at a point)
// has shoelace area exactly 0. Cost: a few dozen rational operations (each with a gcd), about
// 30 us per random pair.
// =============================================================================================

namespace {

struct QPoint {
  mpq_class x, y;
};

// det[b - a, p - a]: positive when (a, b, p) is counter-clockwise.
mpq_class orient(const QPoint& a, const QPoint& b, const QPoint& p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

void check_finite(const Triangle& t) {
  for (const Vec2& p : t) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::domain_error("tetia::exact: non-finite coordinate");
    }
  }
}

// A ∩ B as a polygon whose corners carry the labels of the lines they lie on: Sutherland-Hodgman
// as described above, each corner with `out`, the label of the side that leaves it (0-2 the
// edges of A, edge k opposite vertex k; 3-5 the lines of B), so that a corner lies on the lines
// `out` of its predecessor and its own `out`. Coordinates are translated by `origin`. The
// corners run in A's orientation. Returns false when A or B is flat.
struct LabelledCorner {
  QPoint p;
  int out;
};

bool clip_labelled(const Triangle& A, const Triangle& B, const QPoint& origin, std::vector<LabelledCorner>& poly,
                   std::array<QPoint, 3>& b) {
  check_finite(A);
  check_finite(B);
  std::vector<LabelledCorner> next;
  poly.resize(3);
  next.reserve(8);
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    // The side from vertex i to vertex i + 1 is the edge opposite vertex i + 2.
    poly[k] = {{mpq_class(A[k].x) - origin.x, mpq_class(A[k].y) - origin.y}, (i + 2) % 3};
    b[k] = {mpq_class(B[k].x) - origin.x, mpq_class(B[k].y) - origin.y};
  }
  const int sign_b = sgn(orient(b[0], b[1], b[2]));
  if (sign_b == 0 || sgn(orient(poly[0].p, poly[1].p, poly[2].p)) == 0) return false;
  std::vector<mpq_class> f;
  for (int k = 0; k < 3 && poly.size() >= 3; ++k) {
    // Edge k of B (opposite vertex k); the kept side is the one holding B[k], where
    // sign_b * orient(b1, b2, .) > 0 (orient(b1, b2, b0) = orient(b0, b1, b2): a rotation).
    const QPoint& b1 = b[static_cast<std::size_t>((k + 1) % 3)];
    const QPoint& b2 = b[static_cast<std::size_t>((k + 2) % 3)];
    const std::size_t n = poly.size();
    f.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      f[i] = orient(b1, b2, poly[i].p);
      if (sign_b < 0) f[i] = -f[i];
    }
    next.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = i + 1 == n ? 0 : i + 1;
      const int si = sgn(f[i]), sj = sgn(f[j]);
      // A kept corner leaves along its side, except a corner on the clipping line whose side
      // goes outside: the boundary then goes on along the clipping line.
      if (si >= 0) next.push_back({poly[i].p, si == 0 && sj < 0 ? 3 + k : poly[i].out});
      if (si * sj < 0) {  // strictly on opposite sides: one exact crossing point
        const mpq_class t = f[i] / (f[i] - f[j]);
        next.push_back({{poly[i].p.x + t * (poly[j].p.x - poly[i].p.x), poly[i].p.y + t * (poly[j].p.y - poly[i].p.y)},
                        si > 0 ? 3 + k : poly[i].out});
      }
    }
    poly.swap(next);
  }
  return true;
}

}  // namespace

// Contract: |det[t1 - t0, t2 - t0]| / 2, exactly. Throws std::domain_error on a non-finite
// coordinate.
mpq_class area(const Triangle& t) {
  check_finite(t);
  const QPoint a{t[0].x, t[0].y}, b{t[1].x, t[1].y}, c{t[2].x, t[2].y};
  return abs(orient(a, b, c)) / 2;
}

// Contract: the exact area of A ∩ B for closed A, B in any vertex order; 0 when they touch or
// are disjoint or either is flat. Throws std::domain_error on a non-finite coordinate.
// Reentrant: no shared state.
mpq_class intersection_area(const Triangle& A, const Triangle& B) {
  // Translating both by A's vertex 0 changes no area and keeps the numbers smaller.
  check_finite(A);
  std::vector<LabelledCorner> poly;
  std::array<QPoint, 3> b;
  if (!clip_labelled(A, B, {A[0].x, A[0].y}, poly, b) || poly.size() < 3) return 0;
  mpq_class twice = 0;
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) twice += orient(poly[0].p, poly[i].p, poly[i + 1].p);
  return abs(twice) / 2;
}

// Contract: intersection_area(A, B) correctly rounded to the nearest double (ties to even).
double intersection_area_double(const Triangle& A, const Triangle& B) {
  return round_to_double(intersection_area(A, B));
}

}  // namespace tetia::exact

namespace tetia::detail {

// The exact polygon of clip_labelled, rounded: the kernel's last resort in 2D.
void exact_polygon(const Triangle& A, const Triangle& B, ExactPolygon& out) {
  using exact::LabelledCorner;
  using exact::QPoint;
  out.num_corners = 0;
  out.moments = {};
  const QPoint origin{A[0].x, A[0].y};
  std::vector<LabelledCorner> poly;
  std::array<QPoint, 3> b;
  if (!exact::clip_labelled(A, B, origin, poly, b) || poly.size() < 3) return;
  const std::size_t n = poly.size();
  // Twice the signed area and twice the first moments, by a fan from corner 0; the signs follow
  // A's orientation, which the corners run in.
  mpq_class twice = 0, fx = 0, fy = 0;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const mpq_class t = exact::orient(poly[0].p, poly[i].p, poly[i + 1].p);
    twice += t;
    fx += t * (poly[0].p.x + poly[i].p.x + poly[i + 1].p.x);
    fy += t * (poly[0].p.y + poly[i].p.y + poly[i + 1].p.y);
  }
  const int orientation = sgn(twice);
  if (orientation == 0) return;  // touching or flat: no interior
  const mpq_class area = abs(twice) / 2;
  // Integral of x over a triangle: area times the mean of its vertices; put back the origin.
  out.moments.area = exact::round_to_double(area);
  out.moments.first = {exact::round_to_double(orientation * fx / 6 + area * origin.x),
                       exact::round_to_double(orientation * fy / 6 + area * origin.y)};
  const mpq_class det_b = exact::orient(b[0], b[1], b[2]);
  if (n > static_cast<std::size_t>(Polygon::max_corners)) throw std::logic_error("exact_polygon: too many corners");
  for (std::size_t k = 0; k < n; ++k) {
    // Counter-clockwise: reversed when A runs clockwise. Corner c lies on the side arriving at
    // it (its predecessor's `out`) and on its own `out`.
    const std::size_t c = orientation > 0 ? k : n - 1 - k;
    const LabelledCorner& q = poly[c];
    const int in = poly[(c + n - 1) % n].out;
    out.point[k] = {exact::round_to_double(q.p.x + origin.x), exact::round_to_double(q.p.y + origin.y)};
    out.labels[k][0] = static_cast<std::uint8_t>(std::min(in, q.out));
    out.labels[k][1] = static_cast<std::uint8_t>(std::max(in, q.out));
    for (int v = 0; v < 3; ++v)
      out.bary[k][v] = exact::round_to_double(
          exact::orient(b[static_cast<std::size_t>((v + 1) % 3)], b[static_cast<std::size_t>((v + 2) % 3)], q.p) / det_b);
  }
  out.num_corners = static_cast<int>(n);
}

}  // namespace tetia::detail
