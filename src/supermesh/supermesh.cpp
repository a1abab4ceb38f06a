// The intersection of two tetrahedral meshes, or of two triangular ones: which (source cell,
// target cell) pairs overlap with positive volume (area), found by an advancing front over facet
// adjacency or by an R-tree (packed_box_tree.hpp: the target cells' boxes, packed in their
// Morton order).
//
// One implementation for both dimensions: everything below is a template over the mesh type
// (src/supermesh/dimension.hpp says what differs: the point and cell types, the kernel, volume or
// area); the only dimension-specific function is faces_crossed, the certified side test. The text
// speaks of tetrahedra, faces and volumes; in 2D read triangles, edges and areas (and "removing
// segments" in the argument below becomes "removing points": it still does not disconnect an
// open set of the plane).
//
// The front. Source cells are visited in breadth-first order over the source adjacency, within
// a chunk of consecutive positions along a Morton curve through the cell centroids (a compact
// region whatever the file's numbering). For each source cell s:
//
//   1. Seeds: the targets of s's BFS parent (processed, same chunk), tried one at a time
//      (first those whose box holds the centre of s's box); each one found positive starts a
//      flood fill: a target t positive with s queues its face neighbours across the faces of t
//      that s may cross. In 3D these are the faces on which the kernel's polytope s n t has a
//      facet (OneToMany::moments: where int(s) meets the interior of a face, s n t has a facet
//      there, so without one no path inside s crosses it); otherwise (a reference too flat for
//      its signs to be certain, and in 2D) the faces whose plane does not have all of s strictly
//      on t's side (certified with orient3d's error bound: the neighbour meets s with zero
//      volume). A target tested zero queues nothing. Seeding stops once s is covered (the
//      volumes found add up to |s| to 1e-12), or once a flood found pieces, crossed a risky
//      face and was not cut (step 3 then searches for the rest).
//   2. Not covered yet, and the flood neither crossed a risky face nor was cut (both below):
//      the targets of every processed neighbour of s and their neighbours (this crosses
//      zero-volume contacts: for identical or face-sharing meshes the parent's targets only
//      touch s, and it is their neighbours that intersect it), flood again.
//   3. A face of a target is "risky" when it has no neighbour (the boundary, which also covers
//      non-conforming interior faces) or a flat one (which breaks face connectivity). The
//      flood crossed a risky face when one is among the faces a positive target queued its
//      neighbours across; it was cut when a target it queued that way tested zero. If the
//      flood crossed a risky face and either covered s or was not cut, the targets with a
//      risky face whose bounding box overlaps s's, not yet tested, are tested (in 3D not
//      those whose risky faces all lie beyond a face plane of s), and each positive one
//      starts a flood. Otherwise, if s is not covered (this includes a cell with no
//      processed neighbour, the start of a region), s is tested against every target whose
//      bounding box overlaps its own (R-tree query; in 3D less those that lie beyond a face
//      plane of s, certainly empty), which finds every positive pair by itself.
//
// Why this finds every pair (s, t) with vol(s n t) > 0. The target cells are a mesh: they do
// not overlap (several overlapping meshes in one are found completely only by the R-tree
// search). Let O be the interior of s intersected with the interior of the target domain,
// minus the risky faces. Each piece s n t of positive volume has its interior in O. Inside one
// connected component K of O two pieces are linked by a path avoiding target edges (removing
// segments does not disconnect an open set in R^3); the path crosses target faces at interior
// points of s and of the faces, so s n t has a facet on each face it crosses (and s crosses the
// face's plane), and each such face is shared by two targets that both meet s with positive
// volume: the flood reaches every piece of K from any one of them. The flood found a component
// K0. If K0 were not dense in s, its boundary inside int(s) would separate that open convex
// set, so it would have positive area, and it lies on risky faces: at an interior point of
// such a face, inside s, the target t of K0 on that side has a facet of s n t there, so the
// flood crossed a risky face. So if it crossed none, K0 is dense in s, it is the only component
// (another one would be an open set disjoint from a dense open set), and the flood found every
// positive target. If it did, every other component K has a boundary inside int(s) (which is
// connected), on risky faces; the target on K's side of such a face owns it as a risky face,
// meets s with positive volume and lies in K: the risky pass tests it (that face meets int(s),
// so no face plane of s has it beyond) and floods K. An R-tree pass is complete by itself. The
// seeds only decide how often the R-tree is needed (near the target boundary: O(n^(2/3)) cells
// for meshes of one domain), never what is found;
// zero-volume contacts never stop the front (a flood that finds nothing falls back to the
// R-tree).
//
// The argument is exact; the kernel decides positivity, and its facets, in floating point.
// Below the resolution of doubles it can report zero for a sliver the argument walks through,
// or drop a facet of rounding-sized area. A dropped facet can only hide a region cut off from
// K0 inside s by faces of rounding-sized area; s being convex, one side of such a cut has a
// volume of that order (a relative isoperimetric inequality), and it is not K0, whose pieces
// are above the resolution. A sliver reported zero is caught where it can matter: the flood
// reached it across a face s crosses, so the flood counts as cut, and an uncovered cell then
// gets the full R-tree pass; for a covered cell the coverage test is the guard (a flood cut
// short leaves s visibly uncovered; the tests found such cases with 1e-12 offsets). Zero tests
// across a crossed face also happen without any sliver (a facet of zero area where faces of the
// two meshes coincide, and always with the plane test's wider mask): they only cost the R-tree
// pass. Pieces below the resolution (1e-14 of the smaller cell) are dropped in both searches, so
// front and R-tree return the same pieces.
//
// Threads: the chunks (their number depends on the mesh size only) each have their own front
// and are handed to threads dynamically. Every pair is computed by one kernel call with the
// same arguments whatever the order, and the pieces are sorted by (target, source) at the end,
// so the result, including `candidates`, is the same bit for bit for any number of threads.
// No allocation per pair: each thread keeps its buffers and its pieces until the final merge.
//
// Kept data: where polyhedra, mixed mass matrices or a consumer's numbers are needed, the full
// kernel runs (in 3D on every candidate, in 2D as intersect() on every candidate instead of
// intersection_moments; the same moments bit for bit). keep_polyhedra stores the whole
// polyhedron (polygon) per piece; keep_mixed_mass computes the piece's local mixed mass matrix from it while it is at hand
// (src/supermesh/mixed_mass.hpp, the function the remap uses on kept polyhedra) and stores only
// those 16 (9) numbers, merged in the same order as the pieces.
#include "tetia/supermesh.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iterator>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "dimension.hpp"
#include "../kernel/one_to_many.hpp"
#include "mixed_mass.hpp"
#include "packed_box_tree.hpp"
#include "../compensated_sum.hpp"
#include "../morton.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia {

namespace {

// The pieces' measures summed with compensation (compensated_sum.hpp): totals are compared
// with mesh volumes (areas) to 1e-13.
template <class Piece, class Measure>
double compensated_total(const std::vector<Piece>& pieces, Measure&& measure) {
  detail::CompensatedSum sum;
  for (const auto& p : pieces) sum.add(measure(p));
  return sum.value();
}

}  // namespace

