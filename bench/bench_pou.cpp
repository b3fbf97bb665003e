// Partition-of-unity surfaces (docs/manifold.md) against what users have
// instead: the same mesh inverted as triangles, and its Loop subdivision
// (two levels, 16 times the triangles) inverted as triangles. Build time and
// inversion throughput on bumpy spheres of 1,280 to 81,920 triangles, for
// points near the surface (up to 1% of its size away). Figures in
// docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <unordered_map>
#include <vector>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "samples/sample_geometries.h"

namespace {

using invmap::Geometry;
using invmap::Patch;

struct TriangleMesh {
  std::vector<double> xyz;
  std::vector<std::int64_t> triangles;
};

TriangleMesh BumpySphere(std::int64_t minTriangles) {
  const invmap::Geometry g = invmap::samples::BumpySphere(minTriangles);
  return {g.patches[0].points, g.patches[0].cells};
}

/// One level of Loop subdivision of a closed mesh: every triangle into four,
/// vertices and edge points by Loop's masks (Warren's beta).
TriangleMesh LoopStep(const TriangleMesh& mesh) {
  const std::int64_t nv = static_cast<std::int64_t>(mesh.xyz.size() / 3);
  std::vector<double> neighbourSum(mesh.xyz.size(), 0.0);
  std::vector<int> valence(nv, 0);
  std::unordered_map<std::uint64_t, std::int64_t> edgePoint;
  TriangleMesh out;
  out.xyz.assign(mesh.xyz.size(), 0.0);
  const auto edgeIndex = [&](std::int64_t a, std::int64_t b) {
    const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint64_t>(std::max(a, b));
    auto [it, added] = edgePoint.try_emplace(key, static_cast<std::int64_t>(out.xyz.size() / 3));
    if (added) out.xyz.insert(out.xyz.end(), {0.0, 0.0, 0.0});
    return it->second;
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const std::int64_t v[3] = {mesh.triangles[t], mesh.triangles[t + 1], mesh.triangles[t + 2]};
    std::int64_t e[3];
    for (int i = 0; i < 3; ++i) {
      const std::int64_t a = v[i], b = v[(i + 1) % 3], c = v[(i + 2) % 3];
      e[i] = edgeIndex(a, b);
      // Each edge is met from both its triangles: 3/16 of each end and 1/8
      // of the opposite vertex each time.
      for (int k = 0; k < 3; ++k) {
        out.xyz[3 * e[i] + k] += 3.0 / 16.0 * (mesh.xyz[3 * a + k] + mesh.xyz[3 * b + k]) + 1.0 / 8.0 * mesh.xyz[3 * c + k];
        neighbourSum[3 * a + k] += mesh.xyz[3 * b + k];
      }
      ++valence[a];
    }
    out.triangles.insert(out.triangles.end(), {v[0], e[0], e[2], v[1], e[1], e[0], v[2], e[2], e[1], e[0], e[1], e[2]});
  }
  for (std::int64_t a = 0; a < nv; ++a) {
    const int n = valence[a];
    const double beta = n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
    for (int k = 0; k < 3; ++k) out.xyz[3 * a + k] = (1.0 - n * beta) * mesh.xyz[3 * a + k] + beta * neighbourSum[3 * a + k];
  }
  return out;
}

Geometry AsTriangles(const TriangleMesh& mesh) {
  Geometry g;
  g.dimension = 3;
  Patch& p = g.patches.emplace_back();
  p.kind = Patch::Kind::Mesh;
  p.cell = invmap::CellType::Tri;
  p.points = mesh.xyz;
  p.cells = mesh.triangles;
  return g;
}

Geometry AsPou(const TriangleMesh& mesh) {
  Geometry g;
  g.dimension = 3;
  Patch& p = g.patches.emplace_back();
  const std::string error =
      invmap::BuildPouManifold(mesh.xyz.data(), static_cast<std::int64_t>(mesh.xyz.size() / 3), mesh.triangles.data(),
                               static_cast<std::int64_t>(mesh.triangles.size() / 3), {}, &p);
  if (!error.empty()) std::abort();
  return g;
}

enum Kind { kPou = 0, kTriangles = 1, kLoop = 2 };
const char* const kKindNames[] = {"pou (loop base)", "mesh as triangles", "Loop subdivision x2 as triangles"};

/// The geometry of `kind` for the sphere of at least `triangles` triangles.
Geometry Make(int kind, std::int64_t triangles) {
  const TriangleMesh mesh = BumpySphere(triangles);
  if (kind == kPou) return AsPou(mesh);
  if (kind == kTriangles) return AsTriangles(mesh);
  return AsTriangles(LoopStep(LoopStep(mesh)));
}

/// Points within 1% of the size of the mesh's vertices (the same for every kind).
const std::vector<double>& Queries(std::int64_t triangles, std::size_t count) {
  static std::map<std::pair<std::int64_t, std::size_t>, std::vector<double>> cache;
  std::vector<double>& points = cache[{triangles, count}];
  if (points.empty()) {
    const TriangleMesh mesh = BumpySphere(triangles);
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const std::size_t nv = mesh.xyz.size() / 3;
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t v = random() % nv;
      for (int k = 0; k < 3; ++k) points.push_back(mesh.xyz[3 * v + k] + 0.02 * unit(random));
    }
  }
  return points;
}

void BM_Build(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const std::int64_t triangles = state.range(1);
  for (auto _ : state) {
    // The pou surface's fit and the subdivision are part of what a user waits for.
    const Geometry g = Make(kind, triangles);
    invmap::BuildResult built = invmap::Manifold::Build(g);
    benchmark::DoNotOptimize(built.manifold);
  }
  state.SetLabel(kKindNames[kind]);
}

void BM_Invert(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const std::int64_t triangles = state.range(1);
  const invmap::BuildResult built = invmap::Manifold::Build(Make(kind, triangles));
  // The pou surface's search is about a thousand times slower than a
  // triangle's: fewer points keep a run short.
  const std::vector<double>& points = Queries(triangles, kind == kPou ? 2000 : 200000);
  invmap::Results results;
  for (auto _ : state) {
    built.manifold.Invert(invmap::PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &results);
    benchmark::DoNotOptimize(results.distance.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size() / 3));
  state.SetLabel(kKindNames[kind]);
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (int kind : {kPou, kTriangles, kLoop})
    for (std::int64_t triangles : {1000, 5000, 20000, 80000}) b->Args({kind, triangles});
}

}  // namespace

BENCHMARK(BM_Build)->Apply(Sizes)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_Invert)->Apply(Sizes)->Unit(benchmark::kMillisecond)->MinTime(0.5)->UseRealTime();

BENCHMARK_MAIN();
