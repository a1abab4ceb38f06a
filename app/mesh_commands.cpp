// app/mesh_commands.cpp -- `tetia supermesh`, `tetia remap`, `tetia demo`.
#include "mesh_commands.hpp"

#include <muParser.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pairs.hpp"
#include "tetia/io.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::app {
namespace {

using Function = std::function<double(Vec3)>;

void progress(const std::string& what) {
  if (isatty(fileno(stderr))) std::fprintf(stderr, "tetia: %s\n", what.c_str());
}

// A field given as an expression in x, y, z (muparser syntax: sin, cos, exp, sqrt, ^, pi).
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

 private:
  mu::Parser parser_;
  double x_ = 0.0, y_ = 0.0, z_ = 0.0;
};

std::vector<double> node_values(const TetMesh& m, const Function& f) {
  std::vector<double> v(m.num_nodes());
  for (std::size_t n = 0; n < m.num_nodes(); ++n) v[n] = f(m.nodes[n]);
  return v;
}

double integral(const TetMesh& m, const std::vector<double>& v, int order) {
  return order == 0 ? integral_p0(m, v) : integral_p1(m, v);
}

double l2_error(const TetMesh& m, const std::vector<double>& v, int order, const Function& f) {
  return order == 0 ? l2_error_p0(m, v, f) : l2_error_p1(m, v, f);
}

double l2_norm(const TetMesh& m, const Function& f) {
  return l2_error_p0(m, std::vector<double>(m.num_cells(), 0.0), f);
}

// The source field integrated over the overlap only, from the pieces: a P0 value times the
// piece's volume, or a P1 field (linear on the source cell) at the piece's centroid times its
// volume, which is exact for a linear function.
double overlap_integral(const Supermesh& s, const std::vector<double>& v, int order) {
  double sum = 0.0;
  for (const SupermeshPiece& p : s.pieces) {
    if (order == 0) {
      sum += v[static_cast<std::size_t>(p.source)] * p.volume;
      continue;
    }
    if (!(p.volume > 0.0)) continue;
    const Vec3 c = (1.0 / p.volume) * p.first;
    const Tet t = s.source->cell(static_cast<std::size_t>(p.source));
    const auto& n = s.source->cells[static_cast<std::size_t>(p.source)];
    const double d = orient3d(t[0], t[1], t[2], t[3]);
    const double l1 = orient3d(t[0], c, t[2], t[3]) / d, l2 = orient3d(t[0], t[1], c, t[3]) / d,
                 l3 = orient3d(t[0], t[1], t[2], c) / d;
    sum += p.volume * ((1.0 - l1 - l2 - l3) * v[n[0]] + l1 * v[n[1]] + l2 * v[n[2]] + l3 * v[n[3]]);
  }
  return sum;
}

// The supermesh's pieces as tetrahedra, for ParaView: cell data "source", "target", "volume".
void write_supermesh_vtu(const std::string& file, const Supermesh& s) {
  TetMesh out;
  std::vector<double> source, target, volume;
  for (std::size_t k = 0; k < s.pieces.size(); ++k) {
    for (const Tet& t : s.polyhedra[k].tetrahedra()) {
      const auto base = static_cast<std::int32_t>(out.nodes.size());
      for (const Vec3& p : t) out.nodes.push_back(p);
      out.cells.push_back({base, base + 1, base + 2, base + 3});
      source.push_back(s.pieces[k].source);
      target.push_back(s.pieces[k].target);
      volume.push_back(s.pieces[k].volume);
    }
  }
  write_vtu(file, out, {{"source", source}, {"target", target}, {"piece_volume", volume}});
}

void write_p0_matrix(const std::string& file, const Supermesh& s) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("tetia: " + file + ": cannot write");
  out << "%%MatrixMarket matrix coordinate real general\n"
      << "% tetia P0 coupling matrix: entry (t, s) = volume of target cell t intersected with source cell s\n"
      << s.target->num_cells() << ' ' << s.source->num_cells() << ' ' << s.pieces.size() << '\n';
  char buf[64];
  for (const auto& p : s.pieces) {
    std::snprintf(buf, sizeof buf, "%.17g", p.volume);
    out << p.target + 1 << ' ' << p.source + 1 << ' ' << buf << '\n';
  }
  if (!out) throw std::runtime_error("tetia: " + file + ": write failed");
}

