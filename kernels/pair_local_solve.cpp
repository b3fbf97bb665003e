#include "kernels/pair_local_solve.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

// Joint parameters are at most 6: fixed-capacity matrices keep the solve
// off the heap.
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxPairParams, kMaxPairParams>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPairParams, 1>;


/// The Jacobian (ambient x n) of a jet.
Matrix JacobianOf(const PairJet& jet, int ad, int n) {
  Matrix j(ad, n);
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < n; ++i) j(k, i) = jet.d1[k][i];
  }
  return j;
}

/// The rounding level of F = |z|^2 / 2: z carries a few ulps of the points'
/// magnitude.
double RoundingOfF(const PairJet& jet, int ad, double size) {
  double magnitude = size;
  for (int k = 0; k < ad; ++k) magnitude = std::max({magnitude, std::abs(jet.x[k]), std::abs(jet.y[k])});
  const double zError = 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  return std::sqrt(2.0 * PairSquaredDistance(jet, ad)) * zError + zError * zError;
}

/// Rows of the normals of `working` constraints (m x n).
Matrix ConstraintRows(const PairLayout& layout, const int* working, int m) {
  const int n = layout.n();
  Matrix c(m, n);
  double normal[kMaxPairParams];
  for (int r = 0; r < m; ++r) {
    layout.Normal(working[r], normal);
    for (int i = 0; i < n; ++i) c(r, i) = normal[i];
  }
  return c;
}

/// An orthonormal basis (n x (n - m)) of the null space of the m x n rows
/// `c` (independent: the constraints of a product of simplices that can hold
/// at once are).
Matrix NullSpace(const Matrix& c, int n) {
  const int m = static_cast<int>(c.rows());
  if (m == 0) return Matrix::Identity(n, n);
  const Matrix ct = c.transpose();
  Eigen::HouseholderQR<Matrix> qr(ct);
  const Matrix q = qr.householderQ() * Matrix::Identity(n, n);
  return q.rightCols(n - m);
}

/// Minimizes g . p + p^T B p / 2 (B positive definite) over steps p that keep
/// w + p in the domain: a primal active-set method from p = 0, whose
/// working set starts with the constraints holding at w.
Vector SolveQp(const PairLayout& layout, const double* w, const Matrix& b, const Vector& g) {
  const int n = layout.n();
  Vector p = Vector::Zero(n);
  int working[kMaxPairConstraints];
  bool inWorking[kMaxPairConstraints] = {};
  int m = 0;
  for (int c = 0; c < layout.numConstraints(); ++c) {
    if (layout.Slack(c, w) <= kActiveSlack && m < n) {
      working[m++] = c;
      inWorking[c] = true;
    }
  }
  double normal[kMaxPairParams];
  double at[kMaxPairParams];
  for (int iteration = 0; iteration < 4 * kMaxPairConstraints; ++iteration) {
    const Vector gradient = g + b * p;
    const Matrix c = ConstraintRows(layout, working, m);
    Vector d = Vector::Zero(n);
    if (m < n) {
      const Matrix z = NullSpace(c, n);
      const Matrix reduced = z.transpose() * b * z;
      d = -z * reduced.llt().solve(z.transpose() * gradient);
    }
    if (!d.allFinite()) return p;
    if (d.lpNorm<Eigen::Infinity>() <= kNoStep) {
      if (m == 0) return p;
      // Stationary on the working face: release the constraint whose
      // multiplier (gradient = C^T lambda) pulls away from it most.
      const Vector lambda = (c * c.transpose()).ldlt().solve(c * gradient);
      int release = -1;
      double most = 0.0;
      for (int r = 0; r < m; ++r) {
        if (lambda[r] < most) {
          most = lambda[r];
          release = r;
        }
      }
      if (release < 0) return p;
      inWorking[working[release]] = false;
      working[release] = working[--m];
      continue;
    }
    // The longest step along d that stays in the domain.
    double alpha = 1.0;
    int blocking = -1;
    for (int i = 0; i < n; ++i) at[i] = w[i] + p[i];
    for (int k = 0; k < layout.numConstraints(); ++k) {
      if (inWorking[k]) continue;
      layout.Normal(k, normal);
      double slope = 0.0;
      for (int i = 0; i < n; ++i) slope += normal[i] * d[i];
      if (slope >= 0.0) continue;
      const double reach = std::max(layout.Slack(k, at), 0.0) / -slope;
      if (reach < alpha) {
        alpha = reach;
        blocking = k;
      }
    }
    p += alpha * d;
    if (blocking >= 0 && m < n) {
      working[m++] = blocking;
      inWorking[blocking] = true;
    }
  }
  return p;
}

