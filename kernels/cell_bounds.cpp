#include "kernels/cell_bounds.h"

#include <algorithm>
#include <cmath>

#include "kernels/simplex_index.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

void ComputeControlBox(const CellView& cell, double* lo, double* hi) {
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = 0.0;
  const int n = cell.shape.numControlPoints();
  for (int c = 0; c < n; ++c) {
    for (int k = 0; k < cell.ambientDim; ++k) {
      const double x = cell.points[static_cast<size_t>(c) * cell.ambientDim + k];
      lo[k] = c == 0 ? x : std::min(lo[k], x);
      hi[k] = c == 0 ? x : std::max(hi[k], x);
    }
  }
}

void ReferenceCenter(const CellShape& shape, double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) ref[fac.offset + i] = 1.0 / (fac.dim + 1);
  }
}

void ControlPointLocation(const CellShape& shape, int c, double* ref) {
  int rest = c;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    const SimplexIndex& index = SimplexIndex::Get(fac.dim, fac.degree);
    const std::array<int, 4>& a = index.multi(rest % index.size());
    rest /= index.size();
    for (int i = 0; i < fac.dim; ++i) ref[fac.offset + i] = fac.degree > 0 ? static_cast<double>(a[i + 1]) / fac.degree : 0.0;
  }
}

bool IsAffineCell(const CellView& cell, double size) {
  const int n = cell.shape.numControlPoints();
  const int pd = cell.shape.paramDim();
  const int ad = cell.ambientDim;
  if (cell.weights) {
    for (int c = 1; c < n; ++c) {
      if (std::abs(cell.weights[c] - cell.weights[0]) > kEqualWeights * cell.weights[0]) return false;
    }
  }
  // The candidate affine map x(u) = origin + A u, read off at the reference
  // vertices (the origin and each unit point).
  double origin[3], unit[3], a[3][3];
  double ref[3] = {0, 0, 0};
  MapJet jet;
  EvaluateMap(cell, ref, JetOrder::Value, &jet);
  std::copy(jet.x, jet.x + 3, origin);
  for (int i = 0; i < pd; ++i) {
    std::fill(unit, unit + 3, 0.0);
    unit[i] = 1.0;
    EvaluateMap(cell, unit, JetOrder::Value, &jet);
    for (int k = 0; k < ad; ++k) a[k][i] = jet.x[k] - origin[k];
  }
  const double tol = kAffineCellTolerance * size;
  for (int c = 0; c < n; ++c) {
    ControlPointLocation(cell.shape, c, ref);
    for (int k = 0; k < ad; ++k) {
      double x = origin[k];
      for (int i = 0; i < pd; ++i) x += a[k][i] * ref[i];
      if (std::abs(x - cell.points[static_cast<size_t>(c) * ad + k]) > tol) return false;
    }
  }
  return true;
}

}  // namespace invmap::kernels
