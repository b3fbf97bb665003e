// The shape function of a chart: a tensor-product Bezier patch of bidegree
// (D, D) over the square [-R, R]^2 of the chart's local coordinates (R the
// p-domain's radius), with (D + 1)^2 control points in R^3, x fastest.
#pragma once

#include <string>
#include <vector>

#include "pou/interval.h"

namespace invmap::pou {

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

/// Bounds that hold over the whole square: the largest control point
/// coordinate magnitude, and for each order k = 1, 2, 3 the largest magnitude
/// any k-th partial derivative of any coordinate reaches there (from the
/// difference nets, whose coefficients bound the derivative by the convex
/// hull property, widened for their rounding).
struct ShapeBounds {
  double value = 0.0;
  double derivative[4] = {0, 0, 0, 0};  ///< [1], [2], [3] used.
};
ShapeBounds BoundShape(const ShapeNet& net);

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

/// Least-squares fit of a net of bidegree `degree` over [-radius, radius]^2
/// to `count` samples: parameters `uv` (2 each) and points `xyz` (3 each),
/// with a light penalty (weight 1e-2) on the net's second differences that
/// settles the control points the samples barely reach (the square's corners).
/// Writes the (degree + 1)^2 control points to `out`. Returns an error
/// message when the samples do not determine the net (fewer than unknowns,
/// or rank deficient).
std::string FitShape(int degree, double radius, const std::vector<double>& uv, const std::vector<double>& xyz,
                     std::vector<double>* out);

}  // namespace invmap::pou
