// The search for one point's closest point (algorithm 4): its running best
// answer, and how it solves each kind of candidate (a cell, an affine region,
// an affine simplex item) and tries the volume cells that may hold it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/affine_regions.h"
#include "engine/box_distance.h"
#include "engine/bucket_scratch.h"
#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/simplex_items.h"
#include "engine/warm_start.h"
#include "kernels/cell_solver.h"
#include "kernels/reference_faces.h"
#include "kernels/tolerances.h"

namespace invmap::engine {

/// The running answer of one point.
struct PointSearch {
  PointSearch(const CellStore& s, const SimplexItems& items, const double* point, BucketScratch& work,
              std::int64_t warm, const double* warmAt, double maxDistance)
      : store(s), simplices(items), p(point), scratch(work), warmCell(warm), warmRef(warmAt), best(maxDistance) {}

  const CellStore& store;
  const SimplexItems& simplices;
  const double* p;
  BucketScratch& scratch;
  const std::int64_t warmCell;
  const double* warmRef;
  double best;  // starts at the gap tolerance (algorithm 4, line 3)
  std::int64_t bestCell = -1;
  kernels::CellSolveResult bestResult;
  /// The slot of scratch.models holding the best answer's local model (for
  /// the next point's start), or -1 when it is unknown.
  int bestModel = -1;
  int iterations = 0;
  bool inside = false;  // a volume cell holds the point: nothing is closer
  std::vector<std::int64_t>& tried = scratch.triedCells;

  /// Starts from the best answer the bucket's lane solves found (cell -1: none).
  void Seed(std::int64_t cell, const kernels::CellSolveResult& result) {
    if (cell < 0) return;
    best = result.distance;
    bestCell = cell;
    bestResult = result;
    inside = store.isFullRank(cell) && result.distance <= kernels::kDistanceTolerance * store.cellSize(cell);
  }

  /// Before any answer, how far beyond the gap tolerance a cell of `size`
  /// may answer and still be found: its solve's tolerance. A point is none
  /// only when every cell is certified farther than the gap tolerance (its
  /// lower bounds, or a minimum beyond this band), so a point at distance
  /// exactly D (0 for a point on or inside a cell) is never lost to a solve
  /// that lands a rounding's width beyond it (InversionOptions::maxDistance).
  static double GapBand(double size) { return kernels::kDistanceTolerance * size; }

  /// The squared distance a cell must beat: the best's, or before any
  /// answer the gap tolerance widened by the cell's band (equality admitted).
  double Bound2(const kernels::CellSolver& solver) const {
    if (bestCell >= 0) return best * best;
    const double gap = best + GapBand(solver.size());
    return std::nextafter(gap * gap, std::numeric_limits<double>::infinity());
  }

  /// The squared distance within which a box's cells may still beat the
  /// best: the best's, or before any answer the gap tolerance widened by the
  /// largest band of any cell (equality admitted). Without that band a
  /// point on a cell's surface but a rounding's width outside its box (the
  /// box of the control points, the point an evaluation of the cell) was
  /// pruned with a gap tolerance of 0 and came back none.
  double Prune2() const {
    if (bestCell >= 0) return best * best;
    const double gap = best + GapBand(store.largestSize());
    return std::nextafter(gap * gap, std::numeric_limits<double>::infinity());
  }

  /// True when an answer at `distance` from a cell of size size() replaces
  /// the best: a found answer only a strictly nearer one; before any, one
  /// within the gap tolerance and its band (size() is read only then: it
  /// is a cold read for a mesh's triangle). Compared as distances: their
  /// squares overflow beyond about 1e154.
  template <typename Size>
  bool Beats(double distance, const Size& size) const {
    if (bestCell >= 0) return distance < best;
    return distance <= best || distance <= best + GapBand(size());
  }

  /// The diagonal of a region's box.
  double RegionSize(const AffineRegion& region) const;

  /// Algorithm 6: a region is solved as one block, a cell by the cell solver.
  void Solve(std::int64_t subdivision) {
    if (store.isRegion(subdivision)) {
      SolveRegion(store.subdivisionRegion(subdivision));
      return;
    }
    SolveCell(store.subdivisionCell(subdivision));
  }

  void SolveRegion(const AffineRegion& region);

  void Accept(const RegionSolution& r) {
    best = r.distance;
    bestCell = r.cell;
    bestResult = kernels::CellSolveResult();
    bestModel = -1;
    std::copy(r.ref, r.ref + 3, bestResult.ref);
    std::copy(r.closest, r.closest + 3, bestResult.closest);
    bestResult.distance = r.distance;
    bestResult.status = kernels::PointStatus::Converged;
  }

  void SolveCell(std::int64_t cell);

  /// The cell the warm start predicts (engine/warm_start.h) first: the
  /// answer of most points, and its distance bounds the rest of the search
  /// from the start. An affine simplex is solved from its leaf-order copy
  /// (next to the items the traversal reads anyway; on a large mesh its
  /// solver is cold). Returns the cell solved, or -1.
  std::int64_t SolveWarmCell();

