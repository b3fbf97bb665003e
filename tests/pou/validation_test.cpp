// The one validation of a geometry (engine/geometry_validation.h) on
// pou_manifold patches: each rule's structured error (field, element, item,
// message) written out by hand, and a valid surface passes.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "engine/geometry_validation.h"
#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/support/pou_meshes.h"

namespace invmap::testing {
namespace {

/// The octahedron's surface (6 charts of valence 4), fitted to its Loop limit.
Geometry Octahedron() {
  const TriangleMesh mesh = Bipyramid(4);
  Geometry geometry;
  Patch& patch = geometry.patches.emplace_back();
  EXPECT_EQ(BuildPouManifold(mesh.xyz.data(), mesh.numVertices(), mesh.triangles.data(), mesh.numTriangles(), {},
                             &patch),
            "");
  return geometry;
}

void ExpectError(const Geometry& geometry, GeometryField field, std::int64_t element, std::int64_t item,
                 const std::string& message) {
  const GeometryError e = engine::ValidateGeometry(geometry);
  ASSERT_TRUE(e) << "no error, expected " << message;
  EXPECT_EQ(e.patch, 0);
  EXPECT_EQ(e.field, field) << e.message;
  EXPECT_EQ(e.element, element) << e.message;
  EXPECT_EQ(e.item, item) << e.message;
  EXPECT_EQ(e.message, message);
}

TEST(PouValidationTest, AValidSurfacePasses) {
  const Geometry geometry = Octahedron();
  EXPECT_FALSE(engine::ValidateGeometry(geometry)) << Describe(engine::ValidateGeometry(geometry));
  EXPECT_EQ(Manifold::Build(geometry).error, "");
}

TEST(PouValidationTest, EachRuleNamesItsField) {
  {
    Geometry g = Octahedron();
    g.dimension = 2;
    g.patches[0].points.resize(12);  // 6 points of the plane
    ExpectError(g, GeometryField::Kind, -1, -1, "a pou_manifold is a surface of R^3: it needs dimension 3");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].weights.assign(6, 1.0);
    ExpectError(g, GeometryField::Weights, -1, -1, "a pou_manifold has no weights");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].cells[7] = 6;
    ExpectError(g, GeometryField::Cells, 2, 1, "vertex index 6 out of range (the patch has 6 vertices)");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].degrees.pop_back();
    ExpectError(g, GeometryField::Degrees, -1, -1, "5 values, expected one per vertex (6)");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].degrees[3] = 9;
    ExpectError(g, GeometryField::Degrees, 3, -1, "9, expected 1 to 8");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].chartControlPoints.pop_back();
    const std::size_t n = g.patches[0].chartControlPoints.size() + 1;
    ExpectError(g, GeometryField::ChartControlPoints, -1, -1,
                std::to_string(n - 1) + " coordinates, expected " + std::to_string(n) +
                    " (3 for each of the (degree + 1)^2 control points of every vertex's chart)");
  }
  {
    Geometry g = Octahedron();
    g.patches[0].chartControlPoints[3 * 7 + 2] = std::numeric_limits<double>::quiet_NaN();
    ExpectError(g, GeometryField::ChartControlPoints, 7, 2,
                "coordinate 2 is nan, not a finite number within [-1e100, 1e100]");
  }
}

TEST(PouValidationTest, TheMeshMustBeClosedOrientedAndManifold) {
  {
    // Without its last triangle the mesh has a boundary.
    Geometry g = Octahedron();
    g.patches[0].cells.resize(g.patches[0].cells.size() - 3);
    const GeometryError e = engine::ValidateGeometry(g);
    ASSERT_TRUE(e);
    EXPECT_EQ(e.field, GeometryField::Cells);
    EXPECT_NE(e.message.find("is on the boundary: only triangle"), std::string::npos) << e.message;
    EXPECT_EQ(e.message.rfind("edge (", 0), 0u) << e.message;
  }
  {
    Geometry g = Octahedron();
    auto& cells = g.patches[0].cells;
    std::swap(cells[0], cells[1]);  // triangle 0 turned over
    const GeometryError e = engine::ValidateGeometry(g);
    ASSERT_TRUE(e);
    EXPECT_EQ(e.field, GeometryField::Cells);
    EXPECT_NE(e.message.find("in the same direction (inconsistent orientation)"), std::string::npos) << e.message;
  }
  {
    Geometry g = Octahedron();
    auto& cells = g.patches[0].cells;
    cells[1] = cells[0];  // triangle 0 repeats a vertex
    const GeometryError e = engine::ValidateGeometry(g);
    ASSERT_TRUE(e);
    EXPECT_NE(e.message.find("triangle 0"), std::string::npos) << e.message;
  }
  // Every one of these is refused by Manifold::Build too, with the same words.
  Geometry g = Octahedron();
  g.patches[0].cells.resize(g.patches[0].cells.size() - 3);
  const BuildResult built = Manifold::Build(g);
  EXPECT_EQ(built.code, Error::InvalidArgument);
  EXPECT_EQ(built.error, Describe(engine::ValidateGeometry(g)));
}

}  // namespace
}  // namespace invmap::testing
