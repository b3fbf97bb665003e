#include "engine/invert_batch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/parallel.h"
#include "engine/affine_regions.h"
#include "engine/nearest_cells.h"
#include "engine/spatial_sort.h"
#include "engine/warm_start.h"
#include "kernels/active_set.h"
#include "kernels/tolerances.h"

namespace invmap::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A child of a wide node waiting on the search's stack: its lower bound,
/// and the node (count 0) or the leaf's items it stands for.
struct WideEntry {
  double lowerBound2;
  std::int32_t first;
  std::int32_t count;
};

/// Scratch of one task, reused across its buckets so that the per-point path
/// never allocates once warm.
struct BucketScratch {
  std::vector<CellCandidate> candidates;
  // The candidates each point of the bucket searches (those the lane solve
  // has not covered), with their boxes copied once per bucket into
  // contiguous arrays (lo then hi, per axis): every point reads them, and
  // the solvers that hold them are large and scattered.
  std::vector<int> searched;
  std::vector<double> searchedBox[6];
  std::vector<int> stack;
  std::vector<std::pair<double, int>> order;  // (point's lower bound^2, candidate)
  std::vector<std::pair<double, int>> insideOrder;  // (-inside score, candidate or BVH item)
  std::vector<WideEntry> wideStack;
  std::vector<std::int64_t> triedCells;             // volume cells already tried for the point
  kernels::SolveWorkspace workspace;
  // The local models of a point's best answer so far and of the cell being
  // solved (PointSearch::bestModel says which slot is the best's).
  kernels::AnswerModel models[2];
  // The bucket's points as lanes (structure of arrays) and their best answer
  // over the affine simplex candidates, solved a cell at a time for all lanes.
  std::vector<double> laneCoord[3];
  std::vector<double> laneRef[3], laneClosest[3], laneDistance;
  std::vector<kernels::PointStatus> laneStatus;
  std::vector<std::int64_t> laneBestCell;
  std::vector<kernels::CellSolveResult> laneBest;
};

/// Distance from x to the interval [lo, hi] along one axis.
double AxisGap(double lo, double x, double hi) { return std::max({lo - x, 0.0, x - hi}); }

/// Squared distance from a point to the box [lo, hi].
double BoxDistance2(const double* lo, const double* hi, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = AxisGap(lo[k], p[k], hi[k]);
    d2 += d * d;
  }
  return d2;
}

double BoxDistance2(const BvhBox& box, const double* p, int dim) { return BoxDistance2(box.lo, box.hi, p, dim); }

/// Squared distance from a point to a cell's control-point box.
double CellBoxDistance2(const kernels::CellSolver& solver, const double* p, int dim) {
  return BoxDistance2(solver.boxLo(), solver.boxHi(), p, dim);
}

/// True for a candidate that SolveAffineSimplexLanes already solved.
bool SolvedAsLanes(const CellStore& store, std::int64_t subdivision) {
  return store.affineSimplexCell(subdivision) >= 0;
}

/// Fills scratch.searched and scratch.searchedBox from the bucket's candidates.
void GatherSearchedCandidates(const CellStore& store, bool lanesSolved, BucketScratch& scratch) {
  scratch.searched.clear();
  for (int c = 0; c < static_cast<int>(scratch.candidates.size()); ++c) {
    if (!(lanesSolved && SolvedAsLanes(store, scratch.candidates[c].cell))) scratch.searched.push_back(c);
  }
  const std::size_t n = scratch.searched.size();
  for (std::vector<double>& axis : scratch.searchedBox) axis.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::int64_t s = scratch.candidates[scratch.searched[j]].cell;
    for (int k = 0; k < store.dimension(); ++k) {
      scratch.searchedBox[k][j] = store.subdivisionBoxLo(s)[k];
      scratch.searchedBox[3 + k][j] = store.subdivisionBoxHi(s)[k];
    }
  }
}

/// Squared distance from a point to the box of searched candidate j.
double SearchedBoxDistance2(const BucketScratch& scratch, std::size_t j, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = AxisGap(scratch.searchedBox[k][j], p[k], scratch.searchedBox[3 + k][j]);
    d2 += d * d;
  }
  return d2;
}

void WriteNotFound(Status status, std::int64_t i, Results* results) {
  results->status[i] = status;
  results->patch[i] = -1;
  results->cell[i] = -1;
  for (int k = 0; k < 3; ++k) {
    results->params[3 * i + k] = kNaN;
    results->closest[3 * i + k] = kNaN;
  }
  results->distance[i] = kNaN;
  results->iterations[i] = 0;
}

