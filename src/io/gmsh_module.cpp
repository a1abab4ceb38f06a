// src/io/gmsh_module.cpp -- everything tetia does with the Gmsh library, built as a module of
// its own (libtetia_gmsh.so) that the library loads only when a mesh is generated
// (gmsh_module.hpp): generation with Gmsh's OpenCASCADE kernel, and Gmsh's own reader (for the
// tests that compare it with the strict reader).
//
// Why a module: linking libgmsh (and OpenCASCADE behind it) costs every program about 0.1 s at
// start, in its static initializers, whether it meshes or not; `tetia supermesh` on 75,000
// cells takes 0.15 s. Loaded on demand, only `tetia demo` and generating programs pay it.
//
// Gmsh is one process-wide state (the current model, its views, its options), so every Gmsh
// call here goes through a GmshSession: it holds one mutex for its whole lifetime, starts from
// an empty model and leaves an empty one behind (a 10^6-cell model is not kept alive). Gmsh
// 4.8 is run with General.AbortOnError = 0: with the default (2) an error throws from deep
// inside the reader and leaves Gmsh's "busy" lock set, after which every later open silently
// does nothing. Errors are instead collected from Gmsh's logger after each step and turned into
// std::runtime_error("tetia: NAME: ...").
#include "gmsh_module.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "../mesh/mesh_dim.hpp"
#include "mesh_assembly.hpp"

namespace tetia {

namespace {

namespace fs = std::filesystem;

using detail::drop_repeated_cells;
using detail::Extracted;
using detail::GmshCell;
using detail::TagIndex;
using detail::ViewData;
using detail::check_planar;
using detail::field_values;
using detail::no_cells_message;

[[noreturn]] void fail(const std::string& name, const std::string& what) { detail::io_fail(name, what); }

// ---------------------------------------------------------------------------------------------
// Gmsh sessions

std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

// The text of whatever Gmsh threw: 4.8 throws std::string for its own errors.
std::string current_exception_text() {
  try {
    throw;
  } catch (const std::string& s) {
    return s;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown Gmsh exception";
  }
}

// Exclusive use of Gmsh for one operation. Contract: while a session lives, no other thread
// calls Gmsh (through tetia); the model is empty at the start and cleared at the end; `run`
// executes Gmsh calls and throws "tetia: NAME: message" if they threw or logged an error.
class GmshSession {
 public:
  explicit GmshSession(std::string name) : lock_(gmsh_mutex()), name_(std::move(name)) {
    run("starting Gmsh", [] {
      // Without reading the user's gmshrc: results must not depend on the user's options.
      // A second initialize (by an application that also uses Gmsh) is only a warning.
      static std::once_flag once;
      std::call_once(once, [] { gmsh::initialize(0, nullptr, false); });
      // Asserted on every session: another user of Gmsh in the process may have changed them.
      gmsh::option::setNumber("General.Terminal", 0);      // no console output
      gmsh::option::setNumber("General.Verbosity", 2);     // errors and warnings reach the logger
      gmsh::option::setNumber("General.AbortOnError", 0);  // see the file comment
      gmsh::option::setNumber("General.NumThreads", 1);    // reproducible meshing
      gmsh::logger::start();
      gmsh::clear();
    });
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
  ~GmshSession() {
    try {
      gmsh::clear();
      gmsh::logger::stop();
    } catch (...) {  // nothing useful to do in a destructor
    }
  }

  const std::string& name() const { return name_; }

  template <class F>
  void run(const char* during, F&& f) {
    std::string thrown;
    try {
      f();
    } catch (...) {
      thrown = current_exception_text();
    }
    std::string errors = take_errors();
    if (!thrown.empty() && errors.find(thrown) == std::string::npos)
      errors = errors.empty() ? thrown : thrown + "; " + errors;
    if (!errors.empty()) fail(name_, std::string(during) + ": " + errors);
  }

  // Like run, but an error only makes it return false (for probing views).
  template <class F>
  bool try_run(F&& f) {
    bool ok = true;
    try {
      f();
    } catch (...) {
      ok = false;
    }
    return take_errors().empty() && ok;
  }

 private:
  // The errors logged since the last call, "Error: " stripped, at most a few; clears the log.
  // Gmsh's generic follow-ups ("Error loading 'F'", "Could not merge file 'F'") are dropped,
  // but for the first when nothing more specific was said.
  static std::string take_errors() {
    std::vector<std::string> log;
    gmsh::logger::get(log);
    gmsh::logger::stop();
    gmsh::logger::start();
    std::vector<std::string> specific, generic;
    for (const auto& line : log) {
      constexpr std::string_view kError = "Error";
      if (line.compare(0, kError.size(), kError) != 0) continue;
      std::string_view msg(line);
      msg.remove_prefix(kError.size());
      while (!msg.empty() && (msg.front() == ':' || msg.front() == ' ')) msg.remove_prefix(1);
      while (!msg.empty() && (msg.back() == ' ' || msg.back() == '\n')) msg.remove_suffix(1);
      const bool is_generic = msg.starts_with("Error loading '") || msg.starts_with("Could not merge file '");
      (is_generic ? generic : specific).emplace_back(msg);
    }
    if (specific.empty() && !generic.empty()) specific.push_back(generic.front());
    const auto& shown = specific;
    std::string out;
    for (std::size_t i = 0; i < shown.size() && i < 3; ++i) out += (i > 0 ? "; " : "") + shown[i];
    if (shown.size() > 3) out += " (and " + std::to_string(shown.size() - 3) + " more)";
    return out;
  }

  std::unique_lock<std::mutex> lock_;
  std::string name_;
};

// The current model's nodes (all of them, by increasing tag) and first-order cells of the mesh
// type (every entity, by increasing tag, each node set once). For triangles the nodes' z is
// dropped after checking that the triangles lie in a plane z = const. Contract: inside a
// session, after a mesh was loaded or generated.
template <class Mesh>
Extracted<Mesh> extract(GmshSession& s) {
  using Dm = detail::MeshDim<Mesh>;
  constexpr std::size_t nv = Dm::nv;
  constexpr int kType = GmshCell<Mesh>::type;
  Extracted<Mesh> ex;
  std::vector<std::size_t> node_tags, elem_tags, elem_nodes;
  std::vector<double> xyz, unused_param;
  std::vector<int> types;
  s.run("reading the mesh", [&] {
    gmsh::model::mesh::getNodes(node_tags, xyz, unused_param, -1, -1, false, false);
    gmsh::model::mesh::getElementTypes(types, -1, -1);
    if (std::find(types.begin(), types.end(), kType) != types.end())
      gmsh::model::mesh::getElementsByType(kType, elem_tags, elem_nodes, -1);
  });
  if (xyz.size() != 3 * node_tags.size() || elem_nodes.size() != nv * elem_tags.size())
    fail(s.name(), "inconsistent data from Gmsh");

  std::vector<std::size_t> order;
  ex.node_index.build(node_tags, order, s.name(), "node", [&](std::size_t i, std::size_t j) {
    return std::equal(&xyz[3 * i], &xyz[3 * i + 3], &xyz[3 * j]);
  });
  const std::vector<std::size_t> node_order = order;
  auto& nodes = ex.mesh.nodes;
  nodes.resize(order.size());
  std::vector<double> z;  // 2D: the dropped coordinate, checked below
  if constexpr (Dm::d == 2) z.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const double* p = &xyz[3 * order[k]];
    nodes[k] = Dm::point(p);
    if constexpr (Dm::d == 2) z[k] = p[2];
  }

