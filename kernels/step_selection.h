// The steps the local solve chooses from (algorithm 5): the full-rank step
// -J^-1 r of a volume cell (7.3.2.1), the Newton step of the full Hessian
// (over all parameters or the free ones of a cell of line factors), and on
// any face the general choice: full-rank, reduced Newton, Levenberg-Marquardt
// on the Gauss-Newton model, or gradient descent scaled to its Cauchy step.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "kernels/active_set.h"
#include "kernels/cell_map.h"
#include "kernels/cramer.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

/// Pads the unused diagonal of a reduced matrix with ones, so a face of
/// dimension m < 3 factors like its m x m block.
inline void PadDiagonal(int m, Eigen::Matrix3d* a) {
  for (int c = m; c < 3; ++c) (*a)(c, c) = 1.0;
}

/// x = -H^-1 g for the leading m x m block of the symmetric H, by an LDL^T
/// factorization (x[m..2] = 0). False unless that block is positive
/// definite and x is finite and descends (x . g < 0).
bool NewtonStepOf(const double h[3][3], int m, const double* g, double* x);

/// Newton step -H^-1 g of f / 2 with H = J^T J + sum_k r_k d2x_k, over the
/// m parameters coords[0 .. m) (the others keep step 0). False unless that
/// block of H is positive definite and the step is finite and descends.
inline bool NewtonStepOver(const MapJet& jet, const double* r, const double* grad, const int* coords, int m, int ad,
                           double* step) {
  double h[3][3], g[3] = {0, 0, 0}, x[3];  // g zeroed for the compiler: it is read only below m
  for (int a = 0; a < m; ++a) {
    const int i = coords[a];
    g[a] = grad[i];
    for (int b = 0; b <= a; ++b) {
      const int j = coords[b];
      double v = 0.0;
      for (int k = 0; k < ad; ++k) v += jet.d1[k][i] * jet.d1[k][j] + r[k] * jet.d2[k][i][j];
      h[a][b] = h[b][a] = v;
    }
  }
  if (!NewtonStepOf(h, m, g, x)) return false;
  step[0] = step[1] = step[2] = 0.0;
  for (int a = 0; a < m; ++a) step[coords[a]] = x[a];
  return true;
}

/// The step -J^-1 r of a volume cell (pd = ambient dimension 2 or 3) by
/// Cramer's rule; false when J is singular to kSingularTolerance (as the
/// general path decides) or the step is not finite.
inline bool FullRankStep(const MapJet& jet, const double* r, int pd, double size, double* step) {
  step[2] = 0.0;
  if (pd == 2) {
    const double det = jet.d1[0][0] * jet.d1[1][1] - jet.d1[0][1] * jet.d1[1][0];
    if (!(std::abs(det) > kSingularTolerance * size * size)) return false;
    step[0] = -(r[0] * jet.d1[1][1] - r[1] * jet.d1[0][1]) / det;
    step[1] = -(jet.d1[0][0] * r[1] - jet.d1[1][0] * r[0]) / det;
    return std::isfinite(step[0]) && std::isfinite(step[1]);
  }
  // Columns of J: the derivatives along each parameter.
  double c[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) c[i][k] = jet.d1[k][i];
  }
  const double det = Determinant3(c[0], c[1], c[2]);
  if (!(std::abs(det) > kSingularTolerance * size * size * size)) return false;
  const double minusR[3] = {-r[0], -r[1], -r[2]};
  CramerSolve3(c[0], c[1], c[2], det, minusR, step);
  return std::isfinite(step[0]) && std::isfinite(step[1]) && std::isfinite(step[2]);
}

/// The steps of the general path on the face `face` (its basis T) at an
/// iterate with map `jet`, residual r = x - point and gradient `grad` of f / 2
/// (all zero-padded to 3): `model`, the first of the full-rank step -J^-1 r
/// (`useFullRank`: a volume cell with no constraint met), the Newton step of
/// the reduced Hessian (to `order`: the Gauss-Newton one when First) and
/// Levenberg-Marquardt on the reduced Gauss-Newton model that exists and
/// descends; and `descent`, the gradient's step scaled to the Gauss-Newton
/// model's Cauchy step. Both in the cell's parameters.
/// (Inline, as are the steps above and the tests of kernels/stationarity.h:
/// the local solve's every iteration takes them, and out of line they cost
/// about 0.6% more instructions on the curved tet mesh, callgrind, 3000
/// near points.)
struct FaceSteps {
  Eigen::Vector3d model;
  Eigen::Vector3d descent;
  bool newton = false;  ///< `model` is a Newton (or full-rank) step, not Levenberg-Marquardt's.
};
inline FaceSteps StepsOnFace(const MapJet& jet, const double* r, const double* grad, int pd, int ad,
                             const FaceBasis& face, JetOrder order, bool useFullRank, double size) {
  const int m = face.columns;
  const Eigen::Matrix3d T = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&face.t[0][0]);
  const Eigen::Vector3d g = Eigen::Map<const Eigen::Vector3d>(grad);
  const Eigen::Vector3d gReduced = T.transpose() * g;
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();  // rows: ambient coordinates, columns: parameters
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < pd; ++i) jac(k, i) = jet.d1[k][i];
  }
  bool haveStep = false;
  if (useFullRank) {
    // 7.3.2.1: J is square; -J^-1 r is always a descent direction.
    Eigen::Matrix3d square = jac;
    PadDiagonal(pd, &square);
    if (std::abs(square.determinant()) > kSingularTolerance * std::pow(size, pd)) {
      step = square.partialPivLu().solve(-Eigen::Map<const Eigen::Vector3d>(r));
      haveStep = step.allFinite();
    }
  }
  const Eigen::Matrix3d gaussNewton = jac.transpose() * jac;
  Eigen::Matrix3d gnReduced = T.transpose() * gaussNewton * T;
  // Gradient descent scaled to the Gauss-Newton model's Cauchy step.
  const double curvature = gReduced.dot(gnReduced * gReduced);
  const Eigen::Vector3d descent = -gReduced * (gReduced.squaredNorm() / std::max(curvature, 1e-300));
  PadDiagonal(m, &gnReduced);
  if (!haveStep) {
    Eigen::Matrix3d hessian = gaussNewton;
    if (order == JetOrder::Second) {
      for (int i = 0; i < pd; ++i) {
        for (int j = 0; j < pd; ++j) {
          for (int k = 0; k < ad; ++k) hessian(i, j) += r[k] * jet.d2[k][i][j];
        }
      }
    }
    const Eigen::Matrix3d hReduced = T.transpose() * hessian * T;
    double h[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) h[i][j] = hReduced(i, j);
    }
    Eigen::Vector3d delta;
    if (NewtonStepOf(h, m, gReduced.data(), delta.data())) {
      step = T * delta;
      haveStep = true;
    }
  }
  bool newton = haveStep;
  if (!haveStep) {
    // Levenberg-Marquardt on the Gauss-Newton model: a descent direction
    // for any damping, and well defined for singular Jacobians.
    const double damping = kLevenbergDamping * (gnReduced.trace() + size * size) + 1e-300;
    gnReduced.diagonal().array() += damping;
    Eigen::LLT<Eigen::Matrix3d> llt(gnReduced);
    Eigen::Vector3d delta = llt.solve(-gReduced);
    if (llt.info() != Eigen::Success || !delta.allFinite() || delta.dot(gReduced) >= 0.0) delta = descent;
    step = T * delta;
  }
  FaceSteps steps;
  steps.model = step;
  steps.descent = T * descent;
  steps.newton = newton;
  return steps;
}

}  // namespace invmap::kernels
