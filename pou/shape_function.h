// The shape function of a chart: a tensor-product Bezier patch of bidegree
// (D, D) over the square [-R, R]^2 of the chart's local coordinates (R the
// p-domain's radius), with (D + 1)^2 control points in R^3, x fastest.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "pou/interval.h"

namespace invmap::pou {

/// The largest bidegree of a chart's shape function.
constexpr int kMaxChartDegree = 8;

/// A view of one shape function's net.
struct ShapeNet {
  int degree = 0;
  double radius = 1.0;
  const double* points = nullptr;  ///< (degree + 1)^2 points, 3 coordinates each, x fastest.
};

/// Value, gradient and Hessian of the shape function at (x, y):
/// value[k], grad[k] = {d/dx, d/dy}, hess[k] = {xx, xy, yy} per coordinate k.
struct ShapeJet {
  double value[3];
  double grad[3][2];
  double hess[3][3];
};
ShapeJet EvaluateShape(const ShapeNet& net, double x, double y);
/// The value only (cheaper).
void EvaluateShapePoint(const ShapeNet& net, double x, double y, double out[3]);

/// Bounds of a shape function: the largest control point coordinate
/// magnitude, and for k = 1, 2, 3 the norm of its k-th derivative (a k-linear
/// map from R^2 to R^3, Euclidean norms) over the square [-e R, e R]^2, e the
/// extension (1 for the shape function's own square): sqrt(3 2^k) times the
/// largest k-th partial of any coordinate, which the difference nets of the
/// net extended to that square bound (convex hull property), widened for
/// their rounding.
struct ShapeBounds {
  double value = 0.0;
  double norm[4] = {0, 0, 0, 0};  ///< [1], [2], [3] used.
};
ShapeBounds BoundShape(const ShapeNet& net, double extension);

/// Ranges over the box [lo, hi] of chart coordinates (inside the square) of
/// every coordinate's value (value[k]), first partials (grad[k] = {x, y}),
/// second partials (hess[k] = {xx, xy, yy}), and the largest magnitude of
/// any third partial (third): the control net is cut to the box by de
/// Casteljau's algorithm and its difference nets bound the derivatives
/// (convex hull property), each coefficient widened by a bound of the
/// rounding of the cut.
struct ShapeRanges {
  Interval value[3];
  Interval grad[3][2];
  Interval hess[3][3];
  double third = 0.0;
};
ShapeRanges RangeOverBox(const ShapeNet& net, const double lo[2], const double hi[2]);

/// How far beyond its square [-R, R]^2 a shape function's bounds may be
/// asked for (BoundShape, RangeOverBox): the square enlarged by this factor.
/// The pieces' sampling cells reach slightly past the gluing domains
/// (pou/piece_bounds.h).
constexpr double kShapeBoundExtension = 1.15;

/// Least-squares fit of nets of bidegree `degree` over [-radius, radius]^2
/// to samples at given parameters, with a light penalty (weight 1e-2) on the
/// net's second differences that settles the control points the samples
/// barely reach (the square's corners). Every chart of one valence and
/// degree samples the same parameters, so the factorization is made once
/// and solved for each chart's sample points.
class ShapeFitter {
 public:
  /// Factors the fit to the parameters `uv` (2 each). Returns an error
  /// message when they do not determine the net (fewer than unknowns, or
  /// rank deficient).
  std::string Factor(int degree, double radius, const std::vector<double>& uv);
  /// The (degree + 1)^2 control points fitted to `xyz`, the points (3 each)
  /// at the parameters given to Factor.
  void Solve(const std::vector<double>& xyz, std::vector<double>* out) const;

 private:
  int degree_ = 0, count_ = 0, rows_ = 0;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

}  // namespace invmap::pou