/// The Hessian of F = |z|^2 / 2 at `jet`: J^T J + sum_k z_k d2 z_k.
Matrix HessianOf(const PairJet& jet, const Matrix& j, int ad, int n) {
  Matrix h = j.transpose() * j;
  for (int k = 0; k < ad; ++k) {
    for (int a = 0; a < n; ++a) {
      for (int c = 0; c < n; ++c) h(a, c) += jet.z[k] * jet.d2[k][a][c];
    }
  }
  return h;
}

}  // namespace

PairKkt CheckPairKkt(const PairLayout& layout, const PairJet& jet, const double* w, int ambientDim, double size) {
  PairKkt result;
  const int n = layout.n();
  const Matrix j = JacobianOf(jet, ambientDim, n);
  Vector z(ambientDim);
  for (int k = 0; k < ambientDim; ++k) z[k] = jet.z[k];
  const Vector g = j.transpose() * z;
  for (int i = 0; i < n; ++i) result.gradient[i] = g[i];
  const double r = z.norm();
  if (!(r > kDistanceTolerance * size)) {
    // The models meet here: nothing is closer.
    result.kkt = std::isfinite(r);
    return result;
  }
  // Active: the slack is rounding and the map, moved that far off the
  // face, moves less than 1e-12 of the size.
  double normal[kMaxPairParams];
  for (int c = 0; c < layout.numConstraints(); ++c) {
    const double slack = layout.Slack(c, w);
    if (slack > 1e-12) continue;
    layout.Normal(c, normal);
    double moved2 = 0.0;
    for (int k = 0; k < ambientDim; ++k) {
      double m = 0.0;
      for (int i = 0; i < n; ++i) m += j(k, i) * normal[i];
      moved2 += m * m;
    }
    if (slack * std::sqrt(moved2) <= 1e-12 * size && result.numActive < n) result.active[result.numActive++] = c;
  }
  const int m = result.numActive;
  const Matrix c = ConstraintRows(layout, result.active, m);
  Vector lambda = Vector::Zero(m);
  Matrix pseudoInverse(n, m);  // columns: the step off each active constraint alone
  if (m > 0) {
    const Matrix gram = c * c.transpose();
    lambda = gram.ldlt().solve(c * g);
    pseudoInverse = c.transpose() * gram.inverse();
  }
  for (int a = 0; a < m; ++a) result.multiplier[a] = lambda[a];
  // Each slope judged by how far z moves along its direction, as the point
  // solves judge theirs: |r . J v| <= (1e-7 |r| + 1e-12 size) |J v|.
  const double perLength = 1e-7 * r + 1e-12 * size;
  const double floorLength = kThinDirection * size;
  // Along a direction z barely moves (the two points sliding together
  // along parallel tangents: with more parameters than coordinates there is
  // always one), the distance changes at second order: the direction's
  // length is then its curvature's square root.
  const Matrix h = HessianOf(jet, j, ambientDim, n);
  auto tolerance = [&](const Vector& v) {
    const double bend = std::sqrt(std::max(v.dot(h * v), 0.0));
    return perLength * std::max({(j * v).norm(), bend, floorLength});
  };
  if (m < n) {
    // Free directions whose images under J are orthogonal: a direction the
    // map stretches little is judged by its own length, not another's.
    const Matrix basis = NullSpace(c, n);
    const Matrix metric = basis.transpose() * j.transpose() * j * basis;
    Eigen::SelfAdjointEigenSolver<Matrix> eigen(metric);
    const Matrix directions = basis * eigen.eigenvectors();
    for (int col = 0; col < n - m; ++col) {
      const Vector v = directions.col(col);
      if (!(std::abs(g.dot(v)) <= tolerance(v))) return result;
    }
  }
  for (int a = 0; a < m; ++a) {
    const Vector v = pseudoInverse.col(a);
    if (!(g.dot(v) >= -tolerance(v))) return result;
  }
  result.kkt = true;
  return result;
}

