// The public Manifold API end to end: determinism across thread counts, the
// gap tolerance, invalid query points, every PointsView layout and scalar
// type, 2D and empty and degenerate geometries, malformed geometries
// rejected at Build with a precise message, Info(), API misuse, and a
// 10-million-point batch whose peak memory stays near its input and output.
// Answers are checked against the independent reference of tests/support.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/patch_reference.h"
#include "tests/support/reference_cell.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Builds or fails the test.
Manifold BuildOk(const Geometry& g) {
  BuildResult built = Manifold::Build(g);
  EXPECT_TRUE(built.error.empty()) << built.error;
  EXPECT_TRUE(built.manifold.valid());
  return std::move(built.manifold);
}

/// A query set of every kind on the 3D mixed geometry (all patch kinds).
QuerySet MixedQueries(const std::vector<PatchCell>& cells, double size, int perKind, std::uint64_t seed) {
  QueryMix mix;
  mix.on = perKind;
  mix.near = perKind;
  mix.mid = perKind;
  mix.far = perKind;
  mix.inside = perKind;
  return MakeQueries(cells, 3, size, mix, seed);
}

// ---------------------------------------------------------------------------
// Determinism.

TEST(ManifoldTest, ThreadCountDoesNotChangeAnyBit) {
  const Geometry g = MixedGeometry3();
  const Manifold m = BuildOk(g);
  const QuerySet q = MixedQueries(GeometryCells(g), GeometrySize(g), 5000, 1101);
  // More threads than cores too (this machine may have 2): the same bits,
  // and no library warning on stderr.
  const int threads[] = {1, 2, 0, 3, 7, 64};
  constexpr int kRuns = static_cast<int>(std::size(threads));
  Results byThreads[kRuns];
  for (int i = 0; i < kRuns; ++i) {
    InversionOptions o;
    o.threads = threads[i];
    std::string error;
    ::testing::internal::CaptureStderr();
    byThreads[i] = InvertQueries(m, q, o, &error);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << "threads " << threads[i];
    ASSERT_TRUE(error.empty()) << error;
  }
  for (int i = 1; i < kRuns; ++i) {
    EXPECT_EQ(CompareBitwise(byThreads[0], byThreads[i]), "") << "threads 1 vs " << threads[i] << " (0: all cores)";
  }
  // Repeating a call on the same manifold is deterministic too.
  std::string error;
  const Results again = InvertQueries(m, q, {}, &error);
  EXPECT_EQ(CompareBitwise(byThreads[0], again), "") << "a repeated call";
}

/// Point i's answer of `r` as a bitwise-comparable record.
std::string AnswerBits(const Results& r, std::size_t i) {
  Results one;
  one.status = {r.status[i]};
  one.patch = {r.patch[i]};
  one.cell = {r.cell[i]};
  one.params.assign(r.params.begin() + 3 * i, r.params.begin() + 3 * i + 3);
  one.closest.assign(r.closest.begin() + 3 * i, r.closest.begin() + 3 * i + 3);
  one.distance = {r.distance[i]};
  one.iterations = {0};
  return DescribeResult(one, 0);
}

TEST(ManifoldTest, PointwiseAnswersAreTheSameInEveryBatch) {
  // With InversionOptions::pointwise a point's answer is a function of the
  // point and the geometry: the whole set at once, the set shuffled and cut
  // into batches of other sizes, and single points agree bit for bit.
  // (Without it, the last digits follow the neighbours the batch gives a
  // point to start from.)
  const std::pair<const char*, Geometry> geometries[] = {
      {"mixed 3D", MixedGeometry3()}, {"mixed 2D", MixedGeometry2()}, {"quadratic tets", QuadraticMesh(false)}};
  for (const auto& [name, g] : geometries) {
    SCOPED_TRACE(name);
    const Manifold m = BuildOk(g);
    ReferenceGeometry reference(g);
    QueryMix mix;
    mix.on = mix.near = mix.mid = mix.far = mix.inside = 600;
    const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, 1103);
    InversionOptions o;
    o.pointwise = true;
    // Correct, against the independent reference.
    RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); }, o);
    std::string error;
    const Results whole = InvertQueries(m, q, o, &error);
    ASSERT_TRUE(error.empty()) << error;
    std::vector<std::size_t> order(q.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), std::mt19937_64(1104));
    int differ = 0;
    for (std::size_t first = 0, size = 1; first < order.size(); first += size, size = size * 3 + 1) {
      QuerySet batch;
      batch.dim = q.dim;
      const std::size_t end = std::min(order.size(), first + size);
      for (std::size_t j = first; j < end; ++j) batch.Add(q.point(order[j]), q.kinds[order[j]]);
      const Results part = InvertQueries(m, batch, o, &error);
      ASSERT_TRUE(error.empty()) << error;
      for (std::size_t j = first; j < end; ++j) {
        const std::string alone = AnswerBits(part, j - first), together = AnswerBits(whole, order[j]);
        if (alone != together && differ++ < 5) ADD_FAILURE() << "point " << order[j] << ": " << alone << " vs " << together;
      }
    }
    EXPECT_EQ(differ, 0);
  }
}

