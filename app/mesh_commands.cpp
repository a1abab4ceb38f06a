// app/mesh_commands.cpp -- `tetia supermesh` and `tetia demo`, for tetrahedral (3D) and
// triangular (2D) meshes alike: the dimension comes from the files (tetrahedra: 3, else
// triangles: 2; read_any_mesh), both files must have the same one, and everything after reading
// is one template over the mesh type. JSON keys follow the dimension: *_volume in 3D, *_area
// in 2D, plus "dimension". `tetia remap` and `tetia apply`: app/remap_command.cpp; what they
// share: app/command_support.hpp.
#include "mesh_commands.hpp"

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "command_support.hpp"
#include "mpi_mode.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::app {
namespace {

// The supermesh's pieces as simplices sharing each piece's corners, for ParaView (VTU) or Gmsh
// (.msh): Int64 cell data "piece" (the index of the piece's pair of file cells: the pieces of a
// split hexahedron's tetrahedra with the same target file cell are one), "source" and "target"
// (the file's tags of its two cells), and Float64 "simplex_volume" (area): each simplex's own
// measure, so that summing it over the file gives the intersection's total (the piece's measure
// is the sum over its simplices). piece_pair: file_cell_pairs's, or null where nothing is split
// (each piece its own pair).
template <class Mesh>
void write_supermesh_file(const std::string& file, const typename Kind<Mesh>::Result& s,
                          const std::vector<std::int32_t>* piece_pair, VtuFormat format, int threads) {
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
      piece.push_back(piece_pair ? (*piece_pair)[k] : static_cast<std::int64_t>(k));
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

CandidateSearch parse_search(const std::string& s) {
  if (s == "front") return CandidateSearch::front;
  if (s == "rtree") return CandidateSearch::rtree;
  throw std::invalid_argument("tetia: --search must be front or rtree, not '" + s + "'");
}

template <class Mesh>
int supermesh_command(const SupermeshCommand& cmd, const Mesh& source, const Mesh& target, const std::string& extra) {
  using K = Kind<Mesh>;
  SupermeshOptions options;
  options.search = parse_search(cmd.search);
  options.threads = cmd.threads;
  options.progress = intersection_progress(source.num_cells());
  const auto s = parallel_supermesh(borrow(source), borrow(target), options, cmd.partition);
  // Pairs of file cells: summed where cells were split; otherwise they are the pieces, which
  // file_cell_pairs would copy (a tenth of the command's time on 10^5 pieces).
  const bool split = !source.cell_origin.empty() || !target.cell_origin.empty();
  decltype(file_cell_pairs(s)) pairs;
  if (split) pairs = file_cell_pairs(s);
  const std::size_t num_pairs = split ? pairs.pairs.size() : s.pieces.size();
  if (!cmd.output.empty()) {
    progress("writing " + cmd.output);
    write_supermesh_file<Mesh>(cmd.output, s, split ? &pairs.piece_pair : nullptr,
                               cmd.ascii ? VtuFormat::ascii : VtuFormat::binary, cmd.threads);
  }
  const std::string m = K::measure;
  Progress::get().finish();
  std::printf(
      "{\"dimension\": %d, \"source_cells\": %zu, \"target_cells\": %zu, %s, \"candidates\": %zu, \"pairs\": %zu, "
      "\"simplex_pairs\": %zu, \"source_%s\": %s, \"target_%s\": %s, \"intersection_%s\": %s%s, \"seconds\": %.6f}\n",
      K::dim, source.num_file_cells(), target.num_file_cells(), simplices_json(source, target).c_str(), s.candidates,
      num_pairs, s.pieces.size(), m.c_str(),
      num(K::total(source), "source total").c_str(), m.c_str(), num(K::total(target), "target total").c_str(),
      m.c_str(), num(K::total(s), "intersection total").c_str(), extra.c_str(), s.seconds);
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
      const double oi = overlap_integral<Mesh>(s, in, order == 0 ? Location::cells : Location::nodes);
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
