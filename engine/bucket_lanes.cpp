#include "engine/bucket_lanes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/affine_regions.h"
#include "kernels/cell_bounds.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A point listing more cells than this is left to the per-point search
/// (its first answer was far from its foot: the lanes would solve them all).
constexpr std::size_t kMaxListed = 48;

/// What a point's next cell must beat (as PointSearch::Bound2): its best
/// squared distance, or just above the gap tolerance's when it has none.
double Bound2(const BucketLanes& lanes, int j, double maxDistance) {
  if (lanes.cell[j] >= 0) return lanes.result[j].distance * lanes.result[j].distance;
  return std::nextafter(maxDistance * maxDistance, kInf);
}

/// True when an answer at `distance` replaces point j's (PointSearch::Beats:
/// the gap tolerance admits equality, a found answer only a nearer one).
bool Beats(const BucketLanes& lanes, int j, double distance, double maxDistance) {
  return lanes.cell[j] >= 0 ? distance < lanes.result[j].distance : distance <= maxDistance;
}

/// Squared distance from `p` to the box [lo, hi].
double BoxDistance2(const double* lo, const double* hi, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
    d2 += d * d;
  }
  return d2;
}

/// A start in `cell` from point j's answer: its patch parameters clamped
/// into the cell when both cells tile one B-spline patch, else the centre.
void StartFromAnswer(const CellStore& store, const BucketLanes& lanes, int j, std::int64_t cell, double* start) {
  kernels::ReferenceCenter(store.solver(cell).cell().shape, start);
  if (lanes.cell[j] < 0) return;
  const CellOrigin& from = store.origin(lanes.cell[j]);
  const CellOrigin& to = store.origin(cell);
  if (from.patch != to.patch || !from.sharedParameters) return;
  const int pd = kernels::CellShape::ParamDimOf(to.type);
  for (int i = 0; i < pd; ++i) {
    const double u = from.paramLo[i] + from.paramScale[i] * lanes.result[j].ref[i];
    const double inCell = std::clamp((u - to.paramLo[i]) / to.paramScale[i], 0.0, 1.0);
    if (std::isfinite(inCell)) start[i] = inCell;
  }
}

/// Solves `cell` for the points of pairs [a, b) in lanes, from `starts`
/// (per pair, paramDim values) or from each point's answer, each lane bounded
/// by its point's best so far (none when `bounded` is false); keeps the
/// answers that beat.
void SolveCellForPoints(const CellStore& store, std::int64_t cell, std::size_t a, std::size_t b,
                        const double* const coord[3], const double* starts, bool bounded, double maxDistance,
                        BucketLanes* lanes) {
  const int n = static_cast<int>(b - a);
  const int dim = store.dimension();
  const int pd = store.solver(cell).cell().shape.paramDim();
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
    lanes->bound2[l] = Bound2(*lanes, j, maxDistance);
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
  if (bounded) query.bound2 = lanes->bound2.data();
  result.distance = lanes->distance.data();
  result.status = lanes->status.data();
  result.iterations = lanes->laneIterations.data();
  store.solver(cell).SolveLane(query, result, &lanes->workspace);
  for (int l = 0; l < n; ++l) {
    const int j = lanes->pairs[a + l].second;
    lanes->iterations[j] += lanes->laneIterations[l];
    const kernels::PointStatus status = lanes->status[l];
    if (status == kernels::PointStatus::Farther || status == kernels::PointStatus::InvalidInput) continue;
    if (!Beats(*lanes, j, lanes->distance[l], maxDistance)) continue;
    kernels::CellSolveResult& r = lanes->result[j];
    for (int k = 0; k < 3; ++k) {
      r.ref[k] = lanes->ref[k][l];
      r.closest[k] = lanes->closest[k][l];
    }
    r.distance = lanes->distance[l];
    r.status = status;
    lanes->cell[j] = cell;
  }
}