TEST(ManifoldTest, ChunksOfTheMortonOrderChangeNoAnswer) {
  // More points than one chunk of Morton-ordered answers (65,536), a bucket
  // size that does not divide it, and invalid points among them: every
  // answer must land at its own index, whatever the thread count.
  const Geometry g = MixedGeometry3();
  const Manifold m = BuildOk(g);
  QuerySet q = MixedQueries(GeometryCells(g), GeometrySize(g), 28000, 1102);
  ASSERT_GT(q.size(), 2u * 65536u);
  const double bad[3] = {kNaN, 0.5, kInf};
  for (int i = 0; i < 5; ++i) q.Add(bad, "invalid");
  std::swap_ranges(q.points.end() - 15, q.points.end(), q.points.begin() + 3 * 70000);
  std::swap_ranges(q.kinds.end() - 5, q.kinds.end(), q.kinds.begin() + 70000);
  InversionOptions o;
  o.bucketSize = 7;
  Results byThreads[2];
  for (int i = 0; i < 2; ++i) {
    o.threads = i + 1;
    std::string error;
    byThreads[i] = InvertQueries(m, q, o, &error);
    ASSERT_TRUE(error.empty()) << error;
  }
  EXPECT_EQ(CompareBitwise(byThreads[0], byThreads[1]), "") << "threads 1 vs 2";
  // Every answer is its own point's: the closest point lies at the reported
  // distance from it (another point's answer would not).
  const double tol = 1e-9 * GeometrySize(g);
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (byThreads[0].status[i] != Status::Found) continue;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(byThreads[0].closest[3 * i + k] - q.point(i)[k], 2);
    ASSERT_NEAR(std::sqrt(d2), byThreads[0].distance[i], tol) << "point " << i;
  }
  // A sample against one-point batches (no chunks, no buckets to share).
  for (std::size_t i = 0; i < q.size(); i += 173) {
    QuerySet one;
    one.Add(q.point(i), q.kinds[i]);
    std::string error;
    const Results alone = InvertQueries(m, one, {}, &error);
    ASSERT_TRUE(error.empty()) << error;
    ASSERT_EQ(byThreads[0].status[i], alone.status[0]) << "point " << i;
    if (alone.status[0] == Status::Found) {
      EXPECT_NEAR(byThreads[0].distance[i], alone.distance[0], tol) << "point " << i;
    }
  }
  EXPECT_EQ(byThreads[0].status[70000], Status::Invalid);
}

/// A quadratic triangle (2D) or tet whose control point on the edge between
/// reference vertices (1, 0, ..) and (0, 1, ..) is pushed out to (0.7, 0.7):
/// the closest points of the queries around it lie on the curved face
/// s + t (+ r) = 1.
Geometry BulgedSimplex(int dim) {
  Geometry g;
  g.dimension = dim;
  Patch p;
  p.kind = Patch::Kind::Bezier;
  p.cell = dim == 2 ? CellType::Tri : CellType::Tet;
  p.degrees = {2};
  for (int a3 = 0; a3 <= (dim == 3 ? 2 : 0); ++a3)
    for (int a2 = 0; a2 + a3 <= 2; ++a2)
      for (int a1 = 0; a1 + a2 + a3 <= 2; ++a1) {
        const bool bulge = a1 == 1 && a2 == 1;
        p.points.insert(p.points.end(), {bulge ? 0.7 : a1 / 2.0, bulge ? 0.7 : a2 / 2.0});
        if (dim == 3) p.points.push_back(a3 / 2.0);
      }
  g.patches.push_back(std::move(p));
  return g;
}

TEST(ManifoldTest, BucketSizeNeverChangesCorrectness) {
  // Points of a bucket share one candidate list and warm-start each other;
  // every bucket size must still give the global minimum. The grids put
  // consecutive points near the curved face s + t (+ r) = 1.
  for (int dim : {2, 3}) {
    SCOPED_TRACE("dimension " + std::to_string(dim));
    const Geometry g = BulgedSimplex(dim);
    ReferenceGeometry reference(g);
    QuerySet q;
    q.dim = dim;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j)
        for (int k = 0; k <= (dim == 3 ? 4 : 0); ++k) {
          const double p[3] = {0.3 + 0.05 * i, 0.3 + 0.05 * j, 0.1 * k};
          q.Add(p, "grid");
        }
    for (int bucketSize : {1, 7, 32, 256}) {
      InversionOptions o;
      o.bucketSize = bucketSize;
      const std::string name = "bulged simplex, bucket size " + std::to_string(bucketSize);
      RunFamily(name.c_str(), g, q, [&](const double* p) { return reference.Closest(p); }, o);
    }
  }
}

// ---------------------------------------------------------------------------
// Gap tolerance.

TEST(ManifoldTest, GapToleranceSplitsFoundAndNone) {
  const Geometry g = WavySurfaces();
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 2000;
  mix.near = 8000;
  mix.mid = 8000;
  mix.far = 2000;
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, 1201);
  for (double fraction : {0.0, 0.01, 0.1}) {
    SCOPED_TRACE("maxDistance = " + std::to_string(fraction) + " x size");
    InversionOptions o;
    o.maxDistance = fraction * reference.size();
    // CheckResults requires None beyond maxDistance (patch/cell -1, NaN
    // fields), Found within it, and checks every Found against the reference.
    const CheckSummary s = RunFamily("gap tolerance", g, q, [&](const double* p) { return reference.Closest(p); }, o);
    if (fraction > 0) {
      EXPECT_GT(s.found, 0);
      EXPECT_LT(s.found, s.points);
    }
  }
}

