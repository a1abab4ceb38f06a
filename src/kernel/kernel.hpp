// src/kernel/kernel.hpp -- class Kernel, Algorithm 2 of McCoid & Gander for one pair: its
// state (the sign masks of X's vertices, of the edge-plane and face-line intersections), the
// constructor that computes the binary signs of X's vertices (Section 1), and run.
//
// The steps are defined in the headers that follow, one part of the paper each:
//   algorithm2.hpp          run_steps: the steps in order; Section 3.1 (lines 2-6, vertices of
//                           X in Y) and Section 3.4 (lines 19-23, vertices of Y in X)
//   edge_signs.hpp          Section 3.2, lines 7-17: edges of X against the planes of Y
//   face_signs.hpp          Section 3.3, line 18: faces of X against the lines of Y
//   nonconvex_repair.hpp    Fig. 6 (the non-convex case of Theorem 6's proof): a twisted
//                           cross-section, its edge signs decided again with exact minors
//   corner_coordinates.hpp  the corners' coordinates: eqs. (2), (4), (5), and the guardrail of
//                           Section 4.1.1
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only
// (what it defines in the anonymous namespace is that file's own).
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernel_result.hpp"
#include "lanes.hpp"
#include "tables.hpp"
#include "tetia/kernel_trace.hpp"
#include "tetia/tet_intersection.hpp"

namespace tetia::detail {

namespace {

// The kernel state for one pair. With kWeights, each corner also gets its barycentric weights
// on X's vertices (only a full Polyhedron with U as the reference needs them). kStats: the
// statistics are kept (and contradictions looked for); without, every such test compiles away.
template <bool kWeights, bool kStats>
class Kernel {
 public:
  Kernel(const double (&C)[4][4], IntersectionStats* stats) : C_(C), stats_(kStats ? stats : nullptr) {
    for (int i = 0; i < 4; ++i) {
      unsigned m = 0, pos = 0;  // binary signs (Section 1) and strict positivity
#if TETIA_KERNEL_SSE2
      const __m128d r01 = _mm_loadu_pd(C[i]), r23 = _mm_loadu_pd(C[i] + 2), z = _mm_setzero_pd();
      m = unsigned(_mm_movemask_pd(_mm_cmpge_pd(r01, z))) | unsigned(_mm_movemask_pd(_mm_cmpge_pd(r23, z))) << 2;
      pos = unsigned(_mm_movemask_pd(_mm_cmpgt_pd(r01, z))) | unsigned(_mm_movemask_pd(_mm_cmpgt_pd(r23, z))) << 2;
      // Row i of C arranged for the pairs (y, x) of order_edge_by_pairs: the y-lanes are
      // (0,0), (0,1), (1,2) and the x-lanes (1,2), (3,2), (3,3).
      lanes_[i][0] = _mm_unpacklo_pd(r01, r01);
      lanes_[i][1] = r01;
      lanes_[i][2] = _mm_shuffle_pd(r01, r23, 1);
      lanes_[i][3] = _mm_shuffle_pd(r23, r23, 1);
      lanes_[i][4] = _mm_unpackhi_pd(r23, r23);
#else
      for (int p = 0; p < 4; ++p) {
        m |= unsigned(C[i][p] >= 0.0) << p;
        pos |= unsigned(C[i][p] > 0.0) << p;
      }
#endif
      sm_[i] = static_cast<u8>(m);
      pm_[i] = static_cast<u8>(pos);
    }
  }

  // Runs Algorithm 2; fills `out` with the corners. Returns false when the signs contradict
  // each other, which the proof of Theorem 6 excludes; such contradictions are only looked for
  // when statistics are requested (the tests always request them).
  [[gnu::always_inline]] bool run(KernelResult& out) {
    CornerList cl;
    const bool consistent = run_steps(out, cl);
    out.num_corners = cl.num_corners;
    out.num_facets = 0;
    for (int a = 0; a < 8; ++a) out.on_plane[a] = cl.on_plane[a];
    return consistent;
  }

  bool consistent() const { return consistent_; }

 private:
  // The corners' count and, per plane, the mask of the corners on it, while the corners are
  // added: a local of run() rather than members of `out`, so that the compiler can keep them
  // apart from the corners' byte-sized labels stored in between (a store through a char type
  // may alias anything reachable, a local whose address stays in run() nothing).
  struct CornerList {
    int num_corners = 0;
    std::uint32_t on_plane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  };
  // Algorithm 2 proper (see run; defined in algorithm2.hpp).
  [[gnu::always_inline]] inline bool run_steps(KernelResult& out, CornerList& cl);

 public:
  void export_signs(KernelTrace& t) const;

 private:
  // The members below without a body are defined in the headers named, `inline` as a member
  // defined in the class is (g++ weighs that when it inlines).
  // --- Section 3.2: edges of X against the planes of Y (edge_signs.hpp) -------------------
  bool crosses_before(int i, int j, int y, int x) const;
  void order_edge(int e);
  bool order_edge_by_pairs(int e, int i, int j, unsigned crossed);
  void order_edge_sorted(int e, int i, int j, unsigned crossed);
  unsigned twisted_views() const;  // nonconvex_repair.hpp: Fig. 6
  void untwist(unsigned views);

