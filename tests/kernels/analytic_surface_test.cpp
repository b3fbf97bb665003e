// The closed-form minima of kernels/analytic_surface.h over boxes of own
// parameters, against dense sampling of the box refined around its best
// sample: random frames (either handedness), boxes from a sliver to a
// whole turn anywhere on the circle, ring and spindle tori, points near,
// far, on the axis, at the centre, on a torus's centre circle, beyond a
// cone's apex. The answer must
// be a point of the box on the surface (so never nearer than the minimum)
// and never farther than the sampled minimum.
#include "kernels/analytic_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/own_parameter.h"
#include "tests/kernels/analytic_reference.h"
#include "kernels/trim_region.h"
#include "kernels/trimmed_cell.h"

namespace invmap::kernels {
namespace {

using Kind = AnalyticSurface::Kind;
using reference::AddSquare;
using reference::SampledMinimum2;

void Normalize(double* v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] /= n;
}

double Dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A random orthonormal frame, left-handed when `leftHanded`.
void RandomFrame(std::mt19937_64& rng, bool leftHanded, AnalyticSurface* s) {
  std::normal_distribution<double> normal;
  for (int k = 0; k < 3; ++k) s->z[k] = normal(rng);
  Normalize(s->z);
  for (int k = 0; k < 3; ++k) s->x[k] = normal(rng);
  const double along = Dot(s->x, s->z);
  for (int k = 0; k < 3; ++k) s->x[k] -= along * s->z[k];
  Normalize(s->x);
  const double sign = leftHanded ? -1.0 : 1.0;
  s->y[0] = sign * (s->z[1] * s->x[2] - s->z[2] * s->x[1]);
  s->y[1] = sign * (s->z[2] * s->x[0] - s->z[0] * s->x[2]);
  s->y[2] = sign * (s->z[0] * s->x[1] - s->z[1] * s->x[0]);
  for (int k = 0; k < 3; ++k) s->origin[k] = 4.0 * normal(rng);
}

/// Random surfaces of `kind`, boxes and points; the closed form against sampling.
void CheckKind(Kind kind, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double widths[] = {1e-3, 0.2, M_PI / 6.0, 1.0, 2.5, 5.0, 2.0 * M_PI};
  int checked = 0, declined = 0;
  for (int trial = 0; trial < 60; ++trial) {
    AnalyticSurface s;
    s.kind = kind;
    RandomFrame(rng, trial % 2 == 1, &s);
    s.radius = 0.5 + 3.0 * unit(rng);
    if (kind == Kind::Torus) {
      s.minorRadius = s.radius * (trial % 3 == 0 ? 1.2 + 2.0 * unit(rng) : 0.1 + 0.85 * unit(rng));  // spindle, ring
    }
    if (kind == Kind::Cone) {
      if (trial % 5 == 0) s.radius = 0.0;
      const double angle = (0.1 + 1.3 * unit(rng)) * (trial % 3 == 0 ? -1.0 : 1.0);
      s.sinAngle = std::sin(angle);
      s.cosAngle = std::cos(angle);
    }
    AnalyticCell cell;
    cell.surface = &s;
    const bool uAngular = kind != Kind::Plane;
    const bool vAngular = kind == Kind::Sphere || kind == Kind::Torus;
    cell.angular[0] = uAngular;
    cell.angular[1] = vAngular;
    cell.paramScale[0] = uAngular ? widths[trial % 7] : 0.5 + 4.0 * unit(rng);
    cell.paramLo[0] = uAngular ? -8.0 + 16.0 * unit(rng) : -3.0 + 3.0 * unit(rng);
    if (kind == Kind::Sphere) {
      const double a = -0.5 * M_PI + M_PI * unit(rng), b = -0.5 * M_PI + M_PI * unit(rng);
      cell.paramLo[1] = trial % 4 == 0 ? -0.5 * M_PI : std::min(a, b);
      cell.paramScale[1] = trial % 4 == 0 ? M_PI : std::max(std::abs(b - a), 1e-3);
    } else if (kind == Kind::Torus) {
      cell.paramScale[1] = widths[(trial / 7) % 7];
      cell.paramLo[1] = -8.0 + 16.0 * unit(rng);
    } else {
      cell.paramLo[1] = -4.0 + 5.0 * unit(rng);
      cell.paramScale[1] = 0.3 + 4.0 * unit(rng);
    }
    // An angular box's own parameter runs through the symmetric arc's
    // angle: only spans below a half turn are arcs, wider test boxes are
    // plain angles (reference = linear).
    for (int d = 0; d < 2; ++d) cell.angular[d] = cell.angular[d] && cell.paramScale[d] < M_PI;
    if (!ClosedFormCovers(cell)) {
      // Only a cone's box at its apex, and a spindle torus's reaching its axis, are refused.
      EXPECT_TRUE(kind == Kind::Cone || (kind == Kind::Torus && s.minorRadius > s.radius)) << "trial " << trial;
      ++declined;
      continue;
    }
    const double lo[2] = {cell.paramLo[0], cell.paramLo[1]};
    const double hi[2] = {cell.paramLo[0] + cell.paramScale[0], cell.paramLo[1] + cell.paramScale[1]};
    const double scale = s.radius + s.minorRadius + 5.0;
    for (int q = 0; q < 12; ++q) {
      double p[3];
      std::normal_distribution<double> normal;
      // Random points, and points on the axis, at the origin, on a torus's
      // centre circle, on the surface.
      double local[3] = {normal(rng) * scale, normal(rng) * scale, normal(rng) * scale};
      if (q == 0 || q == 1) local[0] = local[1] = 0.0;
      if (q == 2) local[0] = local[1] = local[2] = 0.0;
      if (q == 3) {
        local[0] = s.radius;
        local[1] = local[2] = 0.0;
      }
      for (int k = 0; k < 3; ++k) p[k] = s.origin[k] + local[0] * s.x[k] + local[1] * s.y[k] + local[2] * s.z[k];
      if (q == 4) s.Evaluate(lo[0] + (hi[0] - lo[0]) * unit(rng), lo[1] + (hi[1] - lo[1]) * unit(rng), p);
      CellSolveResult r;
      ASSERT_TRUE(SolveAnalyticCell(cell, p, std::numeric_limits<double>::infinity(), &r));
      ASSERT_NE(r.status, PointStatus::Farther);
      // The answer is the surface at the own parameters of its reference point.
      double own[2];
      for (int d = 0; d < 2; ++d) {
        ASSERT_GE(r.ref[d], 0.0);
        ASSERT_LE(r.ref[d], 1.0);
        own[d] = OwnParameter(cell.paramLo[d], cell.paramScale[d], cell.angular[d], r.ref[d]);
      }
      double at[3];
      s.Evaluate(own[0], own[1], at);
      EXPECT_NEAR(std::hypot(at[0] - r.closest[0], at[1] - r.closest[1], at[2] - r.closest[2]), 0.0, 1e-12 * scale);
      EXPECT_NEAR(r.distance, std::hypot(p[0] - r.closest[0], p[1] - r.closest[1], p[2] - r.closest[2]),
                  1e-12 * scale);
      const double sampled = std::sqrt(SampledMinimum2(s, lo, hi, p));
      EXPECT_LE(r.distance, sampled + 1e-11 * scale)
          << "trial " << trial << " point " << q << ": closed form " << r.distance << ", sampled " << sampled;
      // And a bound below it makes the cell Farther.
      CellSolveResult farther;
      ASSERT_TRUE(SolveAnalyticCell(cell, p, 0.25 * r.distance * r.distance, &farther));
      if (r.distance > 0.0) {
        EXPECT_EQ(farther.status, PointStatus::Farther);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
  if (kind == Kind::Cone || kind == Kind::Torus) {
    EXPECT_GT(declined, 0);
  }
}

TEST(AnalyticSurface, PlaneBoxMinimaAgainstSampling) { CheckKind(Kind::Plane, 1); }
TEST(AnalyticSurface, CylinderBoxMinimaAgainstSampling) { CheckKind(Kind::Cylinder, 2); }
TEST(AnalyticSurface, ConeBoxMinimaAgainstSampling) { CheckKind(Kind::Cone, 3); }
TEST(AnalyticSurface, SphereBoxMinimaAgainstSampling) { CheckKind(Kind::Sphere, 4); }
TEST(AnalyticSurface, TorusBoxMinimaAgainstSampling) { CheckKind(Kind::Torus, 5); }

/// A trimmed cell of a cylinder of radius 2 (the standard frame) over a
/// whole turn, v in [-5, 5], whose region is a small square about `centre`;
/// the point (3, 0, 1): azimuth 0, 3 from the axis, height 1.
struct TrimmedCylinder {
  AnalyticSurface surface;
  TrimRegion region;
  TrimmedCell trim;
  AnalyticCell cell;

  explicit TrimmedCylinder(const double* centre) {
    surface.kind = Kind::Cylinder;
    surface.radius = 2.0;
    AddSquare(centre, 0.1, &region);
    trim.region = &region;
    trim.paramLo[0] = -1.0;
    trim.paramScale[0] = 2.0 * M_PI;
    trim.paramLo[1] = -5.0;
    trim.paramScale[1] = 10.0;
    const double lo[2] = {-1.0, -5.0}, hi[2] = {-1.0 + 2.0 * M_PI, 5.0};
    trim.near = region.PiecesFor(lo, hi);
    cell.surface = &surface;
    for (int d = 0; d < 2; ++d) {
      cell.paramLo[d] = trim.paramLo[d];
      cell.paramScale[d] = trim.paramScale[d];
    }
    cell.trim = &trim;
  }
};

TEST(AnalyticSurface, TrimmedCellAnswersInsideItsRegionOnly) {
  const double p[3] = {3.0, 0.0, 1.0};
  const double infinity = std::numeric_limits<double>::infinity();
  {
    // The region holds the foot (u 0, v 1): the box's minimum, at 1.
    const double centre[2] = {0.0, 1.0};
    TrimmedCylinder c(centre);
    CellSolveResult r;
    ASSERT_TRUE(SolveAnalyticCell(c.cell, p, infinity, &r));
    ASSERT_EQ(r.status, PointStatus::Converged);
    EXPECT_NEAR(r.distance, 1.0, 1e-14);
  }
  {
    // The region holds the opposite stationary point (u pi, v 1) only:
    // the cell's answer is there, at 3 + 2 (a point of the face).
    const double centre[2] = {M_PI, 1.0};
    TrimmedCylinder c(centre);
    CellSolveResult r;
    ASSERT_TRUE(SolveAnalyticCell(c.cell, p, infinity, &r));
    ASSERT_NE(r.status, PointStatus::Farther);
    EXPECT_NEAR(r.distance, 5.0, 1e-14);
    EXPECT_NEAR(r.closest[0], -2.0, 1e-14);
    EXPECT_NEAR(r.closest[2], 1.0, 1e-14);
  }
  {
    // The region holds no stationary point: no answer of its own (its
    // edges answer the face there).
    const double centre[2] = {1.5, -3.0};
    TrimmedCylinder c(centre);
    CellSolveResult r;
    ASSERT_TRUE(SolveAnalyticCell(c.cell, p, infinity, &r));
    EXPECT_EQ(r.status, PointStatus::Farther);
    // A point on the axis has a circle of stationary points: the closed
    // form leaves it to the NURBS search.
    const double onAxis[3] = {0.0, 0.0, 1.0};
    EXPECT_FALSE(SolveAnalyticCell(c.cell, onAxis, infinity, &r));
  }
}

}  // namespace
}  // namespace invmap::kernels
