// The one validation of a geometry: every check a Geometry must pass before
// the engine converts it to cells, whatever produced it (a reader, the
// Python bindings, a program of the user's). Readers check only what their
// format needs to fill a Geometry at all (syntax, types, rows of the right
// length); they map the GeometryError found here to the file and line the
// faulty value came from.
#pragma once

#include "invmap/invmap.h"

namespace invmap::engine {

/// The first problem of `geometry`, in patch order (within a patch: its
/// kind and cell type, its coordinates, then its kind's fields in the
/// order of the geometry file), or no error. A geometry with no problem
/// satisfies every precondition of CellStore::Build:
///  - dimension 2 or 3; every kind and cell type a known one;
///  - coordinates finite and within [-kMaxCoordinate, kMaxCoordinate], a
///    whole number of points;
///  - B-splines: 1 to 3 directions that fit the dimension, one count and
///    one knot vector per degree, degrees 1 to kMaxDegree, counts at least
///    degree + 1, non-decreasing finite knots of the right length with a
///    non-empty parameter domain, the control points the counts give;
///  - Bezier patches and cells: a degree per simplex factor, each 1 to
///    kMaxDegree, the control points the degrees give, a cell type that
///    fits the dimension;
///  - trimmed surfaces: dimension 3, a 2-direction B-spline as above,
///    angular directions of degree 2 with knot spans shorter than pi, and
///    trimming curves (2D), edges (3D) and pcurves (2D) that are valid
///    B-spline curves (degrees up to TrimRegion::kMaxPieceDegree in the
///    plane, kMaxDegree in space);
///  - meshes: no weights, whole cells, vertex indices within the vertices;
///  - weights: one per control point, finite and within [1 / kMaxWeight,
///    kMaxWeight];
///  - the control points' box at least kMinExtent across, or a single point.
/// Cost: one pass over the geometry's values; no allocation beyond the
/// message.
GeometryError ValidateGeometry(const Geometry& geometry);

}  // namespace invmap::engine
