// bench/bench_supermesh.cpp -- how fast tetia::supermesh intersects two tetrahedral meshes, and
// how much memory it needs; the numbers behind "Supermesh (mesh-mesh intersection)" in
// docs/benchmarks.md. A plain program that prints tables (no Google Benchmark: one call is a
// whole mesh, seconds long for the big cases).
//
//   Part "pyramid": libsupermesh's own test case, lsm_pyramid_0_05.msh (33,901 cells) against
//     lsm_cube_0_05.msh (41,063 cells) from the shared extdata folder (skipped if absent); the
//     intersection has volume 1/3, checked to 1e-12.
//   Part "boxes": pairs of non-matching Gmsh meshes of the unit cube, the source at element size
//     h and the target at h / 1.07 (so about 1.2 times as many cells), for about 10^3, 10^4,
//     10^5 and 10^6 source cells; the intersection has volume 1, checked to 1e-12 relative.
//     Generated meshes are cached as .msh files (default: a folder in the build directory).
//   Part "rect2d": the 2D counterpart (triangular meshes, the same supermesh code): pairs of
//     non-matching Gmsh meshes of the unit square, the target at h / 1.07, for about 10^4, 10^5
//     and 10^6 source triangles; the intersection has area 1, checked to 1e-12 relative. File
//     order only (--order is ignored). Not part of the default run: ask for it with --parts.
//   Part "p1": what P1 remap needs kept, SupermeshOptions::keep_mixed_mass (each piece's local
//     mixed mass matrix, 128 B) against keep_polyhedra (each piece's Polyhedron, 2,216 B), on
//     pyramid x cube and on the box levels up to --max-cells, file order, front search, each
//     thread count: supermesh wall and CPU time (best of --reps), its peak memory (first run,
//     result alive), then remap_p1 of sin(3x) cos(2y) exp(z) from that result (one run; its
//     time and peak over what was resident before it, the supermesh included); for
//     reference also the supermesh keeping neither (pieces only: what P0 needs). "streamed" is
//     P1 remap without keeping the supermesh (tetia::P1Loads handed the pieces, then
//     tetia::solve_p1): the supermesh's time and peak with the loads alive, then the solve's.
//     Every way must give the same remapped values bit for bit (else exit 1). Not part of the
//     default run: --parts=p1 (with --max-cells=1e5 for pyramid x cube and boxes to 10^5);
//     --kept=none,streamed,mixed_mass,polyhedra chooses the ways (default all).
//
// Each case runs front and R-tree search on 1 and 2 threads, best wall time of --reps runs (one
// run only once a run takes more than --long seconds). For each it prints wall and CPU time
// (process CPU time: with 2 threads CPU is about twice wall when both threads are busy),
// kernel calls (candidates) and pieces per second of wall time, time per source cell, and the
// memory the call needs at its peak over what was resident before it (Linux: VmHWM reset
// through /proc/self/clear_refs; the result stays alive until the peak is read, so its pieces
// are included), per cell of both meshes and per piece. Results must be identical bit for bit
// between the searches and thread counts; a mismatch or a wrong volume makes the program exit
// with 1.
//
// Usage: bench_supermesh [--max-cells=N] [--reps=R] [--long=S] [--parts=pyramid,boxes,rect2d,p1]
//                        [--order=file,morton] [--threads=1,2] [--extdata=DIR] [--cache=DIR]
//   --max-cells  skip box levels with more than N source cells (nominal: 10^3 ... 10^6);
//                default 1000000
//   --reps       runs per configuration, the fastest is kept (default 3)
//   --long       a configuration whose first run takes longer than S seconds is run once
//                (default 10)
//   --order      cell order of the meshes: "file" as read or generated (Gmsh numbers cells in
//                no spatial order), "morton": both meshes' cells sorted by the Morton code of
//                their centroids in the common bounding box, nodes renumbered by first use
//                (the sort is done here, before timing, and its time printed); default both
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <time.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

#include "../src/morton.hpp"  // the library's bit spreading (internal)

#ifndef TETIA_SHARED_DIR
#define TETIA_SHARED_DIR "../shared"
#endif
#ifndef TETIA_BENCH_CACHE_DIR
#define TETIA_BENCH_CACHE_DIR "supermesh-meshes"
#endif

namespace fs = std::filesystem;

