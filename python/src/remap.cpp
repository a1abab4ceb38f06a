// python/src/remap.cpp -- the operator behind tetia.Remap: tetia::Remap or tetia::Remap2, built
// once (the supermesh and the matrices, without the GIL), applied to many fields, with any of
// its methods (tetia::RemapMethod).
//
// apply() is the C++ BasicRemap::apply, bit for bit, and const: two Python threads may apply
// one operator at once (the GIL is released while it runs). The matrices leave as CSR triples
// (data, indices, indptr, shape) that tetia/remap.py makes SciPy matrices of, so the extension
// does not depend on SciPy.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "options.hpp"
#include "tetia/remap.hpp"
#include "tetia/remap_operator.hpp"

namespace tetia::python {

namespace {

struct RemapHandle {
  std::variant<std::shared_ptr<const Remap>, std::shared_ptr<const Remap2>> remap;
  template <class F>
  auto visit(F f) const {
    return std::visit([&](const auto& r) { return f(*r); }, remap);
  }
};

RemapMethod method_of(const std::string& method) {
  if (method == "standard") return RemapMethod::standard;
  if (method == "lumped") return RemapMethod::lumped;
  if (method == "bounded") return RemapMethod::bounded;
  if (method == "discontinuous") return RemapMethod::discontinuous;
  if (method == "linear") return RemapMethod::linear_reconstruction;
  value_error("tetia: Remap: method must be \"standard\", \"lumped\", \"bounded\", \"discontinuous\" or "
              "\"linear\", not \"" + method + "\"");
}

RemapHandle make_remap(const MeshHandle& source, const MeshHandle& target, int order, const std::string& method,
                       const std::string& normalization, const std::string& search, std::optional<int> threads) {
  check_same_dimension(source, target, "Remap");
  if (order != 0 && order != 1) value_error("tetia: Remap: order must be 0 or 1, not " + std::to_string(order));
  RemapOptions options;
  options.order = order;
  options.method = method_of(method);
  if ((options.method == RemapMethod::lumped || options.method == RemapMethod::bounded) && order != 1)
    value_error("tetia: Remap: method \"" + method + "\" is P1: give order=1");
  if (options.method == RemapMethod::linear_reconstruction && order != 0)
    value_error("tetia: Remap: method \"linear\" reconstructs cell averages: give order=0");
  if (normalization == "cell_volume")
    options.normalization = P0Normalization::cell_volume;
  else if (normalization == "covered_volume")
    options.normalization = P0Normalization::covered_volume;
  else
    value_error("tetia: Remap: normalization must be \"cell_volume\" or \"covered_volume\", not \"" + normalization +
                "\"");
  options.supermesh = supermesh_options(search, threads);
  RemapHandle h;
  py::gil_scoped_release release;
  if (source.dim() == 3)
    h.remap = std::make_shared<const Remap>(std::get<0>(source.mesh), std::get<0>(target.mesh), options);
  else
    h.remap = std::make_shared<const Remap2>(std::get<1>(source.mesh), std::get<1>(target.mesh), options);
  return h;
}

py::tuple csr(const SparseMatrix& a) {
  SparseMatrix m = a;
  m.makeCompressed();
  const auto nnz = static_cast<std::size_t>(m.nonZeros());
  std::vector<double> data(m.valuePtr(), m.valuePtr() + nnz);
  std::vector<std::int64_t> indices(m.innerIndexPtr(), m.innerIndexPtr() + nnz);
  std::vector<std::int64_t> indptr(m.outerIndexPtr(), m.outerIndexPtr() + m.outerSize() + 1);
  return py::make_tuple(to_array(std::move(data)), to_array(std::move(indices)), to_array(std::move(indptr)),
                        py::make_tuple(m.rows(), m.cols()));
}

/// The field as (values, components), checked against the operator's columns.
std::pair<Doubles, int> field_of(const RemapHandle& h, const py::object& u) {
  Doubles a = as_doubles(u, "field");
  const auto cols = static_cast<py::ssize_t>(h.visit([](const auto& r) { return r.cols(); }));
  const int order = h.visit([](const auto& r) { return r.order(); });
  const bool vertices = order == 0 && h.visit([](const auto& r) { return r.method() == RemapMethod::discontinuous; });
  const char* per = vertices ? "cell vertex" : order == 0 ? "cell" : "node";
  if (a.ndim() != 1 && a.ndim() != 2)
    value_error("tetia: Remap: the field must have shape (n,) or (n, k), got " + shape_text(a));
  if (a.shape(0) != cols)
    value_error("tetia: Remap: the field has " + std::to_string(a.shape(0)) + " rows, but the source has " +
                std::to_string(cols) + " " + per + "s (order " + std::to_string(order) + ": one value per source " +
                per + ")");
  if (a.ndim() == 2 && a.shape(1) < 1) value_error("tetia: Remap: the field has no components, shape " + shape_text(a));
  check_finite(a, "field");
  return {a, a.ndim() == 1 ? 1 : static_cast<int>(a.shape(1))};
}

py::object apply(const RemapHandle& h, const py::object& u, bool with_report) {
  const auto field = field_of(h, u);
  const Doubles& a = field.first;
  const int components = field.second;
  const bool vector = a.ndim() == 2;
  std::vector<double> out;
  P1RemapReport report;
  {
    py::gil_scoped_release release;
    out = h.visit([&](const auto& r) {
      return r.apply(std::span<const double>(a.data(), static_cast<std::size_t>(a.size())), components, &report);
    });
  }
  const auto rows = static_cast<py::ssize_t>(out.size() / static_cast<std::size_t>(components));
  py::array_t<double> result = vector ? to_array(std::move(out), {rows, components}) : to_array(std::move(out));
  if (!with_report) return py::object(std::move(result));
  py::dict r;
  r["iterations"] = report.iterations;
  r["residual"] = report.residual;
  return py::make_tuple(result, r);
}

// tetia::remap_p1 from two meshes: the supermesh is handed to P1Loads, not kept. Components of
// u, (n,) or (n, k), are remapped each on its own, bit for bit as RemapHandle::apply does.
py::object remap_p1_streamed(const MeshHandle& source, const MeshHandle& target, const py::object& u,
                             const std::string& search, std::optional<int> threads, bool with_report) {
  check_same_dimension(source, target, "remap_p1");
  const SupermeshOptions options = supermesh_options(search, threads);
  const std::size_t nodes = std::visit([](const auto& m) { return m->num_nodes(); }, source.mesh);
  const std::size_t rows = std::visit([](const auto& m) { return m->num_nodes(); }, target.mesh);
  Doubles a = as_doubles(u, "field");
  if (a.ndim() != 1 && a.ndim() != 2)
    value_error("tetia: remap_p1: the field must have shape (n,) or (n, k), got " + shape_text(a));
  if (static_cast<std::size_t>(a.shape(0)) != nodes)
    value_error("tetia: remap_p1: the field has " + std::to_string(a.shape(0)) + " rows, but the source has " +
                std::to_string(nodes) + " nodes (one value per source node)");
  if (a.ndim() == 2 && a.shape(1) < 1) value_error("tetia: remap_p1: the field has no components, shape " + shape_text(a));
  check_finite(a, "field");
  const auto k = static_cast<std::size_t>(a.ndim() == 1 ? 1 : a.shape(1));
  std::vector<std::vector<double>> fields(k, std::vector<double>(nodes));
  for (std::size_t i = 0; i < nodes; ++i)
    for (std::size_t c = 0; c < k; ++c) fields[c][i] = a.data()[i * k + c];
  std::vector<std::vector<double>> out;
  std::vector<P1RemapReport> reports;
  {
    py::gil_scoped_release release;
    if (source.dim() == 3)
      out = remap_p1(*std::get<0>(source.mesh), *std::get<0>(target.mesh), fields, options, &reports);
    else
      out = remap_p1(*std::get<1>(source.mesh), *std::get<1>(target.mesh), fields, options, &reports);
  }
  std::vector<double> values(rows * k);
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t c = 0; c < k; ++c) values[i * k + c] = out[c][i];
  const auto rows_i = static_cast<py::ssize_t>(rows), k_i = static_cast<py::ssize_t>(k);
  py::array_t<double> result = a.ndim() == 2 ? to_array(std::move(values), {rows_i, k_i}) : to_array(std::move(values));
  if (!with_report) return py::object(std::move(result));
  py::dict r;  // the last component's solve, as apply reports
  r["iterations"] = reports.back().iterations;
  r["residual"] = reports.back().residual;
  return py::make_tuple(result, r);
}

}  // namespace

