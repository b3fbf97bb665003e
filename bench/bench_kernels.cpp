// Kernel throughput: map evaluations per second and single-cell closest-point
// solves per second, per cell type and degree. Counters are rates.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "kernels/cell_bounds.h"
#include "kernels/cell_solver.h"

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

}  // namespace

BENCHMARK_MAIN();
