// Query points from a numpy array, without a copy when the layout allows.
#pragma once

#include <pybind11/numpy.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::python {

/// A PointsView over numpy memory together with the array that owns it.
struct NumpyPoints {
  /// Keeps the viewed memory alive: the caller's array, or the float64 copy.
  pybind11::array array;
  PointsView view;
};

/// Views `points`, an (N, dim) array (or anything numpy converts to one) of
/// N query points, for Manifold::Invert. float32 and float64 arrays in native
/// byte order are read in place whatever their strides (C or Fortran order,
/// row or column slices, broadcasts), as long as the strides are
/// non-negative and aligned; other integer and float types, reversed or
/// misaligned arrays are copied to C-ordered float64 once.
/// Throws InputError naming the shape or type when `points` is not a 2-D
/// array of real numbers with `dim` columns. Needs the GIL; the view stays
/// valid while the result lives and nobody resizes the caller's array.
NumpyPoints ReadNumpyPoints(pybind11::handle points, int dim);

/// An array's shape as Python prints it, "(5, 2)" or "(7,)", for messages.
std::string ShapeText(const pybind11::array& array);

/// `values` as a C-ordered float64 array (converted when needed), or
/// InputError naming `field`.
pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast> RealArray(
    const pybind11::handle& values, const char* field);

/// `values` as a C-ordered int64 array of indices, or InputError naming
/// `field` (float indices would be truncated silently by a cast).
pybind11::array_t<std::int64_t, pybind11::array::c_style | pybind11::array::forcecast> IndexArray(
    const pybind11::handle& values, const char* field);

/// Throws InputError when `indices` (rows of vertex indices, as IndexArray
/// accepts them) is unsigned and holds an index beyond the int64 range: the
/// cast to int64 would wrap it to a negative index and the message would
/// name a value the caller never gave. The message reads
/// "<rows>[r]: vertex index N out of range [0, vertexCount)".
void CheckUnsignedIndices(const pybind11::array& indices, const std::string& rows, std::int64_t vertexCount);

/// The elements of a C-ordered array. memcpy, because numpy arrays need not
/// be aligned.
template <typename T, int Flags>
std::vector<T> CopyElements(const pybind11::array_t<T, Flags>& array) {
  static_assert((Flags & pybind11::array::c_style) != 0);
  std::vector<T> values(static_cast<std::size_t>(array.size()));
  if (!values.empty()) std::memcpy(values.data(), array.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace invmap::python