  // --- Section 3.3: faces of X against the lines of Y (face_signs.hpp) ---------------------
  void build_segments();

  // The segment's vertices as kSegmentVerts lists them: lone vertex, then the other two.
  const u8* seg_verts(int f, int p) const {
    const int u = kFaceVerts[f][0], v = kFaceVerts[f][1], w = kFaceVerts[f][2];
    const int which = int(bit(sm_[u] ^ sm_[v], p)) | (int(bit(sm_[u] ^ sm_[w], p)) << 1);
    return kSegmentVerts[f][which];
  }
  u8 seg_m1(int f, int p) const { return static_cast<u8>((seg1_[f] >> (4 * p)) & 0xFu); }
  u8 seg_m2(int f, int p) const { return static_cast<u8>((seg2_[f] >> (4 * p)) & 0xFu); }

  void face_line_flags();
  bool pairing(int f, int a, int b, int c) const;
  double numerator5(int c, int a, int b, int i, int j, int k) const;
  bool direct_sign(int f, int a, int b, int c) const;
  void decide_face(int f);
  void resolve_triple(int f, const Triple& T);

  void note_inconsistency() { consistent_ = false; }
  u8 em(int e, int p) const { return static_cast<u8>((em_[e] >> (4 * p)) & 0xFu); }

  // --- corners (corner_coordinates.hpp) ---------------------------------------------------
  RawCorner& add_corner(KernelResult& out, CornerList& cl, int l0, int l1, int l2, u8 kind, int index);
  bool guardrail(double (&b)[4], unsigned zero_mask, unsigned nonneg);
  [[gnu::noinline]] static inline bool clamp_to_simplex(double (&b)[4], unsigned zero_mask);
  Quad edge_point(int i, int j, int p, double (&w)[4]) const;
  void edge_corner_coords(int e, int p, RawCorner& rc);
  bool face_corner_by_eq5(int f, int a, int b, Quad& res, double (&w)[4]) const;
  void face_corner_coords(int f, int a, int b, RawCorner& rc);
  void face_corner_by_eq4(int f, int a, int b, Quad& res, double (&w)[4]) const;

  const double (&C_)[4][4];  // X's barycentric coordinates, row i = vertex x_i
#if TETIA_KERNEL_SSE2
  __m128d lanes_[4][5];
#endif
  u8 sm_[4];               // sign masks of the vertices of X
  u8 pm_[4];               // strict positivity masks (coordinate > 0)
  u8 cross_[6] = {0, 0, 0, 0, 0, 0};  // planes crossed by each edge (line 9)
  std::uint32_t edge_corners_ = 0;     // bit 4e + p: edge e ∩ P_p lies on Y
  std::uint16_t em_[6] = {};  // sign mask at edge e ∩ P_p in nibble p (read as 0 where none)
  std::uint16_t seg1_[4], seg2_[4];  // sign masks at the ends of (face f) ∩ P_p, nibble p
  u8 fexist_[4] = {0, 0, 0, 0};  // lines met by face f (bit L)
  std::uint32_t fsign_[4] = {};  // sign mask at face f ∩ line L, nibble L
  std::uint32_t undecided_[4];   // coordinates of face f ∩ line L not inherited, nibble L
  u8 fsign(int f, int L) const { return static_cast<u8>((fsign_[f] >> (4 * L)) & 0xFu); }
  bool consistent_ = true;
  bool exact_minors_ = false;  // crosses_before decides by the exact sign of its minor (untwist)
  IntersectionStats* stats_;  // only read through stats()
  IntersectionStats* stats() const {
    if constexpr (kStats) return stats_;
    else return nullptr;
  }
  RawCorner overflow_;  // where corners beyond kMaxCorners go (never, for a simple polytope)
};

// The signs decided, for trace_kernel (include/tetia/kernel_trace.hpp: tests and parsimony).
template <bool kWeights, bool kStats>
void Kernel<kWeights, kStats>::export_signs(KernelTrace& t) const {
  for (int e = 0; e < 6; ++e) {
    t.crossings[static_cast<std::size_t>(e)] = cross_[e];
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q)
        t.edge_sign[e][p][q] =
            bit(cross_[e], p) && q != p ? static_cast<std::int8_t>(bit(em(e, p), q)) : std::int8_t{-1};
  }
  const bool level2 = (sm_[0] | sm_[1] | sm_[2] | sm_[3]) == 0xF && (sm_[0] & sm_[1] & sm_[2] & sm_[3]) != 0xF;
  for (int f = 0; f < 4; ++f)
    for (int L = 0; L < 6; ++L)
      for (int c = 0; c < 4; ++c)
        t.face_sign[f][L][c] = level2 && bit(fexist_[f], L) && c != kLines[L][0] && c != kLines[L][1]
                                   ? static_cast<std::int8_t>(bit(fsign(f, L), c))
                                   : std::int8_t{-1};
}

}  // namespace

}  // namespace tetia::detail
