#include "kernels/affine_simplex.h"

#include <algorithm>
#include <cmath>

#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

double Dot(int n, const double* a, const double* b) {
  double s = 0.0;
  for (int k = 0; k < n; ++k) s += a[k] * b[k];
  return s;
}

/// out = u x v (3 coordinates; 2D vectors have a zero third one).
void Cross(const double* u, const double* v, double* out) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
}

/// Closest point on segment ab: returns t in [0, 1] (point a + t (b - a)).
double SegmentParameter(int n, const double* a, const double* b, const double* p) {
  double ab[3], ap[3];
  for (int k = 0; k < n; ++k) {
    ab[k] = b[k] - a[k];
    ap[k] = p[k] - a[k];
  }
  const double len2 = Dot(n, ab, ab);
  if (!(len2 > 0.0)) return 0.0;
  return std::clamp(Dot(n, ap, ab) / len2, 0.0, 1.0);
}

/// Squared distance from p to a + s (b - a) + t (c - a), writing the point.
double Evaluate(int n, const double* a, const double* b, const double* c, double s, double t, const double* p,
                double* closest) {
  double d2 = 0.0;
  for (int k = 0; k < n; ++k) {
    closest[k] = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
    d2 += (closest[k] - p[k]) * (closest[k] - p[k]);
  }
  return d2;
}

/// Closest point on triangle abc as (s, t). First the vertices' regions
/// (Ericson, Real-Time Collision Detection 5.1.5: a vertex is the answer when
/// the point lies in its normal cone, told by two dot products each); then
/// the projection onto the plane when it lies in the triangle, else the
/// nearest point of the edges whose side the projection lies beyond.
///
/// The projection comes from triple products with the normal n = ab x ac:
/// t = n . (ab x ap) / |n|^2, then s from t along ab. The Gram-matrix
/// formulas (Ericson's edge and face regions, the normal equations) lose
/// digits as 1 / sin^2 of the triangle's smallest angle: on a sliver of
/// height 1e-7 of its length they moved the closest point of a point lying
/// on it by 1e-4 of the length. These keep the point within a few roundings
/// of the triangle's size; the error left, from the direction of n, only
/// moves a point above the triangle along its plane, where the distance is
/// stationary. Where even that is too much (sin of the angle at a below
/// 1e-4) or n is lost to rounding (collinear vertices), all three edges are
/// measured as well and the nearest answer kept: every candidate is a point
/// of the triangle, and the edges alone are off by at most the sliver's
/// height.
void TriangleParameters(int n, const double* a, const double* b, const double* c, const double* p, double* s,
                        double* t) {
  double ab[3] = {0, 0, 0}, ac[3] = {0, 0, 0}, ap[3] = {0, 0, 0}, bp[3] = {0, 0, 0}, cp[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
    bp[k] = p[k] - b[k];
    cp[k] = p[k] - c[k];
  }
  const double d1 = Dot(3, ab, ap), d2 = Dot(3, ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *s = *t = 0.0;
    return;
  }
  const double d3 = Dot(3, ab, bp), d4 = Dot(3, ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *s = 1.0;
    *t = 0.0;
    return;
  }
  const double d5 = Dot(3, ab, cp), d6 = Dot(3, ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *s = 0.0;
    *t = 1.0;
    return;
  }
  double normal[3], abXap[3];
  Cross(ab, ac, normal);
  Cross(ab, ap, abXap);
  const double nn = Dot(3, normal, normal), g11 = Dot(3, ab, ab);
  const double tPlane = Dot(3, normal, abXap) / nn;
  const double sPlane = (d1 - tPlane * Dot(3, ab, ac)) / g11;
  const bool inside = sPlane >= 0.0 && tPlane >= 0.0 && sPlane + tPlane <= 1.0;
  *s = sPlane;
  *t = tPlane;
  const bool wellShaped = nn > kWellShapedSin2 * g11 * Dot(3, ac, ac);
  if (inside && wellShaped) return;
  double closest[3];
  double best = inside ? Evaluate(n, a, b, c, sPlane, tPlane, p, closest) : -1.0;
  // The edges as (s, t) = origin + u (direction) over u in [0, 1]; on a
  // well-shaped triangle only those the projection lies beyond.
  const bool beyond[3] = {!wellShaped || tPlane < 0.0, !wellShaped || sPlane < 0.0,
                          !wellShaped || sPlane + tPlane > 1.0};
  const double* const from[3] = {a, a, b};
  const double* const to[3] = {b, c, c};
  for (int e = 0; e < 3; ++e) {
    if (!beyond[e]) continue;
    const double u = SegmentParameter(n, from[e], to[e], p);
    const double st[3][2] = {{u, 0.0}, {0.0, u}, {1.0 - u, u}};
    const double d = Evaluate(n, a, b, c, st[e][0], st[e][1], p, closest);
    if (best < 0.0 || d < best) {
      best = d;
      *s = st[e][0];
      *t = st[e][1];
    }
  }
}

