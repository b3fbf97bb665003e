#include "engine/trimmed_minima.h"

#include <algorithm>
#include <cmath>

#include "kernels/cell_map.h"
#include "kernels/kkt_point.h"
#include "kernels/own_parameter.h"

namespace invmap::engine {
namespace {

/// Reference coordinates a point of the face's boundary may lie outside its
/// cell's box by and still count as held (the rounding of the knot box).
constexpr double kHoldSlack = 1e-12;
/// The step, in reference coordinates of the cell, along which a trimmed
/// face's descent is classified: far beyond the region's resolution
/// (kernels/tolerances.h: kTrimResolution of the loops' extent), far below
/// any feature of the region a local minimum could sit beside.
constexpr double kDescentStep = 1e-6;

/// The KKT test of a surface cell, and on a trimmed face's cell the side
/// of its region the distance falls toward.
bool GrowsIntoFace(const CellStore& store, std::int64_t cell, const double* ref, const double* point) {
  const kernels::CellSolver& solver = store.solver(cell);
  kernels::MapJet jet;
  kernels::EvaluateMap(solver.cell(), ref, kernels::JetOrder::First, &jet);
  if (kernels::IsKktPoint(solver.cell(), jet, point, ref, solver.size())) return true;
  const kernels::TrimmedCell* trim = solver.trim();
  if (!trim) return false;
  // Not stationary on the face's surface: a minimum only where the way
  // down leaves the region. Along the descent (scaled per parameter by the
  // knot box, a positive factor each: still a way down), one short step.
  const int dim = solver.cell().ambientDim;
  double descent[2] = {0, 0}, longest = 0.0;
  for (int i = 0; i < 2; ++i) {
    for (int k = 0; k < dim; ++k) descent[i] -= (jet.x[k] - point[k]) * jet.d1[k][i];
    longest = std::max(longest, std::abs(descent[i]));
  }
  if (!(longest > 0.0)) return true;
  double own[2];
  trim->ToOwn(ref, own);
  for (int i = 0; i < 2; ++i) own[i] += kDescentStep * trim->paramScale[i] * descent[i] / longest;
  return trim->region->ClassifyPoint(own) == kernels::TrimRegion::Side::Outside;
}

}  // namespace

bool HoldsPoint(const CellStore& store, std::int64_t cell, const double* x, double tolerance, double edgeTolerance,
                kernels::SolveWorkspace* ws, double* ref) {
  const kernels::CellSolver& solver = store.solver(cell);
  const kernels::CellSolveResult on = solver.Solve(x, nullptr, ws);
  if (on.status != kernels::PointStatus::Farther && on.distance <= tolerance) {
    std::copy(on.ref, on.ref + 3, ref);
    return true;
  }
  const kernels::TrimmedCell* trim = solver.trim();
  if (!trim) return false;
  const kernels::CellSolver surface(solver.cell());
  const kernels::CellSolveResult untrimmed = surface.Solve(x, nullptr, ws);
  if (untrimmed.status == kernels::PointStatus::Farther || !(untrimmed.distance <= edgeTolerance)) return false;
  // The region within the tolerance's share of the cell around the point.
  const double share = edgeTolerance / std::max(solver.size(), 1e-300);
  double lo[2], hi[2];
  for (int d = 0; d < 2; ++d) {
    lo[d] = untrimmed.ref[d] - share;
    hi[d] = untrimmed.ref[d] + share;
  }
  if (trim->ClassifySubdomain(lo, hi) == kernels::TrimRegion::Side::Outside) return false;
  std::copy(untrimmed.ref, untrimmed.ref + 3, ref);
  return true;
}

std::vector<std::pair<std::int64_t, std::array<double, 3>>> FaceCellsAtEdgePoint(const CellStore& store,
                                                                                std::int64_t edgeCell,
                                                                                const double* ref) {
  std::vector<std::pair<std::int64_t, std::array<double, 3>>> cells;
  const CellOrigin& edge = store.origin(edgeCell);
  if (edge.edge < 0) return cells;
  double uv[3];
  store.ReportedParameters(edgeCell, ref, uv);
  if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) return cells;
  for (std::int64_t c = store.patchFirstCell(edge.patch); c < store.patchFirstCell(edge.patch + 1); ++c) {
    const CellOrigin& face = store.origin(c);
    if (face.edge >= 0) continue;
    std::array<double, 3> at{0, 0, 0};
    bool holds = true;
    for (int d = 0; d < 2 && holds; ++d) {
      // In the knot box first: an angular direction's map to reference
      // coordinates repeats every turn.
      const double slack = kHoldSlack * (std::abs(face.paramScale[d]) + std::abs(face.paramLo[d]));
      holds = uv[d] >= face.paramLo[d] - slack && uv[d] <= face.paramLo[d] + face.paramScale[d] + slack;
      if (!holds) break;
      const double own = std::clamp(uv[d], face.paramLo[d], face.paramLo[d] + face.paramScale[d]);
      at[d] = std::clamp(kernels::ReferenceOfOwn(face.paramLo[d], face.paramScale[d], (face.angular >> d) & 1, own), 0.0, 1.0);
    }
    if (holds) cells.push_back({c, at});
  }
  return cells;
}

bool MinimumOnCell(const CellStore& store, std::int64_t cell, const double* ref, const double* point) {
  if (store.origin(cell).edge < 0) return GrowsIntoFace(store, cell, ref, point);
  const kernels::CellSolver& solver = store.solver(cell);
  kernels::MapJet jet;
  kernels::EvaluateMap(solver.cell(), ref, kernels::JetOrder::First, &jet);
  if (!kernels::IsKktPoint(solver.cell(), jet, point, ref, solver.size())) return false;
  for (const auto& [face, at] : FaceCellsAtEdgePoint(store, cell, ref)) {
    if (!GrowsIntoFace(store, face, at.data(), point)) return false;
  }
  return true;
}

}  // namespace invmap::engine