namespace {

// The meshes outlive every supermesh timed here: it borrows them (a shared pointer owning
// nothing), so that the times are the supermesh's and not a copy's.
template <class Mesh>
std::shared_ptr<const Mesh> borrow(const Mesh& mesh) {
  return std::shared_ptr<const Mesh>(std::shared_ptr<const Mesh>(), &mesh);
}

struct Options {
  std::size_t max_cells = 1000000;
  int reps = 3;
  double long_run = 10.0;
  bool pyramid = true, boxes = true, rect2d = false, p1 = false;
  std::vector<std::string> kept{"none", "streamed", "mixed_mass", "polyhedra"};  // part p1
  bool file_order = true, morton_order = true;
  std::vector<int> threads{1, 2};
  fs::path extdata = fs::path(TETIA_SHARED_DIR) / "extdata";
  fs::path cache = TETIA_BENCH_CACHE_DIR;
};

[[noreturn]] void usage(const char* msg) {
  std::fprintf(stderr,
               "bench_supermesh: %s\nusage: bench_supermesh [--max-cells=N] [--reps=R] [--long=S] "
               "[--parts=pyramid,boxes,rect2d,p1] [--order=file,morton] [--threads=1,2] [--extdata=DIR] [--cache=DIR]\n"
               "       [--kept=none,streamed,mixed_mass,polyhedra]\n",
               msg);
  std::exit(2);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    const std::string key = a.substr(0, eq), val = eq == std::string::npos ? "" : a.substr(eq + 1);
    if (eq == std::string::npos || val.empty()) usage(("bad argument " + a).c_str());
    try {
      if (key == "--max-cells") {
        o.max_cells = static_cast<std::size_t>(std::stod(val));
      } else if (key == "--reps") {
        o.reps = std::max(1, std::stoi(val));
      } else if (key == "--long") {
        o.long_run = std::stod(val);
      } else if (key == "--parts") {
        o.pyramid = o.boxes = o.rect2d = o.p1 = false;
        for (const auto& p : split(val)) {
          if (p == "pyramid") o.pyramid = true;
          else if (p == "boxes") o.boxes = true;
          else if (p == "rect2d") o.rect2d = true;
          else if (p == "p1") o.p1 = true;
          else usage(("unknown part " + p).c_str());
        }
      } else if (key == "--order") {
        o.file_order = o.morton_order = false;
        for (const auto& p : split(val)) {
          if (p == "file") o.file_order = true;
          else if (p == "morton") o.morton_order = true;
          else usage(("unknown order " + p).c_str());
        }
      } else if (key == "--threads") {
        o.threads.clear();
        for (const auto& t : split(val)) o.threads.push_back(std::max(1, std::stoi(t)));
        if (o.threads.empty()) usage("no thread counts");
      } else if (key == "--kept") {
        o.kept = split(val);
        for (const auto& k : o.kept)
          if (k != "none" && k != "streamed" && k != "mixed_mass" && k != "polyhedra") usage(("unknown kept " + k).c_str());
      } else if (key == "--extdata") {
        o.extdata = val;
      } else if (key == "--cache") {
        o.cache = val;
      } else {
        usage(("unknown option " + key).c_str());
      }
    } catch (const std::logic_error&) {
      usage(("bad value in " + a).c_str());
    }
  }
  return o;
}

// --- clocks and memory ------------------------------------------------------------------------

double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double cpu_now() {  // CPU time of the whole process, all threads
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// A field of /proc/self/status in bytes (-1 when unavailable: not Linux).
long long proc_status_bytes(const char* field) {
  std::ifstream in("/proc/self/status");
  const std::size_t n = std::strlen(field);
  for (std::string line; std::getline(in, line);)
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':')
      return 1024LL * std::atoll(line.c_str() + n + 1);
  return -1;
}

// A field of /proc/meminfo in bytes (-1 when unavailable).
long long meminfo_bytes(const char* field) {
  std::ifstream in("/proc/meminfo");
  const std::size_t n = std::strlen(field);
  for (std::string line; std::getline(in, line);)
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':')
      return 1024LL * std::atoll(line.c_str() + n + 1);
  return -1;
}

// Returns free heap memory to the system and resets the peak (VmHWM) to the current resident
// size, so that the peak read after a call belongs to that call. False if the reset failed.
bool reset_peak_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
  std::ofstream f("/proc/self/clear_refs");
  if (!f) return false;
  f << "5";
  f.close();
  return static_cast<bool>(f);
}

// --- the measurement --------------------------------------------------------------------------

const char* search_name(tetia::CandidateSearch s) { return s == tetia::CandidateSearch::front ? "front" : "rtree"; }

// A fingerprint of the result, compared between searches and thread counts (bit for bit).
struct Fingerprint {
  std::size_t pieces = 0, candidates = 0;
  std::uint64_t hash = 0;
  double volume = 0.0;
  bool operator==(const Fingerprint&) const = default;
};

double piece_measure(const tetia::SupermeshPiece& p) { return p.volume; }
double piece_measure(const tetia::SupermeshPiece2& p) { return p.area; }
double total_measure(const tetia::Supermesh& s) { return s.intersection_volume(); }
double total_measure(const tetia::Supermesh2& s) { return s.intersection_area(); }

