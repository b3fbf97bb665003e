#include "kernels/active_set.h"

#include <algorithm>
#include <cmath>

#include "kernels/tolerances.h"

namespace invmap::kernels {

void ClampToDomain(const CellShape& shape, double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double* s = ref + fac.offset;
    double sum = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      s[i] = std::max(0.0, s[i]);
      sum += s[i];
    }
    // Outside the hypotenuse face: scale back onto it.
    if (sum > 1.0) {
      for (int i = 0; i < fac.dim; ++i) s[i] /= sum;
    }
  }
}

namespace {

/// True when x[0] + .. + x[n - 1] <= 1 in exact arithmetic: the expansion
/// of the sum minus 1 (Shewchuk's GROW-EXPANSION, exact two-sums; its
/// components grow in magnitude and do not overlap) has the sign of its
/// largest nonzero component.
bool SumAtMostOne(const double* x, int n) {
  double expansion[5] = {-1.0};
  int size = 1;
  for (int i = 0; i < n; ++i) {
    double carry = x[i];
    for (int j = 0; j < size; ++j) {
      const double sum = carry + expansion[j];
      const double bVirtual = sum - carry;
      const double aVirtual = sum - bVirtual;
      expansion[j] = (carry - aVirtual) + (expansion[j] - bVirtual);
      carry = sum;
    }
    expansion[size++] = carry;
  }
  for (int j = size - 1; j >= 0; --j) {
    if (expansion[j] != 0.0) return expansion[j] < 0.0;
  }
  return true;
}

}  // namespace

void SnapToDomain(CellType type, double* ref) {
  double* s = ref;
  for (int f = 0; f < CellShape::NumFactorsOf(type); ++f) {
    const int dim = CellShape::FactorDimOf(type, f);
    double sum = 0.0;
    for (int i = 0; i < dim; ++i) {
      s[i] = std::clamp(s[i], 0.0, 1.0);
      sum += s[i];
    }
    // Farther out than rounding: back onto the face first (as ClampToDomain).
    if (sum > 1.0 + kOutsideDomain) {
      for (int i = 0; i < dim; ++i) s[i] /= sum;
    }
    // Then over by a few ulps at most.
    while (!SumAtMostOne(s, dim)) {
      double* largest = std::max_element(s, s + dim);
      *largest = std::nextafter(*largest, 0.0);
    }
    s += dim;
  }
}

void BuildFaceBasis(const CellShape& shape, const ActiveSet& active, FaceBasis* basis) {
  basis->columns = 0;
  for (auto& row : basis->t) std::fill(row, row + 3, 0.0);
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    int freeIdx[4];
    int r = 0;
    for (int k = 0; k <= fac.dim; ++k) {
      if (!(active.enforced[f] & (1u << k))) freeIdx[r++] = k;
    }
    for (int t = 1; t < r; ++t) {
      const double norm = 1.0 / std::sqrt(static_cast<double>(t) * (t + 1));
      const int c = basis->columns++;
      // Barycentric component k maps to parameter offset + k - 1; component 0
      // is implicit (it is minus the sum of the others).
      for (int m = 0; m < t; ++m) {
        if (freeIdx[m] > 0) basis->t[fac.offset + freeIdx[m] - 1][c] = norm;
      }
      if (freeIdx[t] > 0) basis->t[fac.offset + freeIdx[t] - 1][c] = -t * norm;
    }
  }
}

void ReleaseDirection(const CellShape& shape, const ActiveSet& active, int f, int k, double* step) {
  const SimplexFactor& fac = shape.factor(f);
  int k0 = 0;
  while (active.enforced[f] & (1u << k0)) ++k0;
  step[0] = step[1] = step[2] = 0.0;
  if (k > 0) step[fac.offset + k - 1] += 1.0;
  if (k0 > 0) step[fac.offset + k0 - 1] -= 1.0;
}

double ReleaseDerivative(const CellShape& shape, const ActiveSet& active, int f, int k, const double* grad) {
  double step[3];
  ReleaseDirection(shape, active, f, k, step);
  return step[0] * grad[0] + step[1] * grad[1] + step[2] * grad[2];
}

void SnapToFace(const CellShape& shape, const ActiveSet& active, double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double* s = ref + fac.offset;
    for (int k = 1; k <= fac.dim; ++k) {
      if (active.enforced[f] & (1u << k)) s[k - 1] = 0.0;
    }
    if (active.enforced[f] & 1u) {
      // lambda_0 = 0: the free coordinates sum to one. Put the excess on the
      // largest free coordinate.
      double sum = 0.0;
      int largest = -1;
      for (int i = 0; i < fac.dim; ++i) {
        sum += s[i];
        if (!(active.enforced[f] & (1u << (i + 1))) && (largest < 0 || s[i] > s[largest])) largest = i;
      }
      if (largest >= 0) s[largest] += 1.0 - sum;
    }
    for (int i = 0; i < fac.dim; ++i) s[i] = std::clamp(s[i], 0.0, 1.0);
  }
}

}  // namespace invmap::kernels
