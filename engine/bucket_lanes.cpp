#include "engine/bucket_lanes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/affine_regions.h"
#include "engine/box_distance.h"
#include "engine/point_search.h"
#include "kernels/cell_bounds.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A point listing more cells than this is left to the per-point search
/// (its first answer was far from its foot: the lanes would solve them all).
constexpr std::size_t kMaxListed = 48;

/// What point j's next answer from a cell of `size` must beat, as
/// PointSearch::Bound2: its best squared distance, or before any answer the
/// gap tolerance widened by the cell's band (equality admitted).
double Bound2(const BucketLanes& lanes, int j, double maxDistance, double size) {
  if (lanes.cell[j] >= 0) return lanes.result[j].distance * lanes.result[j].distance;
  const double gap = maxDistance + PointSearch::GapBand(size);
  return std::nextafter(gap * gap, kInf);
}

/// True when an answer at `distance` from a cell of `size` replaces point
/// j's, as PointSearch::Beats.
bool Beats(const BucketLanes& lanes, int j, double distance, double maxDistance, double size) {
  if (lanes.cell[j] >= 0) return distance < lanes.result[j].distance;
  return distance <= maxDistance || distance <= maxDistance + PointSearch::GapBand(size);
}

/// True when a predicted start lies in its cell's domain: one beyond it
/// (the prediction moves at most one span per direction) says the foot is
/// farther on, and a lane solve there would end on the cell's edge, wasted.
bool InsideDomain(const CellStore& store, std::int64_t cell, const double* ref) {
  const int pd = store.shape(cell).paramDim();
  for (int i = 0; i < pd; ++i) {
    if (!(ref[i] >= 0.0 && ref[i] <= 1.0)) return false;
  }
  return true;
}

/// A start in `cell` from point j's answer: its patch parameters clamped
/// into the cell when both cells tile one B-spline patch, else the centre.
void StartFromAnswer(const CellStore& store, const BucketLanes& lanes, int j, std::int64_t cell, double* start) {
  kernels::ReferenceCenter(store.shape(cell), start);
  if (lanes.cell[j] < 0) return;
  const CellOrigin from = store.origin(lanes.cell[j]);
  const CellOrigin to = store.origin(cell);
  if (from.patch != to.patch || !from.sharedParameters) return;
  const int pd = kernels::CellShape::ParamDimOf(to.type);
  for (int i = 0; i < pd; ++i) {
    const double u = from.paramLo[i] + from.paramScale[i] * lanes.result[j].ref[i];
    const double inCell = std::clamp((u - to.paramLo[i]) / to.paramScale[i], 0.0, 1.0);
    if (std::isfinite(inCell)) start[i] = inCell;
  }
}

/// CellSolver::SolveLane's answers on a cell of a face's elementary
/// surface: each lane in closed form (kernels/analytic_surface.h), or by
/// the cell's solver where the closed form leaves the point to it.
void SolveAnalyticLanes(const kernels::CellSolver& solver, const kernels::AnalyticCell& analytic,
                        const kernels::QueryLane& query, const kernels::ResultLane& result,
                        kernels::SolveWorkspace* workspace) {
  for (int l = 0; l < query.count; ++l) {
    const double p[3] = {query.coord[0][l], query.coord[1][l], query.coord[2][l]};
    const double bound2 = query.bound2 ? query.bound2[l] : kInf;
    kernels::CellSolveResult r;
    if (!kernels::SolveAnalyticCell(analytic, p, bound2, &r)) {
      const double start[3] = {query.initialRef[0] ? query.initialRef[0][l] : 0.5,
                               query.initialRef[1] ? query.initialRef[1][l] : 0.5, 0.0};
      r = solver.Solve(p, start, workspace, bound2);
    }
    for (int k = 0; k < 3; ++k) {
      if (result.ref[k]) result.ref[k][l] = r.ref[k];
      if (result.closest[k]) result.closest[k][l] = r.closest[k];
    }
    result.distance[l] = r.distance;
    result.status[l] = r.status;
    result.iterations[l] = r.iterations;
  }
}

