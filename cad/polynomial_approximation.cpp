#include "cad/polynomial_approximation.h"

#include <TColStd_Array1OfReal.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::cad {
namespace {

constexpr int kDegree = kernels::kMaxDegree;
constexpr int kNodes = kDegree + 1;
/// Halvings of a piece of the geometry's own intervals before giving up.
constexpr int kMaxPiecesPerInterval = 256;
/// Deviation samples per piece and direction (between the nodes).
constexpr int kSamples = 16;

/// Bernstein coefficients from values at the Chebyshev-Lobatto nodes: the
/// inverse of the nodes' Bernstein matrix, by Gauss-Jordan once.
struct Interpolation {
  double node[kNodes];
  double inverse[kNodes][kNodes];

  Interpolation() {
    double a[kNodes][2 * kNodes];
    for (int k = 0; k < kNodes; ++k) {
      node[k] = 0.5 * (1.0 - std::cos(M_PI * k / kDegree));
      for (int j = 0; j < kNodes; ++j) {
        a[k][j] = Bernstein(j, node[k]);
        a[k][kNodes + j] = j == k ? 1.0 : 0.0;
      }
    }
    for (int c = 0; c < kNodes; ++c) {
      int pivot = c;
      for (int r = c + 1; r < kNodes; ++r) {
        if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
      }
      for (int j = 0; j < 2 * kNodes; ++j) std::swap(a[c][j], a[pivot][j]);
      const double d = a[c][c];
      for (int j = 0; j < 2 * kNodes; ++j) a[c][j] /= d;
      for (int r = 0; r < kNodes; ++r) {
        if (r == c) continue;
        const double f = a[r][c];
        for (int j = 0; j < 2 * kNodes; ++j) a[r][j] -= f * a[c][j];
      }
    }
    for (int i = 0; i < kNodes; ++i)
      for (int j = 0; j < kNodes; ++j) inverse[i][j] = a[i][kNodes + j];
  }

  static double Bernstein(int j, double t) {
    double b = 1.0;
    for (int i = 0; i < j; ++i) b *= t * (kDegree - i) / (i + 1);
    for (int i = 0; i < kDegree - j; ++i) b *= 1.0 - t;
    return b;
  }

