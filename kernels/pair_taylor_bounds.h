// Bounds of the Hessian of the squared distance f = |x(s) - y(t)|^2 over a
// pair of subdomains, from first-order Taylor models of each side's map:
// the cheap curvature test of the pair certificate
// (kernels/pair_certificate.h).
//
// Each side's map over its subdomain is the rational net NW_k / WW of its
// factored nets (kernels/pair_nets.h). Every net (NW_k, WW and their first
// and second derivative nets along the subdomain's local coordinates) is
// written as an affine function of those coordinates plus a remainder: the
// least-squares plane through its control values, and the largest distance
// of a control value from that plane, which bounds the polynomial's
// distance from the plane (a net's coefficients minus a plane's are the
// net of their difference). The quotient rule and the products of
//   e^T H e' = 2 [ (J e) . (J e') + z . (D2 z)[e, e'] ],
//   J e = Jx eA - Jy eB,   z = x - y,   D2 z[e, e'] = D2x[eA, e'A] - D2y[eB, e'B],
// are then carried out in affine arithmetic over the joint coordinates:
// what both sides' first-order variations contribute is kept exactly, and
// only second-order terms (of the subdomains' size squared) go into the
// remainder, so the bounds shrink like the joint nets' bounds
// (PairNets::HessianRangesInBasis) while costing the two sides' net sizes
// instead of their product. Along a valley of equal distances, where the
// Hessian is exactly singular, they cannot close what the joint nets can.
#pragma once

#include "kernels/pair_nets.h"

namespace invmap::kernels {

/// The Taylor models of one pair of subdomains.
class PairTaylorBounds {
 public:
  /// From the factored nets of the two subdomains (PairNets' layout).
  /// valid() is false when some weight is not positive or a model is not finite.
  PairTaylorBounds(const PairNets& nets, const double* sideA, const double* sideB);

  bool valid() const { return valid_; }

  /// Bounds lo <= u_r^T H u_c <= hi (n x n, row-major, both triangles) of
  /// the Hessian H of f over the subdomains in their local coordinates, for
  /// the columns u of `basis` (n x n, column c at basis[c n]; null: the unit
  /// vectors). False when a bound is not finite.
  bool HessianBounds(const double* basis, double* lo, double* hi) const;

  /// Joint parameters (n).
  int size() const { return n_; }

  /// An affine function of the joint local coordinates w (offsets s from
  /// the subdomains' centroids) plus a remainder: c + g . s + [-r, r].
  struct Affine {
    double c = 0.0;
    double g[kMaxPairParams] = {};
    double r = 0.0;
  };

 private:
  struct Side {
    Affine x[3];         ///< The map.
    Affine d1[3][3];     ///< [k][p]: dx_k / dt_p.
    Affine d2[3][3][3];  ///< [k][p][q].
  };
  bool BuildSide(const PairNets& nets, int side, const double* values);
  /// Least and largest value of a's linear part over the subdomains.
  void LinearRange(const Affine& a, double* lo, double* hi) const;
  double LinearRadius(const Affine& a) const;
  Affine Multiply(const Affine& a, const Affine& b) const;
  void Range(const Affine& a, double* lo, double* hi) const;

  bool valid_ = false;
  int n_ = 0;
  int ambientDim_ = 3;
  int paramDim_[2] = {0, 0};
  /// Per joint coordinate: its factor's first coordinate and dimension
  /// (the linear parts range over each factor's simplex).
  int factorFirst_[kMaxPairParams] = {};
  int factorDim_[kMaxPairParams] = {};
  Side side_[2];
  Affine z_[3];  ///< x - y.
};

}  // namespace invmap::kernels