PairLocalResult PairLocalSolve(const PairSide& a, const PairSide& b, const PairLayout& layout, const double* start,
                               const PairLocalOptions& options) {
  PairLocalResult result;
  const int n = layout.n();
  const int ad = a.cell.ambientDim;
  double w[kMaxPairParams];
  std::copy(start, start + n, w);
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(w[i])) w[i] = 0.0;
  }
  layout.Project(w);
  PairJet jet;
  EvaluatePair(a, b, layout, w, JetOrder::Second, &jet);
  double f = 0.5 * PairSquaredDistance(jet, ad);
  const double zero = kDistanceTolerance * options.size;
  const double floor = kThinDirection * options.size * kThinDirection * options.size;
  // Newton's model damped Levenberg-Marquardt style (a trust region in the
  // metric of J's columns): where the quadratic model predicts the
  // decrease, the damping falls to zero and the steps are Newton's; where
  // it does not (far from a minimum, where the distance's curvature terms
  // are as large as J^T J and change fast), it grows and the steps shorten
  // toward the gradient's, instead of backtracking along a poor direction.
  double damping = 0.0;
  for (int iteration = 0; iteration < options.maxIterations; ++iteration) {
    if (!(f > 0.5 * zero * zero)) {
      result.converged = std::isfinite(f);
      break;
    }
    const Matrix j = JacobianOf(jet, ad, n);
    Vector z(ad);
    for (int k = 0; k < ad; ++k) z[k] = jet.z[k];
    const Vector g = j.transpose() * z;
    const Matrix h = HessianOf(jet, j, ad, n);
    Vector metric(n);
    for (int c = 0; c < n; ++c) metric[c] = j.col(c).squaredNorm() + floor;
    // Newton's model with its negative curvature turned positive (the
    // Hessian's eigenvalues by their magnitudes): along a direction where
    // the distance is concave it then steps as far as that curvature
    // suggests, where damping the Hessian until it is convex would crawl.
    Eigen::SelfAdjointEigenSolver<Matrix> eigen(h);
    Vector curvature = eigen.eigenvalues().cwiseAbs();
    const double largest = curvature.maxCoeff();
    for (int c = 0; c < n; ++c) curvature[c] = std::max(curvature[c], 1e-12 * largest + floor);
    Matrix model = eigen.eigenvectors() * curvature.asDiagonal() * eigen.eigenvectors().transpose();
    model.diagonal() += damping * metric;
    const bool newton = damping == 0.0 && eigen.eigenvalues().minCoeff() > 0.0;
    const Vector p = SolveQp(layout, w, model, g);
    const double predicted = -(g.dot(p) + 0.5 * p.dot(model * p));
    const double rounding = RoundingOfF(jet, ad, options.size);
    if (!(predicted > rounding) || !(p.lpNorm<Eigen::Infinity>() > kNoStep)) {
      // A Newton step whose decrease the distance's rounding hides is in the
      // quadratic region: taken unchecked, it resolves the point's last
      // digits, along flat directions too (the two points sliding together
      // along parallel tangents, where only the curvature tells).
      if (newton && p.lpNorm<Eigen::Infinity>() > kNoStep && p.lpNorm<Eigen::Infinity>() < options.finalStep) {
        for (int i = 0; i < n; ++i) w[i] += p[i];
        layout.Project(w);
        EvaluatePair(a, b, layout, w, JetOrder::Second, &jet);
      }
      result.converged = true;
      break;
    }
    double wt[kMaxPairParams];
    for (int i = 0; i < n; ++i) wt[i] = w[i] + p[i];
    layout.Project(wt);
    PairJet trial;
    EvaluatePair(a, b, layout, wt, JetOrder::Second, &trial);
    const double ft = 0.5 * PairSquaredDistance(trial, ad);
    ++result.iterations;
    const double ratio = (f - ft) / predicted;
    if (!(ft < f) || ratio < 0.1) {
      damping = std::max(4.0 * damping, 1e-4);
      if (damping > 1e20) {
        // No step decreases the distance beyond rounding: converged as far
        // as doubles tell.
        result.converged = predicted <= 1e3 * rounding;
        break;
      }
      continue;
    }
    if (ratio > 0.75) damping = damping < 1e-12 ? 0.0 : damping / 4.0;
    double moved = 0.0;
    for (int i = 0; i < n; ++i) moved = std::max(moved, std::abs(wt[i] - w[i]));
    std::copy(wt, wt + n, w);
    jet = trial;
    f = ft;
    if (moved <= kNoStep) {
      result.converged = true;
      break;
    }
  }
  std::copy(w, w + n, result.w);
  std::copy(jet.x, jet.x + 3, result.x);
  std::copy(jet.y, jet.y + 3, result.y);
  result.squaredDistance = PairSquaredDistance(jet, ad);
  for (int c = 0; c < layout.numConstraints() && !result.onBoundary; ++c) {
    result.onBoundary = layout.Slack(c, w) <= kActiveSlack;
  }
  if (result.converged) result.kkt = CheckPairKkt(layout, jet, w, ad, options.size);
  return result;
}

}  // namespace invmap::kernels
