#include "samples/sample_geometries.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
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

/// The bent, lifted beam: reference cube [0, 1]^3 to physical space.
std::array<double, 3> BeamMap(double a, double b, double c) {
  const double theta = 1.5 * a;
  const double radius = 2.0 + 0.8 * (b - 0.5);
  const double z = 0.8 * (c - 0.5) + 0.15 * std::sin(3.0 * a) + 0.1 * (b - 0.5) * std::sin(2.0 * a);
  return {radius * std::cos(theta), radius * std::sin(theta), z};
}

}  // namespace

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

QuadraticTetMesh CurvedTetMesh(int resolution) {
  QuadraticTetMesh mesh;
  // Nodes on the doubled grid: corners at even indices, edge midpoints of
  // the Kuhn tets on the odd ones, so shared nodes are shared by index.
  const int m = 2 * resolution + 1;
  auto nodeIndex = [m](int i, int j, int k) { return static_cast<std::int64_t>((k * m + j) * m + i); };
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        const std::array<double, 3> x = BeamMap(i / (m - 1.0), j / (m - 1.0), k / (m - 1.0));
        mesh.nodes.insert(mesh.nodes.end(), x.begin(), x.end());
      }
    }
  }
  // Kuhn split: one tet per ordering of the axes, from corner 000 to 111.
  const int axesOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  // gmsh tet10: vertices 0..3, then edges (0,1), (1,2), (0,2), (0,3), (2,3), (1,3).
  const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  for (int k = 0; k < resolution; ++k) {
    for (int j = 0; j < resolution; ++j) {
      for (int i = 0; i < resolution; ++i) {
        for (const auto& order : axesOrders) {
          std::array<std::array<int, 3>, 4> v;
          std::array<int, 3> corner{2 * i, 2 * j, 2 * k};
          v[0] = corner;
          for (int s = 0; s < 3; ++s) {
            corner[order[s]] += 2;
            v[s + 1] = corner;
          }
          for (int s = 0; s < 4; ++s) mesh.tets.push_back(nodeIndex(v[s][0], v[s][1], v[s][2]));
          for (const auto& e : edges) {
            const std::array<int, 3>& a = v[e[0]];
            const std::array<int, 3>& b = v[e[1]];
            mesh.tets.push_back(nodeIndex((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2));
          }
        }
      }
    }
  }
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

Geometry BumpySphere(std::int64_t minTriangles) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::int64_t, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  while (static_cast<std::int64_t>(faces.size()) < minTriangles) {
    std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> midpoints;
    auto midpoint = [&](std::int64_t a, std::int64_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      std::array<double, 3> m;
      for (int k = 0; k < 3; ++k) m[k] = 0.5 * (vertices[a][k] + vertices[b][k]);
      vertices.push_back(m);
      return midpoints[key] = static_cast<std::int64_t>(vertices.size() - 1);
    };
    std::vector<std::array<std::int64_t, 3>> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const std::int64_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      finer.push_back({f[0], a, c});
      finer.push_back({f[1], b, a});
      finer.push_back({f[2], c, b});
      finer.push_back({a, b, c});
    }
    faces.swap(finer);
  }
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Tri;
  for (const auto& v : vertices) {
    const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double x = v[0] / norm, y = v[1] / norm, z = v[2] / norm;
    const double radius = 1.0 + 0.08 * std::sin(6 * x) * std::sin(5 * y) * std::sin(4 * z);
    patch.points.insert(patch.points.end(), {radius * x, radius * y, radius * z});
  }
  for (const auto& f : faces) patch.cells.insert(patch.cells.end(), f.begin(), f.end());
  Geometry geometry;
  geometry.dimension = 3;
  geometry.patches.push_back(std::move(patch));
  return geometry;
}

}  // namespace invmap::samples
