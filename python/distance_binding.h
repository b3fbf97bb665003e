// Registers invmap._invmap's distance queries: distance, DistanceTracker
// and PointTracker (include/invmap/distance.h).
#pragma once

#include <pybind11/pybind11.h>

namespace invmap::python {

void RegisterDistance(pybind11::module_& m);

}  // namespace invmap::python
