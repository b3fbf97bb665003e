// Meshes the construction refuses, each with a message naming the vertex,
// edge or triangle at fault, and the rings of a valid one.
#include <gtest/gtest.h>

#include <cmath>

#include "pou/closed_mesh.h"
#include "tests/support/pou_meshes.h"

namespace invmap::pou {
namespace {

std::string Check(const testing::TriangleMesh& m) {
  ClosedMesh mesh;
  return mesh.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles());
}

TEST(ClosedMeshTest, RingsTurnCounterClockwiseFromTheFirstTriangle) {
  const testing::TriangleMesh m = testing::Bipyramid(5);
  ClosedMesh mesh;
  ASSERT_EQ(mesh.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles()), "");
  EXPECT_EQ(mesh.valence(0), 5);
  EXPECT_EQ(mesh.valence(2), 4);
  // Apex 0: first triangle (0, 2, 3), so the ring starts at 2 and turns 2, 3, 4, ...
  for (int i = 0; i < 5; ++i) EXPECT_EQ(mesh.neighbor(0, i), 2 + i);
  for (std::int64_t v = 0; v < mesh.numVertices(); ++v) {
    for (int i = 0; i < mesh.valence(v); ++i) {
      const std::int64_t u = mesh.neighbor(v, i);
      EXPECT_EQ(mesh.neighbor(u, mesh.mate(v, i)), v);
      // Triangle i of the star is (v, u_i, u_{i+1}) up to a cyclic shift.
      const std::int64_t t = mesh.starTriangle(v, i);
      const int k = mesh.CornerOf(t, v);
      EXPECT_EQ(mesh.triangles()[3 * t + (k + 1) % 3], u);
      EXPECT_EQ(mesh.triangles()[3 * t + (k + 2) % 3], mesh.neighbor(v, (i + 1) % mesh.valence(v)));
    }
  }
}

TEST(ClosedMeshTest, BoundaryEdge) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  m.triangles.resize(m.triangles.size() - 3);  // drop the last triangle (1, 2, 5): edges (1, 2), (2, 5), (1, 5) open
  EXPECT_EQ(Check(m), "edge (1, 2) is on the boundary: only triangle 1 uses it (the mesh must be closed)");
}

TEST(ClosedMeshTest, NonManifoldEdge) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  m.xyz.insert(m.xyz.end(), {0.5, 0.5, 3.0});
  m.triangles.insert(m.triangles.end(), {0, 2, 6, 2, 0, 6});  // a two-sided fin on edge (0, 2)
  EXPECT_EQ(Check(m), "edge (0, 2) is non-manifold: 4 triangles use it (0, 6, 8, 9)");
}

TEST(ClosedMeshTest, InconsistentOrientation) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  std::swap(m.triangles[1], m.triangles[2]);  // flip triangle 0
  EXPECT_NE(Check(m).find("in the same direction (inconsistent orientation)"), std::string::npos) << Check(m);
}

TEST(ClosedMeshTest, IsolatedVertex) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  m.xyz.insert(m.xyz.end(), {5, 5, 5});
  EXPECT_EQ(Check(m), "vertex 6 belongs to no triangle (isolated)");
}

TEST(ClosedMeshTest, NonManifoldVertex) {
  // Two octahedra sharing one vertex.
  testing::TriangleMesh a = testing::Bipyramid(4), b = testing::Bipyramid(4);
  testing::TriangleMesh m = a;
  const std::int64_t offset = a.numVertices() - 1;
  for (std::int64_t v = 1; v < b.numVertices(); ++v)
    m.xyz.insert(m.xyz.end(), {b.xyz[3 * v], b.xyz[3 * v + 1], b.xyz[3 * v + 2] + 2.2});
  for (std::int64_t i : b.triangles) m.triangles.push_back(i == 0 ? 0 : i + offset);
  EXPECT_EQ(Check(m), "vertex 0 is non-manifold: its triangles form more than one fan");
}

TEST(ClosedMeshTest, DegenerateTriangles) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  m.triangles[1] = m.triangles[0];
  EXPECT_EQ(Check(m), "triangle 0 (vertices 0, 0, 3) repeats a vertex (degenerate)");
  testing::TriangleMesh flat = testing::Bipyramid(4);
  for (int c = 0; c < 3; ++c) flat.xyz[3 * 3 + c] = flat.xyz[3 * 2 + c];  // vertex 3 onto vertex 2
  EXPECT_EQ(Check(flat), "triangle 0 (vertices 0, 2, 3) has zero area (degenerate)");
}

TEST(ClosedMeshTest, NonFiniteVertex) {
  testing::TriangleMesh m = testing::Bipyramid(4);
  m.xyz[3 * 2 + 1] = std::nan("");
  EXPECT_EQ(Check(m), "vertex 2: coordinate 1 is not finite (nan)");
  testing::TriangleMesh far = testing::Bipyramid(4);
  far.xyz[3 * 5 + 2] = HUGE_VAL;
  EXPECT_EQ(Check(far), "vertex 5: coordinate 2 is not finite (inf)");
}

TEST(ClosedMeshTest, ValenceTwo) {
  // A pillow: two triangles glued along their three edges.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::int64_t> tri = {0, 1, 2, 0, 2, 1};
  ClosedMesh mesh;
  EXPECT_EQ(mesh.Build(xyz.data(), 3, tri.data(), 2), "vertex 0 has valence 2 (charts need 3 or more)");
}

}  // namespace
}  // namespace invmap::pou