  /// Item `i` of the BVH, an affine simplex, in closed form from the
  /// vertices `simplices` keeps in leaf order: CellSolver::Solve's answer
  /// for the cell without reading it. (Solve's box test is left out: the
  /// closed form costs less than reading the box, and an answer beyond the
  /// box's bound cannot beat the best; at an exact tie either may win.)
  void SolveSimplexItem(int i) {
    const int pd = simplices.paramDim(i);
    const int dim = store.dimension();
    const double* vertices[4];
    for (int v = 0; v <= pd; ++v) vertices[v] = simplices.Vertex(i, v);
    kernels::CellSolveResult r;
    kernels::CellSolver::SolveAffineSimplex(pd, dim, vertices, p, &r);
    if (!Beats(r.distance, [&] { return store.cellSize(simplices.cell(i)); })) return;
    Consider(simplices.cell(i), r);
  }

  /// Keeps a cell's answer that beats the best so far (true then; its model
  /// is unknown until the caller sets bestModel).
  bool Consider(std::int64_t cell, const kernels::CellSolveResult& r) {
    if (bestCell >= 0 && !(r.distance < best)) return false;
    best = r.distance;
    bestCell = cell;
    bestResult = r;
    bestModel = -1;
    return true;
  }

  /// A start in `cell` from the best answer so far when both cells tile one
  /// B-spline surface: the best point's patch parameters, clamped into the cell.
  /// The foot of a point whose best cell lost to a neighbour is usually just
  /// across their common edge, where this start lands. Clamped across one
  /// edge, the start slides along it to where the best answer's local model
  /// has its least value on the edge's line: there the tangent plane is
  /// nearly level along the edge, and most often already shows the cell
  /// cannot beat the best (LocalSolve's exclusion) before any Newton step.
  /// A slide of more than half the cell is left out: one answer's quadratic
  /// model says little that far away (on the torus's quarter-circle spans
  /// such slides made it slower).
  bool StartFromBest(std::int64_t cell, double* start) const;

  /// 7.3.2.1: a volume cell whose full-rank Newton solve converges inside
  /// holds the point exactly; only the local solve runs, no global search.
  void TryInside(std::int64_t subdivision);

  /// A walk across the faces of the volume mesh (engine/face_adjacency.h)
  /// to the neighbour beyond the face the point lies past, which usually
  /// holds it: for a tetrahedron the face of its straight corner
  /// tetrahedron, for a hexahedron or wedge the face its inside solve names
  /// (an affine cell's preimage, a curved cell's stop on the boundary:
  /// CellSolver::SolveInside). It starts from `from` when given, else from
  /// the start grid's cell for the point (engine/walk_start_grid.h: about
  /// one face from it; 2.0 cells tried a point on random points in
  /// tetrahedra where a start from the previous point's cell tried 3.2, and
  /// starting from that cell when it holds the point measured slower), else
  /// from the previous point's cell or, for the first point of a bucket, the
  /// cell DescendToVolumeCell picks. The walk only proposes
  /// cells: each answer is an inside solve's exact one, and a point the walk
  /// does not place goes to the full search. The cells tried are kept (the
  /// searches skip them).
  void TryInsideByWalk(const Bvh& bvh, std::int64_t from = -1);

  bool IsTriedCell(std::int64_t cell) const { return std::find(tried.begin(), tried.end(), cell) != tried.end(); }

  /// True when subdivision `s` is a cell that TryInsideByWalk tried.
  bool WasTried(std::int64_t s) const { return !store.isRegion(s) && IsTriedCell(store.subdivisionCell(s)); }

  /// True when subdivision `s` is the cell `cell` (not a region).
  bool IsCell(std::int64_t s, std::int64_t cell) const {
    return cell >= 0 && !store.isRegion(s) && store.subdivisionCell(s) == cell;
  }

  /// A volume region holds the point when its exact solution is the point
  /// itself (to the distance tolerance of its size).
  void TryInsideRegion(const AffineRegion& region);

  /// TryInsideCell for the affine tetrahedron of BVH item `item` (its
  /// vertices, as the item keeps them), once its barycentric coordinates
  /// `lambda` (4) put the point within its hull.
  void TryInsideSimplexItem(int item, const double* const* vertices, const double* lambda);

