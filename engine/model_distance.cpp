#include "engine/model_distance.h"

#include <algorithm>
#include <cmath>

#include "engine/pair_bounds.h"
#include "kernels/cell_bounds.h"
#include "kernels/tolerances.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The inside test of a volume model X against model Y: one point of each
/// of Y's distance cells (its centre), inverted into X. A point at distance
/// 0 (X's volume holds it) makes the models intersect; Y's cells that do not
/// meet X's boundary lie wholly inside or outside X, so one point each
/// decides. Returns the index of the first such cell, or -1.
std::int64_t FirstCellInside(const PlacedModel& x, const PlacedModel& y, double zero, int threads,
                             std::vector<double>* hitPoint, Results* hit) {
  const DistanceCells& cellsY = *y.cells;
  const BvhBox& bounds = x.cells->bvh().RootBounds();
  std::vector<double> points;
  std::vector<std::int64_t> source;
  const int dim = x.cells->dimension();
  for (std::int64_t c = 0; c < cellsY.size(); ++c) {
    const DistanceCell& cell = cellsY.cell(c);
    double ref[3], local[3] = {0, 0, 0}, world[3], inX[3];
    kernels::ReferenceCenter(cell.view.shape, ref);
    kernels::MapJet jet;
    kernels::EvaluateMap(cell.view, ref, kernels::JetOrder::Value, &jet);
    for (int k = 0; k < cell.view.ambientDim; ++k) local[k] = jet.x[k];
    y.motion.Apply(local, world);
    ToModelFrame(x.motion, world, inX);
    bool inBox = true;
    for (int k = 0; k < dim; ++k) inBox = inBox && inX[k] >= bounds.lo[k] && inX[k] <= bounds.hi[k];
    if (!inBox) continue;
    points.insert(points.end(), inX, inX + dim);
    source.push_back(c);
  }
  if (source.empty()) return -1;
  InversionOptions options;
  options.maxDistance = zero;
  options.threads = threads;
  Results results;
  if (x.manifold->Invert(PointsView::Interleaved(points.data(), source.size(), dim), options, &results) != Error::Ok) {
    return -1;
  }
  for (std::size_t i = 0; i < source.size(); ++i) {
    if (results.status[i] != Status::Found) continue;
    hitPoint->assign(points.begin() + static_cast<std::int64_t>(i) * dim,
                     points.begin() + static_cast<std::int64_t>(i + 1) * dim);
    hit->status = {results.status[i]};
    hit->patch = {results.patch[i]};
    hit->cell = {results.cell[i]};
    hit->params.assign(results.params.begin() + 3 * i, results.params.begin() + 3 * i + 3);
    return source[i];
  }
  return -1;
}

/// The largest distance from the model's origin of a point of its cells:
/// of a corner of their boxes (each holds its cell's control points, which
/// hold the cell).
double ModelRadius(const DistanceCells& cells) {
  double r2 = 0.0;
  for (const BvhBox& box : cells.bvh().ItemBoxes()) {
    double corner2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double m = std::max(std::abs(box.lo[k]), std::abs(box.hi[k]));
      corner2 += m * m;
    }
    r2 = std::max(r2, corner2);
  }
  return std::sqrt(r2) * (1.0 + 4.0 * std::numeric_limits<double>::epsilon());
}

}  // namespace

/// The pair kernels' view of distance cell `cell` of model `m`. Affine cells
/// keep no nets; where a curved partner needs them they are built into the
/// workspace (`slot` 0 or 1, one per side, reused while the cell stays).
kernels::PairSide PlacedSide(const PlacedModel& m, std::int64_t cell, int slot, bool needNets,
                         ModelDistanceWorkspace* ws) {
  const DistanceCell& c = m.cells->cell(cell);
  kernels::PairSide side;
  side.cell = c.view;
  side.motion = m.motion;
  side.size = c.size;
  side.affine = c.affine;
  side.nets = m.cells->nets(cell);
  // A cell of a trimmed face that its loops cross (a volume's face never is).
  if (!c.isFace) side.trim = m.cells->store().solver(c.sourceCell).trim();
  if (!side.nets && needNets) {
    if (ws->scratchNetsModel[slot] != m.cells || ws->scratchNetsCell[slot] != cell) {
      BuildCellNets(c.view, c.boxLo, c.boxHi, &ws->scratchNets[slot]);
      ws->scratchNetsModel[slot] = m.cells;
      ws->scratchNetsCell[slot] = cell;
    }
    side.nets = &ws->scratchNets[slot];
  }
  return side;
}

