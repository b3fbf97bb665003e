#include "samples/sample_geometries.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace invmap::samples {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Clamped uniform knots over [0, 1] for `spans` spans of degree p.
std::vector<double> ClampedKnots(int spans, int p) {
  std::vector<double> knots(p, 0.0);
  for (int i = 0; i <= spans; ++i) knots.push_back(static_cast<double>(i) / spans);
  knots.insert(knots.end(), p, 1.0);
  return knots;
}

/// Greville abscissae: where each control point "sits" in parameter space.
std::vector<double> Greville(const std::vector<double>& knots, int p) {
  std::vector<double> g(knots.size() - p - 1);
  for (std::size_t i = 0; i < g.size(); ++i) {
    double sum = 0.0;
    for (int k = 1; k <= p; ++k) sum += knots[i + k];
    g[i] = sum / p;
  }
  return g;
}

/// The 9-point rational quadratic unit circle: points, weights, knots.
struct Circle {
  std::array<std::array<double, 2>, 9> points{{{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}}};
  std::array<double, 9> weights{};
  std::vector<double> knots{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  Circle() {
    for (int i = 0; i < 9; ++i) weights[i] = i % 2 ? std::sqrt(0.5) : 1.0;
  }
};

/// The golden ratio: the icosahedron's corners are (0, +-1, +-t) and their
/// cyclic permutations.
const double kGolden = (1.0 + std::sqrt(5.0)) / 2.0;

}  // namespace

namespace detail {

std::array<double, 3> BeamMap(double a, double b, double c) {
  const double theta = 1.5 * a;
  const double radius = 2.0 + 0.8 * (b - 0.5);
  const double z = 0.8 * (c - 0.5) + 0.15 * std::sin(3.0 * a) + 0.1 * (b - 0.5) * std::sin(2.0 * a);
  return {radius * std::cos(theta), radius * std::sin(theta), z};
}

const int kIcosahedronFaces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

std::array<double, 3> Bump(double x, double y, double z) {
  const double radius = 1.0 + 0.08 * std::sin(6 * x) * std::sin(5 * y) * std::sin(4 * z);
  return {radius * x, radius * y, radius * z};
}

}  // namespace detail

