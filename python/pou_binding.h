// Registers invmap.manifold (the partition-of-unity surface of a closed
// triangle mesh, docs/manifold.md) and Manifold.chart_points (its charts
// evaluated at local coordinates).
#pragma once

#include <pybind11/pybind11.h>

namespace invmap::python {

void RegisterPou(pybind11::module_& m);

}  // namespace invmap::python
