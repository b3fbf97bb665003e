// The p-domains and the transition maps between them (the gluing data).
//
// The p-domain of a vertex of valence n is the open disk of radius
// R = cos(pi / n) (the circle inscribed in the regular n-gon whose corners
// are the n-th roots of unity); neighbour i of the vertex sits at angle
// 2 pi i / n. Each chart is related to a "canonical" frame of an edge, in
// which the star is unfolded into equilateral triangles of side 1: a point
// at distance r and angle a from edge i's direction goes to distance
// r (sqrt(3)/2) / R and angle a n / 6 (the sector of each triangle, 2 pi / n
// wide, opens to 60 degrees and the disk to radius sqrt(3)/2). The edge from
// v to u has the frames v = (0, 0), u = (1, 0) and u = (0, 0), v = (1, 0);
// they are related by the half turn (x, y) -> (1 - x, -y). The transition map
// from v's p-domain to u's is: to v's frame of the edge, the half turn, back
// from u's frame of the edge. Its domain (the gluing domain) is the lens of
// points within sqrt(3)/2 of both v and u in the frame, those with
// |a| < 3 pi / n (then |a n / 6| < pi / 2, so the map is one to one there).
// The formula is used only up to FormulaAngle(n) from the edge: beyond a
// half turn of the unfolded angle it would wrap around the frame, and at
// valence 12 and more points a quarter turn from the edge would land back
// next to it.
// The half turn and the equal unfolding of every triangle make the maps
// consistent: going around a triangle's corners composes to the identity.
//
// This is the construction of Siqueira, Xu, Gallier, Nonato, Morera and
// Velho ("A new construction of smooth surfaces from triangle meshes using
// parametric pseudo-manifolds", Computers & Graphics 33, 2009).
//
// Every function is templated on the scalar of the jets.
#pragma once

#include <cmath>

#include "pou/jet.h"
#include "pou/jet_functions.h"

namespace invmap::pou {

constexpr double kPi = 3.141592653589793;
/// sqrt(3) / 2: the p-domain radius in the canonical frame.
constexpr double kFrameRadius = 0.8660254037844386;

/// Constants of the maps as scalars of type S.
inline double AngleCos(int k, int n, double) { return std::cos(2.0 * kPi * k / n); }
inline double AngleSin(int k, int n, double) { return std::sin(2.0 * kPi * k / n); }
/// The largest angle from an edge's direction (in a chart of valence n) at
/// which the transition map's formula is used: the unfolding multiplies
/// angles by n / 6, and this keeps the unfolded angle within a half turn
/// (min(pi, 6 pi / n)). It is at least 3 pi / n, the gluing domain's
/// reach; the edge's bump is zero beyond 2 pi / n (an unfolded 60 degrees,
/// where the disk of radius sqrt(3)/2 about the neighbour is seen from the
/// vertex).
inline double FormulaAngle(int n) { return n > 6 ? 6.0 * kPi / n : kPi; }
/// The angle from an edge's direction beyond which the edge's bump is zero.
inline double SupportAngle(int n) { return 2.0 * kPi / n; }
/// |(x, y)| for chart-sized values (no overflow to guard against, unlike
/// std::hypot, which is several times slower).
inline double Length(double x, double y) { return std::sqrt(x * x + y * y); }
/// The p-domain radius cos(pi / n).
inline double DomainRadius(int n) { return std::cos(kPi / n); }
inline double Constant(double x, double) { return x; }

/// p (in a chart of valence n) rotated so that edge `edge` points along +x.
template <typename S>
JetPoint<S> ToEdgeDirection(int n, int edge, const JetPoint<S>& p) {
  const S c = AngleCos(-edge, n, S()), s = AngleSin(-edge, n, S());
  return {c * p.x - s * p.y, s * p.x + c * p.y};
}

/// A point of the chart, already turned to its edge's direction (x > 0
/// side), in the edge's canonical frame. `angle` receives its angle from the
/// edge (before the unfolding), `distance` its canonical distance from the
/// chart's vertex. The point must not be the chart's centre.
template <typename S>
JetPoint<S> ToFrame(int n, const JetPoint<S>& turned, Jet<S>* angle, Jet<S>* distance) {
  const Jet<S> r = JetSqrt(turned.x * turned.x + turned.y * turned.y);
  *angle = JetAtan2(turned.y, turned.x);
  *distance = Constant(kFrameRadius / DomainRadius(n), S()) * r;
  const Jet<S> unfolded = Constant(n / 6.0, S()) * *angle;
  return {*distance * JetCos(unfolded), *distance * JetSin(unfolded)};
}

/// The inverse: a point of edge `edge`'s canonical frame (not its origin,
/// and within 90 degrees of the edge) in the chart of valence n.
template <typename S>
JetPoint<S> FromFrame(int n, int edge, const JetPoint<S>& c) {
  const Jet<S> rho = JetSqrt(c.x * c.x + c.y * c.y);
  const Jet<S> folded = Constant(6.0 / n, S()) * JetAtan2(c.y, c.x);
  const Jet<S> r = Constant(DomainRadius(n) / kFrameRadius, S()) * rho;
  const JetPoint<S> local{r * JetCos(folded), r * JetSin(folded)};
  const S cs = AngleCos(edge, n, S()), sn = AngleSin(edge, n, S());
  return {cs * local.x - sn * local.y, sn * local.x + cs * local.y};
}

/// The half turn from one end's frame of an edge to the other's.
template <typename S>
JetPoint<S> HalfTurn(const JetPoint<S>& c) {
  return {Jet<S>::Constant(S(1.0)) - c.x, -c.y};
}

}  // namespace invmap::pou
