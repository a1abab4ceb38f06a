// app/remap_command.cpp -- `tetia remap` (a field from one mesh to another by one of the methods
// of app/remap_method.hpp, with coverage and, for the linear methods, the operator saved) and
// `tetia apply` (a saved operator applied without the supermesh), for tetrahedral and
// triangular meshes alike, as app/mesh_commands.cpp describes.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "command_support.hpp"
#include "file_operator.hpp"
#include "mesh_commands.hpp"
#include "mpi_mode.hpp"
#include "operator_file.hpp"
#include "remap_method.hpp"
#include "tetia/remap_methods.hpp"
#include "tetia/remap_operator.hpp"

namespace tetia::app {
namespace {

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

// What remap_command takes from the supermesh: per component, the remapped values (per target
// file cell for cell averages, per node for P1, per simplex and vertex for discontinuous P1) and
// the source integral over the overlap; the coverage; the largest CG iteration count; and the
// supermesh's counts.
struct Remapped {
  std::vector<std::vector<double>> values;  // where the output has them: file cells, nodes, cells' vertices
  std::vector<double> overlap;
  std::vector<double> cell_coverage;  // per target simplex (tetia::cell_coverage)
  std::vector<double> node_coverage;  // per target node (tetia::p1_node_coverage), continuous P1 only
  int iterations = 0;
  std::size_t pairs = 0, pieces = 0;  // of file cells, of simplices
  double total = 0.0, seconds = 0.0;  // intersection measure, supermesh time
};

// P1 without keeping the supermesh (tetia::P1Loads): besides the loads, the pieces handed over
// (in the order of a kept supermesh's pieces) give what the kept path takes from the pieces,
// with the same sums in the same order: the intersection measure, the overlap integrals, each
// target cell's covered measure, and the pairs of file cells (a target file cell's pieces are
// consecutive, as file_cell_pairs relies on too). Its last field is one of ones, whose loads
// are the covered part of each basis function's integral (the node coverage's numerator).
template <class Mesh>
class StreamedP1 final : public Kind<Mesh>::Loads {
  using Piece = typename Kind<Mesh>::Piece;

 public:
  StreamedP1(const Mesh& source, const Mesh& target, const std::vector<std::vector<double>>& components,
             const std::vector<double>& ones)
      : Kind<Mesh>::Loads(source, target, spans(components, ones)), source_(source), target_(target),
        components_(components), overlap_(components.size()), covered_(target.num_cells(), 0.0) {}
  void consume(const Piece& p, const double* values) override {
    Kind<Mesh>::Loads::consume(p, values);
    const double m = Kind<Mesh>::measure_of(p);
    total_.add(m);
    covered_[static_cast<std::size_t>(p.target)] += m;
    for (std::size_t c = 0; c < components_.size(); ++c)
      add_overlap(overlap_[c], source_, p, components_[c], Location::nodes);
    const std::size_t tf = target_.file_cell(static_cast<std::size_t>(p.target));
    if (tf != run_target_) flush(tf);
    run_sources_.push_back(source_.file_cell(static_cast<std::size_t>(p.source)));
  }
  // After the supermesh: the counts, sums and coverage into r.
  void finish(Remapped& r) {
    flush(0);
    r.pairs = pairs_;
    r.total = total_.value();
    for (const auto& o : overlap_) r.overlap.push_back(o.value());
    r.cell_coverage = cell_coverage(target_, covered_);
    const Eigen::VectorXd& ones = this->loads().back();
    r.node_coverage = p1_node_coverage(target_, std::span<const double>(ones.data(), static_cast<std::size_t>(ones.size())));
  }