/// ClosestPointOnSimplex on a simplex whose extent is within [2^-100, 2^100].
double ClosestPointOnUnitSimplex(int dim, int ambientDim, const double* const* v, const double* p, double* ref,
                                 double* closest, bool* onBoundary) {
  const int n = ambientDim;
  if (dim == 1) {
    const double t = SegmentParameter(n, v[0], v[1], p);
    ref[0] = t;
    *onBoundary = t <= 0.0 || t >= 1.0;
    return Evaluate(n, v[0], v[1], v[1], t, 0.0, p, closest);
  }
  if (dim == 2) {
    double s, t;
    TriangleParameters(n, v[0], v[1], v[2], p, &s, &t);
    ref[0] = s;
    ref[1] = t;
    *onBoundary = s <= 0.0 || t <= 0.0 || s + t >= 1.0;
    return Evaluate(n, v[0], v[1], v[2], s, t, p, closest);
  }
  // Tetrahedron: inside by its barycentric coordinates, else the best face.
  double e[3][3], r[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) e[k][i] = v[i + 1][k] - v[0][k];
    r[k] = p[k] - v[0][k];
  }
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  double scale = 1.0;
  for (int i = 0; i < 3; ++i) scale *= std::sqrt(e[0][i] * e[0][i] + e[1][i] * e[1][i] + e[2][i] * e[2][i]);
  if (std::abs(det) > kFlatTetrahedron * scale) {
    // Cramer's rule for the reference coordinates of p.
    double lambda[3];
    for (int i = 0; i < 3; ++i) {
      double m[3][3];
      for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j) m[k][j] = j == i ? r[k] : e[k][j];
      }
      lambda[i] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) /
                  det;
    }
    if (lambda[0] >= 0.0 && lambda[1] >= 0.0 && lambda[2] >= 0.0 && lambda[0] + lambda[1] + lambda[2] <= 1.0) {
      std::copy(lambda, lambda + 3, ref);
      std::copy(p, p + 3, closest);
      *onBoundary = false;
      return 0.0;
    }
  }
  static const int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  double best = -1.0;
  for (const auto& face : kFaces) {
    double s, t, point[3];
    TriangleParameters(3, v[face[0]], v[face[1]], v[face[2]], p, &s, &t);
    const double d = Evaluate(3, v[face[0]], v[face[1]], v[face[2]], s, t, p, point);
    if (best >= 0.0 && d >= best) continue;
    best = d;
    // Barycentric weights of the face's vertices back to the tet's.
    double weight[4] = {0, 0, 0, 0};
    weight[face[0]] = 1.0 - s - t;
    weight[face[1]] = s;
    weight[face[2]] = t;
    std::copy(weight + 1, weight + 4, ref);
    std::copy(point, point + 3, closest);
  }
  *onBoundary = true;
  return best;
}

/// Bounds of the extents solved unscaled, and the farthest a scaled query
/// point is taken (in units of the scaled simplex, whose extent is about 1).
constexpr double kUnscaledLow = 0x1p-100, kUnscaledHigh = 0x1p100;
constexpr int kFarthestExponent = 400;

}  // namespace

double SimplexUnitScale(int dim, int ambientDim, const double* const* v) {
  double extent = 0.0;
  for (int i = 1; i <= dim; ++i) {
    for (int k = 0; k < ambientDim; ++k) extent = std::max(extent, std::abs(v[i][k] - v[0][k]));
  }
  // This runs for every triangle a search solves: compared, not frexp'd.
  if (extent == 0.0 || (extent >= kUnscaledLow && extent < kUnscaledHigh)) return 1.0;
  int exponent = 0;
  std::frexp(extent, &exponent);  // extent in [2^(exponent - 1), 2^exponent)
  return std::ldexp(1.0, -exponent);
}

double ClosestPointOnSimplex(int dim, int ambientDim, const double* const* v, const double* p, double* ref,
                             double* closest, bool* onBoundary) {
  const int n = ambientDim;
  const double scale = SimplexUnitScale(dim, n, v);
  if (scale == 1.0) return ClosestPointOnUnitSimplex(dim, n, v, p, ref, closest, onBoundary);
  // The simplex relative to v[0] and scaled by a power of two: the same
  // differences the closed forms take, exactly scaled. A query point more
  // than 2^400 extents away is taken nearer along its ray from v[0] (its
  // closest point then differs by a fraction 2^-400 of its distance; the
  // distance is measured from the point itself below).
  double scaled[4][3] = {}, q[3] = {0, 0, 0};
  double far = 0.0;
  for (int k = 0; k < n; ++k) {
    for (int i = 1; i <= dim; ++i) scaled[i][k] = (v[i][k] - v[0][k]) * scale;
    q[k] = p[k] - v[0][k];
    far = std::max(far, std::abs(q[k]));
  }
  int farExponent = 0;
  std::frexp(far * scale, &farExponent);
  const double pull = farExponent > kFarthestExponent ? std::ldexp(1.0, kFarthestExponent - farExponent) : 1.0;
  for (int k = 0; k < n; ++k) q[k] = q[k] * pull * scale;
  const double* corners[4] = {scaled[0], scaled[1], scaled[2], scaled[3]};
  double unused[3];
  if (ClosestPointOnUnitSimplex(dim, n, corners, q, ref, unused, onBoundary) == 0.0 && dim == n) {
    std::copy(p, p + n, closest);  // inside a volume: the point itself
    return 0.0;
  }
  // The closest point from its reference coordinates, in the given units.
  double d2 = 0.0;
  for (int k = 0; k < n; ++k) {
    closest[k] = v[0][k];
    for (int i = 1; i <= dim; ++i) closest[k] += ref[i - 1] * (v[i][k] - v[0][k]);
    d2 += (closest[k] - p[k]) * (closest[k] - p[k]);
  }
  return d2;
}

}  // namespace invmap::kernels