double Supermesh::intersection_volume() const {
  return compensated_total(pieces, [](const SupermeshPiece& p) { return p.volume; });
}

double Supermesh2::intersection_area() const {
  return compensated_total(pieces, [](const SupermeshPiece2& p) { return p.area; });
}

namespace {

using detail::Box;

template <class Mesh>
Box<detail::Dim<Mesh>::d> box_of(const typename detail::Dim<Mesh>::Cell& t) {
  // Written out per axis (min and max are exact: any order gives the same box); the front
  // computes it for every candidate.
  const auto lo = [](double a, double b) { return b < a ? b : a; };
  const auto hi = [](double a, double b) { return a < b ? b : a; };
  if constexpr (detail::Dim<Mesh>::d == 3) {
    return {{lo(lo(t[0].x, t[1].x), lo(t[2].x, t[3].x)), lo(lo(t[0].y, t[1].y), lo(t[2].y, t[3].y)),
             lo(lo(t[0].z, t[1].z), lo(t[2].z, t[3].z))},
            {hi(hi(t[0].x, t[1].x), hi(t[2].x, t[3].x)), hi(hi(t[0].y, t[1].y), hi(t[2].y, t[3].y)),
             hi(hi(t[0].z, t[1].z), hi(t[2].z, t[3].z))}};
  } else {
    return {{lo(lo(t[0].x, t[1].x), t[2].x), lo(lo(t[0].y, t[1].y), t[2].y)},
            {hi(hi(t[0].x, t[1].x), t[2].x), hi(hi(t[0].y, t[1].y), t[2].y)}};
  }
}

/// Interiors of the boxes overlap (necessary for an intersection of positive volume).
template <int D>
inline bool overlap_open(const Box<D>& a, const Box<D>& b) {
  bool r = true;
  for (std::size_t k = 0; k < D; ++k) r &= unsigned(a.lo[k] < b.hi[k]) & unsigned(b.lo[k] < a.hi[k]);  // no branches
  return r;
}

// Bit k is set unless every vertex of S lies strictly on T's side of the plane of T's face k,
// which is certified with Shewchuk's static error bound for orient3d; if so, the neighbour of
// T across face k lies on the other side of that plane and meets S with zero volume.
unsigned faces_crossed(const Tet& T, const Tet& S);

// The same test through T's barycentric map (the kernel's change of coordinates, whose signs are
// certified the same way, without branches), given T's conditioning: bit k is set unless every
// vertex of S has coordinate k > 0. The map's signs are those of orient3d only when the sign of
// T's det6 is certain (quality far above its rounding, as in OneToMany::moments); otherwise the
// plain test decides. Used where the kernel's own facets are not at hand (kept polyhedra or
// mixed mass, or OneToMany could not certify them).
unsigned faces_crossed(const Tet& T, const detail::Conditioning& ct, const Tet& S) {
  if (!(ct.quality > detail::kSignCertainQuality)) return faces_crossed(T, S);
  const detail::BarycentricMap map(T, ct.inv_det6);
  double c[4][4];
  for (int i = 0; i < 4; ++i) map(S[static_cast<std::size_t>(i)], c[i]);
  unsigned inside = 0xFu;  // bit k: all four have coordinate k > 0
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) inside &= ~(unsigned(!(c[i][k] > 0.0)) << k);
  return ~inside & 0xFu;
}

unsigned faces_crossed(const Tet& T, const Tet& S) {
  constexpr double kErrBound = 1e-15;  // > (7 + 56 eps) eps, Shewchuk's o3derrboundA
  unsigned mask = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec3& a = T[static_cast<std::size_t>((k + 1) & 3)];
    const Vec3 B = T[static_cast<std::size_t>((k + 2) & 3)] - a, C = T[static_cast<std::size_t>((k + 3) & 3)] - a;
    const Vec3 n = cross(B, C);
    const Vec3 m{std::abs(B.y * C.z) + std::abs(B.z * C.y), std::abs(B.z * C.x) + std::abs(B.x * C.z),
                 std::abs(B.x * C.y) + std::abs(B.y * C.x)};
    const auto side = [&](const Vec3& p) {
      const Vec3 D = p - a;
      const double v = dot(n, D);
      const double e = kErrBound * (std::abs(D.x) * m.x + std::abs(D.y) * m.y + std::abs(D.z) * m.z);
      return v > e ? 1 : (v < -e ? -1 : 0);
    };
    const int own = side(T[static_cast<std::size_t>(k)]);
    bool separated = own != 0;
    for (std::size_t i = 0; i < 4 && separated; ++i) separated = side(S[i]) == own;
    if (!separated) mask |= 1u << k;
  }
  return mask;
}

// The same in 2D: bit k is set unless every vertex of S lies strictly on T's side of the line
// of T's edge k, certified with Shewchuk's static error bound for orient2d (evaluated in his
// order: both differences from the edge's first vertex, then the two products).
unsigned faces_crossed(const Triangle& T, const Triangle& S) {
  constexpr double kErrBound = 1e-15;  // > (3 + 16 eps) eps, Shewchuk's ccwerrboundA
  unsigned mask = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec2& a = T[(k + 1) % 3];
    const Vec2 B = T[(k + 2) % 3] - a;
    const auto side = [&](const Vec2& p) {
      const Vec2 D = p - a;
      const double l = B.x * D.y, r = B.y * D.x;
      const double v = l - r;
      const double e = kErrBound * (std::abs(l) + std::abs(r));
      return v > e ? 1 : (v < -e ? -1 : 0);
    };
    const int own = side(T[k]);
    bool separated = own != 0;
    for (std::size_t i = 0; i < 3 && separated; ++i) separated = side(S[i]) == own;
    if (!separated) mask |= 1u << k;
  }
  return mask;
}

// Large buffers ask for transparent huge pages (Linux, where THP is in "madvise" mode): filling
// hundreds of MB page by page costs more in first-touch page faults than in copying on some
// virtual machines (about 15 us per 4 KiB page measured on the development VM).
void advise_huge_pages(const void* p, std::size_t bytes) {
#ifdef __linux__
  if (bytes < (std::size_t{4} << 20)) return;
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t b = (reinterpret_cast<std::uintptr_t>(p) + page - 1) / page * page;
  const std::uintptr_t e = (reinterpret_cast<std::uintptr_t>(p) + bytes) / page * page;
  if (e > b) madvise(reinterpret_cast<void*>(b), e - b, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  if (n <= v.capacity()) return;
  std::vector<T> w;
  w.reserve(n);
  advise_huge_pages(w.data(), n * sizeof(T));
  w.insert(w.end(), v.begin(), v.end());
  v.swap(w);
}

// reserve_huge for an array about to be filled by `threads` threads: each page of the storage
// is first touched by the thread of a static schedule over it, so that the page faults of
// hundreds of MB are taken on every thread (about 2 s for 0.8 GB on one thread of the
// development VM: the 10^6-cell boxes' result is 0.8 GB, their records 0.2 GB); resize() then
// writes mapped memory. Only storage where no element lives yet (past size()) is written, as
// bytes.
template <class T>
void reserve_touched(std::vector<T>& v, std::size_t n, int threads) {
  reserve_huge(v, n);
  if (n * sizeof(T) < (std::size_t{4} << 20)) return;
  unsigned char* bytes = reinterpret_cast<unsigned char*>(v.data()) + v.size() * sizeof(T);
  const auto pages = static_cast<std::int64_t>((n - v.size()) * sizeof(T) / 4096);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t k = 0; k < pages; ++k) bytes[static_cast<std::size_t>(k) * 4096] = 0;
}

