// The one validation of a geometry: every rule gives its structured error
// (patch, field, element, item and message), written out here by hand, and
// valid geometries of every kind pass.
#include "engine/geometry_validation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A valid rational cubic-by-quadratic surface with 5 x 4 control points
/// (dimension `dim`).
Patch Spline(int dim) {
  Patch p;
  p.kind = Patch::Kind::BSpline;
  p.degrees = {3, 2};
  p.counts = {5, 4};
  p.knots = {{0, 0, 0, 0, 0.25, 1, 1, 1, 1}, {0, 0, 0, 0.5, 1, 1, 1}};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) {
      p.points.insert(p.points.end(), {double(i), double(j)});
      if (dim == 3) p.points.push_back(0.1 * i * j);
    }
  p.weights.assign(20, 1.0);
  return p;
}

/// A valid quadratic Bezier triangle.
Patch BezierTri(int dim) {
  Patch p;
  p.kind = Patch::Kind::Bezier;
  p.cell = CellType::Tri;
  p.degrees = {2};
  for (int i = 0; i < 6; ++i) {
    p.points.insert(p.points.end(), {double(i % 3), double(i / 3)});
    if (dim == 3) p.points.push_back(0.0);
  }
  return p;
}

/// Two triangles on four vertices.
Patch TriMesh(int dim) {
  Patch p;
  p.kind = Patch::Kind::Mesh;
  p.cell = CellType::Tri;
  p.points = dim == 3 ? std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}
                      : std::vector<double>{0, 0, 1, 0, 0, 1, 1, 1};
  p.cells = {0, 1, 2, 1, 3, 2};
  return p;
}

/// A quadratic triangle (points 0-5) and a line (points 6-7) as BezierCells.
Patch MixedCells(int dim) {
  Patch p;
  p.kind = Patch::Kind::BezierCells;
  p.cellTypes = {CellType::Tri, CellType::Line};
  p.cellDegrees = {2, 0, 0, 1, 0, 0};
  p.cellOffsets = {0, 6, 8};
  for (int i = 0; i < 8; ++i) {
    p.points.insert(p.points.end(), {double(i % 3), double(i / 3)});
    if (dim == 3) p.points.push_back(0.0);
  }
  return p;
}

struct Case {
  const char* what;
  std::function<Patch(int)> valid;  ///< The patch before the change.
  std::function<void(Patch&)> change;
  GeometryField field;
  std::int64_t element, item;
  const char* message;
  int dim = 3;
};

/// The changed patch as patch 1 of a geometry whose patch 0 is valid.
GeometryError ValidateChanged(const Case& c) {
  Geometry g;
  g.dimension = c.dim;
  g.patches.push_back(TriMesh(c.dim));
  Patch changed = c.valid(c.dim);
  c.change(changed);
  g.patches.push_back(changed);
  return engine::ValidateGeometry(g);
}

