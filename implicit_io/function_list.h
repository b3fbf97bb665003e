// The function list file of `invmap grid` (docs/grids.md#function-objects): the
// implicit functions of a complex as a JSON list of objects.
#pragma once

#include <string>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::io {

/// Reads a JSON list of function objects (at least one), in file order.
///
/// Objects, by "type" (fields in any order; numbers may be integers):
///  - "sphere":   center [3], radius > 0, optional squared (bool, default false)
///  - "cylinder": axis_point [3], axis_vector [3] (non-zero), radius > 0, optional squared
///  - "plane":    point [3], normal [3] (non-zero)
///  - "torus":    center [3], axis_vector [3] (non-zero), major_radius > 0, minor_radius > 0
///  - "cone":     apex [3], axis_vector [3] (non-zero), angle: the half angle in
///                radians, 0 < angle < pi/2
///  - "quintic":  optional center [3] (default the origin): x^5 + x^4 - 2y^2 of x - center
///  - "gyroid":   period > 0
/// Every object may also carry "name" (a string), which replaces the
/// function's default name (its type) in output labels. Points and vectors
/// have `dimension` numbers: 3, or 2 for a 2D grid (z is then 0). Every
/// number must be finite. Functions are built by the factories of implicit.h.
///
/// Throws InputError at the line of the offending value for: a missing or
/// unreadable file, invalid JSON, a top level that is not a non-empty list,
/// an element that is not an object, a missing or unknown "type" (the
/// message lists the known ones), a missing, unknown (the message lists the
/// allowed ones), duplicate or mistyped field, a wrong array length, a
/// non-finite number and the range violations above.
std::vector<implicit::Function> ReadFunctionList(const std::string& path, int dimension);

/// ReadFunctionList of JSON text held in memory, named `name` in messages
/// (the Python package's lists and dicts).
std::vector<implicit::Function> ParseFunctionList(const std::string& text, const std::string& name, int dimension);

}  // namespace invmap::io
