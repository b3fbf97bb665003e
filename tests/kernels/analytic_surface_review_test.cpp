// Adversarial cases for the closed-form minima of kernels/analytic_surface.h,
// each against an independent reference (a dense grid over the box, refined
// around its best sample): boxes far from [0, 2 pi) or wider than a turn,
// boxes a rounding wide, horn tori, sphere boxes at the poles or past them,
// surfaces a million away from the origin, points 1e8 away, non-finite
// points, and trimmed cells whose region holds the minimum inside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <array>
#include <vector>

#include "kernels/analytic_surface.h"
#include "kernels/own_parameter.h"
#include "kernels/trim_region.h"
#include "kernels/trimmed_cell.h"
#include "tests/kernels/analytic_reference.h"

namespace invmap::kernels {
namespace {

using Kind = AnalyticSurface::Kind;
constexpr double kInf = std::numeric_limits<double>::infinity();
using reference::AddSquare;
using reference::SampledMinimum2;

/// A cell of `s` over [lo, hi] with linear reference coordinates.
AnalyticCell CellOver(const AnalyticSurface& s, const double* lo, const double* hi) {
  AnalyticCell cell;
  cell.surface = &s;
  for (int d = 0; d < 2; ++d) {
    cell.paramLo[d] = lo[d];
    cell.paramScale[d] = hi[d] - lo[d];
  }
  return cell;
}

/// The point at local coordinates `local` in `s`'s frame.
void FromLocal(const AnalyticSurface& s, const double* local, double* p) {
  for (int k = 0; k < 3; ++k) p[k] = s.origin[k] + local[0] * s.x[k] + local[1] * s.y[k] + local[2] * s.z[k];
}

/// The closed form's answer is a point of the box on the surface at its
/// reported parameters, at its reported distance, and no farther than the
/// grid's minimum (`tolerance` absolute, for the coordinates' rounding).
void ExpectGlobal(const AnalyticCell& cell, const double* p, double tolerance, const char* what) {
  const AnalyticSurface& s = *cell.surface;
  CellSolveResult r;
  ASSERT_TRUE(SolveAnalyticCell(cell, p, kInf, &r)) << what;
  ASSERT_NE(r.status, PointStatus::Farther) << what;
  double own[2];
  for (int d = 0; d < 2; ++d) {
    ASSERT_GE(r.ref[d], 0.0) << what;
    ASSERT_LE(r.ref[d], 1.0) << what;
    own[d] = OwnParameter(cell.paramLo[d], cell.paramScale[d], cell.angular[d], r.ref[d]);
  }
  double at[3];
  s.Evaluate(own[0], own[1], at);
  EXPECT_LE(std::hypot(at[0] - r.closest[0], at[1] - r.closest[1], at[2] - r.closest[2]), tolerance) << what;
  EXPECT_NEAR(r.distance, std::hypot(p[0] - r.closest[0], p[1] - r.closest[1], p[2] - r.closest[2]), tolerance)
      << what;
  const double lo[2] = {cell.paramLo[0], cell.paramLo[1]};
  const double hi[2] = {cell.paramLo[0] + cell.paramScale[0], cell.paramLo[1] + cell.paramScale[1]};
  const double sampled = std::sqrt(SampledMinimum2(s, lo, hi, p));
  EXPECT_LE(r.distance, sampled + tolerance) << what << ": closed form " << r.distance << ", sampled " << sampled;
}

/// A few surfaces of every kind (standard frame, left-handed frame).
std::vector<AnalyticSurface> Surfaces(const double* origin) {
  std::vector<AnalyticSurface> out;
  for (int kind = 0; kind < 5; ++kind) {
    for (const double hand : {1.0, -1.0}) {
      AnalyticSurface s;
      s.kind = static_cast<Kind>(kind);
      std::copy(origin, origin + 3, s.origin);
      const double c = std::sqrt(0.5);
      const double x[3] = {c, c, 0}, y[3] = {-c * hand, c * hand, 0}, z[3] = {0, 0, 1};
      std::copy(x, x + 3, s.x);
      std::copy(y, y + 3, s.y);
      std::copy(z, z + 3, s.z);
      s.radius = 1.0;
      s.minorRadius = hand > 0 ? 0.4 : 1.0;  // ring, horn
      const double angle = hand > 0 ? 0.6 : -0.9;
      s.sinAngle = std::sin(angle);
      s.cosAngle = std::cos(angle);
      out.push_back(s);
    }
  }
  return out;
}

/// Query points in the surface's frame: on the axis, at the origin, on the
/// (torus's) centre circle, just off it, near the surface, far away.
std::vector<std::array<double, 3>> Points() {
  return {{0, 0, 0.3},  {0, 0, 0},      {1, 0, 0},         {-1, 1e-13, 0}, {1 + 1e-9, 0, 1e-9},
          {0.3, -2, 1}, {1e-14, 0, 0.8}, {-0.7, -0.7, -2}, {1e8, 3e7, -2e8}, {0, -1e8, 1}};
}

/// Boxes far from [0, 2 pi), wider than a turn, a rounding wide.
std::vector<std::array<double, 4>> AngularBoxes() {
  return {{7.5, 9.0, -0.7, 0.2},       {13.0, 13.0 + 4 * M_PI, 0.1, 1.3}, {-20.0, -19.0, -1.5, -1.0},
          {-1e3, -1e3 + 7, -1.2, 1.2}, {3.0, 3.0 + 1e-12, 0.5, 0.5 + 1e-12}, {-0.1, 0.1, -1.5707963267948966, -1.5},
          {2 * M_PI, 4 * M_PI, 1.0, 1.5707963267948966}};
}

TEST(AnalyticSurfaceReview, BoxesOffTheCircleWiderThanATurnOrARoundingWide) {
  const double origin[3] = {0.5, -0.25, 2.0};
  int checked = 0;
  for (const AnalyticSurface& s : Surfaces(origin)) {
    for (const auto& b : AngularBoxes()) {
      double lo[2] = {b[0], b[2]}, hi[2] = {b[1], b[3]};
      if (s.kind == Kind::Torus) {  // the minor angle off its first turn too
        lo[1] += 6.0;
        hi[1] += 6.0;
      }
      const AnalyticCell cell = CellOver(s, lo, hi);
      if (!ClosedFormCovers(cell)) continue;
      for (const auto& local : Points()) {
        double p[3];
        FromLocal(s, local.data(), p);
        const double scale = std::max(1.0, std::hypot(local[0], local[1], local[2]));
        ExpectGlobal(cell, p, 1e-11 * scale, "off-circle box");
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(AnalyticSurfaceReview, AMillionFromTheOrigin) {
  const double origin[3] = {1e6, -1e6, 1e6};
  for (const AnalyticSurface& s : Surfaces(origin)) {
    for (const auto& b : AngularBoxes()) {
      const double lo[2] = {b[0], b[2]}, hi[2] = {b[1], b[3]};
      const AnalyticCell cell = CellOver(s, lo, hi);
      if (!ClosedFormCovers(cell)) continue;
      for (const auto& local : Points()) {
        if (std::abs(local[0]) > 10.0 || std::abs(local[1]) > 10.0) continue;
        double p[3];
        FromLocal(s, local.data(), p);
        // The coordinates' rounding at 1e6: a few 1e-10.
        ExpectGlobal(cell, p, 1e-8, "offset surface");
      }
    }
  }
}

TEST(AnalyticSurfaceReview, HornTorusDeclinesOnlyWhereItsBoxReachesTheAxis) {
  AnalyticSurface s;
  s.kind = Kind::Torus;
  s.radius = s.minorRadius = 1.0;
  const double lo[2] = {0.0, 3.0}, hi[2] = {1.0, 3.2};  // holds v = pi: the horn
  EXPECT_FALSE(ClosedFormCovers(CellOver(s, lo, hi)));
  const double p[3] = {0.1, 0.0, 0.05};
  CellSolveResult r;
  EXPECT_FALSE(SolveAnalyticCell(CellOver(s, lo, hi), p, kInf, &r));
  const double lo2[2] = {0.0, 2.0}, hi2[2] = {1.0, 3.0};
  ASSERT_TRUE(ClosedFormCovers(CellOver(s, lo2, hi2)));
  ExpectGlobal(CellOver(s, lo2, hi2), p, 1e-12, "horn torus");
}

TEST(AnalyticSurfaceReview, ConeBoxesAcrossOrBeyondTheApex) {
  for (const double angle : {0.5, -0.5, 1.4, -1.4}) {
    AnalyticSurface s;
    s.kind = Kind::Cone;
    s.radius = 1.0;
    s.sinAngle = std::sin(angle);
    s.cosAngle = std::cos(angle);
    const double apex = -s.radius / s.sinAngle;
    // Across the apex: declined, by ClosedFormCovers and by the solve.
    const double lo[2] = {0.0, apex - 0.5}, hi[2] = {2.0, apex + 0.5};
    EXPECT_FALSE(ClosedFormCovers(CellOver(s, lo, hi)));
    // Wholly beyond it (the parallels' radius negative) and just short of it.
    for (const double side : {1.0, -1.0}) {
      const double a = apex + side * 1e-6, b = apex + side * 1.5;
      const double blo[2] = {-2.0, std::min(a, b)}, bhi[2] = {5.0, std::max(a, b)};
      const AnalyticCell cell = CellOver(s, blo, bhi);
      ASSERT_TRUE(ClosedFormCovers(cell));
      for (const auto& local : Points()) {
        double p[3];
        FromLocal(s, local.data(), p);
        p[2] += apex * s.cosAngle;  // about the apex
        ExpectGlobal(cell, p, 1e-11 * std::max(1.0, std::hypot(p[0], p[1], p[2])), "cone about its apex");
      }
    }
  }
}

TEST(AnalyticSurfaceReview, SphereBoxPastAPoleIsDeclinedNotAnsweredWrong) {
  AnalyticSurface s;
  s.kind = Kind::Sphere;
  s.radius = 1.0;
  // Latitudes past pi / 2: cos v < 0 there, where the nearest azimuth is
  // the opposite one; the closed form must leave such a box to the search.
  const double lo[2] = {0.0, 0.0}, hi[2] = {0.5, 3.0};
  const AnalyticCell cell = CellOver(s, lo, hi);
  EXPECT_FALSE(ClosedFormCovers(cell));
  const double p[3] = {-2.0, -0.3, 0.5};
  CellSolveResult r;
  EXPECT_FALSE(SolveAnalyticCell(cell, p, kInf, &r));
  // Within the latitudes the same point is answered, and right.
  const double within[2] = {0.5, 0.5 * M_PI};
  ExpectGlobal(CellOver(s, lo, within), p, 1e-12, "sphere up to its pole");
}

TEST(AnalyticSurfaceReview, NonFinitePointsAreLeftToTheSearch) {
  AnalyticSurface s;
  s.kind = Kind::Sphere;
  s.radius = 1.0;
  const double lo[2] = {0.0, -1.0}, hi[2] = {1.0, 1.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& p : std::vector<std::array<double, 3>>{{nan, 0, 0}, {0, kInf, 0}, {0, 0, -kInf}}) {
    CellSolveResult r;
    EXPECT_FALSE(SolveAnalyticCell(CellOver(s, lo, hi), p.data(), kInf, &r));
  }
}

/// `region`'s trimmed cell over the box [lo, hi] (linear reference coordinates).
void TrimOver(const TrimRegion& region, const double* lo, const double* hi, TrimmedCell* trim) {
  trim->region = &region;
  for (int d = 0; d < 2; ++d) {
    trim->paramLo[d] = lo[d];
    trim->paramScale[d] = hi[d] - lo[d];
  }
  trim->near = region.PiecesFor(lo, hi);
}

// A trimmed cell whose region's nearest point to the query lies inside the
// region (not on its boundary) must answer it: the grid over the region
// finds it, the cell must match it. Anywhere else its answer, if any, is a
// point of the region, never nearer than the region's minimum.
TEST(AnalyticSurfaceReview, TrimmedCellsFindTheRegionsInteriorMinimum) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double origin[3] = {0.0, 0.0, 0.0};
  int interior = 0;
  for (const AnalyticSurface& s : Surfaces(origin)) {
    for (int trial = 0; trial < 12; ++trial) {
      double lo[2] = {-7.0 + 3.0 * unit(rng), -1.2 + 0.4 * unit(rng)};
      double hi[2] = {lo[0] + 0.5 + 6.0 * unit(rng), lo[1] + 0.3 + 1.4 * unit(rng)};
      if (s.kind == Kind::Sphere) hi[1] = std::min(hi[1], 0.5 * M_PI);
      if (s.kind == Kind::Torus) {
        lo[1] += 4.0 * unit(rng);
        hi[1] = std::min(hi[1] + 4.0 * unit(rng), lo[1] + 2.5);
      }
      AnalyticCell cell = CellOver(s, lo, hi);
      if (!ClosedFormCovers(cell)) continue;
      TrimRegion region;
      const double c[2] = {lo[0] + (hi[0] - lo[0]) * unit(rng), lo[1] + (hi[1] - lo[1]) * unit(rng)};
      const double h = 0.15 * std::min(hi[0] - lo[0], hi[1] - lo[1]);
      AddSquare(c, h, &region);
      TrimmedCell trim;
      TrimOver(region, lo, hi, &trim);
      cell.trim = &trim;
      const double rlo[2] = {std::max(lo[0], c[0] - h), std::max(lo[1], c[1] - h)};
      const double rhi[2] = {std::min(hi[0], c[0] + h), std::min(hi[1], c[1] + h)};
      for (int q = 0; q < 6; ++q) {
        // A point off the surface at a parameter of the square (its minimum
        // inside the square then, usually), or anywhere.
        double p[3];
        const double u = rlo[0] + (rhi[0] - rlo[0]) * (0.2 + 0.6 * unit(rng));
        const double v = rlo[1] + (rhi[1] - rlo[1]) * (0.2 + 0.6 * unit(rng));
        s.Evaluate(u, v, p);
        for (int k = 0; k < 3; ++k) p[k] += (q < 4 ? 0.3 : 3.0) * (unit(rng) - 0.5);
        double at[2];
        const double sampled = std::sqrt(SampledMinimum2(s, rlo, rhi, p, at));
        CellSolveResult r;
        if (!SolveAnalyticCell(cell, p, kInf, &r)) continue;  // left to the search: fine
        const double margin = 1e-6 * std::max(rhi[0] - rlo[0], rhi[1] - rlo[1]);
        const bool inside = at[0] > rlo[0] + margin && at[0] < rhi[0] - margin && at[1] > rlo[1] + margin &&
                            at[1] < rhi[1] - margin;
        if (r.status != PointStatus::Farther) {
          EXPECT_GE(r.distance, sampled - 1e-9) << "kind " << static_cast<int>(s.kind) << " trial " << trial << " point " << q;
        }
        if (inside) {
          ++interior;
          ASSERT_NE(r.status, PointStatus::Farther)
              << "kind " << static_cast<int>(s.kind) << " trial " << trial << " point " << q;
          EXPECT_NEAR(r.distance, sampled, 1e-9)
              << "kind " << static_cast<int>(s.kind) << " trial " << trial << " point " << q;
        }
      }
    }
  }
  EXPECT_GT(interior, 50);
}

// A box wider than a turn holds an angle twice; the region may hold the
// second turn only. The cylinder of radius 1 about z over u in [0, 2 pi +
// 2]; the region a square about u = 2 pi + 0.5; the point 2 from the axis
// at azimuth 0.5: its foot (turn 0.5) is outside the region, the same
// point of the surface at turn 2 pi + 0.5 inside it.
TEST(AnalyticSurfaceReview, TrimmedBoxWiderThanATurnFindsTheSecondTurn) {
  AnalyticSurface s;
  s.kind = Kind::Cylinder;
  s.radius = 1.0;
  const double lo[2] = {0.0, -1.0}, hi[2] = {2.0 * M_PI + 2.0, 1.0};
  for (const double height : {0.0, 3.0}) {  // the foot inside the box, then clamped onto v = 1
    TrimRegion region;
    const double centre[2] = {2.0 * M_PI + 0.5, height == 0.0 ? 0.0 : 0.9};
    AddSquare(centre, 0.2, &region);
    TrimmedCell trim;
    TrimOver(region, lo, hi, &trim);
    AnalyticCell cell = CellOver(s, lo, hi);
    cell.trim = &trim;
    const double p[3] = {2.0 * std::cos(0.5), 2.0 * std::sin(0.5), height};
    CellSolveResult r;
    ASSERT_TRUE(SolveAnalyticCell(cell, p, kInf, &r));
    ASSERT_NE(r.status, PointStatus::Farther) << "height " << height;
    EXPECT_NEAR(r.distance, height == 0.0 ? 1.0 : std::sqrt(5.0), 1e-14);
    EXPECT_NEAR(OwnParameter(lo[0], hi[0] - lo[0], false, r.ref[0]), 2.0 * M_PI + 0.5, 1e-14);
  }
}

}  // namespace
}  // namespace invmap::kernels
