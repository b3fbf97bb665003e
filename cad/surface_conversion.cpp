#include "cad/surface_conversion.h"

#include <GeomConvert.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_OffsetSurface.hxx>
#include <Geom_Plane.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_SurfaceOfLinearExtrusion.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <cmath>

#include "cad/curve_conversion.h"
#include "cad/polynomial_approximation.h"
#include "kernels/cell_shape.h"

namespace invmap::cad {
namespace {

struct Frame {
  double origin[3], x[3], y[3], z[3];
};

void Set(const gp_XYZ& v, double* out) {
  out[0] = v.X();
  out[1] = v.Y();
  out[2] = v.Z();
}

Frame FrameOf(const gp_Ax3& position) {
  Frame f;
  Set(position.Location().XYZ(), f.origin);
  Set(position.XDirection().XYZ(), f.x);
  Set(position.YDirection().XYZ(), f.y);
  Set(position.Direction().XYZ(), f.z);
  return f;
}

/// The elementary surface of `kind` in frame `f`.
AnalyticSurface AnalyticOf(AnalyticSurface::Kind kind, const Frame& f, double radius) {
  AnalyticSurface a;
  a.kind = kind;
  std::copy(f.origin, f.origin + 3, a.origin);
  std::copy(f.x, f.x + 3, a.xAxis);
  std::copy(f.y, f.y + 3, a.yAxis);
  std::copy(f.z, f.z + 3, a.axis);
  a.radius = radius;
  return a;
}

/// origin + a x + c z.
void InPlane(const Frame& f, double a, double c, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = f.origin[k] + a * f.x[k] + c * f.z[k];
}

/// The length of the polyline through `spline` at 9 points along u (d = 0)
/// or v (d = 1) over [a, b], the other parameter at `at`.
double ExtentAlong(const Handle(Geom_BSplineSurface)& spline, int d, double a, double b, double at) {
  double length = 0.0;
  gp_Pnt previous;
  for (int k = 0; k <= 8; ++k) {
    const double t = a + (b - a) * k / 8.0;
    const gp_Pnt p = d == 0 ? spline->Value(t, at) : spline->Value(at, t);
    if (k > 0) length += p.Distance(previous);
    previous = p;
  }
  return length;
}

/// Cuts knot spans longer than the longest span across them into equal
/// pieces (at most 16) by knot insertion (exact; the parameters stay the
/// same), as BalanceSpans does for linear directions (spline_builders.h):
/// long thin cells defeat the whole-cell convexity certificate of the cell
/// search (on OpenCascade's sample bearing.iges it passed for 52 % of the
/// searches before, 92 % after).
void BalanceKnotSpans(const Handle(Geom_BSplineSurface)& spline) {
  if (spline->UDegree() == 1 && spline->VDegree() == 1) return;  // flat cells need no convexity proof
  for (int d = 0; d < 2; ++d) {
    TColStd_Array1OfReal knots[2] = {TColStd_Array1OfReal(1, spline->NbUKnots()),
                                     TColStd_Array1OfReal(1, spline->NbVKnots())};
    spline->UKnots(knots[0]);
    spline->VKnots(knots[1]);
    // Each span's extent along both directions, measured at the middle and
    // the ends of the other direction's range.
    std::vector<double> along[2];
    for (int e = 0; e < 2; ++e) {
      const TColStd_Array1OfReal& other = knots[1 - e];
      const double lo = other(other.Lower()), hi = other(other.Upper());
      for (int i = knots[e].Lower(); i < knots[e].Upper(); ++i) {
        double extent = 0.0;
        for (const double at : {lo, 0.5 * (lo + hi), hi}) {
          extent = std::max(extent, ExtentAlong(spline, e, knots[e](i), knots[e](i + 1), at));
        }
        along[e].push_back(extent);
      }
    }
    const double across = *std::max_element(along[1 - d].begin(), along[1 - d].end());
    if (!(across > 0.0)) continue;
    std::vector<double> added;
    for (std::size_t i = 0; i < along[d].size(); ++i) {
      const int pieces = std::min(16, static_cast<int>(std::ceil(along[d][i] / across - 1e-9)));
      const int first = knots[d].Lower() + static_cast<int>(i);
      const double a = knots[d](first), b = knots[d](first + 1);
      for (int k = 1; k < pieces; ++k) added.push_back(a + (b - a) * k / pieces);
    }
    if (added.empty()) continue;
    // All at once: one insertion at a time costs the whole net each.
    TColStd_Array1OfReal newKnots(1, static_cast<int>(added.size()));
    TColStd_Array1OfInteger multiplicities(1, static_cast<int>(added.size()));
    for (std::size_t k = 0; k < added.size(); ++k) {
      newKnots(static_cast<int>(k) + 1) = added[k];
      multiplicities(static_cast<int>(k) + 1) = 1;
    }
    if (d == 0) {
      spline->InsertUKnots(newKnots, multiplicities, 0.0, false);
    } else {
      spline->InsertVKnots(newKnots, multiplicities, 0.0, false);
    }
  }
}

SurfaceSpline FromBSpline(Handle(Geom_BSplineSurface) spline, double u0, double u1, double v0, double v1) {
  spline = Handle(Geom_BSplineSurface)::DownCast(spline->Copy());
  double bu0, bu1, bv0, bv1;
  spline->Bounds(bu0, bu1, bv0, bv1);
  if (!spline->IsUPeriodic()) {
    u0 = std::max(u0, bu0);
    u1 = std::min(u1, bu1);
  } else {
    u1 = std::min(u1, u0 + spline->UPeriod());
  }
  if (!spline->IsVPeriodic()) {
    v0 = std::max(v0, bv0);
    v1 = std::min(v1, bv1);
  } else {
    v1 = std::min(v1, v0 + spline->VPeriod());
  }
  if (u1 > u0 && v1 > v0) spline->Segment(u0, u1, v0, v1);
  if (spline->IsUPeriodic()) spline->SetUNotPeriodic();
  if (spline->IsVPeriodic()) spline->SetVNotPeriodic();
  BalanceKnotSpans(spline);
  SurfaceSpline surface;
  surface.degrees[0] = spline->UDegree();
  surface.degrees[1] = spline->VDegree();
  const int nu = spline->NbUPoles(), nv = spline->NbVPoles();
  surface.counts[0] = nu;
  surface.counts[1] = nv;
  TColStd_Array1OfReal uKnots(1, nu + surface.degrees[0] + 1), vKnots(1, nv + surface.degrees[1] + 1);
  spline->UKnotSequence(uKnots);
  spline->VKnotSequence(vKnots);
  surface.knots[0].assign(uKnots.begin(), uKnots.end());
  surface.knots[1].assign(vKnots.begin(), vKnots.end());
  const TColgp_Array2OfPnt& poles = spline->Poles();
  const bool rational = spline->IsURational() || spline->IsVRational();
  const TColStd_Array2OfReal* weights = spline->Weights();
  for (int j = 1; j <= nv; ++j) {
    for (int i = 1; i <= nu; ++i) {
      const gp_Pnt& p = poles(poles.LowerRow() + i - 1, poles.LowerCol() + j - 1);
      surface.points.insert(surface.points.end(), {p.X(), p.Y(), p.Z()});
      if (rational) surface.weights.push_back((*weights)(weights->LowerRow() + i - 1, weights->LowerCol() + j - 1));
    }
  }
  return surface;
}

ConvertedSurface Approximate(const Handle(Geom_Surface)& surface, double u0, double u1, double v0, double v1,
                             double tolerance, std::string type) {
  ConvertedSurface result;
  result.type = std::move(type);
  result.approximated = true;
  // Within the surface's own domain (its periods, where it has them). An
  // adaptor keeps the parameters as given (a trimmed surface would move
  // them into the period that starts at the surface's first parameter).
  double bu0, bu1, bv0, bv1;
  surface->Bounds(bu0, bu1, bv0, bv1);
  if (!surface->IsUPeriodic()) {
    u0 = std::max(u0, bu0);
    u1 = std::min(u1, bu1);
  } else {
    u1 = std::min(u1, u0 + surface->UPeriod());
  }
  if (!surface->IsVPeriodic()) {
    v0 = std::max(v0, bv0);
    v1 = std::min(v1, bv1);
  } else {
    v1 = std::min(v1, v0 + surface->VPeriod());
  }
  const GeomAdaptor_Surface bounded(surface, u0, u1, v0, v1);
  result.surface = ApproximateSurface(bounded, tolerance, &result.deviation);
  return result;
}

}  // namespace

ConvertedSurface ConvertSurface(const Handle(Geom_Surface)& input, double u0, double u1, double v0, double v1,
                                double tolerance) {
  Handle(Geom_Surface) surface = input;
  while (auto trimmed = Handle(Geom_RectangularTrimmedSurface)::DownCast(surface)) surface = trimmed->BasisSurface();
  ConvertedSurface result;
  if (auto offset = Handle(Geom_OffsetSurface)::DownCast(surface)) {
    // An offset of a plane, cylinder, cone, sphere or torus is one again.
    Handle(Geom_Surface) equivalent = offset->Surface();
    if (equivalent.IsNull()) return Approximate(surface, u0, u1, v0, v1, tolerance, "offset");
    result = ConvertSurface(equivalent, u0, u1, v0, v1, tolerance);
    result.type = "offset";
    return result;
  }
  if (auto plane = Handle(Geom_Plane)::DownCast(surface)) {
    const Frame f = FrameOf(plane->Position());
    result.type = "plane";
    result.surface = PlanePatch(f.origin, f.x, f.y, u0, u1, v0, v1);
    result.analytic = AnalyticOf(AnalyticSurface::Kind::Plane, f, 0.0);
    return result;
  }
  if (auto cylinder = Handle(Geom_CylindricalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(cylinder->Position());
    const double r = cylinder->Radius();
    double p0[3], p1[3];
    InPlane(f, r, v0, p0);
    InPlane(f, r, v1, p1);
    result.type = "cylinder";
    result.surface = Revolve(LineCurve(3, p0, p1, v0, v1), f.origin, f.x, f.y, f.z, u0, u1);
    result.analytic = AnalyticOf(AnalyticSurface::Kind::Cylinder, f, r);
    return result;
  }
  if (auto cone = Handle(Geom_ConicalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(cone->Position());
    const double r = cone->RefRadius(), s = std::sin(cone->SemiAngle()), c = std::cos(cone->SemiAngle());
    double p0[3], p1[3];
    InPlane(f, r + v0 * s, v0 * c, p0);
    InPlane(f, r + v1 * s, v1 * c, p1);
    result.type = "cone";
    result.surface = Revolve(LineCurve(3, p0, p1, v0, v1), f.origin, f.x, f.y, f.z, u0, u1);
    result.analytic = AnalyticOf(AnalyticSurface::Kind::Cone, f, r);
    result.analytic.semiAngle = cone->SemiAngle();
    return result;
  }
  if (auto sphere = Handle(Geom_SphericalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(sphere->Position());
    const double r = sphere->Radius();
    const double x[3] = {r * f.x[0], r * f.x[1], r * f.x[2]}, z[3] = {r * f.z[0], r * f.z[1], r * f.z[2]};
    result.type = "sphere";
    const double lo = std::max(v0, -0.5 * M_PI), hi = std::min(v1, 0.5 * M_PI);
    result.surface = Revolve(ArcCurve(3, f.origin, x, z, lo, hi, kDoublyCurvedArcSpan), f.origin, f.x, f.y, f.z, u0, u1);
    result.analytic = AnalyticOf(AnalyticSurface::Kind::Sphere, f, r);
    return result;
  }
  if (auto torus = Handle(Geom_ToroidalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(torus->Position());
    const double big = torus->MajorRadius(), r = torus->MinorRadius();
    double center[3];
    InPlane(f, big, 0.0, center);
    const double x[3] = {r * f.x[0], r * f.x[1], r * f.x[2]}, z[3] = {r * f.z[0], r * f.z[1], r * f.z[2]};
    result.type = "torus";
    result.surface = Revolve(ArcCurve(3, center, x, z, v0, v1, kDoublyCurvedArcSpan), f.origin, f.x, f.y, f.z, u0, u1);
    result.analytic = AnalyticOf(AnalyticSurface::Kind::Torus, f, big);
    result.analytic.minorRadius = r;
    return result;
  }
  if (auto revolution = Handle(Geom_SurfaceOfRevolution)::DownCast(surface)) {
    const ConvertedCurve profile = ConvertCurve(revolution->BasisCurve(), v0, v1, tolerance, kDoublyCurvedArcSpan);
    const gp_Ax1 axis = revolution->Axis();
    const gp_Ax2 frame(axis.Location(), axis.Direction());
    double origin[3], x[3], y[3], z[3];
    Set(axis.Location().XYZ(), origin);
    Set(frame.XDirection().XYZ(), x);
    Set(frame.Direction().XYZ().Crossed(frame.XDirection().XYZ()), y);
    Set(frame.Direction().XYZ(), z);
    result.type = "revolution";
    result.approximated = profile.approximated;
    result.deviation = profile.deviation;
    result.surface = Revolve(profile.curve, origin, x, y, z, u0, u1);
    return result;
  }
  if (auto extrusion = Handle(Geom_SurfaceOfLinearExtrusion)::DownCast(surface)) {
    const ConvertedCurve profile = ConvertCurve(extrusion->BasisCurve(), u0, u1, tolerance);
    double d[3];
    Set(extrusion->Direction().XYZ(), d);
    result.type = "extrusion";
    result.approximated = profile.approximated;
    result.deviation = profile.deviation;
    result.surface = Extrude(profile.curve, d, v0, v1);
    return result;
  }
  Handle(Geom_BSplineSurface) spline = Handle(Geom_BSplineSurface)::DownCast(surface);
  result.type = spline ? "bspline" : "other";
  if (auto bezier = Handle(Geom_BezierSurface)::DownCast(surface)) {
    spline = GeomConvert::SurfaceToBSplineSurface(bezier);
    result.type = "bezier";
  }
  if (spline && spline->UDegree() <= kernels::kMaxDegree && spline->VDegree() <= kernels::kMaxDegree) {
    result.surface = FromBSpline(spline, u0, u1, v0, v1);
    return result;
  }
  return Approximate(surface, u0, u1, v0, v1, tolerance, result.type);
}

}  // namespace invmap::cad