// Adds one to c and returns its value before: a relaxed atomic increment where other threads
// may add to c at the same time (a locked instruction, kept off the one-thread path).
inline std::uint32_t fetch_increment(std::uint32_t& c, bool concurrent) {
  return concurrent ? std::atomic_ref<std::uint32_t>(c).fetch_add(1, std::memory_order_relaxed) : c++;
}

// Sorts [b, e) by `less`: by insertion where it is short (a target's pieces: 5 to 20 in the
// benchmarks), by std::sort otherwise. An element already in order costs one comparison.
template <class It, class Less>
void sort_small(It b, It e, Less less) {
  if (e - b > 32) {
    std::sort(b, e, less);
    return;
  }
  for (It i = b + (b != e); i < e; ++i) {
    if (!less(*i, *(i - 1))) continue;
    const auto x = *i;
    It j = i;
    do {
      *j = *(j - 1);
      --j;
    } while (j != b && less(x, *(j - 1)));
    *j = x;
  }
}

template <class T>
void reserve_for_one_more(std::vector<T>& v) {
  if (v.size() == v.capacity()) reserve_huge(v, std::max<std::size_t>(1024, 2 * v.capacity()));
}

// A consumer's numbers per piece, in blocks of about 8 MB: appended without ever being copied (a
// growing vector holds its old and its new storage at once, half again its size at the peak),
// read by piece index.
class PieceValues {
 public:
  explicit PieceValues(std::size_t per_piece)
      : per_piece_(per_piece), per_block_(std::max<std::size_t>(1, (std::size_t{1} << 20) / std::max<std::size_t>(1, per_piece))) {}
  double* append() {
    if (n_ == blocks_.size() * per_block_) blocks_.push_back(std::make_unique_for_overwrite<double[]>(per_block_ * per_piece_));
    double* p = at(n_);
    ++n_;
    return p;
  }
  double* at(std::size_t piece) const { return blocks_[piece / per_block_].get() + (piece % per_block_) * per_piece_; }

 private:
  std::size_t per_piece_, per_block_, n_ = 0;
  std::vector<std::unique_ptr<double[]>> blocks_;
};

// A source cell whose pieces found by the front add up to less than (1 - this) times its volume
// goes to the R-tree (see the comment at the top: the coverage test).
constexpr double kCoverageTolerance = 1e-12;

// Pieces of volume at most this times the smaller cell's volume are dropped: below the
// resolution of double arithmetic the kernel cannot tell a sliver from a touching contact
// (it may report 1e-40 for two cells that only share a face, or 0 for a real 1e-40 sliver), so
// whether such "dust" is found would depend on the search; above it every piece is found.
constexpr double kResolution = 1e-14;

struct alignas(64) Chunk {  // aligned: threads fill neighbouring chunks
  std::int32_t begin = 0, end = 0;  // positions [begin, end) in the visiting order
  int worker = 0;                   // the thread that ran it, and its pieces there:
  std::size_t first = 0, last = 0;  // [first, last) of that worker's storage
  std::size_t candidates = 0;
};

// What the front reads of a target cell besides its vertices, in one record. The records are
// stored in the Morton order of the target centroids, and the front names targets by their
// position there (as it marks them): the targets a source cell meets, and their neighbours,
// then lie close in memory whatever the file's numbering (spatially arbitrary for TetGen
// meshes). The vertices stay in the mesh: copying them too made the pyramid x cube benchmark
// 2 % faster still, but doubled the memory first touched per call, which cost more than that
// on the development VM (about 12 us per page fault) for single runs and mid-sized meshes.
template <class Mesh>
struct TargetCell {
  using Dm = detail::Dim<Mesh>;
  // 3D: the conditioning, computed once (see src/kernel/one_to_many.hpp).
  std::conditional_t<Dm::d == 3, detail::Conditioning, std::monostate> conditioning;
  double measure;
  std::array<std::int32_t, Dm::nv> neighbors;  // positions of the neighbours across each facet, -1 none
  std::int32_t id;                              // the cell's index in the target mesh
  std::uint8_t risky_faces;                     // bit k: face k has no neighbour, or a flat one
};

// The same for a source cell, stored in the visiting order (Morton order of the centroids).
template <class Mesh>
struct SourceCell {
  using Dm = detail::Dim<Mesh>;
  double measure;
  std::array<std::int32_t, Dm::nv> neighbors;  // positions of the neighbours across each facet, -1 none
  std::int32_t id;                              // the cell's index in the source mesh
};

template <class Mesh>
struct Shared {
  using Dm = detail::Dim<Mesh>;
  const Mesh& source;
  const Mesh& target;
  const detail::PackedBoxTree<Dm::d>& tree;  // of the target cells' boxes, by position
  Box<Dm::d> target_bounds;  // the bounding box of all target cells
  bool keep_shapes;  // keep the polyhedra (polygons)
  bool keep_mass;    // keep each piece's local mixed mass matrix
  // A caller's consumer (supermesh(source, target, consumer, options)), or null: its numbers per
  // piece are computed here and kept, parallel to the pieces, until the merge hands them over.
  BasicPieceConsumer<typename Dm::Piece, typename Dm::Shape>* consumer;
  std::size_t values_per_piece;
  // The target cells in Morton order and the source cells in their visiting order; the front
  // and the R-tree name cells by their positions there, and pieces carry these positions until
  // the final merge, which writes the cells' indices.
  const std::vector<TargetCell<Mesh>>& targets;
  const std::vector<SourceCell<Mesh>>& sources;
  // Per source cell (position), written only by the thread that owns its chunk.
  std::vector<std::uint8_t>& state;  // 0 unvisited, 1 queued, 2 done
  std::vector<std::int32_t>& parent;
  std::vector<std::size_t>& piece_begin;  // into its worker's pieces
  std::vector<std::size_t>& piece_count;
  // Per target (position): its pieces found so far, on any thread (fetch_increment), so that the
  // merge knows where each target's pieces go.
  std::vector<std::uint32_t>& target_pieces;
  bool concurrent;  // more than one thread
};

// Per-thread work space, reused across chunks and cells. The pieces (and polyhedra, local mixed
// mass matrices) of all the chunks a thread runs stay in its own storage until the final merge.
template <class Mesh>
class Worker {
  using Dm = detail::Dim<Mesh>;
  using Cell = typename Dm::Cell;
  using Piece = typename Dm::Piece;
  using Shape = typename Dm::Shape;
  using LocalMass = typename Dm::LocalMass;

