#include "kernels/affine_simplex.h"

#include <algorithm>
#include <cmath>

namespace invmap::kernels {
namespace {

double Dot(int n, const double* a, const double* b) {
  double s = 0.0;
  for (int k = 0; k < n; ++k) s += a[k] * b[k];
  return s;
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

/// Closest point on triangle abc as (s, t): Ericson's region tests
/// (Real-Time Collision Detection, 5.1.5), then the edges when the triangle
/// is degenerate (no interior region to speak of).
void TriangleParameters(int n, const double* a, const double* b, const double* c, const double* p, double* s,
                        double* t) {
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  for (int k = 0; k < n; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
    bp[k] = p[k] - b[k];
    cp[k] = p[k] - c[k];
  }
  const double d1 = Dot(n, ab, ap), d2 = Dot(n, ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *s = *t = 0.0;
    return;
  }
  const double d3 = Dot(n, ab, bp), d4 = Dot(n, ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *s = 1.0;
    *t = 0.0;
    return;
  }
  const double d5 = Dot(n, ab, cp), d6 = Dot(n, ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *s = 0.0;
    *t = 1.0;
    return;
  }
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  const double area2 = va + vb + vc;  // (twice the area)^2 up to rounding
  const double scale = Dot(n, ab, ab) * Dot(n, ac, ac);
  if (area2 > 1e-14 * scale) {
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
      *s = d1 / (d1 - d3);
      *t = 0.0;
      return;
    }
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
      *s = 0.0;
      *t = d2 / (d2 - d6);
      return;
    }
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
      const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      *s = 1.0 - w;
      *t = w;
      return;
    }
    *s = vb / area2;
    *t = vc / area2;
    return;
  }
  // Degenerate: the closest point lies on one of the edges.
  double best = -1.0, closest[3];
  const double tab = SegmentParameter(n, a, b, p), tac = SegmentParameter(n, a, c, p), tbc = SegmentParameter(n, b, c, p);
  const double candidates[3][2] = {{tab, 0.0}, {0.0, tac}, {1.0 - tbc, tbc}};
  for (const auto& st : candidates) {
    const double d = Evaluate(n, a, b, c, st[0], st[1], p, closest);
    if (best < 0.0 || d < best) {
      best = d;
      *s = st[0];
      *t = st[1];
    }
  }
}

}  // namespace

double ClosestPointOnSimplex(int dim, int ambientDim, const double* const* v, const double* p, double* ref,
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
  if (std::abs(det) > 1e-12 * scale) {
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

}  // namespace invmap::kernels