 private:
  static std::vector<std::span<const double>> spans(const std::vector<std::vector<double>>& c,
                                                    const std::vector<double>& ones) {
    std::vector<std::span<const double>> out(c.begin(), c.end());
    out.emplace_back(ones);
    return out;
  }
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
  std::vector<double> covered_;
  detail::CompensatedSum total_;
  std::size_t run_target_ = static_cast<std::size_t>(-1);
  std::vector<std::size_t> run_sources_;
  std::size_t pairs_ = 0;
};

// Every component remapped: by P1 loads handed the pieces (Galerkin P1 without --matrix, one
// process), else from a kept supermesh (the other methods; P1 with --matrix, which needs the
// pieces' matrices; several MPI ranks, whose pieces are gathered), with the same results bit
// for bit.
template <class Mesh>
Remapped remap_components(const RemapCommand& cmd, Method method, const Mesh& source, const Mesh& target,
                          const std::vector<std::vector<double>>& components) {
  using K = Kind<Mesh>;
  SupermeshOptions options;
  options.threads = cmd.threads;
  options.progress = intersection_progress(source.num_cells());
  Remapped r;
  if (method == Method::p1 && cmd.matrix.empty() && (K::dim == 2 || mpi_ranks() == 1)) {
    const std::vector<double> ones(source.num_nodes(), 1.0);
    StreamedP1<Mesh> loads(source, target, components, ones);
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
  // Every method but the cell averages needs each piece's local mixed mass matrix (not the
  // polyhedron itself).
  options.keep_mixed_mass = needs_mixed_mass(method);
  auto kept = parallel_supermesh(borrow(source), borrow(target), options, cmd.partition);
  const auto pairs = file_cell_pairs(kept);
  progress(cmd.order == 0 ? "remap" : "solve");
  if (!cmd.matrix.empty()) {
    if (cmd.order == 0) write_p0_matrix(cmd.matrix, kept, pairs, K::measure);
    else write_mixed_mass_matrix(kept, cmd.matrix);
  }
  // The library's operator (tetia/remap_operator.hpp) on the kept supermesh: the linear methods
  // are its matrix applied (what --save-operator writes and `tetia apply` applies, bit for
  // bit), the others its apply().
  const Normalize normalize = parse_normalize(cmd.normalize, method);
  const BasicRemap<Mesh> remap(std::move(kept), cmd.order,
                               normalize == Normalize::covered ? P0Normalization::covered_volume
                                                               : P0Normalization::cell_volume,
                               library_method(method));
  const auto& s = remap.supermesh();
  r.cell_coverage = cell_coverage(s);
  const Location from = source_location(method), to = target_location(method);
  if (to == Location::nodes) r.node_coverage = remap.node_coverage();
  const SparseMatrix w = has_operator(method) ? remap.matrix() : SparseMatrix();
  for (const auto& component : components) {
    const std::vector<double> columns = operator_columns(source, from, component);
    P1RemapReport report;
    r.values.push_back(has_operator(method) ? apply_operator(w, columns) : remap.apply(columns, 1, &report));
    r.iterations = std::max(r.iterations, report.iterations);
    r.overlap.push_back(overlap_integral<Mesh>(s, component, from));
  }
  if (!cmd.save_operator.empty()) {
    progress("writing " + cmd.save_operator);
    OperatorFile op;
    op.dimension = K::dim;
    op.method = method_name(method);
    op.normalize = cmd.normalize;
    op.rows = to;
    op.columns = from;
    op.weights = w;
    if (is_esmf_path(cmd.save_operator))
      add_esmf_measures<Mesh>(op, s, remap.coverage(), r.node_coverage, r.cell_coverage);
    write_operator(cmd.save_operator, op);
  }
  r.pairs = pairs.pairs.size();
  r.pieces = s.pieces.size();
  r.total = K::total(s);
  r.seconds = s.seconds;
  return r;
}

// A field's values where the method takes them (per source simplex, node, or simplex and
// vertex) from the expression: cell averages (a file cell's average on each of its simplices),
// node values, or the node values at each cell's vertices.
template <class Mesh>
std::vector<double> expression_values(const Mesh& m, Location where, const Function<Mesh>& f) {
  switch (where) {
    case Location::cells: return spread_to_simplices(m, file_cell_average(m, average_over_cells(m, f)));
    case Location::nodes: return node_values(m, f);
    case Location::cell_nodes: return discontinuous_from_nodes(m, node_values(m, f));
  }
  return {};
}

template <class Mesh>
double integral_at(const Mesh& m, const std::vector<double>& v, Location where) {
  switch (where) {
    case Location::cells: return integral_p0(m, v);
    case Location::nodes: return integral_p1(m, v);
    case Location::cell_nodes: return integral_discontinuous(m, v);
  }
  return 0.0;
}

template <class Mesh>
double l2_error_at(const Mesh& m, const std::vector<double>& v, Location where, const Function<Mesh>& f) {
  switch (where) {
    case Location::cells: return l2_error_p0(m, v, f);
    case Location::nodes: return l2_error_p1(m, v, f);
    case Location::cell_nodes: return l2_error_discontinuous(m, v, f);
  }
  return 0.0;
}

// The coverage of what carries the target's values, as the JSON reports it: how many are not
// covered at all, how many partly (below 1 - 1e-12: above the rounding of a fully covered
// one's sum of pieces), and the least fraction.
struct CoverageSummary {
  const char* of = "cells";
  std::size_t uncovered = 0, partly = 0;
  double least = 1.0;
};
CoverageSummary summarize_coverage(const std::vector<double>& fractions, const char* of) {
  CoverageSummary c;
  c.of = of;
  for (const double f : fractions) {
    if (f == 0.0) ++c.uncovered;
    else if (f < 1.0 - 1e-12) ++c.partly;
    c.least = std::min(c.least, f);
  }
  if (fractions.empty()) c.least = 0.0;
  return c;
}

// An output file's fields by where they live: cell data (per file cell, or per simplex where
// the output has the simplices), node data, element-node data (discontinuous fields).
struct OutputFields {
  std::vector<Field> cells, nodes, cell_nodes;
  void add(Location where, Field field) {
    (where == Location::cells ? cells : where == Location::nodes ? nodes : cell_nodes).push_back(std::move(field));
  }
};

// --uncovered on one component: the values of the entities nothing covers replaced.
template <class Uncovered_, class Kept>
void replace_uncovered(std::vector<double>& values, Uncovered policy, const Uncovered_& is_uncovered, const Kept& kept) {
  if (policy == Uncovered::flag) return;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!is_uncovered(i)) continue;
    if (policy == Uncovered::nan) values[i] = std::numeric_limits<double>::quiet_NaN();
    else if (policy == Uncovered::zero) values[i] = 0.0;
    else values[i] = kept(i);
  }
}

// The target with its remapped fields: Gmsh .msh 4.1 if the name ends in .msh (discontinuous
// fields as element-node data), else VTU, where a discontinuous field is cell data with its
// (d + 1) x components values per simplex, vertex-major (the value at the cell's vertex k,
// component j, at k * components + j), and the cells are the simplices if the target has split
// cells (`per_simplex`; its cell data then per simplex too).
template <class Mesh>
void write_result_file(const std::string& file, const Mesh& target, OutputFields out, bool per_simplex, bool ascii,
                       int threads) {
  progress("writing " + file);
  if (is_msh_path(file)) {
    write_msh(file, target, out.cells, out.nodes, out.cell_nodes);
    return;
  }
  for (Field& dg : out.cell_nodes) {
    dg.components *= Kind<Mesh>::dim + 1;
    out.cells.push_back(std::move(dg));
  }
  VtuOptions vtu;
  vtu.format = ascii ? VtuFormat::ascii : VtuFormat::binary;
  vtu.threads = threads;
  vtu.simplices = per_simplex;
  write_vtu(file, target, out.cells, out.nodes, vtu);
}

// A usage error for a discontinuous result that a .msh file cannot hold (element-node data are
// per element, the result per simplex of a split cell).
template <class Mesh>
void check_discontinuous_output(const Mesh& target, Location to, const std::string& output) {
  if (to == Location::cell_nodes && !target.cell_origin.empty() && is_msh_path(output))
    throw std::invalid_argument("tetia: " + output + ": a discontinuous P1 result on a target with hexahedra, prisms, " +
                                "pyramids or quadrilaterals is per simplex, which a .msh file's element-node data " +
                                "cannot hold: write VTU (its simplices)");
}

template <class Mesh>
int remap_command(const RemapCommand& cmd, const Mesh& source, const Mesh& target, std::vector<Field>&& fields,
                  std::vector<Field>&& target_fields, const std::string& extra) {
  using K = Kind<Mesh>;
  constexpr std::size_t nv = K::dim + 1;
  const Method method = parse_method(cmd.order, cmd.bounded, cmd.lumped, cmd.discontinuous, cmd.reconstruct);
  const Uncovered uncovered = parse_uncovered(cmd.uncovered);
  const Location from = source_location(method), to = target_location(method);
  // A discontinuous result on a target with split cells is written per simplex (VTU only).
  const bool per_simplex = to == Location::cell_nodes && !target.cell_origin.empty();
  // The fields: each named --field (any number of components, at --step), or the expression.
  struct Input {
    std::string name;
    int components = 1;
    std::vector<double> values;  // components per simplex, node, or simplex vertex, in a row
  };
  std::vector<Input> inputs;
  std::unique_ptr<Expression> expr;
  Function<Mesh> f;
  if (!cmd.expr.empty()) {
    expr = std::make_unique<Expression>(cmd.expr);
    f = [&](typename K::Point p) { return (*expr)(p); };
    inputs.push_back({"field", 1, expression_values(source, from, f)});
  } else {
    for (Field& field : fields) inputs.push_back({field.name, field.components, std::move(field.values)});
  }
  // Every component remapped on its own (one solve each for P1); integrals and conservation
  // per component. Every number is formatted before anything is printed (num() fails on one
  // that is not finite), then one line of JSON.
  std::vector<std::vector<double>> components;
  for (const Input& in : inputs)
    for (std::size_t k = 0; k < static_cast<std::size_t>(in.components); ++k)
      components.push_back(component_of(in.values, in.components, k));
  Remapped remapped = remap_components(cmd, method, source, target, components);
  // Coverage per file cell (the volume-weighted average of its simplices' fractions is its
  // covered measure over its measure), or per simplex where the output has the simplices.
  const std::vector<double> coverage =
      per_simplex ? remapped.cell_coverage : file_cell_average(target, remapped.cell_coverage);
  // What carries the values, and whether each is covered at all.
  const std::vector<double>& carrier_coverage =
      to == Location::nodes ? remapped.node_coverage : to == Location::cells ? coverage : remapped.cell_coverage;
  const CoverageSummary summary = summarize_coverage(carrier_coverage, to == Location::nodes ? "nodes" : "cells");
  std::size_t next_component = 0;
  OutputFields output;
  std::string fields_json;
  double first[4] = {0, 0, 0, 0};  // source, overlap, target integral, conservation: the first component
  std::vector<double> first_out;
  for (std::size_t field_index = 0; field_index < inputs.size(); ++field_index) {
    const Input& in = inputs[field_index];
    const auto nc = static_cast<std::size_t>(in.components);
    // Cell averages are per file cell of the target (a hexahedron's value is the volume-weighted
    // average of its tetrahedra's, which is the projection onto constants per hexahedron).
    const std::size_t n_tgt = value_count(target, to);
    std::vector<double> out(n_tgt * nc);
    std::string ints[4];
    for (std::size_t k = 0; k < nc; ++k) {
      const std::size_t c = next_component++;
      const std::vector<double>& component = components[c];
      // The values where the output has them (file cells, nodes, cells' vertices), and per
      // simplex for the integrals and errors below.
      std::vector<double> carried = std::move(remapped.values[c]);
      const std::vector<double> result = to == Location::cells ? spread_to_simplices(target, carried) : carried;
      // Conservation: the target integral against the source integral over the overlap (the
      // whole source integral when the domains coincide), of the remap's values (before
      // --uncovered replaces any).
      const double src_int = integral_at(source, component, from);
      const double tgt_int = integral_at(target, result, to);
      const double overlap_int = remapped.overlap[c];
      const double conservation = std::abs(tgt_int - overlap_int) / std::max(std::abs(overlap_int), 1e-300);
      const double values[4] = {src_int, overlap_int, tgt_int, conservation};
      static const char* const kWhat[4] = {"source integral", "overlap integral", "target integral",
                                           "conservation error"};
      for (int q = 0; q < 4; ++q) ints[q] += (k == 0 ? "" : ", ") + num(values[q], kWhat[q]);
      if (field_index == 0 && k == 0) {
        std::copy(values, values + 4, first);
        first_out = result;
      }
      // --uncovered: what the carriers that nothing covers get (keep: the target's own values
      // where the result has them).
      std::vector<double> kept;
      if (uncovered == Uncovered::keep) {
        const Field& own = target_fields[field_index];
        kept = operator_columns(target, to, component_of(own.values, own.components, k));
      }
      replace_uncovered(
          carried, uncovered,
          [&](std::size_t i) { return carrier_coverage[to == Location::cell_nodes ? i / nv : i] == 0.0; },
          [&](std::size_t i) { return kept[i]; });
      for (std::size_t i = 0; i < n_tgt; ++i) out[i * nc + k] = carried[i];
    }
    fields_json += std::string(fields_json.empty() ? "" : ", ") + "{\"name\": \"" + json_escape(in.name) +
                   "\", \"components\": " + std::to_string(in.components) + ", \"source_integral\": [" + ints[0] +
                   "], \"overlap_integral\": [" + ints[1] + "], \"target_integral\": [" + ints[2] +
                   "], \"conservation_error\": [" + ints[3] + "]}";
    output.add(to, {in.name, std::move(out), in.components});
  }
  double error = -1.0, relative = -1.0;
  if (f) {
    std::vector<double> exact = to == Location::cells ? file_cell_average(target, average_over_cells(target, f))
                                                      : expression_values(target, to, f);
    output.add(to, {"exact", std::move(exact)});
    error = l2_error_at(target, first_out, to, f);
    const double norm = l2_norm(target, f);
    relative = norm > 0.0 ? error / norm : error;
  }
  output.add(Location::cells, {"covered_fraction", coverage});
  if (to == Location::nodes) output.add(Location::nodes, {"node_covered_fraction", remapped.node_coverage});
  const std::string m = K::measure;
  const std::string totals[3] = {num(K::total(source), "source total"), num(K::total(target), "target total"),
                                 num(remapped.total, "intersection total")};
  const std::string integrals[3] = {num(first[0], "source integral"), num(first[1], "overlap integral"),
                                    num(first[2], "target integral")};
  const std::string conservation_text = num(first[3], "conservation error");
  const std::string l2[2] = {f ? num(error, "L2 error") : "null", f ? num(relative, "relative L2 error") : "null"};
  const std::string coverage_json = std::string("{\"of\": \"") + summary.of +
                                    "\", \"uncovered\": " + std::to_string(summary.uncovered) +
                                    ", \"partly_covered\": " + std::to_string(summary.partly) +
                                    ", \"least_fraction\": " + num(summary.least, "least covered fraction") +
                                    ", \"uncovered_values\": \"" + cmd.uncovered + "\"}";
  if (!cmd.output.empty())
    write_result_file(cmd.output, target, std::move(output), per_simplex, cmd.ascii, cmd.threads);
  Progress::get().finish();
  // The default's flag, on stderr whether or not it is a terminal (but for --quiet).
  if (summary.uncovered > 0 && uncovered == Uncovered::flag && !cmd.quiet)
    std::fprintf(stderr,
                 "tetia: %zu target %s are not covered by the source (covered_fraction 0): they have the method's "
                 "value (0 for averages); choose another with --uncovered nan|zero|keep\n",
                 summary.uncovered, summary.of);
  std::printf(
      "{\"dimension\": %d, \"order\": %d, \"method\": \"%s\", \"normalize\": \"%s\", \"source_cells\": %zu, "
      "\"target_cells\": %zu, %s, \"pairs\": %zu, \"simplex_pairs\": %zu, "
      "\"source_%s\": %s, \"target_%s\": %s, \"intersection_%s\": %s, \"source_integral\": %s, "
      "\"overlap_integral\": %s, \"target_integral\": %s, "
      "\"conservation_error\": %s, \"l2_error\": %s, \"relative_l2_error\": %s, \"cg_iterations\": %d, "
      "\"coverage\": %s, \"fields\": [%s]%s, \"seconds\": %.6f}\n",
      K::dim, cmd.order, method_name(method), cmd.normalize.c_str(), source.num_file_cells(), target.num_file_cells(),
      simplices_json(source, target).c_str(), remapped.pairs, remapped.pieces, m.c_str(), totals[0].c_str(),
      m.c_str(), totals[1].c_str(), m.c_str(), totals[2].c_str(), integrals[0].c_str(), integrals[1].c_str(),
      integrals[2].c_str(), conservation_text.c_str(), l2[0].c_str(), l2[1].c_str(), remapped.iterations,
      coverage_json.c_str(), fields_json.c_str(), extra.c_str(), remapped.seconds);
  return exit_ok;
}

}  // namespace

