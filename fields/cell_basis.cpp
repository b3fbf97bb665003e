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

void EvaluateCellBasis(const kernels::CellShape& shape, const double* params, const double* weights,
                       std::vector<double>* out) {
  out->assign(1, 1.0);
  double factor[kernels::SimplexBasisSize(3, kernels::kMaxDegree)];
  std::vector<double> product;
  // Earlier factors vary fastest in the control net.
  for (int f = 0; f < shape.numFactors(); ++f) {
    const kernels::SimplexFactor& simplex = shape.factor(f);
    const int n = FactorValues(simplex.dim, simplex.degree, params + simplex.offset, factor);
    product.resize(out->size() * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      for (std::size_t i = 0; i < out->size(); ++i) product[j * out->size() + i] = (*out)[i] * factor[j];
    }
    out->swap(product);
  }
  if (weights == nullptr) return;
  double sum = 0.0;
  for (std::size_t k = 0; k < out->size(); ++k) sum += ((*out)[k] *= weights[k]);
  for (double& value : *out) value /= sum;
}

}  // namespace invmap::fields