void bind_remap(py::module_& m) {
  m.def("remap_p1", &remap_p1_streamed, py::arg("source"), py::arg("target"), py::arg("field"),
        py::arg("search") = "front", py::arg("threads") = py::none(), py::arg("report") = false,
        "P1 remap straight from two meshes: the supermesh is not kept (tetia::P1Loads).");
  py::class_<RemapHandle>(m, "RemapHandle", "tetia::Remap (3D) or tetia::Remap2 (2D), held by tetia.Remap.")
      .def(py::init(&make_remap), py::arg("source"), py::arg("target"), py::arg("order") = 0,
           py::arg("method") = "standard", py::arg("normalization") = "cell_volume", py::arg("search") = "front",
           py::arg("threads") = py::none())
      .def_property_readonly("order", [](const RemapHandle& h) { return h.visit([](const auto& r) { return r.order(); }); })
      .def_property_readonly("rows", [](const RemapHandle& h) { return h.visit([](const auto& r) { return r.rows(); }); })
      .def_property_readonly("cols", [](const RemapHandle& h) { return h.visit([](const auto& r) { return r.cols(); }); })
      .def_property_readonly("intersection_volume",
                             [](const RemapHandle& h) {
                               return h.visit([](const auto& r) {
                                 if constexpr (std::is_same_v<std::decay_t<decltype(r)>, Remap>)
                                   return r.supermesh().intersection_volume();
                                 else
                                   return r.supermesh().intersection_area();
                               });
                             })
      .def("apply", &apply, py::arg("field"), py::arg("report") = false)
      .def("matrix",
           [](const RemapHandle& h) {
             try {
               return csr(h.visit([](const auto& r) { return r.matrix(); }));
             } catch (const std::logic_error& e) {
               value_error(e.what());
             }
           })
      .def("mixed_mass", [](const RemapHandle& h) { return csr(h.visit([](const auto& r) { return r.mixed_mass(); })); })
      .def("target_mass", [](const RemapHandle& h) { return csr(h.visit([](const auto& r) { return r.target_mass(); })); })
      .def("coverage", [](const RemapHandle& h) { return to_array(h.visit([](const auto& r) { return r.coverage(); })); })
      .def("node_coverage", [](const RemapHandle& h) {
        try {
          return to_array(h.visit([](const auto& r) { return r.node_coverage(); }));
        } catch (const std::logic_error& e) {
          value_error(e.what());
        }
      });
}

}  // namespace tetia::python
