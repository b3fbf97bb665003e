// Tests of the files of `invmap grid`: the function list and CSG tree readers
// on the benchmark inputs and on every error, the initial-grid reader on
// cube6.msh and small gmsh files, and the grid, zero-set and stats writers
// read back by invmap's own readers (and gmsh when installed).
#include "io/implicit_files.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "invmap/implicit.h"
#include "invmap/invmap.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/ply_mesh.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;

const std::string kBenchDir = INVMAP_IMPLICIT_DATA_DIR "/";

/// f(x) of one function at one point.
double Evaluate(const implicit::Function& f, const implicit::Vec3& x) {
  double value = 0, gradient[3] = {0, 0, 0};
  f.evaluate(x.data(), 1, &value, gradient);
  return value;
}

double Distance(const implicit::Vec3& a, const implicit::Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// ---------------------------------------------------------------------------
// Function lists.

TEST(ImplicitFunctionList, ReadsEveryBenchmarkList) {
  const std::map<std::string, std::size_t> expected = {
      {"1-sphere.json", 1},      {"10-wikiBall.json", 10}, {"18-sphere.json", 18}, {"2-close-sphere.json", 2},
      {"2-cylSphere.json", 2},   {"3-cyl3.json", 3},       {"3-sphere.json", 3},
  };
  std::size_t lists = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kBenchDir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".json" || name.find("-tree") != std::string::npos) continue;
    SCOPED_TRACE(name);
    ASSERT_EQ(expected.count(name), 1u) << "unexpected benchmark file";
    const std::vector<implicit::Function> functions = ReadFunctionList(entry.path().string(), 3);
    EXPECT_EQ(functions.size(), expected.at(name));
    for (const implicit::Function& f : functions) EXPECT_TRUE(f.evaluate);
    ++lists;
  }
  EXPECT_EQ(lists, expected.size());
}

TEST(ImplicitFunctionList, SphereValuesFollowTheFile) {
  const std::vector<implicit::Function> one = ReadFunctionList(kBenchDir + "1-sphere.json", 3);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "sphere");
  const implicit::Vec3 center = {0.5112321, 0.51412521, 0.51};
  for (const implicit::Vec3& x : {implicit::Vec3{0.1, 0.2, 0.3}, implicit::Vec3{0.9, 0.5, 0.5}, center}) {
    EXPECT_NEAR(Evaluate(one[0], x), 0.3 - Distance(x, center), 1e-15);
  }

  // 10-wikiBall: planes, squared cylinders and a squared sphere.
  const std::vector<implicit::Function> ball = ReadFunctionList(kBenchDir + "10-wikiBall.json", 3);
  ASSERT_EQ(ball.size(), 10u);
  EXPECT_EQ(ball[0].name, "plane");
  EXPECT_EQ(ball[6].name, "cylinder");
  EXPECT_EQ(ball[9].name, "sphere");
  const implicit::Vec3 x = {0.3, 0.7, 0.45};
  EXPECT_NEAR(Evaluate(ball[0], x), x[1] - 0.8125, 1e-15);  // normal (0, 1, 0) through y = 0.8125
  EXPECT_NEAR(Evaluate(ball[1], x), -(x[1] - 0.2125), 1e-15);
  const implicit::Vec3 c = {0.5125, 0.5125, 0.5125};
  EXPECT_NEAR(Evaluate(ball[9], x), 0.4 * 0.4 - Distance(x, c) * Distance(x, c), 1e-15);
  // Cylinder 6: axis z through (0.5125, 0.5125).
  const double rho2 = (x[0] - 0.5125) * (x[0] - 0.5125) + (x[1] - 0.5125) * (x[1] - 0.5125);
  EXPECT_NEAR(Evaluate(ball[6], x), 0.2 * 0.2 - rho2, 1e-15);
}

