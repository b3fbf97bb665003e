// What is wrong with a geometry, as Manifold::Build found it: the patch, the
// field, the element and a message, so that a reader can point at the place
// of a file the problem came from (the invmap command names the file and the
// line).
#pragma once

#include <cstdint>
#include <string>

namespace invmap {

/// A field of a Geometry or of one of its Patch objects, named as in the
/// geometry file (docs/formats.md, section 2).
enum class GeometryField : std::uint8_t {
  None,           ///< The geometry or the patch as a whole.
  Dimension,      ///< Geometry::dimension.
  Kind,           ///< Patch::kind.
  Cell,           ///< Patch::cell.
  Degrees,        ///< Patch::degrees.
  Knots,          ///< Patch::knots: element = knot vector, item = knot.
  Counts,         ///< Patch::counts.
  ControlPoints,  ///< Patch::points of a BSpline, Bezier or BezierCells patch: element = point, item = coordinate.
  Vertices,       ///< Patch::points of a Mesh or PouManifold patch: element = vertex, item = coordinate.
  Weights,        ///< Patch::weights.
  /// Mesh: Patch::cells, element = cell, item = its vertex. BezierCells:
  /// element = cell, whose cellTypes, cellDegrees and cellOffsets entries
  /// the message names.
  Cells,
  CellDegrees,  ///< Patch::cellDegrees as a whole (its length).
  CellOffsets,  ///< Patch::cellOffsets as a whole (its length).
  Angular,      ///< Patch::angular of a TrimmedSurface: element = direction.
  TrimLoops,    ///< Patch::trimLoops: element = loop, item = its curve.
  Edges,        ///< Patch::edges: element = edge (the message says curve or pcurve).
  /// Patch::chartControlPoints of a PouManifold patch: element = point,
  /// item = coordinate.
  ChartControlPoints,
};

/// The field's name in the geometry file: "degrees", "control_points",
/// "vertices", ...; "" for GeometryField::None.
inline const char* GeometryFieldName(GeometryField field) {
  static const char* const kNames[] = {"",        "dimension", "kind",           "cell",     "degrees",
                                       "knots",   "counts",    "control_points", "vertices", "weights",
                                       "cells",   "cellDegrees", "cellOffsets", "angular",  "trimLoops",
                                       "edges",   "chart_control_points"};
  return kNames[static_cast<int>(field)];
}

/// A problem of a geometry, or none (message empty).
struct GeometryError {
  /// The patch (index into Geometry::patches), or -1 for the geometry as a
  /// whole (its dimension, its extent).
  std::int64_t patch = -1;
  GeometryField field = GeometryField::None;
  /// Index of the element of `field` at fault (a knot vector, a point, a
  /// weight, a degree, a cell), or -1 for the field as a whole.
  std::int64_t element = -1;
  /// Index within the element (a knot of its vector, a coordinate of its
  /// point, a vertex of its cell), or -1. The message says what it is; the
  /// item is there so that a reader can find the very value in its file.
  std::int64_t item = -1;
  /// What is wrong, without the place: "decreasing at index 4 (0.5 > 0.25)".
  /// Empty when nothing is.
  std::string message;

  /// True when there is a problem.
  explicit operator bool() const { return !message.empty(); }
};

/// The error with its place, as Manifold::Build reports it in
/// BuildResult::error: "patch 3: knots[1]: decreasing at index 4 (0.5 > 0.25)",
/// "dimension: 4, expected 2 or 3"; "" when there is no error.
inline std::string Describe(const GeometryError& error) {
  if (!error) return {};
  std::string text;
  if (error.patch >= 0) text = "patch " + std::to_string(error.patch) + ": ";
  if (error.field != GeometryField::None) {
    text += GeometryFieldName(error.field);
    if (error.element >= 0) text += "[" + std::to_string(error.element) + "]";
    text += ": ";
  }
  return text + error.message;
}

}  // namespace invmap