CandidateSearch parse_search(const std::string& s) {
  if (s == "front") return CandidateSearch::front;
  if (s == "rtree") return CandidateSearch::rtree;
  throw std::invalid_argument("tetia: --search must be front or rtree, not '" + s + "'");
}

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Loads a mesh, reporting progress and ignored elements.
TetMesh load(const std::string& file) {
  progress("reading " + file);
  MeshReadInfo info;
  TetMesh m = read_mesh(file, &info);
  if (info.ignored_elements > 0)
    progress(file + ": " + std::to_string(info.ignored_elements) + " non-tetrahedral elements ignored");
  if (m.reoriented_cells > 0)
    std::fprintf(stderr, "tetia: %s: %zu inverted cells reoriented\n", file.c_str(), m.reoriented_cells);
  if (m.flat_cells > 0)
    std::fprintf(stderr, "tetia: %s: %zu zero-volume cells kept (they intersect nothing)\n", file.c_str(),
                 m.flat_cells);
  return m;
}

template <class Body>
int guarded(Body&& body) {
  try {
    return body();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return exit_bad_input;
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tetia: %s\n", e.what());
    return exit_failure;
  }
}

}  // namespace

int run_supermesh(const SupermeshCommand& cmd) {
  return guarded([&] {
    SupermeshOptions options;
    options.search = parse_search(cmd.search);
    options.threads = cmd.threads;
    options.keep_polyhedra = !cmd.output.empty();
    const TetMesh source = load(cmd.source), target = load(cmd.target);
    progress("intersecting " + std::to_string(source.num_cells()) + " x " + std::to_string(target.num_cells()) +
             " cells");
    const Supermesh s = supermesh(source, target, options);
    if (!cmd.output.empty()) {
      progress("writing " + cmd.output);
      write_supermesh_vtu(cmd.output, s);
    }
    std::printf(
        "{\"source_cells\": %zu, \"target_cells\": %zu, \"candidates\": %zu, \"pairs\": %zu, "
        "\"source_volume\": %s, \"target_volume\": %s, \"intersection_volume\": %s, \"seconds\": %.6f}\n",
        source.num_cells(), target.num_cells(), s.candidates, s.pieces.size(), num(source.total_volume()).c_str(),
        num(target.total_volume()).c_str(), num(s.intersection_volume()).c_str(), s.seconds);
    return exit_ok;
  });
}

int run_remap(const RemapCommand& cmd) {
  return guarded([&] {
    if (cmd.order != 0 && cmd.order != 1) throw std::invalid_argument("tetia: --order must be 0 or 1");
    if (cmd.field.empty() == cmd.expr.empty())
      throw std::invalid_argument("tetia: give exactly one of --field NAME and --expr EXPRESSION");
    const TetMesh source = load(cmd.source), target = load(cmd.target);
    std::vector<double> values;
    std::unique_ptr<Expression> expr;
    Function f;
    if (!cmd.expr.empty()) {
      expr = std::make_unique<Expression>(cmd.expr);
      f = [&](Vec3 p) { return (*expr)(p); };
      values = cmd.order == 0 ? average_over_cells(source, f) : node_values(source, f);
    } else {
      values = read_msh_field(cmd.source, cmd.field, cmd.order == 0);
    }
    SupermeshOptions options;
    options.threads = cmd.threads;
    options.keep_polyhedra = cmd.order == 1;
    const Supermesh s = supermesh(source, target, options);
    P1RemapReport report;
    const std::vector<double> out = cmd.order == 0 ? remap_p0(s, values) : remap_p1(s, values, &report);
    if (!cmd.matrix.empty()) {
      if (cmd.order == 0) write_p0_matrix(cmd.matrix, s);
      else write_mixed_mass_matrix(s, cmd.matrix);
    }
    const std::string name = cmd.expr.empty() ? cmd.field : "field";
    std::vector<Field> cell_data, point_data;
    (cmd.order == 0 ? cell_data : point_data).push_back({name, out});
    double error = -1.0, relative = -1.0;
    if (f) {
      const std::vector<double> exact = cmd.order == 0 ? average_over_cells(target, f) : node_values(target, f);
      (cmd.order == 0 ? cell_data : point_data).push_back({"exact", exact});
      error = l2_error(target, out, cmd.order, f);
      const double norm = l2_norm(target, f);
      relative = norm > 0.0 ? error / norm : error;
    }
    if (!cmd.output.empty()) write_vtu(cmd.output, target, cell_data, point_data);
    // Conservation: the target integral against the source integral over the overlap (the
    // whole source integral when the domains coincide).
    const double src_int = integral(source, values, cmd.order);
    const double tgt_int = integral(target, out, cmd.order);
    const double overlap_int = overlap_integral(s, values, cmd.order);
    const double conservation = std::abs(tgt_int - overlap_int) / std::max(std::abs(overlap_int), 1e-300);
    std::printf(
        "{\"order\": %d, \"source_cells\": %zu, \"target_cells\": %zu, \"pairs\": %zu, \"source_volume\": %s, "
        "\"target_volume\": %s, \"intersection_volume\": %s, \"source_integral\": %s, \"overlap_integral\": %s, "
        "\"target_integral\": %s, "
        "\"conservation_error\": %.3e, \"l2_error\": %s, \"relative_l2_error\": %s, \"cg_iterations\": %d, "
        "\"seconds\": %.6f}\n",
        cmd.order, source.num_cells(), target.num_cells(), s.pieces.size(), num(source.total_volume()).c_str(),
        num(target.total_volume()).c_str(), num(s.intersection_volume()).c_str(), num(src_int).c_str(),
        num(overlap_int).c_str(), num(tgt_int).c_str(), conservation, f ? num(error).c_str() : "null", f ? num(relative).c_str() : "null",
        report.iterations, s.seconds);
    return exit_ok;
  });
}

