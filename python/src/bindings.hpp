// python/src/bindings.hpp -- the parts of the extension module tetia._tetia, one per layer
// (kernels.cpp, meshes.cpp, supermesh.cpp, remap.cpp), put together by module.cpp.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <variant>

#include "tetia/mesh.hpp"

namespace tetia::python {

namespace py = pybind11;

void bind_kernels(py::module_& m);
void bind_meshes(py::module_& m);
void bind_supermesh(py::module_& m);
void bind_remap(py::module_& m);

/// What a tetia.Mesh holds: a finalized, immutable mesh of either dimension, shared with every
/// supermesh and remap built from it (so they keep it alive).
struct MeshHandle {
  std::variant<std::shared_ptr<const TetMesh>, std::shared_ptr<const TriMesh>> mesh;
  std::string name;
  int dim() const { return mesh.index() == 0 ? 3 : 2; }
};

/// The same dimension for both, or a ValueError saying what each is.
void check_same_dimension(const MeshHandle& source, const MeshHandle& target, const char* what);

}  // namespace tetia::python