TEST(GeometryValidationTest, EachRuleNamesPatchFieldElementAndItem) {
  using F = GeometryField;
  const Case cases[] = {
      // B-splines.
      {"no degrees", Spline, [](Patch& p) { p.degrees.clear(); }, F::Degrees, -1, -1,
       "0 values, expected 1 to 3 (one per parametric direction)"},
      {"a volume in 2D", Spline, [](Patch& p) { p.degrees.push_back(1); }, F::Degrees, -1, -1,
       "a 3-parameter patch needs dimension 3", 2},
      {"counts per degree", Spline, [](Patch& p) { p.counts.push_back(1); }, F::Counts, -1, -1,
       "3 values, expected one per degree (2)"},
      {"knot vectors per degree", Spline, [](Patch& p) { p.knots.pop_back(); }, F::Knots, -1, -1,
       "1 knot vectors, expected one per degree (2)"},
      {"degree 0", Spline, [](Patch& p) { p.degrees[1] = 0; }, F::Degrees, 1, -1, "0, expected 1 to 8"},
      {"degree 9", Spline, [](Patch& p) { p.degrees[0] = 9; }, F::Degrees, 0, -1,
       "9, expected 1 to 8 (the highest degree invmap supports)"},
      {"count below the degree", Spline, [](Patch& p) { p.counts[1] = 2; }, F::Counts, 1, -1,
       "2, expected at least degrees[1] + 1 = 3"},
      {"knot vector length", Spline, [](Patch& p) { p.knots[1].pop_back(); }, F::Knots, 1, -1,
       "length 6, expected counts[1] + degrees[1] + 1 = 7"},
      {"decreasing knots", Spline, [](Patch& p) { p.knots[0][3] = 0.5; }, F::Knots, 0, 4,
       "decreasing at index 4 (0.5 > 0.25)"},
      {"NaN knot", Spline, [](Patch& p) { p.knots[1][3] = kNaN; }, F::Knots, 1, 3, "knot 3 is not finite (nan)"},
      {"infinite knot", Spline, [](Patch& p) { p.knots[0][8] = kInf; }, F::Knots, 0, 8, "knot 8 is not finite (inf)"},
      {"empty domain", Spline, [](Patch& p) { p.knots[1] = {0, 0, 0, 0, 0, 1, 1}; }, F::Knots, 1, -1,
       "empty parameter domain [knots[1][2], knots[1][4]] = [0, 0]"},
      {"knots wider than a double", Spline,
       [](Patch& p) { p.knots[1] = {-1e308, -1e308, -1e308, 0, 1e308, 1e308, 1e308}; }, F::Knots, 1, -1,
       "[-1e+308, 1e+308] is wider than a double can hold (its differences overflow)"},
      {"a control point missing", Spline, [](Patch& p) { p.points.resize(57); }, F::ControlPoints, -1, -1,
       "19 points, expected 20 (counts 5 x 4)"},
      {"a coordinate missing", Spline, [](Patch& p) { p.points.pop_back(); }, F::ControlPoints, -1, -1,
       "59 coordinates, not a whole number of points of dimension 3"},
      {"infinite coordinate", Spline, [](Patch& p) { p.points[7 * 3 + 2] = -kInf; }, F::ControlPoints, 7, 2,
       "coordinate 2 is not finite (-inf)"},
      {"huge coordinate", Spline, [](Patch& p) { p.points[4] = 1e101; }, F::ControlPoints, 1, 1,
       "coordinate 1 is 1e+101, outside [-1e100, 1e100] (the range invmap supports)"},
      {"weight count", Spline, [](Patch& p) { p.weights.pop_back(); }, F::Weights, -1, -1,
       "19 values, expected one per control point (20)"},
      {"negative weight", Spline, [](Patch& p) { p.weights[12] = -1; }, F::Weights, 12, -1, "-1 is not positive"},
      {"zero weight", Spline, [](Patch& p) { p.weights[0] = 0; }, F::Weights, 0, -1, "0 is not positive"},
      {"NaN weight", Spline, [](Patch& p) { p.weights[3] = kNaN; }, F::Weights, 3, -1, "nan is not finite"},
      {"huge weight", Spline, [](Patch& p) { p.weights[1] = 1e51; }, F::Weights, 1, -1,
       "1e+51 is outside [1e-50, 1e50] (the range invmap supports)"},
      {"tiny weight", Spline, [](Patch& p) { p.weights[2] = 1e-51; }, F::Weights, 2, -1,
       "1e-51 is outside [1e-50, 1e50] (the range invmap supports)"},
      // Bezier patches.
      {"degrees of a quad", BezierTri, [](Patch& p) { p.cell = CellType::Quad; }, F::Degrees, -1, -1,
       "1 values, a quad cell needs 2 [p, q]"},
      {"degree above the cap", BezierTri, [](Patch& p) { p.degrees = {9}; }, F::Degrees, 0, -1,
       "9, expected 1 to 8 (the highest degree invmap supports)"},
      {"control points of a tri", BezierTri, [](Patch& p) { p.points.resize(15); }, F::ControlPoints, -1, -1,
       "5 points, expected 6 for a tri cell of degrees [2]"},
      {"a tet in 2D", BezierTri, [](Patch& p) { p.cell = CellType::Tet; }, F::Cell, -1, -1,
       "a tet cell needs dimension 3", 2},
      {"unknown cell type", BezierTri, [](Patch& p) { p.cell = static_cast<CellType>(9); }, F::Cell, -1, -1,
       "unknown cell type 9"},
      {"unknown kind", BezierTri, [](Patch& p) { p.kind = static_cast<Patch::Kind>(7); }, F::Kind, -1, -1,
       "unknown patch kind 7"},
      {"Bezier weights", BezierTri, [](Patch& p) { p.weights = {1, 1}; }, F::Weights, -1, -1,
       "2 values, expected one per control point (6)"},
      // Meshes.
      {"index past the vertices", TriMesh, [](Patch& p) { p.cells[4] = 4; }, F::Cells, 1, 1,
       "vertex index 4 out of range (the patch has 4 vertices)"},
      {"negative index", TriMesh, [](Patch& p) { p.cells[0] = -1; }, F::Cells, 0, 0,
       "vertex index -1 is negative (indices are 0-based)"},
      {"a vertex of a cell missing", TriMesh, [](Patch& p) { p.cells.pop_back(); }, F::Cells, -1, -1,
       "5 vertex indices, not a whole number of tri cells (3 each)"},
      {"weights on a mesh", TriMesh, [](Patch& p) { p.weights = {1, 1, 1, 1}; }, F::Weights, -1, -1,
       "a mesh has no weights"},
      {"a tet mesh in 2D", TriMesh, [](Patch& p) { p.cell = CellType::Tet; }, F::Cell, -1, -1,
       "a tet mesh needs dimension 3", 2},
      {"NaN vertex", TriMesh, [](Patch& p) { p.points[2] = kNaN; }, F::Vertices, 0, 2,
       "coordinate 2 is not finite (nan)"},
      // BezierCells.
      {"cell degrees", MixedCells, [](Patch& p) { p.cellDegrees.pop_back(); }, F::CellDegrees, -1, -1,
       "5 values, expected 3 per cell (6)"},
      {"cell offsets", MixedCells, [](Patch& p) { p.cellOffsets.pop_back(); }, F::CellOffsets, -1, -1,
       "2 values, expected one per cell and one more (3)"},
      {"a cell's degree", MixedCells, [](Patch& p) { p.cellDegrees[3] = 0; }, F::Cells, 1, -1,
       "degrees[0]: 0, expected 1 to 8"},
      {"a cell's control points", MixedCells, [](Patch& p) { p.cellOffsets[2] = 9; }, F::Cells, 1, -1,
       "control points [6, 9), expected 2 within the 8 points"},
      {"a cell's type", MixedCells, [](Patch& p) { p.cellTypes[0] = static_cast<CellType>(7); }, F::Cells, 0, -1,
       "unknown cell type 7"},
      {"a tet cell in 2D", MixedCells,
       [](Patch& p) {
         p.cellTypes[1] = CellType::Tet;
         p.cellOffsets[2] = 10;
         p.points.resize(20);
       },
       F::Cells, 1, -1, "a tet cell needs dimension 3", 2},
      {"weights of the cells", MixedCells, [](Patch& p) { p.weights = {1, 2}; }, F::Weights, -1, -1,
       "2 values, expected one per control point (8)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const GeometryError e = ValidateChanged(c);
    EXPECT_EQ(e.patch, 1);
    EXPECT_EQ(e.field, c.field) << GeometryFieldName(e.field);
    EXPECT_EQ(e.element, c.element);
    EXPECT_EQ(e.item, c.item);
    EXPECT_EQ(e.message, c.message);
    // Each change breaks a valid patch: the unchanged one passes.
    Geometry g;
    g.dimension = c.dim;
    g.patches.push_back(c.valid(c.dim));
    EXPECT_FALSE(engine::ValidateGeometry(g)) << Describe(engine::ValidateGeometry(g));
  }
}

TEST(GeometryValidationTest, DescribeNamesThePlace) {
  GeometryError e{3, GeometryField::Knots, 1, 4, "decreasing at index 4 (0.5 > 0.25)"};
  EXPECT_EQ(Describe(e), "patch 3: knots[1]: decreasing at index 4 (0.5 > 0.25)");
  e = GeometryError{2, GeometryField::Degrees, -1, -1, "4 values, expected 1 to 3 (one per parametric direction)"};
  EXPECT_EQ(Describe(e), "patch 2: degrees: 4 values, expected 1 to 3 (one per parametric direction)");
  e = GeometryError{-1, GeometryField::Dimension, -1, -1, "4, expected 2 or 3"};
  EXPECT_EQ(Describe(e), "dimension: 4, expected 2 or 3");
  EXPECT_EQ(Describe(GeometryError{}), "");
  EXPECT_FALSE(GeometryError{});
}

TEST(GeometryValidationTest, DimensionAndExtentAreTheGeometrysOwn) {
  for (int dim : {0, 1, 4}) {
    Geometry g;
    g.dimension = dim;
    const GeometryError e = engine::ValidateGeometry(g);
    EXPECT_EQ(e.patch, -1);
    EXPECT_EQ(e.field, GeometryField::Dimension);
    EXPECT_EQ(e.message, std::to_string(dim) + ", expected 2 or 3");
  }
  // A mesh 1.4e-120 across: its squared distances would underflow.
  Geometry g;
  g.patches.push_back(TriMesh(3));
  for (double& x : g.patches[0].points) x *= 1e-120;
  GeometryError e = engine::ValidateGeometry(g);
  EXPECT_EQ(e.patch, -1);
  EXPECT_EQ(e.field, GeometryField::None);
  EXPECT_EQ(e.message,
            "the geometry is 1.41421e-120 across (its box diagonal), below 1e-100 (the smallest extent invmap "
            "supports)");
  // A vertex no cell uses is not part of the geometry.
  g.patches[0].points.insert(g.patches[0].points.end(), {1, 1, 1});
  EXPECT_EQ(engine::ValidateGeometry(g).message, e.message);
  // A single point (every control point equal) has no extent to measure.
  for (double& x : g.patches[0].points) x = 0.5;
  EXPECT_FALSE(engine::ValidateGeometry(g));
}

TEST(GeometryValidationTest, TheFirstProblemInPatchOrderIsReported) {
  Geometry g;
  g.patches.push_back(TriMesh(3));
  g.patches.push_back(TriMesh(3));
  g.patches.push_back(TriMesh(3));
  g.patches[2].cells[0] = 7;
  g.patches[1].cells[5] = -2;
  const GeometryError e = engine::ValidateGeometry(g);
  EXPECT_EQ(e.patch, 1);
  EXPECT_EQ(e.element, 1);
  EXPECT_EQ(e.item, 2);
}

TEST(GeometryValidationTest, ValidGeometriesOfEveryKindPass) {
  const Geometry geometries[] = {WavySurfaces(),     BSplineCurves(2), BSplineCurves(3),     BSplineVolumes(),
                                 QuadraticMesh(false), QuadraticMesh(true), MixedGeometry2(), MixedGeometry3(),
                                 NurbsTorus({0, 0, 0}, 2.0, 0.5)};
  for (const Geometry& g : geometries) {
    EXPECT_FALSE(engine::ValidateGeometry(g)) << Describe(engine::ValidateGeometry(g));
  }
}

TEST(GeometryValidationTest, AGeometryWithoutCellsIsRefused) {
  // Every point would be "none" against it: a mistake, not a geometry.
  Geometry empty;
  const GeometryError error = engine::ValidateGeometry(empty);
  EXPECT_TRUE(error);
  EXPECT_NE(error.message.find("the geometry has no cells"), std::string::npos) << error.message;
}

}  // namespace
}  // namespace invmap::testing
