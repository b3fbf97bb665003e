// What the partition-of-unity tests share: a manifold built over a triangle
// mesh through the public API, and the check of answers against the
// independent reference of tests/support/pou_reference.h.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/support/pou_meshes.h"
#include "tests/support/pou_reference.h"

namespace invmap::testing {

struct BuiltPou {
  Patch patch;
  BuildResult built;
  PouCharts charts;
};

/// The pou_manifold patch over `m` with `base`, its manifold and charts.
inline void BuildPou(const TriangleMesh& m, PouBase base, BuiltPou* out) {
  PouOptions options;
  options.base = base;
  ASSERT_EQ(BuildPouManifold(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), options,
                             &out->patch),
            "")
      << m.name;
  Geometry geometry;
  geometry.patches.push_back(out->patch);
  out->built = Manifold::Build(geometry);
  ASSERT_EQ(out->built.error, "") << m.name;
  ASSERT_EQ(PouCharts::Create(out->patch, &out->charts), "") << m.name;
}

/// Appends `p` moved by `distance` in a direction drawn uniformly from the
/// cube [-1, 1]^3 by `unit` (normalised).
template <typename Rng, typename Distribution>
void PushMovedPoint(const double p[3], double distance, Rng& random, Distribution& unit, std::vector<double>* points) {
  double d[3] = {unit(random), unit(random), unit(random)};
  const double length = std::hypot(d[0], d[1], d[2]);
  for (int c = 0; c < 3; ++c) points->push_back(p[c] + distance * d[c] / length);
}

/// Each answer in `results` for the interleaved 3D `points` is the
/// reference's global minimum: found, never farther beyond 1e-9 of `size`,
/// within 1e-7 of it, and the reported chart and coordinates evaluate (by
/// the reference) to the reported point.
inline void ExpectTheReferenceMinima(const PouReference& reference, const std::vector<double>& points,
                                     const Results& results, double size, const std::string& name) {
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    const std::string where = name + " point " + std::to_string(i);
    std::int64_t chart;
    std::complex<double> at;
    const double expected = reference.Closest(&points[3 * i], &chart, &at);
    ASSERT_EQ(results.status[i], Status::Found) << where;
    EXPECT_LE(results.distance[i], expected + 1e-9 * size) << where;
    EXPECT_NEAR(results.distance[i], expected, 1e-7 * size) << where;
    double exact[3];
    reference.Evaluate(results.cell[i], {results.params[3 * i], results.params[3 * i + 1]}, exact);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(exact[c], results.closest[3 * i + c], 1e-12 * size) << where;
  }
}

}  // namespace invmap::testing