int run_remap(const RemapCommand& cmd) {
  return guarded([&] {
    Progress::get().configure(progress_mode(cmd.progress, cmd.quiet));
    // The method and its options are checked before any file is read.
    const Method method = parse_method(cmd.order, cmd.bounded, cmd.lumped, cmd.discontinuous, cmd.reconstruct);
    (void)parse_normalize(cmd.normalize, method);
    const Uncovered uncovered = parse_uncovered(cmd.uncovered);
    if (cmd.fields.empty() == cmd.expr.empty())
      throw std::invalid_argument("tetia: give --field NAME (one or more) or --expr EXPRESSION, not both");
    check_distinct_fields(cmd.fields);
    if (uncovered == Uncovered::keep && cmd.fields.empty())
      throw std::invalid_argument(
          "tetia: --uncovered keep gives uncovered target values from the target file's field of the same name: "
          "it needs --field (not --expr)");
    check_writable(cmd.output, "-o");
    check_writable(cmd.matrix, "--matrix");
    if (!cmd.save_operator.empty()) {
      if (!is_operator_path(cmd.save_operator))
        throw std::invalid_argument("tetia: --save-operator " + cmd.save_operator +
                                    ": the name must end in .mtx (Matrix Market) or .nc (ESMF weight file, netCDF)");
      if (!has_operator(method))
        throw std::invalid_argument(
            std::string("tetia: --save-operator: ") +
            (method == Method::p1 ? "the Galerkin P1 operator M_t^-1 M_ts is dense (save --lumped or "
                                    "--discontinuous, or write M_ts with --matrix)"
                                  : "--bounded and --reconstruct linear depend on the field (their limiters): they "
                                    "are not linear operators"));
      check_writable(cmd.save_operator, "--save-operator");
    }
    // The fields are read with the source mesh, in one pass; for --uncovered keep the target's
    // own values too, where the result goes.
    MeshReadOptions options = fields_at(cmd.fields, source_location(method), cmd.step);
    options.corner_nodes = cmd.corner_nodes;
    const MeshReadOptions target_options =
        uncovered == Uncovered::keep ? fields_at(cmd.fields, target_location(method), cmd.step) : MeshReadOptions{};
    Loaded l = load_pair(cmd.source, cmd.target, options, target_options);
    check_kept_components(l, cmd.source, cmd.target);
    const std::string extra = straightened_json(cmd.corner_nodes, l.straightened);
    const auto check_target = [&](const auto& target) {
      check_discontinuous_output(target, target_location(method), cmd.output);
    };
    if (const auto* s3 = std::get_if<TetMesh>(&l.source)) {
      check_target(std::get<TetMesh>(l.target));
      return remap_command(cmd, *s3, std::get<TetMesh>(l.target), std::move(l.source_fields),
                           std::move(l.target_fields), extra);
    }
    check_target(std::get<TriMesh>(l.target));
    return remap_command(cmd, std::get<TriMesh>(l.source), std::get<TriMesh>(l.target), std::move(l.source_fields),
                         std::move(l.target_fields), extra);
  });
}

