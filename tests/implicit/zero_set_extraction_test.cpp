// ExtractZeroSets, ValidateCsgTree and EvaluateCsg on box grids whose values
// come from small closed-form fields written here (planes are reproduced
// exactly by the linear interpolant, so their zero sets are checked to
// rounding; spheres to the interpolation error).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "implicit/csg_tree.h"
#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

using Field = std::function<double(const Vec3&)>;
using Label = std::array<int, 4>;

constexpr double kPi = 3.14159265358979323846;

Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 Add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 Scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double Norm(const Vec3& a) { return std::sqrt(Dot(a, a)); }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// Box grid of [lo, hi] with values[v * k + i] = fields[i](vertex v).
Grid MakeGrid(int dimension, int resolution, const std::vector<Field>& fields, const Vec3& lo = {0, 0, 0},
              const Vec3& hi = {1, 1, 1}) {
  Grid grid;
  grid.mesh = SimplexMesh::Box(lo, hi, dimension, resolution);
  grid.functionCount = static_cast<int>(fields.size());
  for (std::size_t v = 0; v < grid.mesh.numVertices(); ++v) {
    const Vec3 x = {grid.mesh.vertices[3 * v], grid.mesh.vertices[3 * v + 1], grid.mesh.vertices[3 * v + 2]};
    for (const Field& f : fields) grid.values.push_back(f(x));
  }
  return grid;
}

GridOptions WithMode(Mode mode, std::vector<CsgNode> tree = {}) {
  GridOptions options;
  options.mode = mode;
  options.tree = std::move(tree);
  return options;
}

Vec3 VertexOf(const ZeroSets& z, std::uint32_t v) {
  return {z.vertices[3 * v], z.vertices[3 * v + 1], z.vertices[3 * v + 2]};
}

Vec3 Corner(const ZeroSets& z, std::size_t triangle, int k) { return VertexOf(z, z.triangles[3 * triangle + k]); }

/// (b - a) x (c - a): twice the area, pointing along the triangle's normal.
Vec3 AreaVector(const ZeroSets& z, std::size_t t) {
  const Vec3 a = Corner(z, t, 0);
  return Cross(Sub(Corner(z, t, 1), a), Sub(Corner(z, t, 2), a));
}

Vec3 Centroid(const ZeroSets& z, std::size_t t) {
  return Scale(Add(Add(Corner(z, t, 0), Corner(z, t, 1)), Corner(z, t, 2)), 1.0 / 3);
}

double TotalArea(const ZeroSets& z) {
  double area = 0;
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) area += Norm(AreaVector(z, t)) / 2;
  return area;
}

double TotalLength(const ZeroSets& z) {
  double length = 0;
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s)
    length += Norm(Sub(VertexOf(z, z.segments[2 * s + 1]), VertexOf(z, z.segments[2 * s])));
  return length;
}

/// Every coordinate finite, every triangle of positive area, every segment of
/// positive length.
void ExpectWellFormed(const ZeroSets& z) {
  for (double c : z.vertices) ASSERT_TRUE(std::isfinite(c));
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) EXPECT_GT(Norm(AreaVector(z, t)), 0) << "triangle " << t;
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s)
    EXPECT_NE(z.segments[2 * s], z.segments[2 * s + 1]) << "segment " << s;
  EXPECT_EQ(z.triangles.size(), 3 * z.triangleLabels.size());
  EXPECT_EQ(z.segments.size(), 2 * z.segmentLabels.size());
  EXPECT_EQ(z.points.size(), z.pointLabels.size());
}

/// A closed, consistently oriented triangle mesh: every directed edge once,
/// and its reverse once. Returns the Euler characteristic V - E + F.
int ExpectClosedOrientedSurface(const ZeroSets& z) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::set<std::uint32_t> used;
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = z.triangles[3 * t + k], b = z.triangles[3 * t + (k + 1) % 3];
      ++directed[{a, b}];
      used.insert(a);
    }
  }
  int problems = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++problems;
  }
  EXPECT_EQ(problems, 0) << "edges not shared by exactly two consistently oriented triangles";
  const int edges = static_cast<int>(directed.size() / 2);
  return static_cast<int>(used.size()) - edges + static_cast<int>(z.triangleLabels.size());
}

