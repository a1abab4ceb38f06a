// python/src/kernels.cpp -- tetia.intersection_volume / intersection_area / intersect: the two
// kernels on one pair or on n pairs, and the polyhedron and polygon they build.
//
// Every volume and area is the C++ call's (tetia::intersection_volume, intersection_area,
// intersect), pair by pair, so Python returns the same doubles bit for bit. Inputs are checked
// here (shape, finiteness: the kernels' contract is any finite input), and the GIL is released
// around each batch.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::python {

namespace {

/// A (4, 3) or (n, 4, 3) array of tetrahedra (corners x coordinates): the array and n (-1 for
/// a single one). The same for triangles, (3, 2) or (n, 3, 2).
struct Simplices {
  Doubles array;
  py::ssize_t count = -1;
};

Simplices simplices(const py::handle& object, const char* what, py::ssize_t corners, py::ssize_t dim) {
  Doubles a = as_doubles(object, what);
  const bool one = a.ndim() == 2 && a.shape(0) == corners && a.shape(1) == dim;
  const bool many = a.ndim() == 3 && a.shape(1) == corners && a.shape(2) == dim;
  if (!one && !many)
    value_error(std::string("tetia: ") + what + ": expected shape (" + std::to_string(corners) + ", " +
                std::to_string(dim) + ") or (n, " + std::to_string(corners) + ", " + std::to_string(dim) +
                "), got " + shape_text(a));
  check_finite(a, what);
  return {a, one ? -1 : a.shape(0)};
}

/// The two arguments of a pairwise call, of the same count.
std::pair<Simplices, Simplices> pair_of(const py::handle& u, const py::handle& v, const char* nu, const char* nv,
                                        py::ssize_t corners, py::ssize_t dim) {
  Simplices a = simplices(u, nu, corners, dim), b = simplices(v, nv, corners, dim);
  if (a.count != b.count)
    value_error(std::string("tetia: ") + nu + " and " + nv + " must have the same shape, got " +
                shape_text(a.array) + " and " + shape_text(b.array));
  return {std::move(a), std::move(b)};
}

Tet tet_at(const double* p) {
  return {Vec3{p[0], p[1], p[2]}, Vec3{p[3], p[4], p[5]}, Vec3{p[6], p[7], p[8]}, Vec3{p[9], p[10], p[11]}};
}

Triangle triangle_at(const double* p) { return {Vec2{p[0], p[1]}, Vec2{p[2], p[3]}, Vec2{p[4], p[5]}}; }

/// Kernel on one pair (a float) or on every pair (an (n,) array), without the GIL.
template <class Shape, class Kernel>
py::object pairwise(const Simplices& a, const Simplices& b, Shape shape_at, Kernel kernel, std::size_t stride) {
  if (a.count < 0) {
    double r;
    {
      py::gil_scoped_release release;
      r = kernel(shape_at(a.array.data()), shape_at(b.array.data()));
    }
    return py::float_(r);
  }
  std::vector<double> out(static_cast<std::size_t>(a.count));
  {
    py::gil_scoped_release release;
    const double* pa = a.array.data();
    const double* pb = b.array.data();
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = kernel(shape_at(pa + stride * i), shape_at(pb + stride * i));
  }
  return to_array(std::move(out));
}

py::array_t<double> points_of(const Polyhedron& p) {
  std::vector<double> xyz;
  for (const Corner& c : p.corners()) xyz.insert(xyz.end(), {c.point.x, c.point.y, c.point.z});
  return to_array(std::move(xyz), {p.num_corners(), 3});
}

}  // namespace

