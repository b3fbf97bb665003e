#include "kernels/layer_newton.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

// At most 3 x 3, never on the heap.
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;

constexpr int kMaxIterations = 50;
/// A log step changes a coordinate by at most this factor's logarithm per
/// iteration (e^2), so one step cannot leap out of the layer.
constexpr double kMaxLogStep = 2.0;

double SquaredDistance(const CellView& cell, const double* point, const double* ref, JetOrder order, MapJet* jet) {
  EvaluateMap(cell, ref, order, jet);
  double f = 0.0;
  for (int k = 0; k < cell.ambientDim; ++k) f += (jet->x[k] - point[k]) * (jet->x[k] - point[k]);
  return f;
}

/// True when `ref` lies in the reference domain (every simplex factor's
/// coordinates non-negative, summing to at most one).
bool InDomain(const CellShape& shape, const double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    double sum = 0.0;
    for (int i = factor.offset; i < factor.offset + factor.dim; ++i) {
      if (!(ref[i] >= 0.0)) return false;
      sum += ref[i];
    }
    if (!(sum <= 1.0)) return false;
  }
  return true;
}

}  // namespace

int LayerNewton(const CellView& cell, const double* point, double size, double* ref) {
  const int pd = cell.shape.paramDim();
  const int ad = cell.ambientDim;
  bool inLayer = false;
  for (int i = 0; i < pd; ++i) inLayer = inLayer || (ref[i] > 0.0 && ref[i] < kLayerCoordinate);
  if (!inLayer) return 0;

  int iteration = 0;
  MapJet jet, trial;
  for (; iteration < kMaxIterations; ++iteration) {
    const double f = SquaredDistance(cell, point, ref, JetOrder::Second, &jet);
    // Half the squared distance: gradient J^T r, Hessian J^T J + sum_k r_k d2x_k.
    double r[3] = {0, 0, 0};
    for (int k = 0; k < ad; ++k) r[k] = jet.x[k] - point[k];
    // The free coordinates (off their faces) and their scale: u_i for a
    // coordinate solved in log u_i (d/dv = u d/du), 1 otherwise.
    int free[3], m = 0;
    bool logarithmic[3];
    double scale[3];
    for (int i = 0; i < pd; ++i) {
      logarithmic[i] = ref[i] > 0.0 && ref[i] < kLayerCoordinate;
      scale[i] = logarithmic[i] ? ref[i] : 1.0;
      if (ref[i] > 0.0) free[m++] = i;
    }
    if (m == 0) break;
    Matrix hessian(m, m);
    Vector gradient(m);
    for (int a = 0; a < m; ++a) {
      const int i = free[a];
      double gi = 0.0;
      for (int k = 0; k < ad; ++k) gi += jet.d1[k][i] * r[k];
      gradient(a) = scale[i] * gi;
      for (int b = 0; b < m; ++b) {
        const int j = free[b];
        double hij = 0.0;
        for (int k = 0; k < ad; ++k) hij += jet.d1[k][i] * jet.d1[k][j] + r[k] * jet.d2[k][i][j];
        hessian(a, b) = scale[i] * scale[j] * hij;
      }
      // d2/dv2 of a log coordinate also picks up u_i * df/du_i.
      if (logarithmic[i]) hessian(a, a) += scale[i] * gi;
    }
    // Newton's step where the model is convex; Levenberg-Marquardt damping
    // (growing tenfold) until it is.
    const double trace = hessian.diagonal().cwiseAbs().sum() + size * size * 1e-300;
    Vector step;
    bool haveStep = false;
    for (double damping = 0.0; !haveStep && damping < 1e30 * trace; damping = damping == 0.0 ? kLayerFirstDamping * trace : 10.0 * damping) {
      Matrix damped = hessian;
      damped.diagonal().array() += damping;
      Eigen::LLT<Matrix> llt(damped);
      if (llt.info() != Eigen::Success) continue;
      step = llt.solve(-gradient);
      haveStep = step.allFinite() && step.dot(gradient) < 0.0;
    }
    if (!haveStep) break;
    const double slope = step.dot(gradient);
    double alpha = 1.0;
    for (int a = 0; a < m; ++a) {
      if (logarithmic[free[a]]) alpha = std::min(alpha, kMaxLogStep / std::abs(step(a)));
    }
    // Armijo backtracking on f, inside the domain.
    bool moved = false;
    double next[3] = {ref[0], ref[1], ref[2]};
    for (int halving = 0; halving < 60 && !moved; ++halving, alpha *= 0.5) {
      for (int a = 0; a < m; ++a) {
        const int i = free[a];
        next[i] = logarithmic[i] ? ref[i] * std::exp(alpha * step(a)) : ref[i] + alpha * step(a);
      }
      if (!InDomain(cell.shape, next)) continue;
      const double trialF = SquaredDistance(cell, point, next, JetOrder::Value, &trial);
      moved = trialF < f && trialF <= f + kSufficientDecrease * alpha * slope;
    }
    if (!moved) break;
    double change = 0.0;  // largest relative change of a coordinate
    for (int a = 0; a < m; ++a) {
      const int i = free[a];
      change = std::max(change, std::abs(next[i] - ref[i]) / std::max(ref[i], kLayerCoordinate));
    }
    std::copy(next, next + pd, ref);
    if (change < kLayerStepTolerance) break;
  }
  return iteration;
}

}  // namespace invmap::kernels