 public:
  // The pieces' storage is reserved for a typical count of all the pieces (between 2.6 and 9
  // per cell of both meshes in the benchmarks), not only this thread's share: address space
  // only until written, growing it by copying is then rare, and the merge can append the other
  // threads' pieces to it in place.
  explicit Worker(const Shared<Mesh>& sh) : sh_(sh), mark_(sh.targets.size(), 0), values_(sh.values_per_piece) {
    const std::size_t cells = sh.sources.size() + sh.targets.size();
    reserve_huge(pieces_, std::min<std::size_t>(10 * cells, std::size_t{1} << 26));
  }

  const std::vector<Piece>& pieces() const { return pieces_; }
  std::vector<Piece>& pieces() { return pieces_; }  // for the merge, once the search is done
  const std::vector<Shape>& shapes() const { return shapes_; }
  const std::vector<LocalMass>& local_mass() const { return mass_; }
  const double* values(std::size_t piece) const { return values_.at(piece); }
  // The first exception a consumer's compute() threw on this thread, if any.
  const std::exception_ptr& error() const { return error_; }

  void run_chunk(Chunk& ch, int id, CandidateSearch search) {
    ch.worker = id;
    ch.first = pieces_.size();
    candidates_ = 0;
    if (error_) {  // the consumer failed on this thread: nothing more is computed (see error())
      ch.last = ch.first;
      ch.candidates = 0;
      return;
    }
    if (search == CandidateSearch::rtree) {
      for (std::int32_t s = ch.begin; s < ch.end; ++s) {
        begin_cell(s);
        rtree_pass(s, false);
        end_cell(s);
      }
    } else {
      run_front(ch);
    }
    ch.last = pieces_.size();
    ch.candidates = candidates_;
  }

 private:
  // Is source cell n (or -1, no cell) in the chunk, a range of positions in the visiting order?
  static bool in_chunk(std::int32_t n, const Chunk& ch) { return n >= ch.begin && n < ch.end; }

  void run_front(const Chunk& ch) {
    queue_.clear();
    for (std::int32_t start = ch.begin; start < ch.end; ++start) {
      if (sh_.state[static_cast<std::size_t>(start)] != 0) continue;
      sh_.state[static_cast<std::size_t>(start)] = 1;
      sh_.parent[static_cast<std::size_t>(start)] = -1;
      queue_.push_back(start);
      for (std::size_t head = 0; head < queue_.size(); ++head) {
        const std::int32_t s = queue_[head];
        prefetch_ahead(sh_.source, sh_.sources, queue_, head + 1);
        process_front(s, ch);
        sh_.state[static_cast<std::size_t>(s)] = 2;
        for (const std::int32_t n : sh_.sources[static_cast<std::size_t>(s)].neighbors) {
          if (!in_chunk(n, ch) || sh_.state[static_cast<std::size_t>(n)] != 0) continue;
          sh_.state[static_cast<std::size_t>(n)] = 1;
          sh_.parent[static_cast<std::size_t>(n)] = s;
          queue_.push_back(n);
        }
      }
      queue_.clear();
    }
  }

  // mark_[t] == stamp_: queued for this source cell; stamp_ + 1: tested.
  void next_stamp() {
    if (stamp_ >= 0xFFFFFFF0u) {
      std::fill(mark_.begin(), mark_.end(), 0u);
      stamp_ = 0;
    }
    stamp_ += 2;
  }
  bool seen(std::int32_t t) const { return mark_[static_cast<std::size_t>(t)] >= stamp_; }
  // across: queued by the flood, across a face of a positive target that s crosses.
  void enqueue(std::int32_t t, bool across = false) {
    if (t < 0 || seen(t)) return;
    mark_[static_cast<std::size_t>(t)] = stamp_;
    cand_.push_back(t);
    across_.push_back(static_cast<std::uint8_t>(across));
  }

  // The kernel on (source cell, target cell), appending the piece if its volume is positive.
  bool test(std::int32_t s, std::int32_t t) {
    mark_[static_cast<std::size_t>(t)] = stamp_ + 1;
    crossed_ = 0xFu;
    const TargetCell<Mesh>& rec = sh_.targets[static_cast<std::size_t>(t)];
    T_ = target_cell(t);
    if (!overlap_open(sbox_, box_of<Mesh>(T_))) return false;
    ++candidates_;
    const double floor = kResolution * std::min(svol_, rec.measure);
    // Every entry point of the kernel gives the same moments bit for bit. In 3D what depends on
    // s or t alone is computed once (OneToMany), and the kernel's facets tell which faces of t
    // s may cross. The whole polyhedron (polygon) is needed where shapes, mixed mass matrices or
    // a consumer's numbers are: in 3D one full kernel call then, with the same facets; in 2D
    // the polygon, whose moments are the same bits.
    const bool shaped = sh_.keep_shapes || sh_.keep_mass || sh_.values_per_piece != 0;
    typename Dm::Moments m;
    if constexpr (Dm::d == 3) {
      if (!one_) one_.emplace(S_);  // on the first candidate: many cells (outside the target) have none
      m = shaped ? one_->intersect(T_, rec.conditioning, shape_, &crossed_) : one_->moments(T_, rec.conditioning, &crossed_);
    } else if (shaped) {
      shape_ = intersect(S_, T_);  // its moments are intersection_moments' bits
      m = shape_.moments();
    } else {
      m = intersection_moments(S_, T_);
    }
    if (!(Dm::measure(m) > floor)) return false;
    if (shaped) {
      if (sh_.values_per_piece != 0) {  // the consumer's numbers, from the piece with its cells' indices
        // An exception must not leave an OpenMP region: it is kept, and rethrown after it.
        double* values = values_.append();
        try {
          if (!error_) sh_.consumer->compute(Dm::piece(sh_.sources[static_cast<std::size_t>(s)].id, rec.id, m), shape_, values);
        } catch (...) {
          error_ = std::current_exception();
        }
      }
      if (sh_.keep_shapes) {
        reserve_for_one_more(shapes_);
        shapes_.push_back(shape_);
      }
      if (sh_.keep_mass) {
        reserve_for_one_more(mass_);
        mass_.emplace_back();
        detail::piece_mixed_mass<Mesh>(S_, shape_, mass_.back());
      }
    }
    reserve_for_one_more(pieces_);
    pieces_.push_back(Dm::piece(s, t, m));
    fetch_increment(sh_.target_pieces[static_cast<std::size_t>(t)], sh_.concurrent);
    covered_ += Dm::measure(m);
    return true;
  }

  // Asks the cache for what reading cell `id` of `mesh` will need: its vertex indices, or
  // (`nodes`) its vertices, whose indices should be cached by then. Cells are visited in Morton
  // order but their vertices lie in the file's order: without this, each cell read waits for
  // memory twice.
  static void prefetch_cell(const Mesh& mesh, std::int32_t id, bool nodes) {
    const auto& v = mesh.cells[static_cast<std::size_t>(id)];
    if (!nodes) {
      __builtin_prefetch(&v);
      return;
    }
    for (const std::int32_t n : v) __builtin_prefetch(&mesh.nodes[static_cast<std::size_t>(n)]);
  }
  // What the cells queue[next] and queue[next + 1] (positions in `records`, cells of `mesh`)
  // will read, where they exist: the vertices of the first, the indices of the second.
  template <class Records>
  static void prefetch_ahead(const Mesh& mesh, const Records& records, const std::vector<std::int32_t>& queue,
                             std::size_t next) {
    if (next + 1 < queue.size()) prefetch_cell(mesh, records[static_cast<std::size_t>(queue[next + 1])].id, false);
    if (next < queue.size()) prefetch_cell(mesh, records[static_cast<std::size_t>(queue[next])].id, true);
  }

