// app/remap_method.hpp -- which remap `tetia remap` runs (its --order, --bounded, --lumped,
// --discontinuous and --reconstruct flags), where its fields live on the source and on the
// target, and what it supports: one place for the rules the command checks before any work.
#pragma once

#include <stdexcept>
#include <string>

#include "tetia/remap_operator.hpp"

namespace tetia::app {

enum class Method {
  p0,                     // cell averages (remap_p0)
  p0_linear,              // --order 0 --reconstruct linear (remap_p0_linear)
  p0_from_discontinuous,  // --order 0 --discontinuous: cell averages of a discontinuous P1 source
  p1,                     // --order 1: Galerkin (remap_p1)
  p1_lumped,              // --order 1 --lumped (remap_p1_lumped)
  p1_bounded,             // --order 1 --bounded (remap_p1_bounded)
  p1_discontinuous,       // --order 1 --discontinuous (remap_p1_discontinuous)
};

// The library's name for it (tetia/remap_operator.hpp), with the order.
inline RemapMethod library_method(Method m) {
  switch (m) {
    case Method::p0:
    case Method::p1: return RemapMethod::standard;
    case Method::p0_linear: return RemapMethod::linear_reconstruction;
    case Method::p0_from_discontinuous:
    case Method::p1_discontinuous: return RemapMethod::discontinuous;
    case Method::p1_lumped: return RemapMethod::lumped;
    case Method::p1_bounded: return RemapMethod::bounded;
  }
  return RemapMethod::standard;
}

// Where a field's values are: per cell (cell data), per node (node data), or per cell and
// vertex of the cell (a discontinuous P1 field: Gmsh's element-node data).
enum class Location { cells, nodes, cell_nodes };

// What the supermesh's pieces must keep: the local mixed mass matrices for every method but the
// cell averages and their reconstruction, which use the pieces' measures and first moments only.
inline bool needs_mixed_mass(Method m) { return m != Method::p0 && m != Method::p0_linear; }

inline Location source_location(Method m) {
  switch (m) {
    case Method::p0:
    case Method::p0_linear: return Location::cells;
    case Method::p0_from_discontinuous: return Location::cell_nodes;
    default: return Location::nodes;
  }
}

inline Location target_location(Method m) {
  switch (m) {
    case Method::p0:
    case Method::p0_linear:
    case Method::p0_from_discontinuous: return Location::cells;
    case Method::p1_discontinuous: return Location::cell_nodes;
    default: return Location::nodes;
  }
}

inline const char* method_name(Method m) {
  switch (m) {
    case Method::p0: return "p0";
    case Method::p0_linear: return "p0_linear";
    case Method::p0_from_discontinuous: return "p0_from_discontinuous";
    case Method::p1: return "p1";
    case Method::p1_lumped: return "p1_lumped";
    case Method::p1_bounded: return "p1_bounded";
    case Method::p1_discontinuous: return "p1_discontinuous";
  }
  return "?";
}

// The method the flags name; a combination that names none is a usage error (exit status 2).
inline Method parse_method(int order, bool bounded, bool lumped, bool discontinuous, const std::string& reconstruct) {
  if (reconstruct != "none" && reconstruct != "linear")
    throw std::invalid_argument("tetia: --reconstruct must be none or linear, not '" + reconstruct + "'");
  const bool linear = reconstruct == "linear";
  if (order == 0) {
    if (bounded || lumped)
      throw std::invalid_argument(std::string("tetia: ") + (bounded ? "--bounded" : "--lumped") +
                                  " is a P1 method: give it with --order 1 (cell averages are bounded already)");
    if (linear && discontinuous)
      throw std::invalid_argument(
          "tetia: --reconstruct linear and --discontinuous exclude each other (a discontinuous P1 source is "
          "linear on each cell already)");
    return linear ? Method::p0_linear : discontinuous ? Method::p0_from_discontinuous : Method::p0;
  }
  if (order != 1) throw std::invalid_argument("tetia: --order must be 0 or 1");
  if (linear)
    throw std::invalid_argument("tetia: --reconstruct linear reconstructs cell averages: give it with --order 0");
  if (int(bounded) + int(lumped) + int(discontinuous) > 1)
    throw std::invalid_argument("tetia: give at most one of --bounded, --lumped, --discontinuous");
  return bounded ? Method::p1_bounded : lumped ? Method::p1_lumped : discontinuous ? Method::p1_discontinuous : Method::p1;
}

// How partly covered cells are averaged: by their whole measure (the source counts as zero
// where it does not cover; conservative) or by the covered measure (the average of what covers
// them). Only methods that give averages have the choice: the cell averages and the lumped P1,
// whose nodal value is an average over its basis function's support.
enum class Normalize { full, covered };
inline Normalize parse_normalize(const std::string& s, Method m) {
  if (s != "full" && s != "covered")
    throw std::invalid_argument("tetia: --normalize must be full or covered, not '" + s + "'");
  if (s == "covered" && target_location(m) != Location::cells && m != Method::p1_lumped)
    throw std::invalid_argument(
        "tetia: --normalize covered applies to cell averages (--order 0) and to --lumped; the Galerkin, "
        "bounded and discontinuous P1 projections have no average to renormalize");
  return s == "full" ? Normalize::full : Normalize::covered;
}

// What target cells (P0, discontinuous P1) or nodes (P1) that the source does not cover at all
// get: flag (the default) keeps the method's value (0 for averages) and says how many there
// are, on stderr and in the JSON, besides the covered_fraction arrays of the output; nan, zero
// and keep (the target file's own values of the field) replace it.
enum class Uncovered { flag, nan, zero, keep };
inline Uncovered parse_uncovered(const std::string& s) {
  if (s == "flag") return Uncovered::flag;
  if (s == "nan") return Uncovered::nan;
  if (s == "zero") return Uncovered::zero;
  if (s == "keep") return Uncovered::keep;
  throw std::invalid_argument("tetia: --uncovered must be flag, nan, zero or keep, not '" + s + "'");
}

}  // namespace tetia::app
