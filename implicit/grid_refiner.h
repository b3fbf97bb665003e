// Longest refinable edge bisection (section 4 of
// docs/grids.md): repeatedly bisect
// the longest edge of a refinable cell, splitting every cell around it, until
// no cell is refinable.
//
// As in the reference implementation, a priority queue holds one entry per
// refinable cell: its longest edge (the first in local order among equal
// ones), keyed by squared length; an entry whose cell has since been split is
// stale and skipped; only the children of a bisection are tested.
//
// Parallel and deterministic: the queue is drained one length at a time.
// All entries of the current longest length are bisected in queue order
// (the topology changes are sequential and cheap), then the new vertices are
// evaluated and the new cells tested in parallel, and the refinable ones are
// queued in cell order. Equal keys leave the queue first in, first out. The
// reference instead tests children right after each bisection; the two differ
// only in the order of equally long edges (which the reference leaves to its
// heap) and when a child's longest edge is longer than the length being
// drained (rare: such a child waits for the rest of its batch).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "implicit/bisection_grid.h"
#include "invmap/implicit.h"

namespace invmap::implicit {

template <int N>
class GridRefiner {
 public:
  /// Arguments must be valid (see RefineGrid).
  GridRefiner(const SimplexMesh& initial, const std::vector<Function>& functions, const GridOptions& options);

  /// Refines; returns an error message (empty on success): a function
  /// returned a value or gradient that is not finite.
  std::string Run();

  /// The refined grid with values and statistics (after Run).
  Grid TakeGrid();

 private:
  struct QueueEntry {
    double length2;
    std::uint64_t sequence;
    std::uint32_t cell;
    std::uint32_t version;
    std::uint8_t edge;
  };
  struct QueueOrder {
    bool operator()(const QueueEntry& x, const QueueEntry& y) const {
      if (x.length2 != y.length2) return x.length2 < y.length2;
      return x.sequence > y.sequence;
    }
  };

  /// Evaluates the functions at vertices [begin, end); error on a non-finite result.
  std::string EvaluateVertices(std::size_t begin, std::size_t end);
  /// Tests `cells` (parallel), records their activity and queues the refinable ones.
  void TestAndQueue(const std::vector<std::uint32_t>& cells);
  void ComputeStats();

  const std::vector<Function>& functions_;
  GridOptions options_;
  int functionCount_;
  BisectionGrid<N> grid_;

  std::vector<double> values_;         ///< functionCount per vertex.
  std::vector<double> gradients_;      ///< 3 * functionCount per vertex.
  std::vector<double> gradientNorms_;  ///< functionCount per vertex.
  std::vector<std::uint8_t> active_;   ///< Per cell.

  std::vector<QueueEntry> queue_;  ///< A heap ordered by QueueOrder.
  std::uint64_t sequence_ = 0;
  GridStats stats_;
};

extern template class GridRefiner<2>;
extern template class GridRefiner<3>;

}  // namespace invmap::implicit