/// x -> motion^-1 x.
void ToModelFrame(const kernels::RigidMotion& motion, const double* world, double* local) {
  double d[3];
  for (int k = 0; k < 3; ++k) d[k] = world[k] - motion.translation[k];
  for (int k = 0; k < 3; ++k) local[k] = motion.rotation[0][k] * d[0] + motion.rotation[1][k] * d[1] + motion.rotation[2][k] * d[2];
}

namespace {

/// Two affine cells, neither of a trimmed face: their squared distance is a
/// convex quadratic, solved without nets (a trimmed face's pair needs them
/// to tell its region's parts apart).
bool ConvexPair(const PlacedModel& a, std::int64_t cellA, const PlacedModel& b, std::int64_t cellB) {
  auto plainAffine = [](const PlacedModel& m, std::int64_t cell) {
    const DistanceCell& c = m.cells->cell(cell);
    return c.affine && (c.isFace || !m.cells->store().solver(c.sourceCell).trim());
  };
  return plainAffine(a, cellA) && plainAffine(b, cellB);
}

}  // namespace

kernels::PairSolveResult SolvePlacedCells(const PlacedModel& a, std::int64_t cellA, const PlacedModel& b,
                                          std::int64_t cellB, const double* startA, const double* startB,
                                          double bound2, ModelDistanceWorkspace* ws,
                                          const kernels::PairReuse* reuse) {
  const bool convex = ConvexPair(a, cellA, b, cellB);
  const kernels::PairSide sideA = PlacedSide(a, cellA, 0, !convex, ws);
  const kernels::PairSide sideB = PlacedSide(b, cellB, 1, !convex, ws);
  return kernels::SolveCellPair(sideA, sideB, startA, startB, &ws->pair, bound2, convex ? nullptr : reuse);
}

namespace {

/// ProbeCellPair (kernels/pair_search.h) of one cell pair.
kernels::PairSolveResult ProbePlacedCells(const PlacedModel& a, std::int64_t cellA, const PlacedModel& b,
                                          std::int64_t cellB, double bound2, ModelDistanceWorkspace* ws) {
  const bool convex = ConvexPair(a, cellA, b, cellB);
  const kernels::PairSide sideA = PlacedSide(a, cellA, 0, !convex, ws);
  const kernels::PairSide sideB = PlacedSide(b, cellB, 1, !convex, ws);
  return kernels::ProbeCellPair(sideA, sideB, &ws->pair, bound2);
}

}  // namespace

