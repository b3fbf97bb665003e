// Registers invmap._invmap.read_points (point files into numpy arrays).
#pragma once

#include <pybind11/pybind11.h>

namespace invmap::python {

void RegisterPointFiles(pybind11::module_& m);

}  // namespace invmap::python
