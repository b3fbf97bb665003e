// CellSolver::SolveLane for curved cells: the local solves of all lanes in
// SIMD lanes (kernels/newton_lanes.h), then each lane's certificate.
#include <algorithm>
#include <cmath>

#include "kernels/cell_solver.h"
#include "kernels/newton_lanes.h"

namespace invmap::kernels {

void CellSolver::SolveCurvedLanes(const QueryLane& queries, const ResultLane& results, SolveWorkspace* ws) const {
  const int pd = cell_.shape.paramDim();
  const int ad = cell_.ambientDim;
  const bool warm = queries.initialRef[0] != nullptr;
  // Cells the lanes do not cover, affine maps (one exact step, no
  // certificate needed) and unbalanced weights (solved in charts) take
  // Solve's path, lane by lane.
  const bool lanesCover = !affine_ && !charts_ && NewtonLanesCover(cell_);
  // The lanes run a chunk at a time from arrays on the stack: the finite
  // points, gathered (Solve answers the others with InvalidInput).
  constexpr int kChunk = 64;
  double point[3][kChunk], ref[3][kChunk], closest[3][kChunk], squaredDistance[kChunk], level[kChunk];
  bool onBoundary[kChunk], convex[kChunk];
  LaneOutcome outcome[kChunk];
  int iterations[kChunk], lane[kChunk];
  const double tau = kDistanceTolerance * size_;
  for (int first = 0; first < queries.count; first += kChunk) {
    const int end = std::min(queries.count, first + kChunk);
    int n = 0;
    for (int l = first; l < end; ++l) {
      double p[3] = {0, 0, 0}, start[3] = {0, 0, 0};  // start: the lanes' own when cold
      bool finite = true;
      for (int k = 0; k < ad; ++k) {
        p[k] = queries.coord[k][l];
        finite = finite && std::isfinite(p[k]);
      }
      if (warm) {
        for (int i = 0; i < pd; ++i) start[i] = queries.initialRef[i][l];
      }
      if (!finite || !lanesCover) {
        WriteLane(l, Solve(p, warm ? start : nullptr, ws), results);
        continue;
      }
      for (int k = 0; k < ad; ++k) point[k][n] = p[k];
      for (int i = 0; i < pd; ++i) ref[i][n] = start[i];
      lane[n++] = l;
    }
    if (n == 0) continue;
    NewtonLanes lanes;
    lanes.count = n;
    for (int k = 0; k < ad; ++k) {
      lanes.point[k] = point[k];
      lanes.closest[k] = closest[k];
    }
    for (int i = 0; i < pd; ++i) lanes.ref[i] = ref[i];
    lanes.squaredDistance = squaredDistance;
    lanes.onBoundary = onBoundary;
    lanes.outcome = outcome;
    lanes.iterations = iterations;
    lanes.startAtNearestControlPoint = !warm;
    SolveNewtonLanes(cell_, size_, lanes);
    // The curvature bounds' certificate (Search's first test) for all the
    // lanes that reached a KKT point farther than tau at once.
    if (curvature_) {
      for (int j = 0; j < n; ++j) level[j] = outcome[j] == LaneOutcome::Kkt ? squaredDistance[j] : -1.0;
      const double* const points[3] = {point[0], point[1], point[2]};
      ProvesConvexLanes(*curvature_, n, points, level, convex);
    }
    for (int j = 0; j < n; ++j) {
      const double p[3] = {point[0][j], point[1][j], ad > 2 ? point[2][j] : 0.0};
      const double at[3] = {ref[0][j], pd > 1 ? ref[1][j] : 0.0, 0.0};
      if (outcome[j] == LaneOutcome::Handover) {
        // The scalar solve carries on from where the lane stopped.
        CellSolveResult r = Solve(p, at, ws);
        r.iterations += iterations[j];
        WriteLane(lane[j], r, results);
        continue;
      }
      // Solve's certificate of a local answer (see Solve).
      LocalSolveResult best;
      std::copy(at, at + 3, best.ref);
      for (int k = 0; k < ad; ++k) best.closest[k] = closest[k][j];
      best.squaredDistance = squaredDistance[j];
      best.onBoundary = onBoundary[j];
      best.converged = best.kkt = true;
      best.iterations = iterations[j];
      int total = iterations[j];
      bool certified = true;
      if (best.squaredDistance > tau * tau && !(curvature_ && convex[j])) {
        certified = Search(p, std::numeric_limits<double>::infinity(), nets_.RoundingSlack(p), &best, &total, ws);
      }
      CellSolveResult r;
      std::copy(best.ref, best.ref + pd, r.ref);
      std::copy(best.closest, best.closest + ad, r.closest);
      r.distance = std::sqrt(best.squaredDistance);
      r.iterations = total;
      r.status = !certified         ? PointStatus::NotCertified
                 : best.onBoundary ? PointStatus::ProjectedToBoundary
                                   : PointStatus::Converged;
      WriteLane(lane[j], r, results);
    }
  }
}

void CellSolver::SolveInsideLane(const QueryLane& queries, const ResultLane& results, bool* inside) const {
  const int pd = cell_.shape.paramDim();
  const int ad = cell_.ambientDim;
  const bool warm = queries.initialRef[0] != nullptr;
  const bool lanesCover = !affine_ && !charts_ && isFullRank() && InsideLanesCover(cell_);
  constexpr int kChunk = 64;
  double point[3][kChunk], ref[3][kChunk], closest[3][kChunk], squaredDistance[kChunk], lambdas[kChunk][4];
  InsideOutcome outcome[kChunk];
  int iterations[kChunk], lane[kChunk];
  bool haveLambda[kChunk];
  for (int first = 0; first < queries.count; first += kChunk) {
    const int end = std::min(queries.count, first + kChunk);
    int n = 0;
    for (int l = first; l < end; ++l) {
      double p[3] = {0, 0, 0}, initial[3] = {0, 0, 0}, start[3] = {0, 0, 0};
      bool finite = true;
      for (int k = 0; k < ad; ++k) {
        p[k] = queries.coord[k][l];
        finite = finite && std::isfinite(p[k]);
      }
      if (warm) {
        for (int i = 0; i < pd; ++i) initial[i] = queries.initialRef[i][l];
      }
      CellSolveResult r;
      if (!finite || !lanesCover) {
        inside[l] = finite && SolveInside(p, warm ? initial : nullptr, &r);
        if (inside[l]) WriteLane(l, r, results);
        continue;
      }
      double* lambda = lambdas[n];
      haveLambda[n] = CornerBarycentric(p, lambda);
      if (!InsideStart(warm ? initial : nullptr, lambda, haveLambda[n], start)) {
        inside[l] = false;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        point[k][n] = p[k];
        ref[k][n] = start[k];
      }
      lane[n++] = l;
    }
    if (n == 0) continue;
    InsideLanes lanes;
    lanes.count = n;
    for (int k = 0; k < 3; ++k) {
      lanes.point[k] = point[k];
      lanes.ref[k] = ref[k];
      lanes.closest[k] = closest[k];
    }
    lanes.squaredDistance = squaredDistance;
    lanes.outcome = outcome;
    lanes.iterations = iterations;
    SolveInsideLanes(cell_, size_, lanes);
    for (int j = 0; j < n; ++j) {
      const int l = lane[j];
      CellSolveResult r;
      if (outcome[j] == InsideOutcome::Handover) {
        // The scalar inside solve decides, from its own start.
        const double p[3] = {point[0][j], point[1][j], point[2][j]};
        double initial[3] = {0, 0, 0};
        if (warm) {
          for (int i = 0; i < pd; ++i) initial[i] = queries.initialRef[i][l];
        }
        inside[l] = SolveInside(p, warm ? initial : nullptr, &r, haveLambda[j] ? lambdas[j] : nullptr);
        if (inside[l]) WriteLane(l, r, results);
        continue;
      }
      inside[l] = outcome[j] == InsideOutcome::Inside;
      if (!inside[l]) continue;
      for (int k = 0; k < 3; ++k) {
        r.ref[k] = ref[k][j];
        r.closest[k] = closest[k][j];
      }
      r.distance = std::sqrt(squaredDistance[j]);
      r.iterations = iterations[j];
      r.status = PointStatus::Converged;
      WriteLane(l, r, results);
    }
  }
}

}  // namespace invmap::kernels
