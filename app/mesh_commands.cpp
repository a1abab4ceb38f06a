// app/mesh_commands.cpp -- `tetia supermesh`, `tetia remap`, `tetia demo`, for tetrahedral (3D)
// and triangular (2D) meshes alike: the dimension comes from the files (tetrahedra: 3, else
// triangles: 2; read_any_mesh), both files must have the same one, and everything after reading
// is one template over the mesh type. JSON keys follow the dimension: *_volume in 3D, *_area
// in 2D, plus "dimension".
#include "mesh_commands.hpp"

#include <muParser.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "../src/compensated_sum.hpp"
#include "mpi_mode.hpp"
#include "pairs.hpp"
#include "progress.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/io.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::app {
namespace {

// What the commands need to know about a dimension: its types and its words.
template <class Mesh>
struct Kind;
template <>
struct Kind<TetMesh> {
  static constexpr int dim = 3;
  using Point = Vec3;
  using Result = Supermesh;
  using Piece = SupermeshPiece;
  using Loads = P1Loads;
  static constexpr const char* measure = "volume";  // the JSON keys' suffix
  static constexpr const char* cells = "tetrahedra";
  static const std::vector<double>& measures(const TetMesh& m) { return m.volumes; }
  static double total(const TetMesh& m) { return m.total_volume(); }
  static double total(const Supermesh& s) { return s.intersection_volume(); }
  static double measure_of(const SupermeshPiece& p) { return p.volume; }
};
template <>
struct Kind<TriMesh> {
  static constexpr int dim = 2;
  using Point = Vec2;
  using Result = Supermesh2;
  using Piece = SupermeshPiece2;
  using Loads = P1Loads2;
  static constexpr const char* measure = "area";
  static constexpr const char* cells = "triangles";
  static const std::vector<double>& measures(const TriMesh& m) { return m.areas; }
  static double total(const TriMesh& m) { return m.total_area(); }
  static double total(const Supermesh2& s) { return s.intersection_area(); }
  static double measure_of(const SupermeshPiece2& p) { return p.area; }
};

// The start of a phase on the progress line (app/progress.hpp).
void progress(const std::string& what) { Progress::get().phase(what); }

// The supermesh's progress callback: its source cells, on the progress line.
std::function<void(std::size_t, std::size_t)> intersection_progress(std::size_t cells) {
  Progress::get().phase("intersection", cells);
  return [](std::size_t done, std::size_t) { Progress::get().advance(done); };
}

// A field given as an expression in x, y, z (muparser syntax: sin, cos, exp, sqrt, ^, pi); in
// 2D z is 0.
class Expression {
 public:
  explicit Expression(const std::string& text) {
    parser_.DefineVar("x", &x_);
    parser_.DefineVar("y", &y_);
    parser_.DefineVar("z", &z_);
    parser_.DefineConst("pi", 3.14159265358979323846);
    parser_.SetExpr(text);
    try {
      (void)parser_.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw std::invalid_argument("tetia: --expr '" + text + "': " + e.GetMsg());
    }
  }
  double operator()(Vec3 p) {
    x_ = p.x, y_ = p.y, z_ = p.z;
    return parser_.Eval();
  }
  double operator()(Vec2 p) { return (*this)(Vec3{p.x, p.y, 0.0}); }