/// Candidates of the bucket's list beyond this many are better found per
/// point: far from the geometry, algorithm 3's box upper bounds admit most of
/// the cells, and a best-first traversal that tightens with each solved cell
/// visits far fewer. The list's traversal gives up as soon as it has
/// collected more than this many, though the final bound might have trimmed
/// some of them: on every workload of more than a few dozen cells (the bicubic
/// surface, the triangle mesh) nearly all lists are given up, so the attempt
/// is kept short: collecting twice as many cost 1.5% (mesh) to 3% (surface)
/// of the time, four times as many 3 to 7%.
constexpr std::size_t kMaxBucketCandidates = 24;

/// Steps of the walk through a tetrahedral mesh before the BVH takes over.
constexpr int kMaxWalk = 8;

/// A cell to start the walk of a point that has no previous point (the first
/// of its bucket): down the BVH, always into the child whose box is nearer
/// (holds the point, when one does), to the leaf's cell whose box is
/// nearest. It depends on the point alone, as every answer must. -1 when
/// that cell is part of an affine region or not a volume.
std::int64_t DescendToVolumeCell(const Bvh& bvh, const CellStore& store, const double* p) {
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  if (nodes.empty()) return -1;
  const int dim = store.dimension();
  int index = 0;
  while (nodes[index].count == 0) {
    const int first = nodes[index].first;
    const double near2 = BoxDistance2(bvh.NodeBounds(first), p, dim);
    index = near2 <= BoxDistance2(bvh.NodeBounds(first + 1), p, dim) ? first : first + 1;
  }
  const BvhNode& leaf = nodes[index];
  int nearest = leaf.first;
  double nearest2 = kInf;
  for (int i = leaf.first; i < leaf.first + leaf.count && nearest2 > 0.0; ++i) {
    const double d2 = BoxDistance2(bvh.ItemBoxes()[i], p, dim);
    if (d2 < nearest2) {
      nearest2 = d2;
      nearest = i;
    }
  }
  const int item = bvh.Items()[nearest];
  if (store.isRegion(item)) return -1;
  const std::int64_t cell = store.subdivisionCell(item);
  return store.solver(cell).isFullRank() ? cell : -1;
}

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
    const kernels::CellSolver& solver = store.solver(cell);
    inside = solver.isFullRank() && result.distance <= kernels::kDistanceTolerance * solver.size();
  }

  /// The squared distance a cell must beat.
  double Bound2() const { return bestCell >= 0 ? best * best : std::nextafter(best * best, kInf); }

  /// True when an answer at `distance` replaces the best: the gap tolerance
  /// admits equality, a found answer only a strictly nearer one. (Compared
  /// as distances: their squares overflow beyond about 1e154.)
  bool Beats(double distance) const { return bestCell >= 0 ? distance < best : distance <= best; }

  /// Algorithm 6: a region is solved as one block, a cell by the cell solver.
  void Solve(std::int64_t subdivision) {
    if (store.isRegion(subdivision)) {
      SolveRegion(store.subdivisionRegion(subdivision));
      return;
    }
    SolveCell(store.subdivisionCell(subdivision));
  }

  void SolveRegion(const AffineRegion& region) {
    const RegionSolution r = SolveAffineRegion(region, p);
    if (!Beats(r.distance)) return;
    Accept(r);
  }

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

  void SolveCell(std::int64_t cell) {
    const kernels::CellSolver& solver = store.solver(cell);
    double start[3];
    const double* initial = cell == warmCell ? warmRef : (StartFromBest(cell, start) ? start : nullptr);
    const int slot = bestModel == 0 ? 1 : 0;
    const kernels::CellSolveResult r = solver.Solve(p, initial, &scratch.workspace, Bound2(), &scratch.models[slot]);
    iterations += r.iterations;
    if (r.status == kernels::PointStatus::Farther) return;
    if (Consider(cell, r) && scratch.models[slot].known) bestModel = slot;
  }

  /// The cell the warm start predicts (engine/warm_start.h) first: the
  /// answer of most points, and its distance bounds the rest of the search
  /// from the start. An affine simplex is solved from its leaf-order copy
  /// (next to the items the traversal reads anyway; on a large mesh its
  /// solver is cold). Returns the cell solved, or -1.
  std::int64_t SolveWarmCell() {
    if (warmCell < 0) return -1;
    const int item = simplices.item(warmCell);
    if (item >= 0) {
      SolveSimplexItem(item);
      return warmCell;
    }
    if (store.inRegion(warmCell) || CellBoxDistance2(store.solver(warmCell), p, store.dimension()) > best * best) {
      return -1;
    }
    SolveCell(warmCell);
    return warmCell;
  }

  /// Item `i` of the BVH, an affine simplex, in closed form from the
  /// vertices `simplices` keeps in leaf order: CellSolver::Solve's answer
  /// for the cell without reading it. (Solve's box test is left out: the
  /// closed form costs less than reading the box, and an answer beyond the
  /// box's bound cannot beat the best; at an exact tie either may win.)
  void SolveSimplexItem(int i) {
    const int pd = simplices.paramDim(i);
    const int dim = store.dimension();
    const double* vertices[4];
    for (int v = 0; v <= pd; ++v) vertices[v] = simplices.vertices(i) + v * dim;
    kernels::CellSolveResult r;
    kernels::CellSolver::SolveAffineSimplex(pd, dim, vertices, p, &r);
    if (!Beats(r.distance)) return;
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
  bool StartFromBest(std::int64_t cell, double* start) const {
    if (bestCell < 0) return false;
    const CellOrigin& from = store.origin(bestCell);
    const CellOrigin& to = store.origin(cell);
    if (from.patch != to.patch || !from.sharedParameters) return false;
    // Surfaces only: on curves, where distinct minima are common (points
    // near the evolute), a start at the cell's end was measured slower than
    // the nearest control point's.
    const int pd = store.solver(cell).cell().shape.paramDim();
    if (pd != 2 || store.solver(bestCell).cell().shape.paramDim() != 2) return false;
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

  /// 7.3.2.1: a volume cell whose full-rank Newton solve converges inside
  /// holds the point exactly; only the local solve runs, no global search.
  void TryInside(std::int64_t subdivision) {
    if (store.isRegion(subdivision)) {
      TryInsideRegion(store.subdivisionRegion(subdivision));
      return;
    }
    TryInsideCell(store.subdivisionCell(subdivision));
  }

  /// The previous point's cell first (7.3.2.1 with a warm start): in Morton
  /// order a volume's points come in runs inside the same cell. Then, in a
  /// tetrahedral mesh, a walk: across the face of each cell's straight
  /// corner tetrahedron that the point lies beyond, to the neighbour there,
  /// which usually holds it. The first point of a bucket starts from the
  /// cell DescendToVolumeCell picks. The cells tried are kept (the searches
  /// skip them).
  void TryInsideByWalk(const Bvh& bvh) {
    tried.clear();
    const std::int64_t start = warmCell >= 0 ? warmCell : DescendToVolumeCell(bvh, store, p);
    if (start < 0 || store.inRegion(start)) return;
    if (!store.solver(start).isFullRank()) return;
    const TetAdjacency& adjacency = store.tetAdjacency();
    std::int64_t cell = start;
    for (int step = 0;; ++step) {
      // One corner barycentric evaluation per cell serves both the inside
      // solve's start and the walk's direction.
      double lambda[4];
      const bool haveLambda = store.solver(cell).CornerBarycentric(p, lambda);
      if (CellBoxDistance2(store.solver(cell), p, store.dimension()) == 0.0) {
        TryInsideCell(cell, haveLambda ? lambda : nullptr);
        tried.push_back(cell);
      }
      if (inside || step == kMaxWalk || adjacency.empty() || !haveLambda) return;
      const int exit = static_cast<int>(std::min_element(lambda, lambda + 4) - lambda);
      // Inside the straight tetrahedron of a cell that did not hold the
      // point: the walk has no direction left.
      if (lambda[exit] >= 0.0) return;
      cell = adjacency.Neighbor(cell, exit);
      if (cell < 0 || store.inRegion(cell) || IsTriedCell(cell)) return;
    }
  }

  bool IsTriedCell(std::int64_t cell) const { return std::find(tried.begin(), tried.end(), cell) != tried.end(); }

  /// True when subdivision `s` is a cell that TryInsideByWalk tried.
  bool WasTried(std::int64_t s) const { return !store.isRegion(s) && IsTriedCell(store.subdivisionCell(s)); }

  /// True when subdivision `s` is the cell `cell` (not a region).
  bool IsCell(std::int64_t s, std::int64_t cell) const {
    return cell >= 0 && !store.isRegion(s) && store.subdivisionCell(s) == cell;
  }

  /// A volume region holds the point when its exact solution is the point
  /// itself (to the distance tolerance of its size).
  void TryInsideRegion(const AffineRegion& region) {
    if (region.paramDim != store.dimension()) return;
    const RegionSolution r = SolveAffineRegion(region, p);
    double size2 = 0.0;
    for (int k = 0; k < store.dimension(); ++k) size2 += (region.boxHi[k] - region.boxLo[k]) * (region.boxHi[k] - region.boxLo[k]);
    if (r.distance > kernels::kDistanceTolerance * std::sqrt(size2)) return;
    Accept(r);
    inside = true;
  }

  /// `cornerLambda`: the cell's CornerBarycentric of the point, when known.
  void TryInsideCell(std::int64_t cell, const double* cornerLambda = nullptr) {
    const kernels::CellSolver& solver = store.solver(cell);
    if (!solver.isFullRank()) return;
    kernels::CellSolveResult r;
    if (solver.SolveInside(p, cell == warmCell ? warmRef : nullptr, &r, cornerLambda)) {
      iterations += r.iterations;
      best = r.distance;
      bestCell = cell;
      bestResult = r;
      bestModel = -1;
      inside = true;
    } else {
      iterations += r.iterations;
    }
  }
};

/// Algorithm 4 over the bucket's candidate list: in a volume the cells whose
/// box holds the point, then the predicted cell, then the rest.
void SearchCandidates(PointSearch& search) {
  const CellStore& store = search.store;
  const int dim = store.dimension();
  std::vector<std::pair<double, int>>& heap = search.scratch.order;
  const std::vector<CellCandidate>& candidates = search.scratch.candidates;
  const std::vector<int>& searched = search.scratch.searched;
  if (store.hasVolumeCells() && !search.inside) {
    // The cells whose box holds the point, likeliest first (by the point's
    // place in the straight tetrahedron of the cell's vertices).
    std::vector<std::pair<double, int>>& boxes = search.scratch.insideOrder;
    boxes.clear();
    for (std::size_t j = 0; j < searched.size(); ++j) {
      const int c = searched[j];
      if (SearchedBoxDistance2(search.scratch, j, search.p, dim) != 0.0 || search.WasTried(candidates[c].cell)) continue;
      const std::int64_t s = candidates[c].cell;
      const double score = store.isRegion(s) ? 0.0 : store.solver(store.subdivisionCell(s)).InsideScore(search.p);
      boxes.emplace_back(-score, c);
    }
    std::stable_sort(boxes.begin(), boxes.end(),
                     [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
    for (const auto& [negativeScore, c] : boxes) {
      if (search.inside) break;
      search.TryInside(candidates[c].cell);
    }
  }
  if (search.inside) return;
  // The predicted cell first when it is one of the candidates left (not a
  // lane's: those are solved already).
  std::int64_t seeded = -1;
  for (const int c : searched) {
    if (search.IsCell(candidates[c].cell, search.warmCell)) seeded = search.SolveWarmCell();
  }
  // Then the others that can still beat the best, in the order of this
  // point's own lower bound (popped lazily from a heap: the search usually
  // stops after the first few). The best only shrinks, so a candidate left
  // out here would never have been solved.
  heap.clear();
  for (std::size_t j = 0; j < searched.size(); ++j) {
    const double lowerBound2 = SearchedBoxDistance2(search.scratch, j, search.p, dim);
    if (lowerBound2 <= search.best * search.best && !search.IsCell(candidates[searched[j]].cell, seeded)) {
      heap.emplace_back(lowerBound2, searched[j]);
    }
  }
  const auto later = [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a > b; };
  std::make_heap(heap.begin(), heap.end(), later);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const auto [lowerBound2, c] = heap.back();
    heap.pop_back();
    if (lowerBound2 > search.best * search.best) break;
    search.Solve(candidates[c].cell);
  }
}

/// Algorithm 4 with the candidates generated lazily: a traversal of the BVH
/// cut at the best distance so far.
void SearchBvh(const Bvh& bvh, const WideBvh& wide, const SimplexItems& simplices, PointSearch& search) {
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  if (nodes.empty()) return;
  const int dim = search.store.dimension();
  const std::vector<BvhBox>& itemBoxes = bvh.ItemBoxes();
  const std::vector<int>& items = bvh.Items();
  // First the volume cells whose box holds the point (the caller has tried
  // the previous point's cell and the walk from it): any whose straight
  // corner tetrahedron holds the point (tried at once: that is almost always
  // the cell, and the traversal stops there), then the others, likeliest
  // first (as in SearchCandidates).
  const CellStore& store = search.store;
  std::vector<int>& stack = search.scratch.stack;
  std::vector<std::pair<double, int>>& boxes = search.scratch.insideOrder;
  boxes.clear();
  stack.assign(store.hasVolumeCells() && !search.inside ? 1 : 0, 0);
  while (!stack.empty() && !search.inside) {
    const int index = stack.back();
    stack.pop_back();
    if (BoxDistance2(bvh.NodeBounds(index), search.p, dim) > 0.0) continue;
    const BvhNode& node = nodes[index];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count && !search.inside; ++i) {
        if (BoxDistance2(itemBoxes[i], search.p, dim) > 0.0 || search.WasTried(items[i])) continue;
        const double score =
            store.isRegion(items[i]) ? 0.0 : store.solver(store.subdivisionCell(items[i])).InsideScore(search.p);
        if (score >= 0.0) {
          search.TryInside(items[i]);
        } else {
          boxes.emplace_back(-score, items[i]);
        }
      }
    } else {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
    }
  }
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
  for (const auto& [negativeScore, item] : boxes) {
    if (search.inside) break;
    search.TryInside(item);
  }
  if (search.inside) return;
  const std::int64_t seeded = search.SolveWarmCell();
  // Depth first over the wide tree, nearest child first; an entry is
  // skipped when its lower bound (recorded when it was pushed) no longer
  // beats the best distance.
  const std::vector<WideNode>& wideNodes = wide.Nodes();
  const WidePoint point = wide.Prepare(search.p);
  std::vector<WideEntry>& pending = search.scratch.wideStack;
  pending.clear();
  pending.push_back({0.0, 0, 0});
  while (!pending.empty()) {
    const WideEntry entry = pending.back();
    pending.pop_back();
    if (entry.lowerBound2 > search.best * search.best) continue;
    if (entry.count > 0) {
      for (int i = entry.first; i < entry.first + entry.count; ++i) {
        // An affine simplex is solved outright: its closed form costs less
        // than reading its two boxes (the traversal waits on memory).
        const std::int64_t simplexCell = simplices.cell(i);
        if (simplexCell >= 0) {
          if (simplexCell != seeded) search.SolveSimplexItem(i);
          continue;
        }
        if (BoxDistance2(itemBoxes[i], search.p, dim) > search.best * search.best) continue;
        if (WideBvh::OrientedDistance2(wide.ItemOrientedBox(i), point) > search.best * search.best) continue;
        if (search.IsCell(items[i], seeded)) continue;
        search.Solve(items[i]);
      }
      continue;
    }
    const WideNode& node = wideNodes[entry.first];
    double box2[4], bound2[4];
    WideBvh::ChildDistances2(node, point, box2, bound2);
    // The children within the best distance, pushed farthest first. Nearest
    // by box, not by the tighter bound: on the wavy surface that order finds
    // the closest cell sooner (the solved cells of a near point ~20% fewer,
    // measured), and the tighter bound still prunes.
    WideEntry near[4];
    double order[4];
    int n = 0;
    for (int c = 0; c < 4; ++c) {
      // An unused slot is skipped outright: with no best distance yet (an
      // infinite gap tolerance, or a squared distance that overflows) its
      // infinite bound would pass the test.
      if (node.count[c] < 0 || !(bound2[c] <= search.best * search.best)) continue;
      const WideEntry child{bound2[c], node.first[c], node.count[c]};
      int at = n++;
      for (; at > 0 && order[at - 1] < box2[c]; --at) {
        near[at] = near[at - 1];
        order[at] = order[at - 1];
      }
      near[at] = child;
      order[at] = box2[c];
    }
    // The children's memory is requested now, while the nearer ones are
    // searched: on large meshes the traversal waits on cache misses.
    for (int c = 0; c < n; ++c) {
      if (near[c].count == 0) {
        for (int line = 0; line < static_cast<int>(sizeof(WideNode)); line += 64) {
          __builtin_prefetch(reinterpret_cast<const char*>(&wideNodes[near[c].first]) + line);
        }
      } else if (simplices.empty()) {
        __builtin_prefetch(&itemBoxes[near[c].first]);
        __builtin_prefetch(&wide.ItemOrientedBox(near[c].first));
      } else {
        simplices.Prefetch(near[c].first, near[c].count);
      }
    }
    for (int c = 0; c < n; ++c) pending.push_back(near[c]);
  }
}