  /// `cornerLambda`: the cell's CornerBarycentric of the point, when known.
  /// `stopRef` (3 values, optional) receives where a failed inside solve
  /// stopped (CellSolver::SolveInside; NaN when none ran).
  void TryInsideCell(std::int64_t cell, const double* cornerLambda = nullptr, double* stopRef = nullptr);

};

/// Requests from memory what the walk (PointSearch::TryInsideByWalk) of a
/// point reads first, a point or two before its search: the start grid's
/// entry of point `later` (two points ahead) and, for point `next` (one
/// ahead, whose entry the previous call requested), its start cell's
/// vertices (an affine tetrahedron's copy), frame (an affine hexahedron's)
/// or solver and control points,
/// and its origin. Each is a cache miss of its own a point on a mesh larger
/// than the cache; requested ahead, they arrive while the point before is
/// searched. Either point may be null.
inline void PrefetchWalk(const CellStore& store, const SimplexItems& simplices, const double* next,
                         const double* later) {
  const WalkStartGrid& grid = store.faceAdjacency().startGrid();
  if (later) grid.Prefetch(later);
  if (!next) return;
  const std::int64_t start = grid.StartCell(next);
  if (start < 0) return;
  const int item = simplices.item(start);
  const auto lines = [](const void* from, std::size_t bytes) {
    const char* first = static_cast<const char*>(from);
    for (std::size_t at = 0; at < bytes; at += 64) __builtin_prefetch(first + at);
    __builtin_prefetch(first + bytes - 1);
  };
  if (item >= 0) {
    lines(simplices.vertices(item), 4 * 3 * sizeof(double));
  } else if (!store.faceAdjacency().frames().empty()) {
    // (Most cells have a frame then; asking whether this one does would
    // wait on the very line requested.)
    store.faceAdjacency().frames().Prefetch(start);
  } else {
    const kernels::CellSolver& solver = store.solver(start);
    lines(&solver, sizeof(kernels::CellSolver));
  }
  lines(&store.origin(start), sizeof(CellOrigin));
}

// The solves every candidate goes through, defined here so that the searches
// (engine/search_candidates.cpp, engine/search_bvh.cpp) inline them as they
// did when all of this was one file: out of line, these and WriteFound cost
// 0.2 to 0.7% more instructions on the surface and curve workloads
// (callgrind, 3000 near points).

inline void PointSearch::SolveCell(std::int64_t cell) {
  const kernels::CellSolver& solver = store.solver(cell);
  // A cell on a face's elementary surface: its minimum in closed form
  // (global over the cell; no start, no certificate), unless the point is
  // one the closed form leaves to the search (kernels/analytic_surface.h).
  if (const kernels::AnalyticCell* analytic = store.analytic(cell)) {
    kernels::CellSolveResult r;
    if (kernels::SolveAnalyticCell(*analytic, p, Bound2(solver), &r)) {
      if (r.status != kernels::PointStatus::Farther) Consider(cell, r);
      return;
    }
  }
  double start[3];
  const double* initial = cell == warmCell ? warmRef : (StartFromBest(cell, start) ? start : nullptr);
  const int slot = bestModel == 0 ? 1 : 0;
  const kernels::CellSolveResult r = solver.Solve(p, initial, &scratch.workspace, Bound2(solver), &scratch.models[slot]);
  iterations += r.iterations;
  if (r.status == kernels::PointStatus::Farther) return;
  if (Consider(cell, r) && scratch.models[slot].known) bestModel = slot;
}

inline std::int64_t PointSearch::SolveWarmCell() {
  if (warmCell < 0) return -1;
  const int item = simplices.item(warmCell);
  if (item >= 0) {
    SolveSimplexItem(item);
    return warmCell;
  }
  if (store.inRegion(warmCell) || CellBoxDistance2(store.solver(warmCell), p, store.dimension()) > Prune2()) {
    return -1;
  }
  SolveCell(warmCell);
  return warmCell;
}

inline bool PointSearch::StartFromBest(std::int64_t cell, double* start) const {
  if (bestCell < 0) return false;
  const CellOrigin from = store.origin(bestCell);
  const CellOrigin to = store.origin(cell);
  if (from.patch != to.patch || !from.sharedParameters) return false;
  // Surfaces only: on curves, where distinct minima are common (points
  // near the evolute), a start at the cell's end was measured slower than
  // the nearest control point's.
  const int pd = store.shape(cell).paramDim();
  if (pd != 2 || store.shape(bestCell).paramDim() != 2) return false;
  double clampedBy = 0.0;  // how far the clamp moved parameter `across` (patch units)
  int clamped = 0, across = -1;
  for (int i = 0; i < pd; ++i) {
    const double u = from.paramLo[i] + from.paramScale[i] * bestResult.ref[i];
    const double inCell = (u - to.paramLo[i]) / to.paramScale[i];
    start[i] = std::clamp(inCell, 0.0, 1.0);
    if (!std::isfinite(start[i])) return false;
    if (start[i] != inCell) {
      ++clamped;
      across = i;
      clampedBy = (start[i] - inCell) * to.paramScale[i];
    }
  }
  if (clamped != 1 || bestModel < 0) return true;
  // The model's least value (in the best cell's reference coordinates)
  // with parameter `across` held at the edge.
  bool held[3] = {false, false, false};
  held[across] = true;
  double step[3] = {0, 0, 0};
  step[across] = clampedBy / from.paramScale[across];
  const double rhs[3] = {0, 0, 0};
  if (!SolveFree(scratch.models[bestModel].hessian, rhs, pd, held, step)) return true;
  const int along = 1 - across;
  const double slide = step[along] * from.paramScale[along] / to.paramScale[along];
  if (std::abs(slide) <= 0.5) start[along] = std::clamp(start[along] + slide, 0.0, 1.0);
  return true;
}

}  // namespace invmap::engine
