#include "engine/volume_lanes.h"

#include <algorithm>
#include <cmath>

namespace invmap::engine {
namespace {

/// The cell whose straight corner tetrahedron holds `p`, walking from
/// `cell` across the face of the most negative corner barycentric
/// coordinate; *last is the last cell visited. -1 when the walk leaves the
/// mesh, meets a cell the lanes do not solve, or runs out of steps.
std::int64_t Walk(const CellStore& store, const double* p, std::int64_t cell, int maxSteps, std::int64_t* last) {
  const FaceAdjacency& adjacency = store.faceAdjacency();
  for (int step = 0; step <= maxSteps; ++step) {
    if (!IsLaneTetrahedron(store, cell)) return -1;
    *last = cell;
    double lambda[4];
    if (!store.solver(cell).CornerBarycentric(p, lambda)) return -1;
    const int exit = static_cast<int>(std::min_element(lambda, lambda + 4) - lambda);
    if (lambda[exit] >= 0.0) return cell;
    if (adjacency.empty()) return -1;
    cell = adjacency.Neighbor(cell, exit);
  }
  return -1;
}

}  // namespace

void SolveInsideByLanes(const CellStore& store, const double* const coord[3], int count, std::int64_t start,
                        int maxSteps, VolumeLanes* lanes) {
  lanes->cell.assign(count, -1);
  lanes->result.resize(count);
  lanes->order.clear();
  std::int64_t from = start;
  for (int j = 1; j < count; ++j) {
    const double p[3] = {coord[0][j], coord[1][j], coord[2][j]};
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) continue;
    std::int64_t last = from;
    const std::int64_t cell = Walk(store, p, from, maxSteps, &last);
    from = last;
    if (cell >= 0) lanes->order.emplace_back(cell, j);
  }
  // The points of each cell, in their bucket order.
  std::sort(lanes->order.begin(), lanes->order.end());
  for (std::size_t a = 0; a < lanes->order.size();) {
    std::size_t b = a;
    while (b < lanes->order.size() && lanes->order[b].first == lanes->order[a].first) ++b;
    const std::int64_t cell = lanes->order[a].first;
    const int n = static_cast<int>(b - a);
    for (int k = 0; k < 3; ++k) {
      lanes->coord[k].resize(n);
      lanes->ref[k].resize(n);
      lanes->closest[k].resize(n);
    }
    lanes->distance.resize(n);
    lanes->status.resize(n);
    lanes->iterations.resize(n);
    if (lanes->insideCapacity < n) {
      lanes->inside.reset(new bool[n]);
      lanes->insideCapacity = n;
    }
    for (int l = 0; l < n; ++l) {
      for (int k = 0; k < 3; ++k) lanes->coord[k][l] = coord[k][lanes->order[a + l].second];
    }
    kernels::QueryLane query;
    query.count = n;
    kernels::ResultLane result;
    for (int k = 0; k < 3; ++k) {
      query.coord[k] = lanes->coord[k].data();
      result.ref[k] = lanes->ref[k].data();
      result.closest[k] = lanes->closest[k].data();
    }
    result.distance = lanes->distance.data();
    result.status = lanes->status.data();
    result.iterations = lanes->iterations.data();
    store.solver(cell).SolveInsideLane(query, result, lanes->inside.get());
    for (int l = 0; l < n; ++l) {
      if (!lanes->inside[l]) continue;
      const int j = lanes->order[a + l].second;
      kernels::CellSolveResult& r = lanes->result[j];
      for (int k = 0; k < 3; ++k) {
        r.ref[k] = lanes->ref[k][l];
        r.closest[k] = lanes->closest[k][l];
      }
      r.distance = lanes->distance[l];
      r.status = lanes->status[l];
      r.iterations = lanes->iterations[l];
      lanes->cell[j] = cell;
    }
    a = b;
  }
}

}  // namespace invmap::engine
