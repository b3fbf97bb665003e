// Node fields in the Python package: what a Manifold carries when its file
// has fields (gmsh $NodeData, VTU point data, Exodus nodal variables), their
// pickled form, and Manifold.probe's field values (docs/fields.md).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "invmap/fields.h"

namespace invmap::python {

/// The pickled state of a manifold with fields: the geometry's state
/// (SerializeGeometry) and the fields, bit for bit. A state without fields
/// is the geometry's state alone, as before.
std::string SerializeModel(const std::string& geometryState, const std::vector<NodeField>& fields);

/// Splits SerializeModel's output. Throws std::invalid_argument on anything
/// malformed, never reads out of bounds.
void ParseModel(const std::string& state, std::string* geometryState, std::vector<NodeField>* fields);

/// The "fields" entry of Manifold.probe: {name: array} with one row per
/// point, (N,) for a scalar and (N, components) otherwise, NaN where the
/// point was not found. `names`: the fields to give, in order (default:
/// every field). Throws InputError for an unknown name or a manifold
/// without fields. Evaluates without the GIL, on `threads` threads (0: all cores).
pybind11::dict ProbeFieldsDict(const FieldGeometry* model, const Results& results,
                               const std::optional<std::vector<std::string>>& names, int threads);

/// Manifold.fields: {name: components}.
pybind11::dict FieldComponents(const FieldGeometry* model);

}  // namespace invmap::python
