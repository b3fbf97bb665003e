// Pieces of theta_v: a shape function composed with a chart map, and the
// blend of the contributions.
#pragma once

#include "pou/chart_maps.h"
#include "pou/jet.h"
#include "pou/jet_functions.h"

namespace invmap::pou {

/// A shape function's value, gradient and Hessian (per coordinate: xx, xy,
/// yy) at a point.
template <typename S>
struct ShapeDerivatives {
  S value[3];
  S grad[3][2];
  S hess[3][3];
};

/// psi(q(u, v)) as jets in (u, v), by the chain rule.
template <typename S>
void ComposeShape(const ShapeDerivatives<S>& psi, const JetPoint<S>& q, Jet<S> out[3]) {
  const Jet<S>& a = q.x;
  const Jet<S>& b = q.y;
  for (int c = 0; c < 3; ++c) {
    const S& gx = psi.grad[c][0];
    const S& gy = psi.grad[c][1];
    const S& hxx = psi.hess[c][0];
    const S& hxy = psi.hess[c][1];
    const S& hyy = psi.hess[c][2];
    Jet<S>& o = out[c];
    o.v = psi.value[c];
    o.du = gx * a.du + gy * b.du;
    o.dv = gx * a.dv + gy * b.dv;
    o.duu = hxx * (a.du * a.du) + S(2.0) * (hxy * (a.du * b.du)) + hyy * (b.du * b.du) + gx * a.duu + gy * b.duu;
    o.duv = hxx * (a.du * a.dv) + hxy * (a.du * b.dv + a.dv * b.du) + hyy * (b.du * b.dv) + gx * a.duv + gy * b.duv;
    o.dvv = hxx * (a.dv * a.dv) + S(2.0) * (hxy * (a.dv * b.dv)) + hyy * (b.dv * b.dv) + gx * a.dvv + gy * b.dvv;
  }
}

/// One neighbour's share of the blend: its bump and its shape function,
/// both as jets in the chart's coordinates.
template <typename S>
struct Contribution {
  Jet<S> weight;
  Jet<S> point[3];
};

/// psi_v + sum_z w_z (psi_z - psi_v) with w_z = gamma_z / (gamma_v + sum gamma):
/// the blend written around the chart's own shape function, so that the
/// weights' rounding multiplies the (small) differences of the shape
/// functions rather than the coordinates.
template <typename S>
void Blend(const Jet<S>& ownWeight, const Jet<S> own[3], const Contribution<S>* others, int count, Jet<S> out[3]) {
  for (int c = 0; c < 3; ++c) out[c] = own[c];
  if (count == 0) return;
  Jet<S> total = ownWeight;
  for (int i = 0; i < count; ++i) total = total + others[i].weight;
  const Jet<S> inverse = JetReciprocal(total);
  for (int i = 0; i < count; ++i) {
    const Contribution<S>& z = others[i];
    const Jet<S> w = z.weight * inverse;
    for (int c = 0; c < 3; ++c) out[c] = out[c] + w * (z.point[c] - own[c]);
  }
}

}  // namespace invmap::pou
