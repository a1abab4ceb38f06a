// app/command_support.hpp -- what the mesh commands (app/mesh_commands.cpp: supermesh, demo;
// app/remap_command.cpp: remap, apply) share: the progress line's phases, fields given as
// expressions, integrals and errors, the source integral over the overlap, loading both meshes
// (with their fields), JSON numbers and strings, output checks, and the guard that turns
// exceptions into exit statuses (2 for bad usage or input, 1 for other failures).
#pragma once

#include <muParser.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "../src/compensated_sum.hpp"
#include "mesh_kind.hpp"
#include "progress.hpp"
#include "remap_method.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/geometry.hpp"
#include "tetia/io.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"
#include "mesh_commands.hpp"
#include "pairs.hpp"

namespace tetia::app {

// The start of a phase on the progress line (app/progress.hpp).
inline void progress(const std::string& what) { Progress::get().phase(what); }

// The supermesh's progress callback: its source cells, on the progress line.
inline std::function<void(std::size_t, std::size_t)> intersection_progress(std::size_t cells) {
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
inline std::array<double, 3> bary_tail(const Tet& t, Vec3 c) {
  const double d = orient3d(t[0], t[1], t[2], t[3]);
  return {orient3d(t[0], c, t[2], t[3]) / d, orient3d(t[0], t[1], c, t[3]) / d, orient3d(t[0], t[1], t[2], c) / d};
}
inline std::array<double, 2> bary_tail(const Triangle& t, Vec2 c) {
  const double d = orient2d(t[0], t[1], t[2]);
  return {orient2d(t[0], c, t[2]) / d, orient2d(t[0], t[1], c) / d};
}

// The source field integrated over the overlap only, from the pieces: a cell value times the
// piece's measure, or a linear field on the source cell (from its nodes' values, or from the
// cell's own vertex values for a discontinuous field) at the piece's centroid times its
// measure, which is exact for a linear function.
template <class Mesh>
void add_overlap(detail::CompensatedSum& sum, const Mesh& source, const typename Kind<Mesh>::Piece& p,
                 const std::vector<double>& v, Location where) {
  const double m = Kind<Mesh>::measure_of(p);
  const auto sc = static_cast<std::size_t>(p.source);
  if (where == Location::cells) {
    sum.add(v[sc] * m);
    return;
  }
  if (!(m > 0.0)) return;
  constexpr std::size_t nv = Kind<Mesh>::dim + 1;
  const auto vertex = [&](std::size_t k) {
    return where == Location::nodes ? v[static_cast<std::size_t>(source.cells[sc][k])] : v[sc * nv + k];
  };
  const auto c = (1.0 / m) * p.first;
  const auto l = bary_tail(source.cell(sc), c);
  double rest = 1.0, value = 0.0;
  for (std::size_t k = 0; k < l.size(); ++k) {
    rest -= l[k];
    value += l[k] * vertex(k + 1);
  }
  sum.add(m * (rest * vertex(0) + value));
}

template <class Mesh>
double overlap_integral(const typename Kind<Mesh>::Result& s, const std::vector<double>& v, Location where) {
  detail::CompensatedSum sum;
  for (const auto& p : s.pieces) add_overlap(sum, *s.source, p, v, where);
  return sum.value();
}

// Output files named *.msh are Gmsh's format (write_msh: the file's cells and tags, the fields as
// node and element data); any other name is VTU.
inline bool is_msh_path(const std::string& file) {
  return file.size() >= 4 && file.compare(file.size() - 4, 4, ".msh") == 0;
}

// A number for the JSON summary: JSON has no NaN or infinity, so a value that is not finite
// is an error naming it (exit status 2: the input's coordinates or values overflow double
// arithmetic), never "nan" in the output.
inline std::string num(double v, const char* what) {
  if (!std::isfinite(v))
    throw std::runtime_error(std::string("tetia: the ") + what + " is not finite (" + (std::isnan(v) ? "NaN" : "infinite") +
                             "): the input's coordinates or values overflow double arithmetic");
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A string for JSON: quotes, backslashes and control characters escaped.
inline std::string json_escape(const std::string& in) {
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
inline void check_writable(const std::string& file, const char* option) {
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

inline int dimension_of(const AnyMesh& m) { return std::holds_alternative<TetMesh>(m) ? 3 : 2; }

// Loads a mesh of either dimension, reporting progress, ignored elements, reoriented and flat
// cells.
inline AnyMesh load(const std::string& file, MeshReadOptions options, std::size_t* straightened, std::vector<Field>* fields) {
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
  std::vector<Field> source_fields, target_fields;  // target_fields: those target_options asks for
};
inline Loaded load_pair(const std::string& source, const std::string& target, const MeshReadOptions& source_options,
                 const MeshReadOptions& target_options = {}) {
  Loaded l;
  MeshReadOptions target_read = target_options;
  target_read.corner_nodes = source_options.corner_nodes;
  l.source = load(source, source_options, &l.straightened[0], &l.source_fields);
  l.target = load(target, target_read, &l.straightened[1], target_read.fields.empty() ? nullptr : &l.target_fields);
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

// Options that read `fields` (at time step `step`) where a method has them: cell, node or
// element-node data.
inline MeshReadOptions fields_at(const std::vector<std::string>& fields, Location where, std::int64_t step) {
  MeshReadOptions o;
  o.fields = fields;
  o.fields_on_cells = where == Location::cells;
  o.fields_on_cell_nodes = where == Location::cell_nodes;
  o.step = step;
  return o;
}

// A usage error for a --field named twice.
inline void check_distinct_fields(const std::vector<std::string>& fields) {
  for (std::size_t i = 0; i < fields.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (fields[i] == fields[j]) throw std::invalid_argument("tetia: --field " + fields[i] + " given twice");
}

// For --uncovered keep: each target field must have as many components as the source's.
inline void check_kept_components(const Loaded& l, const std::string& source, const std::string& target) {
  for (std::size_t i = 0; i < l.target_fields.size(); ++i)
    if (l.target_fields[i].components != l.source_fields[i].components)
      throw std::invalid_argument("tetia: --uncovered keep: field " + l.source_fields[i].name + " has " +
                                  std::to_string(l.source_fields[i].components) + " components in " + source +
                                  " but " + std::to_string(l.target_fields[i].components) + " in " + target);
}

// Component k of a field's values (`components` in a row per entity).
inline std::vector<double> component_of(const std::vector<double>& values, int components, std::size_t k) {
  const auto nc = static_cast<std::size_t>(components);
  std::vector<double> out(values.size() / nc);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = values[i * nc + k];
  return out;
}

// The JSON key that says a geometry was made straight (only with --corner-nodes).
inline std::string straightened_json(bool corner_nodes, const std::size_t (&n)[2]) {
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
  } catch (const std::bad_alloc&) {
    Progress::get().finish();
    std::fprintf(stderr, "tetia: out of memory\n");
    return exit_failure;
  } catch (const std::exception& e) {
    Progress::get().finish();
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

inline Progress::Mode progress_mode(bool always, bool never) {
  if (always && never) throw std::invalid_argument("tetia: --progress and --quiet exclude each other");
  return always ? Progress::Mode::always : never ? Progress::Mode::never : Progress::Mode::automatic;
}

}  // namespace tetia::app