/// Signed volume enclosed by a closed surface (positive for outward normals).
double EnclosedVolume(const ZeroSets& z) {
  double volume = 0;
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t)
    volume += Dot(Corner(z, t, 0), Cross(Corner(z, t, 1), Corner(z, t, 2))) / 6;
  return volume;
}

/// Vertex degrees in the segments; with `directed`, also checks that each
/// vertex has one incoming and one outgoing segment.
std::map<std::uint32_t, int> SegmentDegrees(const ZeroSets& z, bool expectDirectedLoops) {
  std::map<std::uint32_t, int> degree, out, in;
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    ++degree[z.segments[2 * s]];
    ++degree[z.segments[2 * s + 1]];
    ++out[z.segments[2 * s]];
    ++in[z.segments[2 * s + 1]];
  }
  if (expectDirectedLoops) {
    for (const auto& [v, d] : degree) EXPECT_TRUE(out[v] == 1 && in[v] == 1) << "vertex " << v;
  }
  return degree;
}

double Sphere(const Vec3& x, const Vec3& center, double radius) { return radius - Norm(Sub(x, center)); }

// ---------------------------------------------------------------------------
// CSG trees

TEST(CsgTree, ValidTreesPass) {
  EXPECT_EQ(ValidateCsgTree({{CsgNode::Op::Union, -1, -2}}, 2), "");
  // Shared node 3 (a DAG, not a cycle); Negation's b is ignored.
  const std::vector<CsgNode> dag = {{CsgNode::Op::Intersection, 2, 3},
                                    {CsgNode::Op::Union, 3, -1},
                                    {CsgNode::Op::Negation, -2, 99}};
  EXPECT_EQ(ValidateCsgTree(dag, 2), "");
}

TEST(CsgTree, InvalidTreesNameTheProblem) {
  auto expectError = [](const std::vector<CsgNode>& tree, int functions, const std::string& part) {
    const std::string message = ValidateCsgTree(tree, functions);
    EXPECT_NE(message.find(part), std::string::npos) << "message: '" << message << "', expected '" << part << "'";
  };
  expectError({}, 2, "empty");
  expectError({{CsgNode::Op::Union, 2, -1}, {CsgNode::Op::Union, -1, -7}}, 5,
              "node 2: operand -7 names function 7 but there are 5 functions");
  expectError({{CsgNode::Op::Union, 3, -1}, {CsgNode::Op::Union, -1, -2}}, 2, "node 1: operand 3 names node 3");
  expectError({{CsgNode::Op::Intersection, -1, 0}}, 2, "node 1: operand 0");
  expectError({{CsgNode::Op::Negation, 0, -1}}, 2, "node 1: operand 0");
  expectError({{CsgNode::Op::Union, 1, -1}}, 2, "node 1: operand 1 makes a cycle");
  expectError({{CsgNode::Op::Union, 2, -1}, {CsgNode::Op::Negation, 3, 0}, {CsgNode::Op::Union, -2, 1}}, 2,
              "node 3: operand 1 makes a cycle");
  expectError({{CsgNode::Op::Union, -1, -2}, {CsgNode::Op::Union, -1, -2}}, 2,
              "node 2 is not reachable from the root (node 1)");
}

TEST(CsgTree, EvaluatesMinMaxAndNegation) {
  const double f[3] = {0.5, -2.0, 3.0};
  EXPECT_EQ(EvaluateCsg({{CsgNode::Op::Intersection, -1, -2}}, f), 0.5);
  EXPECT_EQ(EvaluateCsg({{CsgNode::Op::Union, -1, -2}}, f), -2.0);
  EXPECT_EQ(EvaluateCsg({{CsgNode::Op::Negation, -3, 0}}, f), -3.0);
  // min(max(f1, -f2), max(-f3, -f2)); node 3 (-f2) is shared.
  const std::vector<CsgNode> tree = {{CsgNode::Op::Union, 2, 4},
                                     {CsgNode::Op::Intersection, -1, 3},
                                     {CsgNode::Op::Negation, -2, 0},
                                     {CsgNode::Op::Intersection, 5, 3},
                                     {CsgNode::Op::Negation, -3, 0}};
  ASSERT_EQ(ValidateCsgTree(tree, 3), "");
  EXPECT_EQ(EvaluateCsg(tree, f), 2.0);  // min(max(0.5, 2), max(-3, 2))
}

