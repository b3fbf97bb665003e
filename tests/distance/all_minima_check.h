// The check of an all-minima list between two one-patch B-spline
// geometries against the lattice reference of tests/support/pair_reference.h:
// none missed, none listed twice, the nearest answer first, and every listed
// minimum the lattice did not resolve a minimum by a ring test of the
// tests' own Cox-de Boor evaluation.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "tests/distance/distance_test_util.h"
#include "tests/support/bspline_reference.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {

/// The point of a one-patch B-spline geometry (3D, rational or not) at
/// patch parameters `params`
/// (clamped into the domain), by Cox-de Boor on the span holding them.
inline void SplinePoint(const Geometry& g, const PoseRows& pose, const double* params, double* out) {
  const Patch& p = g.patches[0];
  const int dims = static_cast<int>(p.degrees.size());
  std::vector<double> basis[2];
  for (int d = 0; d < dims; ++d) {
    const std::vector<double>& knots = p.knots[d];
    const int degree = p.degrees[d], count = p.counts[d];
    const double t = std::clamp(params[d], knots[degree], knots[count]);
    int span = degree;
    while (span + 1 < count && knots[span + 1] <= t) ++span;
    basis[d] = CoxDeBoorBasis(knots, degree, span, t);
  }
  double x[3] = {0, 0, 0}, weight = 0.0;
  const int nu = p.counts[0], nv = dims > 1 ? p.counts[1] : 1;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const std::size_t c = static_cast<std::size_t>(j * nu + i);
      const double w = basis[0][i] * (dims > 1 ? basis[1][j] : 1.0) * (p.weights.empty() ? 1.0 : p.weights[c]);
      weight += w;
      for (int k = 0; k < 3; ++k) x[k] += w * p.points[c * 3 + k];
    }
  }
  for (double& v : x) v /= weight;
  ApplyRows(pose, x, out);
}

/// True when no pair of points whose patch parameters lie on rings of
/// radius 1e-2 down to 1e-5 around the answer's (projected into the
/// domains) is nearer than the answer by more than `tolerance`.
inline bool RingSaysMinimum(const Geometry& a, const PoseRows& poseA, const Geometry& b, const PoseRows& poseB,
                     const DistanceAnswer& m, double tolerance) {
  const int pa = static_cast<int>(a.patches[0].degrees.size()), pb = static_cast<int>(b.patches[0].degrees.size());
  auto distance = [&](const double* ua, const double* ub) {
    double x[3], y[3];
    SplinePoint(a, poseA, ua, x);
    SplinePoint(b, poseB, ub, y);
    return PointDistance(x, y);
  };
  const double d0 = distance(m.a.params, m.b.params);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const double radius : {1e-2, 1e-3, 1e-4, 1e-5}) {
    for (int trial = 0; trial < 200; ++trial) {
      double v[4], length2 = 0.0;
      for (int i = 0; i < pa + pb; ++i) {
        v[i] = normal(rng);
        length2 += v[i] * v[i];
      }
      double ua[3], ub[3];
      for (int i = 0; i < pa; ++i) ua[i] = std::clamp(m.a.params[i] + radius * v[i] / std::sqrt(length2), 0.0, 1.0);
      for (int i = 0; i < pb; ++i) ub[i] = std::clamp(m.b.params[i] + radius * v[pa + i] / std::sqrt(length2), 0.0, 1.0);
      if (distance(ua, ub) < d0 - tolerance) return false;
    }
  }
  return true;
}