  /// Bernstein coefficients c (stride `stride` over `dim` values each) from
  /// values at the nodes laid out the same way.
  void Solve(const double* values, int stride, int dim, double* coefficients) const {
    for (int i = 0; i < kNodes; ++i) {
      for (int k = 0; k < dim; ++k) {
        double s = 0.0;
        for (int j = 0; j < kNodes; ++j) s += inverse[i][j] * values[j * stride + k];
        coefficients[i * stride + k] = s;
      }
    }
  }
};

const Interpolation& Nodes() {
  static const Interpolation interpolation;
  return interpolation;
}

/// Value at t of Bernstein coefficients c (stride, dim values each).
void EvaluateBezier(const double* c, int stride, int dim, double t, double* out) {
  double work[kNodes][3];
  for (int i = 0; i < kNodes; ++i)
    for (int k = 0; k < dim; ++k) work[i][k] = c[i * stride + k];
  for (int level = 1; level < kNodes; ++level)
    for (int i = 0; i < kNodes - level; ++i)
      for (int k = 0; k < dim; ++k) work[i][k] = (1.0 - t) * work[i][k] + t * work[i + 1][k];
  for (int k = 0; k < dim; ++k) out[k] = work[0][k];
}

/// The breaks of an interval list, each interval cut into `pieces[i]` equal parts.
std::vector<double> Breaks(const std::vector<double>& intervals, const std::vector<int>& pieces) {
  std::vector<double> breaks{intervals.front()};
  for (std::size_t i = 0; i + 1 < intervals.size(); ++i) {
    for (int k = 1; k <= pieces[i]; ++k) {
      breaks.push_back(k == pieces[i] ? intervals[i + 1]
                                      : intervals[i] + (intervals[i + 1] - intervals[i]) * k / pieces[i]);
    }
  }
  return breaks;
}

/// Knots of a piecewise Bezier curve of degree kDegree over `breaks`:
/// every break of multiplicity kNodes (pieces joined only by position).
std::vector<double> PiecewiseKnots(const std::vector<double>& breaks) {
  std::vector<double> knots;
  for (double b : breaks) knots.insert(knots.end(), kNodes, b);
  return knots;
}

/// A curve of `dim` coordinates: pieces over `intervals`, refined where
/// they miss the tolerance.
SplineCurve ApproximatePath(const std::function<void(double, double*)>& value, std::vector<double> intervals, int dim,
                            double tolerance, double* deviation) {
  const Interpolation& nodes = Nodes();
  std::vector<int> pieces(intervals.size() - 1, 1);
  SplineCurve curve;
  curve.degree = kDegree;
  for (;;) {
    const std::vector<double> breaks = Breaks(intervals, pieces);
    std::vector<double> points;
    std::vector<double> worst(breaks.size() - 1, 0.0);
    for (std::size_t p = 0; p + 1 < breaks.size(); ++p) {
      const double a = breaks[p], b = breaks[p + 1];
      double values[kNodes * 3], coefficients[kNodes * 3];
      for (int k = 0; k < kNodes; ++k) value(a + (b - a) * nodes.node[k], values + k * 3);
      nodes.Solve(values, 3, dim, coefficients);
      // The ends interpolate exactly (the nodes include them): neighbouring
      // pieces meet, and the first and last points are the curve's own.
      for (int k = 0; k < kNodes; ++k) points.insert(points.end(), coefficients + k * 3, coefficients + k * 3 + dim);
      for (int s = 0; s < kSamples; ++s) {
        const double t = (s + 0.5) / kSamples;
        double exact[3], approx[3];
        value(a + (b - a) * t, exact);
        EvaluateBezier(coefficients, 3, dim, t, approx);
        double d2 = 0.0;
        for (int k = 0; k < dim; ++k) d2 += (exact[k] - approx[k]) * (exact[k] - approx[k]);
        worst[p] = std::max(worst[p], std::sqrt(d2));
      }
    }
    // Refine the intervals whose pieces miss the tolerance.
    bool refined = false;
    std::size_t p = 0;
    *deviation = 0.0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      double intervalWorst = 0.0;
      for (int k = 0; k < pieces[i]; ++k) intervalWorst = std::max(intervalWorst, worst[p++]);
      *deviation = std::max(*deviation, intervalWorst);
      if (intervalWorst > tolerance && pieces[i] < kMaxPiecesPerInterval) {
        pieces[i] *= 2;
        refined = true;
      }
    }
    if (!refined) {
      curve.knots = PiecewiseKnots(breaks);
      // Shared ends appear once per piece: a B-spline with knots of
      // multiplicity kNodes has kNodes points per piece, ends repeated.
      curve.points = std::move(points);
      return curve;
    }
  }
}

std::vector<double> CurveIntervals(const Adaptor3d_Curve& curve) {
  const int n = curve.NbIntervals(GeomAbs_C2);
  TColStd_Array1OfReal t(1, n + 1);
  curve.Intervals(t, GeomAbs_C2);
  return std::vector<double>(t.begin(), t.end());
}

}  // namespace

SplineCurve ApproximateCurve(const Adaptor3d_Curve& curve, double tolerance, double* deviation) {
  return ApproximatePath(
      [&](double t, double* out) {
        const gp_Pnt p = curve.Value(t);
        out[0] = p.X();
        out[1] = p.Y();
        out[2] = p.Z();
      },
      CurveIntervals(curve), 3, tolerance, deviation);
}

SplineCurve ApproximateCurve2d(const Adaptor2d_Curve2d& curve, double tolerance, double* deviation) {
  const int n = curve.NbIntervals(GeomAbs_C2);
  TColStd_Array1OfReal t(1, n + 1);
  curve.Intervals(t, GeomAbs_C2);
  return ApproximatePath(
      [&](double s, double* out) {
        const gp_Pnt2d p = curve.Value(s);
        out[0] = p.X();
        out[1] = p.Y();
      },
      std::vector<double>(t.begin(), t.end()), 2, tolerance, deviation);
}

