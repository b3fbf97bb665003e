// Tests of the function list and CSG tree readers of `invmap grid`: every
// benchmark input, the values of the functions read, and every error with
// its line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "implicit_io/csg_tree_file.h"
#include "implicit_io/function_list.h"
#include "invmap/implicit.h"
#include "io/input_error.h"
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

}  // namespace
}  // namespace invmap::io

namespace invmap::io {
namespace {

TEST(ImplicitFiles, EndlessAndHugeFilesAreRefusedAfterABoundedRead) {
  // /dev/zero under a .json name (and a sparse file of gigabytes) is no
  // function list or tree: the readers stop at 64 MiB, not at the memory's end.
  ScratchDir dir;
  const std::string zero = dir.Path("zero.json");
  std::filesystem::create_symlink("/dev/zero", zero);
  ExpectInputError([&] { ReadFunctionList(zero, 3); }, 0, {"zero.json: more than 64 MiB"});
  ExpectInputError([&] { ReadCsgTree(zero, 2); }, 0, {"zero.json: more than 64 MiB"});
  const std::string sparse = dir.Write("sparse.json", "");
  std::filesystem::resize_file(sparse, std::uintmax_t{2} << 30);
  ExpectInputError([&] { ReadFunctionList(sparse, 3); }, 0, {"sparse.json: more than 64 MiB"});
}

}  // namespace
}  // namespace invmap::io