// 3D or 2D alike (`volume` is the area in 2D).
template <class Result>
Fingerprint fingerprint(const Result& s) {
  Fingerprint f;
  f.pieces = s.pieces.size();
  f.candidates = s.candidates;
  f.volume = total_measure(s);
  std::uint64_t h = 1469598103934665603ULL;
  const auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ULL; };
  for (const auto& p : s.pieces) {
    std::uint64_t bits;
    const double m = piece_measure(p);
    std::memcpy(&bits, &m, sizeof bits);
    mix(static_cast<std::uint32_t>(p.source));
    mix(static_cast<std::uint32_t>(p.target));
    mix(bits);
  }
  f.hash = h;
  return f;
}

struct Row {
  std::string label;
  std::size_t ns = 0, nt = 0;
  tetia::CandidateSearch search{};
  int threads = 1;
  int runs = 0;
  double wall = 0.0, cpu = 0.0;  // of the fastest run
  double wall_median = 0.0;
  long long peak_extra = -1;  // bytes over the resident size before the call (first run)
  Fingerprint fp;
};

template <class Mesh>
Row measure(const std::string& label, const Mesh& src, const Mesh& tgt, tetia::CandidateSearch search, int threads,
            const Options& o) {
  Row r;
  r.label = label;
  r.ns = src.num_cells();
  r.nt = tgt.num_cells();
  r.search = search;
  r.threads = threads;
  tetia::SupermeshOptions opt;
  opt.search = search;
  opt.threads = threads;
  std::vector<double> walls;
  for (int rep = 0; rep < o.reps; ++rep) {
    const bool first = rep == 0;
    long long before = -1;
    if (first && reset_peak_memory()) before = proc_status_bytes("VmRSS");
    const double w0 = wall_now(), c0 = cpu_now();
    const auto s = tetia::supermesh(borrow(src), borrow(tgt), opt);  // timed without copying the meshes
    const double w = wall_now() - w0, c = cpu_now() - c0;
    if (first) {
      const long long peak = proc_status_bytes("VmHWM");
      if (before >= 0 && peak >= 0) r.peak_extra = peak - before;
      r.fp = fingerprint(s);
    }
    walls.push_back(w);
    if (walls.size() == 1 || w < r.wall) {
      r.wall = w;
      r.cpu = c;
    }
    if (first && w > o.long_run) break;
  }
  r.runs = static_cast<int>(walls.size());
  std::sort(walls.begin(), walls.end());
  r.wall_median = walls[walls.size() / 2];
  return r;
}

void print_header() {
  std::printf("%-20s %9s %9s %-6s %2s %4s %8s %8s %6s %11s %10s %8s %8s %7s %8s %7s %7s\n", "case", "source",
              "target", "search", "th", "runs", "wall s", "cpu s", "cpu/w", "candidates", "pieces", "Mcand/s",
              "Mpiece/s", "us/cell", "peak MiB", "B/cell", "B/piece");
}

void print_row(const Row& r) {
  const double ms = static_cast<double>(r.peak_extra) / (1024.0 * 1024.0);
  const double per_cell = static_cast<double>(r.peak_extra) / static_cast<double>(r.ns + r.nt);
  std::printf("%-20s %9zu %9zu %-6s %2d %4d %8.4f %8.4f %6.2f %11zu %10zu %8.3f %8.3f %7.3f ", r.label.c_str(), r.ns,
              r.nt, search_name(r.search), r.threads, r.runs, r.wall, r.cpu, r.cpu / r.wall, r.fp.candidates,
              r.fp.pieces, 1e-6 * static_cast<double>(r.fp.candidates) / r.wall,
              1e-6 * static_cast<double>(r.fp.pieces) / r.wall, 1e6 * r.wall / static_cast<double>(r.ns));
  if (r.peak_extra >= 0)
    std::printf("%8.1f %7.0f %7.0f\n", ms, per_cell,
                static_cast<double>(r.peak_extra) / static_cast<double>(std::max<std::size_t>(1, r.fp.pieces)));
  else
    std::printf("%8s %7s %7s\n", "n/a", "n/a", "n/a");
  std::fflush(stdout);
}

// Bytes held by a finalized TetMesh's vectors (nodes, cells, neighbours, volumes).
double mesh_bytes(const tetia::TetMesh& m) {
  return static_cast<double>(m.nodes.capacity() * sizeof(tetia::Vec3) + m.cells.capacity() * sizeof(m.cells[0]) +
                             m.neighbors.capacity() * sizeof(m.neighbors[0]) +
                             m.volumes.capacity() * sizeof(double));
}

