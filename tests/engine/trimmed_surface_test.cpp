// Trimmed surfaces (Patch::Kind::TrimmedSurface) built by hand, against
// closed forms: a square plate with a round hole, and a part of a cylinder
// cut out by a loop of its parameters, whose own u is the angle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "invmap/invmap.h"

namespace invmap {
namespace {

SplineCurve Line(const std::vector<double>& a, const std::vector<double>& b, double t0, double t1) {
  SplineCurve c;
  c.degree = 1;
  c.knots = {t0, t0, t1, t1};
  c.points = a;
  c.points.insert(c.points.end(), b.begin(), b.end());
  return c;
}

/// center + cos(t) x + sin(t) y for t in [a, b], quarter-turn spans at most.
SplineCurve Arc(int dim, const double* center, const double* x, const double* y, double a, double b) {
  const int spans = static_cast<int>(std::ceil((b - a) / (M_PI / 2) - 1e-9));
  const double step = (b - a) / spans, h = step / 2;
  SplineCurve c;
  c.degree = 2;
  c.angular = true;
  c.knots = {a, a, a};
  auto at = [&](double t, double scale) {
    for (int k = 0; k < dim; ++k) c.points.push_back(center[k] + scale * (std::cos(t) * x[k] + std::sin(t) * y[k]));
  };
  at(a, 1.0);
  c.weights.push_back(1.0);
  for (int s = 0; s < spans; ++s) {
    const double lo = a + s * step, hi = s + 1 == spans ? b : a + (s + 1) * step;
    at(lo + h, 1.0 / std::cos(h));
    c.weights.push_back(std::cos(h));
    at(hi, 1.0);
    c.weights.push_back(1.0);
    c.knots.insert(c.knots.end(), {hi, hi});
  }
  c.knots.push_back(b);
  return c;
}

double Hypot(double a, double b) { return std::sqrt(a * a + b * b); }

/// The square plate [0, 10]^2 at z = 0 less the disk of radius 3 about (5, 5).
Patch PlateWithHole() {
  Patch p;
  p.kind = Patch::Kind::TrimmedSurface;
  p.degrees = {1, 1};
  p.knots = {{0, 0, 10, 10}, {0, 0, 10, 10}};
  p.counts = {2, 2};
  p.points = {0, 0, 0, 10, 0, 0, 0, 10, 0, 10, 10, 0};
  const double corner[5][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
  std::vector<SplineCurve> outer;
  for (int k = 0; k < 4; ++k) {
    const std::vector<double> a{corner[k][0], corner[k][1]}, b{corner[k + 1][0], corner[k + 1][1]};
    outer.push_back(Line(a, b, 0, 10));
    PatchEdge edge;
    edge.curve = Line({a[0], a[1], 0}, {b[0], b[1], 0}, 0, 10);
    edge.pcurve = outer.back();
    p.edges.push_back(edge);
  }
  const double c2[2] = {5, 5}, x2[2] = {3, 0}, y2[2] = {0, 3};
  const double c3[3] = {5, 5, 0}, x3[3] = {3, 0, 0}, y3[3] = {0, 3, 0};
  PatchEdge circle;
  circle.curve = Arc(3, c3, x3, y3, 0, 2 * M_PI);
  circle.pcurve = Arc(2, c2, x2, y2, 0, 2 * M_PI);
  p.edges.push_back(circle);
  p.trimLoops = {outer, {circle.pcurve}};
  return p;
}

/// The cylinder of radius 2 about the z axis, u the angle in [0, pi] (two
/// quarter arcs), v = z in [0, 4], cut to u in [0.4, 2.6], v in [1, 3].
Patch CylinderWindow() {
  Patch p;
  p.kind = Patch::Kind::TrimmedSurface;
  const double origin[3] = {0, 0, 0}, x[3] = {2, 0, 0}, y[3] = {0, 2, 0};
  const SplineCurve arc = Arc(3, origin, x, y, 0, M_PI);
  p.degrees = {2, 1};
  p.knots = {arc.knots, {0, 0, 4, 4}};
  p.counts = {static_cast<int>(arc.weights.size()), 2};
  for (const double z : {0.0, 4.0}) {
    for (std::size_t i = 0; i < arc.weights.size(); ++i) {
      p.points.insert(p.points.end(), {arc.points[3 * i], arc.points[3 * i + 1], z});
      p.weights.push_back(arc.weights[i]);
    }
  }
  p.angular = {1, 0};
  const double u0 = 0.4, u1 = 2.6;
  for (const double z : {1.0, 3.0}) {
    const double center[3] = {0, 0, z};
    PatchEdge edge;
    edge.curve = Arc(3, center, x, y, u0, u1);
    edge.pcurve = Line({u0, z}, {u1, z}, u0, u1);
    p.edges.push_back(edge);
  }
  for (const double u : {u0, u1}) {
    PatchEdge edge;
    edge.curve = Line({2 * std::cos(u), 2 * std::sin(u), 1}, {2 * std::cos(u), 2 * std::sin(u), 3}, 1, 3);
    edge.pcurve = Line({u, 1}, {u, 3}, 1, 3);
    p.edges.push_back(edge);
  }
  p.trimLoops = {{Line({u0, 1}, {u1, 1}, 0, 1), Line({u1, 1}, {u1, 3}, 0, 1), Line({u1, 3}, {u0, 3}, 0, 1),
                  Line({u0, 3}, {u0, 1}, 0, 1)}};
  return p;
}

double SegmentDistance(const double* p, const double* a, const double* b) {
  double ab[3], ap[3], t = 0, len2 = 0;
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ap[k] = p[k] - a[k];
    t += ab[k] * ap[k];
    len2 += ab[k] * ab[k];
  }
  t = std::clamp(t / len2, 0.0, 1.0);
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
  return std::sqrt(d2);
}

Results Invert(const Patch& patch, const std::vector<double>& points) {
  Geometry g;
  g.patches.push_back(patch);
  BuildResult built = Manifold::Build(g);
  EXPECT_EQ(built.error, "");
  Results r;
  EXPECT_EQ(built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &r), Error::Ok);
  return r;
}

std::vector<double> RandomPoints(int n, const double* lo, const double* hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> points;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) points.push_back(lo[k] + (hi[k] - lo[k]) * unit(rng));
  return points;
}