TEST(CsgTree, DeepChainEvaluatesWithoutRecursion) {
  // 100000 nested negations of f1: an even count gives f1 back.
  std::vector<CsgNode> tree;
  const int depth = 100000;
  for (int n = 1; n < depth; ++n) tree.push_back({CsgNode::Op::Negation, n + 1, 0});
  tree.push_back({CsgNode::Op::Negation, -1, 0});
  ASSERT_EQ(ValidateCsgTree(tree, 1), "");
  const double f = 0.25;
  EXPECT_EQ(EvaluateCsg(tree, &f), 0.25);
}

// ---------------------------------------------------------------------------
// Arrangement, 3D

// z = 0.4 + 0.1 x + 0.2 y stays inside the unit box.
double TiltedPlane(const Vec3& x) { return x[2] - 0.4 - 0.1 * x[0] - 0.2 * x[1]; }

TEST(ArrangementExtraction, PlaneLiesOnThePlaneWithTheExactArea) {
  const Grid grid = MakeGrid(3, 5, {TiltedPlane});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  ASSERT_GT(z.triangleLabels.size(), 0u);
  for (std::size_t v = 0; v < z.vertices.size() / 3; ++v) EXPECT_NEAR(TiltedPlane(VertexOf(z, v)), 0, 1e-12);
  EXPECT_NEAR(TotalArea(z), std::sqrt(1 + 0.01 + 0.04), 1e-12);
  const Vec3 gradient = {-0.1, -0.2, 1};
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) {
    EXPECT_EQ(z.triangleLabels[t], (Label{0, -1, -1, -1}));
    EXPECT_GT(Dot(AreaVector(z, t), gradient), 0) << "normal toward increasing f";
  }
  EXPECT_TRUE(z.segments.empty());
  EXPECT_TRUE(z.points.empty());
}

TEST(ArrangementExtraction, SphereIsWatertightAndClose) {
  const Vec3 center = {0.51, 0.49, 0.5};
  const double radius = 0.3;
  const Grid grid = MakeGrid(3, 20, {[&](const Vec3& x) { return Sphere(x, center, radius); }});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  EXPECT_EQ(ExpectClosedOrientedSurface(z), 2) << "a sphere's Euler characteristic";
  // Linear interpolation of r - |x - c| on cells of diameter h sqrt(3)
  // (h = 0.05) errs by at most about diameter^2 / (2 r) = 0.0125.
  double worst = 0;
  for (std::size_t v = 0; v < z.vertices.size() / 3; ++v)
    worst = std::max(worst, std::abs(Norm(Sub(VertexOf(z, v), center)) - radius));
  EXPECT_LT(worst, 0.0125);
  EXPECT_NEAR(TotalArea(z), 4 * kPi * radius * radius, 0.02 * 4 * kPi * radius * radius);
  // Toward increasing f is inward: the enclosed volume comes out negative.
  EXPECT_NEAR(EnclosedVolume(z), -4.0 / 3 * kPi * std::pow(radius, 3), 0.03 * 4.0 / 3 * kPi * std::pow(radius, 3));
}

double SteepPlane(const Vec3& x) { return x[0] - 0.55 - 0.1 * x[1]; }
double ThirdPlane(const Vec3& x) { return x[1] - 0.37 - 0.05 * x[0] + 0.02 * x[2]; }

TEST(ArrangementExtraction, TwoPlanesMeetInTheirLine) {
  const Grid grid = MakeGrid(3, 6, {TiltedPlane, SteepPlane});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  ASSERT_GT(z.segmentLabels.size(), 0u);
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    EXPECT_EQ(z.segmentLabels[s], (Label{0, 1, -1, -1}));
    for (int k = 0; k < 2; ++k) {
      const Vec3 x = VertexOf(z, z.segments[2 * s + k]);
      EXPECT_NEAR(TiltedPlane(x), 0, 1e-12);
      EXPECT_NEAR(SteepPlane(x), 0, 1e-12);
    }
  }
  // x = 0.55 + 0.1 y, z = 0.455 + 0.21 y for y in [0, 1].
  EXPECT_NEAR(TotalLength(z), std::sqrt(0.01 + 1 + 0.21 * 0.21), 1e-12);
  // One open polyline: two ends of degree 1, the rest degree 2.
  int ends = 0;
  for (const auto& [v, d] : SegmentDegrees(z, false)) {
    EXPECT_LE(d, 2);
    ends += d == 1;
  }
  EXPECT_EQ(ends, 2);
  // Each plane's surface is still complete.
  std::array<double, 2> area = {0, 0};
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) area[z.triangleLabels[t][0]] += Norm(AreaVector(z, t)) / 2;
  EXPECT_NEAR(area[0], std::sqrt(1.05), 1e-12);
  EXPECT_NEAR(area[1], std::sqrt(1.01), 1e-12);
}