TEST(ImplicitFunctionList, EveryTypeAndTwoDimensionalPoints) {
  ScratchDir dir;
  const std::string path = dir.Write("all.json", R"([
  {"type": "sphere", "center": [1, 2, 0], "radius": 2, "name": "disk"},
  {"type": "cylinder", "axis_point": [0, 0, 0], "axis_vector": [0, 0, 3], "radius": 1, "squared": true},
  {"type": "plane", "point": [0, 0, 1], "normal": [0, 0, -2]},
  {"type": "torus", "center": [0, 0, 0], "axis_vector": [0, 0, 1], "major_radius": 2, "minor_radius": 0.5},
  {"type": "cone", "apex": [0, 0, 0], "axis_vector": [0, 0, 1], "apex_angle": 0.5},
  {"type": "quintic"},
  {"type": "quintic", "center": [1.0, 0, 0]},
  {"type": "gyroid", "period": 2}
])");
  const std::vector<implicit::Function> f = ReadFunctionList(path, 3);
  ASSERT_EQ(f.size(), 8u);
  EXPECT_EQ(f[0].name, "disk");
  EXPECT_EQ(f[1].name, "cylinder");
  EXPECT_EQ(f[7].name, "gyroid");
  // The 2D centre has z = 0.
  EXPECT_NEAR(Evaluate(f[0], {1, 2, 0}), 2, 1e-15);
  EXPECT_NEAR(Evaluate(f[0], {1, 2, 1}), 1, 1e-15);
  EXPECT_NEAR(Evaluate(f[1], {0.5, 0, 7}), 1 - 0.25, 1e-15);
  EXPECT_NEAR(Evaluate(f[2], {5, 5, 0.25}), 0.75, 1e-15);  // normalized normal
  EXPECT_NEAR(Evaluate(f[3], {2, 0, 0}), 0.5, 1e-12);      // on the core circle
  EXPECT_NEAR(Evaluate(f[5], {1, 1, 0}), 1 + 1 - 2, 1e-15);
  EXPECT_NEAR(Evaluate(f[6], {2, 1, 0}), 1 + 1 - 2, 1e-15);

  // A 2D grid's functions have 2-number points (z = 0), and only those.
  const std::string planar = dir.Write("planar.json", R"([
  {"type": "sphere", "center": [1, 2], "radius": 2},
  {"type": "quintic", "center": [1.0, 0]}
])");
  const std::vector<implicit::Function> g = ReadFunctionList(planar, 2);
  EXPECT_NEAR(Evaluate(g[0], {1, 2, 0}), 2, 1e-15);
  EXPECT_NEAR(Evaluate(g[1], {2, 1, 0}), 1 + 1 - 2, 1e-15);
  ExpectInputError([&] { ReadFunctionList(planar, 3); }, planar, 2, "center: 2 numbers, expected 3 numbers (the grid is 3D)");
  ExpectInputError([&] { ReadFunctionList(path, 2); }, path, 2, "center: 3 numbers, expected 2 numbers (the grid is 2D)");
}

