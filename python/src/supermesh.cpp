// python/src/supermesh.cpp -- tetia.supermesh: every pair of overlapping cells of two meshes,
// per file cell (tetia::file_cell_pairs: a hexahedron's tetrahedra are one cell), as arrays.
//
// The total is the C++ Supermesh::intersection_volume() (intersection_area() in 2D): the
// compensated sum over the pieces, bit for bit what `tetia supermesh` prints. The GIL is released
// while the supermesh is built (OpenMP threads as in C++).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <optional>
#include <type_traits>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "options.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::python {

namespace {

/// The pairs of file cells as arrays, and the totals; the same for both dimensions.
template <class Result>
py::dict pairs_of(const Result& s) {
  constexpr bool three = std::is_same_v<Result, Supermesh>;
  constexpr std::size_t dim = three ? 3 : 2;
  const auto f = file_cell_pairs(s);
  const std::size_t n = f.pairs.size();
  std::vector<std::int64_t> source(n), target(n);
  std::vector<double> measure(n), centroid(dim * n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto& p = f.pairs[k];
    source[k] = p.source;
    target[k] = p.target;
    if constexpr (three) {
      measure[k] = p.volume;
      const Vec3 c = Moments{p.volume, p.first}.centroid();
      std::copy_n(std::array<double, 3>{c.x, c.y, c.z}.begin(), 3, centroid.begin() + static_cast<std::ptrdiff_t>(3 * k));
    } else {
      measure[k] = p.area;
      const Vec2 c = Moments2{p.area, p.first}.centroid();
      std::copy_n(std::array<double, 2>{c.x, c.y}.begin(), 2, centroid.begin() + static_cast<std::ptrdiff_t>(2 * k));
    }
  }
  py::dict d;
  d["source_cell"] = to_array(std::move(source));
  d["target_cell"] = to_array(std::move(target));
  d["volume"] = to_array(std::move(measure));
  d["centroid"] = to_array(std::move(centroid), {static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(dim)});
  if constexpr (three)
    d["intersection_volume"] = s.intersection_volume();
  else
    d["intersection_volume"] = s.intersection_area();
  d["candidates"] = s.candidates;
  d["seconds"] = s.seconds;
  d["pieces"] = s.pieces.size();
  return d;
}

}  // namespace

void bind_supermesh(py::module_& m) {
  m.def(
      "supermesh",
      [](const MeshHandle& source, const MeshHandle& target, const std::string& search, std::optional<int> threads) {
        check_same_dimension(source, target, "supermesh");
        const SupermeshOptions options = supermesh_options(search, threads);
        if (source.dim() == 3) {
          Supermesh s;
          {
            py::gil_scoped_release release;
            s = supermesh(std::get<0>(source.mesh), std::get<0>(target.mesh), options);
          }
          return pairs_of(s);
        }
        Supermesh2 s;
        {
          py::gil_scoped_release release;
          s = supermesh(std::get<1>(source.mesh), std::get<1>(target.mesh), options);
        }
        return pairs_of(s);
      },
      py::arg("source"), py::arg("target"), py::arg("search") = "front", py::arg("threads") = py::none(),
      "The overlapping pairs of file cells of two meshes of one dimension, as a dict of arrays.");
}

}  // namespace tetia::python
