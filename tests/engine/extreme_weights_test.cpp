// Rational patches whose weights lie many orders of magnitude apart. A heavy
// weight makes the curve or surface cross a whole control leg within a
// parameter interval as short as 1 / weight, next to its edge: the
// branch and bound must resolve that scale, its rounding grows with the
// weights, and the local solve must step by 1e-16 in a parameter. The
// reference is this file's own: the map evaluated in long double from the
// Bernstein basis, sampled on parameters both log-spaced toward the edges and
// uniform, then polished by a pattern search. Its answer is a point of the
// patch, so invmap may never be farther than it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::testing {
namespace {

using Real = long double;

/// Cubic Bernstein basis at t.
std::array<Real, 4> Cubic(Real t) {
  const Real s = 1 - t;
  return {s * s * s, 3 * t * s * s, 3 * t * t * s, t * t * t};
}

/// A rational cubic Bezier curve (2D) or bicubic patch (3D) given by its
/// control points and weights, u fastest (docs/formats.md order).
struct RationalPatch {
  int paramDim = 1;
  int dim = 2;
  std::vector<std::array<Real, 3>> points;
  std::vector<Real> weights;

  std::array<Real, 3> Evaluate(Real u, Real v) const {
    const std::array<Real, 4> bu = Cubic(u);
    const std::array<Real, 4> bv = paramDim > 1 ? Cubic(v) : std::array<Real, 4>{1, 0, 0, 0};
    std::array<Real, 3> x{0, 0, 0};
    Real w = 0;
    for (int j = 0; j < (paramDim > 1 ? 4 : 1); ++j) {
      for (int i = 0; i < 4; ++i) {
        const int c = i + 4 * j;
        const Real b = bu[i] * bv[j] * weights[c];
        w += b;
        for (int k = 0; k < 3; ++k) x[k] += b * points[c][k];
      }
    }
    for (Real& xk : x) xk /= w;
    return x;
  }
  Real Distance(const double* q, Real u, Real v) const {
    const std::array<Real, 3> x = Evaluate(u, v);
    Real d2 = 0;
    for (int k = 0; k < dim; ++k) d2 += (x[k] - q[k]) * (x[k] - q[k]);
    return std::sqrt(d2);
  }
  Geometry ToGeometry() const {
    Patch patch;
    patch.kind = Patch::Kind::Bezier;
    patch.cell = paramDim == 1 ? CellType::Line : CellType::Quad;
    patch.degrees = paramDim == 1 ? std::vector<int>{3} : std::vector<int>{3, 3};
    for (const auto& p : points) {
      for (int k = 0; k < dim; ++k) patch.points.push_back(static_cast<double>(p[k]));
    }
    for (Real w : weights) patch.weights.push_back(static_cast<double>(w));
    Geometry g;
    g.dimension = dim;
    g.patches.push_back(patch);
    return g;
  }
};

/// Parameters dense where a heavy weight next to an edge acts: log-spaced
/// from 10^-`decades` toward 0 and from 1e-16 toward 1 (what a double
/// parameter resolves there), plus a uniform grid.
std::vector<Real> SampleParameters(int decades, int logCount, int uniformCount) {
  std::vector<Real> t;
  for (int i = 0; i < logCount; ++i) {
    const Real fraction = Real(i) / (logCount - 1);
    t.push_back(std::pow(Real(10), -decades * (1 - fraction)));
    t.push_back(1 - std::pow(Real(10), -16 * (1 - fraction)));
  }
  for (int i = 0; i <= uniformCount; ++i) t.push_back(Real(i) / uniformCount);
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

/// How finely double parameters resolve the patch at `at`: the sum over
/// parameters of |dx/dt| (a central difference) times the spacing of
/// doubles at t. Next to t = 1 a heavy weight's patch can move 1e12 times
/// its size per unit of t, and 1.1e-16 of t there is 1e-4 of the patch: the
/// parameters reported there (in the cell's own coordinates) say no more.
double Resolution(const RationalPatch& patch, const Real* at) {
  double resolution = 0;
  for (int d = 0; d < patch.paramDim; ++d) {
    const double t = static_cast<double>(at[d]);
    const Real spacing = std::nextafter(std::min(t, 0.5) + (t > 0.5 ? t - 0.5 : 0.0), 2.0) - t;
    Real lo[2] = {at[0], at[1]}, hi[2] = {at[0], at[1]};
    const Real h = std::max(spacing, Real(1e-30));
    lo[d] = std::max(Real(0), at[d] - h);
    hi[d] = std::min(Real(1), at[d] + h);
    const std::array<Real, 3> a = patch.Evaluate(lo[0], lo[1]), b = patch.Evaluate(hi[0], hi[1]);
    Real change2 = 0;
    for (int k = 0; k < patch.dim; ++k) change2 += (b[k] - a[k]) * (b[k] - a[k]);
    resolution += static_cast<double>(std::sqrt(change2) / (hi[d] - lo[d]) * spacing);
  }
  return resolution;
}

/// The sampled parameters' nearest to `q`, polished by a pattern search
/// whose steps start at the local sample spacing: the distance of a point of
/// the patch, at least the true minimum.
Real ReferenceDistance(const RationalPatch& patch, const std::vector<Real>& samples, const double* q) {
  const int n = static_cast<int>(samples.size());
  int bestI = 0, bestJ = 0;
  Real best = patch.Distance(q, samples[0], 0);
  for (int j = 0; j < (patch.paramDim > 1 ? n : 1); ++j) {
    for (int i = 0; i < n; ++i) {
      const Real d = patch.Distance(q, samples[i], patch.paramDim > 1 ? samples[j] : 0);
      if (d < best) {
        best = d;
        bestI = i;
        bestJ = j;
      }
    }
  }
  Real at[2] = {samples[bestI], patch.paramDim > 1 ? samples[bestJ] : 0};
  const auto spacing = [&](int i) {
    return std::max(samples[std::min(i + 1, n - 1)] - samples[i], samples[i] - samples[std::max(i - 1, 0)]);
  };
  Real step[2] = {spacing(bestI), spacing(bestJ)};
  for (int round = 0; round < 4000 && std::max(step[0], step[1]) > 0; ++round) {
    bool moved = false;
    for (int d = 0; d < patch.paramDim; ++d) {
      for (const Real sign : {Real(1), Real(-1)}) {
        Real trial[2] = {at[0], at[1]};
        trial[d] = std::clamp(trial[d] + sign * step[d], Real(0), Real(1));
        const Real dt = patch.Distance(q, trial[0], trial[1]);
        if (dt < best) {
          best = dt;
          at[0] = trial[0];
          at[1] = trial[1];
          moved = true;
        }
      }
    }
    if (!moved) {
      step[0] *= 0.5L;
      step[1] *= 0.5L;
      if (std::max(step[0], step[1]) < 1e-300L) break;
    }
  }
  return best;
}

/// Points around the patch: near its control legs (where the heavy weight
/// draws it) and anywhere in its control box.
std::vector<double> QueriesAround(const RationalPatch& patch, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int m = static_cast<int>(patch.points.size());
  std::vector<double> q;
  for (int i = 0; i < count; ++i) {
    const auto& a = patch.points[rng() % m];
    const auto& b = patch.points[rng() % m];
    const double s = unit(rng);
    for (int k = 0; k < patch.dim; ++k) {
      const double onLeg = static_cast<double>((1 - s) * a[k] + s * b[k]);
      q.push_back(onLeg + (i % 3 == 0 ? 0.3 : 0.03) * normal(rng));
    }
  }
  return q;
}

/// Inverts `q` on `patch` and checks every answer against the reference:
/// never farther than it (beyond 1e-9 of the patch's size), and the point
/// reported is the patch's point at the reported parameters (as far as
/// those resolve it).
void CheckAgainstReference(const RationalPatch& patch, const std::vector<double>& q, const std::string& name) {
  const BuildResult built = Manifold::Build(patch.ToGeometry());
  ASSERT_TRUE(built.error.empty()) << built.error;
  const std::size_t n = q.size() / patch.dim;
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(q.data(), n, patch.dim), {}, &results), Error::Ok);
  Real lo[3] = {1e300L, 1e300L, 1e300L}, hi[3] = {-1e300L, -1e300L, -1e300L};
  for (const auto& p : patch.points) {
    for (int k = 0; k < patch.dim; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  Real size2 = 0;
  for (int k = 0; k < patch.dim; ++k) size2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  const double tolerance = 1e-9 * static_cast<double>(std::sqrt(size2));
  const std::vector<Real> samples =
      patch.paramDim > 1 ? SampleParameters(20, 60, 100) : SampleParameters(300, 3000, 4000);
  int failures = 0;
  for (std::size_t i = 0; i < n && failures < 10; ++i) {
    const double* point = q.data() + i * patch.dim;
    ASSERT_EQ(results.status[i], Status::Found) << name << " point " << i;
    const double best = static_cast<double>(ReferenceDistance(patch, samples, point));
    const double u = results.params[3 * i], v = patch.paramDim > 1 ? results.params[3 * i + 1] : 0.0;
    const Real reported[2] = {u, v};
    const double atParams = static_cast<double>(patch.Distance(point, u, v));
    const double atParamsTolerance = tolerance + Resolution(patch, reported);
    std::string where = name + " point " + std::to_string(i) + " (" + std::to_string(point[0]) + ", " +
                        std::to_string(point[1]) + (patch.dim > 2 ? ", " + std::to_string(point[2]) : "") + ")";
    EXPECT_LE(results.distance[i], best + tolerance)
        << where << ": a local minimum (u " << u << ", v " << v << ")";
    EXPECT_NEAR(results.distance[i], atParams, atParamsTolerance) << where << ": distance not the patch's at its parameters";
    if (results.distance[i] > best + tolerance ||
        std::abs(results.distance[i] - atParams) > atParamsTolerance) {
      ++failures;
    }
  }
}

/// A cubic like the QA report's whose second control point weighs `heavy`
/// times the others, as a Bezier cell. All weights are scaled by
/// 1 / sqrt(heavy) (the same curve): the ratio 1e100 then stays within the
/// weights invmap accepts, [1e-50, 1e50].
RationalPatch CurveWithHeavyWeight(Real heavy) {
  RationalPatch c;
  c.paramDim = 1;
  c.dim = 2;
  c.points = {{0, 0, 0}, {1, 2, 0}, {2, -1, 0}, {3, 2, 0}};
  const Real light = 1 / std::sqrt(heavy);
  c.weights = {light, heavy * light, light, light};
  return c;
}

TEST(ExtremeWeightsTest, CurveCrossingALegInATinyParameterInterval) {
  for (const Real heavy : {1e3L, 1e8L, 1e12L, 1e15L, 1e20L, 1e100L}) {
    const RationalPatch curve = CurveWithHeavyWeight(heavy);
    std::vector<double> q = QueriesAround(curve, 150, 91);
    // On the leg (0,0)-(1,2), which the curve covers for t below ~1 / heavy.
    for (const double s : {0.05, 0.25, 0.5, 0.9}) {
      q.push_back(s);
      q.push_back(2 * s + 0.01);
    }
    CheckAgainstReference(curve, q, "curve, weight " + std::to_string(static_cast<double>(heavy)));
  }
}

/// A bicubic patch over [0, 3]^2 with a bump, and `weights` set at
/// control points (index i + 4 j) with the others 1.
RationalPatch SurfaceWithWeights(const std::vector<std::pair<int, Real>>& weights) {
  RationalPatch surface;
  surface.paramDim = 2;
  surface.dim = 3;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      surface.points.push_back({Real(i), Real(j), 0.3L * std::sin(Real(i + 2 * j))});
      surface.weights.push_back(1);
    }
  }
  surface.points[1 + 4 * 1][2] = 2;
  for (const auto& [index, weight] : weights) surface.weights[index] = weight;
  return surface;
}