  // The vertices of the target at position t.
  Cell target_cell(std::int32_t t) const {
    return sh_.target.cell(static_cast<std::size_t>(sh_.targets[static_cast<std::size_t>(t)].id));
  }

  // faces_crossed(T_, S_) for target t (in 3D through its map).
  unsigned plane_test(std::int32_t t) const {
    if constexpr (Dm::d == 3) return faces_crossed(T_, sh_.targets[static_cast<std::size_t>(t)].conditioning, S_);
    else return faces_crossed(T_, S_);
  }

  // Tests the queued candidates from cand_[head_] on; a positive one queues its neighbours
  // across the faces s may cross (the others lead to zero-volume neighbours, or no path inside s
  // crosses them). It does not stop at a risky face: the R-tree pass that may follow then tests
  // only what the flood has not.
  void flood(std::int32_t s) {
    while (head_ < cand_.size()) {
      prefetch_ahead(sh_.target, sh_.targets, cand_, head_ + 1);
      const bool across = across_[head_] != 0;
      const std::int32_t t = cand_[head_++];
      if (!test(s, t)) {
        cut_ |= across;  // queued across a face s crosses, yet zero: the flood may be cut here
        continue;
      }
      // The kernel's own certified signs (see OneToMany::moments), with the plane test where
      // they do not include it.
      const unsigned crossed = crossed_ & detail::OneToMany::kPlanesTested ? crossed_ & 0xFu
                                                                            : crossed_ & plane_test(t);
      const TargetCell<Mesh>& rec = sh_.targets[static_cast<std::size_t>(t)];
      if (crossed & rec.risky_faces) crossed_risky_ = true;
      const auto& nb = rec.neighbors;
      for (std::size_t k = 0; k < nb.size(); ++k)
        if (crossed >> k & 1u) enqueue(nb[k], true);
    }
  }

  // hits_: the targets whose bounding box overlaps s's (none, without a query, when s's box is
  // outside the target mesh's).
  void query_box() {
    hits_.clear();
    if (overlap_open(sbox_, sh_.target_bounds))
      sh_.tree.query(sbox_, [this](std::size_t t) { hits_.push_back(static_cast<std::int32_t>(t)); });
  }

  // Every target whose bounding box overlaps s's, not yet tested. With `filter` (the front's
  // fallback, near the target boundary, where most of them meet s with zero volume), in 3D not
  // those that lie beyond a face plane of s (separated_from_s: their intersection is empty).
  // The plain R-tree search tests every one: there most meet s, and the filter costs more than
  // it saves (10 % slower at 10^6 cells).
  void rtree_pass(std::int32_t s, bool filter) {
    query_box();
    for (const std::int32_t h : hits_) {
      if (mark_[static_cast<std::size_t>(h)] == stamp_ + 1) continue;
      if constexpr (Dm::d == 3) {
        if (filter && separated_from_s(h)) continue;
      }
      test(s, h);
    }
  }

  // For an s whose flood crossed a risky face: the targets with a risky face whose bounding box
  // overlaps s's, not yet tested, each a seed for a flood (see "Why this finds every pair"). The
  // argument needs only targets with a risky face that meets the interior of s; in 3D those whose
  // risky faces all lie outside s (risky_faces_outside) are left out.
  void risky_pass(std::int32_t s) {
    query_box();
    for (const std::int32_t h : hits_) {
      const unsigned risky = sh_.targets[static_cast<std::size_t>(h)].risky_faces;
      if (!risky || seen(h)) continue;
      if constexpr (Dm::d == 3) {
        if (risky_faces_outside(h, risky)) continue;
      }
      enqueue(h);
    }
    flood(s);
  }

  // 3D: is each face of target t in `faces` outside s, certainly? Face k of t is, when its three
  // vertices have a common negative barycentric coordinate of s (negative_coordinates): the
  // triangle then lies in the open half-space beyond one of s's face planes.
  bool risky_faces_outside(std::int32_t t, unsigned faces) {
    unsigned negative[4];
    if (!negative_coordinates(t, negative)) return false;
    for (std::size_t k = 0; k < 4; ++k) {
      if (!(faces >> k & 1u)) continue;
      unsigned common = 0xFu;  // over the face's vertices (all but k)
      for (std::size_t i = 0; i < 4; ++i)
        if (i != k) common &= negative[i];
      if (!common) return false;
    }
    return true;
  }

  // 3D: does target t lie beyond a face plane of s, certainly (its four vertices have a common
  // negative barycentric coordinate of s)? Then s n t is empty.
  bool separated_from_s(std::int32_t t) {
    unsigned negative[4];
    return negative_coordinates(t, negative) && (negative[0] & negative[1] & negative[2] & negative[3]) != 0;
  }

  // 3D: bit p of negative[i]: barycentric coordinate p of s at t's vertex i is negative. The
  // signs come from s's barycentric map, the one OneToMany keeps (made here if no candidate was
  // tested yet), certain when the sign of s's determinant is (kSignCertainQuality): its
  // snapping leaves a coordinate within rounding of 0 at exactly 0. Returns false, and nothing,
  // when they are not.
  bool negative_coordinates(std::int32_t t, unsigned (&negative)[4]) {
    if (!one_) one_.emplace(S_);
    if (!one_->signs_certain()) return false;
    const Cell T = target_cell(t);
    for (std::size_t i = 0; i < 4; ++i) {
      double c[4];
      one_->map()(T[i], c);
      negative[i] = unsigned(c[0] < 0.0) | unsigned(c[1] < 0.0) << 1 | unsigned(c[2] < 0.0) << 2 | unsigned(c[3] < 0.0) << 3;
    }
    return true;
  }

  void begin_cell(std::int32_t s) {
    next_stamp();
    cand_.clear();
    across_.clear();
    cut_ = false;
    head_ = 0;
    crossed_risky_ = false;
    covered_ = 0.0;
    const SourceCell<Mesh>& rec = sh_.sources[static_cast<std::size_t>(s)];
    S_ = sh_.source.cell(static_cast<std::size_t>(rec.id));
    if constexpr (Dm::d == 3) one_.reset();
    svol_ = rec.measure;
    sbox_ = box_of<Mesh>(S_);
    sh_.piece_begin[static_cast<std::size_t>(s)] = pieces_.size();
  }
  void end_cell(std::int32_t s) {
    sh_.piece_count[static_cast<std::size_t>(s)] = pieces_.size() - sh_.piece_begin[static_cast<std::size_t>(s)];
  }

