// Splines in Bezier extraction form for the tests of Cubit's formats: the
// extraction operators computed here independently of invmap (each B-spline
// function sampled on an element by Cox-de Boor and interpolated in the
// Bernstein basis), and writers of the three formats Cubit exports.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace invmap::testing {

/// A tensor-product B-spline or NURBS curve, surface or volume in 3D.
struct TestSpline {
  std::vector<int> degrees;
  std::vector<std::vector<double>> knots;
  std::vector<int> counts;
  std::vector<std::array<double, 3>> points;  ///< u fastest.
  std::vector<double> weights;                ///< Empty: polynomial.

  /// The point at knot values `t` (one per direction) of the span `spans`.
  std::array<double, 3> Evaluate(const std::array<int, 3>& spans, const std::array<double, 3>& t) const;
};

/// One element (non-empty knot span) of a spline in a model.
struct TestElement {
  int spline = 0;                   ///< Index in TestModel::splines.
  std::array<int, 3> spans{0, 0, 0};
  std::vector<int> points;          ///< Global control point indices of its functions.
  std::vector<int> vectors;         ///< Their coefficient vectors (indices into TestModel::vectors).
};

/// Several splines (Cubit's blocks, of different degrees) in one model.
struct TestModel {
  std::vector<TestSpline> splines;
  std::vector<std::array<double, 3>> points;  ///< Every spline's control points, one after the other.
  std::vector<double> weights;                ///< Empty when no spline is rational.
  std::vector<std::vector<double>> vectors;
  std::vector<TestElement> elements;          ///< Spline by spline, u fastest.

  /// The element's knot values at its reference coordinates `s` in [0, 1].
  std::array<double, 3> KnotValues(const TestElement& e, const std::array<double, 3>& s) const;
};

/// Extracts every element of every spline.
TestModel Extract(const std::vector<TestSpline>& splines);

/// Cubit's LS-DYNA Bezier extraction file: one patch, one element block per spline.
std::string BextText(const TestModel& model);
/// Cubit's current Bezier extraction JSON: one block_elem_map entry per spline.
std::string CubitJsonText(const TestModel& model);
/// Cubit's Exodus Bezier extraction file (the Exodus library plus netCDF for
/// the blob and the attributes): one element block per spline. False on error.
bool WriteExodusBex(const std::string& path, const TestModel& model);

}  // namespace invmap::testing
