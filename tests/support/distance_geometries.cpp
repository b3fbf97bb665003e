#include "tests/support/distance_geometries.h"

#include <algorithm>
#include <cmath>

namespace invmap::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Interpolating (Greville) control points of a clamped uniform cubic
/// B-spline: a smooth approximation of f, enough for test geometry.
std::vector<double> UniformClampedKnots(int degree, int spans) {
  std::vector<double> knots(degree + 1, 0.0);
  for (int i = 1; i < spans; ++i) knots.push_back(static_cast<double>(i) / spans);
  knots.insert(knots.end(), degree + 1, 1.0);
  return knots;
}

double GrevilleOf(const std::vector<double>& knots, int degree, int i) {
  double sum = 0.0;
  for (int k = 1; k <= degree; ++k) sum += knots[i + k];
  return sum / degree;
}

}  // namespace

Geometry NurbsCylinder(double r, double h) {
  const double kHalfSqrt2 = std::sqrt(0.5);
  const double circle[9][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}};
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2, 1};
  patch.counts = {9, 2};
  patch.knots = {{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}, {0, 0, 1, 1}};
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 9; ++i) {
      patch.points.insert(patch.points.end(), {r * circle[i][0], r * circle[i][1], (j == 0 ? -0.5 : 0.5) * h});
      patch.weights.push_back(i % 2 == 1 ? kHalfSqrt2 : 1.0);
    }
  }
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

Geometry BezierCurve(const std::vector<std::array<double, 3>>& points) {
  Patch patch;
  patch.kind = Patch::Kind::Bezier;
  patch.cell = CellType::Line;
  patch.degrees = {static_cast<int>(points.size()) - 1};
  for (const auto& p : points) patch.points.insert(patch.points.end(), p.begin(), p.end());
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

Geometry PlaneSquare(double s) {
  Patch patch;
  patch.kind = Patch::Kind::Bezier;
  patch.cell = CellType::Quad;
  patch.degrees = {1, 1};
  patch.points = {-s, -s, 0, s, -s, 0, -s, s, 0, s, s, 0};
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

Geometry WavyCurve(double amplitude, int waves, int spans) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {3};
  patch.knots = {UniformClampedKnots(3, spans)};
  const int n = spans + 3;
  patch.counts = {n};
  for (int i = 0; i < n; ++i) {
    const double x = GrevilleOf(patch.knots[0], 3, i);
    patch.points.insert(patch.points.end(),
                        {x, 0.1 * std::cos(3.0 * x), amplitude * std::sin(waves * 2.0 * kPi * x)});
  }
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

Geometry WavySurface(double amplitude, int wx, int wy, int spans, bool rational) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {3, 3};
  patch.knots = {UniformClampedKnots(3, spans), UniformClampedKnots(3, spans)};
  const int n = spans + 3;
  patch.counts = {n, n};
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = GrevilleOf(patch.knots[0], 3, i), y = GrevilleOf(patch.knots[1], 3, j);
      patch.points.insert(patch.points.end(),
                          {x, y, amplitude * std::sin(wx * 2.0 * kPi * x) * std::cos(wy * 2.0 * kPi * y)});
      if (rational) patch.weights.push_back(1.0 + 0.25 * std::sin(3.0 * i + 2.0 * j));
    }
  }
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

Geometry MeshGeometry(const Patch& patch) {
  Geometry g;
  g.patches.push_back(patch);
  return g;
}

Geometry BoxHexMesh(const std::array<double, 3>& lo, const std::array<double, 3>& hi, int n) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Hex;
  auto index = [n](int i, int j, int k) { return static_cast<std::int64_t>((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        patch.points.insert(patch.points.end(), {lo[0] + (hi[0] - lo[0]) * i / n, lo[1] + (hi[1] - lo[1]) * j / n,
                                                 lo[2] + (hi[2] - lo[2]) * k / n});
      }
    }
  }
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        patch.cells.insert(patch.cells.end(), {index(i, j, k), index(i + 1, j, k), index(i + 1, j + 1, k),
                                               index(i, j + 1, k), index(i, j, k + 1), index(i + 1, j, k + 1),
                                               index(i + 1, j + 1, k + 1), index(i, j + 1, k + 1)});
      }
    }
  }
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

double BoxDistance(const std::array<double, 3>& lo, const std::array<double, 3>& hi, const double* p) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
    d2 += gap * gap;
  }
  return std::sqrt(d2);
}

}  // namespace invmap::testing