  // Queues the targets of processed source cell q and their neighbours.
  void enqueue_targets_of(std::int32_t q) {
    const std::size_t b = sh_.piece_begin[static_cast<std::size_t>(q)];
    const std::size_t e = b + sh_.piece_count[static_cast<std::size_t>(q)];
    for (std::size_t i = b; i < e; ++i) {
      const std::int32_t t = pieces_[i].target;
      enqueue(t);
      for (const std::int32_t n : sh_.targets[static_cast<std::size_t>(t)].neighbors) enqueue(n);
    }
  }

  // The flood found pieces (after `first`), crossed a risky face and was not cut.
  bool component_found(std::size_t first) const { return pieces_.size() > first && crossed_risky_ && !cut_; }

  void process_front(std::int32_t s, const Chunk& ch) {
    begin_cell(s);
    const std::size_t first = pieces_.size();
    const std::int32_t p = sh_.parent[static_cast<std::size_t>(s)];
    const double full = (1.0 - kCoverageTolerance) * svol_;
    const auto covered = [&] { return pieces_.size() > first && covered_ >= full; };
    bool complete = false;
    if (p >= 0) {
      // Step 1: the parent's targets, one at a time until the flood from the positive ones
      // covers s (many of them do not meet s: not testing them saves kernel calls). First those
      // whose box holds the centre of s's box, the likeliest to meet s. A flood that found
      // pieces, crossed a risky face and was not cut has found its component, and step 3's
      // risky search finds any other (below): seeding stops there too, which spares a cell
      // the target boundary cuts (never covered) the rest of its parent's targets.
      const std::size_t b = sh_.piece_begin[static_cast<std::size_t>(p)];
      const std::size_t e = b + sh_.piece_count[static_cast<std::size_t>(p)];
      std::array<double, Dm::d> centre;
      for (std::size_t k = 0; k < Dm::d; ++k) centre[k] = 0.5 * (sbox_.lo[k] + sbox_.hi[k]);
      for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t i = b; i < e && !complete && !component_found(first); ++i) {
          const std::int32_t t = pieces_[i].target;  // by index: test() appends to pieces_
          if (seen(t)) continue;
          if (pass == 0) {
            const auto tb = box_of<Mesh>(target_cell(t));
            bool holds = true;
            for (std::size_t k = 0; k < Dm::d; ++k) holds &= unsigned(tb.lo[k] <= centre[k]) & unsigned(centre[k] <= tb.hi[k]);
            if (!holds) continue;
          }
          enqueue(t);
          flood(s);
          complete = covered();
        }
      }
      // A flood that crossed a risky face, and was not cut, has found its component (below).
      if (!complete && !(crossed_risky_ && !cut_)) {
        // Step 2: all processed neighbours' targets and their neighbours.
        for (const std::int32_t q : sh_.sources[static_cast<std::size_t>(s)].neighbors)
          if (in_chunk(q, ch) && sh_.state[static_cast<std::size_t>(q)] == 2) enqueue_targets_of(q);
        flood(s);
        complete = covered();
      }
    }
    // Step 3: at risk. A flood that crossed a risky face and was not cut (or covered s): only
    // the other components of O can hold pieces, and each holds a target with a risky face.
    // Otherwise, not covered: every candidate.
    if (crossed_risky_ && (complete || !cut_)) risky_pass(s);
    else if (!complete) rtree_pass(s, true);
    end_cell(s);
  }

  const Shared<Mesh>& sh_;
  std::vector<std::uint32_t> mark_;
  std::uint32_t stamp_ = 0;
  std::vector<std::int32_t> cand_, queue_;
  std::vector<std::uint8_t> across_;  // parallel to cand_: see enqueue
  bool cut_ = false;                   // a candidate queued across a crossed face tested zero
  std::size_t head_ = 0;
  std::vector<std::int32_t> hits_;  // positions of targets
  std::vector<Piece> pieces_;
  std::vector<Shape> shapes_;
  std::vector<LocalMass> mass_;  // parallel to pieces_ when kept
  PieceValues values_;           // a consumer's values_per_piece numbers per piece, parallel to pieces_
  std::exception_ptr error_;     // see error()
  std::size_t candidates_ = 0;
  bool crossed_risky_ = false;  // a positive target's risky face crossed by s (flood)
  double covered_ = 0.0;  // volume of s's pieces found so far
  Cell S_{};
  Cell T_{};  // the target cell last tested
  Box<Dm::d> sbox_{};
  double svol_ = 0.0;
  Shape shape_;
  unsigned crossed_ = 0xFu;  // faces of T_ that S_ may meet, as the kernel knew (OneToMany::moments)
  // 3D: the source cell prepared for intersection_moments with many targets (its map also serves
  // negative_coordinates), made on first use.
  std::conditional_t<Dm::d == 3, std::optional<detail::OneToMany>, std::monostate> one_;
};

// The cells of a mesh by the Morton code of their centroids (63 / d bits per axis, 21 in 3D
// and 31 in 2D) in the bounding box of the mesh's nodes; `rank` is its inverse. The codes are
// computed on `threads` threads (each reads its cell's nodes: cache misses in a file's order).
template <class Mesh>
void morton_order(const Mesh& mesh, std::vector<std::int32_t>& order, std::vector<std::int32_t>& rank, int threads) {
  using Dm = detail::Dim<Mesh>;
  constexpr int d = Dm::d;
  const std::size_t ns = mesh.num_cells();
  Box<d> all;
  for (std::size_t k = 0; k < d; ++k) all.lo[k] = all.hi[k] = Dm::coord(mesh.nodes[0], static_cast<int>(k));
  for (const auto& p : mesh.nodes)
    for (std::size_t k = 0; k < d; ++k) {
      const double x = Dm::coord(p, static_cast<int>(k));
      all.lo[k] = x < all.lo[k] ? x : all.lo[k];
      all.hi[k] = all.hi[k] < x ? x : all.hi[k];
    }
  std::vector<std::pair<std::uint64_t, std::int32_t>> keys(ns);
  const auto ns_i = static_cast<std::int64_t>(ns);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t i = 0; i < ns_i; ++i) {
    const auto c = static_cast<std::size_t>(i);
    const auto t = mesh.cell(c);
    double centre[d];
    for (int k = 0; k < d; ++k) {
      double sum = Dm::coord(t[0], k);
      for (std::size_t v = 1; v < t.size(); ++v) sum += Dm::coord(t[v], k);
      centre[k] = (1.0 / static_cast<double>(t.size())) * sum;
    }
    keys[c] = {detail::morton_code<d>(centre, all.lo.data(), all.hi.data()), static_cast<std::int32_t>(c)};
  }
  detail::sort_by_key(keys);
  order.resize(ns);
  rank.resize(ns);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t i = 0; i < ns_i; ++i) {
    const auto k = static_cast<std::size_t>(i);
    order[k] = keys[k].second;
    rank[static_cast<std::size_t>(keys[k].second)] = static_cast<std::int32_t>(i);
  }
}