TEST(ManifoldTest, GapToleranceZeroFindsEveryPointOnOrInsideTheGeometry) {
  // A point at distance <= D is found for every D >= 0, D = 0 included: the
  // points of surfaces (made by the tests' own evaluator, so a rounding off
  // them) and those inside curved volumes, a third of them 1e-8 to 1e-4 of
  // the cell from a face in parameters (QA: 14 of 100,000 inside points of
  // quadratic tets came back none at D = 0; solves near a face land an
  // ulp beyond 0).
  const std::pair<const char*, Geometry> geometries[] = {{"wavy surfaces", WavySurfaces()},
                                                         {"quadratic tets", QuadraticMesh(false)},
                                                         {"quadratic hexes", QuadraticMesh(true)},
                                                         {"B-spline volumes", BSplineVolumes()}};
  for (const auto& [name, g] : geometries) {
    SCOPED_TRACE(name);
    const Manifold m = BuildOk(g);
    const std::vector<PatchCell> cells = GeometryCells(g);
    const double size = GeometrySize(g);
    std::mt19937_64 rng(1202);
    QuerySet q;
    q.dim = g.dimension;
    std::vector<bool> fullRank;
    for (int i = 0; i < ScaledCount(6000); ++i) {
      const RefCell& cell = cells[rng() % cells.size()].cell;
      std::array<double, 3> u = RandomRefPoint(cell.type, rng);
      if (i % 3 == 0) {
        // Toward a point of the boundary: still inside (the domain is convex).
        std::array<double, 3> outward;
        const std::array<double, 3> face = RandomBoundaryRefPoint(cell.type, rng, &outward);
        const double t = std::pow(10.0, std::uniform_real_distribution<double>(-8.0, -4.0)(rng));
        for (int k = 0; k < 3; ++k) u[k] = face[k] + t * (u[k] - face[k]);
      }
      double x[3] = {0, 0, 0};
      RefEvaluate(cell, u.data(), x);
      q.Add(x, "on");
      fullRank.push_back(cell.paramDim() == g.dimension);
    }
    for (const double maxDistance : {0.0, 1e-15 * size}) {
      InversionOptions o;
      o.maxDistance = maxDistance;
      std::string error;
      const Results r = InvertQueries(m, q, o, &error);
      ASSERT_TRUE(error.empty()) << error;
      int missed = 0, inexact = 0;
      for (std::size_t i = 0; i < q.size(); ++i) {
        if (r.status[i] != Status::Found || !(r.distance[i] <= 1e-11 * size)) {
          ++missed;
          continue;
        }
        // Inside a volume: the point itself, at distance exactly 0.
        if (fullRank[i]) inexact += r.distance[i] != 0.0;
      }
      EXPECT_EQ(missed, 0) << "of " << q.size() << " points on the geometry, D = " << maxDistance;
      EXPECT_EQ(inexact, 0) << "inside points not at distance 0, D = " << maxDistance;
    }
  }
}

// ---------------------------------------------------------------------------
// Invalid query points.

TEST(ManifoldTest, NonFinitePointsAreInvalidAndDisturbNothing) {
  const Geometry g = WavySurfaces();
  const Manifold m = BuildOk(g);
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.near = 6000;
  mix.far = 2000;
  const QuerySet clean = MakeQueries(reference.cells(), 3, reference.size(), mix, 1301);
  // Every 5th point of the mixed set is broken in one coordinate.
  const double bad[4] = {kNaN, kInf, -kInf, -kNaN};
  QuerySet mixed;
  std::vector<std::size_t> cleanIndex;  // mixed index -> clean index, or npos
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (i % 4 == 0) {
      double p[3] = {clean.point(i)[0], clean.point(i)[1], clean.point(i)[2]};
      p[(i / 4) % 3] = bad[(i / 12) % 4];
      mixed.Add(p, "non-finite");
      cleanIndex.push_back(std::string::npos);
    }
    mixed.Add(clean.point(i), clean.kinds[i]);
    cleanIndex.push_back(i);
  }
  std::string error;
  const Results a = InvertQueries(m, clean, {}, &error);
  ASSERT_TRUE(error.empty()) << error;
  const Results b = InvertQueries(m, mixed, {}, &error);
  ASSERT_TRUE(error.empty()) << error;
  // Invalid points: status and fields; valid points: against the reference.
  const CheckSummary s = CheckResults(g, mixed, b, [&](const double* p) { return reference.Closest(p); });
  EXPECT_EQ(s.failures, 0) << s.report;
  // The valid points get the same answers as without the broken ones (up to
  // the solver tolerance: the buckets, hence warm starts, differ).
  const double tol = 1e-9 * reference.size();
  int invalid = 0;
  for (std::size_t j = 0; j < mixed.size(); ++j) {
    if (cleanIndex[j] == std::string::npos) {
      ++invalid;
      continue;
    }
    const std::size_t i = cleanIndex[j];
    ASSERT_EQ(b.status[j], a.status[i]) << "point " << j;
    EXPECT_NEAR(b.distance[j], a.distance[i], tol) << "point " << j;
  }
  EXPECT_EQ(invalid, static_cast<int>((clean.size() + 3) / 4));
}

// ---------------------------------------------------------------------------
// Points views.