// The cells of `m` sorted by the Morton code (21 bits per axis) of their centroids within the
// box [lo, hi], nodes renumbered in order of first use; finalized again.
tetia::TetMesh morton_sorted(const tetia::TetMesh& m, tetia::Vec3 lo, tetia::Vec3 hi) {
  const auto spread = tetia::detail::spread_bits<3>;  // 21 bits to every third bit
  const auto quant = [](double v, double a, double b) {
    const double t = (v - a) / (b - a) * 2097151.0;
    return static_cast<std::uint64_t>(std::clamp(t, 0.0, 2097151.0));
  };
  const std::size_t n = m.num_cells();
  std::vector<std::pair<std::uint64_t, std::int32_t>> key(n);
  for (std::size_t c = 0; c < n; ++c) {
    const tetia::Tet t = m.cell(c);
    const double x = 0.25 * (t[0].x + t[1].x + t[2].x + t[3].x), y = 0.25 * (t[0].y + t[1].y + t[2].y + t[3].y),
                 z = 0.25 * (t[0].z + t[1].z + t[2].z + t[3].z);
    key[c] = {spread(quant(x, lo.x, hi.x)) | spread(quant(y, lo.y, hi.y)) << 1 | spread(quant(z, lo.z, hi.z)) << 2,
              static_cast<std::int32_t>(c)};
  }
  std::sort(key.begin(), key.end());
  tetia::TetMesh r;
  std::vector<std::int32_t> new_index(m.num_nodes(), -1);
  r.cells.reserve(n);
  for (const auto& [k, c] : key) {
    std::array<std::int32_t, 4> cell = m.cells[static_cast<std::size_t>(c)];
    for (auto& v : cell) {
      auto& ni = new_index[static_cast<std::size_t>(v)];
      if (ni < 0) {
        ni = static_cast<std::int32_t>(r.nodes.size());
        r.nodes.push_back(m.nodes[static_cast<std::size_t>(v)]);
      }
      v = ni;
    }
    r.cells.push_back(cell);
  }
  tetia::finalize(r, "morton_sorted");
  return r;
}

void bounds(const tetia::TetMesh& m, tetia::Vec3& lo, tetia::Vec3& hi) {
  for (const auto& p : m.nodes) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
}

// Mean distance between the centroids of consecutive cells: how spatially coherent the cell
// numbering is (about the cell size for a coherent order, about half the domain for a random one).
double order_locality(const tetia::TetMesh& m) {
  double sum = 0.0;
  const auto centroid = [&m](std::size_t c) {
    const tetia::Tet t = m.cell(c);
    return tetia::Vec3{0.25 * (t[0].x + t[1].x + t[2].x + t[3].x), 0.25 * (t[0].y + t[1].y + t[2].y + t[3].y),
                       0.25 * (t[0].z + t[1].z + t[2].z + t[3].z)};
  };
  for (std::size_t c = 1; c < m.num_cells(); ++c) {
    const tetia::Vec3 d = centroid(c) - centroid(c - 1);
    sum += std::sqrt(dot(d, d));
  }
  return m.num_cells() > 1 ? sum / static_cast<double>(m.num_cells() - 1) : 0.0;
}

// Runs every (search, threads) configuration on one pair of meshes; checks the volume against
// `expected` (relative tolerance `tol`) and that all configurations agree bit for bit.
template <class Mesh>
bool run_case(const std::string& label, const Mesh& src, const Mesh& tgt, double expected, double tol,
              const Options& o, std::vector<Row>& rows) {
  bool ok = true;
  std::vector<Row> mine;
  for (const auto search : {tetia::CandidateSearch::front, tetia::CandidateSearch::rtree})
    for (const int th : o.threads) {
      mine.push_back(measure(label, src, tgt, search, th, o));
      print_row(mine.back());
    }
  const Fingerprint& ref = mine.front().fp;
  for (const Row& r : mine) {
    // Candidates differ between the searches (the R-tree tests every box overlap); the pieces
    // must not. Between thread counts of one search, everything is equal.
    const bool same_pieces = r.fp.pieces == ref.pieces && r.fp.hash == ref.hash && r.fp.volume == ref.volume;
    if (!same_pieces) {
      std::printf("  MISMATCH: %s %s %d threads differs from %s %d threads\n", label.c_str(), search_name(r.search),
                  r.threads, search_name(mine.front().search), mine.front().threads);
      ok = false;
    }
    for (const Row& q : mine)
      if (q.search == r.search && !(q.fp == r.fp)) {
        std::printf("  MISMATCH: %s %s: %d and %d threads differ\n", label.c_str(), search_name(r.search), r.threads,
                    q.threads);
        ok = false;
      }
  }
  const double err = std::abs(ref.volume - expected);
  const bool vol_ok = err <= tol * expected;
  std::printf("  %s: total %s %.17g, |V - %.17g| = %.3g (%s, tolerance %.0e); results identical across "
              "searches and threads: %s\n",
              label.c_str(), std::is_same_v<Mesh, tetia::TriMesh> ? "area" : "volume", ref.volume, expected, err, vol_ok ? "OK" : "FAILED", tol * expected, ok ? "yes" : "NO");
  rows.insert(rows.end(), mine.begin(), mine.end());
  return ok && vol_ok;
}