  {
    TagIndex by_tag;  // only for the order; cell_index is built on the cells kept
    by_tag.build(elem_tags, order, s.name(), "element", [&](std::size_t i, std::size_t j) {
      std::array<std::size_t, nv> a, b;
      std::copy_n(&elem_nodes[nv * i], nv, a.begin());
      std::copy_n(&elem_nodes[nv * j], nv, b.begin());
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      return a == b;
    });
  }
  ex.ignored += elem_tags.size() - order.size();
  auto& cells = ex.mesh.cells;
  std::vector<std::size_t> cell_tags(order.size());
  cells.resize(order.size());
  for (std::size_t c = 0; c < order.size(); ++c) {
    cell_tags[c] = elem_tags[order[c]];
    const std::size_t* en = &elem_nodes[nv * order[c]];
    for (std::size_t j = 0; j < nv; ++j) {
      const std::int32_t idx = ex.node_index.find(en[j]);
      if (idx < 0)
        fail(s.name(), "element " + std::to_string(cell_tags[c]) + ": unknown node tag " + std::to_string(en[j]));
      cells[c][j] = idx;
    }
  }
  ex.ignored += drop_repeated_cells(cells, cell_tags);
  ex.cell_index.build(cell_tags, order, s.name(), "element", [](std::size_t, std::size_t) { return false; });
  ex.mesh.node_tags.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) ex.mesh.node_tags[k] = static_cast<std::int64_t>(node_tags[node_order[k]]);
  ex.mesh.cell_tags.assign(cell_tags.begin(), cell_tags.end());
  if constexpr (Dm::d == 2) check_planar(s.name(), nodes, z, cells);