TEST(ImplicitFunctionList, Errors) {
  ScratchDir dir;
  struct Case {
    const char* text;
    std::int64_t line;
    const char* part;
  };
  const Case cases[] = {
      {"", 1, "empty file"},
      {"\n\n", 3, "empty file"},
      {"[\n  {\"type\": \"sphere\",\n   \"center\": [0, 0, 0]\n   \"radius\": 1}]", 4, "invalid JSON"},
      {"[\n{\"type\": \"sphere\", \"center\": [0, 0, NaN], \"radius\": 1}]", 2, "every number must be finite"},
      {"{\"type\": \"sphere\"}", 1, "expected a JSON list"},
      {"\n  []", 2, "empty list"},
      {"[\n  1.5\n]", 2, "expected a function object, found 1.5"},
      {"[\n  {\"center\": [0, 0, 0], \"radius\": 1}\n]", 2, "missing field \"type\""},
      {"[\n  {\"type\": 3}\n]", 2, "functions[0].type: expected a string"},
      {"[{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1},\n {\"type\": \"blob\"}]", 2,
       "unknown function type \"blob\" (known: sphere, cylinder, plane, torus, cone, quintic, gyroid)"},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": 1,\n \"radus\": 2}]", 4,
       "unknown field \"radus\""},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0]}]", 1, "functions[0]: missing field \"radius\""},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": \"1\"}]", 3,
       "functions[0].radius: expected a number, found the string \"1\""},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": 1, \"squared\": 1}]", 3,
       "squared: expected true or false"},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0, 1],\n \"radius\": 1}]", 2, "center: 4 numbers, expected 3"},
      {"[{\"type\": \"sphere\",\n \"center\": [0],\n \"radius\": 1}]", 2, "center: 1 numbers"},
      {"[{\"type\": \"sphere\",\n \"center\": 0,\n \"radius\": 1}]", 2, "center: expected a list of 3 numbers"},
      {"[{\"type\": \"sphere\",\n \"center\": [0,\n null, 0],\n \"radius\": 1}]", 3,
       "center[1]: expected a number, found null"},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": 1e999}]", 3, "number overflow"},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": 0}]", 3, "radius: 0, expected a positive"},
      {"[{\"type\": \"sphere\",\n \"center\": [0, 0, 0],\n \"radius\": -1.5}]", 3, "-1.5, expected a positive"},
      {"[{\"type\": \"sphere\", \"radius\": 1,\n \"center\": [0, 0, 0],\n \"radius\": 2}]", 3,
       "duplicate field \"radius\""},
      {"[{\"type\": \"plane\", \"point\": [0, 0, 0],\n \"normal\": [0, 0, 0]}]", 2, "normal: zero vector"},
      {"[{\"type\": \"plane\", \"point\": [0, 0, 0],\n \"normal\": [1e300, 1e300, 0]}]", 2, "overflows"},
      {"[{\"type\": \"cylinder\", \"axis_point\": [0, 0, 0],\n \"axis_vector\": [0, 0, 0],\n \"radius\": 1}]", 2,
       "axis_vector: zero vector"},
      {"[{\"type\": \"torus\", \"center\": [0, 0, 0], \"axis_vector\": [0, 0, 1],\n \"major_radius\": 1,\n"
       " \"minor_radius\": -1}]",
       3, "minor_radius: -1"},
      {"[{\"type\": \"cone\", \"apex\": [0, 0, 0], \"axis_vector\": [0, 0, 1],\n \"apex_angle\": 2}]", 2,
       "angle: 2, expected a half angle in radians in (0, pi/2)"},
      {"[{\"type\": \"gyroid\",\n \"period\": 0}]", 2, "period: 0"},
      {"[{\"type\": \"gyroid\"}]", 1, "missing field \"period\""},
      {"[{\"type\": \"quintic\",\n \"name\": 7}]", 2, "name: expected a string"},
      {"[{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],\n \"radius\": 1}]", 2,
       "unknown field \"radius\" for a plane (fields: type, name, point, normal)"},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string path = dir.Write("case" + std::to_string(index++) + ".json", c.text);
    ExpectInputError([&] { ReadFunctionList(path, 3); }, path, c.line, c.part);
  }
  ExpectInputError([&] { ReadFunctionList(dir.Path("missing.json"), 3); }, dir.Path("missing.json"), -1, "");
}

// ---------------------------------------------------------------------------
// CSG trees.

TEST(ImplicitCsgTree, ReadsTheWikiBallTree) {
  const std::vector<implicit::CsgNode> tree = ReadCsgTree(kBenchDir + "10-wikiBall-tree.json", 10);
  ASSERT_EQ(tree.size(), 14u);
  EXPECT_EQ(tree[0].op, implicit::CsgNode::Op::Intersection);
  EXPECT_EQ(tree[0].a, 2);
  EXPECT_EQ(tree[0].b, 8);
  EXPECT_EQ(tree[2].a, -1);
  EXPECT_EQ(tree[2].b, 4);
  EXPECT_EQ(tree[7].op, implicit::CsgNode::Op::Negation);
  EXPECT_EQ(tree[7].a, 9);
  EXPECT_EQ(tree[7].b, 0);
  EXPECT_EQ(tree[8].op, implicit::CsgNode::Op::Union);
  EXPECT_EQ(tree[13].a, -10);
  // With 9 functions, node 14's operand -10 (line 96) is out of range.
  ExpectInputError([&] { ReadCsgTree(kBenchDir + "10-wikiBall-tree.json", 9); },
                   kBenchDir + "10-wikiBall-tree.json", 96, "function 10 out of range (there are 9 functions");
}

