#include "cad/curve_conversion.h"

#include <Geom2dAdaptor_Curve.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <GeomConvert.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_BezierCurve.hxx>
#include <Geom2d_Circle.hxx>
#include <Geom2d_Ellipse.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_Circle.hxx>
#include <Geom_Ellipse.hxx>
#include <Geom_Line.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array1OfPnt2d.hxx>

#include <algorithm>

#include "cad/polynomial_approximation.h"
#include "cad/spline_builders.h"
#include "kernels/cell_shape.h"
#include "kernels/trim_region.h"

namespace invmap::cad {
namespace {

void Coordinates(const gp_Pnt& p, double* out) {
  out[0] = p.X();
  out[1] = p.Y();
  out[2] = p.Z();
}
void Coordinates(const gp_Pnt2d& p, double* out) {
  out[0] = p.X();
  out[1] = p.Y();
}
void Coordinates(const gp_Dir& d, double scale, double* out) {
  out[0] = scale * d.X();
  out[1] = scale * d.Y();
  out[2] = scale * d.Z();
}
void Coordinates(const gp_Dir2d& d, double scale, double* out) {
  out[0] = scale * d.X();
  out[1] = scale * d.Y();
}

/// The B-spline's flat knots, poles and weights (2D or 3D), over
/// [first, last] when `segment` (a copy is cut; periodic ones are unrolled).
template <typename BSpline, typename PointArray>
SplineCurve FromBSpline(Handle(BSpline) spline, double first, double last, int dim) {
  spline = Handle(BSpline)::DownCast(spline->Copy());
  if (!spline->IsPeriodic()) {
    first = std::max(first, spline->FirstParameter());
    last = std::min(last, spline->LastParameter());
  }
  if (last > first) spline->Segment(first, last);
  if (spline->IsPeriodic()) spline->SetNotPeriodic();
  SplineCurve curve;
  curve.degree = spline->Degree();
  TColStd_Array1OfReal knots(1, spline->NbPoles() + spline->Degree() + 1);
  spline->KnotSequence(knots);
  curve.knots.assign(knots.begin(), knots.end());
  const PointArray& poles = spline->Poles();
  for (int i = poles.Lower(); i <= poles.Upper(); ++i) {
    double p[3];
    Coordinates(poles(i), p);
    curve.points.insert(curve.points.end(), p, p + dim);
  }
  if (spline->IsRational()) {
    const TColStd_Array1OfReal* weights = spline->Weights();
    curve.weights.assign(weights->begin(), weights->end());
  }
  return curve;
}

}  // namespace

ConvertedCurve ConvertCurve(const Handle(Geom_Curve)& input, double first, double last, double tolerance,
                            double arcSpan) {
  Handle(Geom_Curve) curve = input;
  while (curve->IsKind(STANDARD_TYPE(Geom_TrimmedCurve))) curve = Handle(Geom_TrimmedCurve)::DownCast(curve)->BasisCurve();
  ConvertedCurve result;
  try {
    if (auto line = Handle(Geom_Line)::DownCast(curve)) {
      double p0[3], p1[3];
      Coordinates(line->Value(first), p0);
      Coordinates(line->Value(last), p1);
      result.curve = LineCurve(3, p0, p1, first, last);
      return result;
    }
    if (auto circle = Handle(Geom_Circle)::DownCast(curve)) {
      double c[3], x[3], y[3];
      Coordinates(circle->Location(), c);
      Coordinates(circle->Position().XDirection(), circle->Radius(), x);
      Coordinates(circle->Position().YDirection(), circle->Radius(), y);
      result.curve = ArcCurve(3, c, x, y, first, last, arcSpan);
      return result;
    }
    if (auto ellipse = Handle(Geom_Ellipse)::DownCast(curve)) {
      double c[3], x[3], y[3];
      Coordinates(ellipse->Location(), c);
      Coordinates(ellipse->Position().XDirection(), ellipse->MajorRadius(), x);
      Coordinates(ellipse->Position().YDirection(), ellipse->MinorRadius(), y);
      result.curve = ArcCurve(3, c, x, y, first, last, arcSpan);
      return result;
    }
    Handle(Geom_BSplineCurve) spline = Handle(Geom_BSplineCurve)::DownCast(curve);
    if (auto bezier = Handle(Geom_BezierCurve)::DownCast(curve)) spline = GeomConvert::CurveToBSplineCurve(bezier);
    if (spline && spline->Degree() <= kernels::kMaxDegree) {
      result.curve = FromBSpline<Geom_BSplineCurve, TColgp_Array1OfPnt>(spline, first, last, 3);
      return result;
    }
  } catch (const Standard_Failure&) {
    // Fall through to the approximation.
  }
  // Offset curves, hyperbolas, degrees above 8: approximated in the curve's
  // own parameter.
  result.approximated = true;
  result.curve = ApproximateCurve(GeomAdaptor_Curve(curve, first, last), tolerance, &result.deviation);
  return result;
}

ConvertedCurve ConvertCurve2d(const Handle(Geom2d_Curve)& input, double first, double last, double tolerance) {
  Handle(Geom2d_Curve) curve = input;
  while (curve->IsKind(STANDARD_TYPE(Geom2d_TrimmedCurve))) {
    curve = Handle(Geom2d_TrimmedCurve)::DownCast(curve)->BasisCurve();
  }
  ConvertedCurve result;
  try {
    if (auto line = Handle(Geom2d_Line)::DownCast(curve)) {
      double p0[2], p1[2];
      Coordinates(line->Value(first), p0);
      Coordinates(line->Value(last), p1);
      result.curve = LineCurve(2, p0, p1, first, last);
      return result;
    }
    if (auto circle = Handle(Geom2d_Circle)::DownCast(curve)) {
      double c[2], x[2], y[2];
      Coordinates(circle->Location(), c);
      Coordinates(circle->Position().XDirection(), circle->Radius(), x);
      Coordinates(circle->Position().YDirection(), circle->Radius(), y);
      result.curve = ArcCurve(2, c, x, y, first, last);
      return result;
    }
    if (auto ellipse = Handle(Geom2d_Ellipse)::DownCast(curve)) {
      double c[2], x[2], y[2];
      Coordinates(ellipse->Location(), c);
      Coordinates(ellipse->Position().XDirection(), ellipse->MajorRadius(), x);
      Coordinates(ellipse->Position().YDirection(), ellipse->MinorRadius(), y);
      result.curve = ArcCurve(2, c, x, y, first, last);
      return result;
    }
    Handle(Geom2d_BSplineCurve) spline = Handle(Geom2d_BSplineCurve)::DownCast(curve);
    if (auto bezier = Handle(Geom2d_BezierCurve)::DownCast(curve)) spline = Geom2dConvert::CurveToBSplineCurve(bezier);
    if (spline) {  // any degree: the trimming takes pcurves up to 25
      result.curve = FromBSpline<Geom2d_BSplineCurve, TColgp_Array1OfPnt2d>(spline, first, last, 2);
      return result;
    }
  } catch (const Standard_Failure&) {
  }
  result.approximated = true;
  result.curve = ApproximateCurve2d(Geom2dAdaptor_Curve(curve, first, last), tolerance, &result.deviation);
  return result;
}

}  // namespace invmap::cad
