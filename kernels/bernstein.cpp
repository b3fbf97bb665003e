#include "kernels/bernstein.h"

#include <algorithm>

#include "kernels/simplex_index.h"

namespace invmap::kernels {
namespace {

/// Line factor: the Bernstein triangle up to degree p by the de Casteljau
/// recurrence B^n_i = (1 - t) B^{n-1}_i + t B^{n-1}_{i-1}; the derivatives
/// come from the two lower degrees.
void EvaluateLineBasis(int degree, double t, JetOrder order, FactorBasis* out) {
  out->size = degree + 1;
  const double u = 1.0 - t;
  // Degrees p - 2, p - 1 and p of the triangle, each raised from the one
  // below (no copies: the arrays ping-pong).
  double buffer[2][kMaxDegree + 1];
  double lower2[kMaxDegree + 1], lower1[kMaxDegree + 1];
  auto raise = [u, t](const double* from, int n, double* to) {  // degree n - 1 -> n
    to[n] = t * from[n - 1];
    for (int i = n - 1; i > 0; --i) to[i] = u * from[i] + t * from[i - 1];
    to[0] = u * from[0];
  };
  buffer[0][0] = 1.0;
  const double* current = buffer[0];
  int n = 0;
  for (; n < degree - 2; ++n) {
    double* next = buffer[(n + 1) % 2];
    raise(current, n + 1, next);
    current = next;
  }
  // current is degree max(0, p - 2) here.
  if (degree >= 2) {
    for (int i = 0; i <= degree - 2; ++i) lower2[i] = current[i];
    raise(lower2, degree - 1, lower1);
    raise(lower1, degree, out->value);
  } else if (degree == 1) {
    lower1[0] = 1.0;
    raise(lower1, 1, out->value);
  } else {
    out->value[0] = 1.0;
  }
  if (order == JetOrder::Value) return;
  for (int i = 0; i <= degree; ++i) {
    const double left = i >= 1 ? lower1[i - 1] : 0.0;
    const double right = i < degree ? lower1[i] : 0.0;
    out->d1[i][0] = degree >= 1 ? degree * (left - right) : 0.0;
  }
  if (order != JetOrder::Second) return;
  for (int i = 0; i <= degree; ++i) {
    double d2 = 0.0;
    if (degree >= 2) {
      const double a = i >= 2 ? lower2[i - 2] : 0.0;
      const double b = i >= 1 && i - 1 <= degree - 2 ? lower2[i - 1] : 0.0;
      const double c = i <= degree - 2 ? lower2[i] : 0.0;
      d2 = degree * (degree - 1) * (a - 2.0 * b + c);
    }
    out->d2[i][0][0] = d2;
  }
}

}  // namespace

void EvaluateFactorBasis(int dim, int degree, const double* s, JetOrder order, FactorBasis* out) {
  if (dim == 1) {
    EvaluateLineBasis(degree, s[0], order, out);
    return;
  }
  const SimplexIndex& index = SimplexIndex::Get(dim, degree);
  out->size = index.size();

  // Barycentric coordinates and their powers lambda_k^e for e = 0..degree.
  double lambda[4];
  lambda[0] = 1.0;
  for (int i = 0; i < dim; ++i) {
    lambda[i + 1] = s[i];
    lambda[0] -= s[i];
  }
  double power[4][kMaxDegree + 1];
  for (int k = 0; k <= dim; ++k) {
    power[k][0] = 1.0;
    for (int e = 1; e <= degree; ++e) power[k][e] = power[k][e - 1] * lambda[k];
  }

  for (int b = 0; b < index.size(); ++b) {
    const std::array<int, 4>& a = index.multi(b);
    const double c = index.multinomial(b);
    // Factors of the monomial and of its first and second derivatives along
    // each barycentric coordinate: written as a_k * lambda^(a_k - 1) so that a
    // zero exponent gives a zero derivative even where lambda_k = 0.
    double v[4], dv[4], ddv[4];
    for (int k = 0; k <= dim; ++k) {
      const int e = a[k];
      v[k] = power[k][e];
      dv[k] = e >= 1 ? e * power[k][e - 1] : 0.0;
      ddv[k] = e >= 2 ? e * (e - 1) * power[k][e - 2] : 0.0;
    }
    double value = c;
    for (int k = 0; k <= dim; ++k) value *= v[k];
    out->value[b] = value;
    if (order == JetOrder::Value) continue;

    // Derivatives with respect to the barycentric coordinates.
    double dLambda[4];
    double ddLambda[4][4];
    for (int k = 0; k <= dim; ++k) {
      double prod = c * dv[k];
      for (int l = 0; l <= dim; ++l) {
        if (l != k) prod *= v[l];
      }
      dLambda[k] = prod;
    }
    if (order == JetOrder::Second) {
      for (int k = 0; k <= dim; ++k) {
        for (int l = k; l <= dim; ++l) {
          double prod = c;
          if (k == l) {
            prod *= ddv[k];
          } else {
            prod *= dv[k] * dv[l];
          }
          for (int m = 0; m <= dim; ++m) {
            if (m != k && m != l) prod *= v[m];
          }
          ddLambda[k][l] = ddLambda[l][k] = prod;
        }
      }
    }
    // Chain rule: d/ds_i = d/dlambda_i - d/dlambda_0.
    for (int i = 0; i < dim; ++i) {
      out->d1[b][i] = dLambda[i + 1] - dLambda[0];
      if (order != JetOrder::Second) continue;
      for (int j = 0; j <= i; ++j) {
        const double d2 = ddLambda[i + 1][j + 1] - ddLambda[i + 1][0] - ddLambda[0][j + 1] + ddLambda[0][0];
        out->d2[b][i][j] = out->d2[b][j][i] = d2;
      }
    }
  }
}

}  // namespace invmap::kernels
