// CellSolver::SolveLane for curved cells: the local solves of all lanes in
// SIMD lanes (kernels/newton_lanes.h), then each lane's certificate.
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/cell_solver.h"
#include "kernels/newton_lanes.h"

namespace invmap::kernels {

void CellSolver::SolveCurvedLanes(const QueryLane& queries, const ResultLane& results, SolveWorkspace* ws) const {
  const int pd = cell_.shape.paramDim();
  const int ad = cell_.ambientDim;
  const bool warm = queries.initialRef[0] != nullptr;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Cells the lanes do not cover, affine maps (one exact step, no
  // certificate needed), unbalanced weights (solved in charts) and trimmed
  // cells (whose answers the face's region admits) take Solve's path, lane
  // by lane.
  const bool lanesCover = !affine_ && !charts_ && !trim_ && NewtonLanesCover(cell_);
  // The lanes run a chunk at a time from arrays on the stack: the finite
  // points that a bound does not exclude at once, gathered.
  constexpr int kChunk = 64;
  double point[3][kChunk], ref[3][kChunk], closest[3][kChunk], squaredDistance[kChunk], level[kChunk];
  double bound[kChunk], slack[kChunk], lower[kChunk], exclusion[kChunk];
  bool onBoundary[kChunk], convex[kChunk];
  LaneOutcome outcome[kChunk];
  int iterations[kChunk], lane[kChunk];
  const double tau = kDistanceTolerance * size_;
  const NetLanes nets{nets_.size(), ad, nets_.rational(), nets_.nn(), {nets_.nw(0), nets_.nw(1), ad > 2 ? nets_.nw(2) : nullptr},
                      nets_.ww(), nets_.center()};
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
      const double bound2 = queries.bound2 ? queries.bound2[l] : kInf;
      if (!finite || !lanesCover) {
        WriteLane(l, Solve(p, warm ? start : nullptr, ws, bound2), results);
        continue;
      }
      for (int k = 0; k < ad; ++k) point[k][n] = p[k];
      for (int i = 0; i < pd; ++i) ref[i][n] = start[i];
      bound[n] = bound2;
      lane[n++] = l;
    }
    if (n == 0) continue;
    const double* const points[3] = {point[0], point[1], point[2]};
    if (queries.bound2) {
      // Solve's first test, for all lanes: the larger of the box's and the
      // nets' lower bounds (less their rounding) against the bound.
      NetLowerBoundLanes(nets, n, points, lower);
      int kept = 0;
      for (int j = 0; j < n; ++j) {
        const double p[3] = {point[0][j], point[1][j], ad > 2 ? point[2][j] : 0.0};
        slack[j] = nets_.RoundingSlack(p);
        double box2 = 0.0;
        for (int k = 0; k < ad; ++k) {
          const double d = std::max({boxLo_[k] - p[k], 0.0, p[k] - boxHi_[k]});
          box2 += d * d;
        }
        if (bound[j] < kInf && std::max(box2, lower[j] - slack[j]) >= bound[j]) {
          CellSolveResult farther;
          farther.status = PointStatus::Farther;
          WriteLane(lane[j], farther, results);
          continue;
        }
        // Surfaces that must beat a bound try LocalSolve's exclusion.
        exclusion[kept] = bound[j] < kInf && pd > 1 ? ExclusionLevel(bound[j], tau, slack[j]) : -kInf;
        for (int k = 0; k < 3; ++k) {
          point[k][kept] = point[k][j];
          ref[k][kept] = ref[k][j];
        }
        bound[kept] = bound[j];
        slack[kept] = slack[j];
        lane[kept++] = lane[j];
      }
      n = kept;
      if (n == 0) continue;
    }
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
    if (queries.bound2) lanes.exclusionLevel = exclusion;
    SolveNewtonLanes(cell_, size_, lanes);
    // The curvature bounds' certificate for all lanes at once: of a KKT
    // point farther than tau at its distance (Search's first test), of an
    // exclusion at its level (ExcessIsConvex's first test).
    if (curvature_) {
      for (int j = 0; j < n; ++j) {
        level[j] = outcome[j] == LaneOutcome::Kkt ? squaredDistance[j]
                   : outcome[j] == LaneOutcome::AboveLevel ? exclusion[j]
                                                            : -1.0;
      }
      ProvesConvexLanes(*curvature_, n, points, level, convex);
    }
    for (int j = 0; j < n; ++j) {
      const double p[3] = {point[0][j], point[1][j], ad > 2 ? point[2][j] : 0.0};
      const double at[3] = {ref[0][j], pd > 1 ? ref[1][j] : 0.0, 0.0};
      const double bound2 = bound[j];
      if (outcome[j] == LaneOutcome::AboveLevel) {
        if (!(curvature_ && convex[j])) {
          // The rest of ExcessIsConvex: the net of q - level WW.
          if (ws->scratch.size() < static_cast<std::size_t>(nets_.size())) ws->scratch.resize(nets_.size());
          nets_.SquaredDistanceNumerator(p, ws->scratch.data());
          convex[j] = ExcessIsConvex(p, exclusion[j], slack[j], ws->scratch.data());
        }
        if (convex[j]) {
          CellSolveResult farther;
          farther.status = PointStatus::Farther;
          farther.iterations = iterations[j];
          WriteLane(lane[j], farther, results);
          continue;
        }
        outcome[j] = LaneOutcome::Handover;
      }
      if (outcome[j] == LaneOutcome::Handover) {
        // The scalar solve carries on from where the lane stopped.
        CellSolveResult r = Solve(p, at, ws, bound2);
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
        certified = Search(p, bound2, nets_.RoundingSlack(p), &best, &total, ws, nullptr);
      }
      CellSolveResult r;
      std::copy(best.ref, best.ref + pd, r.ref);
      std::copy(best.closest, best.closest + ad, r.closest);
      r.distance = std::sqrt(best.squaredDistance);
      r.iterations = total;
      r.status = best.squaredDistance >= bound2 ? PointStatus::Farther
                 : !certified                  ? PointStatus::NotCertified
                 : best.onBoundary             ? PointStatus::ProjectedToBoundary
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
