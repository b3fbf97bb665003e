// invmap's oracle ratio: the engine's full time over the time of the cell
// solves alone, on the cell the engine reported, from the cell's center (a
// cell on a CAD face's elementary surface in closed form, as the engine
// solves it).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "bench/peers/harness.h"
#include "engine/cell_store.h"
#include "engine/geometry_validation.h"
#include "kernels/analytic_surface.h"
#include "kernels/cell_solver.h"

namespace invmap::bench {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Per patch, the store's cell of each reported cell index (-1 for none).
/// Not simply the patch's first cell plus the index: a trimmed face has no
/// cell for its spans outside the region, and numbers its edge cells after
/// all of its spans.
std::vector<std::vector<std::int64_t>> CellsByReportedIndex(const engine::CellStore& store) {
  std::vector<std::vector<std::int64_t>> cells(store.numPatches());
  for (std::int64_t c = 0; c < store.size(); ++c) {
    const engine::CellOrigin& origin = store.origin(c);
    std::vector<std::int64_t>& patch = cells[origin.patch];
    if (static_cast<std::int64_t>(patch.size()) <= origin.indexInPatch) patch.resize(origin.indexInPatch + 1, -1);
    patch[origin.indexInPatch] = c;
  }
  return cells;
}

}  // namespace

OracleRun RunOracle(const Geometry& geometry, const PointSet& set, std::int64_t count, const Results& invmapResults,
                    double tolerance) {
  OracleRun run;
  // A second copy of the cells, built the same way as the manifold's, so the
  // oracle reaches the solvers without going through the engine's private Impl.
  if (const GeometryError problem = engine::ValidateGeometry(geometry)) {
    std::fprintf(stderr, "invmap_bench_peers: oracle: %s\n", Describe(problem).c_str());
    std::exit(2);
  }
  const engine::CellStore store = engine::CellStore::Build(geometry, 0);
  const std::vector<std::vector<std::int64_t>> byReported = CellsByReportedIndex(store);
  std::vector<std::int64_t> cells(count, -1);
  for (std::int64_t i = 0; i < count; ++i) {
    if (invmapResults.status[i] != Status::Found) continue;
    cells[i] = byReported[invmapResults.patch[i]][invmapResults.cell[i]];
  }
  std::vector<double> distance(count, std::nan(""));
  kernels::SolveWorkspace workspace;
  // Warm-up: the workspace's first allocations.
  for (std::int64_t i = 0; i < std::min<std::int64_t>(count, 100); ++i) {
    if (cells[i] >= 0) store.solver(cells[i]).Solve(set.point(i), nullptr, &workspace);
  }
  const double t0 = Now();
  for (std::int64_t i = 0; i < count; ++i) {
    if (cells[i] < 0) continue;
    const kernels::CellSolver& solver = store.solver(cells[i]);
    // A volume cell that holds the point needs only its local solve, as in
    // the engine (7.3.2.1); the full cell solve is the fallback.
    kernels::CellSolveResult r;
    const kernels::AnalyticCell* analytic = store.analytic(cells[i]);
    const bool closedForm = analytic && kernels::SolveAnalyticCell(*analytic, set.point(i), kInfinity, &r);
    if (!closedForm && !(solver.isFullRank() && solver.SolveInside(set.point(i), nullptr, &r))) {
      r = solver.Solve(set.point(i), nullptr, &workspace);
    }
    distance[i] = r.distance;
  }
  run.seconds = Now() - t0;
  run.count = count;
  for (std::int64_t i = 0; i < count; ++i) {
    if (cells[i] >= 0 && !(std::abs(distance[i] - invmapResults.distance[i]) <= tolerance)) ++run.disagreements;
  }
  return run;
}

}  // namespace invmap::bench