/// Step 5 of the batch (DESIGN.md): the bucket's points that target an affine
/// segment, triangle or tetrahedron are solved together, one candidate cell
/// at a time for all lanes, by the vectorized closed form; each lane keeps
/// its best. Returns false (nothing done) when no candidate is one.
bool SolveAffineSimplexLanes(const CellStore& store, const QueryPoints& points, std::int64_t first, std::int64_t count,
                             double maxDistance, BucketScratch& scratch) {
  bool any = false;
  for (const CellCandidate& candidate : scratch.candidates) any = any || SolvedAsLanes(store, candidate.cell);
  if (!any) return false;
  const int dim = store.dimension();
  const int lanes = static_cast<int>(count);
  for (int k = 0; k < 3; ++k) {
    scratch.laneCoord[k].resize(lanes);
    scratch.laneRef[k].resize(lanes);
    scratch.laneClosest[k].resize(lanes);
  }
  scratch.laneDistance.resize(lanes);
  scratch.laneStatus.resize(lanes);
  scratch.laneBestCell.assign(lanes, -1);
  scratch.laneBest.resize(lanes);
  for (int l = 0; l < lanes; ++l)
    for (int k = 0; k < 3; ++k) scratch.laneCoord[k][l] = k < dim ? points.coord[k][first + l] : 0.0;
  kernels::QueryLane query;
  query.count = lanes;
  kernels::ResultLane result;
  for (int k = 0; k < 3; ++k) {
    query.coord[k] = scratch.laneCoord[k].data();
    result.ref[k] = scratch.laneRef[k].data();
    result.closest[k] = scratch.laneClosest[k].data();
  }
  result.distance = scratch.laneDistance.data();
  result.status = scratch.laneStatus.data();
  for (const CellCandidate& candidate : scratch.candidates) {
    if (!SolvedAsLanes(store, candidate.cell)) continue;
    const std::int64_t cell = store.subdivisionCell(candidate.cell);
    store.solver(cell).SolveLane(query, result, &scratch.workspace);
    for (int l = 0; l < lanes; ++l) {
      if (scratch.laneStatus[l] == kernels::PointStatus::InvalidInput) continue;
      const double d = scratch.laneDistance[l];
      // As PointSearch: the gap tolerance admits equality, a found answer
      // only a strictly better one (so ties keep the earlier candidate).
      if (scratch.laneBestCell[l] >= 0 ? !(d < scratch.laneBest[l].distance) : !(d <= maxDistance)) continue;
      kernels::CellSolveResult& best = scratch.laneBest[l];
      for (int k = 0; k < 3; ++k) {
        best.ref[k] = scratch.laneRef[k][l];
        best.closest[k] = scratch.laneClosest[k][l];
      }
      best.distance = d;
      best.status = scratch.laneStatus[l];
      best.iterations = 0;
      scratch.laneBestCell[l] = cell;
    }
  }
  return true;
}

