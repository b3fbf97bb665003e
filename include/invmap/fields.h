// Fields given at the nodes of a finite-element geometry (temperatures,
// displacements, stresses), and their values at inverted points: each field
// is interpolated with the basis of the cell that holds the point, at the
// parameters the inversion found (docs/fields.md).
//
//   invmap::FieldGeometry model = ...;                 // e.g. from a .vtu, .exo or .msh reader
//   invmap::BuildResult built = invmap::Manifold::Build(model.geometry);
//   invmap::Results results;
//   built.manifold.Invert(points, {}, &results);
//   std::vector<double> values;                        // one row of FieldWidth(fields) values per point
//   invmap::ProbeFields(model.geometry, {&model.fields[0]}, results, &values);
#pragma once

#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap {

/// A field given at a geometry's nodes, stored per patch in the layout of
/// that patch's control points, so that every cell interpolates it exactly
/// as it maps its parameters to space (the same change of basis turned the
/// element's nodal values into these coefficients).
struct NodeField {
  std::string name;
  /// Values per node: 1 for a scalar, 3 for a vector, 6 or 9 for a tensor.
  int components = 1;
  /// One array per patch of the geometry, `components` values per control
  /// point (BezierCells and Bezier patches: the field's Bernstein
  /// coefficients, in the order of the patch's points) or per vertex (Mesh
  /// patches), point-major. An empty array: the field does not cover that
  /// patch (its points get NaN).
  std::vector<std::vector<double>> patchValues;
};

/// A geometry and the fields its file carries.
struct FieldGeometry {
  Geometry geometry;
  std::vector<NodeField> fields;
};

/// Checks that `fields` fit `geometry`: one array per patch, each empty or
/// holding `components` values per point of its patch, components >= 1,
/// no BSpline patch covered, names unique and not empty. Returns an empty
/// string, or the problem ("field 'T': patch 2: 30 values, expected 33").
std::string CheckFields(const Geometry& geometry, const std::vector<NodeField>& fields);

/// Number of values per point of `fields` together: the sum of their components.
int FieldWidth(const std::vector<const NodeField*>& fields);

/// Column names of `fields` (docs/fields.md): NAME for a scalar,
/// NAME_0, NAME_1, ... for each component of a vector or tensor.
std::vector<std::string> FieldColumnNames(const std::vector<const NodeField*>& fields);

/// Values of `fields` at the points of `results` (an inversion on a
/// manifold built from `geometry`): for every found point, each field
/// interpolated with the basis of the reported cell at the reported
/// parameters (rational cells with their rational basis); NaN for points
/// not found and for patches a field does not cover. `values` receives
/// FieldWidth(fields) values per point, point-major, the fields in the
/// given order. The fields must have passed CheckFields against
/// `geometry`, else Error::InvalidArgument. `threads`: worker threads, 0
/// for all cores (the values do not depend on it). Never throws.
Error ProbeFields(const Geometry& geometry, const std::vector<const NodeField*>& fields, const Results& results,
                  std::vector<double>* values, std::string* message = nullptr, int threads = 0);

}  // namespace invmap