TEST(ManifoldTest, PointsViewLayoutsAndScalarsAgree) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE("dimension " + std::to_string(dim));
    const Geometry g = dim == 3 ? MixedGeometry3() : MixedGeometry2();
    const Manifold m = BuildOk(g);
    QueryMix mix;
    mix.near = 3000;
    mix.far = 1000;
    mix.inside = 1000;
    const QuerySet q = MakeQueries(GeometryCells(g), dim, GeometrySize(g), mix, 1401 + dim);
    const std::size_t n = q.size();
    // Float-representable coordinates, in every layout.
    std::vector<float> f32(q.points.size());
    for (std::size_t i = 0; i < f32.size(); ++i) f32[i] = static_cast<float>(q.points[i]);
    std::vector<double> f64(f32.begin(), f32.end());
    std::vector<double> sepD[3];
    std::vector<float> sepF[3];
    std::vector<double> strided(5 * n, -7.0);  // records of 5 values, coordinates first
    for (int k = 0; k < dim; ++k) {
      for (std::size_t i = 0; i < n; ++i) {
        sepD[k].push_back(f64[i * dim + k]);
        sepF[k].push_back(f32[i * dim + k]);
        strided[5 * i + k] = f64[i * dim + k];
      }
    }
    PointsView views[5] = {
        PointsView::Interleaved(f64.data(), n, dim),
        PointsView::Interleaved(f32.data(), n, dim),
        PointsView::Separate(sepD[0].data(), sepD[1].data(), dim == 3 ? sepD[2].data() : nullptr, n, dim),
        PointsView::Separate(sepF[0].data(), sepF[1].data(), dim == 3 ? sepF[2].data() : nullptr, n, dim),
        PointsView::Interleaved(strided.data(), n, dim)};
    views[4].stride = 5;
    const char* names[5] = {"float64 interleaved", "float32 interleaved", "float64 separate", "float32 separate",
                            "float64 stride 5"};
    Results results[5];
    for (int v = 0; v < 5; ++v) {
      std::string message;
      ASSERT_EQ(m.Invert(views[v], {}, &results[v], &message), Error::Ok) << names[v] << ": " << message;
    }
    for (int v = 1; v < 5; ++v) EXPECT_EQ(CompareBitwise(results[0], results[v]), "") << names[v];
    // And the answers themselves are right.
    ReferenceGeometry reference(g);
    QuerySet exact;
    exact.dim = dim;
    for (std::size_t i = 0; i < n; ++i) exact.Add(&f64[i * dim], q.kinds[i]);
    const CheckSummary s = CheckResults(g, exact, results[0], [&](const double* p) { return reference.Closest(p); });
    EXPECT_EQ(s.failures, 0) << s.report;
  }
}

/// A 2D polyline mesh patch from points and segments.
Geometry Polyline(const std::vector<double>& xy, const std::vector<std::int64_t>& segments) {
  Geometry g;
  g.dimension = 2;
  Patch p;
  p.kind = Patch::Kind::Mesh;
  p.cell = CellType::Line;
  p.points = xy;
  p.cells = segments;
  g.patches.push_back(p);
  return g;
}

/// Distance from (x, y) to the nearest segment, by brute force in long
/// double (squares of coordinates beyond 1e154 stay finite).
double NearestSegmentDistance(const std::vector<double>& xy, const std::vector<std::int64_t>& segments, double x,
                              double y) {
  long double best = std::numeric_limits<long double>::infinity();
  for (std::size_t s = 0; s < segments.size(); s += 2) {
    const long double ax = xy[2 * segments[s]], ay = xy[2 * segments[s] + 1];
    const long double dx = xy[2 * segments[s + 1]] - ax, dy = xy[2 * segments[s + 1] + 1] - ay;
    const long double t = std::clamp(((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy), 0.0L, 1.0L);
    const long double ex = ax + t * dx - x, ey = ay + t * dy - y;
    best = std::min(best, std::sqrt(ex * ex + ey * ey));
  }
  return static_cast<double>(best);
}

/// Inverts the 2D points `xy` (interleaved) with no gap tolerance: every one
/// is found, at the brute-force distance to within 1e-9 of it (or of 1).
void ExpectNearestSegmentDistances(const Manifold& m, const std::vector<double>& xy,
                                   const std::vector<std::int64_t>& segments, const std::vector<double>& q) {
  const std::int64_t n = static_cast<std::int64_t>(q.size() / 2);
  Results r;
  ASSERT_EQ(m.Invert(PointsView::Interleaved(q.data(), n, 2), {}, &r), Error::Ok);
  for (std::int64_t i = 0; i < n; ++i) {
    SCOPED_TRACE(::testing::Message() << "point " << i);
    ASSERT_EQ(r.status[i], Status::Found);
    const double expected = NearestSegmentDistance(xy, segments, q[2 * i], q[2 * i + 1]);
    EXPECT_LE(std::abs(r.distance[i] - expected), 1e-9 * std::max(1.0, expected));
  }
}

TEST(ManifoldTest, PointsBeyondSquaredOverflowAreAnswered) {
  // With no gap tolerance the search's squared distances overflow to
  // infinity for points this far; it must still end, with the right answer.
  std::vector<double> xy;
  std::vector<std::int64_t> segments;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    xy.insert(xy.end(), {std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n)});
    segments.insert(segments.end(), {i, (i + 1) % n});
  }
  const Manifold m = BuildOk(Polyline(xy, segments));
  ExpectNearestSegmentDistances(m, xy, segments, {1e160, 5e159, -3e200, 1e10, 0.1, 0.2, 1e300, -1e300});
}

TEST(ManifoldTest, GeometryBeyondTheFloatRangeOfOffsetsIsSearchedExactly) {
  // Four walls of segments near +-1e35 and +-7e34, and points between them:
  // coordinates far beyond any fixed clamp of the search's float offsets.
  std::vector<double> xy;
  std::vector<std::int64_t> segments;
  const auto segment = [&](double x0, double y0, double x1, double y1) {
    const std::int64_t first = static_cast<std::int64_t>(xy.size() / 2);
    xy.insert(xy.end(), {x0, y0, x1, y1});
    segments.insert(segments.end(), {first, first + 1});
  };
  const double s = 1e35;
  for (int j = 0; j < 30; ++j) {
    const double t = (j - 15) * 1e32;
    segment(s, t, s, t + 1e32);
    segment(-s, t, -s, t + 1e32);
    segment(t, 0.7 * s, t + 1e32, 0.7 * s);
    segment(t, -0.7 * s, t + 1e32, -0.7 * s);
  }
  const Manifold m = BuildOk(Polyline(xy, segments));
  ExpectNearestSegmentDistances(
      m, xy, segments, {0.5 * s, 0.0, -0.5 * s, 0.3 * s, 0.5 * s, -0.3 * s, -0.4 * s, -0.2 * s, 0.1 * s, 0.1 * s});
}