/// Writes one point's answer at position `index` of `results` (its place in
/// the chunk's Morton order) and keeps it as the next point's warm start.
void WriteFound(const CellStore& store, const PointSearch& search, std::int64_t index, WarmStart* warm,
                Results* results) {
  if (search.bestCell < 0) {
    WriteNotFound(Status::None, index, results);
    results->iterations[index] = search.iterations;
    return;
  }
  const int dim = store.dimension();
  const CellOrigin& origin = store.origin(search.bestCell);
  const kernels::CellSolveResult& r = search.bestResult;
  const int pd = kernels::CellShape::ParamDimOf(origin.type);
  // Exactly in the reference domain: the solves leave a coordinate or a
  // simplex's sum an ulp outside it now and then.
  double ref[3] = {r.ref[0], r.ref[1], r.ref[2]};
  kernels::SnapToDomain(origin.type, ref);
  // A cell as wide as the space (a volume, or a surface in the plane) that
  // holds the point, to the distance tolerance of its size: the point is
  // its own closest point, at distance 0 (the map at the solved parameters
  // would be an ulp or a Newton residual off it).
  const bool holds =
      search.inside ||
      (pd == dim && r.distance <= kernels::kDistanceTolerance * store.solver(search.bestCell).size());
  results->status[index] = Status::Found;
  results->patch[index] = origin.patch;
  results->cell[index] = origin.indexInPatch;
  for (int k = 0; k < 3; ++k) {
    results->params[3 * index + k] = k < pd ? origin.paramLo[k] + origin.paramScale[k] * ref[k] : kNaN;
    results->closest[3 * index + k] = k < dim ? (holds ? search.p[k] : r.closest[k]) : 0.0;
  }
  // Beyond about 1e154 the solvers' squared distances overflow: measure
  // such an answer's distance from its closest point instead.
  results->distance[index] =
      holds ? 0.0
      : std::isfinite(r.distance)
          ? r.distance
          : std::hypot(r.closest[0] - search.p[0], r.closest[1] - search.p[1], r.closest[2] - search.p[2]);
  results->iterations[index] = search.iterations;
  warm->cell = search.bestCell;
  for (int k = 0; k < 3; ++k) {
    warm->point[k] = search.p[k];
    warm->ref[k] = r.ref[k];
    warm->closest[k] = r.closest[k];
  }
  warm->model.known = search.bestModel >= 0;
  if (warm->model.known) warm->model = search.scratch.models[search.bestModel];
}

