// Kernel throughput: map evaluations per second and single-cell closest-point
// solves per second, per cell type and degree. Counters are rates.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "kernels/cell_bounds.h"
#include "kernels/cell_solver.h"
#include "kernels/local_solver.h"
#include "kernels/newton_lanes.h"

namespace {

using invmap::kernels::CellShape;
using invmap::kernels::CellSolver;
using invmap::kernels::CellType;
using invmap::kernels::CellView;

/// A visibly curved cell: the lattice of the reference domain, embedded in
/// 3D, with control points moved by up to `bend` (fixed seed).
struct BenchCell {
  CellShape shape;
  std::vector<double> points;
  std::vector<double> weights;
  CellView view() const { return {shape, 3, points.data(), weights.empty() ? nullptr : weights.data()}; }
};

BenchCell MakeCell(CellType type, int degree, bool rational, double bend) {
  BenchCell cell;
  cell.shape = CellShape(type, {degree, degree, degree});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-bend, bend), weight(0.5, 2.0);
  const int n = cell.shape.numControlPoints();
  for (int c = 0; c < n; ++c) {
    double ref[3] = {0, 0, 0};
    invmap::kernels::ControlPointLocation(cell.shape, c, ref);
    for (int k = 0; k < 3; ++k) cell.points.push_back(ref[k] + jitter(rng));
    if (rational) cell.weights.push_back(weight(rng));
  }
  return cell;
}

/// Query points around the cell's box: about half near the cell, half farther.
std::vector<double> MakePoints(const CellSolver& solver, int count) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-0.25, 1.25);
  std::vector<double> points;
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double lo = solver.boxLo()[k], hi = solver.boxHi()[k];
      points.push_back(lo + unit(rng) * (hi - lo));
    }
  }
  return points;
}

CellType TypeArg(int64_t t) { return static_cast<CellType>(t); }