TEST(ManifoldTest, EmptyBatch) {
  const Manifold m = BuildOk(MixedGeometry3());
  Results r;
  r.status.assign(5, Status::Found);  // stale content must go
  std::string message;
  ASSERT_EQ(m.Invert(PointsView::Interleaved(static_cast<const double*>(nullptr), 0, 3), {}, &r, &message), Error::Ok)
      << message;
  EXPECT_TRUE(r.status.empty());
  EXPECT_TRUE(r.distance.empty());
  EXPECT_TRUE(r.params.empty());
}

// ---------------------------------------------------------------------------
// Empty and degenerate geometries.

TEST(ManifoldTest, AGeometryWithoutCellsIsAnInputError) {
  // Every point would be "none" against it: an empty file or list is a
  // mistake to report, not a geometry.
  for (int dim : {2, 3}) {
    Geometry g;
    g.dimension = dim;
    BuildResult built = Manifold::Build(g);
    EXPECT_FALSE(built.manifold.valid());
    EXPECT_NE(built.error.find("the geometry has no cells"), std::string::npos) << built.error;
    // Patches without cells: a mesh with no cells, a B-spline of empty spans only.
    Patch mesh;
    mesh.kind = Patch::Kind::Mesh;
    mesh.cell = CellType::Tri;
    mesh.points.assign(3 * static_cast<std::size_t>(dim), 0.0);
    g.patches.push_back(mesh);
    built = Manifold::Build(g);
    EXPECT_FALSE(built.manifold.valid());
    EXPECT_NE(built.error.find("the geometry has no cells"), std::string::npos) << built.error;
  }
}

/// Degenerate cells of every kind in one geometry of dimension dim; with
/// `folded`, only a zero-area quadratic triangle (kept apart because each of
/// its points costs invmap about 20 ms: a whole curve of exact ties).
Geometry DegenerateGeometry(int dim, bool folded) {
  Geometry g;
  g.dimension = dim;
  const auto bezier = [&](const RefCell& cell, CellType type, double shift) {
    Patch p;
    p.kind = Patch::Kind::Bezier;
    p.cell = type;
    p.degrees.push_back(cell.degrees[0]);
    if (type == CellType::Quad) p.degrees.push_back(cell.degrees[1]);
    for (std::size_t i = 0; i < cell.points.size(); i += 2) {
      p.points.insert(p.points.end(), {cell.points[i] + shift, cell.points[i + 1]});
      if (dim == 3) p.points.push_back(0.1 * shift);
    }
    p.weights = cell.weights;
    return p;
  };
  // A zero-area quadratic triangle (folded onto a segment) and a quad with a
  // collapsed edge (both 2D generators, lifted into 3D when needed).
  if (folded) {
    g.patches.push_back(bezier(ZeroAreaTriangle(), CellType::Tri, 0.0));
    return g;
  }
  g.patches.push_back(bezier(CollapsedEdgeQuad(), CellType::Quad, 3.0));
  // Linear mesh triangles: collinear vertices, two coincident vertices, all three coincident.
  Patch mesh;
  mesh.kind = Patch::Kind::Mesh;
  mesh.cell = CellType::Tri;
  const double v[7][3] = {{6, 0, 0}, {7, 1, 0}, {8, 2, 0}, {6, 3, 0.5}, {7, 3, 0.5}, {9, 1, 1}, {9, 1, 1}};
  for (const auto& x : v) mesh.points.insert(mesh.points.end(), x, x + dim);
  mesh.cells = {0, 1, 2, 3, 3, 4, 5, 6, 5};
  g.patches.push_back(mesh);
  // A bicubic B-spline surface (or, in 2D, region) whose v = 0 row collapses to one point.
  Patch spline;
  spline.kind = Patch::Kind::BSpline;
  spline.degrees = {3, 2};
  spline.counts = {5, 4};
  spline.knots = {{0, 0, 0, 0, 0.4, 1, 1, 1, 1}, {0, 0, 0, 0.5, 1, 1, 1}};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) {
      const double r = 0.5 * j;
      spline.points.insert(spline.points.end(), {-4 + r * (i - 2), 1 + r * (1 + 0.2 * i)});
      if (dim == 3) spline.points.push_back(0.3 * j * (i % 2));
    }
  g.patches.push_back(spline);
  // A Bezier quad shrunk to a single point.
  Patch point;
  point.kind = Patch::Kind::Bezier;
  point.cell = CellType::Quad;
  point.degrees = {2, 1};
  const double at[3] = {-3.0, -2.0, 0.5};
  for (int i = 0; i < 6; ++i) point.points.insert(point.points.end(), at, at + dim);
  g.patches.push_back(point);
  return g;
}

/// Compares `mix` queries on DegenerateGeometry(dim, folded) with the reference.
void RunDegenerate(int dim, bool folded, const QueryMix& mix, std::uint64_t seed) {
  SCOPED_TRACE("dimension " + std::to_string(dim));
  const Geometry g = DegenerateGeometry(dim, folded);
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), dim, reference.size(), mix, seed);
  const std::string name = std::string(folded ? "folded triangle " : "degenerate cells ") + (dim == 2 ? "2D" : "3D");
  const CheckSummary s = RunFamily(name.c_str(), g, q, [&](const double* p) { return reference.Closest(p); });
  EXPECT_EQ(s.found, s.points);  // hence finite distance, closest point and parameters
}

