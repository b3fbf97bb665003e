// Distance queries' rates, 1 thread: PointTracker updates per second for a
// probe taking small steps near a bicubic surface and a 100k-triangle mesh,
// DistanceTracker poses per second for a model moving in small steps near
// another (surfaces of thousands of cells, meshes), and fresh model-to-model
// queries. Every answer is the certified global one (the tracker verifies
// each update over the whole model).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "samples/sample_geometries.h"
#include "invmap/distance.h"
#include "invmap/invmap.h"

namespace {

using invmap::Geometry;

/// A manifold with its distance model, kept together (the model refers to it).
struct Model {
  invmap::Manifold manifold;
  invmap::DistanceModel distance;
};

std::unique_ptr<Model> Build(const Geometry& geometry) {
  auto model = std::make_unique<Model>();
  model->manifold = std::move(invmap::Manifold::Build(geometry).manifold);
  model->distance = invmap::DistanceModel::Build(model->manifold).model;
  return model;
}

/// A bumpy sphere of radius `radius` as a latitude-longitude triangle mesh
/// with 2 * lon * lat triangles (poles fanned), centred at the origin.
Geometry BumpyMesh(int lon, int lat, double radius) {
  invmap::Patch patch;
  patch.kind = invmap::Patch::Kind::Mesh;
  patch.cell = invmap::CellType::Tri;
  const double pi = 3.14159265358979323846;
  for (int j = 0; j <= lat; ++j) {
    for (int i = 0; i < lon; ++i) {
      const double theta = pi * j / lat, phi = 2.0 * pi * i / lon;
      const double r = radius * (1.0 + 0.05 * std::sin(5.0 * phi) * std::sin(4.0 * theta));
      patch.points.insert(patch.points.end(),
                          {r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
  }
  auto index = [lon](int i, int j) { return static_cast<std::int64_t>(j) * lon + (i % lon); };
  for (int j = 0; j < lat; ++j) {
    for (int i = 0; i < lon; ++i) {
      patch.cells.insert(patch.cells.end(), {index(i, j), index(i, j + 1), index(i + 1, j + 1)});
      patch.cells.insert(patch.cells.end(), {index(i, j), index(i + 1, j + 1), index(i + 1, j)});
    }
  }
  Geometry g;
  g.patches.push_back(patch);
  return g;
}

/// A rotation about z by `angle` and a translation, as a pose.
invmap::Pose Pose(double angle, double x, double y, double z) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double rows[12] = {c, -s, 0, x, s, c, 0, y, 0, 0, 1, z};
  return invmap::Pose::FromRows(rows);
}

/// Probe points a small step apart along a smooth path near the geometry.
void TrackPoint(benchmark::State& state, const Geometry& geometry, const double* start, double step) {
  const auto model = Build(geometry);
  invmap::PointTracker tracker(model->manifold);
  invmap::PointAnswer answer;
  double p[3] = {start[0], start[1], start[2]};
  std::int64_t i = 0;
  for (auto _ : state) {
    const double t = 0.001 * static_cast<double>(i++);
    p[0] = start[0] + step * std::sin(7.0 * t) * 300.0;
    p[1] = start[1] + step * std::cos(5.0 * t) * 300.0;
    p[2] = start[2] + step * std::sin(3.0 * t) * 30.0;
    tracker.Update(p, &answer);
    benchmark::DoNotOptimize(answer.distance);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_PointTrackerBicubic(benchmark::State& state) {
  const double start[3] = {0.4, 0.5, 0.15};
  TrackPoint(state, invmap::samples::WavySurface(static_cast<int>(state.range(0))), start, 1e-4);
}
BENCHMARK(BM_PointTrackerBicubic)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);

void BM_PointTrackerMesh100k(benchmark::State& state) {
  const double start[3] = {0.3, 0.2, 1.05};
  TrackPoint(state, BumpyMesh(250, 200, 1.0), start, 1e-4);
}
BENCHMARK(BM_PointTrackerMesh100k)->Unit(benchmark::kMicrosecond);

/// Model B moving in small steps near model A, tracked.
void TrackModels(benchmark::State& state, const Geometry& a, const Geometry& b, double height, double step) {
  const auto ma = Build(a);
  const auto mb = Build(b);
  invmap::DistanceTracker tracker(ma->distance, mb->distance);
  invmap::DistanceResult result;
  std::int64_t i = 0;
  for (auto _ : state) {
    const double t = static_cast<double>(i++);
    tracker.Update(Pose(0.01 * t * step * 100, 0.5 + 0.2 * std::sin(step * t), 0.5 + 0.2 * std::cos(1.3 * step * t),
                        height),
                   &result);
    benchmark::DoNotOptimize(result.nearest.distance);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_DistanceTrackerSurfaces(benchmark::State& state) {
  // A bicubic surface of spans^2 cells (plus its crease) and a small torus
  // of 16 NURBS cells hovering over it.
  TrackModels(state, invmap::samples::WavySurface(static_cast<int>(state.range(0))),
              invmap::samples::NurbsTorus(0.1, 0.04), 0.25, 1e-3);
}
BENCHMARK(BM_DistanceTrackerSurfaces)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);

void BM_DistanceTrackerMeshes(benchmark::State& state) {
  // A 100k-triangle sphere and a 2,000-triangle one moving along it.
  const auto big = BumpyMesh(250, 200, 1.0);
  TrackModels(state, big, BumpyMesh(25, 40, 0.1), 1.2, 1e-3);
}
BENCHMARK(BM_DistanceTrackerMeshes)->Unit(benchmark::kMicrosecond);

void BM_DistanceFresh(benchmark::State& state) {
  const auto a = Build(invmap::samples::WavySurface(32));
  const auto b = Build(invmap::samples::NurbsTorus(0.1, 0.04));
  invmap::DistanceResult result;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.1, 0.9);
  for (auto _ : state) {
    invmap::Distance(a->distance, invmap::Pose(), b->distance, Pose(u(rng) * 6, u(rng), u(rng), 0.2 + 0.3 * u(rng)),
                     {}, &result);
    benchmark::DoNotOptimize(result.nearest.distance);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DistanceFresh)->Unit(benchmark::kMicrosecond);

void BM_DistanceFreshMeshes(benchmark::State& state) {
  // A sphere of range(0) triangles and one of range(1) at 0.15 its size,
  // at random poses around it.
  const auto a = Build(invmap::samples::BumpySphere(state.range(0)));
  auto small = invmap::samples::BumpySphere(state.range(1));
  for (double& x : small.patches[0].points) x *= 0.15;
  const auto b = Build(small);
  invmap::DistanceOptions options;
  options.threads = 1;
  invmap::DistanceResult result;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto _ : state) {
    const double z = 2 * u(rng) - 1, phi = 6.283185307179586 * u(rng), r = std::sqrt(1 - z * z);
    const double axis[3] = {0.6, 0.0, 0.8}, t[3] = {1.4 * r * std::cos(phi), 1.4 * r * std::sin(phi), 1.4 * z};
    invmap::Distance(a->distance, invmap::Pose(), b->distance, invmap::Pose::FromAxisAngle(axis, 6 * u(rng), t),
                     options, &result);
    benchmark::DoNotOptimize(result.nearest.distance);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DistanceFreshMeshes)->Args({81920, 5120})->Args({1280, 320})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