TEST(ImplicitCsgTree, Errors) {
  ScratchDir dir;
  struct Case {
    const char* text;
    std::int64_t line;
    const char* part;
  };
  const Case cases[] = {
      {"[]", 1, "empty list"},
      {"{}", 1, "expected a JSON list of CSG nodes"},
      {"[\n 3]", 2, "node 1: expected an object"},
      {"[{\"type\": \"Union\", \"elements\": [-1, -2]},\n {\"type\": \"Xor\", \"elements\": [-1, -2]}]", 2,
       "node 2.type: unknown node type \"Xor\" (known: Intersection, Union or Negation)"},
      {"[{\"type\": \"union\", \"elements\": [-1, -2]}]", 1, "unknown node type \"union\""},
      {"[{\"elements\": [-1, -2]}]", 1, "missing field \"type\""},
      {"[{\"type\": \"Union\"}]", 1, "missing field \"elements\""},
      {"[{\"type\": \"Union\", \"elements\": [-1, -2],\n \"extra\": 1}]", 2, "unknown field \"extra\""},
      {"[{\"type\": \"Union\",\n \"elements\": [-1]}]", 2, "1 operand, Union takes two"},
      {"[{\"type\": \"Negation\",\n \"elements\": [-1, -2]}]", 2, "the second must be 0"},
      {"[{\"type\": \"Negation\",\n \"elements\": []}]", 2, "0 operands, a Negation has one"},
      {"[{\"type\": \"Union\", \"elements\": [-1,\n 1.5]}]", 2, "expected an integer operand"},
      {"[{\"type\": \"Union\", \"elements\": [-1,\n 0]}]", 2, "operand 0 is neither a node nor a function"},
      {"[{\"type\": \"Union\", \"elements\": [-1,\n 2]}]", 2, "node 2 out of range (the tree has 1 nodes)"},
      {"[{\"type\": \"Union\", \"elements\": [-1,\n -4]}]", 2, "function 4 out of range (there are 3 functions"},
      {"[{\"type\": \"Union\", \"elements\": [-1,\n 1]}]", 2, "cycle: node 1 -> node 1"},
      {"[{\"type\": \"Union\", \"elements\": [-1, 2]},\n"
       " {\"type\": \"Negation\", \"elements\": [3, 0]},\n"
       " {\"type\": \"Intersection\", \"elements\": [-2,\n 2]}]",
       4, "cycle: node 2 -> node 3 -> node 2"},
      {"[{\"type\": \"Union\", \"elements\": [-1, 3]},\n"
       " {\"type\": \"Negation\", \"elements\": [-2, 0]},\n"
       " {\"type\": \"Negation\", \"elements\": [-3, 0]}]",
       2, "node 2 is not reachable from the root"},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string path = dir.Write("tree" + std::to_string(index++) + ".json", c.text);
    ExpectInputError([&] { ReadCsgTree(path, 3); }, path, c.line, c.part);
  }
  // Negation written with one operand; 2.0 counts as an integer.
  const std::string ok = dir.Write(
      "ok.json", "[{\"type\": \"Negation\", \"elements\": [2]}, {\"type\": \"Union\", \"elements\": [-1, -2.0]}]");
  const std::vector<implicit::CsgNode> tree = ReadCsgTree(ok, 2);
  ASSERT_EQ(tree.size(), 2u);
  EXPECT_EQ(tree[0].a, 2);
  EXPECT_EQ(tree[0].b, 0);
  EXPECT_EQ(tree[1].b, -2);
}

// ---------------------------------------------------------------------------
// Initial grids from gmsh.

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

// ---------------------------------------------------------------------------
// Grid writers.

/// Two tetrahedra sharing the face (1, 2, 3), two functions, one active cell.
implicit::Grid SmallGrid3() {
  implicit::Grid grid;
  grid.mesh.dimension = 3;
  grid.mesh.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1.0 / 3};
  grid.mesh.cells = {0, 1, 2, 3, 1, 4, 2, 3};
  grid.functionCount = 2;
  for (std::size_t v = 0; v < 5; ++v) {
    const double* x = &grid.mesh.vertices[3 * v];
    grid.values.push_back(x[0] + x[1] + x[2] - 0.1);  // f0
    grid.values.push_back(static_cast<double>(v) / 3);  // f1
  }
  grid.active = {1, 0};
  return grid;
}