TEST(ManifoldTest, DegenerateCellsGiveFiniteCorrectAnswers) {
  QueryMix mix;
  mix.on = 2000;
  mix.near = 8000;
  mix.mid = 4000;
  mix.far = 2000;
  mix.nearFraction = 0.05;
  for (int dim : {2, 3}) RunDegenerate(dim, false, mix, 1501 + dim);
}

TEST(ManifoldTest, ZeroAreaTriangleGivesFiniteCorrectAnswers) {
  QueryMix mix;
  mix.on = 40;
  mix.near = 80;
  mix.mid = 40;
  mix.far = 40;
  mix.nearFraction = 0.05;
  for (int dim : {2, 3}) RunDegenerate(dim, true, mix, 1511 + dim);
}

// ---------------------------------------------------------------------------
// Malformed geometries.

/// A valid patch to put first, so the bad one is patch 1.
Patch ValidBezierTri(int dim) {
  Patch p;
  p.kind = Patch::Kind::Bezier;
  p.cell = CellType::Tri;
  p.degrees = {1};
  p.points = dim == 3 ? std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0} : std::vector<double>{0, 0, 1, 0, 0, 1};
  return p;
}

Patch ValidBSplineSurface() {
  Patch p;
  p.kind = Patch::Kind::BSpline;
  p.degrees = {2, 1};
  p.counts = {4, 2};
  p.knots = {{0, 0, 0, 0.5, 1, 1, 1}, {0, 0, 1, 1}};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) p.points.insert(p.points.end(), {double(i), double(j), 0.1 * i * j});
  return p;
}

Patch ValidMesh() {
  Patch p;
  p.kind = Patch::Kind::Mesh;
  p.cell = CellType::Tri;
  p.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  p.cells = {0, 1, 2, 1, 3, 2};
  return p;
}

struct MalformedCase {
  const char* what;
  Geometry geometry;
  const char* field;  ///< Text the message must contain besides "patch 1".
};

std::vector<MalformedCase> MalformedCases() {
  std::vector<MalformedCase> cases;
  const auto add = [&](const char* what, Patch bad, const char* field, int dim = 3) {
    Geometry g;
    g.dimension = dim;
    g.patches.push_back(ValidBezierTri(dim));
    g.patches.push_back(std::move(bad));
    cases.push_back({what, std::move(g), field});
  };
  Patch p;
  p = ValidBSplineSurface(), p.points.resize(p.points.size() - 3);
  add("B-spline with a control point missing", p, "control_points");
  p = ValidBezierTri(3), p.cell = CellType::Quad, p.degrees = {1, 1};
  add("Bezier quad with 3 of 4 control points", p, "control_points");
  p = ValidBSplineSurface(), p.counts = {5, 2};
  add("B-spline counts not matching the knots", p, "knots");
  p = ValidBSplineSurface(), p.knots[0] = {0, 0, 0, 0.6, 0.5, 1, 1};
  add("decreasing knots", p, "knots[0]");
  p = ValidBSplineSurface(), p.knots[1] = {0, 0, 1, kNaN};
  add("NaN knot", p, "knots[1]");
  p = ValidBSplineSurface(), p.weights = {1, 1, 1, 0, 1, 1, 1, 1};
  add("zero weight", p, "weights");
  p = ValidBSplineSurface(), p.weights = {1, 1, 1, 1, 1, -2, 1, 1};
  add("negative weight", p, "weights");
  p = ValidBezierTri(3), p.weights = {1, kInf, 1};
  add("infinite weight", p, "weights");
  p = ValidBezierTri(3), p.weights = {1, 1e51, 1};
  add("weight above the supported range", p, "weights[1]: 1e+51 is outside [1e-50, 1e50]");
  p = ValidBezierTri(3), p.weights = {1e-51, 1, 1};
  add("weight below the supported range", p, "weights[0]: 1e-51 is outside [1e-50, 1e50]");
  p = ValidBezierTri(3), p.weights = {1, 1};
  add("weights of the wrong length", p, "weights");
  p = ValidMesh(), p.cells[4] = 4;
  add("mesh index past the last vertex", p, "cells");
  p = ValidMesh(), p.cells[0] = -1;
  add("negative mesh index", p, "cells");
  p = ValidMesh(), p.cells.pop_back();
  add("mesh cell with a vertex missing", p, "cells");
  p = ValidBezierTri(3), p.points[4] = kNaN;
  add("NaN control point", p, "control_points");
  p = ValidBSplineSurface(), p.points[7] = -kInf;
  add("infinite B-spline control point", p, "control_points");
  p = ValidMesh(), p.points[2] = kNaN;
  add("NaN mesh vertex", p, "vertices");
  p = ValidBezierTri(3), p.points[4] = 1e101;
  add("control point beyond the supported range", p, "control_points[1]: coordinate 1 is 1e+101, outside [-1e100, 1e100]");
  p = ValidMesh(), p.points[2] = -2e150;
  add("mesh vertex beyond the supported range", p, "vertices[0]: coordinate 2 is -2e+150, outside [-1e100, 1e100]");
  p = ValidBezierTri(3), p.degrees = {0};
  add("degree 0", p, "degrees");
  p = ValidBezierTri(3), p.degrees = {1, 1};
  add("two degrees for a triangle", p, "degrees");
  p = ValidBezierTri(3), p.cell = CellType::Tet, p.points.insert(p.points.end(), {0, 0, 1});
  add("tet in 2D", p, "dimension", 2);
  p = ValidBSplineSurface(), p.degrees = {2, 1, 1}, p.counts = {4, 2, 2}, p.knots.push_back({0, 0, 1, 1});
  p.points.insert(p.points.end(), p.points.begin(), p.points.end());
  add("B-spline volume in 2D", p, "degrees", 2);
  p = ValidMesh(), p.points.pop_back();
  add("2D mesh vertices in a 3D geometry", p, "vertices");
  return cases;
}