// --- part "p1": keep_mixed_mass against keep_polyhedra -----------------------------------------

struct P1Row {
  std::string label, kept;
  std::size_t ns = 0, nt = 0, pieces = 0;
  int threads = 1, runs = 0;
  double wall = 0.0, cpu = 0.0;  // supermesh, fastest run
  long long peak_extra = -1;     // supermesh, first run, result alive
  double remap_wall = 0.0;       // remap_p1 from the result of the last run
  long long remap_peak_extra = -1;  // its peak over the resident size before it (result alive)
  int cg_iterations = 0;
  std::vector<double> remapped;
};

enum class Kept { none, streamed, mixed_mass, polyhedra };
const char* kept_name(Kept k) {
  return k == Kept::none ? "none" : k == Kept::streamed ? "streamed" : k == Kept::mixed_mass ? "mixed_mass" : "polyhedra";
}

// P1 remap without keeping the supermesh: the loads summed by a consumer, then the solve.
P1Row measure_streamed(P1Row r, const tetia::TetMesh& src, const tetia::TetMesh& tgt, const tetia::SupermeshOptions& opt,
                       const std::vector<double>& field) {
  long long before = -1;
  if (reset_peak_memory()) before = proc_status_bytes("VmRSS");
  const double w0 = wall_now(), c0 = cpu_now();
  tetia::P1Loads loads(src, tgt, {field});
  const tetia::SupermeshSummary sum = tetia::supermesh(src, tgt, loads, opt);
  r.wall = wall_now() - w0;
  r.cpu = cpu_now() - c0;
  r.runs = 1;
  r.pieces = sum.pieces;
  const long long peak = proc_status_bytes("VmHWM");
  if (before >= 0 && peak >= 0) r.peak_extra = peak - before;
  tetia::P1RemapReport report;
  long long rbefore = -1;
  if (reset_peak_memory()) rbefore = proc_status_bytes("VmRSS");
  const double q0 = wall_now();
  r.remapped = tetia::solve_p1(tgt, loads.loads()[0], &report);
  r.remap_wall = wall_now() - q0;
  const long long rpeak = proc_status_bytes("VmHWM");
  if (rbefore >= 0 && rpeak >= 0) r.remap_peak_extra = rpeak - rbefore;
  r.cg_iterations = report.iterations;
  return r;
}

P1Row measure_p1(const std::string& label, const tetia::TetMesh& src, const tetia::TetMesh& tgt, Kept kept,
                 int threads, const std::vector<double>& field, const Options& o) {
  const bool mass = kept == Kept::mixed_mass;
  P1Row r;
  r.label = label;
  r.kept = kept_name(kept);
  r.ns = src.num_cells();
  r.nt = tgt.num_cells();
  r.threads = threads;
  tetia::SupermeshOptions opt;
  opt.threads = threads;
  if (kept == Kept::streamed) return measure_streamed(r, src, tgt, opt, field);
  opt.keep_mixed_mass = mass;
  opt.keep_polyhedra = kept == Kept::polyhedra;
  for (int rep = 0; rep < o.reps; ++rep) {
    const bool first = rep == 0;
    long long before = -1;
    if (first && reset_peak_memory()) before = proc_status_bytes("VmRSS");
    const double w0 = wall_now(), c0 = cpu_now();
    const auto s = tetia::supermesh(borrow(src), borrow(tgt), opt);  // timed without copying the meshes
    const double w = wall_now() - w0, c = cpu_now() - c0;
    if (first) {
      const long long peak = proc_status_bytes("VmHWM");
      if (before >= 0 && peak >= 0) r.peak_extra = peak - before;
      r.pieces = s.pieces.size();
    }
    ++r.runs;
    if (first || w < r.wall) {
      r.wall = w;
      r.cpu = c;
    }
    const bool last = rep + 1 == o.reps || (first && w > o.long_run);
    if (last && kept != Kept::none) {
      tetia::P1RemapReport report;
      long long rbefore = -1;
      if (reset_peak_memory()) rbefore = proc_status_bytes("VmRSS");
      const double q0 = wall_now();
      r.remapped = tetia::remap_p1(s, field, &report);
      r.remap_wall = wall_now() - q0;
      const long long rpeak = proc_status_bytes("VmHWM");
      if (rbefore >= 0 && rpeak >= 0) r.remap_peak_extra = rpeak - rbefore;
      r.cg_iterations = report.iterations;
    }
    if (last) break;
  }
  return r;
}

