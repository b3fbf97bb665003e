#include "python/numpy_points.h"

#include <cstdint>
#include <limits>
#include <string>

#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {

std::string ShapeText(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) {
    if (d) text += ", ";
    text += std::to_string(array.shape(d));
  }
  return text + (array.ndim() == 1 ? ",)" : ")");
}

py::array_t<double, py::array::c_style | py::array::forcecast> RealArray(const py::handle& values, const char* field) {
  const py::array array = py::array::ensure(values);
  if (!array || (array.dtype().kind() != 'f' && array.dtype().kind() != 'i' && array.dtype().kind() != 'u')) {
    throw InputError(std::string(field) + ": expected an array of real numbers");
  }
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
}

py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> IndexArray(const py::handle& values,
                                                                               const char* field) {
  const py::array array = py::array::ensure(values);
  if (!array || (array.dtype().kind() != 'i' && array.dtype().kind() != 'u')) {
    throw InputError(std::string(field) + ": expected an array of integer vertex indices");
  }
  return py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(array);
}

void CheckUnsignedIndices(const py::array& indices, const std::string& rows, std::int64_t vertexCount) {
  if (indices.dtype().kind() != 'u') return;
  const auto values = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(indices);
  const py::ssize_t rowWidth = indices.ndim() == 2 && indices.shape(1) > 0 ? indices.shape(1) : 1;
  for (py::ssize_t i = 0; i < values.size(); ++i) {
    const std::uint64_t index = values.data()[i];
    if (index > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      throw InputError(rows + "[" + std::to_string(i / rowWidth) + "]: vertex index " + std::to_string(index) +
                       " out of range [0, " + std::to_string(vertexCount) + ")");
    }
  }
}

namespace {

/// The view of `array` in place, if PointsView can express its layout: one
/// element stride shared by all coordinates, so both strides must be
/// non-negative multiples of the element size, and the data aligned.
template <typename T>
bool ViewInPlace(const py::array& array, Scalar scalar, int dim, PointsView* view) {
  if (!py::array_t<T>::check_(array)) return false;
  if (!(array.flags() & py::detail::npy_api::NPY_ARRAY_ALIGNED_)) return false;
  const py::ssize_t rowStride = array.strides(0);
  const py::ssize_t columnStride = array.strides(1);
  const auto size = static_cast<py::ssize_t>(sizeof(T));
  if (rowStride < 0 || columnStride < 0 || rowStride % size != 0 || columnStride % size != 0) return false;
  const T* data = static_cast<const T*>(array.data());
  view->count = static_cast<std::size_t>(array.shape(0));
  view->dim = dim;
  view->scalar = scalar;
  for (int k = 0; k < dim; ++k) view->coord[k] = data + k * (columnStride / size);
  view->stride = static_cast<std::size_t>(rowStride / size);
  return true;
}

}  // namespace

NumpyPoints ReadNumpyPoints(py::handle points, int dim) {
  NumpyPoints result;
  result.array = py::array::ensure(points);
  if (!result.array) throw InputError("points: not convertible to a numpy array");
  const py::array& array = result.array;
  const char kind = array.dtype().kind();
  // Booleans, complex numbers, strings and objects are no coordinates; numpy
  // would cast some of them silently.
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw InputError("points: dtype " + std::string(py::str(array.dtype())) + ", expected float32 or float64");
  }
  if (array.ndim() != 2 || array.shape(1) != dim) {
    throw InputError("points: shape " + ShapeText(array) + ", expected (N, " + std::to_string(dim) + ") for a " +
                     std::to_string(dim) + "-D geometry");
  }
  if (ViewInPlace<double>(array, Scalar::Float64, dim, &result.view) ||
      ViewInPlace<float>(array, Scalar::Float32, dim, &result.view)) {
    return result;
  }
  // np.array always copies, to fresh aligned memory, so the view below holds.
  result.array = py::module_::import("numpy").attr("array")(array, py::arg("dtype") = "float64", py::arg("order") = "C");
  ViewInPlace<double>(result.array, Scalar::Float64, dim, &result.view);
  return result;
}

}  // namespace invmap::python
