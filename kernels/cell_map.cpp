#include "kernels/cell_map.h"

#include <cstddef>

namespace invmap::kernels {
namespace {

/// Homogeneous sums of one evaluation: the weighted numerator N (ambient
/// coordinates) and the denominator W, each with derivatives.
struct HomogeneousJet {
  double value[4] = {};  // N_0..N_{dim-1}, then W at index ambientDim.
  double d1[4][3] = {};
  double d2[4][3][3] = {};
};

/// Product of one basis function per factor: value, gradient and Hessian with
/// respect to the cell's parameters.
struct TensorBasis {
  double value;
  double d1[3];
  double d2[3][3];
};

void CombineFactors(const CellShape& shape, const FactorBasis* basis, const int* index, JetOrder order,
                    TensorBasis* out) {
  const int nf = shape.numFactors();
  out->value = 1.0;
  for (int f = 0; f < nf; ++f) out->value *= basis[f].value[index[f]];
  if (order == JetOrder::Value) return;

  // Derivative along a parameter of factor f: factor f contributes its
  // derivative, the others their values.
  for (int f = 0; f < nf; ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double others = 1.0;
    for (int g = 0; g < nf; ++g) {
      if (g != f) others *= basis[g].value[index[g]];
    }
    for (int i = 0; i < fac.dim; ++i) out->d1[fac.offset + i] = others * basis[f].d1[index[f]][i];
  }
  if (order != JetOrder::Second) return;

  for (int f = 0; f < nf; ++f) {
    const SimplexFactor& ff = shape.factor(f);
    for (int g = f; g < nf; ++g) {
      const SimplexFactor& fg = shape.factor(g);
      double others = 1.0;
      for (int h = 0; h < nf; ++h) {
        if (h != f && h != g) others *= basis[h].value[index[h]];
      }
      for (int i = 0; i < ff.dim; ++i) {
        for (int j = 0; j < fg.dim; ++j) {
          const double d2 = f == g ? basis[f].d2[index[f]][i][j]
                                   : basis[f].d1[index[f]][i] * basis[g].d1[index[g]][j];
          const int a = ff.offset + i, b = fg.offset + j;
          out->d2[a][b] = out->d2[b][a] = others * d2;
        }
      }
    }
  }
}

}  // namespace

void EvaluateMap(const CellView& cell, const double* ref, JetOrder order, MapJet* out) {
  const CellShape& shape = cell.shape;
  const int nf = shape.numFactors();
  const int pd = shape.paramDim();
  const int ad = cell.ambientDim;

  FactorBasis basis[kMaxFactors];
  for (int f = 0; f < nf; ++f) {
    const SimplexFactor& fac = shape.factor(f);
    EvaluateFactorBasis(fac.dim, fac.degree, ref + fac.offset, order, &basis[f]);
  }

  HomogeneousJet h;
  int index[kMaxFactors] = {0, 0, 0};
  const int n = shape.numControlPoints();
  for (int c = 0; c < n; ++c) {
    TensorBasis t;
    CombineFactors(shape, basis, index, order, &t);
    const double w = cell.weights ? cell.weights[c] : 1.0;
    const double* p = cell.points + static_cast<size_t>(c) * ad;
    // Homogeneous coordinates (w p, w); the last slot accumulates W.
    for (int k = 0; k <= ad; ++k) {
      const double coef = k < ad ? w * p[k] : w;
      h.value[k] += coef * t.value;
      if (order == JetOrder::Value) continue;
      for (int i = 0; i < pd; ++i) h.d1[k][i] += coef * t.d1[i];
      if (order != JetOrder::Second) continue;
      for (int i = 0; i < pd; ++i) {
        for (int j = 0; j <= i; ++j) h.d2[k][i][j] += coef * t.d2[i][j];
      }
    }
    // Advance the tensor index, first factor fastest.
    for (int f = 0; f < nf; ++f) {
      if (++index[f] < basis[f].size) break;
      index[f] = 0;
    }
  }

  // Quotient rule: x = N / W and its derivatives.
  const double W = h.value[ad];
  const double invW = 1.0 / W;
  for (int k = 0; k < ad; ++k) out->x[k] = h.value[k] * invW;
  if (order == JetOrder::Value) return;
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < pd; ++i) out->d1[k][i] = (h.d1[k][i] - out->x[k] * h.d1[ad][i]) * invW;
  }
  if (order != JetOrder::Second) return;
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < pd; ++i) {
      for (int j = 0; j <= i; ++j) {
        const double d2 = (h.d2[k][i][j] - h.d1[ad][i] * out->d1[k][j] - h.d1[ad][j] * out->d1[k][i] -
                           out->x[k] * h.d2[ad][i][j]) *
                          invW;
        out->d2[k][i][j] = out->d2[k][j][i] = d2;
      }
    }
  }
}

}  // namespace invmap::kernels