template <class Mesh>
typename detail::Dim<Mesh>::Result build(
    std::shared_ptr<const Mesh> source_mesh, std::shared_ptr<const Mesh> target_mesh, const SupermeshOptions& options,
    BasicPieceConsumer<typename detail::Dim<Mesh>::Piece, typename detail::Dim<Mesh>::Shape>* consumer = nullptr,
    std::size_t* pieces_handed = nullptr) {
  using Dm = detail::Dim<Mesh>;
  if (!source_mesh || !target_mesh) throw std::invalid_argument("tetia: supermesh: a mesh is null");
  const auto t0 = std::chrono::steady_clock::now();
  typename Dm::Result out;
  out.source = std::move(source_mesh);
  out.target = std::move(target_mesh);
  const Mesh& source = *out.source;
  const Mesh& target = *out.target;
  const std::size_t ns = source.num_cells(), nt = target.num_cells();
  if (ns == 0 || nt == 0) return out;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();

  // The target records in Morton order, and the R-tree of their boxes packed in that order.
  std::vector<TargetCell<Mesh>> targets;
  std::vector<Box<Dm::d>> boxes;  // by position
  reserve_touched(targets, nt, threads);
  reserve_touched(boxes, nt, threads);
  targets.resize(nt);
  boxes.resize(nt);
  const auto nt_i = static_cast<std::int64_t>(nt);
  {
    std::vector<std::int32_t> torder, trank;
    morton_order(target, torder, trank, threads);
    const auto& target_measures = Dm::measures(target);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::int64_t i = 0; i < nt_i; ++i) {
      const auto t = static_cast<std::size_t>(torder[static_cast<std::size_t>(i)]);
      TargetCell<Mesh>& rec = targets[static_cast<std::size_t>(i)];
      const auto cell = target.cell(t);
      boxes[static_cast<std::size_t>(i)] = box_of<Mesh>(cell);
      unsigned r = 0;
      for (std::size_t k = 0; k < target.neighbors[t].size(); ++k) {
        const std::int32_t n = target.neighbors[t][k];
        r |= unsigned(n < 0 || !(target_measures[static_cast<std::size_t>(n)] > 0.0)) << k;
        rec.neighbors[k] = n < 0 ? -1 : trank[static_cast<std::size_t>(n)];
      }
      rec.risky_faces = static_cast<std::uint8_t>(r);
      rec.measure = target_measures[t];
      rec.id = static_cast<std::int32_t>(t);
    }
    if constexpr (Dm::d == 3) {  // two at a time (both lanes of shape_qualities)
#pragma omp parallel for schedule(static) num_threads(threads)
      for (std::int64_t i = 0; i < nt_i; i += 2) {
        const auto a = static_cast<std::size_t>(i), b = std::min(a + 1, nt - 1);
        detail::conditioning(target.cell(static_cast<std::size_t>(targets[a].id)),
                             target.cell(static_cast<std::size_t>(targets[b].id)), targets[a].conditioning,
                             targets[b].conditioning);
      }
    }
  }
  const detail::PackedBoxTree<Dm::d> tree(boxes);
  boxes = {};

  // Source cells are visited along a space-filling (Morton) curve through their centroids, so
  // that a chunk is a compact region whatever the file's numbering (Gmsh numbers cells in no
  // spatial order; with chunks of consecutive indices the front then degenerates into R-tree
  // queries). The order depends on the mesh only: results stay identical for any thread count.
  std::vector<SourceCell<Mesh>> sources;
  reserve_touched(sources, ns, threads);
  sources.resize(ns);
  std::vector<std::int32_t> source_position;  // of each source cell in that order
  {
    std::vector<std::int32_t> order;
    morton_order(source, order, source_position, threads);
    const auto ns_i = static_cast<std::int64_t>(ns);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::int64_t i = 0; i < ns_i; ++i) {
      const auto c = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
      SourceCell<Mesh>& rec = sources[static_cast<std::size_t>(i)];
      rec.measure = Dm::measures(source)[c];
      for (std::size_t k = 0; k < rec.neighbors.size(); ++k) {
        const std::int32_t n = source.neighbors[c][k];
        rec.neighbors[k] = n < 0 ? -1 : source_position[static_cast<std::size_t>(n)];
      }
      rec.id = static_cast<std::int32_t>(c);
    }
  }
  std::vector<std::uint8_t> state(ns, 0);
  std::vector<std::int32_t> parent(ns, -1);
  std::vector<std::size_t> piece_begin(ns, 0), piece_count(ns, 0);
  std::vector<std::uint32_t> target_pieces(nt, 0);
  const std::size_t values_per_piece = consumer ? consumer->values_per_piece() : 0;
  const Shared<Mesh> sh{source,    target, tree,  tree.bounds(), options.keep_polyhedra, options.keep_mixed_mass,
                        consumer,  values_per_piece, targets, sources, state, parent, piece_begin, piece_count,
                        target_pieces, threads > 1};

  // Chunks of consecutive positions in that order; their number depends on the mesh only.
  constexpr std::size_t kChunkCells = 4096;
  const std::size_t nchunks = std::clamp<std::size_t>((ns + kChunkCells - 1) / kChunkCells, 1, 1024);
  std::vector<Chunk> chunks(nchunks);
  for (std::size_t c = 0; c < nchunks; ++c) {
    chunks[c].begin = static_cast<std::int32_t>(ns * c / nchunks);
    chunks[c].end = static_cast<std::int32_t>(ns * (c + 1) / nchunks);
  }
  const auto nchunks_i = static_cast<std::int64_t>(nchunks);
  std::vector<std::unique_ptr<Worker<Mesh>>> workers(static_cast<std::size_t>(threads));
  // An exception must not leave an OpenMP region (it would terminate the process): what a
  // thread throws (std::bad_alloc as its pieces grow, the progress callback's) is kept, the
  // thread computes nothing more, and the first is rethrown after the region.
  std::vector<std::exception_ptr> thread_errors(static_cast<std::size_t>(threads));
  std::atomic<std::size_t> done{0};  // source cells finished, for options.progress
