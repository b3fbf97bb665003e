#include "kernels/pair_problem.h"

#include <algorithm>

namespace invmap::kernels {

void RigidMotion::Apply(const double* x, double* out) const {
  const double in[3] = {x[0], x[1], x[2]};
  for (int k = 0; k < 3; ++k) {
    out[k] = rotation[k][0] * in[0] + rotation[k][1] * in[1] + rotation[k][2] * in[2] + translation[k];
  }
}

void RigidMotion::Rotate(const double* v, double* out) const {
  const double in[3] = {v[0], v[1], v[2]};
  for (int k = 0; k < 3; ++k) out[k] = rotation[k][0] * in[0] + rotation[k][1] * in[1] + rotation[k][2] * in[2];
}

bool RigidMotion::IsIdentity() const {
  for (int k = 0; k < 3; ++k) {
    if (translation[k] != 0.0) return false;
    for (int j = 0; j < 3; ++j) {
      if (rotation[k][j] != (k == j ? 1.0 : 0.0)) return false;
    }
  }
  return true;
}

PairLayout::PairLayout(const CellShape& a, const CellShape& b) {
  shape_[0] = a;
  shape_[1] = b;
  paramDim_[0] = a.paramDim();
  paramDim_[1] = b.paramDim();
  n_ = paramDim_[0] + paramDim_[1];
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = shape_[side];
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& factor = shape.factor(f);
      const int first = offset(side) + factor.offset;
      for (int i = 0; i < factor.dim; ++i) constraints_[numConstraints_++] = Constraint{first + i, 1, false};
      constraints_[numConstraints_++] = Constraint{first, factor.dim, true};
    }
  }
}

double PairLayout::Slack(int c, const double* w) const {
  const Constraint& k = constraints_[c];
  if (!k.sum) return w[k.first];
  double s = 1.0;
  for (int i = 0; i < k.count; ++i) s -= w[k.first + i];
  return s;
}

void PairLayout::Normal(int c, double* normal) const {
  std::fill(normal, normal + n_, 0.0);
  const Constraint& k = constraints_[c];
  if (!k.sum) {
    normal[k.first] = 1.0;
    return;
  }
  for (int i = 0; i < k.count; ++i) normal[k.first + i] = -1.0;
}

void PairLayout::Project(double* w) const {
  for (int c = 0; c < numConstraints_; ++c) {
    const Constraint& k = constraints_[c];
    if (!k.sum) {
      w[k.first] = std::max(w[k.first], 0.0);
      continue;
    }
    // The sum constraint comes after its factor's coordinates were clamped.
    double sum = 0.0;
    for (int i = 0; i < k.count; ++i) sum += w[k.first + i];
    if (sum > 1.0) {
      for (int i = 0; i < k.count; ++i) w[k.first + i] /= sum;
    }
  }
}

void PairLayout::Center(double* w) const {
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = shape_[side];
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& factor = shape.factor(f);
      for (int i = 0; i < factor.dim; ++i) w[offset(side) + factor.offset + i] = 1.0 / (factor.dim + 1);
    }
  }
}

void EvaluatePair(const PairSide& a, const PairSide& b, const PairLayout& layout, const double* w, JetOrder order,
                  PairJet* jet) {
  MapJet ja, jb;
  EvaluateMap(a.cell, w, order, &ja);
  EvaluateMap(b.cell, w + layout.offset(1), order, &jb);
  const int ad = a.cell.ambientDim;
  // Into the common frame: points moved, derivatives rotated.
  double pa[3] = {ja.x[0], ja.x[1], ad > 2 ? ja.x[2] : 0.0};
  double pb[3] = {jb.x[0], jb.x[1], ad > 2 ? jb.x[2] : 0.0};
  a.motion.Apply(pa, jet->x);
  b.motion.Apply(pb, jet->y);
  for (int k = 0; k < 3; ++k) jet->z[k] = jet->x[k] - jet->y[k];
  if (order == JetOrder::Value) return;
  const int n = layout.n();
  for (int side = 0; side < 2; ++side) {
    const MapJet& j = side == 0 ? ja : jb;
    const RigidMotion& motion = side == 0 ? a.motion : b.motion;
    const double sign = side == 0 ? 1.0 : -1.0;
    const int pd = layout.paramDim(side), off = layout.offset(side);
    for (int i = 0; i < pd; ++i) {
      double column[3] = {j.d1[0][i], j.d1[1][i], ad > 2 ? j.d1[2][i] : 0.0};
      motion.Rotate(column, column);
      for (int k = 0; k < 3; ++k) jet->d1[k][off + i] = sign * column[k];
    }
    if (order != JetOrder::Second) continue;
    for (int i = 0; i < pd; ++i) {
      for (int l = 0; l <= i; ++l) {
        double column[3] = {j.d2[0][i][l], j.d2[1][i][l], ad > 2 ? j.d2[2][i][l] : 0.0};
        motion.Rotate(column, column);
        for (int k = 0; k < 3; ++k) jet->d2[k][off + i][off + l] = jet->d2[k][off + l][off + i] = sign * column[k];
      }
    }
  }
  if (order == JetOrder::Second) {
    // x and y do not mix: the blocks between the sides are zero.
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < layout.paramDim(0); ++i) {
        for (int l = layout.offset(1); l < n; ++l) jet->d2[k][i][l] = jet->d2[k][l][i] = 0.0;
      }
    }
  }
}

double PairSquaredDistance(const PairJet& jet, int ambientDim) {
  double f = 0.0;
  for (int k = 0; k < ambientDim; ++k) f += jet.z[k] * jet.z[k];
  return f;
}

double CellWeightAt(const CellView& cell, const double* ref) {
  if (!cell.weights) return 1.0;
  const CellShape& shape = cell.shape;
  // The tensor product of the factors' Bernstein values, first factor fastest.
  double values[kMaxFactors][SimplexBasisSize(3, kMaxDegree)];
  int sizes[kMaxFactors] = {1, 1, 1};
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    const double* s = ref + factor.offset;
    if (factor.dim == 1) {
      FactorBasis<1> basis;
      EvaluateFactorBasis<1>(factor.degree, s, JetOrder::Value, &basis);
      std::copy(basis.value, basis.value + basis.size, values[f]);
      sizes[f] = basis.size;
    } else if (factor.dim == 2) {
      FactorBasis<2> basis;
      EvaluateFactorBasis<2>(factor.degree, s, JetOrder::Value, &basis);
      std::copy(basis.value, basis.value + basis.size, values[f]);
      sizes[f] = basis.size;
    } else {
      FactorBasis<3> basis;
      EvaluateFactorBasis<3>(factor.degree, s, JetOrder::Value, &basis);
      std::copy(basis.value, basis.value + basis.size, values[f]);
      sizes[f] = basis.size;
    }
  }
  double sum = 0.0;
  int c = 0;
  for (int k = 0; k < (shape.numFactors() > 2 ? sizes[2] : 1); ++k) {
    for (int j = 0; j < (shape.numFactors() > 1 ? sizes[1] : 1); ++j) {
      const double outer = (shape.numFactors() > 2 ? values[2][k] : 1.0) * (shape.numFactors() > 1 ? values[1][j] : 1.0);
      for (int i = 0; i < sizes[0]; ++i) sum += cell.weights[c++] * values[0][i] * outer;
    }
  }
  return sum;
}

}  // namespace invmap::kernels