TEST(ArrangementExtraction, ThreePlanesMeetInOnePoint) {
  const Grid grid = MakeGrid(3, 6, {TiltedPlane, SteepPlane, ThirdPlane});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  ASSERT_EQ(z.pointLabels.size(), 1u);
  EXPECT_EQ(z.pointLabels[0], (Label{0, 1, 2, -1}));
  // Fixed-point iteration of the three plane equations (a contraction here).
  Vec3 x = {0.5, 0.5, 0.5};
  for (int iteration = 0; iteration < 200; ++iteration) {
    x[0] = 0.55 + 0.1 * x[1];
    x[1] = 0.37 + 0.05 * x[0] - 0.02 * x[2];
    x[2] = 0.4 + 0.1 * x[0] + 0.2 * x[1];
  }
  const Vec3 found = VertexOf(z, z.points[0]);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(found[c], x[c], 1e-12);
}

TEST(ArrangementExtraction, SameOutputForAnyThreadCount) {
  const std::vector<Field> fields = {[](const Vec3& x) { return Sphere(x, {0.5, 0.45, 0.5}, 0.3); },
                                     [](const Vec3& x) { return Sphere(x, {0.6, 0.55, 0.5}, 0.25); }, TiltedPlane};
  const Grid grid = MakeGrid(3, 24, fields);
  GridOptions one = WithMode(Mode::Arrangement), two = one;
  one.threads = 1;
  two.threads = 2;
  const ZeroSets a = ExtractZeroSets(grid, one), b = ExtractZeroSets(grid, two);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.triangleLabels, b.triangleLabels);
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.points, b.points);
  EXPECT_GT(a.pointLabels.size(), 0u);  // sphere, sphere and plane meet
}

// ---------------------------------------------------------------------------
// Exact zeros at grid vertices

TEST(ZeroValues, PlaneThroughGridVerticesGivesTheSquareOnce) {
  // z = 0.4 is a layer of the 5-cube grid: the values there are exactly 0.
  const Grid grid = MakeGrid(3, 5, {[](const Vec3& x) { return x[2] - 0.4; }});
  ASSERT_EQ(grid.values[2 * 6 * 6], 0.0);  // vertex (0, 0, layer 2)
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  EXPECT_NEAR(TotalArea(z), 1.0, 1e-12);
  for (std::size_t v = 0; v < z.vertices.size() / 3; ++v) EXPECT_EQ(z.vertices[3 * v + 2], 0.4);
}

TEST(ZeroValues, SphereThroughGridVerticesStaysWatertight) {
  // r^2 - |x - c|^2 with r = 0.25 is exactly 0 at six vertices of the 8-grid.
  const Grid grid = MakeGrid(3, 8, {[](const Vec3& x) {
    const Vec3 d = Sub(x, {0.5, 0.5, 0.5});
    return 0.0625 - Dot(d, d);
  }});
  ASSERT_EQ(std::count(grid.values.begin(), grid.values.end(), 0.0), 6);
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  EXPECT_EQ(ExpectClosedOrientedSurface(z), 2);
}

TEST(ZeroValues, TwoDimensionalAndMaterialTiesAreFinite) {
  // Lines through grid vertices and a three-way material tie at a vertex.
  const Grid lines = MakeGrid(2, 4, {[](const Vec3& x) { return x[0] - 0.5; }, [](const Vec3& x) { return x[1] - 0.25; }});
  const ZeroSets a = ExtractZeroSets(lines, WithMode(Mode::Arrangement));
  ExpectWellFormed(a);
  EXPECT_NEAR(TotalLength(a), 2.0, 1e-12);
  ASSERT_EQ(a.pointLabels.size(), 1u);
  EXPECT_EQ(VertexOf(a, a.points[0]), (Vec3{0.5, 0.25, 0}));

  const Grid materials = MakeGrid(3, 4, {[](const Vec3& x) { return x[0] - 0.5; }, [](const Vec3& x) { return x[1] - 0.5; },
                                         [](const Vec3& x) { return 0.5 - x[2]; }});
  const ZeroSets b = ExtractZeroSets(materials, WithMode(Mode::MaterialInterface));
  ExpectWellFormed(b);
  EXPECT_GT(b.triangleLabels.size(), 0u);

  const ZeroSets c = ExtractZeroSets(materials, WithMode(Mode::Csg, {{CsgNode::Op::Intersection, -1, -2}}));
  ExpectWellFormed(c);
  EXPECT_GT(c.triangleLabels.size(), 0u);
}