/// Solves `cell` for the points of pairs [a, b) in lanes, from `starts`
/// (per pair, 3 values) or from each point's answer, each lane bounded by its
/// point's best so far (by the gap tolerance before any); keeps the answers
/// that beat.
void SolveCellForPoints(const CellStore& store, std::int64_t cell, std::size_t a, std::size_t b,
                        const double* const coord[3], const double* starts, double maxDistance, BucketLanes* lanes) {
  const int n = static_cast<int>(b - a);
  const int dim = store.dimension();
  const kernels::CellSolver& solver = store.solver(cell);
  const int pd = solver.cell().shape.paramDim();
  for (int k = 0; k < 3; ++k) {
    for (std::vector<double>* v : {&lanes->coord[k], &lanes->start[k], &lanes->ref[k], &lanes->closest[k]}) {
      v->resize(n);
    }
  }
  lanes->bound2.resize(n);
  lanes->distance.resize(n);
  lanes->status.resize(n);
  lanes->laneIterations.resize(n);
  for (int l = 0; l < n; ++l) {
    const int j = lanes->pairs[a + l].second;
    for (int k = 0; k < 3; ++k) lanes->coord[k][l] = k < dim ? coord[k][j] : 0.0;
    double start[3] = {0, 0, 0};
    if (starts) {
      std::copy(starts + 3 * (a + l), starts + 3 * (a + l) + 3, start);
    } else {
      StartFromAnswer(store, *lanes, j, cell, start);
    }
    for (int i = 0; i < 3; ++i) lanes->start[i][l] = start[i];
    lanes->bound2[l] = Bound2(*lanes, j, maxDistance, solver.size());
  }
  kernels::QueryLane query;
  query.count = n;
  kernels::ResultLane result;
  for (int k = 0; k < 3; ++k) {
    query.coord[k] = lanes->coord[k].data();
    if (k < pd) query.initialRef[k] = lanes->start[k].data();
    result.ref[k] = lanes->ref[k].data();
    result.closest[k] = lanes->closest[k].data();
  }
  // Unbounded (an infinite gap tolerance and no answer yet): no bound at all.
  const bool bounded = std::any_of(lanes->bound2.begin(), lanes->bound2.end(), [](double b2) { return b2 < kInf; });
  if (bounded) query.bound2 = lanes->bound2.data();
  result.distance = lanes->distance.data();
  result.status = lanes->status.data();
  result.iterations = lanes->laneIterations.data();
  if (const kernels::AnalyticCell* analytic = store.analytic(cell)) {
    SolveAnalyticLanes(solver, *analytic, query, result, &lanes->workspace);
  } else {
    solver.SolveLane(query, result, &lanes->workspace);
  }
  for (int l = 0; l < n; ++l) {
    const int j = lanes->pairs[a + l].second;
    lanes->iterations[j] += lanes->laneIterations[l];
    const kernels::PointStatus status = lanes->status[l];
    if (status == kernels::PointStatus::Farther || status == kernels::PointStatus::InvalidInput) continue;
    if (!Beats(*lanes, j, lanes->distance[l], maxDistance, solver.size())) continue;
    kernels::CellSolveResult& r = lanes->result[j];
    for (int k = 0; k < 3; ++k) {
      r.ref[k] = lanes->ref[k][l];
      r.closest[k] = lanes->closest[k][l];
    }
    r.distance = lanes->distance[l];
    r.status = status;
    r.iterations = lanes->laneIterations[l];
    lanes->cell[j] = cell;
  }
}

/// Lists in lanes->pairs the subdivisions whose lower bound from point j
/// (which has an answer) is within its best (the 4-ary tree cut there, as
/// SearchBvh's traversal), other than its answer's cell. False (nothing
/// listed) when there are more than kMaxListed.
bool ListCandidates(const CellStore& store, const WideBvh& wide, const Bvh& bvh, const SimplexItems& simplices,
                    const double* p, int j, BucketLanes* lanes) {
  const std::vector<WideNode>& nodes = wide.Nodes();
  if (nodes.empty()) return true;
  const double bound2 = lanes->result[j].distance * lanes->result[j].distance;
  const std::int64_t answered = lanes->cell[j];
  const std::size_t before = lanes->pairs.size();
  const WidePoint point = wide.Prepare(p);
  const std::vector<BvhBox>& itemBoxes = bvh.ItemBoxes();
  const std::vector<int>& items = bvh.Items();
  const int dim = store.dimension();
  lanes->stackBound2.assign(1, 0.0);
  lanes->stackFirst.assign(1, 0);
  lanes->stackCount.assign(1, 0);
  while (!lanes->stackBound2.empty()) {
    const double lowerBound2 = lanes->stackBound2.back();
    const std::int32_t first = lanes->stackFirst.back(), count = lanes->stackCount.back();
    lanes->stackBound2.pop_back();
    lanes->stackFirst.pop_back();
    lanes->stackCount.pop_back();
    if (lowerBound2 > bound2) continue;
    if (count > 0) {
      for (int i = first; i < first + count; ++i) {
        const int s = items[i];
        if (!store.isRegion(s) && store.subdivisionCell(s) == answered) continue;
        if (simplices.cell(i) < 0) {
          if (BoxDistance2(itemBoxes[i], p, dim) > bound2) continue;
          if (WideBvh::OrientedDistance2(wide.ItemOrientedBox(i), point) > bound2) continue;
        }
        lanes->pairs.emplace_back(s, j);
      }
      if (lanes->pairs.size() - before > kMaxListed) {
        lanes->pairs.resize(before);
        return false;
      }
      continue;
    }
    double box2[4], childBound2[4];
    WideBvh::ChildDistances2(nodes[first], point, box2, childBound2);
    for (int c = 0; c < 4; ++c) {
      if (nodes[first].count[c] < 0 || !(childBound2[c] <= bound2)) continue;
      lanes->stackBound2.push_back(childBound2[c]);
      lanes->stackFirst.push_back(nodes[first].first[c]);
      lanes->stackCount.push_back(nodes[first].count[c]);
    }
  }
  return true;
}

