// Registers invmap._invmap._grid (adaptive grids for implicit complexes).
#pragma once

#include <pybind11/pybind11.h>

namespace invmap::python {

void RegisterGrid(pybind11::module_& m);

}  // namespace invmap::python