  // Count what is ignored without fetching its connectivity.
  for (const int type : types) {
    if (type == kType) continue;
    std::vector<std::size_t> tags, unused_nodes;
    std::string elem_name;
    int dim = 0, elem_order = 0, num_nodes = 0, num_primary = 0;
    std::vector<double> unused_coord;
    s.run("reading the mesh", [&] {
      gmsh::model::mesh::preallocateElementsByType(type, true, false, tags, unused_nodes, -1);
      gmsh::model::mesh::getElementProperties(type, elem_name, dim, elem_order, num_nodes, unused_coord, num_primary);
    });
    ex.ignored += tags.size();
    if (dim == Dm::d && elem_name.rfind(GmshCell<Mesh>::family, 0) == 0) ex.higher_order += tags.size();
  }
  return ex;
}

// The dimension of the loaded model's mesh: 3 with tetrahedra (of any order), else 2 with
// triangles (of any order), else 0.
int loaded_dimension(GmshSession& s) {
  std::vector<int> types;
  s.run("reading the mesh", [&] { gmsh::model::mesh::getElementTypes(types, -1, -1); });
  int dim = 0;
  for (const int type : types) {
    std::string elem_name;
    int edim = 0, elem_order = 0, num_nodes = 0, num_primary = 0;
    std::vector<double> unused_coord;
    s.run("reading the mesh", [&] {
      gmsh::model::mesh::getElementProperties(type, elem_name, edim, elem_order, num_nodes, unused_coord, num_primary);
    });
    if (elem_name.rfind("Tetrahedron", 0) == 0) dim = 3;
    else if (elem_name.rfind("Triangle", 0) == 0 && dim < 2) dim = 2;
  }
  return dim;
}

// The views loaded with the file (Gmsh makes one per $NodeData/$ElementData name), each at its
// first non-empty time step. `with_values` = false keeps names and types only.
std::vector<ViewData> loaded_views(GmshSession& s, bool with_values) {
  std::vector<int> view_tags;
  s.run("reading data", [&] { gmsh::view::getTags(view_tags); });
  std::vector<ViewData> out;
  for (const int tag : view_tags) {
    ViewData v;
    double steps = 0;
    if (!s.try_run([&] {
          const std::string opt = "View[" + std::to_string(gmsh::view::getIndex(tag)) + "].";
          gmsh::option::getString(opt + "Name", v.name);
          gmsh::option::getNumber(opt + "NbTimeStep", steps);
        }))
      continue;
    for (int step = 0; step < std::max(1, static_cast<int>(steps)); ++step) {
      double time = 0;
      std::string type;
      std::vector<std::size_t> tags;
      std::vector<std::vector<double>> values;
      int comps = 0;
      if (!s.try_run([&] { gmsh::view::getModelData(tag, step, type, tags, values, time, comps); })) break;
      if (type != "NodeData" && type != "ElementData") break;
      v.type = type;
      if (tags.empty()) continue;
      v.components = comps;
      if (with_values) {
        // Flat, one value per tag (only scalar fields are read; entries without one dropped).
        for (std::size_t i = 0; i < tags.size(); ++i)
          if (!values[i].empty()) {
            v.tags.push_back(tags[i]);
            v.values.push_back(values[i][0]);
          }
      }
      break;
    }
    if (!v.type.empty()) out.push_back(std::move(v));
  }
  return out;
}

// Fails unless `file` is a readable regular file named *.msh starting with "$MeshFormat".
// Checked before Gmsh sees the file: Gmsh ignores a missing file silently, parses anything
// that is not a mesh as a .geo script (which can run commands), and picks its reader by the
// extension first (a .msh file named x.stl goes to the STL reader).
void check_mesh_file(const fs::path& file, const std::string& name) {
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (!fs::exists(st)) fail(name, "cannot open: no such file");
  if (fs::is_directory(st)) fail(name, "cannot open: is a directory");
  std::string ext = file.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".msh") fail(name, "not a .msh file name (Gmsh chooses its reader by the extension)");
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (f == nullptr) fail(name, std::string("cannot open: ") + std::strerror(errno));
  char head[64] = {};
  const std::size_t got = std::fread(head, 1, sizeof head - 1, f);
  std::fclose(f);
  std::string_view text(head, got);
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t' || text.front() == '\r' || text.front() == '\n'))
    text.remove_prefix(1);
  if (text.substr(0, 11) != "$MeshFormat") fail(name, "not a Gmsh mesh file (no $MeshFormat header)");
}