CellPairAnswer NearestPair(const PlacedModel& a, const PlacedModel& b, const ModelDistanceOptions& options,
                           ModelDistanceWorkspace* ws) {
  CellPairAnswer answer;
  const DistanceCells& cellsA = *a.cells;
  const DistanceCells& cellsB = *b.cells;
  if (cellsA.size() == 0 || cellsB.size() == 0) return answer;
  const kernels::RigidMotion bIntoA = RelativeMotion(a.motion, b.motion);
  const BoxPairBound bound(bIntoA);
  // Found means within maxDistance: the bound admits a pair at exactly it.
  double best2 = options.maxDistance < kInf ? options.maxDistance * options.maxDistance * (1.0 + 1e-15) : kInf;
  const double zero = kernels::kDistanceTolerance * std::max(cellsA.modelSize(), cellsB.modelSize());
  PairBoundCache* cache = options.boundCache;
  if (cache) {
    if (!cache->hasRadius()) cache->SetRadius(ModelRadius(cellsB));
    cache->MoveTo(bIntoA);
  }
  auto record = [&](std::int64_t ia, std::int64_t ib, const kernels::PairSolveResult& r) {
    if (cache) cache->Record(ia, ib, r.lowerBound);
  };
  // A pair's search, from the subdomains its last search left (trackers).
  auto solve = [&](std::int64_t ia, std::int64_t ib, const double* startA, const double* startB) {
    kernels::PairPartition* kept = cache ? cache->Partition(ia, ib) : nullptr;
    if (!kept) return SolvePlacedCells(a, ia, b, ib, startA, startB, best2, ws);
    const kernels::PairReuse reuse{kept, &ws->nextPartition, cache->drift()};
    const kernels::PairSolveResult r = SolvePlacedCells(a, ia, b, ib, startA, startB, best2, ws, &reuse);
    std::swap(*kept, ws->nextPartition);
    return r;
  };

  // Pairs whose search ran out of its budget, and the bound of what it
  // left open: they matter only if that is below the final answer.
  std::vector<OpenPair> open;
  auto accept = [&](std::int64_t ia, std::int64_t ib, const kernels::PairSolveResult& r) {
    if (!(r.distance * r.distance < best2)) return;
    best2 = r.distance * r.distance;
    answer.found = true;
    answer.cell[0] = ia;
    answer.cell[1] = ib;
    std::copy(r.refA, r.refA + 3, answer.ref[0]);
    std::copy(r.refB, r.refB + 3, answer.ref[1]);
    std::copy(r.pointA, r.pointA + 3, answer.point[0]);
    std::copy(r.pointB, r.pointB + 3, answer.point[1]);
    answer.distance = r.distance;
  };
  auto consider = [&](std::int64_t ia, std::int64_t ib, const kernels::PairSolveResult& r) {
    record(ia, ib, r);
    if (r.status == kernels::PairStatus::Farther) return;
    if (r.status == kernels::PairStatus::NotCertified) open.push_back({r.openBound2, best2, ia, ib});
    accept(ia, ib, r);
  };
  // Pairs the traversal only probed (one local solve each, which lowers the
  // bound at once); each is searched after the traversal, nearest bound
  // first, under the best distance all of them found, which prunes far
  // more of it than the bound it was reached under.
  std::vector<OpenPair>& probed = ws->probed;
  probed.clear();
  auto probe = [&](std::int64_t ia, std::int64_t ib) {
    const kernels::PairSolveResult r = ProbePlacedCells(a, ia, b, ib, best2, ws);
    record(ia, ib, r);
    if (r.status == kernels::PairStatus::Farther) return;
    if (r.status == kernels::PairStatus::NotCertified) probed.push_back({r.openBound2, best2, ia, ib});
    accept(ia, ib, r);
  };

  // The previous answer's pair, solved first from its parameters: it is
  // solved whole (the traversal below skips it).
  std::int64_t warmA = -1, warmB = -1;
  if (options.warm && options.warm->found && options.warm->cell[0] >= 0 && options.warm->cell[1] >= 0 &&
      options.warm->cell[0] < cellsA.size() && options.warm->cell[1] < cellsB.size()) {
    const CellPairAnswer& warm = *options.warm;
    warmA = warm.cell[0];
    warmB = warm.cell[1];
    consider(warmA, warmB, solve(warmA, warmB, warm.ref[0], warm.ref[1]));
  }

  const Bvh& treeA = cellsA.bvh();
  const Bvh& treeB = cellsB.bvh();
  // Nodes by their oriented bounds: the axis-aligned boxes of a tilted
  // patch are fat, its oriented ones as thin as it is flat.
  const std::size_t nodesB = treeB.Nodes().size();
  if (ws->movedStamp.size() != nodesB || ++ws->stamp == 0) {
    ws->movedStamp.assign(nodesB, 0);
    ws->moved.resize(nodesB);
    ws->stamp = 1;
  }
  auto nodeBound = [&](int na, int nb) {
    if (ws->movedStamp[nb] != ws->stamp) {
      ws->moved[nb] = Moved(cellsB.nodeOriented(nb), bIntoA);
      ws->movedStamp[nb] = ws->stamp;
    }
    return OrientedPairLowerBound(cellsA.nodeOriented(na), ws->moved[nb], std::sqrt(best2));
  };
  auto diagonal2 = [](const BvhBox& box) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += (box.hi[k] - box.lo[k]) * (box.hi[k] - box.lo[k]);
    return d2;
  };
  auto heapOrder = [](const ModelDistanceWorkspace::Entry& x, const ModelDistanceWorkspace::Entry& y) {
    return x.lowerBound > y.lowerBound;
  };
  // Two leaves: their cell pairs, nearest boxes first.
  auto solveLeaves = [&](const BvhNode& nodeA, const BvhNode& nodeB) {
    auto& candidates = ws->candidates;
    candidates.clear();
    for (int i = nodeA.first; i < nodeA.first + nodeA.count; ++i) {
      const BvhBox& boxA = treeA.ItemBoxes()[i];
      for (int j = nodeB.first; j < nodeB.first + nodeB.count; ++j) {
        const BvhBox& boxB = treeB.ItemBoxes()[j];
        const double lb = bound.LowerBound(boxA.lo, boxA.hi, boxB.lo, boxB.hi);
        if (lb * lb < best2) candidates.push_back({lb, {treeA.Items()[i], treeB.Items()[j]}});
      }
    }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [lb, pair] : candidates) {
      if (!(lb * lb < best2) || !(best2 > zero * zero)) break;
      if (pair.first == warmA && pair.second == warmB) continue;
      if (cache && cache->Excludes(pair.first, pair.second, std::sqrt(best2))) continue;
      // A pair with a partition kept is searched from it after the
      // traversal; a probe (a local solve from the whole pair's nets) would
      // cost about as much as that search.
      if (cache && cache->HasPartition(pair.first, pair.second)) {
        probed.push_back({0.0, best2, pair.first, pair.second});
        continue;
      }
      probe(pair.first, pair.second);
    }
  };
  // Descend the larger node (a leaf stays whole).
  auto splitsA = [&](int na, int nb) {
    const BvhNode& nodeA = treeA.Nodes()[na];
    const BvhNode& nodeB = treeB.Nodes()[nb];
    return nodeB.count > 0 || (nodeA.count == 0 && diagonal2(treeA.NodeBounds(na)) >= diagonal2(treeB.NodeBounds(nb)));
  };

  // Without a bound yet, one dive to the nearer child at every level gives
  // a first pair: the search below then prunes from its first step.
  if (!(best2 < kInf)) {
    int na = 0, nb = 0;
    for (;;) {
      const BvhNode& nodeA = treeA.Nodes()[na];
      const BvhNode& nodeB = treeB.Nodes()[nb];
      if (nodeA.count > 0 && nodeB.count > 0) {
        solveLeaves(nodeA, nodeB);
        break;
      }
      const bool splitA = splitsA(na, nb);
      const int first = splitA ? nodeA.first : nodeB.first;
      const double lb0 = splitA ? nodeBound(first, nb) : nodeBound(na, first);
      const double lb1 = splitA ? nodeBound(first + 1, nb) : nodeBound(na, first + 1);
      (splitA ? na : nb) = lb1 < lb0 ? first + 1 : first;
    }
  }

  std::vector<ModelDistanceWorkspace::Entry>& heap = ws->heap;
  heap.clear();
  // With a cache, where the traversal stops is kept (PairBoundCache): every
  // pair of nodes it prunes, with its bound, and every pair of leaves it solves.
  std::vector<PairBoundCache::FrontierEntry>& frontier = ws->frontier;
  frontier.clear();
  auto stopAt = [&](int na, int nb, double lb) {
    if (cache) frontier.push_back({na, nb, lb, cache->drift()});
  };
  const bool fromRoots = !cache || cache->frontier().empty();
  if (fromRoots) {
    heap.push_back({nodeBound(0, 0), 0, 0});
  } else {
    // The previous frontier covers every pair of cells once: an entry whose
    // bound the drift has not used up stays pruned; the rest are
    // descended from.
    for (const PairBoundCache::FrontierEntry& e : cache->frontier()) {
      if (cache->Holds(e, std::sqrt(best2))) {
        frontier.push_back(e);
        continue;
      }
      const double lb = nodeBound(e.nodeA, e.nodeB);
      if (lb * lb < best2) {
        heap.push_back({lb, e.nodeA, e.nodeB});
      } else {
        stopAt(e.nodeA, e.nodeB, lb);
      }
    }
    std::make_heap(heap.begin(), heap.end(), heapOrder);
  }
  while (!heap.empty() && best2 > zero * zero) {
    std::pop_heap(heap.begin(), heap.end(), heapOrder);
    const ModelDistanceWorkspace::Entry entry = heap.back();
    heap.pop_back();
    if (!(entry.lowerBound * entry.lowerBound < best2)) {
      stopAt(entry.nodeA, entry.nodeB, entry.lowerBound);
      break;  // every other pair is farther still
    }
    const BvhNode& nodeA = treeA.Nodes()[entry.nodeA];
    const BvhNode& nodeB = treeB.Nodes()[entry.nodeB];
    if (nodeA.count > 0 && nodeB.count > 0) {
      solveLeaves(nodeA, nodeB);
      stopAt(entry.nodeA, entry.nodeB, entry.lowerBound);
      continue;
    }
    const bool splitA = splitsA(entry.nodeA, entry.nodeB);
    for (int child = 0; child < 2; ++child) {
      const int na = splitA ? nodeA.first + child : entry.nodeA;
      const int nb = splitA ? entry.nodeB : nodeB.first + child;
      const double lb = nodeBound(na, nb);
      if (lb * lb < best2) {
        heap.push_back({lb, na, nb});
        std::push_heap(heap.begin(), heap.end(), heapOrder);
      } else {
        stopAt(na, nb, lb);
      }
    }
  }
  // What the traversal left in its heap is pruned by the entries' bounds.
  for (const ModelDistanceWorkspace::Entry& entry : heap) stopAt(entry.nodeA, entry.nodeB, entry.lowerBound);
  if (cache) cache->SetFrontier(&frontier, fromRoots);

  std::sort(probed.begin(), probed.end(), [](const OpenPair& x, const OpenPair& y) { return x.openBound2 < y.openBound2; });
  for (const OpenPair& pair : probed) {
    if (!(pair.openBound2 < best2) || !(best2 > zero * zero)) break;
    consider(pair.a, pair.b, solve(pair.a, pair.b, nullptr, nullptr));
  }

  // An open pair is settled when its open parts lie beyond the answer; one
  // that may still hold a closer pair is searched again under the answer's
  // bound (which prunes far more than its first search's own best did).
  for (const OpenPair& pair : open) {
    if (pair.openBound2 >= best2) continue;
    // Searched under this very bound already: a second search ends the same way.
    if (pair.bound2 <= best2) {
      answer.certified = false;
      continue;
    }
    const kernels::PairSolveResult again = SolvePlacedCells(a, pair.a, b, pair.b, nullptr, nullptr, best2, ws);
    if (again.status == kernels::PairStatus::Farther) continue;
    if (again.status == kernels::PairStatus::NotCertified && again.openBound2 < best2) answer.certified = false;
    accept(pair.a, pair.b, again);
  }

  // A model inside a volume meets none of its boundary faces.
  if (!(answer.found && answer.distance <= zero)) {
    for (int side = 0; side < 2; ++side) {
      const PlacedModel& x = side == 0 ? a : b;
      const PlacedModel& y = side == 0 ? b : a;
      if (!x.cells->hasVolumes() || !x.manifold) continue;
      std::vector<double> inX;
      Results hit;
      const std::int64_t c = FirstCellInside(x, y, zero, options.threads, &inX, &hit);
      if (c < 0) continue;
      answer = CellPairAnswer();
      answer.found = true;
      answer.distance = 0.0;
      const int ys = 1 - side;
      answer.cell[ys] = c;
      kernels::ReferenceCenter(y.cells->cell(c).view.shape, answer.ref[ys]);
      const CellStore& storeX = x.cells->store();
      answer.sourceCell[side] = storeX.patchFirstCell(hit.patch[0]) + hit.cell[0];
      const CellOrigin origin = storeX.origin(answer.sourceCell[side]);
      for (int i = 0; i < 3; ++i) {
        answer.sourceRef[side][i] = i < storeX.shape(answer.sourceCell[side]).paramDim()
                                        ? (hit.params[i] - origin.paramLo[i]) / origin.paramScale[i]
                                        : 0.0;
      }
      double local[3] = {0, 0, 0};
      std::copy(inX.begin(), inX.end(), local);
      x.motion.Apply(local, answer.point[side]);
      std::copy(answer.point[side], answer.point[side] + 3, answer.point[ys]);
      break;
    }
  }
  if (answer.found) {
    for (int side = 0; side < 2; ++side) {
      if (answer.cell[side] < 0) continue;
      const DistanceCells& cells = side == 0 ? cellsA : cellsB;
      answer.sourceCell[side] = cells.cell(answer.cell[side]).sourceCell;
      cells.ToSourceRef(answer.cell[side], answer.ref[side], answer.sourceRef[side]);
    }
    // Models that meet are at distance 0.
    if (answer.distance <= zero) answer.distance = 0.0;
  }
  return answer;
}

}  // namespace invmap::engine