/// Two triangles of the unit square, one function.
implicit::Grid SmallGrid2() {
  implicit::Grid grid;
  grid.mesh.dimension = 2;
  grid.mesh.vertices = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  grid.mesh.cells = {0, 1, 2, 0, 2, 3};
  grid.functionCount = 1;
  grid.values = {0.1, 0.2, 0.3, 0.4};
  grid.active = {0, 1};
  return grid;
}

bool HaveGmsh() {
  static const bool have = std::system("gmsh -version > /dev/null 2>&1") == 0;
  return have;
}

TEST(ImplicitGridWriters, MshRoundTrip) {
  ScratchDir dir;
  for (const implicit::Grid& grid : {SmallGrid3(), SmallGrid2()}) {
    const int dim = grid.mesh.dimension;
    SCOPED_TRACE(dim);
    const std::string path = dir.Path("grid" + std::to_string(dim) + ".msh");
    const std::vector<std::string> names = dim == 3 ? std::vector<std::string>{"sphere", "pla\"ne"}
                                                    : std::vector<std::string>{};
    WriteGridMsh(grid, names, path);

    const Geometry geometry = ReadGmsh(path);
    EXPECT_EQ(geometry.dimension, dim);
    ASSERT_EQ(geometry.patches.size(), 1u);
    const Patch& patch = geometry.patches[0];
    const std::size_t per = static_cast<std::size_t>(dim + 1);
    ASSERT_EQ(patch.cellTypes.size(), grid.mesh.numCells());
    for (std::size_t c = 0; c < grid.mesh.numCells(); ++c) {
      EXPECT_EQ(patch.cellTypes[c], dim == 3 ? CellType::Tet : CellType::Tri);
      for (std::size_t j = 0; j < per; ++j) {
        for (int a = 0; a < dim; ++a) {
          EXPECT_EQ(patch.points[(static_cast<std::size_t>(patch.cellOffsets[c]) + j) * dim + a],
                    grid.mesh.vertices[3 * grid.mesh.cells[c * per + j] + a]);
        }
      }
    }
    // And back to a simplex mesh: the same vertices and cells (all positive).
    const implicit::SimplexMesh mesh = ReadSimplexMeshMsh(path);
    EXPECT_EQ(mesh.vertices, grid.mesh.vertices);
    EXPECT_EQ(mesh.cells, grid.mesh.cells);

    const std::string text = ReadAll(path);
    EXPECT_EQ(text.rfind("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 0), 0u);
    if (dim == 3) {
      EXPECT_NE(text.find("\"f0 sphere\""), std::string::npos);
      EXPECT_NE(text.find("\"f1 pla'ne\""), std::string::npos);
      EXPECT_NE(text.find("\n2 0.3333333333333333\n"), std::string::npos) << "shortest round-trip text";
    } else {
      EXPECT_NE(text.find("\"f0\""), std::string::npos);
    }
    EXPECT_NE(text.find("$ElementData\n1\n\"active\"\n1\n0\n3\n0\n1\n" + std::to_string(grid.mesh.numCells()) +
                        "\n1 " + std::to_string(grid.active[0]) + "\n"),
              std::string::npos);

    if (!HaveGmsh()) continue;
    const std::string out = dir.Path("gmsh" + std::to_string(dim) + ".msh");
    const std::string command = "gmsh '" + path + "' -0 -o '" + out + "' > '" + dir.Path("gmsh.log") + "' 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << ReadAll(dir.Path("gmsh.log"));
    const Geometry again = ReadGmsh(out);
    ASSERT_EQ(again.patches.size(), 1u);
    EXPECT_EQ(again.patches[0].cellTypes.size(), grid.mesh.numCells());
  }
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed: checked with invmap's reader only";
}

TEST(ImplicitGridWriters, MshViewsReadByGmsh) {
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed (Debian package gmsh)";
  ScratchDir dir;
  const std::string path = dir.Path("grid.msh");
  WriteGridMsh(SmallGrid3(), {"a", "b"}, path);
  // gmsh parses the views too: re-save them and find the values.
  const std::string geo = dir.Write("views.geo", "Merge \"" + path +
                                                     "\";\nSave View[0] \"" + dir.Path("view0.pos") + "\";\n");
  const std::string command = "gmsh '" + geo + "' -0 -o '" + dir.Path("out.msh") + "' > '" + dir.Path("gmsh.log") +
                              "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadAll(dir.Path("gmsh.log"));
  const std::string view = ReadAll(dir.Path("view0.pos"));
  EXPECT_NE(view.find("f0 a"), std::string::npos) << view;
}

/// The parts of a raw-appended VTU file.
struct VtuParts {
  std::string xml;                   ///< Everything outside the raw data (the data replaced by nothing).
  std::string raw;                   ///< The bytes after '_' up to the closing tag.
  std::vector<std::uint64_t> offsets;  ///< Declared offset="..." attributes, in file order.
};

VtuParts SplitVtu(const std::string& text) {
  VtuParts parts;
  const std::size_t open = text.find("<AppendedData encoding=\"raw\">");
  const std::size_t underscore = text.find('_', open);
  const std::string closing = "\n  </AppendedData>\n</VTKFile>\n";
  EXPECT_NE(open, std::string::npos);
  EXPECT_GE(text.size(), closing.size());
  EXPECT_EQ(text.compare(text.size() - closing.size(), closing.size(), closing), 0);
  parts.xml = text.substr(0, underscore) + text.substr(text.size() - closing.size());
  parts.raw = text.substr(underscore + 1, text.size() - closing.size() - underscore - 1);
  for (std::size_t at = text.find("offset=\""); at < open; at = text.find("offset=\"", at + 1)) {
    parts.offsets.push_back(std::stoull(text.substr(at + 8)));
  }
  return parts;
}

TEST(ImplicitGridWriters, VtuBlocksAndValues) {
  ScratchDir dir;
  const implicit::Grid grid = SmallGrid3();
  const std::string path = dir.Path("grid.vtu");
  WriteGridVtu(grid, {"s<1>", "p&q"}, path);
  const VtuParts parts = SplitVtu(ReadAll(path));
  EXPECT_NE(parts.xml.find("Name=\"f0 s&lt;1&gt;\""), std::string::npos);
  EXPECT_NE(parts.xml.find("Name=\"f1 p&amp;q\""), std::string::npos);
  EXPECT_NE(parts.xml.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(parts.xml.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);

  // Walk the blocks: each declared offset starts a block, and the blocks
  // fill the appended section exactly.
  std::vector<std::uint64_t> sizes;
  std::uint64_t at = 0;
  while (at < parts.raw.size()) {
    ASSERT_LE(at + 8, parts.raw.size());
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, parts.raw.data() + at, 8);
    ASSERT_EQ(sizes.size() < parts.offsets.size() ? parts.offsets[sizes.size()] : ~0ull, at);
    sizes.push_back(bytes);
    at += 8 + bytes;
  }
  EXPECT_EQ(at, parts.raw.size());
  // f0, f1, active, points, connectivity, offsets, types.
  const std::vector<std::uint64_t> expected = {5 * 8, 5 * 8, 2, 5 * 24, 8 * 8, 2 * 8, 2};
  EXPECT_EQ(sizes, expected);

  const auto blockData = [&](std::size_t b) { return parts.raw.data() + parts.offsets[b] + 8; };
  for (std::size_t v = 0; v < 5; ++v) {
    double f1 = 0, y = 0;
    std::memcpy(&f1, blockData(1) + 8 * v, 8);
    std::memcpy(&y, blockData(3) + 24 * v + 8, 8);
    EXPECT_EQ(f1, grid.values[2 * v + 1]);
    EXPECT_EQ(y, grid.mesh.vertices[3 * v + 1]);
  }
  EXPECT_EQ(blockData(2)[0], 1);
  EXPECT_EQ(blockData(2)[1], 0);
  std::int64_t connectivity[8], offsets[2];
  std::memcpy(connectivity, blockData(4), sizeof connectivity);
  std::memcpy(offsets, blockData(5), sizeof offsets);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(connectivity[i], grid.mesh.cells[i]);
  EXPECT_EQ(offsets[0], 4);
  EXPECT_EQ(offsets[1], 8);
  EXPECT_EQ(blockData(6)[0], 10);

  // The XML around the data is well formed.
  const std::string xmlPath = dir.Write("skeleton.xml", parts.xml);
  if (std::system("xmllint --version > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("xmllint --noout '" + xmlPath + "'").c_str()), 0) << parts.xml;
  }

  // 2D: triangles, no names.
  WriteGridVtu(SmallGrid2(), {}, dir.Path("grid2.vtu"));
  const VtuParts two = SplitVtu(ReadAll(dir.Path("grid2.vtu")));
  EXPECT_NE(two.xml.find("Name=\"f0\""), std::string::npos);
  ASSERT_EQ(two.offsets.size(), 6u);
  EXPECT_EQ(two.raw[two.offsets[5] + 8], 5);
  EXPECT_EQ(two.raw.size(), two.offsets[5] + 8 + 2);
}

TEST(ImplicitGridWriters, InconsistentGridIsAProgrammingError) {
  ScratchDir dir;
  implicit::Grid grid = SmallGrid3();
  EXPECT_THROW(WriteGridMsh(grid, {"only one"}, dir.Path("a.msh")), std::invalid_argument);
  grid.values.pop_back();
  EXPECT_THROW(WriteGridVtu(grid, {}, dir.Path("a.vtu")), std::invalid_argument);
  EXPECT_EQ(dir.EntryCount(), 0u);
}

// ---------------------------------------------------------------------------
// Zero sets and stats.

implicit::ZeroSets SmallZeroSets() {
  implicit::ZeroSets z;
  z.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2};
  z.triangles = {0, 1, 2, 0, 2, 3, 1, 2, 3};
  z.triangleLabels = {{2, -1, -1, -1}, {0, -1, -1, -1}, {2, -1, -1, -1}};
  z.segments = {1, 2};
  z.segmentLabels = {{0, 2, -1, -1}};
  z.points = {2};
  z.pointLabels = {{0, 1, 2, -1}};
  return z;  // Vertices 4 and 5 are used by no triangle.
}

/// Number of lines starting with `prefix`.
std::size_t CountLines(const std::string& text, const std::string& prefix) {
  std::size_t count = 0;
  for (std::size_t at = 0; at < text.size();) {
    if (text.compare(at, prefix.size(), prefix) == 0) ++count;
    const std::size_t end = text.find('\n', at);
    at = end == std::string::npos ? text.size() : end + 1;
  }
  return count;
}

TEST(ImplicitZeroSets, ObjGroupsByLabel) {
  ScratchDir dir;
  const std::string path = dir.Path("zero_sets.obj");
  WriteZeroSetsObj(SmallZeroSets(), path);
  const std::string text = ReadAll(path);
  EXPECT_EQ(CountLines(text, "v "), 6u);
  EXPECT_EQ(CountLines(text, "f "), 3u);
  EXPECT_EQ(CountLines(text, "l "), 1u);
  EXPECT_EQ(CountLines(text, "p "), 1u);
  EXPECT_EQ(CountLines(text, "g "), 4u);
  // Groups in label order, primitives 1-based.
  const std::size_t g0 = text.find("g f0\nf 1 3 4\n");
  const std::size_t g012 = text.find("g f0_f1_f2\np 3\n");
  const std::size_t g02 = text.find("g f0_f2\nl 2 3\n");
  const std::size_t g2 = text.find("g f2\nf 1 2 3\nf 2 3 4\n");
  EXPECT_NE(g0, std::string::npos) << text;
  EXPECT_LT(g0, g012);
  EXPECT_LT(g012, g02);
  EXPECT_LT(g02, g2);
  EXPECT_NE(g2, std::string::npos) << text;
  EXPECT_NE(text.find("v 2 2 2\n"), std::string::npos);

  implicit::ZeroSets bad = SmallZeroSets();
  bad.segmentLabels.clear();
  EXPECT_THROW(WriteZeroSetsObj(bad, dir.Path("bad.obj")), std::invalid_argument);
  bad = SmallZeroSets();
  bad.points = {6};
  EXPECT_THROW(WriteZeroSetsObj(bad, dir.Path("bad.obj")), std::invalid_argument);
}

TEST(ImplicitZeroSets, PlyReadsBackAsAMesh) {
  ScratchDir dir;
  const std::string path = dir.Path("surfaces.ply");
  const implicit::ZeroSets z = SmallZeroSets();
  WriteZeroSetsPly(z, path);
  const Geometry geometry = ReadPlyMesh(path);
  EXPECT_EQ(geometry.dimension, 3);
  ASSERT_EQ(geometry.patches.size(), 1u);
  const Patch& patch = geometry.patches[0];
  EXPECT_EQ(patch.kind, Patch::Kind::Mesh);
  EXPECT_EQ(patch.cell, CellType::Tri);
  ASSERT_EQ(patch.cells.size(), z.triangles.size());
  EXPECT_EQ(patch.points.size(), 4u * 3);  // Only the used vertices.
  for (std::size_t i = 0; i < z.triangles.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(patch.points[3 * static_cast<std::size_t>(patch.cells[i]) + a], z.vertices[3 * z.triangles[i] + a]);
    }
  }
}

TEST(ImplicitGridStats, ExactKeys) {
  ScratchDir dir;
  implicit::GridStats stats;
  stats.cells = 30218;
  stats.activeCells = 14636;
  stats.vertices = 5555;
  stats.minRadiusRatio = 0.1;
  stats.minRadiusRatioActive = 0.25;
  stats.seconds = 0.3;
  const std::string path = dir.Path("stats.json");
  WriteGridStats(stats, path);
  const nlohmann::ordered_json json = nlohmann::ordered_json::parse(ReadAll(path));
  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());
  const std::vector<std::string> expected = {"cells",
                                             "active_cells",
                                             "vertices",
                                             "min_radius_ratio",
                                             "min_radius_ratio_active",
                                             "seconds"};
  EXPECT_EQ(keys, expected);
  EXPECT_TRUE(json["cells"].is_number_integer());
  EXPECT_EQ(json["cells"].get<std::int64_t>(), 30218);
  EXPECT_EQ(json["active_cells"].get<std::int64_t>(), 14636);
  EXPECT_EQ(json["vertices"].get<std::int64_t>(), 5555);
  EXPECT_EQ(json["min_radius_ratio"].get<double>(), 0.1);
  EXPECT_EQ(json["min_radius_ratio_active"].get<double>(), 0.25);
  EXPECT_EQ(json["seconds"].get<double>(), 0.3);
}