void BM_EvaluateMap(benchmark::State& state) {
  const BenchCell cell = MakeCell(TypeArg(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0, 0.2);
  const CellView view = cell.view();
  double ref[3] = {0.2, 0.3, 0.1};
  invmap::kernels::MapJet jet;
  for (auto _ : state) {
    invmap::kernels::EvaluateMap(view, ref, invmap::kernels::JetOrder::Second, &jet);
    benchmark::DoNotOptimize(jet);
  }
  state.counters["evals/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SolveCell(benchmark::State& state) {
  const BenchCell cell = MakeCell(TypeArg(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0, 0.2);
  const CellView view = cell.view();
  const CellSolver solver(view);
  const std::vector<double> points = MakePoints(solver, 1024);
  invmap::kernels::SolveWorkspace ws;
  size_t i = 0;
  int64_t iterations = 0;
  for (auto _ : state) {
    const auto r = solver.Solve(&points[3 * (i++ % 1024)], nullptr, &ws);
    iterations += r.iterations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["solves/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["newton_iters"] = static_cast<double>(iterations) / static_cast<double>(state.iterations());
}

/// Building one cell's solver (its distance nets and curvature bounds, the
/// cost of a geometry's build per cell): cells/s, and the nets' bytes.
void BM_BuildCell(benchmark::State& state) {
  const BenchCell cell = MakeCell(TypeArg(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0, 0.2);
  const CellView view = cell.view();
  std::size_t bytes = CellSolver(view).NetMemoryBytes();  // also builds the shape's shared stencil once
  for (auto _ : state) {
    const CellSolver solver(view);
    benchmark::DoNotOptimize(solver.size());
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["net_bytes"] = static_cast<double>(bytes);
}

// Arguments: cell type (0 line, 1 tri, 2 quad, 3 tet, 4 hex, 5 wedge), degree
// (1 to 8, the highest the format allows), rational.
void BuildArgs(benchmark::internal::Benchmark* b) {
  for (int type = 0; type <= 5; ++type) {
    for (int degree = 1; degree <= 8; ++degree) b->Args({type, degree, 0});
  }
}

// Arguments: cell type (0 line, 1 tri, 2 quad, 3 tet, 4 hex, 5 wedge), degree, rational.
void CellArgs(benchmark::internal::Benchmark* b) {
  for (int type = 0; type <= 5; ++type) {
    for (int degree = 1; degree <= 3; ++degree) {
      for (int rational = 0; rational <= 1; ++rational) b->Args({type, degree, rational});
    }
  }
}

BENCHMARK(BM_EvaluateMap)->Apply(CellArgs);
BENCHMARK(BM_SolveCell)->Apply(CellArgs);
BENCHMARK(BM_BuildCell)->Apply(BuildArgs)->Unit(benchmark::kMicrosecond);

/// SolveLane's output arrays for `count` lanes and the ResultLane pointing at them.
struct LaneResults {
  explicit LaneResults(int count) : distance(count), status(count), iterations(count) {
    for (int k = 0; k < 3; ++k) {
      ref[k].resize(count);
      closest[k].resize(count);
      out.ref[k] = ref[k].data();
      out.closest[k] = closest[k].data();
    }
    out.distance = distance.data();
    out.status = status.data();
    out.iterations = iterations.data();
  }
  std::vector<double> ref[3], closest[3], distance;
  std::vector<invmap::kernels::PointStatus> status;
  std::vector<int> iterations;
  invmap::kernels::ResultLane out;
};

/// Points near the cell (the engine's common case: a bucket's points that
/// share a candidate cell): the map at random reference points, moved by up
/// to 2% of the cell's size in a random direction; as structure of arrays.
struct NearPoints {
  std::vector<double> coord[3];
  int count() const { return static_cast<int>(coord[0].size()); }
};
NearPoints MakeNearPoints(const CellSolver& solver, int count) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-0.02, 0.02);
  NearPoints points;
  const int pd = solver.cell().shape.paramDim();
  for (int i = 0; i < count; ++i) {
    double ref[3] = {unit(rng), pd > 1 ? unit(rng) : 0.0, 0.0};
    invmap::kernels::MapJet jet;
    invmap::kernels::EvaluateMap(solver.cell(), ref, invmap::kernels::JetOrder::Value, &jet);
    for (int k = 0; k < 3; ++k) points.coord[k].push_back(jet.x[k] + offset(rng) * solver.size());
  }
  return points;
}

/// Certified solves of 64 near points on one curve or surface: SolveLane
/// (SIMD lanes for the local solves) against Solve point by point, in the
/// same run. Arguments: cell type (0 line, 2 quad), degree, rational,
/// lanes (1) or point by point (0), bend in percent of the cell (20: as
/// BM_SolveCell's cells; 2: as a B-spline surface's spans).
void BM_SolveNearPoints(benchmark::State& state) {
  const BenchCell cell = MakeCell(TypeArg(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0,
                                  0.01 * static_cast<double>(state.range(4)));
  const CellSolver solver(cell.view());
  const NearPoints points = MakeNearPoints(solver, 64);
  const bool lanes = state.range(3) != 0;
  invmap::kernels::SolveWorkspace ws;
  invmap::kernels::QueryLane query;
  query.count = points.count();
  for (int k = 0; k < 3; ++k) query.coord[k] = points.coord[k].data();
  LaneResults output(query.count);
  const invmap::kernels::ResultLane& result = output.out;
  std::vector<double>& distance = output.distance;
  for (auto _ : state) {
    if (lanes) {
      solver.SolveLane(query, result, &ws);
    } else {
      for (int l = 0; l < query.count; ++l) {
        const double p[3] = {points.coord[0][l], points.coord[1][l], points.coord[2][l]};
        distance[l] = solver.Solve(p, nullptr, &ws).distance;
      }
    }
    benchmark::DoNotOptimize(distance.data());
  }
  state.counters["solves/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * query.count, benchmark::Counter::kIsRate);
  state.SetLabel(lanes ? invmap::kernels::LaneIsaName(invmap::kernels::BestLaneIsa()) : "point by point");
}

void NearArgs(benchmark::internal::Benchmark* b) {
  for (int type : {0, 2}) {
    for (int degree = 2; degree <= 3; ++degree) {
      for (int rational = 0; rational <= 1; ++rational) {
        for (int bend : {20, 2}) {
          for (int lanes = 0; lanes <= 1; ++lanes) b->Args({type, degree, rational, lanes, bend});
        }
      }
    }
  }
}
BENCHMARK(BM_SolveNearPoints)->Apply(NearArgs);

/// Inside solves of 64 points inside one mildly curved polynomial
/// tetrahedron (a curved mesh's boundary element): SolveInsideLane (SIMD
/// lanes) against SolveInside point by point, in the same run. Arguments:
/// degree, lanes (1) or point by point (0).
void BM_SolveInsidePoints(benchmark::State& state) {
  const BenchCell cell = MakeCell(CellType::Tet, static_cast<int>(state.range(0)), false, 0.03);
  const CellSolver solver(cell.view());
  const bool lanes = state.range(1) != 0;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  NearPoints points;
  while (points.count() < 64) {
    double ref[3] = {unit(rng), unit(rng), unit(rng)};
    if (ref[0] + ref[1] + ref[2] > 1.0) continue;
    invmap::kernels::MapJet jet;
    invmap::kernels::EvaluateMap(solver.cell(), ref, invmap::kernels::JetOrder::Value, &jet);
    for (int k = 0; k < 3; ++k) points.coord[k].push_back(jet.x[k]);
  }
  invmap::kernels::QueryLane query;
  query.count = points.count();
  for (int k = 0; k < 3; ++k) query.coord[k] = points.coord[k].data();
  LaneResults output(query.count);
  const invmap::kernels::ResultLane& result = output.out;
  bool inside[64];
  for (auto _ : state) {
    if (lanes) {
      solver.SolveInsideLane(query, result, inside);
    } else {
      for (int l = 0; l < query.count; ++l) {
        const double p[3] = {points.coord[0][l], points.coord[1][l], points.coord[2][l]};
        invmap::kernels::CellSolveResult r;
        inside[l] = solver.SolveInside(p, nullptr, &r);
      }
    }
    benchmark::DoNotOptimize(inside);
  }
  state.counters["solves/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * query.count, benchmark::Counter::kIsRate);
  state.SetLabel(lanes ? invmap::kernels::LaneIsaName(invmap::kernels::BestLaneIsa()) : "point by point");
}
BENCHMARK(BM_SolveInsidePoints)->ArgsProduct({{2, 3}, {0, 1}});

}  // namespace

BENCHMARK_MAIN();
