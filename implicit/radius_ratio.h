// Shape quality of a simplex: the radius ratio n * inradius / circumradius,
// 1 for a regular simplex and 0 for a flat one (the figure the reference
// implementation reports for its grids).
#pragma once

#include <cmath>

namespace invmap::implicit {

/// Tetrahedron p0..p3 (3 coordinates each): 3 r / R = 108 V^2 / (|N| A), with
/// A the total face area and N the numerator of the circumcentre formula
/// (R = |N| / (12 V)).
inline double TetRadiusRatio(const double* p0, const double* p1, const double* p2, const double* p3) {
  auto sub = [](const double* a, const double* b, double* out) {
    for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
  };
  auto cross = [](const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto norm = [&](const double* a) { return std::sqrt(dot(a, a)); };
  double a[3], b[3], c[3];  // edges from p0
  sub(p1, p0, a);
  sub(p2, p0, b);
  sub(p3, p0, c);
  double bc[3], ca[3], ab[3];
  cross(b, c, bc);
  cross(c, a, ca);
  cross(a, b, ab);
  const double volume6 = dot(a, bc);
  // Circumcentre relative to p0: (|a|^2 (b x c) + |b|^2 (c x a) + |c|^2 (a x b)) / (2 * 6V).
  double numerator[3];
  for (int k = 0; k < 3; ++k) numerator[k] = dot(a, a) * bc[k] + dot(b, b) * ca[k] + dot(c, c) * ab[k];
  double bmA[3], cmA[3], face[3];
  sub(b, a, bmA);
  sub(c, a, cmA);
  cross(bmA, cmA, face);
  const double area2 = norm(ab) + norm(bc) + norm(ca) + norm(face);  // twice the total face area
  const double denominator = norm(numerator) * area2;
  if (!(denominator > 0)) return 0;
  // r = 3V / A = volume6 / area2 and R = |numerator| / (2 volume6), so
  // 3 r / R = 6 volume6^2 / (|numerator| area2).
  return 6 * volume6 * volume6 / denominator;
}

/// Triangle p0..p2 (3 coordinates each): 2 r / R = 8 A^2 / (s a b c), s the
/// semi-perimeter.
inline double TriangleRadiusRatio(const double* p0, const double* p1, const double* p2) {
  auto distance = [](const double* p, const double* q) {
    return std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
  };
  const double a = distance(p1, p2), b = distance(p2, p0), c = distance(p0, p1);
  const double s = (a + b + c) / 2;
  // Heron's formula in its stable product form: 16 A^2 = ...
  const double area2x16 = (a + b + c) * (-a + b + c) * (a - b + c) * (a + b - c);
  if (!(s > 0) || !(area2x16 > 0)) return 0;
  return 8 * (area2x16 / 16) / (s * a * b * c);
}

}  // namespace invmap::implicit
