// ProbeFields and CheckFields on hand-made patches: linear meshes, single
// Bezier cells, rational cells (their rational basis), points not found,
// patches a field does not cover, and the checks' messages.
#include <gtest/gtest.h>

#include <cmath>

#include "invmap/fields.h"
#include "tests/fem/fem_test_support.h"

namespace invmap::testing {
namespace {

/// Two linear tets sharing a face (a Mesh patch) with a vertex field.
Geometry TwoTets() {
  Geometry g;
  Patch& p = g.patches.emplace_back();
  p.kind = Patch::Kind::Mesh;
  p.cell = CellType::Tet;
  p.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  p.cells = {0, 1, 2, 3, 1, 2, 3, 4};
  return g;
}

TEST(ProbeFields, LinearMeshFieldIsInterpolatedInEachCell) {
  const Geometry g = TwoTets();
  NodeField f{"f", 1, {{10, 11, 12, 13, 14}}};
  ASSERT_EQ(CheckFields(g, {f}), "");
  // Cell 1 at reference (0.2, 0.3, 0.1): vertices 1, 2, 3, 4 with weights 0.4, 0.2, 0.3, 0.1.
  Results r = OnePointAt(0, 1, {0.2, 0.3, 0.1});
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(g, {&f}, r, &values), Error::Ok);
  EXPECT_NEAR(values[0], 0.4 * 11 + 0.2 * 12 + 0.3 * 13 + 0.1 * 14, 1e-14);
}

/// Two cells of one linear type back to back in a BezierCells patch (a
/// mesh of one element type read from a file becomes one), its control
/// points unused by the interpolation.
Geometry TwoLinearCells(CellType type, int nodes) {
  Geometry g;
  Patch& p = g.patches.emplace_back();
  p.kind = Patch::Kind::BezierCells;
  p.cellOffsets = {0};
  for (int c = 0; c < 2; ++c) {
    for (int k = 0; k < 3 * nodes; ++k) p.points.push_back(0.1 * k + c);
    p.cellTypes.push_back(type);
    p.cellDegrees.insert(p.cellDegrees.end(), {1, 1, 1});
    p.cellOffsets.push_back((c + 1) * nodes);
  }
  return g;
}

TEST(ProbeFields, UniformLinearCellsInterpolateTheirCoefficients) {
  // Cell 1 of each: a scalar and a 2-vector field, against the closed
  // forms (barycentric coordinates; the trilinear basis, first parameter
  // fastest in the node order).
  const std::array<double, 3> u{0.2, 0.7, 0.35};
  for (const bool hex : {false, true}) {
    const int nodes = hex ? 8 : 4;
    const Geometry g = TwoLinearCells(hex ? CellType::Hex : CellType::Tet, nodes);
    NodeField scalar{"s", 1, {{}}}, vector{"v", 2, {{}}};
    for (int k = 0; k < 2 * nodes; ++k) {
      scalar.patchValues[0].push_back(std::sin(1.0 + k));
      vector.patchValues[0].insert(vector.patchValues[0].end(), {std::cos(2.0 * k), 3.0 - k});
    }
    ASSERT_EQ(CheckFields(g, {scalar, vector}), "");
    std::vector<double> values;
    ASSERT_EQ(ProbeFields(g, {&scalar, &vector}, OnePointAt(0, 1, u), &values), Error::Ok);
    double expected[3] = {0, 0, 0};
    for (int n = 0; n < nodes; ++n) {
      double b = 0.0;
      if (hex) {
        b = ((n & 1) ? u[0] : 1 - u[0]) * ((n & 2) ? u[1] : 1 - u[1]) * ((n & 4) ? u[2] : 1 - u[2]);
      } else {
        b = n == 0 ? 1 - u[0] - u[1] - u[2] : u[n - 1];
      }
      expected[0] += b * scalar.patchValues[0][nodes + n];
      for (int j = 0; j < 2; ++j) expected[1 + j] += b * vector.patchValues[0][2 * (nodes + n) + j];
    }
    ASSERT_EQ(values.size(), 3u);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(values[j], expected[j], 1e-14) << (hex ? "hex " : "tet ") << j;
  }
}

TEST(ProbeFields, QuadMeshUsesFiniteElementVertexOrder) {
  Geometry g;
  g.dimension = 2;
  Patch& p = g.patches.emplace_back();
  p.kind = Patch::Kind::Mesh;
  p.cell = CellType::Quad;
  p.points = {0, 0, 1, 0, 1, 1, 0, 1};
  p.cells = {0, 1, 2, 3};  // counter-clockwise
  NodeField f{"f", 1, {{0, 1, 2, 3}}};
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(g, {&f}, OnePointAt(0, 0, {1.0, 1.0, 0}), &values), Error::Ok);
  EXPECT_EQ(values[0], 2.0);  // vertex 2 is at (1, 1)
  ASSERT_EQ(ProbeFields(g, {&f}, OnePointAt(0, 0, {0.0, 1.0, 0}), &values), Error::Ok);
  EXPECT_EQ(values[0], 3.0);
}

