// python/src/arrays.hpp -- NumPy arrays in and out of the bindings, and the errors they raise.
//
// Contract. Arrays in: `as_doubles` / `as_indices` accept any array-like NumPy converts (lists,
// other dtypes, other layouts), copying only where the array is not already C-contiguous of the
// type (py::array::forcecast); `as_indices` refuses arrays that are not of an integer (or bool)
// dtype rather than truncate floats. Shapes and finiteness are checked here, at the boundary,
// with a ValueError naming the argument, its shape and the offending element; the kernels behind
// get only finite, well-shaped data. Arrays out: `to_array` hands a std::vector's storage to
// NumPy without a copy (the vector lives in a capsule owned by the array).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace tetia::python {

namespace py = pybind11;

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Indices = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// "(4, 3)" for a shape.
inline std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

[[noreturn]] inline void value_error(const std::string& message) { throw py::value_error(message); }

/// The object as a C-contiguous float64 array (a copy only where needed).
inline Doubles as_doubles(const py::handle& object, const char* what) {
  py::array any = py::array::ensure(object);
  if (!any) value_error(std::string("tetia: ") + what + ": not an array of numbers");
  if (any.dtype().kind() == 'O' || any.dtype().kind() == 'U' || any.dtype().kind() == 'S' ||
      any.dtype().kind() == 'c')
    value_error(std::string("tetia: ") + what + ": expected real numbers, got an array of dtype " +
                std::string(py::str(any.dtype())));
  return Doubles::ensure(any);
}

/// The object as a C-contiguous int64 array; only integer (and bool) dtypes are accepted.
inline Indices as_indices(const py::handle& object, const char* what) {
  py::array any = py::array::ensure(object);
  if (!any) value_error(std::string("tetia: ") + what + ": not an array of integers");
  const char kind = any.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'b')
    value_error(std::string("tetia: ") + what + ": expected node indices of an integer dtype, got " +
                std::string(py::str(any.dtype())));
  if (kind == 'u' && any.dtype().itemsize() == 8 && any.size() > 0) {
    // uint64 above 2^63 would wrap to negative indices: say what they are instead.
    auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(any);
    const std::uint64_t* p = u.data();
    for (py::ssize_t i = 0; i < u.size(); ++i)
      if (p[i] > static_cast<std::uint64_t>(INT64_MAX))
        value_error(std::string("tetia: ") + what + ": node index " + std::to_string(p[i]) + " out of range");
  }
  return Indices::ensure(any);
}

/// Throws unless every value is finite; names the first that is not by its index in `a`.
inline void check_finite(const Doubles& a, const char* what) {
  const double* p = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (std::isfinite(p[i])) continue;
    std::string index;
    py::ssize_t rest = i;
    std::vector<py::ssize_t> digits(static_cast<std::size_t>(a.ndim()));
    for (py::ssize_t d = a.ndim() - 1; d >= 0; --d) {
      digits[static_cast<std::size_t>(d)] = rest % a.shape(d);
      rest /= a.shape(d);
    }
    for (std::size_t d = 0; d < digits.size(); ++d) index += (d ? ", " : "") + std::to_string(digits[d]);
    value_error(std::string("tetia: ") + what + "[" + index + "] is not finite (" +
                std::string(py::str(py::float_(p[i]))) + ")");
  }
}

/// A std::vector's storage as a NumPy array of the given shape (product = size), without a copy.
template <class T>
py::array_t<T> to_array(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = static_cast<py::ssize_t>(sizeof(T));
  for (std::size_t d = shape.size(); d-- > 0;) {
    strides[d] = stride;
    stride *= shape[d];
  }
  return py::array_t<T>(std::move(shape), std::move(strides), owned->data(), free_when_done);
}

template <class T>
py::array_t<T> to_array(std::vector<T>&& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return to_array(std::move(values), {n});
}

}  // namespace tetia::python