#pragma omp parallel num_threads(threads)
  {
    const int id = omp_get_thread_num();
    auto& w = workers[static_cast<std::size_t>(id)];
    std::exception_ptr& error = thread_errors[static_cast<std::size_t>(id)];
    try {
      w = std::make_unique<Worker<Mesh>>(sh);
    } catch (...) {
      error = std::current_exception();
    }
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t c = 0; c < nchunks_i; ++c) {
      if (error) continue;  // every chunk is still taken by some thread; none of this one's runs
      try {
        const Chunk& ch = chunks[static_cast<std::size_t>(c)];
        w->run_chunk(chunks[static_cast<std::size_t>(c)], id, options.search);
        if (options.progress) {
          const std::size_t now = done.fetch_add(static_cast<std::size_t>(ch.end - ch.begin)) +
                                  static_cast<std::size_t>(ch.end - ch.begin);
          if (id == 0) options.progress(now, ns);  // the caller's thread only: never concurrent
        }
      } catch (...) {
        error = std::current_exception();
      }
    }
  }
  for (const auto& e : thread_errors)
    if (e) std::rethrow_exception(e);
  for (const auto& w : workers)  // the first thread's whose consumer failed, once every thread is done
    if (w && w->error()) std::rethrow_exception(w->error());
  if (options.progress) options.progress(ns, ns);

  // The merge, sorted by (target, source), in parallel, reading each thread's storage once and
  // in order. Each target's pieces were counted as they were found, so its range in the result
  // is known; every piece then gets its cells' indices and is put in its target's range (at the
  // range's next place, fetch_increment): the piece itself where only the pieces are
  // kept, otherwise an 8 B reference to it (its source's index, its number among all pieces),
  // through which the polyhedra, local mixed mass matrices or consumer's numbers follow. Each
  // range is then sorted by source. A piece is the only one of its pair of cells, so the order
  // does not depend on the threads that found the pieces.
  std::vector<std::size_t> base(workers.size() + 1, 0);  // of each thread's pieces, numbered together
  for (const Chunk& ch : chunks) out.candidates += ch.candidates;
  for (std::size_t w = 0; w < workers.size(); ++w)
    base[w + 1] = base[w] + (workers[w] ? workers[w]->pieces().size() : 0);
  const std::size_t total = base.back();
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("tetia: supermesh: more than 2^32 - 1 pieces");
  std::vector<std::uint32_t> offset(nt + 1, 0);  // of target t's (by index) pieces in the result
  for (std::size_t t = 0; t < nt; ++t) offset[static_cast<std::size_t>(targets[t].id) + 1] = target_pieces[t];
  for (std::size_t t = 0; t < nt; ++t) offset[t + 1] += offset[t];
  for (std::size_t t = 0; t < nt; ++t) target_pieces[t] = offset[static_cast<std::size_t>(targets[t].id)];  // next place
  const bool refer = consumer || options.keep_polyhedra || options.keep_mixed_mass;
  struct Ref {
    std::int32_t source;  // the piece's source cell
    std::uint32_t piece;  // its number: base[w] + its index in thread w's storage
  };
  std::vector<Ref> refs;
  if (refer) {
    reserve_touched(refs, total, threads);
    refs.resize(total);
  } else {
    reserve_touched(out.pieces, total, threads);
    out.pieces.resize(total);
  }
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::int64_t c = 0; c < nchunks_i; ++c) {
    const Chunk& ch = chunks[static_cast<std::size_t>(c)];
    auto& pcs = workers[static_cast<std::size_t>(ch.worker)]->pieces();
    for (std::size_t i = ch.first; i < ch.last; ++i) {
      typename Dm::Piece& piece = pcs[i];
      const auto t = static_cast<std::size_t>(piece.target);
      const std::uint32_t k = fetch_increment(target_pieces[t], threads > 1);
      piece.source = sources[static_cast<std::size_t>(piece.source)].id;
      piece.target = targets[t].id;
      if (refer) refs[k] = Ref{piece.source, static_cast<std::uint32_t>(base[static_cast<std::size_t>(ch.worker)] + i)};
      else out.pieces[k] = piece;
    }
  }
  target_pieces = {};
  const auto by_source = [](const auto& a, const auto& b) { return a.source < b.source; };
#pragma omp parallel for schedule(dynamic, 4096) num_threads(threads)
  for (std::int64_t t = 0; t < nt_i; ++t) {
    const std::size_t b = offset[static_cast<std::size_t>(t)], e = offset[static_cast<std::size_t>(t) + 1];
    if (refer) sort_small(refs.begin() + b, refs.begin() + e, by_source);
    else sort_small(out.pieces.begin() + b, out.pieces.begin() + e, by_source);
  }
  offset = {};
  if (!refer) {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  const auto worker_of = [&](const Ref& r) {  // the thread whose storage holds r's piece, and its index there
    std::size_t w = 0;
    while (base[w + 1] <= r.piece) ++w;
    return std::pair<Worker<Mesh>&, std::size_t>(*workers[w], r.piece - base[w]);
  };
  if (consumer) {  // handed over in (target, source) order, from this thread; nothing kept
    for (const Ref& r : refs) {
      const auto [w, i] = worker_of(r);
      consumer->consume(w.pieces()[i], values_per_piece != 0 ? w.values(i) : nullptr);
    }
    if (pieces_handed) *pieces_handed = total;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  reserve_touched(out.pieces, total, threads);
  out.pieces.resize(total);
  auto& mass = Dm::local_mass(out);
  if (options.keep_mixed_mass) {
    reserve_touched(mass, total, threads);
    mass.resize(total);
  }
  const bool gather_mass = options.keep_mixed_mass;
  const auto total_i = static_cast<std::int64_t>(total);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t k = 0; k < total_i; ++k) {
    const auto [w, i] = worker_of(refs[static_cast<std::size_t>(k)]);
    out.pieces[static_cast<std::size_t>(k)] = w.pieces()[i];
    if (gather_mass) mass[static_cast<std::size_t>(k)] = w.local_mass()[i];
  }
  if (options.keep_polyhedra) {
    auto& shapes = Dm::shapes(out);
    reserve_huge(shapes, total);
    for (const Ref& r : refs) {
      const auto [w, i] = worker_of(r);
      shapes.push_back(w.shapes()[i]);
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

Supermesh supermesh(std::shared_ptr<const TetMesh> source, std::shared_ptr<const TetMesh> target,
                    const SupermeshOptions& options) {
  return build(std::move(source), std::move(target), options);
}

Supermesh supermesh(const TetMesh& source, const TetMesh& target, const SupermeshOptions& options) {
  return build(std::make_shared<const TetMesh>(source), std::make_shared<const TetMesh>(target), options);
}

Supermesh2 supermesh(std::shared_ptr<const TriMesh> source, std::shared_ptr<const TriMesh> target,
                     const SupermeshOptions& options) {
  return build(std::move(source), std::move(target), options);
}

Supermesh2 supermesh(const TriMesh& source, const TriMesh& target, const SupermeshOptions& options) {
  return build(std::make_shared<const TriMesh>(source), std::make_shared<const TriMesh>(target), options);
}

namespace {

template <class Mesh, class Consumer>
SupermeshSummary build_for(const Mesh& source, const Mesh& target, Consumer& consumer, const SupermeshOptions& options) {
  if (options.keep_polyhedra || options.keep_mixed_mass)
    throw std::invalid_argument(
        "tetia: supermesh: a supermesh handed to a consumer keeps nothing: keep_polyhedra and keep_mixed_mass must be "
        "false (the consumer computes what it needs from each piece's polyhedron)");
  // Borrowed, not owned: the result is not kept, and the meshes outlive this call.
  const std::shared_ptr<const Mesh> src(std::shared_ptr<const Mesh>(), &source), tgt(std::shared_ptr<const Mesh>(), &target);
  std::size_t pieces = 0;
  const auto r = build(src, tgt, options, &consumer, &pieces);
  return {pieces, r.candidates, r.seconds};
}

}  // namespace

SupermeshSummary supermesh(const TetMesh& source, const TetMesh& target, PieceConsumer& consumer,
                           const SupermeshOptions& options) {
  return build_for(source, target, consumer, options);
}

SupermeshSummary supermesh(const TriMesh& source, const TriMesh& target, PieceConsumer2& consumer,
                           const SupermeshOptions& options) {
  return build_for(source, target, consumer, options);
}

}  // namespace tetia