/// Solves the listed regions of pairs [a, b) (all the same region) for their points.
void SolveRegionForPoints(const CellStore& store, const AffineRegion& region, std::size_t a, std::size_t b,
                          const double* const coord[3], double maxDistance, BucketLanes* lanes) {
  const int dim = store.dimension();
  for (std::size_t q = a; q < b; ++q) {
    const int j = lanes->pairs[q].second;
    const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
    const RegionSolution r = SolveAffineRegion(region, p);
    // A region is listed only for a point with an answer: its size is not needed.
    if (!Beats(*lanes, j, r.distance, maxDistance, 0.0)) continue;
    kernels::CellSolveResult& best = lanes->result[j];
    best = kernels::CellSolveResult();
    std::copy(r.ref, r.ref + 3, best.ref);
    std::copy(r.closest, r.closest + 3, best.closest);
    best.distance = r.distance;
    best.status = kernels::PointStatus::Converged;
    lanes->cell[j] = r.cell;
  }
}

}  // namespace

void SolveBucketInLanes(const CellStore& store, const WideBvh& wide, const Bvh& bvh, const SimplexItems& simplices,
                        const double* const coord[3], int count, const WarmStart& first, double maxDistance,
                        BucketLanes* lanes) {
  const int dim = store.dimension();
  lanes->settled.assign(count, 1);
  lanes->settled[0] = 0;
  lanes->cell.assign(count, -1);
  lanes->result.assign(count, kernels::CellSolveResult());
  lanes->iterations.assign(count, 0);
  // 1. The predicted cells, each solved for the points predicted in it.
  lanes->pairs.clear();
  std::vector<char>& settled = lanes->settled;
  std::vector<double>& pairStarts = lanes->pairStarts;
  for (int j = 1; j < count; ++j) {
    const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
    std::int64_t cell = -1;
    double ref[3] = {0, 0, 0};
    const bool finite = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    if (finite) PredictStart(store, first, p, &cell, ref);
    if (!StartsBucketLanes(store, simplices, cell) || !InsideDomain(store, cell, ref)) {
      settled[j] = 0;
      continue;
    }
    lanes->pairs.emplace_back(cell, j);
    std::copy(ref, ref + 3, lanes->result[j].ref);  // the start, until the cell is solved
  }
  std::sort(lanes->pairs.begin(), lanes->pairs.end());
  pairStarts.resize(3 * lanes->pairs.size());
  for (std::size_t q = 0; q < lanes->pairs.size(); ++q) {
    const double* start = lanes->result[lanes->pairs[q].second].ref;
    std::copy(start, start + 3, &pairStarts[3 * q]);
  }
  for (std::size_t a = 0; a < lanes->pairs.size();) {
    std::size_t b = a;
    while (b < lanes->pairs.size() && lanes->pairs[b].first == lanes->pairs[a].first) ++b;
    SolveCellForPoints(store, lanes->pairs[a].first, a, b, coord, pairStarts.data(), maxDistance, lanes);
    a = b;
  }
  // 2. The cells each point must still exclude (or solve). A point without
  // an answer yet is left to the per-point search: its bound is the gap
  // tolerance, which on most geometries lists every cell.
  lanes->pairs.clear();
  for (int j = 1; j < count; ++j) {
    if (!settled[j]) continue;
    if (lanes->cell[j] < 0) {
      settled[j] = 0;
      continue;
    }
    const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
    settled[j] = ListCandidates(store, wide, bvh, simplices, p, j, lanes);
  }
  // 3. Each listed cell for all the points that listed it, bounded.
  std::sort(lanes->pairs.begin(), lanes->pairs.end());
  for (std::size_t a = 0; a < lanes->pairs.size();) {
    std::size_t b = a;
    while (b < lanes->pairs.size() && lanes->pairs[b].first == lanes->pairs[a].first) ++b;
    const std::int64_t s = lanes->pairs[a].first;
    if (store.isRegion(s)) {
      SolveRegionForPoints(store, store.subdivisionRegion(s), a, b, coord, maxDistance, lanes);
    } else {
      SolveCellForPoints(store, store.subdivisionCell(s), a, b, coord, nullptr, maxDistance, lanes);
    }
    a = b;
  }
}

}  // namespace invmap::engine