TEST(ManifoldTest, AGeometryBelowTheSmallestExtentIsRejected) {
  // Its squared distances would underflow (QA: a sphere 1e-170 across had
  // every point at distance 0).
  Geometry g;
  g.patches.push_back(ValidMesh());
  for (double& x : g.patches[0].points) x *= 1e-120;
  const BuildResult built = Manifold::Build(g);
  EXPECT_FALSE(built.manifold.valid());
  EXPECT_NE(built.error.find("is 1.41421e-120 across (its box diagonal), below 1e-100"), std::string::npos)
      << built.error;
  // A single point (all control points equal) has no extent to measure.
  for (double& x : g.patches[0].points) x = 0.5;
  EXPECT_TRUE(Manifold::Build(g).error.empty());
  // Far below the range of squares: a triangle 1e-280 across (its squared
  // extent in units of 1e-100 underflowed to 0, and it passed as a point,
  // a query 5e-281 away at distance 0).
  Geometry tiny;
  tiny.dimension = 3;
  Patch triangle;
  triangle.kind = Patch::Kind::Mesh;
  triangle.cell = CellType::Tri;
  triangle.points = {0, 0, 0, 1e-280, 0, 0, 0, 1e-280, 0};
  triangle.cells = {0, 1, 2};
  tiny.patches.push_back(triangle);
  const BuildResult tinyBuilt = Manifold::Build(tiny);
  EXPECT_FALSE(tinyBuilt.manifold.valid());
  EXPECT_NE(tinyBuilt.error.find("is 1.41421e-280 across (its box diagonal), below 1e-100"), std::string::npos)
      << tinyBuilt.error;
  // Just at the limit along one axis is accepted.
  triangle.points = {0, 0, 0, 1e-100, 0, 0, 0, 0, 0};
  tiny.patches[0] = triangle;
  EXPECT_TRUE(Manifold::Build(tiny).error.empty()) << Manifold::Build(tiny).error;
}

TEST(ManifoldTest, MalformedGeometryIsRejectedWithPatchAndField) {
  for (const MalformedCase& c : MalformedCases()) {
    SCOPED_TRACE(c.what);
    const BuildResult built = Manifold::Build(c.geometry);
    EXPECT_FALSE(built.error.empty());
    EXPECT_FALSE(built.manifold.valid());
    EXPECT_NE(built.error.find("patch 1"), std::string::npos) << built.error;
    EXPECT_NE(built.error.find(c.field), std::string::npos) << "expected '" << c.field << "' in: " << built.error;
  }
  for (int dim : {0, 1, 4}) {
    Geometry g;
    g.dimension = dim;
    const BuildResult built = Manifold::Build(g);
    EXPECT_NE(built.error.find("dimension"), std::string::npos) << "dimension " << dim << ": " << built.error;
    EXPECT_FALSE(built.manifold.valid());
  }
}

// ---------------------------------------------------------------------------
// Info.

TEST(ManifoldTest, InfoCountsCellsAndBoundsTheGeometry) {
  Geometry g = WavySurfaces();
  g.patches.push_back(ValidMesh());
  g.patches.push_back(QuadraticMesh(false).patches[0]);
  const Manifold m = BuildOk(g);
  const ManifoldInfo info = m.Info();
  const std::vector<std::int64_t> counts = CellCounts(g);
  std::int64_t total = 0;
  for (std::int64_t c : counts) total += c;
  EXPECT_EQ(info.dimension, 3);
  EXPECT_EQ(info.patches, g.patches.size());
  EXPECT_EQ(info.cells, static_cast<std::size_t>(total));
  std::size_t byShape = 0;
  std::size_t quad33 = 0, tri1 = 0, tet2 = 0;
  for (const auto& [shape, n] : info.cellsByShape) {
    byShape += n;
    if (shape == "quad 3x3") quad33 += n;  // the documented spelling
    if (shape.rfind("tri 1", 0) == 0) tri1 += n;
    if (shape.rfind("tet 2", 0) == 0) tet2 += n;
  }
  EXPECT_EQ(byShape, info.cells);
  EXPECT_EQ(quad33, static_cast<std::size_t>(counts[0]));
  EXPECT_EQ(tri1, static_cast<std::size_t>(counts[2]));
  EXPECT_EQ(tet2, static_cast<std::size_t>(counts[3]));
  // Bounds: hold every point of every cell, and lie in the control points' box.
  double lo[3], hi[3];
  GeometryControlBox(g, lo, hi);
  const double tol = 1e-12 * GeometrySize(g);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(info.boundsLo[k], lo[k] - tol);
    EXPECT_LE(info.boundsHi[k], hi[k] + tol);
  }
  std::mt19937_64 rng(1601);
  for (const PatchCell& pc : GeometryCells(g)) {
    for (int s = 0; s < 4; ++s) {
      const std::array<double, 3> u = RandomRefPoint(pc.cell.type, rng);
      double x[3];
      RefEvaluate(pc.cell, u.data(), x);
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(x[k], info.boundsLo[k] - tol);
        ASSERT_LE(x[k], info.boundsHi[k] + tol);
      }
    }
  }
  EXPECT_GT(info.memoryBytes, 0u);
  // A default-constructed manifold is empty.
  const Manifold empty;
  EXPECT_FALSE(empty.valid());
  EXPECT_EQ(empty.Info().cells, 0u);
}

