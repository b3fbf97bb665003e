#include "pou/shape_function.h"

#include <algorithm>
#include <cmath>

namespace invmap::pou {
namespace {

constexpr int kMaxBasis = 32;
/// Weight of the smoothing rows of the fit against the sample rows (whose
/// basis values add up to 1).
constexpr double kSmoothingWeight = 1e-2;

/// Bernstein polynomials of degree d at s, with their first and second
/// derivatives in s.
struct Basis1 {
  double b[kMaxBasis], d1[kMaxBasis], d2[kMaxBasis];
};

/// All Bernstein polynomials of degree `degree` at s, into out[0 .. degree].
void Bernstein(int degree, double s, double* out) {
  out[0] = 1.0;
  for (int d = 1; d <= degree; ++d) {
    out[d] = s * out[d - 1];
    for (int j = d - 1; j >= 1; --j) out[j] = (1.0 - s) * out[j] + s * out[j - 1];
    out[0] *= 1.0 - s;
  }
}

/// From the polynomials of degree d - 1 at s, those of degree d (one step
/// of the recurrence).
void RaiseDegree(int d, double s, const double* lower, double* out) {
  out[0] = (1.0 - s) * lower[0];
  for (int j = 1; j < d; ++j) out[j] = (1.0 - s) * lower[j] + s * lower[j - 1];
  out[d] = s * lower[d - 1];
}

Basis1 BernsteinWithDerivatives(int degree, double s) {
  Basis1 r;
  double lower1[kMaxBasis] = {}, lower2[kMaxBasis] = {};
  // Degree d - 2 once, then d - 1 and d by one step each.
  if (degree >= 2) {
    Bernstein(degree - 2, s, lower2);
    RaiseDegree(degree - 1, s, lower2, lower1);
    RaiseDegree(degree, s, lower1, r.b);
  } else if (degree == 1) {
    lower1[0] = 1.0;
    RaiseDegree(1, s, lower1, r.b);
  } else {
    r.b[0] = 1.0;
  }
  for (int j = 0; j <= degree; ++j) {
    const double a = j >= 1 ? lower1[j - 1] : 0.0;
    const double b = j <= degree - 1 ? lower1[j] : 0.0;
    r.d1[j] = degree * (a - b);
    const double c0 = j >= 2 ? lower2[j - 2] : 0.0;
    const double c1 = j >= 1 && j - 1 <= degree - 2 ? lower2[j - 1] : 0.0;
    const double c2 = j <= degree - 2 ? lower2[j] : 0.0;
    r.d2[j] = degree * (degree - 1) * (c0 - 2.0 * c1 + c2);
  }
  return r;
}

/// Cuts one row of Bezier coefficients (degree d, stride `stride`) from
/// [0, 1] to [s0, s1] (s0 < s1, both within [-0.075, 1.075]), in place:
/// de Casteljau's steps, which beyond [0, 1] extend the polynomial. The
/// end inside [0, 1] is cut second, so that its step's parameter stays in
/// [0, 1] too and every step's weights add up to at most 1.15 in size.
void CutRow(int d, double s0, double s1, double* c, int stride) {
  double work[kMaxBasis];
  for (int i = 0; i <= d; ++i) work[i] = c[i * stride];
  // The left part of [0, 1] at s: [0, s] (work[i] ends as its coefficient i).
  const auto left = [&](double s) {
    for (int level = 1; level <= d; ++level)
      for (int i = d; i >= level; --i) work[i] = (1.0 - s) * work[i - 1] + s * work[i];
  };
  // The right part at s: [s, 1].
  const auto right = [&](double s) {
    for (int level = 1; level <= d; ++level)
      for (int i = 0; i + level <= d; ++i) work[i] = (1.0 - s) * work[i] + s * work[i + 1];
  };
  if (s0 < 0.0 && s1 <= 1.0) {
    right(s0);
    left((s1 - s0) / (1.0 - s0));
  } else {
    left(s1);
    right(s0 / s1);
  }
  for (int i = 0; i <= d; ++i) c[i * stride] = work[i];
}

}  // namespace

ShapeJet EvaluateShape(const ShapeNet& net, double x, double y) {
  const int d = net.degree;
  const double scale = 1.0 / (2.0 * net.radius);
  const Basis1 bx = BernsteinWithDerivatives(d, (x + net.radius) * scale);
  const Basis1 by = BernsteinWithDerivatives(d, (y + net.radius) * scale);
  ShapeJet jet{};
  for (int k = 0; k <= d; ++k) {
    // Contract the row first: sums over j of each x factor, then the y factor.
    double row[3][3] = {};  // [x factor: b, d1, d2][coordinate]
    for (int j = 0; j <= d; ++j) {
      const double* p = net.points + 3 * (j + (d + 1) * k);
      for (int c = 0; c < 3; ++c) {
        row[0][c] += bx.b[j] * p[c];
        row[1][c] += bx.d1[j] * p[c];
        row[2][c] += bx.d2[j] * p[c];
      }
    }
    for (int c = 0; c < 3; ++c) {
      jet.value[c] += by.b[k] * row[0][c];
      jet.grad[c][0] += by.b[k] * row[1][c];
      jet.grad[c][1] += by.d1[k] * row[0][c];
      jet.hess[c][0] += by.b[k] * row[2][c];
      jet.hess[c][1] += by.d1[k] * row[1][c];
      jet.hess[c][2] += by.d2[k] * row[0][c];
    }
  }
  for (int c = 0; c < 3; ++c) {
    jet.grad[c][0] *= scale;
    jet.grad[c][1] *= scale;
    for (int h = 0; h < 3; ++h) jet.hess[c][h] *= scale * scale;
  }
  return jet;
}

void EvaluateShapePoint(const ShapeNet& net, double x, double y, double out[3]) {
  const int d = net.degree;
  const double scale = 1.0 / (2.0 * net.radius);
  double bx[kMaxBasis], by[kMaxBasis];
  Bernstein(d, (x + net.radius) * scale, bx);
  Bernstein(d, (y + net.radius) * scale, by);
  out[0] = out[1] = out[2] = 0.0;
  for (int k = 0; k <= d; ++k) {
    double row[3] = {};
    for (int j = 0; j <= d; ++j) {
      const double* p = net.points + 3 * (j + (d + 1) * k);
      for (int c = 0; c < 3; ++c) row[c] += bx[j] * p[c];
    }
    for (int c = 0; c < 3; ++c) out[c] += by[k] * row[c];
  }
}

ShapeBounds BoundShape(const ShapeNet& net, double extension) {
  const int d = net.degree, n = d + 1;
  ShapeBounds bounds;
  for (int i = 0; i < 3 * n * n; ++i) bounds.value = std::max(bounds.value, std::fabs(net.points[i]));
  // The net over the extended square: each row and column re-parametrized
  // from [0, 1] to [(1 - e) / 2, (1 + e) / 2] (de Casteljau beyond the ends).
  const double s0 = 0.5 * (1.0 - extension), s1 = 0.5 * (1.0 + extension);
  std::vector<double> extended(3 * n * n);
  double largest = 0.0;
  for (int c = 0; c < 3; ++c) {
    double* net3 = extended.data() + c * n * n;
    for (int i = 0; i < n * n; ++i) net3[i] = net.points[3 * i + c];
    for (int k = 0; k < n; ++k) CutRow(d, s0, s1, net3 + n * k, 1);
    for (int j = 0; j < n; ++j) CutRow(d, s0, s1, net3 + j, n);
    for (int i = 0; i < n * n; ++i) largest = std::max(largest, std::fabs(net3[i]));
  }
  const double scale = 1.0 / (2.0 * extension * net.radius);
  for (int order = 1; order <= 3; ++order) {
    double partial = 0.0;
    for (int a = 0; a <= order; ++a) {
      const int b = order - a;
      if (a > d || b > d) continue;
      // Coefficients of d^a/ds^a d^b/dt^b: falling factorials times forward
      // differences a times along x and b times along y.
      double factor = 1.0;
      for (int i = 0; i < a; ++i) factor *= d - i;
      for (int i = 0; i < b; ++i) factor *= d - i;
      for (int c = 0; c < 3; ++c) {
        std::vector<double> diff(extended.begin() + c * n * n, extended.begin() + (c + 1) * n * n);
        int nx = n, ny = n;
        for (int i = 0; i < a; ++i, --nx) {
          for (int k = 0; k < ny; ++k)
            for (int j = 0; j + 1 < nx; ++j) diff[j + n * k] = diff[j + 1 + n * k] - diff[j + n * k];
        }
        for (int i = 0; i < b; ++i, --ny) {
          for (int k = 0; k + 1 < ny; ++k)
            for (int j = 0; j < nx; ++j) diff[j + n * k] = diff[j + n * (k + 1)] - diff[j + n * k];
        }
        for (int k = 0; k < ny; ++k)
          for (int j = 0; j < nx; ++j) partial = std::max(partial, factor * std::fabs(diff[j + n * k]));
      }
    }
    // Rounding of the extension (2 d levels of combinations with weights up
    // to e in size) and of the differences (an ulp of values up to 2^order
    // times the largest coefficient per level), far below this allowance.
    double factorMax = 1.0;
    for (int i = 0; i < order; ++i) factorMax *= d;
    const double rounding = factorMax * std::ldexp(largest, order) * 1e-12;
    bounds.norm[order] = std::sqrt(3.0 * (1 << order)) * (partial + rounding) * std::pow(scale, order) * (1.0 + 1e-12);
  }
  return bounds;
}


ShapeRanges RangeOverBox(const ShapeNet& net, const double lo[2], const double hi[2]) {
  const int d = net.degree, n = d + 1;
  const double scale = 1.0 / (2.0 * net.radius);
  // Parameter ranges, rounded outward (the cut covers at least the box),
  // within the square enlarged by kShapeBoundExtension.
  const double reach = 0.5 * kShapeBoundExtension;
  double s0[2], s1[2], width[2];
  for (int i = 0; i < 2; ++i) {
    s0[i] = std::max(0.5 - reach, std::nextafter((lo[i] + net.radius) * scale, -1.0) - 0x1p-52);
    s1[i] = std::min(0.5 + reach, std::nextafter((hi[i] + net.radius) * scale, 2.0) + 0x1p-52);
    width[i] = (s1[i] - s0[i]) / scale;  // in chart units
  }
  double largest = 0.0;
  for (int i = 0; i < 3 * n * n; ++i) largest = std::max(largest, std::fabs(net.points[i]));
  // Each cut is two de Casteljau runs of d levels of combinations whose
  // weights add up to at most 1.15 in size (CutRow).
  const double rounding = 8.0 * (2.0 * d + 2.0) * 0x1p-53 * largest * std::pow(1.15, 2 * d);
  ShapeRanges r;
  double third = 0.0;
  for (int c = 0; c < 3; ++c) {
    double cut[kMaxBasis * kMaxBasis];
    for (int i = 0; i < n * n; ++i) cut[i] = net.points[3 * i + c];
    for (int k = 0; k < n; ++k) CutRow(d, s0[0], s1[0], cut + n * k, 1);
    for (int j = 0; j < n; ++j) CutRow(d, s0[1], s1[1], cut + j, n);
    const auto range = [&](auto coefficient, int nx, int ny, double factor, double error) {
      double a = coefficient(0, 0), b = a;
      for (int k = 0; k < ny; ++k)
        for (int j = 0; j < nx; ++j) {
          const double v = coefficient(j, k);
          a = std::min(a, v);
          b = std::max(b, v);
        }
      const double pad = factor * error;
      return Interval(interval_detail::Down(factor * a - pad), interval_detail::Up(factor * b + pad));
    };
    const auto at = [&](int j, int k) { return cut[j + n * k]; };
    r.value[c] = range(at, n, n, 1.0, rounding);
    if (d >= 1) {
      r.grad[c][0] = range([&](int j, int k) { return at(j + 1, k) - at(j, k); }, n - 1, n, d / width[0], 2 * rounding);
      r.grad[c][1] = range([&](int j, int k) { return at(j, k + 1) - at(j, k); }, n, n - 1, d / width[1], 2 * rounding);
    } else {
      r.grad[c][0] = r.grad[c][1] = Interval(0.0);
    }
    if (d >= 2) {
      r.hess[c][0] = range([&](int j, int k) { return at(j + 2, k) - 2 * at(j + 1, k) + at(j, k); }, n - 2, n,
                           d * (d - 1) / (width[0] * width[0]), 4 * rounding);
      r.hess[c][2] = range([&](int j, int k) { return at(j, k + 2) - 2 * at(j, k + 1) + at(j, k); }, n, n - 2,
                           d * (d - 1) / (width[1] * width[1]), 4 * rounding);
    } else {
      r.hess[c][0] = r.hess[c][2] = Interval(0.0);
    }
    r.hess[c][1] = d >= 1 ? range([&](int j, int k) { return at(j + 1, k + 1) - at(j + 1, k) - at(j, k + 1) + at(j, k); },
                                  n - 1, n - 1, d * d / (width[0] * width[1]), 4 * rounding)
                          : Interval(0.0);
    // Third partials: every mix of differences along x and y.
    for (int ax = 0; ax <= 3; ++ax) {
      const int ay = 3 - ax;
      if (ax > d || ay > d) continue;
      double factor = 1.0;
      for (int i = 0; i < ax; ++i) factor *= (d - i) / width[0];
      for (int i = 0; i < ay; ++i) factor *= (d - i) / width[1];
      double diff[kMaxBasis * kMaxBasis];
      std::copy(cut, cut + n * n, diff);
      int nx = n, ny = n;
      for (int i = 0; i < ax; ++i, --nx)
        for (int k = 0; k < ny; ++k)
          for (int j = 0; j + 1 < nx; ++j) diff[j + n * k] = diff[j + 1 + n * k] - diff[j + n * k];
      for (int i = 0; i < ay; ++i, --ny)
        for (int k = 0; k + 1 < ny; ++k)
          for (int j = 0; j < nx; ++j) diff[j + n * k] = diff[j + n * (k + 1)] - diff[j + n * k];
      for (int k = 0; k < ny; ++k)
        for (int j = 0; j < nx; ++j) third = std::max(third, factor * (std::fabs(diff[j + n * k]) + 8 * rounding));
    }
  }
  r.third = third * (1.0 + 1e-12);
  return r;
}

std::string ShapeFitter::Factor(int degree, double radius, const std::vector<double>& uv) {
  const int n = degree + 1, unknowns = n * n;
  const int count = static_cast<int>(uv.size() / 2);
  degree_ = degree;
  count_ = count;
  if (count < unknowns) {
    return std::to_string(count) + " samples for " + std::to_string(unknowns) + " control points";
  }
  // The samples cover the star of the vertex, not the corners of the square:
  // a light penalty on the net's second differences keeps the control
  // points there near a smooth continuation instead of wherever the
  // samples leave them (up to 100 times the star's size without it), which
  // would also make every derivative bound of the net useless.
  const int penalties = degree >= 2 ? 2 * n * (n - 2) + (n - 1) * (n - 1) : 0;
  rows_ = count + penalties;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows_, unknowns);
  const double scale = 1.0 / (2.0 * radius);
  double bx[kMaxBasis], by[kMaxBasis];
  for (int s = 0; s < count; ++s) {
    Bernstein(degree, (uv[2 * s] + radius) * scale, bx);
    Bernstein(degree, (uv[2 * s + 1] + radius) * scale, by);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) a(s, j + n * k) = bx[j] * by[k];
  }
  const double weight = kSmoothingWeight;
  int row = count;
  for (int k = 0; k < n && degree >= 2; ++k) {
    for (int j = 0; j + 2 < n; ++j, ++row) {
      a(row, j + n * k) = weight;
      a(row, j + 1 + n * k) = -2.0 * weight;
      a(row, j + 2 + n * k) = weight;
    }
  }
  for (int k = 0; k + 2 < n; ++k) {
    for (int j = 0; j < n; ++j, ++row) {
      a(row, j + n * k) = weight;
      a(row, j + n * (k + 1)) = -2.0 * weight;
      a(row, j + n * (k + 2)) = weight;
    }
  }
  for (int k = 0; k + 1 < n && degree >= 2; ++k) {
    for (int j = 0; j + 1 < n; ++j, ++row) {
      a(row, j + n * k) = weight;
      a(row, j + 1 + n * k) = -weight;
      a(row, j + n * (k + 1)) = -weight;
      a(row, j + 1 + n * (k + 1)) = weight;
    }
  }
  qr_.compute(a);
  if (qr_.rank() < unknowns) {
    return "the samples determine only " + std::to_string(qr_.rank()) + " of " + std::to_string(unknowns) +
           " control points";
  }
  return {};
}

void ShapeFitter::Solve(const std::vector<double>& xyz, std::vector<double>* out) const {
  const int unknowns = (degree_ + 1) * (degree_ + 1);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(rows_, 3);
  for (int s = 0; s < count_; ++s)
    for (int c = 0; c < 3; ++c) rhs(s, c) = xyz[3 * s + c];
  const Eigen::MatrixXd solution = qr_.solve(rhs);
  out->resize(3 * unknowns);
  for (int i = 0; i < unknowns; ++i)
    for (int c = 0; c < 3; ++c) (*out)[3 * i + c] = solution(i, c);
}

}  // namespace invmap::pou