TEST(ExtremeWeightsTest, SurfaceWithOneHeavyInnerWeight) {
  // The heavy weight's reach ends along u v ~ 1 / weight near two edges.
  for (const Real heavy : {1e3L, 1e8L, 1e10L, 1e12L, 1e15L}) {
    CheckAgainstReference(SurfaceWithWeights({{5, heavy}}), QueriesAround(SurfaceWithWeights({{5, heavy}}), 80, 92),
                          "surface, weight " + std::to_string(static_cast<double>(heavy)));
  }
}

TEST(ExtremeWeightsTest, SurfaceWithSeveralHeavyOrTinyWeights) {
  const std::vector<std::pair<int, Real>> cases[] = {
      {{0, 1e10L}, {6, 1e10L}, {13, 1e10L}},  // a corner, an inner and an edge control point
      {{3, 1e12L}, {9, 1e12L}, {10, 1e12L}},
      {{6, 1e-12L}, {9, 1e-12L}},  // tiny ones: the rest of the patch is heavy
      {{0, 1e-10L}, {15, 1e8L}},
  };
  int k = 0;
  for (const auto& weights : cases) {
    const RationalPatch surface = SurfaceWithWeights(weights);
    CheckAgainstReference(surface, QueriesAround(surface, 80, 93 + k), "surface, weights case " + std::to_string(k));
    ++k;
  }
}

}  // namespace
}  // namespace invmap::testing
