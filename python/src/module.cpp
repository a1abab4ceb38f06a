// python/src/module.cpp -- the extension module tetia._tetia; the public API is the package
// tetia (python/tetia/), which wraps it.
#include <pybind11/pybind11.h>

#include "bindings.hpp"

PYBIND11_MODULE(_tetia, m) {
  m.doc() = "tetia's C++ library: kernels, meshes, supermesh, remap (use the package tetia)";
  tetia::python::bind_kernels(m);
  tetia::python::bind_meshes(m);
  tetia::python::bind_supermesh(m);
  tetia::python::bind_remap(m);
#ifdef TETIA_VERSION
  m.attr("__version__") = TETIA_VERSION;
#endif
}
