// The output arrays of CellSolver::SolveLane for a number of lanes (filled
// with -7 to show writes) and the ResultLane pointing at them.
#pragma once

#include <vector>

#include "kernels/cell_solver.h"

namespace invmap::testing {

struct LaneOutput {
  explicit LaneOutput(int count) : distance(count), status(count), iterations(count) {
    for (int k = 0; k < 3; ++k) {
      ref[k].assign(count, -7.0);
      closest[k].assign(count, -7.0);
      out.ref[k] = ref[k].data();
      out.closest[k] = closest[k].data();
    }
    out.distance = distance.data();
    out.status = status.data();
    out.iterations = iterations.data();
  }
  LaneOutput(const LaneOutput&) = delete;
  LaneOutput& operator=(const LaneOutput&) = delete;

  std::vector<double> ref[3], closest[3];
  std::vector<double> distance;
  std::vector<kernels::PointStatus> status;
  std::vector<int> iterations;
  kernels::ResultLane out;
};

}  // namespace invmap::testing
