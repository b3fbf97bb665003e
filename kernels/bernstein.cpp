#include "kernels/bernstein.h"

#include "kernels/simplex_index.h"

namespace invmap::kernels {

void EvaluateFactorBasis(int dim, int degree, const double* s, JetOrder order, FactorBasis* out) {
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
