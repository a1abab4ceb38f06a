// app/main.cpp -- the `tetia` command line: subcommands over the library.
//
// Exit codes: 0 success (also --help, --version); 1 an I/O error or an algorithm failure;
// 2 a usage error or malformed input (the message says which line).
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "mesh_commands.hpp"
#include "mpi_mode.hpp"
#include "pairs.hpp"

#ifndef TETIA_VERSION
#define TETIA_VERSION "unknown"
#endif

namespace {

using tetia::app::Algorithm;
using tetia::app::Format;

struct PairsCommand {
  std::string algorithm = "tetia";
  std::string format = "volume";
  std::string input = "-";
  int dimension = 3;
};

void add_pairs_command(CLI::App& app, PairsCommand& cmd) {
  CLI::App* sub = app.add_subcommand(
      "pairs", "Intersection volumes of tetrahedron pairs (areas of triangle pairs with --dim 2)\n"
               "read from standard input");
  sub->footer(
      "Input: one pair per line, 24 numbers separated by blanks: U's four vertices (x y z\n"
      "each), then V's. Blank lines and lines starting with '#' are skipped.\n"
      "Output: one line per pair, the volume with 17 significant digits; with --format json\n"
      "an object {\"line\", \"volume\"} and, for --algorithm tetia, \"corners\" (point,\n"
      "bary: barycentric coordinates in V, labels: the three planes, 0-3 faces of U and 4-7\n"
      "faces of V, face k opposite vertex k), \"facets\" (label, corner indices counter-\n"
      "clockwise seen from outside) and \"touched_faces_of_v\" (faces of V the intersection\n"
      "lies on with a facet).\n"
      "Algorithms: tetia, the robust algorithm of McCoid & Gander; clip, Sutherland-Hodgman\n"
      "clipping; pang, PANG-style points and convex hull; exact, GMP rationals rounded to the\n"
      "nearest double (slow).\n"
      "With --dim 2: 12 numbers a line, triangle A's three vertices (x y each), then B's;\n"
      "the output is the area; JSON objects have \"area\", \"corners\" (point, bary in B,\n"
      "labels: the two lines, 0-2 edges of A and 3-5 edges of B, edge k opposite vertex k),\n"
      "counter-clockwise, and \"touched_edges_of_b\".\n"
      "Errors: a line that is not exactly 24 (12) finite numbers stops the run with\n"
      "'tetia: line N: <what is wrong>' on stderr and exit status 2; the lines before it\n"
      "have been printed.");
  sub->add_option("--algorithm", cmd.algorithm, "Which method computes the intersection")
      ->check(CLI::IsMember({"tetia", "clip", "pang", "exact"}))
      ->capture_default_str();
  sub->add_option("--format", cmd.format, "volume: one number per line; json: one object per line")
      ->check(CLI::IsMember({"volume", "json"}))
      ->capture_default_str();
  sub->add_option("--dim", cmd.dimension, "3: tetrahedron pairs, 2: triangle pairs")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  sub->add_option("input", cmd.input, "Read this file instead of standard input ('-')")
      ->capture_default_str();
}

int run_pairs_command(const PairsCommand& cmd) {
  tetia::app::PairsOptions options;
  options.algorithm = *tetia::app::parse_algorithm(cmd.algorithm);  // checked by CLI11
  options.format = *tetia::app::parse_format(cmd.format);
  options.dimension = cmd.dimension;
  if (cmd.input == "-") return tetia::app::run_pairs(options, stdin, stdout, stderr);
  std::FILE* in = std::fopen(cmd.input.c_str(), "rb");
  if (in == nullptr) {
    std::fprintf(stderr, "tetia: cannot open '%s': %s\n", cmd.input.c_str(), std::strerror(errno));
    return tetia::app::exit_bad_input;
  }
  const int rc = tetia::app::run_pairs(options, in, stdout, stderr);
  std::fclose(in);
  return rc;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{
      "tetia: robust tetrahedron-tetrahedron intersection in floating point\n"
      "(McCoid & Gander's algorithm: a real intersection never vanishes through rounding).",
      "tetia"};
  app.set_version_flag("--version", std::string("tetia ") + TETIA_VERSION);
  app.require_subcommand(0, 1);

  PairsCommand pairs;
  add_pairs_command(app, pairs);

  tetia::app::SupermeshCommand sm;
  CLI::App* sm_cmd =
      app.add_subcommand("supermesh", "Intersect two tetrahedral meshes, or two triangular ones (.msh files)");
  sm_cmd->add_option("source", sm.source, "Source mesh (.msh 2.2 or 4.1, ASCII or binary)")->required();
  sm_cmd->add_option("target", sm.target, "Target mesh")->required();
  sm_cmd->add_option("-o,--output", sm.output,
                     "Write the supermesh as VTU: its pieces as simplices, with cell data piece, source and target "
                     "(the files' cell tags) and simplex_volume (simplex_area); Gmsh .msh 4.1 (the same as "
                     "element data) if the name ends in .msh");
  sm_cmd->add_flag("--ascii", sm.ascii, "Write the VTU as text (default: binary, zlib-compressed)");
  sm_cmd->add_flag("--progress", sm.progress, "Show the progress line on stderr even when it is not a terminal");
  sm_cmd->add_flag("--quiet", sm.quiet, "No progress line and no notes on stderr");
  sm_cmd->add_flag("--corner-nodes", sm.corner_nodes,
                   "Read second- and higher-order cells by their corner nodes: straight cells (the JSON then "
                   "has straightened_cells: [source, target])");
  sm_cmd->add_option("--threads", sm.threads, "OpenMP threads (0: default)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  sm_cmd->add_option("--search", sm.search, "Candidate search: front (advancing front; target cells must not overlap) or rtree")
      ->check(CLI::IsMember({"front", "rtree"}))
      ->capture_default_str();
  sm_cmd->add_option("--partition", sm.partition,
                     "Under mpiexec: how the meshes are cut among the ranks: morton (runs along a Morton curve), "
                     "reversed (the target's runs to the ranks in reverse: partitions that do not match), random")
      ->check(CLI::IsMember({"morton", "reversed", "random"}))
      ->capture_default_str();
  sm_cmd->footer("The dimension comes from the files: tetrahedra make a 3D mesh; without them,\n"
                 "triangles (in a plane z = const) a 2D one. Both files must have the same dimension.\n"
                 "Prints a JSON summary: dimension (3 or 2), source_cells, target_cells (the files'\n"
                 "cells: a hexahedron is one), source_simplices, target_simplices (a hexahedron is 6\n"
                 "tetrahedra), candidates, pairs (of file cells that overlap), simplex_pairs, seconds,\n"
                 "and in 3D source_volume, target_volume, intersection_volume, in 2D source_area,\n"
                 "target_area, intersection_area. With -o, each piece's simplices carry piece (its pair\n"
                 "of file cells), source, target (the file cells' tags) and simplex_volume.");

  tetia::app::RemapCommand rm;
  CLI::App* rm_cmd = app.add_subcommand("remap", "Transfer a field conservatively from one mesh to another");
  rm_cmd->add_option("source", rm.source, "Source mesh (.msh)")->required();
  rm_cmd->add_option("target", rm.target, "Target mesh (.msh)")->required();
  rm_cmd->add_option("--field", rm.fields,
                     "A field stored in the source .msh (cell data for --order 0, node data for --order 1); "
                     "repeat for several; vectors and tensors have every component remapped");
  rm_cmd->add_option("--step", rm.step, "The time step of the fields (required when a field has several)");
  rm_cmd->add_option("--expr", rm.expr,
                     "An analytic field in x, y, z (z = 0 in 2D), e.g. \"sin(x)*y\" (muparser syntax)");
  rm_cmd->add_option("--order", rm.order, "0: cell averages (P0); 1: nodal (P1: continuous, or discontinuous)")
      ->check(CLI::IsMember({0, 1}))
      ->capture_default_str();
  rm_cmd->add_flag("--bounded", rm.bounded,
                   "P1 within the local bounds of the source (the least and largest source value on the source cells "
                   "that overlap each node's support): the Galerkin solution corrected by clip-and-assured-sum");
  rm_cmd->add_flag("--lumped", rm.lumped, "P1 by the lumped-mass projection (first order, bounded, conservative)");
  rm_cmd->add_flag("--discontinuous", rm.discontinuous,
                   "With --order 1: the L2 projection onto discontinuous P1 on the target (values per cell and "
                   "vertex); with --order 0: cell averages of a discontinuous P1 source (a --field of element-node "
                   "data)");
  rm_cmd->add_option("--reconstruct", rm.reconstruct,
                     "With --order 0: linear: second-order cell averages by a limited (Barth-Jespersen) least-squares "
                     "gradient per source cell, integrated exactly on each piece")
      ->check(CLI::IsMember({"none", "linear"}))
      ->capture_default_str();
  rm_cmd->add_option("--normalize", rm.normalize,
                     "Averages over partly covered target cells (--order 0, --lumped): full (by the cell's measure: "
                     "the source counts as 0 outside its domain; conservative) or covered (by the covered measure)")
      ->check(CLI::IsMember({"full", "covered"}))
      ->capture_default_str();
  rm_cmd->add_option("--uncovered", rm.uncovered,
                     "Values of target cells (nodes for P1) that the source does not cover at all: flag (the method's "
                     "value, 0 for averages, counted on stderr and in the JSON), nan, zero, or keep (the target "
                     "file's own values of the field)")
      ->check(CLI::IsMember({"flag", "nan", "zero", "keep"}))
      ->capture_default_str();
  rm_cmd->add_option("-o,--output", rm.output,
                     "Write the target mesh with the remapped fields: VTU (node_id and cell_id: the file's "
                     "tags), or Gmsh .msh 4.1 if the name ends in .msh (the file's cells and tags)");
  rm_cmd->add_flag("--ascii", rm.ascii, "Write the VTU as text (default: binary, zlib-compressed)");
  rm_cmd->add_flag("--progress", rm.progress, "Show the progress line on stderr even when it is not a terminal");
  rm_cmd->add_flag("--quiet", rm.quiet, "No progress line and no notes on stderr");
  rm_cmd->add_flag("--corner-nodes", rm.corner_nodes,
                   "Read second- and higher-order cells by their corner nodes: straight cells (the JSON then "
                   "has straightened_cells: [source, target])");
  rm_cmd->add_option("--matrix", rm.matrix, "Write the coupling (mixed mass) matrix in Matrix Market format");
  rm_cmd->add_option("--save-operator", rm.save_operator,
                     "Write the remap operator W (the result is W times the field) for 'tetia apply': Matrix Market "
                     "if the name ends in .mtx, an ESMF weight file (netCDF) if in .nc; for the linear methods: "
                     "--order 0 (also --discontinuous), --lumped, --discontinuous");
  rm_cmd->add_option("--threads", rm.threads, "OpenMP threads (0: default)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  rm_cmd->add_option("--partition", rm.partition,
                     "Under mpiexec: how the meshes are cut among the ranks: morton (runs along a Morton curve), "
                     "reversed (the target's runs to the ranks in reverse: partitions that do not match), random")
      ->check(CLI::IsMember({"morton", "reversed", "random"}))
      ->capture_default_str();
  rm_cmd->footer("Meshes of either dimension (as for supermesh), both the same.\n"
                 "Results are per cell of the files (P0: one value per hexahedron, prism, pyramid,\n"
                 "quadrilateral; the VTU and --matrix have the files' cells).\n"
                 "Prints a JSON summary: dimension, order, source_cells, target_cells,\n"
                 "source_simplices, target_simplices, pairs, simplex_pairs (as for supermesh),\n"
                 "source_volume, target_volume, intersection_volume (in 2D: source_area, target_area,\n"
                 "intersection_area), source_integral, overlap_integral (the source integral over the\n"
                 "overlap), target_integral, conservation_error (target against overlap integral,\n"
                 "relative), l2_error and relative_l2_error (with --expr; else null), cg_iterations\n"
                 "(P1; the most over the components), all of the first field's first component;\n"
                 "method (p0, p0_linear, p0_from_discontinuous, p1, p1_lumped, p1_bounded,\n"
                 "p1_discontinuous), normalize; coverage: of (cells or nodes: what carries the values),\n"
                 "uncovered and partly_covered (how many), least_fraction, uncovered_values;\n"
                 "fields: per field name, components, and per component source_integral,\n"
                 "overlap_integral, target_integral, conservation_error; seconds (the supermesh).\n"
                 "Integrals and errors are of the remap's values, before --uncovered replaces any.\n"
                 "Output: cell data covered_fraction (per file cell: the fraction of its measure the\n"
                 "source covers) and, for continuous P1, point data node_covered_fraction (of each\n"
                 "basis function's integral). A discontinuous P1 result is element-node data in .msh\n"
                 "and, in VTU, cell data with (d + 1) x components values per cell, vertex-major (the\n"
                 "value at the cell's vertex k, component j, at k * components + j); on a target with\n"
                 "hexahedra, prisms, pyramids or quadrilaterals it is per simplex (VTU only).");

  tetia::app::ApplyCommand ap;
  CLI::App* ap_cmd = app.add_subcommand(
      "apply", "Apply a saved remap operator (tetia remap --save-operator) to fields, without the supermesh");
  ap_cmd->add_option("operator", ap.op, "The operator file (.mtx or .nc)")->required();
  ap_cmd->add_option("source", ap.source, "The source mesh with the fields (.msh)")->required();
  ap_cmd->add_option("target", ap.target, "The target mesh (.msh)")->required();
  ap_cmd->add_option("--field", ap.fields, "A field stored in the source .msh (repeat for several)")->required();
  ap_cmd->add_option("--step", ap.step, "The time step of the fields (required when a field has several)");
  ap_cmd->add_option("-o,--output", ap.output, "Write the target with the fields: VTU, or .msh if the name ends in .msh");
  ap_cmd->add_option("--uncovered", ap.uncovered,
                     "Values the operator has no entries for (nothing covers them): flag (0, counted on stderr), nan, "
                     "zero, or keep (the target file's own values of the field)")
      ->check(CLI::IsMember({"flag", "nan", "zero", "keep"}))
      ->capture_default_str();
  ap_cmd->add_flag("--ascii", ap.ascii, "Write the VTU as text (default: binary, zlib-compressed)");
  ap_cmd->add_flag("--progress", ap.progress, "Show the progress line on stderr even when it is not a terminal");
  ap_cmd->add_flag("--quiet", ap.quiet, "No progress line and no notes on stderr");
  ap_cmd->add_flag("--corner-nodes", ap.corner_nodes, "Read higher-order cells by their corner nodes (as remap)");
  ap_cmd->add_option("--threads", ap.threads, "OpenMP threads for the VTU's compression (0: default)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  ap_cmd->footer("The fields are read where the operator's columns are (cells, nodes or cell_nodes:\n"
                 "element data, node data, element-node data) and written where its rows are; the\n"
                 "meshes must be those it was saved for (the counts are checked). The result is bit for\n"
                 "bit what 'tetia remap' computed when it saved the operator. Prints a JSON summary:\n"
                 "dimension, method, normalize, rows, row_values, columns, column_values, entries,\n"
                 "uncovered (rows without entries), uncovered_values, fields (name, components,\n"
                 "target_integral per component, before --uncovered).");

  tetia::app::DemoCommand demo;
  CLI::App* demo_cmd = app.add_subcommand(
      "demo", "The main job on built-in meshes (Gmsh box and ball; with --dim 2 rectangle, disk, annulus)");
  demo_cmd->add_option("-o,--output-dir", demo.output_dir, "Where to write the VTU files")->capture_default_str();
  demo_cmd->add_option("--size", demo.size, "Element size of the finer mesh (default 0.12 in 3D, 0.03 in 2D)");
  demo_cmd->add_option("--dim", demo.dim, "3: tetrahedral meshes, 2: triangular meshes")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  demo_cmd->add_option("--threads", demo.threads, "OpenMP threads (0: default)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : tetia::app::exit_bad_input;
  }

  if (app.got_subcommand("pairs")) return run_pairs_command(pairs);
  if (app.got_subcommand("supermesh")) return tetia::app::run_supermesh(sm);
  if (app.got_subcommand("remap")) return tetia::app::run_remap(rm);
  if (app.got_subcommand("apply")) return tetia::app::run_apply(ap);
  if (app.got_subcommand("demo")) return tetia::app::run_demo(demo);

  std::fputs(app.help().c_str(), stderr);
  std::fputs("tetia: a subcommand is required (see 'tetia pairs --help')\n", stderr);
  return tetia::app::exit_bad_input;
}

// Under mpiexec, ranks other than 0 serve rank 0 (app/mpi_mode.hpp) and return from
// mpi_start(); rank 0 runs the command and tells them its exit status.
int main(int argc, char** argv) {
  if (const auto status = tetia::app::mpi_start(argc, argv)) return *status;
  return tetia::app::mpi_finish(run(argc, argv));
}