 private:
  mu::Parser parser_;
  double x_ = 0.0, y_ = 0.0, z_ = 0.0;
};

template <class Mesh>
using Function = std::function<double(typename Kind<Mesh>::Point)>;

template <class Mesh>
std::vector<double> node_values(const Mesh& m, const Function<Mesh>& f) {
  std::vector<double> v(m.num_nodes());
  for (std::size_t n = 0; n < m.num_nodes(); ++n) v[n] = f(m.nodes[n]);
  return v;
}

template <class Mesh>
double integral(const Mesh& m, const std::vector<double>& v, int order) {
  return order == 0 ? integral_p0(m, v) : integral_p1(m, v);
}

template <class Mesh>
double l2_error(const Mesh& m, const std::vector<double>& v, int order, const Function<Mesh>& f) {
  return order == 0 ? l2_error_p0(m, v, f) : l2_error_p1(m, v, f);
}

template <class Mesh>
double l2_norm(const Mesh& m, const Function<Mesh>& f) {
  return l2_error_p0(m, std::vector<double>(m.num_cells(), 0.0), f);
}

// Barycentric coordinates of c in the cell (weights of vertices 1..d; vertex 0 gets the rest).
std::array<double, 3> bary_tail(const Tet& t, Vec3 c) {
  const double d = orient3d(t[0], t[1], t[2], t[3]);
  return {orient3d(t[0], c, t[2], t[3]) / d, orient3d(t[0], t[1], c, t[3]) / d, orient3d(t[0], t[1], t[2], c) / d};
}
std::array<double, 2> bary_tail(const Triangle& t, Vec2 c) {
  const double d = orient2d(t[0], t[1], t[2]);
  return {orient2d(t[0], c, t[2]) / d, orient2d(t[0], t[1], c) / d};
}

// The source field integrated over the overlap only, from the pieces: a P0 value times the
// piece's volume, or a P1 field (linear on the source cell) at the piece's centroid times its
// volume, which is exact for a linear function.
template <class Mesh>
void add_overlap(detail::CompensatedSum& sum, const Mesh& source, const typename Kind<Mesh>::Piece& p,
                 const std::vector<double>& v, int order) {
  const double m = Kind<Mesh>::measure_of(p);
  if (order == 0) {
    sum.add(v[static_cast<std::size_t>(p.source)] * m);
    return;
  }
  if (!(m > 0.0)) return;
  const auto c = (1.0 / m) * p.first;
  const auto& n = source.cells[static_cast<std::size_t>(p.source)];
  const auto l = bary_tail(source.cell(static_cast<std::size_t>(p.source)), c);
  double rest = 1.0, value = 0.0;
  for (std::size_t k = 0; k < l.size(); ++k) {
    rest -= l[k];
    value += l[k] * v[static_cast<std::size_t>(n[k + 1])];
  }
  sum.add(m * (rest * v[static_cast<std::size_t>(n[0])] + value));
}

template <class Mesh>
double overlap_integral(const typename Kind<Mesh>::Result& s, const std::vector<double>& v, int order) {
  detail::CompensatedSum sum;
  for (const auto& p : s.pieces) add_overlap(sum, *s.source, p, v, order);
  return sum.value();
}


// Output files named *.msh are Gmsh's format (write_msh: the file's cells and tags, the fields as
// node and element data); any other name is VTU.
bool is_msh_path(const std::string& file) {
  return file.size() >= 4 && file.compare(file.size() - 4, 4, ".msh") == 0;
}

// The supermesh's pieces as simplices sharing each piece's corners, for ParaView (VTU) or Gmsh
// (.msh): Int64 cell data "piece" (the index of the piece's pair of file cells: the pieces of a
// split hexahedron's tetrahedra with the same target file cell are one), "source" and "target"
// (the file's tags of its two cells), and Float64 "simplex_volume" (area): each simplex's own
// measure, so that summing it over the file gives the intersection's total (the piece's measure
// is the sum over its simplices).
template <class Mesh, class Pairs>
void write_supermesh_file(const std::string& file, const typename Kind<Mesh>::Result& s, const Pairs& pairs,
                         VtuFormat format, int threads) {
  Mesh out;
  std::vector<std::int64_t> piece, source, target;
  std::vector<double> measure;
  const auto tag = [](const Mesh& m, std::int32_t c) {  // a split file cell's simplices: the file cell's tag
    if (!m.cell_origin.empty()) return m.origin_tags[static_cast<std::size_t>(m.cell_origin[static_cast<std::size_t>(c)])];
    return m.cell_tags.empty() ? std::int64_t{c} + 1 : m.cell_tags[static_cast<std::size_t>(c)];
  };
  // Each piece's corners once, its simplices (the fan of tetrahedra() / triangles()) by index.
  const auto add = [&](std::size_t k, const auto& shape, const auto& simplices) {
    const auto base = static_cast<std::int32_t>(out.nodes.size());
    for (const auto& c : shape.corners()) out.nodes.push_back(c.point);
    for (const auto& idx : simplices) {
      typename std::remove_reference_t<decltype(out.cells)>::value_type cell{};
      typename std::remove_cvref_t<decltype(out.cell(0))> simplex{};
      for (std::size_t v = 0; v < idx.size(); ++v) {
        cell[v] = base + static_cast<std::int32_t>(idx[v]);
        simplex[v] = shape.corner(idx[v]).point;
      }
      out.cells.push_back(cell);
      piece.push_back(pairs.piece_pair[k]);
      source.push_back(tag(*s.source, s.pieces[k].source));
      target.push_back(tag(*s.target, s.pieces[k].target));
      if constexpr (Kind<Mesh>::dim == 3) {
        measure.push_back(std::abs(signed_volume(simplex)));
      } else {
        measure.push_back(std::abs(signed_area(simplex)));
      }
    }
  };
  // About five simplices and eight corners per piece: reserved, so that growing does not copy
  // (and fault in) hundreds of megabytes again.
  const std::size_t expected = 5 * s.pieces.size();
  out.nodes.reserve(8 * s.pieces.size());
  out.cells.reserve(expected);
  for (auto* v : {&piece, &source, &target}) v->reserve(expected);
  measure.reserve(expected);
  // The shapes are computed again here, one piece at a time, rather than kept by the supermesh
  // (about 3 KB a polyhedron, most of the time and memory of a run with -o): the kernel on the
  // same two cells gives the same shape bit for bit (the supermesh calls it on exactly these).
  for (std::size_t k = 0; k < s.pieces.size(); ++k) {
    const auto& p = s.pieces[k];
    const auto shape = intersect(s.source->cell(static_cast<std::size_t>(p.source)),
                                 s.target->cell(static_cast<std::size_t>(p.target)));
    if constexpr (Kind<Mesh>::dim == 3) {
      add(k, shape, shape.tetrahedra_corners());
    } else {
      add(k, shape, shape.triangle_corners());
    }
  }
  const std::string measure_name = std::string("simplex_") + Kind<Mesh>::measure;
  if (is_msh_path(file)) {  // Gmsh's element data are numbers: the ids as doubles (exact below 2^53)
    const auto as_doubles = [](const std::vector<std::int64_t>& v) { return std::vector<double>(v.begin(), v.end()); };
    write_msh(file, out,
              {{"piece", as_doubles(piece)}, {"source", as_doubles(source)}, {"target", as_doubles(target)},
               {measure_name, measure}});
    return;
  }
  VtuOptions options;
  options.format = format;
  options.threads = threads;
  options.cell_ids = {{"piece", std::move(piece)}, {"source", std::move(source)}, {"target", std::move(target)}};
  write_vtu(file, out, {{measure_name, measure}}, {}, options);
}

// Rows and columns are the file cells (tetia/file_cells.hpp), in the order of their tags: a
// split hexahedron is one row or column.
template <class Result, class Pairs>
void write_p0_matrix(const std::string& file, const Result& s, const Pairs& pairs, const char* measure) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("tetia: " + file + ": cannot write");
  out << "%%MatrixMarket matrix coordinate real general\n"
      << "% tetia P0 coupling matrix: entry (t, s) = " << measure
      << " of target cell t intersected with source cell s (cells of the files, in tag order)\n"
      << s.target->num_file_cells() << ' ' << s.source->num_file_cells() << ' ' << pairs.pairs.size() << '\n';
  char buf[64];
  for (const auto& p : pairs.pairs) {
    std::snprintf(buf, sizeof buf, "%.17g", Kind<std::remove_cvref_t<decltype(*s.source)>>::measure_of(p));
    out << p.target + 1 << ' ' << p.source + 1 << ' ' << buf << '\n';
  }
  if (!out) throw std::runtime_error("tetia: " + file + ": write failed");
}