/// The box of the finite points of `points` (lo = hi = 0 when there is
/// none), reduced over blocks in parallel: min and max are exact, so the box
/// does not depend on the threads.
void FinitePointBounds(const QueryPoints& points, int dim, int threads, double* lo, double* hi) {
  struct BlockBox {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    bool any = false;  ///< The block holds a finite point.
  };
  constexpr std::int64_t kBlock = 1 << 16;
  std::vector<BlockBox> blocks(static_cast<std::size_t>((points.count + kBlock - 1) / kBlock));
  ForEachBlock(
      ExecutionPolicy::Par, static_cast<std::int64_t>(blocks.size()), 1,
      [&](std::int64_t firstBlock, std::int64_t endBlock) {
        for (std::int64_t b = firstBlock; b < endBlock; ++b) {
          BlockBox& box = blocks[b];
          for (std::int64_t i = b * kBlock; i < std::min(points.count, (b + 1) * kBlock); ++i) {
            bool finite = true;
            for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(points.coord[k][i]);
            if (!finite) continue;
            for (int k = 0; k < dim; ++k) {
              const double x = points.coord[k][i];
              box.lo[k] = box.any ? std::min(box.lo[k], x) : x;
              box.hi[k] = box.any ? std::max(box.hi[k], x) : x;
            }
            box.any = true;
          }
        }
      },
      threads);
  bool any = false;
  for (const BlockBox& box : blocks) {
    if (!box.any) continue;
    for (int k = 0; k < dim; ++k) {
      lo[k] = any ? std::min(lo[k], box.lo[k]) : box.lo[k];
      hi[k] = any ? std::max(hi[k], box.hi[k]) : box.hi[k];
    }
    any = true;
  }
}

