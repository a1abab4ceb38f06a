// python/src/meshes.cpp -- the mesh handle behind tetia.Mesh: built from arrays
// (tetia::make_tet_mesh / make_tri_mesh) or read from a .msh file (tetia's own strict reader),
// and what Python reads back from it (nodes, file cells, measures).
//
// Errors: a mesh from arrays raises ValueError with the C++ message (it names the cell or the
// array); a file that cannot be read raises OSError with the reader's message (it names the
// file and the line or byte). The GIL is released while a mesh is built or read.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "tetia/file_cells.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh_from_arrays.hpp"

namespace tetia::python {

namespace {

[[noreturn]] void os_error(const std::string& message) {
  PyErr_SetString(PyExc_OSError, message.c_str());
  throw py::error_already_set();
}

/// Gmsh's type (2-7) of a file cell of this mesh.
template <class Mesh>
int simplex_type() {
  return std::is_same_v<Mesh, TetMesh> ? 4 : 2;
}

/// The file cells as runs of one type, in order: [(gmsh type, (m, nodes) int64 array), ...].
template <class Mesh>
py::list file_cell_blocks(const Mesh& mesh) {
  py::list blocks;
  if (mesh.cell_origin.empty()) {
    std::vector<std::int64_t> nodes;
    nodes.reserve(mesh.cells.size() * mesh.cells[0].size());
    for (const auto& c : mesh.cells) nodes.insert(nodes.end(), c.begin(), c.end());
    const auto k = static_cast<py::ssize_t>(mesh.cells[0].size());
    blocks.append(py::make_tuple(simplex_type<Mesh>(), to_array(std::move(nodes), {static_cast<py::ssize_t>(mesh.cells.size()), k})));
    return blocks;
  }
  std::size_t offset = 0;
  for (std::size_t i = 0; i < mesh.origin_types.size();) {
    const int type = mesh.origin_types[i];
    const auto k = static_cast<std::size_t>(file_cell_nodes(type));
    std::size_t j = i;
    std::vector<std::int64_t> nodes;
    while (j < mesh.origin_types.size() && mesh.origin_types[j] == type) {
      nodes.insert(nodes.end(), mesh.origin_nodes.begin() + static_cast<std::ptrdiff_t>(offset),
                   mesh.origin_nodes.begin() + static_cast<std::ptrdiff_t>(offset + k));
      offset += k;
      ++j;
    }
    blocks.append(py::make_tuple(type, to_array(std::move(nodes), {static_cast<py::ssize_t>(j - i), static_cast<py::ssize_t>(k)})));
    i = j;
  }
  return blocks;
}

template <class Mesh>
py::array_t<double> node_array(const Mesh& mesh) {
  constexpr bool three = std::is_same_v<Mesh, TetMesh>;
  std::vector<double> xyz;
  xyz.reserve(mesh.nodes.size() * (three ? 3 : 2));
  for (const auto& p : mesh.nodes) {
    if constexpr (three)
      xyz.insert(xyz.end(), {p.x, p.y, p.z});
    else
      xyz.insert(xyz.end(), {p.x, p.y});
  }
  return to_array(std::move(xyz), {static_cast<py::ssize_t>(mesh.nodes.size()), three ? 3 : 2});
}

template <class Mesh>
py::array_t<std::int64_t> simplex_array(const Mesh& mesh) {
  std::vector<std::int64_t> nodes;
  for (const auto& c : mesh.cells) nodes.insert(nodes.end(), c.begin(), c.end());
  return to_array(std::move(nodes), {static_cast<py::ssize_t>(mesh.cells.size()), static_cast<py::ssize_t>(mesh.cells.empty() ? 0 : mesh.cells[0].size())});
}

/// The file cells' tags: the file's element tags (a .msh file), else 1, 2, ... .
template <class Mesh>
py::array_t<std::int64_t> file_cell_tags(const Mesh& mesh) {
  std::vector<std::int64_t> tags;
  if (!mesh.cell_origin.empty())
    tags = mesh.origin_tags;
  else if (!mesh.cell_tags.empty())
    tags = mesh.cell_tags;
  else
    for (std::size_t c = 0; c < mesh.cells.size(); ++c) tags.push_back(static_cast<std::int64_t>(c) + 1);
  return to_array(std::move(tags));
}

template <class Mesh>
py::array_t<std::int64_t> node_tags(const Mesh& mesh) {
  std::vector<std::int64_t> tags = mesh.node_tags;
  if (tags.empty())
    for (std::size_t n = 0; n < mesh.nodes.size(); ++n) tags.push_back(static_cast<std::int64_t>(n) + 1);
  return to_array(std::move(tags));
}

template <class F>
auto on_mesh(const MeshHandle& h, F f) {
  return std::visit([&](const auto& m) { return f(*m); }, h.mesh);
}

/// make_tet_mesh / make_tri_mesh from (points, [(gmsh type, int array), ...]).
MeshHandle from_arrays(const py::object& points, const py::list& blocks, const std::string& name) {
  const Doubles xyz = as_doubles(points, "points");
  if (xyz.ndim() != 2 || (xyz.shape(1) != 2 && xyz.shape(1) != 3))
    value_error("tetia: " + name + ": points must have shape (n, 3) or (n, 2), got " + shape_text(xyz));
  std::vector<Indices> arrays;
  std::vector<CellBlock> cells;
  int dim = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto pair = blocks[b].cast<py::tuple>();
    const int type = pair[0].cast<int>();
    const int k = file_cell_nodes(type);
    if (k == 0) value_error("tetia: " + name + ": cell block " + std::to_string(b) + ": unknown Gmsh type " + std::to_string(type));
    const int block_dim = type >= 4 ? 3 : 2;
    if (dim != 0 && block_dim != dim)
      value_error("tetia: " + name + ": cell blocks of 2D and 3D cells mixed (block " + std::to_string(b) + ")");
    dim = block_dim;
    Indices a = as_indices(pair[1], "cells");
    if (!(a.ndim() == 2 && a.shape(1) == k) && !(a.ndim() == 1 && a.size() == 0))
      value_error("tetia: " + name + ": cell block " + std::to_string(b) + ": expected shape (m, " + std::to_string(k) +
                  "), got " + shape_text(a));
    cells.push_back({type, {a.data(), static_cast<std::size_t>(a.size())}});
    arrays.push_back(std::move(a));
  }
  if (dim == 3 && xyz.shape(1) != 3)
    value_error("tetia: " + name + ": a mesh of 3D cells needs points of shape (n, 3), got " + shape_text(xyz));
  MeshHandle h;
  h.name = name;
  try {
    py::gil_scoped_release release;
    const std::span<const double> coordinates(xyz.data(), static_cast<std::size_t>(xyz.size()));
    if (dim == 3)
      h.mesh = std::make_shared<const TetMesh>(make_tet_mesh(coordinates, cells, name));
    else
      h.mesh = std::make_shared<const TriMesh>(
          make_tri_mesh(coordinates, static_cast<int>(xyz.shape(1)), cells, name));
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    value_error(e.what());
  }
  return h;
}

MeshHandle read(const std::filesystem::path& file, bool corner_nodes) {
  MeshHandle h;
  h.name = file.string();
  try {
    py::gil_scoped_release release;
    MeshReadOptions options;
    options.corner_nodes = corner_nodes;
    AnyMesh any = read_any_mesh(file, nullptr, options);
    if (auto* tet = std::get_if<TetMesh>(&any))
      h.mesh = std::make_shared<const TetMesh>(std::move(*tet));
    else
      h.mesh = std::make_shared<const TriMesh>(std::move(std::get<TriMesh>(any)));
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    os_error(e.what());
  }
  return h;
}

/// The node data and element data of a .msh file, as (point_data, cell_data) dicts of arrays
/// ((n,) for scalars, (n, components) otherwise) in the order of read()'s nodes and file
/// cells: every field with values at one time step, and for a field with several the last
/// (largest) step. Element-node data ($ElementNodeData: one value per node of each element)
/// has no place in either and is left out (the C++ read_msh_field reads it). A field the mesh
/// cannot take (values on boundary elements only, a node without a value, a bad line) is left
/// out with a warning that names it and says why: the mesh itself reads as without its fields.
/// One pass over the file for the list, and one for each kind (node or element data) and step:
/// the fields of a group are read together, with the mesh; one pass per field of a group where
/// that fails, to tell which are left out.
py::tuple read_data(const std::filesystem::path& file, bool corner_nodes) {
  struct Read {
    std::string name;
    bool on_cells;
    int components;
    std::vector<double> values;
  };
  std::vector<Read> fields;
  std::vector<std::string> skipped;
  try {
    py::gil_scoped_release release;
    MeshReadOptions options;  // the mesh's, as read() reads it
    options.corner_nodes = corner_nodes;
    // Fields of one kind at one step are read together, in one pass with the mesh; where that
    // fails (a field the mesh cannot take), that group's fields are read one by one, so that
    // only the failing ones are left out.
    struct Group {
      bool on_cells;
      std::int64_t step;
      std::vector<std::string> names;
    };
    std::vector<Group> groups;
    for (const FieldInfo& info : msh_fields(file)) {
      if (info.on_cell_nodes || info.steps.empty()) continue;
      const std::int64_t step = info.steps.back();
      auto g = std::find_if(groups.begin(), groups.end(),
                            [&](const Group& x) { return x.on_cells == info.on_cells && x.step == step; });
      if (g == groups.end()) g = groups.insert(groups.end(), Group{info.on_cells, step, {}});
      g->names.push_back(info.name);
    }
    for (const Group& g : groups) {
      MeshReadOptions together = options;
      together.fields = g.names;
      together.fields_on_cells = g.on_cells;
      together.step = g.step;
      MeshReadInfo info;
      bool read_together = true;
      try {
        read_any_mesh(file, &info, together);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception&) {
        read_together = false;
      }
      if (read_together) {
        for (Field& f : info.fields) fields.push_back(Read{f.name, g.on_cells, f.components, std::move(f.values)});
        continue;
      }
      for (const std::string& name : g.names) {
        Read r{name, g.on_cells, 1, {}};
        try {
          r.values = read_msh_field(file, name, g.on_cells, g.step, &r.components, options);
        } catch (const std::bad_alloc&) {
          throw;
        } catch (const std::exception& e) {
          skipped.push_back(std::string(e.what()) + "; " + (g.on_cells ? "element" : "node") + " data \"" + name +
                            "\" left out");
          continue;
        }
        fields.push_back(std::move(r));
      }
    }
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    os_error(e.what());
  }
  for (const std::string& w : skipped)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 2) != 0) throw py::error_already_set();
  py::dict point_data, cell_data;
  for (Read& r : fields) {
    const auto rows = static_cast<py::ssize_t>(r.values.size() / static_cast<std::size_t>(r.components));
    py::array_t<double> a = r.components == 1 ? to_array(std::move(r.values))
                                              : to_array(std::move(r.values), {rows, static_cast<py::ssize_t>(r.components)});
    (r.on_cells ? cell_data : point_data)[py::str(r.name)] = std::move(a);
  }
  return py::make_tuple(point_data, cell_data);
}

}  // namespace

