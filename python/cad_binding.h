// CAD models in Python: invmap.load("part.step") and what the CAD model adds
// to a Manifold (its description in info(), signed distances, pickling by
// the file's own bytes).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "cad/model.h"

namespace invmap::python {

/// A CAD model read for Python, and its pickled form: the file's bytes and
/// extension, from which a worker process reads the very same model.
struct CadSource {
  std::shared_ptr<const cad::Model> model;
  std::string state;
};

/// True when `path` is a CAD file (by extension).
bool IsCadPath(const std::string& path);

/// Reads a CAD file; FileError when it cannot be opened, InputError when its
/// content is not a usable model (messages name the file). Pure C++:
/// callers may release the GIL.
CadSource LoadCad(const std::string& path);

/// True for a pickled state that LoadCadState reads.
bool IsCadState(const std::string& state);
/// Reads the model back from its pickled state (InputError when corrupt).
CadSource LoadCadState(const std::string& state);

/// The model's description, the "cad" entry of Manifold.info().
pybind11::dict CadInfo(const cad::Model& model);

/// Signed distances of `count` points (xyz, 3 each) from their results;
/// InputError naming the open shell when the model has no inside.
std::vector<double> SignedDistances(const cad::Model& model, const double* xyz, std::size_t count,
                                    const Results& results, int threads);

}  // namespace invmap::python