/// Points a chunk of buckets holds (see InvertBatch).
constexpr std::int64_t kSortedChunk = 1 << 16;

/// Sizes every array of `results` for `count` points.
void ResizeResults(std::int64_t count, Results* results) {
  const std::size_t n = static_cast<std::size_t>(count);
  results->status.resize(n);
  results->patch.resize(n);
  results->cell.resize(n);
  results->params.resize(3 * n);
  results->closest.resize(3 * n);
  results->distance.resize(n);
  results->iterations.resize(n);
}

/// Rows [begin, end) of `from` (`width` values each) written to rows
/// to[begin..end) of *into.
template <typename T>
void ScatterRows(const std::vector<T>& from, const std::int64_t* to, std::int64_t begin, std::int64_t end, int width,
                 std::vector<T>* into) {
  for (std::int64_t s = begin; s < end; ++s) {
    for (int k = 0; k < width; ++k) (*into)[width * to[s] + k] = from[width * s + k];
  }
}

/// Answers [begin, end) of `source` written to answers to[begin..end) of
/// *target. One array at a time: each answer lands on cache lines of its
/// own in every array, and a loop over all seven arrays at once kept that
/// many streams of misses open (the whole scatter 1.25x slower, measured on
/// a million random points).
void ScatterResults(const Results& source, const std::int64_t* to, std::int64_t begin, std::int64_t end,
                    Results* target) {
  ScatterRows(source.status, to, begin, end, 1, &target->status);
  ScatterRows(source.patch, to, begin, end, 1, &target->patch);
  ScatterRows(source.cell, to, begin, end, 1, &target->cell);
  ScatterRows(source.params, to, begin, end, 3, &target->params);
  ScatterRows(source.closest, to, begin, end, 3, &target->closest);
  ScatterRows(source.distance, to, begin, end, 1, &target->distance);
  ScatterRows(source.iterations, to, begin, end, 1, &target->iterations);
}

