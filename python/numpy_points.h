// Query points from a numpy array, without a copy when the layout allows.
#pragma once

#include <pybind11/numpy.h>

#include <string>

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

}  // namespace invmap::python