/// Lists in lanes->pairs the subdivisions whose lower bound from point j is
/// below its best (the 4-ary tree cut there, as SearchBvh's traversal),
/// other than its answer's cell. False (nothing listed) when there are more
/// than kMaxListed.
bool ListCandidates(const CellStore& store, const WideBvh& wide, const Bvh& bvh, const SimplexItems& simplices,
                    const double* p, int j, double maxDistance, BucketLanes* lanes) {
  const std::vector<WideNode>& nodes = wide.Nodes();
  if (nodes.empty()) return true;
  const double bound2 = Bound2(*lanes, j, maxDistance);
  const std::int64_t answered = lanes->cell[j];
  const std::size_t before = lanes->pairs.size();
  const WidePoint point = wide.Prepare(p);
  const std::vector<BvhBox>& itemBoxes = bvh.ItemBoxes();
  const std::vector<int>& items = bvh.Items();
  const int dim = store.dimension();
  lanes->stack.clear();
  lanes->stackFirst.clear();
  lanes->stackCount.clear();
  lanes->stack.emplace_back(0.0, 0);
  lanes->stackFirst.push_back(0);
  lanes->stackCount.push_back(0);
  while (!lanes->stack.empty()) {
    const double lowerBound2 = lanes->stack.back().first;
    const std::int32_t first = lanes->stackFirst.back(), count = lanes->stackCount.back();
    lanes->stack.pop_back();
    lanes->stackFirst.pop_back();
    lanes->stackCount.pop_back();
    if (lowerBound2 > bound2) continue;
    if (count > 0) {
      for (int i = first; i < first + count; ++i) {
        const int s = items[i];
        if (!store.isRegion(s) && store.subdivisionCell(s) == answered) continue;
        if (simplices.cell(i) < 0) {
          if (BoxDistance2(itemBoxes[i].lo, itemBoxes[i].hi, p, dim) > bound2) continue;
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
      lanes->stack.emplace_back(childBound2[c], 0);
      lanes->stackFirst.push_back(nodes[first].first[c]);
      lanes->stackCount.push_back(nodes[first].count[c]);
    }
  }
  return true;
}

}  // namespace

void SolveBucketInLanes(const CellStore& store, const WideBvh& wide, const Bvh& bvh, const SimplexItems& simplices,
                        const double* const coord[3], int count, const WarmStart& first, double maxDistance,
                        BucketLanes* lanes) {
  const int dim = store.dimension();
  lanes->cell.assign(count, -1);
  lanes->result.resize(count);
  lanes->iterations.assign(count, 0);
  // 1. The predicted cells, each solved for the points predicted in it.
  lanes->pairs.clear();
  std::vector<char>& handled = lanes->handled;
  handled.assign(count, 1);
  for (int j = 1; j < count; ++j) {
    const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
    std::int64_t cell = -1;
    double ref[3] = {0, 0, 0};
    const bool finite = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    if (finite) PredictStart(store, first, p, &cell, ref);
    if (cell < 0 || store.inRegion(cell) || store.solver(cell).isAffineSimplex()) {
      handled[j] = 0;
      continue;
    }
    lanes->pairs.emplace_back(cell, j);
    lanes->result[j].ref[0] = ref[0];  // the start, until the cell is solved
    lanes->result[j].ref[1] = ref[1];
    lanes->result[j].ref[2] = ref[2];
  }
  std::sort(lanes->pairs.begin(), lanes->pairs.end());
  std::vector<double>& pairStarts = lanes->pairStarts;
  pairStarts.resize(3 * lanes->pairs.size());
  for (std::size_t q = 0; q < lanes->pairs.size(); ++q) {
    std::copy(lanes->result[lanes->pairs[q].second].ref, lanes->result[lanes->pairs[q].second].ref + 3,
              &pairStarts[3 * q]);
  }
  for (std::size_t a = 0; a < lanes->pairs.size();) {
    std::size_t b = a;
    while (b < lanes->pairs.size() && lanes->pairs[b].first == lanes->pairs[a].first) ++b;
    SolveCellForPoints(store, lanes->pairs[a].first, a, b, coord, pairStarts.data(), maxDistance < kInf,
                       maxDistance, lanes);
    a = b;
  }
  // 2. The cells each point must still exclude (or solve).
  lanes->pairs.clear();
  for (int j = 1; j < count; ++j) {
    if (!handled[j] || lanes->cell[j] < 0) {
      handled[j] = 0;
      continue;
    }
    const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
    handled[j] = ListCandidates(store, wide, bvh, simplices, p, j, maxDistance, lanes);
  }
  // 3. Each listed cell for all the points that listed it, bounded.
  std::sort(lanes->pairs.begin(), lanes->pairs.end());
  for (std::size_t a = 0; a < lanes->pairs.size();) {
    std::size_t b = a;
    while (b < lanes->pairs.size() && lanes->pairs[b].first == lanes->pairs[a].first) ++b;
    const std::int64_t s = lanes->pairs[a].first;
    if (store.isRegion(s)) {
      const AffineRegion& region = store.subdivisionRegion(s);
      for (std::size_t q = a; q < b; ++q) {
        const int j = lanes->pairs[q].second;
        const double p[3] = {coord[0][j], coord[1][j], dim > 2 ? coord[2][j] : 0.0};
        const RegionSolution r = SolveAffineRegion(region, p);
        if (!Beats(*lanes, j, r.distance, maxDistance)) continue;
        kernels::CellSolveResult& best = lanes->result[j];
        std::copy(r.ref, r.ref + 3, best.ref);
        std::copy(r.closest, r.closest + 3, best.closest);
        best.distance = r.distance;
        best.status = kernels::PointStatus::Converged;
        lanes->cell[j] = r.cell;
      }
    } else {
      SolveCellForPoints(store, store.subdivisionCell(s), a, b, coord, nullptr, true, maxDistance, lanes);
    }
    a = b;
  }
  // Points the lanes did not settle go to the per-point search.
  for (int j = 1; j < count; ++j) {
    if (!handled[j]) lanes->cell[j] = -2;
  }
}

}  // namespace invmap::engine
