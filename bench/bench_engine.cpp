// Engine throughput: whole batches (points/s) on a surface, a curve, a
// triangle mesh and a quadratic tet mesh, with 1 and 2 threads; and the
// oracle ratio: full engine time over the time to solve each point only on
// the cell the engine found, from the same start (culling and scheduling cost).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "engine/cell_store.h"
#include "invmap/invmap.h"
#include "samples/sample_geometries.h"

namespace {

using invmap::Geometry;
using invmap::Manifold;

/// A bicubic B-spline plate over [0, 1]^2 with 128 x 128 uniform spans whose
/// control points sit at the Greville abscissae, lifted by `waviness` *
/// sin: with waviness 0 it is exactly affine (one affine region, algorithm
/// 6); with a tiny waviness every cell is curved and searched on its own.
Geometry Plate(double waviness) {
  constexpr int kSpans = 128, kDegree = 3, kCount = kSpans + kDegree;
  std::vector<double> knots(kDegree + 1, 0.0);
  for (int i = 1; i < kSpans; ++i) knots.push_back(static_cast<double>(i) / kSpans);
  knots.insert(knots.end(), kDegree + 1, 1.0);
  auto greville = [&](int i) { return (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3; };
  invmap::Patch patch;
  patch.kind = invmap::Patch::Kind::BSpline;
  patch.degrees = {kDegree, kDegree};
  patch.knots = {knots, knots};
  patch.counts = {kCount, kCount};
  for (int j = 0; j < kCount; ++j)
    for (int i = 0; i < kCount; ++i) {
      const double u = greville(i), v = greville(j);
      patch.points.insert(patch.points.end(), {u + 0.2 * v, v, 0.3 * u + waviness * std::sin(20 * u) * std::sin(20 * v)});
    }
  Geometry g;
  g.patches.push_back(patch);
  return g;
}

/// Workloads: 0 wavy bicubic surface (32 x 32 spans), 1 NURBS torus,
/// 2 planar NURBS curve, 3 bumpy-sphere triangle mesh (1.3 M triangles),
/// 4 quadratic tet mesh (8^3 cubes), 5 flat plate (one affine region of
/// 16384 bicubic cells), 6 the same plate with waviness 1e-3 (no region),
/// 7 the triangle mesh of 3 with scan-like points (within 1e-4 of its size),
/// 8 the tet mesh of 4 with near points (inside, and outside by the boundary).
Geometry MakeGeometry(int workload) {
  switch (workload) {
    case 5:
      return Plate(0.0);
    case 6:
      return Plate(1e-3);
    case 0:
      return invmap::samples::WavySurface(32);
    case 1:
      return invmap::samples::NurbsTorus(2.0, 0.7);
    case 2:
      return invmap::samples::NurbsCurve2D();
    case 3:
    case 7:
      return invmap::samples::BumpySphere(1000000);
    default:
      return invmap::samples::ToBezierGeometry(invmap::samples::CurvedTetMesh(8));
  }
}

const char* WorkloadName(int workload) {
  static const char* const kNames[] = {"surface", "torus", "curve2d", "trimesh", "tets_p2", "flat_plate", "wavy_plate", "trimesh_scan", "tets_near"};
  return kNames[workload];
}

/// A built manifold and its query points, shared by the benchmarks of a workload.
struct Workload {
  Manifold manifold;
  int dim = 3;
  std::vector<double> points;
};

/// Points: near the geometry (within 2% of its size) for surfaces, curves and
/// meshes (and the tet mesh of workload 8); inside the cells for workload 4.
const Workload& GetWorkload(int workload) {
  static std::map<int, Workload> cache;
  auto found = cache.find(workload);
  if (found != cache.end()) return found->second;
  Workload& w = cache[workload];
  invmap::BuildResult built = Manifold::Build(MakeGeometry(workload));
  w.manifold = std::move(built.manifold);
  const invmap::ManifoldInfo info = w.manifold.Info();
  w.dim = info.dimension;
  double size2 = 0.0;
  for (int k = 0; k < w.dim; ++k) size2 += (info.boundsHi[k] - info.boundsLo[k]) * (info.boundsHi[k] - info.boundsLo[k]);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0), symmetric(-1.0, 1.0);
  const std::int64_t cells = w.manifold.NumCells(0);
  const double spread = workload == 4 ? 0.0 : (workload == 7 ? 1e-4 : 0.02) * std::sqrt(size2);
  for (int i = 0; i < 200000; ++i) {
    const double sample[3] = {unit(rng), unit(rng), unit(rng)};
    double params[3], point[3];
    w.manifold.PointAt(0, static_cast<std::int64_t>(unit(rng) * cells) % cells, sample, params, point);
    for (int k = 0; k < w.dim; ++k) w.points.push_back(point[k] + spread * symmetric(rng));
  }
  return w;
}

void BM_InvertBatch(benchmark::State& state) {
  const Workload& w = GetWorkload(static_cast<int>(state.range(0)));
  invmap::InversionOptions options;
  options.threads = static_cast<int>(state.range(1));
  const std::size_t n = w.points.size() / w.dim;
  invmap::Results results;
  std::int64_t iterations = 0;
  for (auto _ : state) {
    w.manifold.Invert(invmap::PointsView::Interleaved(w.points.data(), n, w.dim), options, &results);
    for (std::size_t i = 0; i < n; ++i) iterations += results.iterations[i];
  }
  state.SetLabel(WorkloadName(static_cast<int>(state.range(0))));
  state.counters["points/s"] =
      benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["newton_iters"] = static_cast<double>(iterations) / (static_cast<double>(n) * state.iterations());
}

/// The engine against an oracle that knows each point's cell: the same cell
/// solver (certified, from the cell's center) on just the cell the engine
/// reported, with no culling or scheduling. Reported as a ratio of times, 1 thread.
void BM_OracleRatio(benchmark::State& state) {
  const int workload = static_cast<int>(state.range(0));
  const Workload& w = GetWorkload(workload);
  const std::size_t n = std::min<std::size_t>(w.points.size() / w.dim, 50000);
  invmap::InversionOptions options;
  options.threads = 1;
  invmap::Results results;
  w.manifold.Invert(invmap::PointsView::Interleaved(w.points.data(), n, w.dim), options, &results);
  // The workloads are valid geometries (the manifold above was built from one).
  const invmap::engine::CellStore store = invmap::engine::CellStore::Build(MakeGeometry(workload), 1);
  std::vector<std::int64_t> cellOf(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (results.status[i] == invmap::Status::Found) cellOf[i] = store.patchFirstCell(results.patch[i]) + results.cell[i];
  }
  invmap::kernels::SolveWorkspace ws;
  double engineSeconds = 0.0, oracleSeconds = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    w.manifold.Invert(invmap::PointsView::Interleaved(w.points.data(), n, w.dim), options, &results);
    const auto t1 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      if (cellOf[i] < 0) continue;
      const auto r = store.solver(cellOf[i]).Solve(&w.points[i * w.dim], nullptr, &ws);
      benchmark::DoNotOptimize(r);
    }
    const auto t2 = std::chrono::steady_clock::now();
    engineSeconds += std::chrono::duration<double>(t1 - t0).count();
    oracleSeconds += std::chrono::duration<double>(t2 - t1).count();
  }
  state.SetLabel(WorkloadName(workload));
  state.counters["oracle_ratio"] = engineSeconds / oracleSeconds;
}

// Arguments: workload, threads (0 = all cores).
BENCHMARK(BM_InvertBatch)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6, 7, 8}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OracleRatio)->DenseRange(0, 8)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