/// Inverts `points` (a run of the Morton order that starts a bucket), in
/// parallel over its buckets of `bucketSize` points; answer s of `sorted` is
/// that of point s.
void InvertBuckets(const CellStore& store, const Bvh& bvh, const WideBvh& wide, const SimplexItems& simplices,
                   const QueryPoints& points, int bucketSize, const InversionOptions& options, Results* sorted) {
  const std::int64_t n = points.count;
  const int dim = store.dimension();
  const double maxDistance = options.maxDistance;
  ForEachBlock(
      ExecutionPolicy::Par, (n + bucketSize - 1) / bucketSize, 8,
      [&](std::int64_t bucketBegin, std::int64_t bucketEnd) {
        // One scratch per worker thread, kept across batches: warm calls do
        // not allocate. It holds no state that changes any result.
        thread_local BucketScratch scratch;
        for (std::int64_t b = bucketBegin; b < bucketEnd; ++b) {
          const std::int64_t first = b * bucketSize;
          const std::int64_t last = std::min(n, first + bucketSize);
          // The bucket's box over its finite points; the others are invalid.
          double blo[3] = {0, 0, 0}, bhi[3] = {0, 0, 0};
          bool haveBox = false;
          for (std::int64_t s = first; s < last; ++s) {
            bool finite = true;
            for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(points.coord[k][s]);
            if (!finite) {
              WriteNotFound(Status::Invalid, s, sorted);
              continue;
            }
            for (int k = 0; k < dim; ++k) {
              const double x = points.coord[k][s];
              blo[k] = haveBox ? std::min(blo[k], x) : x;
              bhi[k] = haveBox ? std::max(bhi[k], x) : x;
            }
            haveBox = true;
          }
          if (!haveBox) continue;
          // Algorithm 3 once for the whole bucket. A volume's points are
          // usually found inside the previous point's cell or a neighbour
          // (TryInsideByWalk) and need no list: there it is built
          // when the first point needs it (the list and the lanes depend on
          // the bucket alone, so when they are built changes no answer).
          bool prepared = false, useBucketList = false, lanesSolved = false;
          const auto prepare = [&] {
            prepared = true;
            useBucketList = NearestCells(bvh, blo, bhi, &scratch.candidates, &scratch.stack, maxDistance,
                                         kMaxBucketCandidates) &&
                            scratch.candidates.size() <= kMaxBucketCandidates;
            lanesSolved = useBucketList &&
                          SolveAffineSimplexLanes(store, points, first, last - first, maxDistance, scratch);
            if (useBucketList) GatherSearchedCandidates(store, lanesSolved, scratch);
          };
          if (!store.hasVolumeCells()) prepare();
          WarmStart warm;
          for (std::int64_t s = first; s < last; ++s) {
            double p[3] = {0, 0, 0};
            bool finite = true;
            for (int k = 0; k < dim; ++k) {
              p[k] = points.coord[k][s];
              finite = finite && std::isfinite(p[k]);
            }
            if (!finite) continue;
            std::int64_t startCell;
            double startRef[3];
            PredictStart(store, warm, p, &startCell, startRef);
            PointSearch search(store, simplices, p, scratch, startCell, startRef, maxDistance);
            if (store.hasVolumeCells()) search.TryInsideByWalk(bvh);
            if (!search.inside) {
              if (!prepared) prepare();
              if (useBucketList) {
                if (lanesSolved) search.Seed(scratch.laneBestCell[s - first], scratch.laneBest[s - first]);
                SearchCandidates(search);
              } else {
                SearchBvh(bvh, wide, simplices, search);
              }
            }
            WriteFound(store, search, s, &warm, sorted);
          }
        }
      },
      options.threads);
}

}  // namespace