// Loads `file` into an empty model: merge rather than open, which would also take Gmsh's
// project lock and reset state we set.
void load(GmshSession& s, const fs::path& file) {
  s.run("cannot read", [&] { gmsh::merge(file.string()); });
}

// ---------------------------------------------------------------------------------------------
// Generation

// Meshes the OCC shape `add_shape` creates at size h and extracts it. `measure` (the exact
// volume or area) only bounds the work: a mesh whose cells could not be indexed with 32 bits is
// refused before Gmsh spends hours on it.
template <class Mesh, class AddShape>
Mesh generate(const std::string& name, double h, double measure, AddShape&& add_shape) {
  constexpr int dim = detail::MeshDim<Mesh>::d;
  if (!(h > 0.0) || !std::isfinite(h))
    throw std::invalid_argument("tetia: " + name + ": element size must be positive");
  // A regular tetrahedron of edge h has volume h^3 / (6 sqrt 2) ~ h^3 / 8.5; an equilateral
  // triangle has area h^2 sqrt(3) / 4 ~ h^2 / 2.3.
  const double cell = dim == 3 ? h * h * h / 8.5 : h * h / 2.3;
  if (measure / cell > 1e9)
    throw std::invalid_argument("tetia: " + name + ": element size too small (over 10^9 cells)");
  Extracted<Mesh> ex;
  {
    GmshSession s(name);
    s.run("meshing", [&] {
      gmsh::model::add("tetia");
      add_shape();
      gmsh::model::occ::synchronize();
      // Everything the result depends on, set explicitly: the defaults may have been changed.
      gmsh::option::setNumber("Mesh.MeshSizeMin", h);
      gmsh::option::setNumber("Mesh.MeshSizeMax", h);
      gmsh::option::setNumber("Mesh.MeshSizeFactor", 1.0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 1);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
      gmsh::option::setNumber("Mesh.Algorithm", 6);    // Frontal-Delaunay (surfaces)
      gmsh::option::setNumber("Mesh.Algorithm3D", 1);  // Delaunay
      gmsh::option::setNumber("Mesh.RandomSeed", 1);
      gmsh::option::setNumber("Mesh.ElementOrder", 1);
      gmsh::option::setNumber("Mesh.Optimize", 1);
      gmsh::model::mesh::generate(dim);
    });
    ex = extract<Mesh>(s);
  }
  if (ex.mesh.cells.empty()) fail(name, std::string("Gmsh produced no ") + detail::MeshDim<Mesh>::cells_word);
  finalize(ex.mesh, name);
  return std::move(ex.mesh);
}




// Gmsh's reader, for the tests that compare the two (io/gmsh_reader.hpp): one Gmsh session,
// the dimension decided on the loaded model, which is then extracted.
AnyMesh read_any_mesh_impl(const std::filesystem::path& file, MeshReadInfo* info) {
  const std::string name = file.string();
  check_mesh_file(file, name);
  GmshSession s(name);
  load(s, file);
  const int dim = loaded_dimension(s);
  if (dim == 0) fail(name, "no tetrahedra or triangles");
  // With values: the info lists the fields that have some (as the strict reader's does).
  const std::vector<ViewData> views = info != nullptr ? loaded_views(s, true) : std::vector<ViewData>{};
  if (dim == 3) return detail::finish_read(extract<TetMesh>(s), name, views, info);
  return detail::finish_read(extract<TriMesh>(s), name, views, info);
}

std::vector<double> read_msh_field_impl(const std::filesystem::path& file, const std::string& field_name,
                                        bool on_cells) {
  const std::string name = file.string();
  check_mesh_file(file, name);
  GmshSession s(name);
  load(s, file);
  const std::vector<ViewData> views = loaded_views(s, true);
  if (loaded_dimension(s) == 2) return field_values(name, extract<TriMesh>(s), views, field_name, on_cells);
  return field_values(name, extract<TetMesh>(s), views, field_name, on_cells);
}