void print_p1_header() {
  std::printf("%-16s %9s %9s %-10s %2s %4s %9s %8s %9s %10s %9s %8s %9s %9s %9s\n", "case", "source", "target",
              "kept", "th", "runs", "pieces", "wall s", "cpu s", "peak MiB", "B/piece", "remap s", "remap MiB", "CG iter",
              "total s");
}

void print_p1_row(const P1Row& r) {
  std::printf("%-16s %9zu %9zu %-10s %2d %4d %9zu %8.4f %9.4f ", r.label.c_str(), r.ns, r.nt, r.kept.c_str(), r.threads,
              r.runs, r.pieces, r.wall, r.cpu);
  if (r.peak_extra >= 0)
    std::printf("%10.1f %9.0f", static_cast<double>(r.peak_extra) / (1024.0 * 1024.0),
                static_cast<double>(r.peak_extra) / static_cast<double>(std::max<std::size_t>(1, r.pieces)));
  else
    std::printf("%10s %9s", "n/a", "n/a");
  if (r.remapped.empty())
    std::printf(" %8s %9s %9s %9s\n", "-", "-", "-", "-");
  else
    std::printf(" %8.4f %9.1f %9d %9.4f\n", r.remap_wall, static_cast<double>(r.remap_peak_extra) / (1024.0 * 1024.0),
                r.cg_iterations, r.wall + r.remap_wall);
  std::fflush(stdout);
}

// Both ways on one pair, for each thread count; the remapped values must agree bit for bit.
// The boxes: source element size for about 10^3 ... 10^6 cells (Gmsh's count jumps with the
// number of boundary segments, ceil(1/h)); the target is meshed at h / 1.07.
struct BoxLevel {
  const char* label;
  std::size_t nominal;
  double h;
};
constexpr BoxLevel kBoxLevels[] = {{"box 1e3", 1000, 0.19}, {"box 1e4", 10000, 0.082}, {"box 1e5", 100000, 0.037},
                                   {"box 1e6", 1000000, 0.0166}};

bool run_p1_case(const std::string& label, const tetia::TetMesh& src, const tetia::TetMesh& tgt, const Options& o) {
  std::vector<double> field(src.num_nodes());
  for (std::size_t n = 0; n < src.num_nodes(); ++n) {
    const tetia::Vec3 p = src.nodes[n];
    field[n] = std::sin(3.0 * p.x) * std::cos(2.0 * p.y) * std::exp(p.z);
  }
  bool ok = true;
  std::vector<double> ref;
  std::size_t pieces = 0;
  int compared = 0;
  for (const int th : o.threads)
    for (const Kept kept : {Kept::none, Kept::streamed, Kept::mixed_mass, Kept::polyhedra}) {
      if (std::find(o.kept.begin(), o.kept.end(), kept_name(kept)) == o.kept.end()) continue;
      // The polyhedra are held twice at the peak (per thread, then merged): skip that run when
      // it would not fit in the memory available now (the 10^6 boxes need about 85 GB).
      const double need = 2.0 * static_cast<double>(pieces) * static_cast<double>(sizeof(tetia::Polyhedron));
      const double avail = static_cast<double>(meminfo_bytes("MemAvailable"));
      if (kept == Kept::polyhedra && avail > 0.0 && need > 0.8 * avail) {
        std::printf("%-16s keep_polyhedra, %d threads: skipped (needs about %.1f GB, %.1f GB available)\n",
                    label.c_str(), th, 1e-9 * need, 1e-9 * avail);
        continue;
      }
      const P1Row r = measure_p1(label, src, tgt, kept, th, field, o);
      pieces = std::max(pieces, r.pieces);
      print_p1_row(r);
      if (kept == Kept::none) continue;
      ++compared;
      if (ref.empty()) {
        ref = r.remapped;
      } else if (r.remapped.size() != ref.size() ||
                 std::memcmp(r.remapped.data(), ref.data(), ref.size() * sizeof(double)) != 0) {
        std::printf("  MISMATCH: %s, %s, %d threads: remap_p1 differs\n", label.c_str(), r.kept.c_str(), th);
        ok = false;
      }
    }
  std::printf("  %s: remap_p1 identical bit for bit over the %d runs that remapped (streamed, keep_mixed_mass, "
              "keep_polyhedra; all thread counts): %s\n",
              label.c_str(), compared, ok ? "yes" : "NO");
  return ok;
}

tetia::TetMesh timed_read(const fs::path& p) {
  const double w0 = wall_now();
  tetia::TetMesh m = tetia::read_mesh(p);
  std::printf("read %s: %zu cells, %zu nodes, %.2f s\n", p.string().c_str(), m.num_cells(), m.num_nodes(),
              wall_now() - w0);
  return m;
}

