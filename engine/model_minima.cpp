#include "engine/model_minima.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "engine/pair_bounds.h"
#include "engine/trimmed_minima.h"
#include "kernels/kkt_point.h"
#include "kernels/local_solver.h"
#include "kernels/pair_local_solve.h"
#include "kernels/pair_minima.h"
#include "kernels/tolerances.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Every pair of distance cells whose boxes come within `reach`.
std::vector<std::pair<std::int64_t, std::int64_t>> CellPairsWithin(const PlacedModel& a, const PlacedModel& b,
                                                                  double reach) {
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  const Bvh& treeA = a.cells->bvh();
  const Bvh& treeB = b.cells->bvh();
  if (treeA.Nodes().empty() || treeB.Nodes().empty()) return pairs;
  const BoxPairBound bound(RelativeMotion(a.motion, b.motion));
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [na, nb] = stack.back();
    stack.pop_back();
    const BvhBox boxA = treeA.NodeBounds(na), boxB = treeB.NodeBounds(nb);
    if (!(bound.LowerBound(boxA.lo, boxA.hi, boxB.lo, boxB.hi) <= reach)) continue;
    const BvhNode& nodeA = treeA.Nodes()[na];
    const BvhNode& nodeB = treeB.Nodes()[nb];
    if (nodeA.count > 0 && nodeB.count > 0) {
      for (int i = nodeA.first; i < nodeA.first + nodeA.count; ++i) {
        for (int j = nodeB.first; j < nodeB.first + nodeB.count; ++j) {
          const BvhBox& ia = treeA.ItemBoxes()[i];
          const BvhBox& ib = treeB.ItemBoxes()[j];
          if (bound.LowerBound(ia.lo, ia.hi, ib.lo, ib.hi) <= reach) pairs.push_back({treeA.Items()[i], treeB.Items()[j]});
        }
      }
      continue;
    }
    if (nodeB.count > 0 || (nodeA.count == 0 && na <= nb)) {
      stack.push_back({nodeA.first, nb});
      stack.push_back({nodeA.first + 1, nb});
    } else {
      stack.push_back({na, nodeB.first});
      stack.push_back({na, nodeB.first + 1});
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// The distance cells of `m` that hold the world point x, with x's
/// reference coordinates on each (a point solve onto the cell lands on x;
/// a trimmed face's cells as engine/trimmed_minima.h's HoldsPoint says).
std::vector<std::pair<std::int64_t, std::array<double, 3>>> CellsHolding(const PlacedModel& m, const double* world,
                                                                        double tolerance, double edgeTolerance) {
  std::vector<std::pair<std::int64_t, std::array<double, 3>>> out;
  double local[3];
  ToModelFrame(m.motion, world, local);
  const DistanceCells& cells = *m.cells;
  const int dim = cells.dimension();
  kernels::SolveWorkspace workspace;
  for (std::int64_t c = 0; c < cells.size(); ++c) {
    const DistanceCell& cell = cells.cell(c);
    bool inBox = true;
    for (int k = 0; k < dim; ++k) {
      inBox = inBox && local[k] >= cell.boxLo[k] - edgeTolerance && local[k] <= cell.boxHi[k] + edgeTolerance;
    }
    if (!inBox) continue;
    std::array<double, 3> ref{0, 0, 0};
    if (!cell.isFace) {
      if (HoldsPoint(cells.store(), cell.sourceCell, local, tolerance, edgeTolerance, &workspace, ref.data())) {
        out.push_back({c, ref});
      }
      continue;
    }
    // A volume's face gets a solver of its own.
    const kernels::CellSolver solver(cell.view);
    const kernels::CellSolveResult r = solver.Solve(local, nullptr, &workspace);
    if (!(r.distance <= tolerance)) continue;
    out.push_back({c, {r.ref[0], r.ref[1], r.ref[2]}});
  }
  return out;
}

/// Where distance cell `c` of `m` is a volume's face: whether the
/// distance from the world point `other` grows into the volume at the
/// face's point `ref` (the volume cell's KKT test there).
bool GrowsIntoVolume(const PlacedModel& m, std::int64_t c, const double* ref, const double* other) {
  const DistanceCell& cell = m.cells->cell(c);
  if (!cell.isFace) return true;
  double sourceRef[3] = {0, 0, 0}, local[3];
  m.cells->ToSourceRef(c, ref, sourceRef);
  ToModelFrame(m.motion, other, local);
  const kernels::CellSolver& solver = m.cells->store().solver(cell.sourceCell);
  kernels::MapJet jet;
  kernels::EvaluateMap(solver.cell(), sourceRef, kernels::JetOrder::First, &jet);
  return kernels::IsKktPoint(solver.cell(), jet, local, sourceRef, solver.size());
}

/// True when the world point `x` of distance cell `c` of `m` (at `ref` on
/// it) may be a local minimum of the distance to the world point `other`
/// as far as that cell says: its KKT test, on a volume's face also the
/// distance growing into the volume, on a trimmed face's cells and edges
/// the face's own test (engine/trimmed_minima.h).
bool MinimumOnSide(const PlacedModel& m, std::int64_t c, const double* ref, const double* other) {
  const DistanceCell& cell = m.cells->cell(c);
  double local[3];
  ToModelFrame(m.motion, other, local);
  if (!cell.isFace) {
    double sourceRef[3] = {0, 0, 0};
    m.cells->ToSourceRef(c, ref, sourceRef);
    return MinimumOnCell(m.cells->store(), cell.sourceCell, sourceRef, local);
  }
  kernels::MapJet jet;
  kernels::EvaluateMap(cell.view, ref, kernels::JetOrder::First, &jet);
  return kernels::IsKktPoint(cell.view, jet, local, ref, cell.size) && GrowsIntoVolume(m, c, ref, other);
}

}  // namespace

std::vector<CellPairAnswer> AllPairMinima(const PlacedModel& a, const PlacedModel& b, double maxDistance,
                                          bool* certified, ModelDistanceWorkspace* ws) {
  *certified = true;
  const bool trimmed = a.cells->store().hasTrimmedSurfaces() || b.cells->store().hasTrimmedSurfaces();
  std::vector<CellPairAnswer> candidates;
  for (const auto& [ia, ib] : CellPairsWithin(a, b, maxDistance)) {
    const kernels::PairSide sa = PlacedSide(a, ia, 0, true, ws);
    const kernels::PairSide sb = PlacedSide(b, ib, 1, true, ws);
    const kernels::PairMinimaResult found = kernels::PairLocalMinima(sa, sb, maxDistance);
    if (!found.certified) *certified = false;
    for (const kernels::PairMinimum& m : found.minima) {
      CellPairAnswer answer;
      answer.found = true;
      answer.cell[0] = ia;
      answer.cell[1] = ib;
      std::copy(m.refA, m.refA + 3, answer.ref[0]);
      std::copy(m.refB, m.refB + 3, answer.ref[1]);
      std::copy(m.pointA, m.pointA + 3, answer.point[0]);
      std::copy(m.pointB, m.pointB + 3, answer.point[1]);
      answer.distance = m.distance;
      candidates.push_back(answer);
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const CellPairAnswer& x, const CellPairAnswer& y) {
    return x.distance != y.distance ? x.distance < y.distance
                                    : std::make_pair(x.cell[0], x.cell[1]) < std::make_pair(y.cell[0], y.cell[1]);
  });
  const double size = std::max(a.cells->modelSize(), b.cells->modelSize());
  const double onTolerance = 1e-9 * std::max(size, 1e-300);
  const double mergeTolerance = 1e-7 * std::max(size, 1e-300);
  // A CAD model's edges lie within its tolerance of the faces they bound.
  const double edgeTolerance = trimmed ? mergeTolerance : onTolerance;
  auto gap = [](const double* x, const double* y) {
    return std::sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]));
  };
  std::vector<CellPairAnswer> kept;
  for (const CellPairAnswer& candidate : candidates) {
    bool known = false;
    for (const CellPairAnswer& k : kept) {
      known = known || (gap(k.point[0], candidate.point[0]) <= mergeTolerance &&
                        gap(k.point[1], candidate.point[1]) <= mergeTolerance);
    }
    if (known) continue;
    // Every pair of cells holding the two points must have them as a KKT point.
    const auto holdersA = CellsHolding(a, candidate.point[0], onTolerance, edgeTolerance);
    const auto holdersB = CellsHolding(b, candidate.point[1], onTolerance, edgeTolerance);
    bool minimum = true;
    if (trimmed) {
      // The joint KKT conditions split into each side's with the other
      // point held (their domains are a product), which a trimmed face's
      // cells and edges judge with its region (engine/trimmed_minima.h). A
      // trimmed face's cell answers only points of its region: one of its
      // boundary it does not land on is its edges' to judge.
      minimum = MinimumOnSide(a, candidate.cell[0], candidate.ref[0], candidate.point[1]) &&
                MinimumOnSide(b, candidate.cell[1], candidate.ref[1], candidate.point[0]);
      for (const auto& [ca, refA] : holdersA) minimum = minimum && MinimumOnSide(a, ca, refA.data(), candidate.point[1]);
      for (const auto& [cb, refB] : holdersB) minimum = minimum && MinimumOnSide(b, cb, refB.data(), candidate.point[0]);
    } else {
      for (const auto& [ca, refA] : holdersA) {
        minimum = minimum && GrowsIntoVolume(a, ca, refA.data(), candidate.point[1]);
        for (const auto& [cb, refB] : holdersB) {
          if (!minimum) break;
          const kernels::PairSide sa = PlacedSide(a, ca, 0, false, ws);
          const kernels::PairSide sb = PlacedSide(b, cb, 1, false, ws);
          const kernels::PairLayout layout(sa.cell.shape, sb.cell.shape);
          double w[kernels::kMaxPairParams];
          std::copy(refA.begin(), refA.begin() + layout.paramDim(0), w);
          std::copy(refB.begin(), refB.begin() + layout.paramDim(1), w + layout.paramDim(0));
          kernels::PairJet jet;
          kernels::EvaluatePair(sa, sb, layout, w, kernels::JetOrder::Second, &jet);
          minimum = kernels::CheckPairKkt(layout, jet, w, sa.cell.ambientDim, sa.size + sb.size).kkt;
        }
      }
      for (const auto& [cb, refB] : holdersB) minimum = minimum && GrowsIntoVolume(b, cb, refB.data(), candidate.point[0]);
    }
    if (!minimum) continue;
    CellPairAnswer answer = candidate;
    for (int side = 0; side < 2; ++side) {
      const PlacedModel& m = side == 0 ? a : b;
      answer.sourceCell[side] = m.cells->cell(answer.cell[side]).sourceCell;
      m.cells->ToSourceRef(answer.cell[side], answer.ref[side], answer.sourceRef[side]);
    }
    if (answer.distance <= kernels::kDistanceTolerance * size) answer.distance = 0.0;
    kept.push_back(answer);
  }
  return kept;
}

}  // namespace invmap::engine