namespace {

template <class Mesh>
int apply_command(const ApplyCommand& cmd, const OperatorFile& op, const Mesh& source, const Mesh& target,
                  std::vector<Field>&& fields, std::vector<Field>&& target_fields, Uncovered uncovered) {
  using K = Kind<Mesh>;
  if (op.dimension != K::dim)
    throw std::invalid_argument("tetia: " + cmd.op + " is an operator between " + std::to_string(op.dimension) +
                                "D meshes, but " + cmd.source + " is " + std::to_string(K::dim) + "D");
  const auto check = [&](const Mesh& m, Location where, Eigen::Index want, const std::string& file, const char* side) {
    if (value_count(m, where) != static_cast<std::size_t>(want))
      throw std::invalid_argument("tetia: " + cmd.op + " has " + std::to_string(want) + " " + side + " (" +
                                  location_name(where) + "), but " + file + " has " +
                                  std::to_string(value_count(m, where)) + " " + location_name(where) +
                                  ": not the meshes it was saved for");
  };
  check(source, op.columns, op.weights.cols(), cmd.source, "columns");
  check(target, op.rows, op.weights.rows(), cmd.target, "rows");
  // Uncovered values: the rows without entries (nothing of the source reaches them; a
  // discontinuous result's cell has all its vertices' rows empty or none). Counted as remap
  // counts them: per cell for a discontinuous result.
  std::vector<char> empty(static_cast<std::size_t>(op.weights.rows()), 0);
  std::size_t empty_rows = 0;
  for (Eigen::Index r = 0; r < op.weights.outerSize(); ++r) {
    const SparseMatrix::InnerIterator it(op.weights, r);
    if (!it) {
      empty[static_cast<std::size_t>(r)] = 1;
      ++empty_rows;
    }
  }
  if (op.rows == Location::cell_nodes) empty_rows /= K::dim + 1;
  const bool per_simplex = op.rows == Location::cell_nodes && !target.cell_origin.empty();
  OutputFields output;
  std::string fields_json;
  for (std::size_t fi = 0; fi < fields.size(); ++fi) {
    const Field& field = fields[fi];
    const auto nc = static_cast<std::size_t>(field.components);
    std::vector<double> out(static_cast<std::size_t>(op.weights.rows()) * nc);
    std::string integrals;
    for (std::size_t k = 0; k < nc; ++k) {
      const std::vector<double> columns =
          operator_columns(source, op.columns, component_of(field.values, field.components, k));
      std::vector<double> values = apply_operator(op.weights, columns);
      const double integral =
          integral_at(target, op.rows == Location::cells ? spread_to_simplices(target, values) : values, op.rows);
      integrals += (k == 0 ? "" : ", ") + num(integral, "target integral");
      std::vector<double> kept;
      if (uncovered == Uncovered::keep) {
        const Field& own = target_fields[fi];
        kept = operator_columns(target, op.rows, component_of(own.values, own.components, k));
      }
      replace_uncovered(
          values, uncovered, [&](std::size_t i) { return empty[i] != 0; }, [&](std::size_t i) { return kept[i]; });
      for (std::size_t i = 0; i < values.size(); ++i) out[i * nc + k] = values[i];
    }
    fields_json += std::string(fields_json.empty() ? "" : ", ") + "{\"name\": \"" + json_escape(field.name) +
                   "\", \"components\": " + std::to_string(field.components) + ", \"target_integral\": [" +
                   integrals + "]}";
    output.add(op.rows, {field.name, std::move(out), field.components});
  }
  if (!cmd.output.empty())
    write_result_file(cmd.output, target, std::move(output), per_simplex, cmd.ascii, cmd.threads);
  Progress::get().finish();
  if (empty_rows > 0 && uncovered == Uncovered::flag && !cmd.quiet)
    std::fprintf(stderr,
                 "tetia: %zu target values have no entries in the operator (nothing covers them): they are 0; "
                 "choose another with --uncovered nan|zero|keep\n",
                 empty_rows);
  std::printf(
      "{\"dimension\": %d, \"method\": \"%s\", \"normalize\": \"%s\", \"rows\": %lld, \"row_values\": \"%s\", "
      "\"columns\": %lld, \"column_values\": \"%s\", \"entries\": %lld, \"uncovered\": %zu, "
      "\"uncovered_values\": \"%s\", \"fields\": [%s]}\n",
      K::dim, json_escape(op.method).c_str(), op.normalize.c_str(), static_cast<long long>(op.weights.rows()),
      location_name(op.rows), static_cast<long long>(op.weights.cols()), location_name(op.columns),
      static_cast<long long>(op.weights.nonZeros()), empty_rows, cmd.uncovered.c_str(), fields_json.c_str());
  return exit_ok;
}

}  // namespace