// The unit cube meshed by Gmsh at size h, from the cache if there, else generated and cached.
tetia::TetMesh cached_box(const Options& o, double h) {
  char name[64];
  std::snprintf(name, sizeof name, "box_h%.6f.msh", h);
  const fs::path file = o.cache / name;
  if (fs::exists(file)) {
    try {
      return timed_read(file);
    } catch (const std::exception& e) {
      std::printf("cache file unreadable (%s), generating again\n", e.what());
    }
  }
  const double w0 = wall_now();
  tetia::TetMesh m = tetia::generate_box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, h);
  std::printf("generated box h=%.6f: %zu cells, %zu nodes, %.2f s", h, m.num_cells(), m.num_nodes(), wall_now() - w0);
  std::error_code ec;
  fs::create_directories(o.cache, ec);
  try {
    tetia::write_msh(file, m);
    std::printf(" (cached as %s)\n", file.string().c_str());
  } catch (const std::exception& e) {
    std::printf(" (not cached: %s)\n", e.what());
  }
  return m;
}

// The unit square meshed by Gmsh at size h (triangles), cached as for the boxes.
tetia::TriMesh cached_rectangle(const Options& o, double h) {
  char name[64];
  std::snprintf(name, sizeof name, "rect_h%.7f.msh", h);
  const fs::path file = o.cache / name;
  if (fs::exists(file)) {
    try {
      const double w0 = wall_now();
      tetia::TriMesh m = tetia::read_tri_mesh(file);
      std::printf("read %s: %zu cells, %zu nodes, %.2f s\n", file.string().c_str(), m.num_cells(), m.num_nodes(),
                  wall_now() - w0);
      return m;
    } catch (const std::exception& e) {
      std::printf("cache file unreadable (%s), generating again\n", e.what());
    }
  }
  const double w0 = wall_now();
  tetia::TriMesh m = tetia::generate_rectangle({0.0, 0.0}, {1.0, 1.0}, h);
  std::printf("generated rectangle h=%.7f: %zu cells, %zu nodes, %.2f s", h, m.num_cells(), m.num_nodes(),
              wall_now() - w0);
  std::error_code ec;
  fs::create_directories(o.cache, ec);
  try {
    tetia::write_msh(file, m);
    std::printf(" (cached as %s)\n", file.string().c_str());
  } catch (const std::exception& e) {
    std::printf(" (not cached: %s)\n", e.what());
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  bool ok = true;
  std::vector<Row> rows;
  std::printf("bench_supermesh: reps %d (once above %.0f s), threads", o.reps, o.long_run);
  for (const int t : o.threads) std::printf(" %d", t);
  std::printf("; peak memory measurement: %s\n\n", reset_peak_memory() ? "VmHWM reset per call" : "unavailable");

  // One pair of meshes in each requested cell order.
  const auto run_orders = [&](const std::string& name, const tetia::TetMesh& src, const tetia::TetMesh& tgt,
                              double expected, double tol) {
    if (o.file_order) {
      std::printf("%s, file order: mean distance between consecutive cells %.4f (source), %.4f (target)\n",
                  name.c_str(), order_locality(src), order_locality(tgt));
      print_header();
      ok &= run_case(name + " file", src, tgt, expected, tol, o, rows);
    }
    if (o.morton_order) {
      tetia::Vec3 lo = src.nodes.front(), hi = lo;
      bounds(src, lo, hi);
      bounds(tgt, lo, hi);
      const double w0 = wall_now();
      const tetia::TetMesh s2 = morton_sorted(src, lo, hi), t2 = morton_sorted(tgt, lo, hi);
      std::printf("%s, Morton order (sorting both meshes and finalizing again: %.3f s): mean distance between "
                  "consecutive cells %.4f (source), %.4f (target)\n",
                  name.c_str(), wall_now() - w0, order_locality(s2), order_locality(t2));
      print_header();
      ok &= run_case(name + " morton", s2, t2, expected, tol, o, rows);
    }
    std::printf("\n");
  };

  try {
    if (o.pyramid) {
      const fs::path pyr = o.extdata / "lsm_pyramid_0_05.msh", cube = o.extdata / "lsm_cube_0_05.msh";
      if (!fs::exists(pyr) || !fs::exists(cube)) {
        std::printf("pyramid x cube: skipped (%s or %s absent)\n\n", pyr.string().c_str(), cube.string().c_str());
      } else {
        const tetia::TetMesh p = timed_read(pyr), c = timed_read(cube);
        std::printf("\n");
        run_orders("pyr x cube", p, c, 1.0 / 3.0, 3e-12);
        run_orders("cube x pyr", c, p, 1.0 / 3.0, 3e-12);
      }
    }
    if (o.boxes) {
      for (const BoxLevel& lv : kBoxLevels) {
        if (lv.nominal > o.max_cells) {
          std::printf("%s: skipped (--max-cells=%zu)\n", lv.label, o.max_cells);
          continue;
        }
        const tetia::TetMesh src = cached_box(o, lv.h);
        const tetia::TetMesh tgt = cached_box(o, lv.h / 1.07);
        std::printf("mesh memory: %.1f and %.1f bytes per cell (nodes, cells, neighbours, volumes)\n",
                    mesh_bytes(src) / static_cast<double>(src.num_cells()),
                    mesh_bytes(tgt) / static_cast<double>(tgt.num_cells()));
        run_orders(lv.label, src, tgt, 1.0, 1e-12);
      }
    }
    if (o.p1) {
      std::printf("P1 remap: SupermeshOptions::keep_mixed_mass (local mixed mass matrices, %zu B per piece) "
                  "against keep_polyhedra (%zu B per piece); file order, front search\n",
                  sizeof(decltype(tetia::Supermesh::local_mass)::value_type), sizeof(tetia::Polyhedron));
      std::printf("kept none: pieces only (P0), for reference; remap s: remap_p1 from the result; total: "
                  "supermesh (fastest run) + remap\n");
      const fs::path pyr = o.extdata / "lsm_pyramid_0_05.msh", cube = o.extdata / "lsm_cube_0_05.msh";
      if (!fs::exists(pyr) || !fs::exists(cube)) {
        std::printf("pyramid x cube: skipped (%s or %s absent)\n", pyr.string().c_str(), cube.string().c_str());
      } else {
        const tetia::TetMesh p = timed_read(pyr), c = timed_read(cube);
        print_p1_header();
        ok &= run_p1_case("p1 pyr x cube", p, c, o);
        std::printf("\n");
      }
      for (const BoxLevel& lv : kBoxLevels) {
        const std::string label = std::string("p1 ") + lv.label;
        if (lv.nominal > o.max_cells) {
          std::printf("%s: skipped (--max-cells=%zu)\n", label.c_str(), o.max_cells);
          continue;
        }
        const tetia::TetMesh src = cached_box(o, lv.h);
        const tetia::TetMesh tgt = cached_box(o, lv.h / 1.07);
        print_p1_header();
        ok &= run_p1_case(label, src, tgt, o);
        std::printf("\n");
      }
    }
    if (o.rect2d) {
      // About 10^4, 10^5, 10^6 source triangles (an equilateral triangle of edge h has area
      // 0.43 h^2); the target at h / 1.07.
      struct Level {
        const char* label;
        std::size_t nominal;
        double h;
      };
      const Level levels[] = {{"rect2d 1e4", 10000, 0.0152}, {"rect2d 1e5", 100000, 0.0048},
                              {"rect2d 1e6", 1000000, 0.00152}};
      for (const Level& lv : levels) {
        if (lv.nominal > o.max_cells) {
          std::printf("%s: skipped (--max-cells=%zu)\n", lv.label, o.max_cells);
          continue;
        }
        const tetia::TriMesh src = cached_rectangle(o, lv.h);
        const tetia::TriMesh tgt = cached_rectangle(o, lv.h / 1.07);
        std::printf("%s, file order\n", lv.label);
        print_header();
        ok &= run_case(std::string(lv.label), src, tgt, 1.0, 1e-12, o, rows);
        std::printf("\n");
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_supermesh: %s\n", e.what());
    return 1;
  }

  // Summary: speed-up of 2 threads over 1 and of the front over the R-tree, per case.
  if (!rows.empty()) {
    std::printf("summary (wall time of the fastest run):\n");
    std::printf("%-20s %-6s %10s %10s %8s\n", "case", "search", "1 thread", "2 threads", "speedup");
    for (const Row& r : rows) {
      if (r.threads != 1) continue;
      for (const Row& q : rows)
        if (q.label == r.label && q.search == r.search && q.threads == 2)
          std::printf("%-20s %-6s %10.4f %10.4f %8.2f\n", r.label.c_str(), search_name(r.search), r.wall, q.wall,
                      r.wall / q.wall);
    }
    std::printf("%-20s %-7s %10s %10s %8s\n", "case", "threads", "front", "rtree", "rtree/front");
    for (const Row& r : rows) {
      if (r.search != tetia::CandidateSearch::front) continue;
      for (const Row& q : rows)
        if (q.label == r.label && q.threads == r.threads && q.search == tetia::CandidateSearch::rtree)
          std::printf("%-20s %-7d %10.4f %10.4f %8.2f\n", r.label.c_str(), r.threads, r.wall, q.wall, q.wall / r.wall);
    }
  }
  std::printf("\nchecks: %s\n", ok ? "OK" : "FAILED");
  return ok ? 0 : 1;
}
