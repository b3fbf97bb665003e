#include "kernels/step_selection.h"

namespace invmap::kernels {

bool NewtonStepOf(const double h[3][3], int m, const double* g, double* x) {
  // LDL^T: l[i][j] (j < i) below the diagonal, d[i] on it.
  double l[3][3] = {}, d[3];
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < i; ++j) {
      double v = h[i][j];
      for (int k = 0; k < j; ++k) v -= l[i][k] * d[k] * l[j][k];
      l[i][j] = v / d[j];
    }
    double v = h[i][i];
    for (int k = 0; k < i; ++k) v -= l[i][k] * d[k] * l[i][k];
    if (!(v > 0.0)) return false;
    d[i] = v;
  }
  double y[3];
  for (int i = 0; i < m; ++i) {
    y[i] = -g[i];
    for (int k = 0; k < i; ++k) y[i] -= l[i][k] * y[k];
  }
  double slope = 0.0;
  for (int i = m - 1; i >= 0; --i) {
    x[i] = y[i] / d[i];
    for (int k = i + 1; k < m; ++k) x[i] -= l[k][i] * x[k];
    slope += x[i] * g[i];
  }
  for (int i = m; i < 3; ++i) x[i] = 0.0;
  return std::isfinite(slope) && slope < 0.0;
}

}  // namespace invmap::kernels