SurfaceSpline ApproximateSurface(const Adaptor3d_Surface& surface, double tolerance, double* deviation) {
  const Interpolation& nodes = Nodes();
  std::vector<double> intervals[2];
  for (int d = 0; d < 2; ++d) {
    const int n = d == 0 ? surface.NbUIntervals(GeomAbs_C2) : surface.NbVIntervals(GeomAbs_C2);
    TColStd_Array1OfReal t(1, n + 1);
    if (d == 0) {
      surface.UIntervals(t, GeomAbs_C2);
    } else {
      surface.VIntervals(t, GeomAbs_C2);
    }
    intervals[d].assign(t.begin(), t.end());
  }
  std::vector<int> pieces[2] = {std::vector<int>(intervals[0].size() - 1, 1),
                                std::vector<int>(intervals[1].size() - 1, 1)};
  for (;;) {
    const std::vector<double> breaks[2] = {Breaks(intervals[0], pieces[0]), Breaks(intervals[1], pieces[1])};
    const std::size_t nu = breaks[0].size() - 1, nv = breaks[1].size() - 1;
    // The control net of all pieces: kNodes x kNodes per piece, u fastest.
    const std::size_t rowLength = nu * kNodes;
    std::vector<double> points(rowLength * nv * kNodes * 3);
    std::vector<double> worstU(nu, 0.0), worstV(nv, 0.0);
    for (std::size_t j = 0; j < nv; ++j) {
      for (std::size_t i = 0; i < nu; ++i) {
        const double u0 = breaks[0][i], u1 = breaks[0][i + 1], v0 = breaks[1][j], v1 = breaks[1][j + 1];
        double values[kNodes][kNodes][3], rows[kNodes][kNodes][3], net[kNodes][kNodes][3];
        for (int b = 0; b < kNodes; ++b) {
          for (int a = 0; a < kNodes; ++a) {
            const gp_Pnt p = surface.Value(u0 + (u1 - u0) * nodes.node[a], v0 + (v1 - v0) * nodes.node[b]);
            values[b][a][0] = p.X();
            values[b][a][1] = p.Y();
            values[b][a][2] = p.Z();
          }
          nodes.Solve(&values[b][0][0], 3, 3, &rows[b][0][0]);  // along u, per v node
        }
        for (int a = 0; a < kNodes; ++a) nodes.Solve(&rows[0][a][0], kNodes * 3, 3, &net[0][a][0]);  // along v
        for (int b = 0; b < kNodes; ++b)
          for (int a = 0; a < kNodes; ++a)
            for (int k = 0; k < 3; ++k)
              points[((j * kNodes + b) * rowLength + i * kNodes + a) * 3 + k] = net[b][a][k];
        double worst = 0.0;
        for (int sb = 0; sb < kSamples; ++sb) {
          const double t = (sb + 0.5) / kSamples;
          double column[kNodes][3];
          for (int a = 0; a < kNodes; ++a) EvaluateBezier(&net[0][a][0], kNodes * 3, 3, t, column[a]);
          for (int sa = 0; sa < kSamples; ++sa) {
            const double s = (sa + 0.5) / kSamples;
            double approx[3];
            EvaluateBezier(&column[0][0], 3, 3, s, approx);
            const gp_Pnt exact = surface.Value(u0 + (u1 - u0) * s, v0 + (v1 - v0) * t);
            worst = std::max(worst, exact.Distance(gp_Pnt(approx[0], approx[1], approx[2])));
          }
        }
        worstU[i] = std::max(worstU[i], worst);
        worstV[j] = std::max(worstV[j], worst);
      }
    }
    bool refined = false;
    *deviation = 0.0;
    for (int d = 0; d < 2; ++d) {
      const std::vector<double>& worst = d == 0 ? worstU : worstV;
      std::size_t p = 0;
      for (std::size_t i = 0; i < pieces[d].size(); ++i) {
        double intervalWorst = 0.0;
        for (int k = 0; k < pieces[d][i]; ++k) intervalWorst = std::max(intervalWorst, worst[p++]);
        *deviation = std::max(*deviation, intervalWorst);
        if (intervalWorst > tolerance && pieces[d][i] < kMaxPiecesPerInterval) {
          pieces[d][i] *= 2;
          refined = true;
        }
      }
    }
    if (!refined) {
      SurfaceSpline result;
      result.degrees[0] = result.degrees[1] = kDegree;
      for (int d = 0; d < 2; ++d) result.knots[d] = PiecewiseKnots(breaks[d]);
      result.counts[0] = static_cast<int>(nu * kNodes);
      result.counts[1] = static_cast<int>(nv * kNodes);
      result.points = std::move(points);
      return result;
    }
  }
}

}  // namespace invmap::cad
