#include "engine/point_search.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Steps of the walk through a volume mesh before the BVH takes over.
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

void PointSearch::TryInsideByWalk(const Bvh& bvh, std::int64_t from) {
  tried.clear();
  const FaceAdjacency& adjacency = store.faceAdjacency();
  std::int64_t start = from;
  if (start < 0) start = adjacency.startGrid().StartCell(p);
  if (start < 0) start = warmCell >= 0 ? warmCell : DescendToVolumeCell(bvh, store, p);
  if (start < 0) return;
  // An affine tetrahedron's item says it is a full-rank cell of no region:
  // its solver, a cold read, is not needed.
  // So does an affine hexahedron's frame.
  const HexFrames& frames = adjacency.frames();
  const int startItem = simplices.item(start);
  if (startItem < 0 || simplices.paramDim(startItem) != 3) {
    if (store.inRegion(start) || (!frames.Of(start) && !store.solver(start).isFullRank())) return;
  }
  std::int64_t cell = start;
  for (int step = 0;; ++step) {
    // The answer's origin (engine/bezier_nets.h), which WriteFound reads in
    // cell order, a cache miss of its own a point: requested now, while the
    // cell is tried.
    const char* origin = reinterpret_cast<const char*>(&store.origin(cell));
    __builtin_prefetch(origin);
    __builtin_prefetch(origin + sizeof(CellOrigin) - 1);
    // The faces to leave by, likeliest first.
    int exits[kernels::kMaxFaces];
    int exitCount = 0;
    const int item = simplices.item(cell);
    const HexFrame* frame = item < 0 ? frames.Of(cell) : nullptr;
    if (frame) {
      // An affine hexahedron, from its frame record (next to its
      // neighbours; its solver and control points are cold): the steps of
      // a walk through a mesh of parallelepipeds read nothing else, unless
      // the point lies within rounding of the cell's boundary.
      kernels::CellSolveResult r;
      const FrameVerdict verdict = HexFrames::Locate(*frame, p, &r);
      tried.push_back(cell);
      if (verdict == FrameVerdict::Inside) {
        best = r.distance;
        bestCell = cell;
        bestResult = r;
        bestModel = -1;
        inside = true;
      } else if (verdict == FrameVerdict::Outside) {
        exitCount = HexFrames::ExitFaces(r.ref, exits);
      } else {
        double stopRef[3];
        TryInsideCell(cell, nullptr, stopRef);
        if (!inside) exitCount = kernels::FacesAt(store.solver(cell).cell().shape, stopRef, exits);
      }
    } else if (item >= 0 && simplices.paramDim(item) == 3) {
      // An affine tetrahedron, from the copy of its vertices the BVH keeps
      // in leaf order (next to its neighbours'; its solver is cold): the
      // steps of a walk through a linear mesh read nothing else.
      const double* vertices[4];
      for (int v = 0; v < 4; ++v) vertices[v] = simplices.vertices(item) + 3 * v;
      double lambda[4];
      if (kernels::CellSolver::TetBarycentric(vertices, p, lambda)) {
        const int exit = static_cast<int>(std::min_element(lambda, lambda + 4) - lambda);
        if (lambda[exit] >= -kernels::kHullSlack) {
          TryInsideSimplexItem(item, vertices, lambda);
          tried.push_back(cell);
        } else {
          exits[exitCount++] = exit;
        }
      }
    } else if (store.solver(cell).isTetrahedron()) {
      const kernels::CellSolver& solver = store.solver(cell);
      // One corner barycentric evaluation serves both the inside solve's
      // start and the walk's direction: the face of the straight corner
      // tetrahedron the point lies beyond (none when inside it).
      double lambda[4];
      const bool haveLambda = solver.CornerBarycentric(p, lambda);
      if (CellBoxDistance2(solver, p, store.dimension()) == 0.0) {
        TryInsideCell(cell, haveLambda ? lambda : nullptr);
        tried.push_back(cell);
      }
      const int exit = static_cast<int>(std::min_element(lambda, lambda + 4) - lambda);
      if (haveLambda && lambda[exit] < 0.0) exits[exitCount++] = exit;
    } else {
      const kernels::CellSolver& solver = store.solver(cell);
      // Hexahedra and wedges: the inside solve runs, and names the face the
      // point lies beyond (CellSolver::SolveInside: an affine cell's
      // preimage in closed form, a curved cell's stop on the boundary).
      // (Without neighbours, as in 2D, only a cell whose box holds the
      // point is worth the solve.)
      if (!adjacency.empty() || CellBoxDistance2(solver, p, store.dimension()) == 0.0) {
        double stopRef[3];
        TryInsideCell(cell, nullptr, stopRef);
        tried.push_back(cell);
        if (!inside) exitCount = kernels::FacesAt(solver.cell().shape, stopRef, exits);
      }
    }
    if (inside || step == kMaxWalk || adjacency.empty()) return;
    std::int64_t next = -1;
    for (int e = 0; e < exitCount && next < 0; ++e) {
      const std::int64_t across = frame ? frame->neighbors[exits[e]] : adjacency.Neighbor(cell, exits[e]);
      if (across >= 0 && !store.inRegion(across) && !IsTriedCell(across)) next = across;
    }
    if (next < 0) return;
    cell = next;
  }
}