// ---------------------------------------------------------------------------
// Arrangement, 2D

TEST(ArrangementExtraction2D, CircleIsAClosedClockwiseLoop) {
  const Vec3 center = {0.52, 0.47, 0};
  const double radius = 0.3;
  const Grid grid = MakeGrid(2, 30, {[&](const Vec3& x) { return Sphere(x, center, radius); }});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  EXPECT_EQ(z.dimension, 2);
  EXPECT_TRUE(z.triangles.empty());
  for (const auto& [v, d] : SegmentDegrees(z, true)) EXPECT_EQ(d, 2) << "vertex " << v;
  EXPECT_NEAR(TotalLength(z), 2 * kPi * radius, 0.01 * 2 * kPi * radius);
  // The normal (dy, -dx) points toward increasing f, i.e. inward: clockwise.
  double twiceArea = 0;
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    const Vec3 a = VertexOf(z, z.segments[2 * s]), b = VertexOf(z, z.segments[2 * s + 1]);
    twiceArea += a[0] * b[1] - a[1] * b[0];
    EXPECT_EQ(b[2], 0);
  }
  EXPECT_NEAR(twiceArea / 2, -kPi * radius * radius, 0.02 * kPi * radius * radius);
}

TEST(ArrangementExtraction2D, TwoCrossingLinesGiveOnePoint) {
  const Grid grid = MakeGrid(2, 7, {[](const Vec3& x) { return x[0] - 0.3 * x[1] - 0.41; },
                                    [](const Vec3& x) { return x[1] + 0.2 * x[0] - 0.58; }});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Arrangement));
  ExpectWellFormed(z);
  ASSERT_EQ(z.pointLabels.size(), 1u);
  EXPECT_EQ(z.pointLabels[0], (Label{0, 1, -1, -1}));
  // x = 0.41 + 0.3 y, y = 0.58 - 0.2 x.
  const double x = (0.41 + 0.3 * 0.58) / (1 + 0.3 * 0.2), y = 0.58 - 0.2 * x;
  const Vec3 found = VertexOf(z, z.points[0]);
  EXPECT_NEAR(found[0], x, 1e-12);
  EXPECT_NEAR(found[1], y, 1e-12);
}

// ---------------------------------------------------------------------------
// Material interfaces

TEST(MaterialExtraction, ThreeLinearMaterials) {
  // f0 = x, f1 = y, f2 = 1 - x - y + 0.1 z: all three tie on the line
  // x = y = (1 + 0.1 z) / 3.
  const std::vector<Field> f = {[](const Vec3& x) { return x[0]; }, [](const Vec3& x) { return x[1]; },
                                [](const Vec3& x) { return 1 - x[0] - x[1] + 0.1 * x[2]; }};
  const Grid grid = MakeGrid(3, 7, f);
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::MaterialInterface));
  ExpectWellFormed(z);
  std::map<std::pair<int, int>, double> area;
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) {
    const int i = z.triangleLabels[t][0], j = z.triangleLabels[t][1];
    ASSERT_TRUE(i >= 0 && i < j && j < 3 && z.triangleLabels[t][2] == -1);
    const int l = 3 - i - j;
    for (int k = 0; k < 3; ++k) {
      const Vec3 x = Corner(z, t, k);
      EXPECT_NEAR(f[i](x), f[j](x), 1e-12);
      EXPECT_GE(f[i](x), f[l](x) - 1e-12);
    }
    // Normal from material i into material j.
    const Vec3 c = Centroid(z, t), n = AreaVector(z, t);
    const Vec3 step = Scale(n, 1e-6 / Norm(n));
    EXPECT_GT(f[j](Add(c, step)), f[i](Add(c, step)));
    area[{i, j}] += Norm(n) / 2;
  }
  // Interface (0, 1): the plane x = y where x >= (1 + 0.1 z) / 3.
  EXPECT_NEAR(area[std::make_pair(0, 1)], 0.65 * std::sqrt(2.0), 1e-12);
  ASSERT_GT(z.segmentLabels.size(), 0u);
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    EXPECT_EQ(z.segmentLabels[s], (Label{0, 1, 2, -1}));
    for (int k = 0; k < 2; ++k) {
      const Vec3 x = VertexOf(z, z.segments[2 * s + k]);
      EXPECT_NEAR(x[0], (1 + 0.1 * x[2]) / 3, 1e-12);
      EXPECT_NEAR(x[1], (1 + 0.1 * x[2]) / 3, 1e-12);
    }
  }
  EXPECT_NEAR(TotalLength(z), std::sqrt(2 * (0.1 / 3) * (0.1 / 3) + 1), 1e-12);
  EXPECT_TRUE(z.points.empty());
}

