#include "kernels/kkt_point.h"

#include <cmath>

#include "kernels/active_set.h"
#include "kernels/stationarity.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

/// True when a coordinate of `value` (<= 1e-12) along whose direction the
/// map moves `length` per unit lies on its face: the map there is within
/// 1e-12 of the cell's `size` of the face's. (A coordinate of 1e-13 next to
/// a weight of 1e12 is a point of its own, not rounding off the face.)
bool OnFace(double value, double length, double size) {
  return value <= kKktOnFace && value * length <= kKktOnFace * size;
}

/// IsKktPoint's test for a cell of line factors, whose parameters are its
/// factors' coordinates: the general test below with its face basis and
/// multipliers written out (the same arithmetic, so the same verdict).
/// Parameter i is held at 0 when it is on that face (OnFace; its
/// multiplier is grad_i), else at 1 when 1 - u_i is (multiplier -grad_i),
/// else free (its basis vector is -e_i / sqrt(2)).
bool IsKktOnUnitBox(const double* ref, const double* grad, const DirectionScale& scale, double size) {
  const double norm = 1.0 / std::sqrt(2.0);
  for (int i = 0; i < scale.paramDim; ++i) {
    const double length = scale.ColumnLength(i);
    if (OnFace(ref[i], length, size)) {
      if (grad[i] < -scale.Tolerance(length)) return false;
    } else if (OnFace(1.0 - ref[i], length, size)) {
      if (-grad[i] < -scale.Tolerance(length)) return false;
    } else if (std::abs(-norm * grad[i]) > scale.Tolerance(norm * length)) {
      return false;
    }
  }
  return true;
}

}  // namespace

bool IsKktPoint(const CellView& cell, const MapJet& jet, const double* point, const double* ref, double size) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  double grad[3] = {0, 0, 0}, r2 = 0.0;
  for (int k = 0; k < cell.ambientDim; ++k) {
    const double r = jet.x[k] - point[k];
    r2 += r * r;
    for (int i = 0; i < pd; ++i) grad[i] += jet.d1[k][i] * r;
  }
  // A converged solve leaves slopes r . J v near rounding; a point that is
  // not stationary along v has one of the order of |J v| |r|. (Square roots
  // apart: r2 times a squared length overflows long before either factor.
  // A tolerance that still overflows would accept any point: not KKT then.)
  const DirectionScale scale{jet, cell.ambientDim, pd, kKktSlope * std::sqrt(r2) + kKktSlopeFloor * size, kThinDirection * size};
  if (!std::isfinite(scale.perLength)) return false;
  if (shape.isBox()) return IsKktOnUnitBox(ref, grad, scale, size);
  ActiveSet active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    // lambda_k moves along parameter k - 1; lambda_0 along all of the
    // factor's (the largest of their lengths: the face is held less often).
    double lengths[4] = {0, 0, 0, 0};
    for (int i = 0; i < factor.dim; ++i) {
      double unit[3] = {0, 0, 0};
      unit[factor.offset + i] = 1.0;
      lengths[i + 1] = scale.MappedLength(unit);
      lengths[0] = std::max(lengths[0], lengths[i + 1]);
    }
    for (int k = 0; k <= factor.dim; ++k) {
      if (OnFace(lambda[k], lengths[k], size)) active.enforced[f] |= 1u << k;
    }
    if (active.enforced[f] == (1u << (factor.dim + 1)) - 1) active.enforced[f] &= ~1u;
  }
  FaceBasis face;
  BuildFaceBasis(shape, active, &face);
  if (!IsStationaryOnFace(face, grad, scale)) return false;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    for (int k = 0; k <= factor.dim; ++k) {
      if (!(active.enforced[f] & (1u << k))) continue;
      // Releasing lambda_k moves it up and a free lambda_j down. On the
      // face, where the point is stationary, every free j gives the same
      // derivative up to the tolerance: the one whose direction the map
      // stretches least judges it most finely (a free coordinate next to a
      // heavy weight would lend the test its scale).
      double slope = 0.0, tolerance = -1.0;
      for (int j = 0; j <= factor.dim; ++j) {
        if (active.enforced[f] & (1u << j)) continue;
        double release[3] = {0, 0, 0};
        if (k > 0) release[factor.offset + k - 1] += 1.0;
        if (j > 0) release[factor.offset + j - 1] -= 1.0;
        const double candidate = scale.Tolerance(scale.MappedLength(release));
        if (tolerance < 0.0 || candidate < tolerance) {
          tolerance = candidate;
          slope = 0.0;
          for (int i = 0; i < pd; ++i) slope += release[i] * grad[i];
        }
      }
      if (slope < -tolerance) return false;
    }
  }
  return true;
}

}  // namespace invmap::kernels