void PointSearch::TryInsideSimplexItem(int item, const double* const* vertices, const double* lambda) {
  if (*std::min_element(lambda, lambda + 4) >= 0.0) {
    // Within the closed tetrahedron: the point is its own closest point,
    // its preimage its barycentric coordinates (what the closed form below
    // would find, to rounding).
    kernels::CellSolveResult r;
    std::copy(lambda + 1, lambda + 4, r.ref);
    std::copy(p, p + 3, r.closest);
    r.distance = 0.0;
    r.status = kernels::PointStatus::Converged;
    best = 0.0;
    bestCell = simplices.cell(item);
    bestResult = r;
    bestModel = -1;
    inside = true;
    return;
  }
  // CellSolver::SolveInside of an affine tetrahedron whose corner
  // barycentrics passed its hull test: the closed form, inside within the
  // distance tolerance of the cell's size, the diagonal of its control
  // points' box: its vertices' (the other control points lie between them),
  // read here from the item's copy rather than from the cold solver.
  double size2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({vertices[0][k], vertices[1][k], vertices[2][k], vertices[3][k]});
    const double hi = std::max({vertices[0][k], vertices[1][k], vertices[2][k], vertices[3][k]});
    size2 += (hi - lo) * (hi - lo);
  }
  kernels::CellSolveResult r;
  kernels::CellSolver::SolveAffineSimplex(3, 3, vertices, p, &r);
  if (!(r.distance <= kernels::kDistanceTolerance * std::sqrt(size2))) return;
  const std::int64_t cell = simplices.cell(item);
  best = r.distance;
  bestCell = cell;
  bestResult = r;
  bestModel = -1;
  inside = true;
}

void PointSearch::TryInsideRegion(const AffineRegion& region) {
  if (region.paramDim != store.dimension()) return;
  const RegionSolution r = SolveAffineRegion(region, p);
  if (r.distance > kernels::kDistanceTolerance * RegionSize(region)) return;
  Accept(r);
  inside = true;
}

void PointSearch::TryInsideCell(std::int64_t cell, const double* cornerLambda, double* stopRef) {
  const kernels::CellSolver& solver = store.solver(cell);
  if (stopRef) std::fill(stopRef, stopRef + 3, std::numeric_limits<double>::quiet_NaN());  // on no face
  if (!solver.isFullRank()) return;
  kernels::CellSolveResult r;
  const bool holds = solver.SolveInside(p, cell == warmCell ? warmRef : nullptr, &r, cornerLambda);
  if (stopRef) std::copy(r.ref, r.ref + 3, stopRef);
  if (holds) {
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
