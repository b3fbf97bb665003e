// Majorants: upper bounds of the norms of a map's derivatives of orders 0 to
// 3 over a region (the k-th derivative as a k-linear map, with Euclidean
// norms on both sides), and the rules that carry them through sums,
// products and compositions: Leibniz's and Faa di Bruno's formulas with
// every term replaced by the product of its factors' norms. They hold at
// every point of the region, whatever its shape.
#pragma once

namespace invmap::pou {

struct Majorant {
  double d[4] = {0, 0, 0, 0};
};

inline Majorant operator+(const Majorant& a, const Majorant& b) {
  return {{a.d[0] + b.d[0], a.d[1] + b.d[1], a.d[2] + b.d[2], a.d[3] + b.d[3]}};
}

/// A product of two maps (scalar times scalar or vector, or a bilinear
/// product of norm at most 1).
inline Majorant Product(const Majorant& a, const Majorant& b) {
  return {{a.d[0] * b.d[0], a.d[1] * b.d[0] + a.d[0] * b.d[1],
           a.d[2] * b.d[0] + 2.0 * a.d[1] * b.d[1] + a.d[0] * b.d[2],
           a.d[3] * b.d[0] + 3.0 * a.d[2] * b.d[1] + 3.0 * a.d[1] * b.d[2] + a.d[0] * b.d[3]}};
}

/// f o g, from the bounds of f's derivatives over (a set holding) g's values
/// and g's majorant; f's bound of order 0 is the result's.
inline Majorant Compose(const Majorant& f, const Majorant& g) {
  const double g1 = g.d[1], g2 = g.d[2], g3 = g.d[3];
  return {{f.d[0], f.d[1] * g1, f.d[2] * g1 * g1 + f.d[1] * g2,
           f.d[3] * g1 * g1 * g1 + 3.0 * f.d[2] * g1 * g2 + f.d[1] * g3}};
}

}  // namespace invmap::pou