int run_demo(const DemoCommand& cmd) {
  return guarded([&] {
    namespace fs = std::filesystem;
    fs::create_directories(cmd.output_dir);
    const double h = cmd.size;
    const auto f = [](Vec3 p) { return std::sin(p.x) * std::cos(p.y) * std::exp(p.z); };
    struct Case {
      std::string name;
      TetMesh a, b;
    };
    progress("generating meshes with Gmsh");
    std::vector<Case> cases;
    // Same domain, non-matching: conservation is exact up to rounding.
    cases.push_back({"box/box", generate_box({0, 0, 0}, {1, 1, 1}, 1.6 * h), generate_box({0, 0, 0}, {1, 1, 1}, h)});
    // Different domains: a ball cutting a box; what is conserved is the integral over the overlap.
    cases.push_back({"ball/box", generate_ball({0.5, 0.5, 0.5}, 0.6, 1.3 * h), generate_box({0, 0, 0}, {1, 1, 1}, h)});
    std::printf("%-9s %-5s %5s %9s %9s %9s %8s %10s %10s %12s %11s\n", "meshes", "dir", "order", "src cells",
                "tgt cells", "pairs", "seconds", "overlap", "vol. err", "conservation", "rel. L2 err");
    for (auto& c : cases) {
      const std::string stem = (fs::path(cmd.output_dir) / c.name.substr(0, c.name.find('/'))).string();
      for (int dir = 0; dir < 2; ++dir) {
        const TetMesh& src = dir == 0 ? c.a : c.b;
        const TetMesh& tgt = dir == 0 ? c.b : c.a;
        SupermeshOptions options;
        options.threads = cmd.threads;
        options.keep_polyhedra = true;
        const Supermesh s = supermesh(src, tgt, options);
        // For the same domain the overlap is the mesh volume; for the ball and box it is not known
        // exactly (curved, discretized), so no error is printed there.
        const double vol_err = std::abs(s.intersection_volume() - tgt.total_volume()) / tgt.total_volume();
        for (int order = 0; order < 2; ++order) {
          const std::vector<double> in = order == 0 ? average_over_cells(src, f) : node_values(src, f);
          const std::vector<double> out = order == 0 ? remap_p0(s, in) : remap_p1(s, in);
          const double oi = overlap_integral(s, in, order);
          const double ti = integral(tgt, out, order);
          // The L2 error is only meaningful where the target is covered: same-domain pairs.
          const bool same_domain = c.name == "box/box";
          const double rel = same_domain ? l2_error(tgt, out, order, f) / l2_norm(tgt, f) : 0.0;
          char vol_col[32] = "-", l2_col[32] = "-";
          if (same_domain) {
            std::snprintf(vol_col, sizeof vol_col, "%.2e", vol_err);
            std::snprintf(l2_col, sizeof l2_col, "%.3e", rel);
          }
          std::printf("%-9s %-5s %5d %9zu %9zu %9zu %8.3f %10.6f %10s %12.2e %11s\n", c.name.c_str(),
                      dir == 0 ? "a->b" : "b->a", order, src.num_cells(), tgt.num_cells(), s.pieces.size(),
                      s.seconds, s.intersection_volume(), vol_col, std::abs(ti - oi) / std::abs(oi), l2_col);
          const std::string file = stem + (dir == 0 ? "_a_to_b" : "_b_to_a") + "_p" + std::to_string(order) + ".vtu";
          std::vector<Field> cd, pd;
          (order == 0 ? cd : pd).push_back({"remapped", out});
          (order == 0 ? cd : pd).push_back({"exact", order == 0 ? average_over_cells(tgt, f) : node_values(tgt, f)});
          write_vtu(file, tgt, cd, pd);
        }
      }
    }
    std::printf("field: sin(x) cos(y) exp(z); VTU files in %s/ (open them in ParaView)\n", cmd.output_dir.c_str());
    std::printf("overlap: volume of the supermesh; vol. err: |overlap - mesh volume| / mesh volume (same domain)\n"
                "conservation: |integral on the target - source integral over the overlap| / the latter\n"
                "rel. L2 err: against the exact field, where the target is covered (same-domain pairs)\n");
    return exit_ok;
  });
}

}  // namespace tetia::app