void check_same_dimension(const MeshHandle& source, const MeshHandle& target, const char* what) {
  if (source.dim() != target.dim())
    value_error(std::string("tetia: ") + what + ": the source mesh is " + std::to_string(source.dim()) +
                "D and the target mesh " + std::to_string(target.dim()) + "D");
}

void bind_meshes(py::module_& m) {
  py::class_<MeshHandle>(m, "MeshHandle",
                         "A finalized mesh (tetrahedra, or triangles in the plane) held by tetia.Mesh; shared with "
                         "the supermeshes and remaps built from it.")
      .def_property_readonly("dim", &MeshHandle::dim)
      .def_property_readonly("name", [](const MeshHandle& h) { return h.name; })
      .def_property_readonly("num_nodes", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return x.num_nodes(); }); })
      .def_property_readonly("num_cells", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return x.num_file_cells(); }); })
      .def_property_readonly("num_simplices", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return x.num_cells(); }); })
      .def_property_readonly("reoriented_cells", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return x.reoriented_cells; }); })
      .def_property_readonly("flat_cells", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return x.flat_cells; }); })
      .def_property_readonly("nodes", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return node_array(x); }); })
      .def_property_readonly("simplices", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return simplex_array(x); }); })
      .def_property_readonly("simplex_cell",
                             [](const MeshHandle& h) {
                               return on_mesh(h, [](const auto& x) {
                                 std::vector<std::int64_t> c(x.num_cells());
                                 for (std::size_t i = 0; i < c.size(); ++i) c[i] = static_cast<std::int64_t>(x.file_cell(i));
                                 return to_array(std::move(c));
                               });
                             })
      .def_property_readonly("measures", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return to_array(file_cell_measures(x)); }); })
      .def_property_readonly("cell_tags", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return file_cell_tags(x); }); })
      .def_property_readonly("node_tags", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return node_tags(x); }); })
      .def("file_cell_blocks", [](const MeshHandle& h) { return on_mesh(h, [](const auto& x) { return file_cell_blocks(x); }); });

  m.def("make_mesh", &from_arrays, py::arg("points"), py::arg("blocks"), py::arg("name") = "mesh",
        "A mesh from points (n, 3) or (n, 2) and blocks [(gmsh type, (m, k) node indices), ...] (tetia::make_tet_mesh "
        "or make_tri_mesh by the cells' dimension). ValueError for bad arrays.");
  m.def("read_msh", &read, py::arg("path"), py::arg("corner_nodes") = false,
        "A mesh read from a Gmsh .msh file by tetia's reader (tetia::read_any_mesh). OSError if it cannot be read.");
  m.def("read_msh_data", &read_data, py::arg("path"), py::arg("corner_nodes") = false,
        "(point_data, cell_data): the node data and element data of a .msh file, in the order of read_msh's nodes "
        "and cells; a field with several time steps at its last one; element-node data left out; a field the mesh "
        "cannot take left out with a UserWarning. OSError if the file cannot be read.");
}

}  // namespace tetia::python
