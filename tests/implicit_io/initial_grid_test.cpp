// Tests of the initial-grid reader of `invmap grid` on cube6.msh and on
// small gmsh files: merged vertices, orientation, and every error.
#include "implicit_io/initial_grid.h"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "invmap/implicit.h"
#include "io/input_error.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;

const std::string kBenchDir = INVMAP_IMPLICIT_DATA_DIR "/";

double SignedVolume(const implicit::SimplexMesh& mesh, std::size_t c) {
  const std::size_t per = static_cast<std::size_t>(mesh.dimension + 1);
  const double* v = mesh.vertices.data();
  const std::uint32_t* cell = mesh.cells.data() + c * per;
  double e[3][3];
  for (int i = 0; i < mesh.dimension; ++i)
    for (int a = 0; a < 3; ++a) e[i][a] = v[3 * cell[i + 1] + a] - v[3 * cell[0] + a];
  if (mesh.dimension == 2) return (e[0][0] * e[1][1] - e[0][1] * e[1][0]) / 2;
  return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
          e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
         6;
}

TEST(ImplicitGridMsh, ReadsCube6) {
  const implicit::SimplexMesh mesh = ReadSimplexMeshMsh(kBenchDir + "cube6.msh");
  EXPECT_EQ(mesh.dimension, 3);
  EXPECT_EQ(mesh.numVertices(), 8u);
  ASSERT_EQ(mesh.numCells(), 6u);
  double total = 0;
  for (std::size_t c = 0; c < mesh.numCells(); ++c) {
    const double volume = SignedVolume(mesh, c);
    EXPECT_GT(volume, 0) << "cell " << c;
    total += volume;
  }
  EXPECT_NEAR(total, 1.0, 1e-15);
  for (const double x : mesh.vertices) EXPECT_TRUE(x == 0.0 || x == 1.0);
}

/// A one-entity MSH 4.1 file: `nodes` (x y z each) tagged 1.., and one
/// element block of gmsh `type` of the given dimension, elements tagged 1..
std::string MshText(const std::vector<std::array<double, 3>>& nodes, int dim, int type,
                    const std::vector<std::vector<int>>& elements) {
  std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 " + std::to_string(nodes.size()) + " 1 " +
                  std::to_string(nodes.size()) + "\n" + std::to_string(dim) + " 1 0 " + std::to_string(nodes.size()) +
                  "\n";
  for (std::size_t i = 0; i < nodes.size(); ++i) s += std::to_string(i + 1) + "\n";
  for (const auto& p : nodes) {
    char line[100];
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    s += line;
  }
  s += "$EndNodes\n$Elements\n1 " + std::to_string(elements.size()) + " 1 " + std::to_string(elements.size()) + "\n" +
       std::to_string(dim) + " 1 " + std::to_string(type) + " " + std::to_string(elements.size()) + "\n";
  for (std::size_t e = 0; e < elements.size(); ++e) {
    s += std::to_string(e + 1);
    for (const int n : elements[e]) s += " " + std::to_string(n);
    s += "\n";
  }
  return s + "$EndElements\n";
}

TEST(ImplicitGridMsh, TrianglesMergedAndOriented) {
  ScratchDir dir;
  // A unit square of two triangles, the second clockwise, with a duplicate
  // node (5 = 3) that must merge.
  const std::string path = dir.Write(
      "square.msh", MshText({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1, 0}}, 2, 2, {{1, 2, 3}, {1, 4, 5}}));
  const implicit::SimplexMesh mesh = ReadSimplexMeshMsh(path);
  EXPECT_EQ(mesh.dimension, 2);
  EXPECT_EQ(mesh.numVertices(), 4u);
  ASSERT_EQ(mesh.numCells(), 2u);
  EXPECT_NEAR(SignedVolume(mesh, 0), 0.5, 1e-15);
  EXPECT_NEAR(SignedVolume(mesh, 1), 0.5, 1e-15);
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) EXPECT_EQ(mesh.vertices[3 * v + 2], 0.0);
}

TEST(ImplicitGridMsh, Errors) {
  ScratchDir dir;
  const std::vector<std::array<double, 3>> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}};
  // A flat tetrahedron (nodes 1, 2, 3, 5 in the plane z = 0).
  const std::string flat = dir.Write("flat.msh", MshText(corners, 3, 4, {{1, 2, 3, 4}, {1, 2, 3, 5}}));
  ExpectInputError([&] { ReadSimplexMeshMsh(flat); }, flat, 0, "cell 1 has zero volume");
  // A quadrangle in 2D.
  const std::string quad = dir.Write("quad.msh", MshText({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 2, 3,
                                                         {{1, 2, 3, 4}}));
  ExpectInputError([&] { ReadSimplexMeshMsh(quad); }, quad, 0, "element 1 (in file order) is a quadrangle");
  // A quadratic triangle.
  const std::string curved = dir.Write(
      "p2.msh", MshText({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {0, 0.5, 0}}, 2, 9,
                        {{1, 2, 3, 4, 5, 6}}));
  ExpectInputError([&] { ReadSimplexMeshMsh(curved); }, curved, 0, "triangle of order 2");
  // Triangles off the plane z = 0 make a 3D surface, not a grid.
  const std::string surface =
      dir.Write("surface.msh", MshText({{0, 0, 0}, {1, 0, 0}, {0, 1, 1}}, 2, 2, {{1, 2, 3}}));
  ExpectInputError([&] { ReadSimplexMeshMsh(surface); }, surface, 0, "no cells: an initial grid has linear tetrahedra");
  // ReadGmsh's own errors pass through.
  const std::string broken = dir.Write("broken.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  ExpectInputError([&] { ReadSimplexMeshMsh(broken); }, broken, -1, "");
}

}  // namespace
}  // namespace invmap::io