void bind_kernels(py::module_& m) {
  py::class_<Polyhedron>(m, "Polyhedron",
                         "The intersection of two tetrahedra U and V (tetia/polyhedron.hpp). Each corner lies on "
                         "three of the eight planes (its labels: faces 0-3 of U, 4-7 of V, face k opposite vertex "
                         "k); facets are outward oriented cycles of corner indices. Empty: no interior.")
      .def_property_readonly("volume", &Polyhedron::volume)
      .def_property_readonly("centroid",
                             [](const Polyhedron& p) {
                               const Vec3 c = p.centroid();
                               return to_array(std::vector<double>{c.x, c.y, c.z});
                             })
      .def_property_readonly("empty", &Polyhedron::empty)
      .def_property_readonly("points", &points_of, "corners, (k, 3)")
      .def_property_readonly(
          "bary",
          [](const Polyhedron& p) {
            std::vector<double> b;
            for (const Corner& c : p.corners()) b.insert(b.end(), c.bary.begin(), c.bary.end());
            return to_array(std::move(b), {p.num_corners(), 4});
          },
          "barycentric coordinates of the corners in V, (k, 4)")
      .def_property_readonly(
          "labels",
          [](const Polyhedron& p) {
            std::vector<std::uint8_t> l;
            for (const Corner& c : p.corners()) l.insert(l.end(), c.labels.begin(), c.labels.end());
            return to_array(std::move(l), {p.num_corners(), 3});
          },
          "the three planes each corner lies on, ascending, (k, 3)")
      .def_property_readonly(
          "facets",
          [](const Polyhedron& p) {
            py::list facets;
            for (int f = 0; f < p.num_facets(); ++f) {
              const auto idx = p.facet(f);
              facets.append(to_array(std::vector<std::int64_t>(idx.begin(), idx.end())));
            }
            return facets;
          },
          "corner indices of each facet, counter-clockwise seen from outside")
      .def_property_readonly(
          "facet_labels",
          [](const Polyhedron& p) {
            std::vector<std::int64_t> l;
            for (int f = 0; f < p.num_facets(); ++f) l.push_back(p.facet_label(f));
            return to_array(std::move(l));
          },
          "the plane (0-7) each facet lies in")
      .def_property_readonly("touched_faces_of_v", &Polyhedron::touched_faces_of_v)
      .def(
          "tetrahedra",
          [](const Polyhedron& p) {
            const std::vector<Tet> tets = p.tetrahedra();
            std::vector<double> xyz;
            for (const Tet& t : tets)
              for (const Vec3& c : t) xyz.insert(xyz.end(), {c.x, c.y, c.z});
            return to_array(std::move(xyz), {static_cast<py::ssize_t>(tets.size()), 4, 3});
          },
          "positively oriented tetrahedra (a fan from corner 0) whose volumes add up to volume, (m, 4, 3)")
      .def("__len__", &Polyhedron::num_corners)
      .def("__repr__", [](const Polyhedron& p) {
        return "<tetia.Polyhedron: " + std::to_string(p.num_corners()) + " corners, " +
               std::to_string(p.num_facets()) + " facets, volume " + std::string(py::repr(py::float_(p.volume()))) +
               ">";
      });

  py::class_<Polygon>(m, "Polygon",
                      "The intersection of two triangles A and B (tetia/polygon.hpp): corners counter-clockwise, "
                      "each on two of the six lines (labels: edges 0-2 of A, 3-5 of B). Empty: no interior.")
      .def_property_readonly("area", &Polygon::area)
      .def_property_readonly("volume", &Polygon::area, "the area (the measure, as for a Polyhedron)")
      .def_property_readonly("centroid",
                             [](const Polygon& p) {
                               const Vec2 c = p.centroid();
                               return to_array(std::vector<double>{c.x, c.y});
                             })
      .def_property_readonly("empty", &Polygon::empty)
      .def_property_readonly("points",
                             [](const Polygon& p) {
                               std::vector<double> xy;
                               for (const PolygonCorner& c : p.corners()) xy.insert(xy.end(), {c.point.x, c.point.y});
                               return to_array(std::move(xy), {p.num_corners(), 2});
                             })
      .def_property_readonly("bary",
                             [](const Polygon& p) {
                               std::vector<double> b;
                               for (const PolygonCorner& c : p.corners()) b.insert(b.end(), c.bary.begin(), c.bary.end());
                               return to_array(std::move(b), {p.num_corners(), 3});
                             })
      .def_property_readonly("labels",
                             [](const Polygon& p) {
                               std::vector<std::uint8_t> l;
                               for (const PolygonCorner& c : p.corners()) l.insert(l.end(), c.labels.begin(), c.labels.end());
                               return to_array(std::move(l), {p.num_corners(), 2});
                             })
      .def_property_readonly("touched_edges_of_b", &Polygon::touched_edges_of_b)
      .def(
          "triangles",
          [](const Polygon& p) {
            const std::vector<Triangle> tris = p.triangles();
            std::vector<double> xy;
            for (const Triangle& t : tris)
              for (const Vec2& c : t) xy.insert(xy.end(), {c.x, c.y});
            return to_array(std::move(xy), {static_cast<py::ssize_t>(tris.size()), 3, 2});
          },
          "counter-clockwise triangles (a fan from corner 0) whose areas add up to area, (m, 3, 2)")
      .def("__len__", &Polygon::num_corners)
      .def("__repr__", [](const Polygon& p) {
        return "<tetia.Polygon: " + std::to_string(p.num_corners()) + " corners, area " +
               std::string(py::repr(py::float_(p.area()))) + ">";
      });

  m.def(
      "intersection_volume",
      [](const py::object& u, const py::object& v) {
        const auto [a, b] = pair_of(u, v, "U", "V", 4, 3);
        return pairwise(a, b, tet_at, [](const Tet& x, const Tet& y) { return intersection_volume(x, y); }, 12);
      },
      py::arg("U"), py::arg("V"),
      "Volume of the intersection of tetrahedra U and V, each (4, 3): a float; or of n pairs, each (n, 4, 3): "
      "an (n,) array. Bit for bit what tetia::intersection_volume returns.");
  m.def(
      "intersection_area",
      [](const py::object& a, const py::object& b) {
        const auto [x, y] = pair_of(a, b, "A", "B", 3, 2);
        return pairwise(x, y, triangle_at, [](const Triangle& p, const Triangle& q) { return intersection_area(p, q); },
                        6);
      },
      py::arg("A"), py::arg("B"),
      "Area of the intersection of triangles A and B, each (3, 2): a float; or of n pairs, each (n, 3, 2): an (n,) "
      "array. Bit for bit what tetia::intersection_area returns.");
  m.def(
      "intersect",
      [](const py::object& u, const py::object& v) -> py::object {
        const Doubles probe = as_doubles(u, "U");
        if (probe.ndim() == 2 && probe.shape(0) == 3 && probe.shape(1) == 2) {
          const auto [a, b] = pair_of(u, v, "A", "B", 3, 2);
          if (a.count >= 0) value_error("tetia: intersect: one pair of triangles, (3, 2) each");
          Polygon p;
          {
            py::gil_scoped_release release;
            p = intersect(triangle_at(a.array.data()), triangle_at(b.array.data()));
          }
          return py::cast(p);
        }
        const auto [a, b] = pair_of(u, v, "U", "V", 4, 3);
        if (a.count >= 0) value_error("tetia: intersect: one pair of tetrahedra, (4, 3) each");
        Polyhedron p;
        {
          py::gil_scoped_release release;
          p = intersect(tet_at(a.array.data()), tet_at(b.array.data()));
        }
        return py::cast(p);
      },
      py::arg("U"), py::arg("V"),
      "The intersection of two tetrahedra ((4, 3) each) as a Polyhedron, or of two triangles ((3, 2) each) as a "
      "Polygon.");
}

}  // namespace tetia::python
