// src/kernel/kernel_result.hpp -- what the kernel produces for one pair: the corners found by
// Algorithm 2 of McCoid & Gander (RawCorner: coordinates, labels, and which part of the
// hierarchy of Section 3 found it), and the facets, volume and moments built from them.
// Part of the kernel's one translation unit: included by src/kernel/tet_intersection.cpp only.
#pragma once

#include <cstdint>

#include "tables.hpp"  // u8
#include "tetia/polyhedron.hpp"

namespace tetia::detail {

// Corner kinds, in the order of the hierarchy of Section 3.
enum : u8 { kVertexOfX = 0, kEdgeOfX = 1, kFaceOfX = 2, kVertexOfY = 3 };

// One corner as the kernel finds it: barycentric coordinates in the reference tetrahedron
// (exactly zero in the coordinates of the planes of Y it lies on) and its labels in the
// kernel's own numbering (0-3 faces of X, 4-7 planes P_0..P_3), ascending.
struct RawCorner {
  double bary[4];
  double weights[4];  // barycentric weights on X's vertices (not set for vertices of Y)
  u8 labels[3];
  u8 kind;
  u8 index;  // vertex of X, edge * 4 + plane, face * 8 + line, or vertex of Y
  // The guardrail moved the corner (clamped a coordinate): the weights on X's vertices describe
  // the point before the move and are not used (see PolyhedronBuilder::fill).
  bool moved;
};

// Everything the kernel produces; no heap. Facets are cycles over corner indices, in the
// direction of the walk (oriented later, only when a Polyhedron is built).
struct KernelResult {
  static constexpr int kMaxCorners = Polyhedron::max_corners;
  RawCorner corners[kMaxCorners];
  int num_corners = 0;
  int num_facets = 0;
  std::uint32_t on_plane[8];  // corners carrying each label, as bit masks
  u8 facet_label[8];
  u8 facet_begin[9];
  u8 facet_index[Polyhedron::max_facet_indices];
  bool contradiction = false;              // a sign relation failed (checked with statistics)
  bool corner_apex = false;                // fans from corner 0 (build_facets' kCornerApex)
  bool x_inside = false;                   // all four vertices of X inside Y: X n Y is X (run_kernel)
  double facet_volume6[8];                // signed fan volumes (x6) of the facets as stored
  double coordinate_scale = 1.0;          // largest |coordinate| of X's vertices
  double ref_volume = 0.0;                // volume in the reference frame (Y has volume 1/6)
  double ref_first[3] = {0.0, 0.0, 0.0};  // first moments in the reference frame
  // The kernel's volume was not certified to 1e-12 of the smaller tetrahedron and was computed
  // again (refined_clip.hpp): these moments, in the frame's coordinates, are the result.
  bool refined = false;
  Moments refined_moments;
  // Empty because X lies strictly on the negative side of a plane of Y (run_kernel): certain.
  bool certainly_empty = false;

  // The empty result: no corners, no facets, zero volume and moments.
  void set_empty() {
    num_corners = 0;
    num_facets = 0;
    facet_begin[0] = 0;
    ref_volume = 0.0;
    ref_first[0] = ref_first[1] = ref_first[2] = 0.0;
    x_inside = false;
    refined = false;
    certainly_empty = false;
  }
};

}  // namespace tetia::detail