TEST(TrimmedSurface, PlateWithHoleAgainstClosedForm) {
  const double lo[3] = {-3, -3, -2}, hi[3] = {13, 13, 2};
  const std::vector<double> points = RandomPoints(20000, lo, hi, 1);
  const Results r = Invert(PlateWithHole(), points);
  int wrong = 0, badParams = 0;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    const double* p = &points[3 * i];
    const double outside = Hypot(std::max({-p[0], 0.0, p[0] - 10}), std::max({-p[1], 0.0, p[1] - 10}));
    const double inPlane = outside > 0 ? outside : std::max(0.0, 3 - Hypot(p[0] - 5, p[1] - 5));
    const double exact = Hypot(inPlane, p[2]);
    wrong += std::abs(r.distance[i] - exact) > 1e-10 ? 1 : 0;
    // The plane's own parameters are x and y, on the face and on its edges.
    badParams += std::abs(r.params[3 * i] - r.closest[3 * i]) > 1e-9 ||
                         std::abs(r.params[3 * i + 1] - r.closest[3 * i + 1]) > 1e-9 || !std::isnan(r.params[3 * i + 2])
                     ? 1
                     : 0;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(badParams, 0);
}

TEST(TrimmedSurface, CylinderWindowAgainstClosedFormWithAngles) {
  const double lo[3] = {-4, -4, -1}, hi[3] = {4, 4, 5};
  const std::vector<double> points = RandomPoints(20000, lo, hi, 2);
  const Results r = Invert(CylinderWindow(), points);
  int wrong = 0, badParams = 0;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    const double* p = &points[3 * i];
    const double phi = std::atan2(p[1], p[0]);
    double exact = std::numeric_limits<double>::infinity();
    if (phi >= 0.4 && phi <= 2.6) exact = Hypot(Hypot(p[0], p[1]) - 2, std::max({1 - p[2], 0.0, p[2] - 3}));
    for (const double u : {0.4, 2.6}) {
      const double a[3] = {2 * std::cos(u), 2 * std::sin(u), 1}, b[3] = {a[0], a[1], 3};
      exact = std::min(exact, SegmentDistance(p, a, b));
    }
    wrong += std::abs(r.distance[i] - exact) > 1e-10 ? 1 : 0;
    // u is the angle of the closest point, v its height.
    const double* x = &r.closest[3 * i];
    badParams += std::abs(r.params[3 * i] - std::atan2(x[1], x[0])) > 1e-9 || std::abs(r.params[3 * i + 1] - x[2]) > 1e-9
                     ? 1
                     : 0;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(badParams, 0);
}

TEST(TrimmedSurface, CellsAreTheSurfaceSpansThenTheEdgeSpans) {
  // The window (u from 0.4 to 2.6) meets both quarter spans of u, so both
  // have cells (0 and 1); then the edges: two arcs of two spans each (0.4
  // to pi/2 and pi/2 to 2.6), two segments of one.
  Geometry g;
  g.patches.push_back(CylinderWindow());
  BuildResult built = Manifold::Build(g);
  ASSERT_EQ(built.error, "");
  EXPECT_EQ(built.manifold.NumCells(0), 2 + 2 + 2 + 1 + 1);
}

TEST(TrimmedSurface, InvalidFieldsAreNamed) {
  Patch p = PlateWithHole();
  p.trimLoops[0][1].knots = {0, 5, 1, 10};
  Geometry g;
  g.patches.push_back(p);
  BuildResult built = Manifold::Build(g);
  EXPECT_EQ(built.code, Error::InvalidArgument);
  EXPECT_EQ(built.problem.field, GeometryField::TrimLoops);
  EXPECT_EQ(built.problem.element, 0);
  EXPECT_EQ(built.problem.item, 1);
  EXPECT_NE(built.error.find("patch 0: trimLoops[0]: curve 1: knots: decreasing"), std::string::npos) << built.error;
  p = CylinderWindow();
  p.angular = {0, 1};  // v is linear: an angular direction must be quadratic arcs
  g.patches = {p};
  built = Manifold::Build(g);
  EXPECT_EQ(built.problem.field, GeometryField::Knots);
  EXPECT_EQ(built.problem.element, 1);
  EXPECT_NE(built.error.find("angular"), std::string::npos) << built.error;
  p = PlateWithHole();
  p.edges[4].curve.weights[1] = -1.0;
  g.patches = {p};
  built = Manifold::Build(g);
  EXPECT_EQ(built.problem.field, GeometryField::Edges);
  EXPECT_EQ(built.problem.element, 4);
  EXPECT_NE(built.error.find("edges[4]: curve: weights[1]"), std::string::npos) << built.error;
}

}  // namespace
}  // namespace invmap
