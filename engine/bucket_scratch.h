// The scratch memory of one task of the batch, reused across its buckets so
// that the per-point path never allocates once warm. It holds no state that
// changes any result.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/bucket_lanes.h"
#include "engine/nearest_cells.h"
#include "engine/volume_lanes.h"
#include "kernels/cell_solver.h"
#include "kernels/local_solver.h"

namespace invmap::engine {

/// A child of a wide node waiting on the search's stack: its lower bound,
/// and the node (count 0) or the leaf's items it stands for.
struct WideEntry {
  double lowerBound2;
  std::int32_t first;
  std::int32_t count;
};

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
  // The answers of the bucket's points that the curved cells' lanes settled.
  BucketLanes bucketLanes;
  VolumeLanes volumeLanes;
};

}  // namespace invmap::engine
