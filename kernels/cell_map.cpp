#include "kernels/cell_map.h"

#include <cstddef>

namespace invmap::kernels {
namespace {

/// Value and derivatives of the homogeneous sums (w x_k for k < ambientDim,
/// then w) with respect to the parameters contracted so far.
struct HomogeneousJet {
  double value[4];
  double d1[4][3];
  double d2[4][3][3];
};

void ClearJet(int components, int paramDim, JetOrder order, HomogeneousJet* jet) {
  for (int k = 0; k < components; ++k) {
    jet->value[k] = 0.0;
    if (order == JetOrder::Value) continue;
    for (int i = 0; i < paramDim; ++i) {
      jet->d1[k][i] = 0.0;
      if (order == JetOrder::Second) {
        for (int j = 0; j < paramDim; ++j) jet->d2[k][i][j] = 0.0;
      }
    }
  }
}

/// jet += basis function b of factor `fac` times `part`, where `part` is a
/// jet over the parameters before fac.offset (the factors contracted before).
void AccumulateFactor(int components, const SimplexFactor& fac, const FactorBasis& basis, int b,
                      const HomogeneousJet& part, JetOrder order, HomogeneousJet* jet) {
  const int before = fac.offset;
  const double v = basis.value[b];
  for (int k = 0; k < components; ++k) {
    const double pv = part.value[k];
    jet->value[k] += pv * v;
    if (order == JetOrder::Value) continue;
    for (int i = 0; i < before; ++i) jet->d1[k][i] += part.d1[k][i] * v;
    for (int i = 0; i < fac.dim; ++i) jet->d1[k][before + i] += pv * basis.d1[b][i];
    if (order != JetOrder::Second) continue;
    for (int i = 0; i < before; ++i) {
      for (int j = 0; j <= i; ++j) jet->d2[k][i][j] += part.d2[k][i][j] * v;
      for (int j = 0; j < fac.dim; ++j) jet->d2[k][before + j][i] += part.d1[k][i] * basis.d1[b][j];
    }
    for (int i = 0; i < fac.dim; ++i) {
      for (int j = 0; j <= i; ++j) jet->d2[k][before + i][before + j] += pv * basis.d2[b][i][j];
    }
  }
}

/// General path: contract the tensor net one factor at a time, first factor
/// first (it is the fastest index): jets[o] holds the partial sum for outer index o.
void EvaluateTensorSimplices(const CellView& cell, const FactorBasis* basis, JetOrder order, HomogeneousJet* out) {
  const CellShape& shape = cell.shape;
  const int nf = shape.numFactors();
  const int pd = shape.paramDim();
  const int ad = cell.ambientDim;
  const bool rational = cell.weights != nullptr;
  const int components = ad + (rational ? 1 : 0);
  constexpr int kMaxOuter = (kMaxDegree + 1) * (kMaxDegree + 1);
  HomogeneousJet jets[kMaxOuter];
  HomogeneousJet unit;
  unit.value[0] = 1.0;  // the empty product, for the first factor
  int outer = shape.numControlPoints() / basis[0].size;
  {
    const int n0 = basis[0].size;
    const SimplexFactor& fac = shape.factor(0);
    for (int o = 0; o < outer; ++o) {
      HomogeneousJet& jet = jets[o];
      ClearJet(components, pd, order, &jet);
      for (int b = 0; b < n0; ++b) {
        const int c = o * n0 + b;
        const double w = rational ? cell.weights[c] : 1.0;
        const double* p = cell.points + static_cast<size_t>(c) * ad;
        for (int k = 0; k < components; ++k) unit.value[k] = k < ad ? w * p[k] : w;
        AccumulateFactor(components, fac, basis[0], b, unit, order, &jet);
      }
    }
  }
  for (int f = 1; f < nf; ++f) {
    const int nb = basis[f].size;
    const int next = outer / nb;
    for (int o = 0; o < next; ++o) {
      HomogeneousJet jet;
      ClearJet(components, pd, order, &jet);
      for (int b = 0; b < nb; ++b) AccumulateFactor(components, shape.factor(f), basis[f], b, jets[o * nb + b], order, &jet);
      jets[o] = jet;
    }
    outer = next;
  }
  *out = jets[0];
}

/// Fast path for tensor products of lines (line, quad, hex cells: every
/// B-spline cell): contract one direction at a time with plain loops. Slot
/// layout of a partial jet: value, then first derivatives, then the second
/// derivatives (i, j) with j <= i, each `components` wide.
void EvaluateTensorLines(const CellView& cell, const FactorBasis* basis, JetOrder order, HomogeneousJet* out) {
  const CellShape& shape = cell.shape;
  const int nf = shape.numFactors();
  const int ad = cell.ambientDim;
  const bool rational = cell.weights != nullptr;
  const int comps = ad + (rational ? 1 : 0);
  const int n0 = basis[0].size;
  const int outer0 = shape.numControlPoints() / n0;
  // After contracting direction 0: per outer index, value and (when asked)
  // d/du0 and d2/du0^2.
  constexpr int kMaxOuter = (kMaxDegree + 1) * (kMaxDegree + 1);
  double r0[kMaxOuter][3][4];
  const int slots0 = order == JetOrder::Value ? 1 : (order == JetOrder::First ? 2 : 3);
  for (int o = 0; o < outer0; ++o) {
    double (*acc)[4] = r0[o];
    for (int s = 0; s < slots0; ++s) {
      for (int k = 0; k < comps; ++k) acc[s][k] = 0.0;
    }
    for (int b = 0; b < n0; ++b) {
      const int c = o * n0 + b;
      const double w = rational ? cell.weights[c] : 1.0;
      const double* p = cell.points + static_cast<size_t>(c) * ad;
      double h[4];
      for (int k = 0; k < ad; ++k) h[k] = w * p[k];
      h[ad] = w;
      const double bv[3] = {basis[0].value[b], slots0 > 1 ? basis[0].d1[b][0] : 0.0, slots0 > 2 ? basis[0].d2[b][0][0] : 0.0};
      for (int s = 0; s < slots0; ++s) {
        for (int k = 0; k < comps; ++k) acc[s][k] += bv[s] * h[k];
      }
    }
  }
  if (nf == 1) {
    for (int k = 0; k < comps; ++k) {
      out->value[k] = r0[0][0][k];
      if (slots0 > 1) out->d1[k][0] = r0[0][1][k];
      if (slots0 > 2) out->d2[k][0][0] = r0[0][2][k];
    }
    return;
  }
  // Contract direction 1: slots (v, d0, d1, d00, d10, d11).
  const int n1 = basis[1].size;
  const int outer1 = outer0 / n1;
  double r1[kMaxDegree + 1][6][4];
  const bool first = order != JetOrder::Value, second = order == JetOrder::Second;
  for (int o = 0; o < outer1; ++o) {
    double (*acc)[4] = r1[o];
    for (int s = 0; s < 6; ++s) {
      for (int k = 0; k < comps; ++k) acc[s][k] = 0.0;
    }
    for (int b = 0; b < n1; ++b) {
      const double (*q)[4] = r0[o * n1 + b];
      const double bv = basis[1].value[b];
      for (int k = 0; k < comps; ++k) {
        acc[0][k] += bv * q[0][k];
        if (!first) continue;
        const double bd = basis[1].d1[b][0];
        acc[1][k] += bv * q[1][k];
        acc[2][k] += bd * q[0][k];
        if (!second) continue;
        acc[3][k] += bv * q[2][k];
        acc[4][k] += bd * q[1][k];
        acc[5][k] += basis[1].d2[b][0][0] * q[0][k];
      }
    }
  }
  if (nf == 2) {
    for (int k = 0; k < comps; ++k) {
      out->value[k] = r1[0][0][k];
      out->d1[k][0] = r1[0][1][k];
      out->d1[k][1] = r1[0][2][k];
      out->d2[k][0][0] = r1[0][3][k];
      out->d2[k][1][0] = r1[0][4][k];
      out->d2[k][1][1] = r1[0][5][k];
    }
    return;
  }
  // Contract direction 2 (hex).
  const int n2 = basis[2].size;
  for (int k = 0; k < comps; ++k) {
    double acc[10] = {};
    for (int b = 0; b < n2; ++b) {
      const double (*q)[4] = r1[b];
      const double bv = basis[2].value[b];
      acc[0] += bv * q[0][k];
      if (!first) continue;
      const double bd = basis[2].d1[b][0];
      acc[1] += bv * q[1][k];
      acc[2] += bv * q[2][k];
      acc[3] += bd * q[0][k];
      if (!second) continue;
      acc[4] += bv * q[3][k];
      acc[5] += bv * q[4][k];
      acc[6] += bv * q[5][k];
      acc[7] += bd * q[1][k];
      acc[8] += bd * q[2][k];
      acc[9] += basis[2].d2[b][0][0] * q[0][k];
    }
    out->value[k] = acc[0];
    out->d1[k][0] = acc[1];
    out->d1[k][1] = acc[2];
    out->d1[k][2] = acc[3];
    out->d2[k][0][0] = acc[4];
    out->d2[k][1][0] = acc[5];
    out->d2[k][1][1] = acc[6];
    out->d2[k][2][0] = acc[7];
    out->d2[k][2][1] = acc[8];
    out->d2[k][2][2] = acc[9];
  }
}

}  // namespace

void EvaluateMap(const CellView& cell, const double* ref, JetOrder order, MapJet* out) {
  const CellShape& shape = cell.shape;
  const int nf = shape.numFactors();
  const int pd = shape.paramDim();
  const int ad = cell.ambientDim;
  const bool rational = cell.weights != nullptr;

  FactorBasis basis[kMaxFactors];
  for (int f = 0; f < nf; ++f) {
    const SimplexFactor& fac = shape.factor(f);
    EvaluateFactorBasis(fac.dim, fac.degree, ref + fac.offset, order, &basis[f]);
  }

  bool allLines = true;
  for (int f = 0; f < nf; ++f) allLines = allLines && shape.factor(f).dim == 1;
  HomogeneousJet h{};
  if (allLines) {
    EvaluateTensorLines(cell, basis, order, &h);
  } else {
    EvaluateTensorSimplices(cell, basis, order, &h);
  }

  // d2 was accumulated in the lower triangle; mirror it.
  if (!rational) {
    for (int k = 0; k < ad; ++k) {
      out->x[k] = h.value[k];
      if (order == JetOrder::Value) continue;
      for (int i = 0; i < pd; ++i) {
        out->d1[k][i] = h.d1[k][i];
        if (order != JetOrder::Second) continue;
        for (int j = 0; j <= i; ++j) out->d2[k][i][j] = out->d2[k][j][i] = h.d2[k][i][j];
      }
    }
    return;
  }
  // Quotient rule: x = N / W and its derivatives.
  const double invW = 1.0 / h.value[ad];
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