CandidateSearch parse_search(const std::string& s) {
  if (s == "front") return CandidateSearch::front;
  if (s == "rtree") return CandidateSearch::rtree;
  throw std::invalid_argument("tetia: --search must be front or rtree, not '" + s + "'");
}

// A number for the JSON summary: JSON has no NaN or infinity, so a value that is not finite
// is an error naming it (exit status 2: the input's coordinates or values overflow double
// arithmetic), never "nan" in the output.
std::string num(double v, const char* what) {
  if (!std::isfinite(v))
    throw std::runtime_error(std::string("tetia: the ") + what + " is not finite (" + (std::isnan(v) ? "NaN" : "infinite") +
                             "): the input's coordinates or values overflow double arithmetic");
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A string for JSON: quotes, backslashes and control characters escaped.
std::string json_escape(const std::string& in) {
  std::string out;
  for (const char c : in) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

// Fails before any work if `file` cannot be written: a directory, a missing directory, no
// permission. A file that did not exist is removed again.
void check_writable(const std::string& file, const char* option) {
  if (file.empty()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw std::runtime_error("tetia: " + file + ": cannot write (" + option + "): is a directory");
  const bool existed = fs::exists(file, ec);
  std::FILE* f = std::fopen(file.c_str(), "ab");
  if (f == nullptr)
    throw std::runtime_error("tetia: " + file + ": cannot write (" + option + "): " + std::strerror(errno));
  std::fclose(f);
  if (!existed) fs::remove(file, ec);
}

int dimension_of(const AnyMesh& m) { return std::holds_alternative<TetMesh>(m) ? 3 : 2; }

// Loads a mesh of either dimension, reporting progress, ignored elements, reoriented and flat
// cells.
AnyMesh load(const std::string& file, MeshReadOptions options, std::size_t* straightened, std::vector<Field>* fields) {
  progress("reading " + file);
  MeshReadInfo info;
  AnyMesh any = read_any_mesh(file, &info, options);
  *straightened = info.straightened_cells;
  if (fields != nullptr) *fields = std::move(info.fields);
  if (info.straightened_cells > 0)
    Progress::get().note(file + ": " + std::to_string(info.straightened_cells) +
                         " higher-order cells read by their corner nodes: their geometry was made straight");
  std::visit(
      [&](const auto& m) {
        using K = Kind<std::remove_cvref_t<decltype(m)>>;
        if (info.ignored_elements > 0)
          Progress::get().note(file + ": " + std::to_string(info.ignored_elements) + " elements other than " +
                               K::cells + " ignored");
        if (m.reoriented_cells > 0)
          std::fprintf(stderr, "tetia: %s: %zu inverted cells reoriented\n", file.c_str(), m.reoriented_cells);
        if (m.flat_cells > 0)
          std::fprintf(stderr, "tetia: %s: %zu zero-%s cells kept (they intersect nothing)\n", file.c_str(),
                       m.flat_cells, K::measure);
      },
      any);
  return any;
}

// Both meshes, which must have the same dimension (a usage error otherwise: exit status 2).
// Also the number of cells of each made straight (--corner-nodes), and the source's fields that
// `source_options` asks for, read in the same pass as its mesh.
struct Loaded {
  AnyMesh source, target;
  std::size_t straightened[2] = {0, 0};
  std::vector<Field> source_fields;
};
Loaded load_pair(const std::string& source, const std::string& target, const MeshReadOptions& source_options) {
  Loaded l;
  MeshReadOptions target_options;
  target_options.corner_nodes = source_options.corner_nodes;
  l.source = load(source, source_options, &l.straightened[0], &l.source_fields);
  l.target = load(target, target_options, &l.straightened[1], nullptr);
  AnyMesh& a = l.source;
  AnyMesh& b = l.target;
  if (dimension_of(a) != dimension_of(b)) {
    const auto what = [](const AnyMesh& m) {
      return dimension_of(m) == 3 ? std::string("a 3D mesh (tetrahedra)") : std::string("a 2D mesh (triangles)");
    };
    throw std::invalid_argument("tetia: " + source + " is " + what(a) + " but " + target + " is " + what(b) +
                                "; both meshes must have the same dimension");
  }
  return l;
}

// The JSON key that says a geometry was made straight (only with --corner-nodes).
std::string straightened_json(bool corner_nodes, const std::size_t (&n)[2]) {
  if (!corner_nodes) return "";
  return ", \"straightened_cells\": [" + std::to_string(n[0]) + ", " + std::to_string(n[1]) + "]";
}

template <class Body>
int guarded(Body&& body) {
  try {
    const int status = body();
    Progress::get().finish();
    return status;
  } catch (const std::invalid_argument& e) {
    Progress::get().finish();
    std::fprintf(stderr, "%s\n", e.what());
    return exit_bad_input;
  } catch (const std::runtime_error& e) {
    Progress::get().finish();
    std::fprintf(stderr, "%s\n", e.what());
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tetia: %s\n", e.what());
    return exit_failure;
  }
}

// A command's meshes outlive every supermesh built from them (all within the command), so the
// supermesh borrows them (a shared pointer that owns nothing) instead of copying them.
template <class Mesh>
std::shared_ptr<const Mesh> borrow(const Mesh& mesh) {
  return std::shared_ptr<const Mesh>(std::shared_ptr<const Mesh>(), &mesh);
}

// The cells as the kernels see them: a file's hexahedron is 6 tetrahedra ("source_cells",
// "target_cells" and "pairs" count the file's cells).
template <class Mesh>
std::string simplices_json(const Mesh& source, const Mesh& target) {
  return std::string("\"source_simplices\": ") + std::to_string(source.num_cells()) +
         ", \"target_simplices\": " + std::to_string(target.num_cells());
}

template <class Mesh>
int supermesh_command(const SupermeshCommand& cmd, const Mesh& source, const Mesh& target, const std::string& extra) {
  using K = Kind<Mesh>;
  SupermeshOptions options;
  options.search = parse_search(cmd.search);
  options.threads = cmd.threads;
  options.progress = intersection_progress(source.num_cells());
  const auto s = parallel_supermesh(borrow(source), borrow(target), options, cmd.partition);
  const auto pairs = file_cell_pairs(s);
  if (!cmd.output.empty()) {
    progress("writing " + cmd.output);
    write_supermesh_file<Mesh>(cmd.output, s, pairs, cmd.ascii ? VtuFormat::ascii : VtuFormat::binary, cmd.threads);
  }
  const std::string m = K::measure;
  Progress::get().finish();
  std::printf(
      "{\"dimension\": %d, \"source_cells\": %zu, \"target_cells\": %zu, %s, \"candidates\": %zu, \"pairs\": %zu, "
      "\"simplex_pairs\": %zu, \"source_%s\": %s, \"target_%s\": %s, \"intersection_%s\": %s%s, \"seconds\": %.6f}\n",
      K::dim, source.num_file_cells(), target.num_file_cells(), simplices_json(source, target).c_str(), s.candidates,
      pairs.pairs.size(), s.pieces.size(), m.c_str(),
      num(K::total(source), "source total").c_str(), m.c_str(), num(K::total(target), "target total").c_str(),
      m.c_str(), num(K::total(s), "intersection total").c_str(), extra.c_str(), s.seconds);
  return exit_ok;
}

// What remap_command takes from the supermesh: per component, the remapped values (per target
// cell for P0, per node for P1) and the source integral over the overlap; the largest CG
// iteration count; and the supermesh's counts.
struct Remapped {
  std::vector<std::vector<double>> values;
  std::vector<double> overlap;
  int iterations = 0;
  std::size_t pairs = 0, pieces = 0;  // of file cells, of simplices
  double total = 0.0, seconds = 0.0;  // intersection measure, supermesh time
};

// P1 without keeping the supermesh (tetia::P1Loads): besides the loads, the pieces handed over
// (in the order of a kept supermesh's pieces) give what the kept path takes from the pieces,
// with the same sums in the same order: the intersection measure, the overlap integrals, and
// the pairs of file cells (a target file cell's pieces are consecutive, as file_cell_pairs
// relies on too).
template <class Mesh>
class StreamedP1 final : public Kind<Mesh>::Loads {
  using Piece = typename Kind<Mesh>::Piece;

 public:
  StreamedP1(const Mesh& source, const Mesh& target, const std::vector<std::vector<double>>& components)
      : Kind<Mesh>::Loads(source, target, std::vector<std::span<const double>>(components.begin(), components.end())),
        source_(source), target_(target), components_(components), overlap_(components.size()) {}
  void consume(const Piece& p, const double* values) override {
    Kind<Mesh>::Loads::consume(p, values);
    total_.add(Kind<Mesh>::measure_of(p));
    for (std::size_t c = 0; c < components_.size(); ++c) add_overlap(overlap_[c], source_, p, components_[c], 1);
    const std::size_t tf = target_.file_cell(static_cast<std::size_t>(p.target));
    if (tf != run_target_) flush(tf);
    run_sources_.push_back(source_.file_cell(static_cast<std::size_t>(p.source)));
  }
  // After the supermesh: the counts and sums into r.
  void finish(Remapped& r) {
    flush(0);
    r.pairs = pairs_;
    r.total = total_.value();
    for (const auto& o : overlap_) r.overlap.push_back(o.value());
  }

 private:
  void flush(std::size_t next_target) {  // the pairs of the target file cell run just ended
    std::sort(run_sources_.begin(), run_sources_.end());
    pairs_ += static_cast<std::size_t>(std::unique(run_sources_.begin(), run_sources_.end()) - run_sources_.begin());
    run_sources_.clear();
    run_target_ = next_target;
  }
  const Mesh& source_;
  const Mesh& target_;
  const std::vector<std::vector<double>>& components_;
  std::vector<detail::CompensatedSum> overlap_;
  detail::CompensatedSum total_;
  std::size_t run_target_ = static_cast<std::size_t>(-1);
  std::vector<std::size_t> run_sources_;
  std::size_t pairs_ = 0;
};

// Every component remapped: by P1 loads handed the pieces (P1 without --matrix, one process),
// else from a kept supermesh (P0; P1 with --matrix, which needs the pieces' matrices; several
// MPI ranks, whose pieces are gathered), with the same results bit for bit.
template <class Mesh>
Remapped remap_components(const RemapCommand& cmd, const Mesh& source, const Mesh& target,
                          const std::vector<std::vector<double>>& components) {
  using K = Kind<Mesh>;
  SupermeshOptions options;
  options.threads = cmd.threads;
  options.progress = intersection_progress(source.num_cells());
  Remapped r;
  if (cmd.order == 1 && cmd.matrix.empty() && (K::dim == 2 || mpi_ranks() == 1)) {
    StreamedP1<Mesh> loads(source, target, components);
    const SupermeshSummary sum = supermesh(source, target, loads, options);
    loads.finish(r);
    r.pieces = sum.pieces;
    r.seconds = sum.seconds;
    progress("solve");
    for (std::size_t c = 0; c < components.size(); ++c) {
      P1RemapReport report;
      r.values.push_back(solve_p1(target, loads.loads()[c], &report));
      r.iterations = std::max(r.iterations, report.iterations);
    }
    return r;
  }
  // P1 (and its --matrix) needs each piece's local mixed mass matrix, not the polyhedron itself.
  options.keep_mixed_mass = cmd.order == 1;
  const auto s = parallel_supermesh(borrow(source), borrow(target), options, cmd.partition);
  const auto pairs = file_cell_pairs(s);
  progress(cmd.order == 0 ? "remap" : "solve");
  if (!cmd.matrix.empty()) {
    if (cmd.order == 0) write_p0_matrix(cmd.matrix, s, pairs, K::measure);
    else write_mixed_mass_matrix(s, cmd.matrix);
  }
  for (const auto& component : components) {
    P1RemapReport report;
    r.values.push_back(cmd.order == 0 ? remap_p0(s, component) : remap_p1(s, component, &report));
    r.iterations = std::max(r.iterations, report.iterations);
    r.overlap.push_back(overlap_integral<Mesh>(s, component, cmd.order));
  }
  r.pairs = pairs.pairs.size();
  r.pieces = s.pieces.size();
  r.total = K::total(s);
  r.seconds = s.seconds;
  return r;
}

template <class Mesh>
int remap_command(const RemapCommand& cmd, const Mesh& source, const Mesh& target, std::vector<Field>&& fields,
                  const std::string& extra) {
  using K = Kind<Mesh>;
  // The fields: each named --field (any number of components, at --step), or the expression.
  struct Input {
    std::string name;
    int components = 1;
    std::vector<double> values;  // components per cell (P0) or node (P1), in a row
  };
  std::vector<Input> inputs;
  std::unique_ptr<Expression> expr;
  Function<Mesh> f;
  if (!cmd.expr.empty()) {
    expr = std::make_unique<Expression>(cmd.expr);
    f = [&](typename K::Point p) { return (*expr)(p); };
    // P0: one value per file cell (a hexahedron's average, on each of its tetrahedra).
    inputs.push_back({"field", 1,
                      cmd.order == 0 ? spread_to_simplices(source, file_cell_average(source, average_over_cells(source, f)))
                                     : node_values(source, f)});
  } else {
    for (Field& field : fields) inputs.push_back({field.name, field.components, std::move(field.values)});
  }
  // Every component remapped on its own (one solve each for P1); integrals and conservation
  // per component. Every number is formatted before anything is printed (num() fails on one
  // that is not finite), then one line of JSON.
  std::vector<std::vector<double>> components;
  for (const Input& in : inputs) {
    const auto nc = static_cast<std::size_t>(in.components);
    for (std::size_t k = 0; k < nc; ++k) {
      std::vector<double>& component = components.emplace_back(in.values.size() / nc);
      for (std::size_t i = 0; i < component.size(); ++i) component[i] = in.values[i * nc + k];
    }
  }
  Remapped remapped = remap_components(cmd, source, target, components);
  std::size_t next_component = 0;
  std::vector<Field> cell_data, point_data;
  std::string fields_json;
  double first[4] = {0, 0, 0, 0};  // source, overlap, target integral, conservation: the first component
  std::vector<double> first_out;
  for (const Input& in : inputs) {
    const auto nc = static_cast<std::size_t>(in.components);
    // P0 results are per file cell of the target (a hexahedron's value is the volume-weighted
    // average of its tetrahedra's, which is the projection onto constants per hexahedron).
    const std::size_t n_tgt = cmd.order == 0 ? target.num_file_cells() : target.num_nodes();
    std::vector<double> out(n_tgt * nc);
    std::string ints[4];
    for (std::size_t k = 0; k < nc; ++k) {
      const std::size_t c = next_component++;
      const std::vector<double>& component = components[c];
      std::vector<double> result = std::move(remapped.values[c]);
      if (cmd.order == 0 && !target.cell_origin.empty()) {
        const std::vector<double> per_file_cell = file_cell_average(target, result);
        for (std::size_t i = 0; i < n_tgt; ++i) out[i * nc + k] = per_file_cell[i];
        result = spread_to_simplices(target, per_file_cell);  // for the integrals and errors below
      } else {
        for (std::size_t i = 0; i < n_tgt; ++i) out[i * nc + k] = result[i];
      }
      // Conservation: the target integral against the source integral over the overlap (the
      // whole source integral when the domains coincide).
      const double src_int = integral(source, component, cmd.order);
      const double tgt_int = integral(target, result, cmd.order);
      const double overlap_int = remapped.overlap[c];
      const double conservation = std::abs(tgt_int - overlap_int) / std::max(std::abs(overlap_int), 1e-300);
      const double values[4] = {src_int, overlap_int, tgt_int, conservation};
      static const char* const kWhat[4] = {"source integral", "overlap integral", "target integral",
                                           "conservation error"};
      for (int q = 0; q < 4; ++q) ints[q] += (k == 0 ? "" : ", ") + num(values[q], kWhat[q]);
      if (&in == &inputs.front() && k == 0) {
        std::copy(values, values + 4, first);
        first_out = result;
      }
    }
    fields_json += std::string(fields_json.empty() ? "" : ", ") + "{\"name\": \"" + json_escape(in.name) +
                   "\", \"components\": " + std::to_string(in.components) + ", \"source_integral\": [" + ints[0] +
                   "], \"overlap_integral\": [" + ints[1] + "], \"target_integral\": [" + ints[2] +
                   "], \"conservation_error\": [" + ints[3] + "]}";
    (cmd.order == 0 ? cell_data : point_data).push_back({in.name, std::move(out), in.components});
  }
  double error = -1.0, relative = -1.0;
  if (f) {
    const std::vector<double> exact =
        cmd.order == 0 ? file_cell_average(target, average_over_cells(target, f)) : node_values(target, f);
    (cmd.order == 0 ? cell_data : point_data).push_back({"exact", exact});
    error = l2_error(target, first_out, cmd.order, f);
    const double norm = l2_norm(target, f);
    relative = norm > 0.0 ? error / norm : error;
  }
  const std::string m = K::measure;
  const std::string totals[3] = {num(K::total(source), "source total"), num(K::total(target), "target total"),
                                 num(remapped.total, "intersection total")};
  const std::string integrals[3] = {num(first[0], "source integral"), num(first[1], "overlap integral"),
                                    num(first[2], "target integral")};
  const std::string conservation_text = num(first[3], "conservation error");
  const std::string l2[2] = {f ? num(error, "L2 error") : "null", f ? num(relative, "relative L2 error") : "null"};
  if (!cmd.output.empty()) {
    progress("writing " + cmd.output);
    if (is_msh_path(cmd.output)) {
      write_msh(cmd.output, target, cell_data, point_data);
    } else {
      VtuOptions vtu;
      vtu.format = cmd.ascii ? VtuFormat::ascii : VtuFormat::binary;
      vtu.threads = cmd.threads;
      write_vtu(cmd.output, target, cell_data, point_data, vtu);
    }
  }
  Progress::get().finish();
  std::printf(
      "{\"dimension\": %d, \"order\": %d, \"source_cells\": %zu, \"target_cells\": %zu, %s, \"pairs\": %zu, "
      "\"simplex_pairs\": %zu, "
      "\"source_%s\": %s, \"target_%s\": %s, \"intersection_%s\": %s, \"source_integral\": %s, "
      "\"overlap_integral\": %s, \"target_integral\": %s, "
      "\"conservation_error\": %s, \"l2_error\": %s, \"relative_l2_error\": %s, \"cg_iterations\": %d, "
      "\"fields\": [%s]%s, \"seconds\": %.6f}\n",
      K::dim, cmd.order, source.num_file_cells(), target.num_file_cells(), simplices_json(source, target).c_str(),
      remapped.pairs, remapped.pieces, m.c_str(), totals[0].c_str(),
      m.c_str(), totals[1].c_str(), m.c_str(), totals[2].c_str(), integrals[0].c_str(), integrals[1].c_str(),
      integrals[2].c_str(), conservation_text.c_str(), l2[0].c_str(), l2[1].c_str(), remapped.iterations,
      fields_json.c_str(), extra.c_str(), remapped.seconds);
  return exit_ok;
}

// One demo case: two meshes remapped both ways, P0 and P1; rows of the table, VTU files.
template <class Mesh>
void demo_case(const std::string& name, const Mesh& a, const Mesh& b, bool same_domain, const Function<Mesh>& f,
               const DemoCommand& cmd) {
  namespace fs = std::filesystem;
  using K = Kind<Mesh>;
  const std::string stem = (fs::path(cmd.output_dir) / name.substr(0, name.find('/'))).string();
  for (int dir = 0; dir < 2; ++dir) {
    const Mesh& src = dir == 0 ? a : b;
    const Mesh& tgt = dir == 0 ? b : a;
    SupermeshOptions options;
    options.threads = cmd.threads;
    options.keep_mixed_mass = true;  // P1: the local mixed mass matrices (no shapes are written)
    const auto s = supermesh(borrow(src), borrow(tgt), options);
    // For the same domain the overlap is the mesh volume; for different domains it is not known
    // exactly (curved, discretized), so no error is printed there.
    const double vol_err = std::abs(K::total(s) - K::total(tgt)) / K::total(tgt);
    for (int order = 0; order < 2; ++order) {
      const std::vector<double> in = order == 0 ? average_over_cells(src, f) : node_values(src, f);
      const std::vector<double> out = order == 0 ? remap_p0(s, in) : remap_p1(s, in);
      const double oi = overlap_integral<Mesh>(s, in, order);
      const double ti = integral(tgt, out, order);
      // The L2 error is only meaningful where the target is covered: same-domain pairs.
      const double rel = same_domain ? l2_error(tgt, out, order, f) / l2_norm(tgt, f) : 0.0;
      char vol_col[32] = "-", l2_col[32] = "-";
      if (same_domain) {
        std::snprintf(vol_col, sizeof vol_col, "%.2e", vol_err);
        std::snprintf(l2_col, sizeof l2_col, "%.3e", rel);
      }
      std::printf("%-9s %-5s %5d %9zu %9zu %9zu %8.3f %10.6f %10s %12.2e %11s\n", name.c_str(),
                  dir == 0 ? "a->b" : "b->a", order, src.num_cells(), tgt.num_cells(), s.pieces.size(), s.seconds,
                  K::total(s), vol_col, std::abs(ti - oi) / std::abs(oi), l2_col);
      const std::string file = stem + (dir == 0 ? "_a_to_b" : "_b_to_a") + "_p" + std::to_string(order) + ".vtu";
      std::vector<Field> cd, pd;
      (order == 0 ? cd : pd).push_back({"remapped", out});
      (order == 0 ? cd : pd).push_back({"exact", order == 0 ? average_over_cells(tgt, f) : node_values(tgt, f)});
      write_vtu(file, tgt, cd, pd);
    }
  }
}

}  // namespace

Progress::Mode progress_mode(bool always, bool never) {
  if (always && never) throw std::invalid_argument("tetia: --progress and --quiet exclude each other");
  return always ? Progress::Mode::always : never ? Progress::Mode::never : Progress::Mode::automatic;
}

int run_supermesh(const SupermeshCommand& cmd) {
  return guarded([&] {
    Progress::get().configure(progress_mode(cmd.progress, cmd.quiet));
    check_writable(cmd.output, "-o");
    MeshReadOptions options;
    options.corner_nodes = cmd.corner_nodes;
    const Loaded l = load_pair(cmd.source, cmd.target, options);
    const std::string extra = straightened_json(cmd.corner_nodes, l.straightened);
    if (const auto* s3 = std::get_if<TetMesh>(&l.source))
      return supermesh_command(cmd, *s3, std::get<TetMesh>(l.target), extra);
    return supermesh_command(cmd, std::get<TriMesh>(l.source), std::get<TriMesh>(l.target), extra);
  });
}

int run_remap(const RemapCommand& cmd) {
  return guarded([&] {
    Progress::get().configure(progress_mode(cmd.progress, cmd.quiet));
    if (cmd.order != 0 && cmd.order != 1) throw std::invalid_argument("tetia: --order must be 0 or 1");
    if (cmd.fields.empty() == cmd.expr.empty())
      throw std::invalid_argument("tetia: give --field NAME (one or more) or --expr EXPRESSION, not both");
    for (std::size_t i = 0; i < cmd.fields.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (cmd.fields[i] == cmd.fields[j]) throw std::invalid_argument("tetia: --field " + cmd.fields[i] + " given twice");
    check_writable(cmd.output, "-o");
    check_writable(cmd.matrix, "--matrix");
    MeshReadOptions options;  // the fields are read with the source mesh, in one pass
    options.corner_nodes = cmd.corner_nodes;
    options.fields = cmd.fields;
    options.fields_on_cells = cmd.order == 0;
    options.step = cmd.step;
    Loaded l = load_pair(cmd.source, cmd.target, options);
    const std::string extra = straightened_json(cmd.corner_nodes, l.straightened);
    if (const auto* s3 = std::get_if<TetMesh>(&l.source))
      return remap_command(cmd, *s3, std::get<TetMesh>(l.target), std::move(l.source_fields), extra);
    return remap_command(cmd, std::get<TriMesh>(l.source), std::get<TriMesh>(l.target), std::move(l.source_fields),
                         extra);
  });
}

int run_demo(const DemoCommand& cmd) {
  return guarded([&] {
    Progress::get().configure(Progress::Mode::automatic);
    if (cmd.dim != 2 && cmd.dim != 3) throw std::invalid_argument("tetia: --dim must be 2 or 3");
    std::filesystem::create_directories(cmd.output_dir);
    const double h = cmd.size > 0.0 ? cmd.size : (cmd.dim == 3 ? 0.12 : 0.03);
    progress("generating meshes with Gmsh");
    std::printf("%-9s %-5s %5s %9s %9s %9s %8s %10s %10s %12s %11s\n", "meshes", "dir", "order", "src cells",
                "tgt cells", "pairs", "seconds", "overlap", cmd.dim == 3 ? "vol. err" : "area err", "conservation",
                "rel. L2 err");
    if (cmd.dim == 3) {
      const Function<TetMesh> f = [](Vec3 p) { return std::sin(p.x) * std::cos(p.y) * std::exp(p.z); };
      // Same domain, non-matching: conservation is exact up to rounding.
      demo_case<TetMesh>("box/box", generate_box({0, 0, 0}, {1, 1, 1}, 1.6 * h), generate_box({0, 0, 0}, {1, 1, 1}, h),
                         true, f, cmd);
      // Different domains: a ball cutting a box; what is conserved is the integral over the overlap.
      demo_case<TetMesh>("ball/box", generate_ball({0.5, 0.5, 0.5}, 0.6, 1.3 * h),
                         generate_box({0, 0, 0}, {1, 1, 1}, h), false, f, cmd);
      std::printf("field: sin(x) cos(y) exp(z); VTU files in %s/ (open them in ParaView)\n", cmd.output_dir.c_str());
    } else {
      const Function<TriMesh> f = [](Vec2 p) { return std::sin(p.x) * std::cos(p.y); };
      demo_case<TriMesh>("rect/rect", generate_rectangle({0, 0}, {1, 1}, 1.6 * h), generate_rectangle({0, 0}, {1, 1}, h),
                         true, f, cmd);
      demo_case<TriMesh>("disk/rect", generate_disk({0.5, 0.5}, 0.6, 1.3 * h), generate_rectangle({0, 0}, {1, 1}, h),
                         false, f, cmd);
      demo_case<TriMesh>("ring/rect", generate_annulus({0.5, 0.5}, 0.2, 0.6, 1.3 * h),
                         generate_rectangle({0, 0}, {1, 1}, h), false, f, cmd);
      std::printf("field: sin(x) cos(y); VTU files in %s/ (open them in ParaView)\n", cmd.output_dir.c_str());
    }
    const char* m = cmd.dim == 3 ? "volume" : "area";
    std::printf("overlap: %s of the supermesh; %s err: |overlap - mesh %s| / mesh %s (same domain)\n"
                "conservation: |integral on the target - source integral over the overlap| / the latter\n"
                "rel. L2 err: against the exact field, where the target is covered (same-domain pairs)\n",
                m, cmd.dim == 3 ? "vol." : "area", m, m);
    return exit_ok;
  });
}

}  // namespace tetia::app