// The generators: Gmsh's OpenCASCADE shapes, meshed at size h (Mesh.MeshSizeMin = Max = h),
// Frontal-Delaunay surfaces and Delaunay volumes, one thread, fixed seed: the same arguments
// give the same mesh. Boundary nodes lie on the exact boundary: the ball comes out slightly
// smaller than 4/3 pi r^3 (the disk than pi r^2; the torus, in practice, than 2 pi^2 R r^2).
// 2D shapes lie in the plane z = 0. Bad arguments throw std::invalid_argument; Gmsh's
// failures std::runtime_error.
TetMesh generate_box_impl(Vec3 lo, Vec3 hi, double h) {
  const Vec3 d = hi - lo;
  if (!(d.x > 0.0 && d.y > 0.0 && d.z > 0.0) || !std::isfinite(d.x + d.y + d.z))
    throw std::invalid_argument("tetia: generate_box: need lo < hi in every coordinate");
  return generate<TetMesh>("generate_box", h, d.x * d.y * d.z,
                           [&] { gmsh::model::occ::addBox(lo.x, lo.y, lo.z, d.x, d.y, d.z); });
}

TetMesh generate_ball_impl(Vec3 center, double radius, double h) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !std::isfinite(center.x + center.y + center.z))
    throw std::invalid_argument("tetia: generate_ball: need a finite center and a positive radius");
  return generate<TetMesh>("generate_ball", h, 4.0 / 3.0 * std::numbers::pi * radius * radius * radius,
                           [&] { gmsh::model::occ::addSphere(center.x, center.y, center.z, radius); });
}

TetMesh generate_torus_impl(Vec3 center, double major_radius, double minor_radius, double h) {
  if (!(minor_radius > 0.0 && major_radius > minor_radius) || !std::isfinite(major_radius) ||
      !std::isfinite(center.x + center.y + center.z))
    throw std::invalid_argument("tetia: generate_torus: need 0 < minor radius < major radius");
  // Axis z, as Gmsh makes it.
  return generate<TetMesh>("generate_torus", h,
                           2.0 * std::numbers::pi * std::numbers::pi * major_radius * minor_radius * minor_radius,
                           [&] { gmsh::model::occ::addTorus(center.x, center.y, center.z, major_radius, minor_radius); });
}

TriMesh generate_rectangle_impl(Vec2 lo, Vec2 hi, double h) {
  const Vec2 d = hi - lo;
  if (!(d.x > 0.0 && d.y > 0.0) || !std::isfinite(d.x + d.y))
    throw std::invalid_argument("tetia: generate_rectangle: need lo < hi in every coordinate");
  return generate<TriMesh>("generate_rectangle", h, d.x * d.y,
                           [&] { gmsh::model::occ::addRectangle(lo.x, lo.y, 0.0, d.x, d.y); });
}

TriMesh generate_disk_impl(Vec2 center, double radius, double h) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !std::isfinite(center.x + center.y))
    throw std::invalid_argument("tetia: generate_disk: need a finite center and a positive radius");
  return generate<TriMesh>("generate_disk", h, std::numbers::pi * radius * radius,
                           [&] { gmsh::model::occ::addDisk(center.x, center.y, 0.0, radius, radius); });
}

TriMesh generate_annulus_impl(Vec2 center, double inner_radius, double outer_radius, double h) {
  if (!(inner_radius > 0.0 && outer_radius > inner_radius) || !std::isfinite(outer_radius) ||
      !std::isfinite(center.x + center.y))
    throw std::invalid_argument("tetia: generate_annulus: need 0 < inner radius < outer radius");
  return generate<TriMesh>(
      "generate_annulus", h, std::numbers::pi * (outer_radius * outer_radius - inner_radius * inner_radius), [&] {
        const int outer = gmsh::model::occ::addDisk(center.x, center.y, 0.0, outer_radius, outer_radius);
        const int inner = gmsh::model::occ::addDisk(center.x, center.y, 0.0, inner_radius, inner_radius);
        std::vector<std::pair<int, int>> out;
        std::vector<std::vector<std::pair<int, int>>> out_map;
        gmsh::model::occ::cut({{2, outer}}, {{2, inner}}, out, out_map);
      });
}

}  // namespace

}  // namespace tetia

// The module's one export (gmsh_module.hpp).
extern "C" __attribute__((visibility("default"))) const tetia::detail::GmshModule* tetia_gmsh_module() {
  static const tetia::detail::GmshModule m{tetia::detail::kGmshModuleVersion,
                                           tetia::generate_box_impl,
                                           tetia::generate_ball_impl,
                                           tetia::generate_torus_impl,
                                           tetia::generate_rectangle_impl,
                                           tetia::generate_disk_impl,
                                           tetia::generate_annulus_impl,
                                           tetia::read_any_mesh_impl,
                                           tetia::read_msh_field_impl};
  return &m;
}