/// Runs allMinima and checks the list against the lattice reference:
/// complete whether certified or not, and certified when `mustCertify`
/// (some random curve and surface pairs run out of the enumeration's
/// budget: docs/limitations.md). `listed` (optional) receives the number
/// of minima listed.
inline void CheckAllMinima(const Geometry& a, const Geometry& b, const PoseRows& poseB, double maxDistance,
                    const std::string& name, bool mustCertify = true, std::size_t* listed = nullptr) {
  SCOPED_TRACE(name);
  const auto ma = BuildModel(a);
  const auto mb = BuildModel(b);
  const double size = GeometrySize(a) + GeometrySize(b);
  DistanceOptions options;
  options.allMinima = true;
  options.maxDistance = maxDistance;
  const DistanceResult r = DistanceQuery(*ma, IdentityRows(), *mb, poseB, options);
  if (listed) *listed = r.minima.size();
  const std::vector<PairReferenceAnswer> reference =
      BruteForcePairMinima(a, IdentityRows(), b, poseB, maxDistance, 1e-5 * size);
  if (reference.empty()) {
    EXPECT_TRUE(r.minima.empty());
    return;
  }
  ASSERT_FALSE(r.minima.empty());
  EXPECT_TRUE(r.nearest.certified);
  if (reference.front().distance <= 1e-9 * size) {
    // The models meet. Where they cross along a curve the points at
    // distance 0 are a continuum, which no list holds (docs/distance.md):
    // the first is a common point, and a list that claims to be complete
    // must still hold every minimum apart from the contact.
    EXPECT_EQ(r.nearest.distance, 0.0);
    EXPECT_EQ(r.minima.front().distance, 0.0);
    if (!r.minima.front().certified) return;
  }
  for (const DistanceAnswer& m : r.minima) EXPECT_EQ(m.certified, r.minima.front().certified);
  if (mustCertify) {
    EXPECT_TRUE(r.minima.front().certified);
  }
  // The nearest answer is the first minimum (both points), and the
  // reference's nearest minimum is no nearer.
  EXPECT_NEAR(r.minima.front().distance, r.nearest.distance, 1e-12 * size);
  EXPECT_LE(PointDistance(r.minima.front().a.point, r.nearest.a.point), 1e-7 * size);
  EXPECT_LE(PointDistance(r.minima.front().b.point, r.nearest.b.point), 1e-7 * size);
  EXPECT_LE(r.nearest.distance, reference.front().distance + 1e-9 * size);
  for (std::size_t i = 0; i < r.minima.size(); ++i) {
    ExpectConsistent(*ma, IdentityRows(), *mb, poseB, r.minima[i], 1e-9 * size);
    if (i > 0) {
      EXPECT_LE(r.minima[i - 1].distance, r.minima[i].distance);
    }
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(PointDistance(r.minima[i].a.point, r.minima[j].a.point) <= 1e-6 * size &&
                   PointDistance(r.minima[i].b.point, r.minima[j].b.point) <= 1e-6 * size)
          << "minima " << j << " and " << i << " are one";
    }
  }
  auto same = [&](const DistanceAnswer& f, const PairReferenceAnswer& ref) {
    return PointDistance(f.a.point, ref.a.point.data()) <= 1e-5 * size &&
           PointDistance(f.b.point, ref.b.point.data()) <= 1e-5 * size &&
           std::abs(f.distance - ref.distance) <= 1e-8 * size;
  };
  for (const PairReferenceAnswer& ref : reference) {
    bool matched = false;
    for (const DistanceAnswer& f : r.minima) matched = matched || same(f, ref);
    EXPECT_TRUE(matched) << "the reference's minimum " << ref.distance << " at params " << ref.a.ref[0] << " / "
                         << ref.b.ref[0] << " " << ref.b.ref[1] << " (cells " << ref.a.cell << ", " << ref.b.cell
                         << ") is missing";
  }
  // A listed minimum the lattice did not resolve (too shallow for it) must
  // still be one by the ring test.
  for (const DistanceAnswer& f : r.minima) {
    bool matched = false;
    for (const PairReferenceAnswer& ref : reference) matched = matched || same(f, ref);
    if (!matched) {
      EXPECT_TRUE(RingSaysMinimum(a, IdentityRows(), b, poseB, f, 1e-12 * size))
          << "listed minimum " << f.distance << " at params " << f.a.params[0] << " / " << f.b.params[0] << " "
          << f.b.params[1] << " is not a minimum";
    }
  }
}

}  // namespace invmap::testing
