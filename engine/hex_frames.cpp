#include "engine/hex_frames.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/cramer.h"
#include "kernels/reference_faces.h"
#include "kernels/tolerances.h"

namespace invmap::engine {

bool HexFrames::IsFramed(const kernels::CellSolver& solver) {
  const kernels::CellView& cell = solver.cell();
  return cell.shape.type() == kernels::CellType::Hex && cell.ambientDim == 3 && solver.isAffine() &&
         solver.isFullRank();
}

bool HexFrames::Fill(const kernels::CellSolver& solver, HexFrame* frame) {
  frame->tau2 = std::numeric_limits<double>::quiet_NaN();
  std::fill(frame->neighbors, frame->neighbors + 6, -1);
  if (!IsFramed(solver)) return false;
  const kernels::CellView& cell = solver.cell();
  // The corners FrameCoordinates reads: at the reference origin and at the
  // unit point of each parameter (factor i holds parameter i).
  const auto corner = [&](int i) {
    int vertex[kernels::kMaxFactors] = {0, 0, 0};
    if (i >= 0) vertex[i] = 1;
    return cell.points + static_cast<std::size_t>(kernels::CornerControlPoint(cell.shape, vertex)) * 3;
  };
  const double* origin = corner(-1);
  for (int k = 0; k < 3; ++k) frame->origin[k] = origin[k];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) frame->edge[i][k] = corner(i)[k] - origin[k];
  }
  const double det = kernels::Determinant3(frame->edge[0], frame->edge[1], frame->edge[2]);
  if (!(std::fabs(det) > 0) || !std::isfinite(det)) return false;
  const double tau = kernels::kDistanceTolerance * solver.size();
  frame->tau2 = tau * tau;
  return true;
}

FrameVerdict HexFrames::Locate(const HexFrame& frame, const double* point, kernels::CellSolveResult* result) {
  double w[3], x[3];
  for (int k = 0; k < 3; ++k) w[k] = point[k] - frame.origin[k];
  const double det = kernels::Determinant3(frame.edge[0], frame.edge[1], frame.edge[2]);
  kernels::CramerSolve3(frame.edge[0], frame.edge[1], frame.edge[2], det, w, x);
  if (!(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))) return FrameVerdict::Unsure;
  std::copy(x, x + 3, result->ref);
  // LeastBarycentric of a hexahedron: each factor's (1 - u, u).
  double least = 1.0;
  for (int i = 0; i < 3; ++i) {
    double lambda0 = 1.0;
    lambda0 -= x[i];
    least = std::min({least, lambda0, x[i]});
  }
  if (least < -kernels::kHullSlack) return FrameVerdict::Outside;
  if (least < 0.0) return FrameVerdict::Unsure;  // SolveInside clamps it into the domain first
  // The frame's map at x less the point.
  double r[3], d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    r[k] = frame.edge[0][k] * x[0] + frame.edge[1][k] * x[1] + frame.edge[2][k] * x[2] - w[k];
    d2 += r[k] * r[k];
  }
  if (!(d2 <= 0.25 * frame.tau2)) return FrameVerdict::Unsure;
  for (int k = 0; k < 3; ++k) result->closest[k] = point[k] + r[k];
  result->distance = std::sqrt(d2);
  result->status = least > 0.0 ? kernels::PointStatus::Converged : kernels::PointStatus::ProjectedToBoundary;
  result->iterations = 0;
  return FrameVerdict::Inside;
}

int HexFrames::ExitFaces(const double* ref, int* faces) {
  static const kernels::CellShape kHexahedron(kernels::CellType::Hex, {1, 1, 1});
  return kernels::FacesAt(kHexahedron, ref, faces);
}

}  // namespace invmap::engine
