// src/mesh/split_cells.hpp -- hexahedra, prisms, pyramids and quadrilaterals as simplices,
// conforming across shared faces without new nodes (issue 16, part 3; internal to the library).
//
// The rule: every quadrilateral face is split along its diagonal through its node of smallest
// tag (the file's global node number), so two cells that share the face split it alike. A cell
// is then the cone from its node of smallest tag, v, over the triangles of its faces that do not
// contain v: each such triangle and v make a tetrahedron (a hexahedron gives 6, a prism 3, a
// pyramid 2). The faces through v are split through v by the same rule (v is their smallest
// node too), which is what the cone implies there, so the simplices tile the cell and meet the
// neighbours' on every shared face. For a cell whose faces are planar (any convex cell with
// planar faces) the simplices' volumes sum to the cell's exactly (in exact arithmetic); a twisted
// face is defined by the split, the same for both neighbours. (Dompierre, Labbe, Vallet and
// Camarero, "How to subdivide pyramids, prisms and hexahedra into tetrahedra", 1999, show the
// same rule and count the cases where a hexahedron needs only 5; 6 always works.)
//
// Node orders are Gmsh's (its manual, "Node ordering"): a positively oriented cell gives
// positively oriented simplices, since its faces below are listed counter-clockwise seen from
// outside and the cone's apex lies inside them. A quadrilateral gives two triangles in its own
// order. Collapsed cells (a node twice) give fewer pieces (see split_cell). Allocation-free; the
// output arrays hold the indices given in `nodes`.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace tetia::detail {

/// The cell types split here, by Gmsh's element type numbers.
enum class SplitShape { quadrangle = 3, hexahedron = 5, prism = 6, pyramid = 7 };

/// Corner nodes of each shape (the nodes read).
constexpr int split_shape_nodes(SplitShape s) {
  return s == SplitShape::quadrangle ? 4 : s == SplitShape::hexahedron ? 8 : s == SplitShape::prism ? 6 : 5;
}

/// At most this many simplices per cell.
inline constexpr int kMaxSplitSimplices = 6;

namespace split_impl {

struct Face {
  int n;       // 3 or 4 nodes
  int v[4];    // local node numbers, counter-clockwise seen from outside
};
struct ShapeFaces {
  int count;
  Face f[6];
};

constexpr ShapeFaces faces_of(SplitShape s) {
  switch (s) {
    case SplitShape::hexahedron:
      return {6,
              {{4, {0, 3, 2, 1}}, {4, {4, 5, 6, 7}}, {4, {0, 1, 5, 4}}, {4, {1, 2, 6, 5}}, {4, {2, 3, 7, 6}},
               {4, {3, 0, 4, 7}}}};
    case SplitShape::prism:
      return {5, {{3, {0, 2, 1, 0}}, {3, {3, 4, 5, 0}}, {4, {0, 1, 4, 3}}, {4, {1, 2, 5, 4}}, {4, {2, 0, 3, 5}}}};
    case SplitShape::pyramid:
      return {5, {{4, {0, 3, 2, 1}}, {3, {0, 1, 4, 0}}, {3, {1, 2, 4, 0}}, {3, {2, 3, 4, 0}}, {3, {3, 0, 4, 0}}}};
    case SplitShape::quadrangle:
      break;
  }
  return {0, {}};
}

// The two triangles of quadrilateral (a, b, c, d) (local positions 0-3) split along the diagonal
// through its node of smallest tag, in the quadrilateral's own rotational order.
inline void split_quad(const int (&q)[4], const std::uint64_t* tags, int (&tri)[2][3]) {
  int smallest = 0;
  for (int k = 1; k < 4; ++k)
    if (tags[q[k]] < tags[q[smallest]]) smallest = k;
  const int s = smallest & 1;  // 0: the diagonal a-c, 1: b-d
  tri[0][0] = q[s], tri[0][1] = q[s + 1], tri[0][2] = q[(s + 2) & 3];
  tri[1][0] = q[s], tri[1][1] = q[(s + 2) & 3], tri[1][2] = q[(s + 3) & 3];
}

}  // namespace split_impl

/// Whether a simplex has a node twice (it has no volume: the piece of a collapsed face).
template <class Index, std::size_t N>
bool repeats_a_node(const std::array<Index, N>& s) {
  for (std::size_t a = 0; a < N; ++a)
    for (std::size_t b = a + 1; b < N; ++b)
      if (s[a] == s[b]) return true;
  return false;
}

/// The tetrahedra of a hexahedron, prism or pyramid: `nodes` and `tags` hold its corner nodes in
/// Gmsh's order (what the mesh indexes, and the file's tags, which decide the split). Writes up
/// to kMaxSplitSimplices tetrahedra of mesh node indices to `out`; returns how many.
///
/// Collapsed cells (a node given twice, as mesh generators write a prism or a pyramid as a
/// degenerate hexahedron) are split by the same rule, with "the faces through the apex" read by
/// tag, so that the cone still runs over the boundary of the collapsed cell; the pieces of its
/// collapsed faces (a node twice) have no volume and are left out. What is left tiles the
/// collapsed cell and meets its neighbours' faces as before: a quadrilateral face with a node
/// twice is a triangle, and its split keeps exactly that triangle.
template <class Index>
int split_cell(SplitShape shape, const Index* nodes, const std::uint64_t* tags,
               std::array<Index, 4> (&out)[kMaxSplitSimplices]) {
  using namespace split_impl;
  const int nv = split_shape_nodes(shape);
  int apex = 0;
  for (int k = 1; k < nv; ++k)
    if (tags[k] < tags[apex]) apex = k;
  const ShapeFaces sf = faces_of(shape);
  int count = 0;
  const auto add = [&](const std::array<Index, 4>& t) {
    if (!repeats_a_node(t)) out[count++] = t;
  };
  for (int f = 0; f < sf.count; ++f) {
    const Face& face = sf.f[f];
    bool through_apex = false;
    for (int k = 0; k < face.n; ++k) through_apex |= tags[face.v[k]] == tags[apex];
    if (through_apex) continue;
    if (face.n == 3) {
      add({nodes[apex], nodes[face.v[0]], nodes[face.v[1]], nodes[face.v[2]]});
    } else {
      const int q[4] = {face.v[0], face.v[1], face.v[2], face.v[3]};
      int tri[2][3];
      split_quad(q, tags, tri);
      for (const auto& t : tri) add({nodes[apex], nodes[t[0]], nodes[t[1]], nodes[t[2]]});
    }
  }
  return count;
}

/// The triangles of a quadrilateral (Gmsh's order: counter-clockwise), split along the diagonal
/// through its node of smallest tag, in the quadrilateral's rotational order: two, or one for a
/// quadrilateral with a node twice (a triangle; the other piece has no area), or none if it has
/// no area at all. Returns how many.
template <class Index>
int split_quadrangle(const Index* nodes, const std::uint64_t* tags, std::array<Index, 3> (&out)[2]) {
  const int q[4] = {0, 1, 2, 3};
  int tri[2][3];
  split_impl::split_quad(q, tags, tri);
  int count = 0;
  for (int t = 0; t < 2; ++t) {
    const std::array<Index, 3> s{nodes[tri[t][0]], nodes[tri[t][1]], nodes[tri[t][2]]};
    if (!repeats_a_node(s)) out[count++] = s;
  }
  return count;
}

}  // namespace tetia::detail
