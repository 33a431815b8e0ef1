// numpy arrays over C++ vectors, without a copy.
#pragma once

#include <pybind11/numpy.h>

#include <vector>

namespace flexsens_python {

namespace py = pybind11;

/// A read-only C-contiguous float64 array over `data` (shape in elements; their product must be
/// data.size()), kept alive by `owner`, the Python object that holds the vector.
inline py::array readOnlyView(const py::object& owner, const std::vector<double>& data, std::vector<py::ssize_t> shape) {
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = sizeof(double);
  for (size_t i = shape.size(); i-- > 0;) {
    strides[i] = stride;
    stride *= shape[i];
  }
  static const double none = 0.0;  // numpy wants a pointer also for an empty array
  py::array a(py::dtype::of<double>(), shape, strides, data.empty() ? &none : data.data(), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

}  // namespace flexsens_python