TEST(MaterialExtraction, FourMaterialsMeetInOnePoint) {
  // All four tie at t = f_i with x = t - 0.05, y = t, z = t + 0.03 and
  // 1.1 - x - y - z = t: t = 0.28, off every face of the grid.
  const std::vector<Field> f = {[](const Vec3& x) { return x[0] + 0.05; }, [](const Vec3& x) { return x[1]; },
                                [](const Vec3& x) { return x[2] - 0.03; },
                                [](const Vec3& x) { return 1.1 - x[0] - x[1] - x[2]; }};
  const Grid grid = MakeGrid(3, 5, f);
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::MaterialInterface));
  ExpectWellFormed(z);
  ASSERT_EQ(z.pointLabels.size(), 1u);
  EXPECT_EQ(z.pointLabels[0], (Label{0, 1, 2, 3}));
  const Vec3 x = VertexOf(z, z.points[0]);
  const Vec3 expected = {0.23, 0.28, 0.31};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[c], expected[c], 1e-12);
  // Every triple has a junction line and every pair an interface.
  std::set<Label> junctions(z.segmentLabels.begin(), z.segmentLabels.end());
  EXPECT_EQ(junctions.size(), 4u);
  std::set<Label> interfaces(z.triangleLabels.begin(), z.triangleLabels.end());
  EXPECT_EQ(interfaces.size(), 6u);
}

TEST(MaterialExtraction, EachMaterialIsEnclosedByItsInterfaces) {
  // Two overlapping balls in a background (f = 0): each ball material is a
  // closed region whose interfaces, turned to face out of it, close up.
  const std::vector<Field> f = {[](const Vec3& x) { return Sphere(x, {0.42, 0.5, 0.48}, 0.25); },
                                [](const Vec3& x) { return Sphere(x, {0.62, 0.47, 0.53}, 0.2); },
                                [](const Vec3&) { return 0.0; }};
  const ZeroSets all = ExtractZeroSets(MakeGrid(3, 20, f), WithMode(Mode::MaterialInterface));
  ExpectWellFormed(all);
  for (int material = 0; material < 2; ++material) {
    SCOPED_TRACE(material);
    ZeroSets boundary = all;
    boundary.triangles.clear();
    boundary.triangleLabels.clear();
    for (std::size_t t = 0; t < all.triangleLabels.size(); ++t) {
      const Label& label = all.triangleLabels[t];
      if (label[0] != material && label[1] != material) continue;
      // Normals point from material label[0] into label[1].
      const bool flip = label[1] == material;
      for (int k : {0, flip ? 2 : 1, flip ? 1 : 2}) boundary.triangles.push_back(all.triangles[3 * t + k]);
      boundary.triangleLabels.push_back(label);
    }
    EXPECT_EQ(ExpectClosedOrientedSurface(boundary), 2);
    EXPECT_GT(EnclosedVolume(boundary), 0);
  }
  std::set<Label> junctions(all.segmentLabels.begin(), all.segmentLabels.end());
  EXPECT_EQ(junctions, (std::set<Label>{{0, 1, 2, -1}}));
}