// A rational quadratic Bezier line: a field's value is the rational
// combination w_i B_i f_i / sum w_j B_j.
TEST(ProbeFields, RationalCellUsesItsRationalBasis) {
  Geometry g;
  Patch& p = g.patches.emplace_back();
  p.kind = Patch::Kind::Bezier;
  p.cell = CellType::Line;
  p.degrees = {2};
  p.points = {1, 0, 0, 1, 1, 0, 0, 1, 0};
  p.weights = {1, std::sqrt(0.5), 1};
  NodeField f{"f", 2, {{1, 0, 1, 1, 0, 1}}};  // the control points' x and y: the quarter circle
  ASSERT_EQ(CheckFields(g, {f}), "");
  std::vector<double> values;
  const double t = 0.3;
  ASSERT_EQ(ProbeFields(g, {&f}, OnePointAt(0, 0, {t, 0, 0}), &values), Error::Ok);
  EXPECT_NEAR(std::hypot(values[0], values[1]), 1.0, 1e-15);
  const double b[3] = {(1 - t) * (1 - t), 2 * t * (1 - t) * std::sqrt(0.5), t * t};
  EXPECT_NEAR(values[1], (b[1] + b[2]) / (b[0] + b[1] + b[2]), 1e-15);
}

TEST(ProbeFields, NotFoundAndUncoveredPointsAreNaN) {
  Geometry g = TwoTets();
  Patch& spline = g.patches.emplace_back();
  spline.kind = Patch::Kind::BSpline;
  NodeField f{"f", 3, {std::vector<double>(15, 1.0), {}}};
  ASSERT_EQ(CheckFields(g, {f}), "");
  Results r = OnePointAt(1, 0, {0.5, 0.5, 0});
  r.status.push_back(Status::None);
  r.patch.push_back(-1);
  r.cell.push_back(-1);
  r.params.insert(r.params.end(), 3, std::nan(""));
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(g, {&f}, r, &values), Error::Ok);
  ASSERT_EQ(values.size(), 6u);
  for (double v : values) EXPECT_TRUE(std::isnan(v));
  std::string message;
  EXPECT_EQ(ProbeFields(g, {&f}, OnePointAt(5, 0, {0, 0, 0}), &values, &message), Error::InvalidArgument);
  EXPECT_NE(message.find("patch 5"), std::string::npos) << message;
}

TEST(ProbeFields, ChecksAndColumnNames) {
  Geometry g = TwoTets();
  EXPECT_NE(CheckFields(g, {{"f", 1, {{1, 2}}}}).find("field 'f': patch 0: 2 values, expected 5"), std::string::npos);
  EXPECT_NE(CheckFields(g, {{"f", 1, {{}}}, {"f", 1, {{}}}}).find("defined twice"), std::string::npos);
  EXPECT_NE(CheckFields(g, {{"f", 0, {{}}}}).find("components"), std::string::npos);
  EXPECT_NE(CheckFields(g, {{"f", 1, {}}}).find("0 patch arrays for 1 patches"), std::string::npos);
  const NodeField a{"T", 1, {}}, b{"U", 3, {}};
  EXPECT_EQ(FieldColumnNames({&a, &b}), (std::vector<std::string>{"T", "U_0", "U_1", "U_2"}));
  EXPECT_EQ(FieldWidth({&a, &b}), 4);
}

}  // namespace
}  // namespace invmap::testing
