#include "fields/cell_basis.h"

#include "kernels/bernstein.h"

namespace invmap::fields {
namespace {

/// Bernstein values of one simplex factor of dimension Dim at its free coordinates.
template <int Dim>
int FactorValues(int degree, const double* s, double* out) {
  kernels::FactorBasis<Dim> basis;
  kernels::EvaluateFactorBasis<Dim>(degree, s, kernels::JetOrder::Value, &basis);
  for (int k = 0; k < basis.size; ++k) out[k] = basis.value[k];
  return basis.size;
}

int FactorValues(int dim, int degree, const double* s, double* out) {
  // Degree 1 (every factor of a linear cell) is the barycentric coordinates
  // (1 - s1 - .. - sd, s1, .., sd) in net order; no basis tables needed.
  if (degree == 1) {
    out[0] = 1.0;
    for (int i = 0; i < dim; ++i) {
      out[0] -= s[i];
      out[i + 1] = s[i];
    }
    return dim + 1;
  }
  switch (dim) {
    case 1:
      return FactorValues<1>(degree, s, out);
    case 2:
      return FactorValues<2>(degree, s, out);
    default:
      return FactorValues<3>(degree, s, out);
  }
}

}  // namespace

int EvaluateCellBasis(const kernels::CellShape& shape, const double* params, const double* weights, double* out) {
  double factor[kernels::SimplexBasisSize(3, kernels::kMaxDegree)];
  out[0] = 1.0;
  int size = 1;
  // Earlier factors vary fastest: value (i, j) goes to j * size + i. Going
  // down from the last j keeps out[0 .. size) until j = 0 reads it last.
  for (int f = 0; f < shape.numFactors(); ++f) {
    const kernels::SimplexFactor& simplex = shape.factor(f);
    const int n = FactorValues(simplex.dim, simplex.degree, params + simplex.offset, factor);
    for (int j = n - 1; j >= 0; --j) {
      for (int i = size - 1; i >= 0; --i) out[j * size + i] = out[i] * factor[j];
    }
    size *= n;
  }
  if (weights == nullptr) return size;
  double sum = 0.0;
  for (int k = 0; k < size; ++k) sum += (out[k] *= weights[k]);
  for (int k = 0; k < size; ++k) out[k] /= sum;
  return size;
}

}  // namespace invmap::fields