TEST(MaterialExtraction2D, ThreeMaterialsMeetInOnePoint) {
  // Tie at t = x + 0.02 = y = 0.9 - x - y: t = 0.92 / 3.
  const std::vector<Field> f = {[](const Vec3& x) { return x[0] + 0.02; }, [](const Vec3& x) { return x[1]; },
                                [](const Vec3& x) { return 0.9 - x[0] - x[1]; }};
  const Grid grid = MakeGrid(2, 6, f);
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::MaterialInterface));
  ExpectWellFormed(z);
  ASSERT_EQ(z.pointLabels.size(), 1u);
  EXPECT_EQ(z.pointLabels[0], (Label{0, 1, 2, -1}));
  const Vec3 x = VertexOf(z, z.points[0]);
  EXPECT_NEAR(x[0], 0.92 / 3 - 0.02, 1e-12);
  EXPECT_NEAR(x[1], 0.92 / 3, 1e-12);
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    const int i = z.segmentLabels[s][0], j = z.segmentLabels[s][1];
    for (int k = 0; k < 2; ++k) {
      const Vec3 p = VertexOf(z, z.segments[2 * s + k]);
      EXPECT_NEAR(f[i](p), f[j](p), 1e-12);
      EXPECT_GE(f[i](p), f[3 - i - j](p) - 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------
// CSG

/// Every triangle separates the solid (behind it) from the outside (in
/// front), judged by the exact CSG function 1e-6 away from its centroid.
/// Slivers of area below 1e-12 are skipped: where a plane passes within
/// rounding of a grid vertex (TiltedPlane does, at (1/3, 1/3, 1/2)), their
/// corners are rounding apart and their normals are noise.
void ExpectOutwardBoundary(const ZeroSets& z, const std::vector<CsgNode>& tree, const std::vector<Field>& f) {
  std::vector<double> values(f.size());
  auto inside = [&](const Vec3& x) {
    for (std::size_t i = 0; i < f.size(); ++i) values[i] = f[i](x);
    return EvaluateCsg(tree, values.data()) <= 0;
  };
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) {
    const Vec3 c = Centroid(z, t), n = AreaVector(z, t);
    if (Norm(n) / 2 < 1e-12) continue;
    const Vec3 step = Scale(n, 1e-6 / Norm(n));
    EXPECT_TRUE(inside(Sub(c, step))) << "triangle " << t;
    EXPECT_FALSE(inside(Add(c, step))) << "triangle " << t;
  }
}

TEST(CsgExtraction, IntersectionOfTwoHalfSpacesKeepsOnlyTheBoundary) {
  // Operand regions are {f <= 0}: x <= 0.62 and y <= 0.43.
  const std::vector<Field> f = {[](const Vec3& x) { return x[0] - 0.62; }, [](const Vec3& x) { return x[1] - 0.43; }};
  const std::vector<CsgNode> tree = {{CsgNode::Op::Intersection, -1, -2}};
  const ZeroSets z = ExtractZeroSets(MakeGrid(3, 5, f), WithMode(Mode::Csg, tree));
  ExpectWellFormed(z);
  ExpectOutwardBoundary(z, tree, f);
  // Faces x = 0.62 (y <= 0.43) and y = 0.43 (x <= 0.62), unit height.
  EXPECT_NEAR(TotalArea(z), 0.43 + 0.62, 1e-12);
  EXPECT_NEAR(TotalLength(z), 1.0, 1e-12);
  for (const Label& label : z.segmentLabels) EXPECT_EQ(label, (Label{0, 1, -1, -1}));
}

TEST(CsgExtraction, TiltedHalfSpacesAndAThirdFunctionThatNeverMatters) {
  const std::vector<Field> f = {TiltedPlane, [](const Vec3& x) { return -SteepPlane(x); },
                                [](const Vec3& x) { return Sphere(x, {0.2, 0.2, 0.2}, 0.15); }};
  // (f1 and f2) or (f3 and not f3): the sphere contributes nothing.
  const std::vector<CsgNode> tree = {{CsgNode::Op::Union, 2, 3},
                                     {CsgNode::Op::Intersection, -1, -2},
                                     {CsgNode::Op::Intersection, -3, 4},
                                     {CsgNode::Op::Negation, -3, 0}};
  const ZeroSets z = ExtractZeroSets(MakeGrid(3, 6, f), WithMode(Mode::Csg, tree));
  ExpectWellFormed(z);
  ExpectOutwardBoundary(z, tree, f);
  for (const Label& label : z.triangleLabels) EXPECT_NE(label[0], 2);
  EXPECT_GT(z.triangleLabels.size(), 0u);
  EXPECT_TRUE(z.points.empty());
}

TEST(CsgExtraction, SphereMinusSphereIsAClosedOutwardSurface) {
  const Vec3 a = {0.5, 0.5, 0.5}, b = {0.72, 0.51, 0.49};
  const double ra = 0.3, rb = 0.2;
  const std::vector<Field> f = {[&](const Vec3& x) { return Sphere(x, a, ra); },
                                [&](const Vec3& x) { return Sphere(x, b, rb); }};
  // Inside A (Negation: f_A >= 0) and outside B (f_B <= 0).
  const std::vector<CsgNode> tree = {{CsgNode::Op::Intersection, 2, -2}, {CsgNode::Op::Negation, -1, 0}};
  const ZeroSets z = ExtractZeroSets(MakeGrid(3, 24, f), WithMode(Mode::Csg, tree));
  ExpectWellFormed(z);
  EXPECT_EQ(ExpectClosedOrientedSurface(z), 2);
  // Each piece lies on its own sphere, on the solid's side of the other.
  for (std::size_t t = 0; t < z.triangleLabels.size(); ++t) {
    const int i = z.triangleLabels[t][0];
    ASSERT_TRUE(i == 0 || i == 1);
    for (int k = 0; k < 3; ++k) {
      const Vec3 x = Corner(z, t, k);
      EXPECT_NEAR(f[i](x), 0, 0.01);
      // On the solid's side of the other sphere: outside B, inside A.
      EXPECT_GE(i == 0 ? -f[1](x) : f[0](x), -0.01);
    }
  }
  // A minus the lens A n B (d = |a - b|).
  const double d = Norm(Sub(a, b));
  const double lens = kPi * std::pow(ra + rb - d, 2) * (d * d + 2 * d * rb - 3 * rb * rb + 2 * d * ra + 6 * rb * ra - 3 * ra * ra) /
                      (12 * d);
  const double expected = 4.0 / 3 * kPi * std::pow(ra, 3) - lens;
  EXPECT_NEAR(EnclosedVolume(z), expected, 0.03 * expected);
  // The crease is a closed loop.
  ASSERT_GT(z.segmentLabels.size(), 0u);
  for (const auto& [v, degree] : SegmentDegrees(z, false)) EXPECT_EQ(degree, 2) << "vertex " << v;
}

TEST(CsgExtraction2D, DiscMinusDiscIsAClosedCounterClockwiseLoop) {
  const std::vector<Field> f = {[](const Vec3& x) { return Sphere(x, {0.5, 0.5, 0}, 0.3); },
                                [](const Vec3& x) { return Sphere(x, {0.73, 0.52, 0}, 0.2); }};
  // Inside A (Negation: f_A >= 0) and outside B (f_B <= 0).
  const std::vector<CsgNode> tree = {{CsgNode::Op::Intersection, 2, -2}, {CsgNode::Op::Negation, -1, 0}};
  const ZeroSets z = ExtractZeroSets(MakeGrid(2, 40, f), WithMode(Mode::Csg, tree));
  ExpectWellFormed(z);
  for (const auto& [v, d] : SegmentDegrees(z, true)) EXPECT_EQ(d, 2) << "vertex " << v;
  double twiceArea = 0;
  for (std::size_t s = 0; s < z.segmentLabels.size(); ++s) {
    const Vec3 p = VertexOf(z, z.segments[2 * s]), q = VertexOf(z, z.segments[2 * s + 1]);
    twiceArea += p[0] * q[1] - p[1] * q[0];
  }
  EXPECT_GT(twiceArea, 0) << "outward normals: counter-clockwise";
  EXPECT_EQ(z.pointLabels.size(), 2u) << "the two corners where the circles cross";
}

TEST(CsgExtraction, InvalidTreeGivesNothing) {
  const Grid grid = MakeGrid(3, 3, {TiltedPlane});
  const ZeroSets z = ExtractZeroSets(grid, WithMode(Mode::Csg, {{CsgNode::Op::Union, -1, -2}}));
  EXPECT_TRUE(z.vertices.empty());
  EXPECT_TRUE(z.triangles.empty());
}

}  // namespace
}  // namespace invmap::implicit