int run_apply(const ApplyCommand& cmd) {
  return guarded([&] {
    Progress::get().configure(progress_mode(cmd.progress, cmd.quiet));
    const Uncovered uncovered = parse_uncovered(cmd.uncovered);
    if (cmd.fields.empty()) throw std::invalid_argument("tetia: apply: give --field NAME (one or more)");
    check_distinct_fields(cmd.fields);
    check_writable(cmd.output, "-o");
    // The operator's description first (where the fields are), the meshes and fields, then its
    // weights, whose sizes the meshes bound.
    const OperatorFile description = read_operator(cmd.op, 0, true);
    MeshReadOptions options = fields_at(cmd.fields, description.columns, cmd.step);
    options.corner_nodes = cmd.corner_nodes;
    const MeshReadOptions target_options =
        uncovered == Uncovered::keep ? fields_at(cmd.fields, description.rows, cmd.step) : MeshReadOptions{};
    Loaded l = load_pair(cmd.source, cmd.target, options, target_options);
    check_kept_components(l, cmd.source, cmd.target);
    const std::size_t most = std::visit(
        [](const auto& a, const auto& b) {
          std::size_t n = 0;
          for (const Location where : {Location::cells, Location::nodes, Location::cell_nodes})
            n = std::max({n, value_count(a, where), value_count(b, where)});
          return n;
        },
        l.source, l.target);
    progress("reading " + cmd.op);
    const OperatorFile op = read_operator(cmd.op, most);
    if (const auto* s3 = std::get_if<TetMesh>(&l.source)) {
      check_discontinuous_output(std::get<TetMesh>(l.target), op.rows, cmd.output);
      return apply_command(cmd, op, *s3, std::get<TetMesh>(l.target), std::move(l.source_fields),
                           std::move(l.target_fields), uncovered);
    }
    check_discontinuous_output(std::get<TriMesh>(l.target), op.rows, cmd.output);
    return apply_command(cmd, op, std::get<TriMesh>(l.source), std::get<TriMesh>(l.target), std::move(l.source_fields),
                         std::move(l.target_fields), uncovered);
  });
}

}  // namespace tetia::app