TEST(ImplicitWriters, UnwritableOutputLeavesNoFile) {
  ScratchDir dir;
  const std::string missing = dir.Path("no_such_dir");
  const auto expectOutputError = [&](const std::function<void(const std::string&)>& write, const std::string& name) {
    SCOPED_TRACE(name);
    const std::string path = missing + "/" + name;
    ExpectInputError([&] { write(path); }, path, 0, "", InputError::Kind::Output);
    EXPECT_FALSE(std::filesystem::exists(path));
  };
  expectOutputError([](const std::string& p) { WriteGridMsh(SmallGrid3(), {}, p); }, "grid.msh");
  expectOutputError([](const std::string& p) { WriteGridVtu(SmallGrid3(), {}, p); }, "grid.vtu");
  expectOutputError([](const std::string& p) { WriteZeroSetsObj(SmallZeroSets(), p); }, "zero_sets.obj");
  expectOutputError([](const std::string& p) { WriteZeroSetsPly(SmallZeroSets(), p); }, "zero_sets.ply");
  expectOutputError([](const std::string& p) { WriteGridStats(implicit::GridStats(), p); }, "stats.json");
  // A directory in the way of the target: an error, and the directory stays.
  std::filesystem::create_directory(dir.Path("stats.json"));
  ExpectInputError([&] { WriteGridStats(implicit::GridStats(), dir.Path("stats.json")); }, dir.Path("stats.json"), 0,
                   "is a directory", InputError::Kind::Output);
  EXPECT_TRUE(std::filesystem::is_directory(dir.Path("stats.json")));
  EXPECT_EQ(dir.EntryCount(), 1u);
}

}  // namespace
}  // namespace invmap::io
