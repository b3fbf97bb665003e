#include "engine/point_search.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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

}  // namespace

void PointSearch::SolveRegion(const AffineRegion& region) {
  const RegionSolution r = SolveAffineRegion(region, p);
  if (!Beats(r.distance, [&] { return RegionSize(region); })) return;
  Accept(r);
}

double PointSearch::RegionSize(const AffineRegion& region) const {
  double size2 = 0.0;
  for (int k = 0; k < store.dimension(); ++k) {
    size2 += (region.boxHi[k] - region.boxLo[k]) * (region.boxHi[k] - region.boxLo[k]);
  }
  return std::sqrt(size2);
}

void PointSearch::TryInside(std::int64_t subdivision) {
  if (store.isRegion(subdivision)) {
    TryInsideRegion(store.subdivisionRegion(subdivision));
    return;
  }
  TryInsideCell(store.subdivisionCell(subdivision));
}

void PointSearch::TryInsideByWalk(const Bvh& bvh) {
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

void PointSearch::TryInsideRegion(const AffineRegion& region) {
  if (region.paramDim != store.dimension()) return;
  const RegionSolution r = SolveAffineRegion(region, p);
  if (r.distance > kernels::kDistanceTolerance * RegionSize(region)) return;
  Accept(r);
  inside = true;
}

void PointSearch::TryInsideCell(std::int64_t cell, const double* cornerLambda) {
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

}  // namespace invmap::engine
