// The minimum distance between two models under rigid motions: a dual
// traversal of their BVHs, best pair of nodes first, cut at the best
// distance so far; each pair of cells it reaches is solved by the certified
// pair search (kernels/pair_search.h), which excludes most of them by their
// Bernstein nets alone. A volume's boundary faces stand for it, and a model
// lying inside a volume is found by inverting one point of each of its
// cells into the volume.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "engine/distance_cells.h"
#include "engine/pair_bound_cache.h"
#include "invmap/invmap.h"
#include "kernels/pair_search.h"

namespace invmap::engine {

/// The closest pair of points of two models, in terms of their distance cells.
struct CellPairAnswer {
  bool found = false;                ///< False when the models are farther apart than maxDistance.
  /// Distance cells of A and B (-1 for a point inside a volume, which the
  /// inside test found: it has a source cell only).
  std::int64_t cell[2] = {-1, -1};
  double ref[2][3] = {};             ///< Reference coordinates on those cells.
  std::int64_t sourceCell[2] = {-1, -1};  ///< The store cells the points are reported on.
  double sourceRef[2][3] = {};            ///< Their reference coordinates there.
  double point[2][3] = {};           ///< The points, in the common (world) frame.
  double distance = std::numeric_limits<double>::quiet_NaN();
  bool certified = true;             ///< Every pair solve that could matter closed its search.
};

/// One model of a query.
struct PlacedModel {
  const DistanceCells* cells = nullptr;
  kernels::RigidMotion motion;       ///< Its frame into the world.
  /// Its manifold, for the inside test of volumes (null: no volumes).
  const Manifold* manifold = nullptr;
};

struct ModelDistanceOptions {
  double maxDistance = std::numeric_limits<double>::infinity();
  /// A previous answer whose cell pair is solved first, from its
  /// parameters (trackers), or null.
  const CellPairAnswer* warm = nullptr;
  /// The lower bounds of cell pairs proved at earlier motions of the same
  /// two models (trackers), or null: read to skip pairs, and updated.
  PairBoundCache* boundCache = nullptr;
  int threads = 0;  ///< For the inside tests' inversions.
};

/// A pair of cells left for later, and the squared lower bound of what of
/// it is still open.
struct OpenPair {
  double openBound2;  ///< Lower bound of what its search (or probe) left open.
  double bound2;      ///< The bound it was searched under.
  std::int64_t a, b;
};

/// Scratch of the queries; one per thread.
struct ModelDistanceWorkspace {
  kernels::PairWorkspace pair;
  struct Entry {
    double lowerBound;
    int nodeA, nodeB;
  };
  std::vector<Entry> heap;
  std::vector<std::pair<double, std::pair<std::int64_t, std::int64_t>>> candidates;
  std::vector<OpenPair> probed;
  std::vector<PairBoundCache::FrontierEntry> frontier;  ///< The traversal's, for a PairBoundCache.
  /// B's node bounds moved into A's frame, as the traversal meets them:
  /// valid where movedStamp equals stamp (one stamp per query).
  std::vector<OrientedBounds> moved;
  std::vector<std::uint32_t> movedStamp;
  std::uint32_t stamp = 0;
  kernels::DistanceNets scratchNets[2];
  std::int64_t scratchNetsCell[2] = {-1, -1};
  const DistanceCells* scratchNetsModel[2] = {nullptr, nullptr};
  /// What a tracked pair's search leaves, swapped into its PairBoundCache.
  kernels::PairPartition nextPartition;
};

/// The global minimum of |a - b| over the points a of A and b of B (within
/// the pair searches' tolerance), or not found beyond options.maxDistance.
CellPairAnswer NearestPair(const PlacedModel& a, const PlacedModel& b, const ModelDistanceOptions& options,
                           ModelDistanceWorkspace* ws);

/// The pair kernels' view of distance cell `cell` of model `m`. An affine
/// cell keeps no nets; with `needNets` they are built into the workspace
/// (`slot` 0 or 1, one per side, reused while the cell stays the same).
kernels::PairSide PlacedSide(const PlacedModel& m, std::int64_t cell, int slot, bool needNets,
                             ModelDistanceWorkspace* ws);

/// x -> motion^-1 x.
void ToModelFrame(const kernels::RigidMotion& motion, const double* world, double* local);

/// The pair solve of one cell pair, as NearestPair runs it (`start`: both
/// sides' reference coordinates, or null); `bound2` as SolveCellPair's.
/// `reuse`: a tracker's partitions of the pair (kernels::PairReuse), or null.
kernels::PairSolveResult SolvePlacedCells(const PlacedModel& a, std::int64_t cellA, const PlacedModel& b,
                                          std::int64_t cellB, const double* startA, const double* startB,
                                          double bound2, ModelDistanceWorkspace* ws,
                                          const kernels::PairReuse* reuse = nullptr);

}  // namespace invmap::engine