Geometry WavySurface(int spans) {
  const int p = 3;
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {p, p};
  // u: a triple knot at 0.5 makes the surface only C0 there (the crease).
  std::vector<double> u = ClampedKnots(spans, p);
  const double crease = 0.5;
  const auto at = std::lower_bound(u.begin(), u.end(), crease);
  const int present = static_cast<int>(std::count(u.begin(), u.end(), crease));
  u.insert(at, p - present, crease);
  const std::vector<double> v = ClampedKnots(spans, p);
  patch.knots = {u, v};
  const std::vector<double> gu = Greville(u, p), gv = Greville(v, p);
  patch.counts = {static_cast<int>(gu.size()), static_cast<int>(gv.size())};
  for (double y : gv) {
    for (double x : gu) {
      const double z = 0.08 * std::sin(2 * kPi * 3 * x) * std::cos(2 * kPi * 2 * y) + 0.25 * std::abs(x - crease);
      patch.points.insert(patch.points.end(), {x, y, z});
    }
  }
  Geometry geometry;
  geometry.dimension = 3;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

Geometry NurbsTorus(double major, double minor) {
  const Circle circle;
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2, 2};
  patch.knots = {circle.knots, circle.knots};
  patch.counts = {9, 9};
  // u sweeps the tube's center around z; v goes around the tube.
  for (int j = 0; j < 9; ++j) {
    for (int i = 0; i < 9; ++i) {
      const double ring = major + minor * circle.points[j][0];
      patch.points.insert(patch.points.end(),
                          {ring * circle.points[i][0], ring * circle.points[i][1], minor * circle.points[j][1]});
      patch.weights.push_back(circle.weights[i] * circle.weights[j]);
    }
  }
  Geometry geometry;
  geometry.dimension = 3;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

Geometry NurbsCurve2D() {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {3};
  patch.points = {0.0, 0.0, 3.0, 0.0, 3.2, 2.0, 0.5, 2.3, 0.3, 0.2, 1.6, 0.5, 1.7, 1.3, 1.1, 1.1, 1.3, 0.8, 2.5, 0.9};
  patch.weights = {1.0, 0.7, 2.0, 1.2, 0.6, 1.5, 1.0, 2.5, 0.8, 1.0};
  patch.counts = {static_cast<int>(patch.weights.size())};
  patch.knots = {{0, 0, 0, 0, 0.1, 0.15, 0.35, 0.5, 0.55, 0.8, 1, 1, 1, 1}};
  Geometry geometry;
  geometry.dimension = 2;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

CurvedTetGrid::CurvedTetGrid(int resolution) : resolution_(resolution), m_(2 * resolution + 1) {}

// Nodes on the doubled grid: corners at even indices, edge midpoints of the
// Kuhn tets on the odd ones, so shared nodes are shared by index.
std::int64_t CurvedTetGrid::NumNodes() const { return static_cast<std::int64_t>(m_) * m_ * m_; }

std::int64_t CurvedTetGrid::NumTets() const { return 6 * static_cast<std::int64_t>(resolution_) * resolution_ * resolution_; }

QuadraticTetMesh CurvedTetMesh(int resolution) {
  const CurvedTetGrid grid(resolution);
  QuadraticTetMesh mesh;
  mesh.nodes.reserve(3 * static_cast<std::size_t>(grid.NumNodes()));
  mesh.tets.reserve(10 * static_cast<std::size_t>(grid.NumTets()));
  grid.ForEachNode([&](double x, double y, double z) { mesh.nodes.insert(mesh.nodes.end(), {x, y, z}); });
  grid.ForEachTet([&](const std::int64_t* nodes) { mesh.tets.insert(mesh.tets.end(), nodes, nodes + 10); });
  return mesh;
}

Geometry ToBezierGeometry(const QuadraticTetMesh& mesh) {
  Patch patch;
  patch.kind = Patch::Kind::BezierCells;
  const std::size_t numTets = mesh.tets.size() / 10;
  // Bezier order of a quadratic tet (a1 fastest, then a2, then a3): vertex 0,
  // edge 01, vertex 1, edge 02, edge 12, vertex 2, edge 03, edge 13, edge 23, vertex 3.
  // Each entry: the gmsh node (vertex) or the gmsh edge node with its two vertices.
  struct Slot {
    int node, a, b;
  };
  const Slot slots[10] = {{0, -1, -1}, {4, 0, 1}, {1, -1, -1}, {6, 0, 2}, {5, 1, 2},
                          {2, -1, -1}, {7, 0, 3}, {9, 1, 3}, {8, 2, 3}, {3, -1, -1}};
  patch.cellOffsets.push_back(0);
  for (std::size_t t = 0; t < numTets; ++t) {
    const std::int64_t* tet = &mesh.tets[10 * t];
    for (const Slot& slot : slots) {
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.nodes[3 * tet[slot.node] + k];
        // Quadratic Lagrange to Bernstein: an edge's control point is
        // 2 * midpoint - (end0 + end1) / 2; vertices are interpolated.
        patch.points.push_back(slot.a < 0 ? x
                                          : 2.0 * x - 0.5 * (mesh.nodes[3 * tet[slot.a] + k] + mesh.nodes[3 * tet[slot.b] + k]));
      }
    }
    patch.cellTypes.push_back(CellType::Tet);
    patch.cellDegrees.insert(patch.cellDegrees.end(), {2, 0, 0});
    patch.cellOffsets.push_back(static_cast<std::int64_t>(10 * (t + 1)));
  }
  Geometry geometry;
  geometry.dimension = 3;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

BumpySphereMesh::BumpySphereMesh(std::int64_t minTriangles) {
  while (20 * n_ * n_ < minTriangles) n_ *= 2;
  int count = 0;
  for (auto& row : edgeOf_) std::fill(std::begin(row), std::end(row), -1);
  for (const auto& face : detail::kIcosahedronFaces) {
    for (int e = 0; e < 3; ++e) {
      const int P = std::min(face[e], face[(e + 1) % 3]), Q = std::max(face[e], face[(e + 1) % 3]);
      if (edgeOf_[P][Q] >= 0) continue;
      edgeOf_[P][Q] = edgeOf_[Q][P] = count;
      edges_[count++] = {P, Q};
    }
  }
}

std::int64_t BumpySphereMesh::NumVertices() const { return 10 * n_ * n_ + 2; }

std::int64_t BumpySphereMesh::NumTriangles() const { return 20 * n_ * n_; }

std::array<double, 3> BumpySphereMesh::Corner(int c) const {
  const double t = kGolden;
  static const double kCorners[12][3] = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  return {kCorners[c][0], kCorners[c][1], kCorners[c][2]};
}

std::int64_t BumpySphereMesh::GridVertex(int f, std::int64_t i, std::int64_t j) const {
  const int* corner = detail::kIcosahedronFaces[f];
  const std::int64_t a = n_ - i - j;
  if (i == 0 && j == 0) return corner[0];
  if (i == n_) return corner[1];
  if (j == n_) return corner[2];
  // On an edge (P, Q), `steps` from P: counted from the edge's lower corner.
  const auto onEdge = [&](int P, int Q, std::int64_t steps) {
    const std::int64_t t = P < Q ? steps : n_ - steps;
    return 12 + edgeOf_[P][Q] * (n_ - 1) + (t - 1);
  };
  if (j == 0) return onEdge(corner[0], corner[1], i);
  if (i == 0) return onEdge(corner[0], corner[2], j);
  if (a == 0) return onEdge(corner[1], corner[2], j);
  // Inside: rows j = 1 .. n - 2 of n - 1 - j vertices each.
  const std::int64_t perFace = (n_ - 1) * (n_ - 2) / 2;
  const std::int64_t row = (j - 1) * (n_ - 1) - (j - 1) * j / 2;
  return 12 + 30 * (n_ - 1) + f * perFace + row + (i - 1);
}

Geometry BumpySphere(std::int64_t minTriangles) {
  const BumpySphereMesh mesh(minTriangles);
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Tri;
  patch.points.reserve(3 * static_cast<std::size_t>(mesh.NumVertices()));
  patch.cells.reserve(3 * static_cast<std::size_t>(mesh.NumTriangles()));
  mesh.ForEachVertex([&](double x, double y, double z) { patch.points.insert(patch.points.end(), {x, y, z}); });
  mesh.ForEachTriangle(
      [&](std::int64_t a, std::int64_t b, std::int64_t c) { patch.cells.insert(patch.cells.end(), {a, b, c}); });
  Geometry geometry;
  geometry.dimension = 3;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

}  // namespace invmap::samples