void InvertBatch(const CellStore& store, const Bvh& bvh, const WideBvh& wide, const SimplexItems& simplices,
                 const QueryPoints& points, const InversionOptions& options, Results* results) {
  const std::int64_t n = points.count;
  const int dim = store.dimension();
  ResizeResults(n, results);
  if (n == 0) return;

  // Morton order over the box of the finite points.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  FinitePointBounds(points, dim, options.threads, lo, hi);
  std::vector<std::int64_t> pointNew2Old;
  SpatialSort(ExecutionPolicy::Par, points.coord[0], points.coord[1], dim == 3 ? points.coord[2] : nullptr, n, lo, hi,
              &pointNew2Old, nullptr, options.threads);

  const int bucketSize = std::max(1, options.bucketSize);
  // The buckets read their points, gathered into Morton order, and write
  // their answers in that order into `sorted`, which is then scattered to
  // the input order: writing each answer at its input index at once touches
  // a new cache line of every result array per point (1.35x slower on a
  // million random points in tetrahedra). Chunks of whole buckets keep the
  // extra memory bounded and the buckets fixed runs of the Morton order.
  const std::int64_t chunk = std::max<std::int64_t>(1, kSortedChunk / bucketSize) * bucketSize;
  Results sorted;
  std::vector<double> sortedCoord[3];
  for (std::int64_t chunkFirst = 0; chunkFirst < n; chunkFirst += chunk) {
    const std::int64_t count = std::min(chunk, n - chunkFirst);
    const std::int64_t* chunkNew2Old = pointNew2Old.data() + chunkFirst;
    QueryPoints chunkPoints;
    chunkPoints.count = count;
    for (int k = 0; k < dim; ++k) {
      sortedCoord[k].resize(count);
      chunkPoints.coord[k] = sortedCoord[k].data();
    }
    ForEachBlock(
        ExecutionPolicy::Par, count, 4096,
        [&](std::int64_t begin, std::int64_t end) {
          // One coordinate array at a time, as ScatterResults.
          for (int k = 0; k < dim; ++k) {
            for (std::int64_t s = begin; s < end; ++s) sortedCoord[k][s] = points.coord[k][chunkNew2Old[s]];
          }
        },
        options.threads);
    ResizeResults(count, &sorted);
    InvertBuckets(store, bvh, wide, simplices, chunkPoints, bucketSize, options, &sorted);
    ForEachBlock(
        ExecutionPolicy::Par, count, 4096,
        [&](std::int64_t begin, std::int64_t end) {
          ScatterResults(sorted, chunkNew2Old, begin, end, results);
        },
        options.threads);
  }
}

}  // namespace invmap::engine