// ---------------------------------------------------------------------------
// API misuse: batch-level errors, never exceptions or crashes.

TEST(ManifoldTest, MisuseIsReportedAsInvalidArgument) {
  const Manifold m = BuildOk(MixedGeometry3());
  const double xyz[6] = {0, 0, 0, 1, 1, 1};
  Results r;
  std::string message;
  EXPECT_EQ(m.Invert(PointsView::Interleaved(xyz, 2, 2), {}, &r, &message), Error::InvalidArgument);
  EXPECT_FALSE(message.empty());
  EXPECT_EQ(m.Invert(PointsView::Interleaved(xyz, 2, 3), {}, nullptr, &message), Error::InvalidArgument);
  PointsView missing = PointsView::Separate(xyz, nullptr, xyz, 2, 3);
  EXPECT_EQ(m.Invert(missing, {}, &r, &message), Error::InvalidArgument);
  for (double bad : {-1.0, kNaN}) {
    InversionOptions o;
    o.maxDistance = bad;
    EXPECT_EQ(m.Invert(PointsView::Interleaved(xyz, 2, 3), o, &r, &message), Error::InvalidArgument) << bad;
  }
  InversionOptions negativeThreads;
  negativeThreads.threads = -2;
  EXPECT_EQ(m.Invert(PointsView::Interleaved(xyz, 2, 3), negativeThreads, &r, &message), Error::InvalidArgument);
  const Manifold empty;
  EXPECT_EQ(empty.Invert(PointsView::Interleaved(xyz, 2, 3), {}, &r, &message), Error::InvalidArgument);
  // Still usable afterwards.
  EXPECT_EQ(m.Invert(PointsView::Interleaved(xyz, 2, 3), {}, &r, &message), Error::Ok) << message;
  EXPECT_EQ(r.status[0], Status::Found);
}

// ---------------------------------------------------------------------------
// Scale: 10 million points.

/// Peak resident set size of the process so far, in bytes (Linux: kilobytes).
double PeakRssBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return 1024.0 * static_cast<double>(usage.ru_maxrss);
}

TEST(ManifoldTest, TenMillionPointsInBoundedMemory) {
  Geometry g;
  g.patches.push_back(BumpySphereMesh(12, 6, {{0, 0, 0}}, 1.0));
  const Manifold m = BuildOk(g);
  const std::size_t n = static_cast<std::size_t>(std::max(100000, ScaledCount(10000000)));
  // The peak before the batch: when other tests ran first in this process
  // it may already be high, which only makes the check more lenient.
  const double before = PeakRssBytes();
  std::vector<double> xyz(3 * n);
  std::uint64_t state = 0x9e3779b97f4a7c15ull;
  for (double& x : xyz) {
    // xorshift64*: 10 million points must be cheap to draw.
    state ^= state >> 12, state ^= state << 25, state ^= state >> 27;
    x = 3.0 * (static_cast<double>((state * 0x2545f4914f6cdd1dull) >> 11) * 0x1.0p-53) - 1.5;
  }
  Results r;
  std::string message;
  const double t0 = Seconds(), c0 = CpuSeconds();
  ASSERT_EQ(m.Invert(PointsView::Interleaved(xyz.data(), n, 3), {}, &r, &message), Error::Ok) << message;
  const double t1 = Seconds(), c1 = CpuSeconds();
  const double after = PeakRssBytes();
  const double inputBytes = static_cast<double>(xyz.size() * sizeof(double));
  const double outputBytes =
      static_cast<double>(r.status.size() * sizeof(Status) + r.patch.size() * sizeof(std::int32_t) +
                          r.cell.size() * sizeof(std::int64_t) + r.params.size() * sizeof(double) +
                          r.closest.size() * sizeof(double) + r.distance.size() * sizeof(double) +
                          r.iterations.size() * sizeof(std::int32_t));
  std::printf("[10M points] invmap %.2f s (cpu %.2f s); peak RSS grew %.0f MB for %.0f MB of points and %.0f MB of "
              "results\n",
              t1 - t0, c1 - c0, (after - before) / 1e6, inputBytes / 1e6, outputBytes / 1e6);
  EXPECT_LE(after - before, 2.5 * (inputBytes + outputBytes));
  ASSERT_EQ(r.status.size(), n);
  std::size_t found = 0;
  for (Status s : r.status) found += s == Status::Found;
  EXPECT_EQ(found, n);
  // A sample of the answers against the reference.
  ReferenceGeometry reference(g);
  QuerySet sample;
  Results sampled;
  for (std::size_t i = 0; i < n; i += 997) {
    sample.Add(&xyz[3 * i], "uniform");
    sampled.status.push_back(r.status[i]);
    sampled.patch.push_back(r.patch[i]);
    sampled.cell.push_back(r.cell[i]);
    sampled.distance.push_back(r.distance[i]);
    sampled.iterations.push_back(r.iterations[i]);
    for (int k = 0; k < 3; ++k) {
      sampled.params.push_back(r.params[3 * i + k]);
      sampled.closest.push_back(r.closest[3 * i + k]);
    }
  }
  const CheckSummary s = CheckResults(g, sample, sampled, [&](const double* p) { return reference.Closest(p); });
  EXPECT_EQ(s.failures, 0) << s.report;
}

}  // namespace
}  // namespace invmap::testing
