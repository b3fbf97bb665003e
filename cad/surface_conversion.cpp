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

/// origin + a x + c z.
void InPlane(const Frame& f, double a, double c, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = f.origin[k] + a * f.x[k] + c * f.z[k];
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
    return result;
  }
  if (auto sphere = Handle(Geom_SphericalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(sphere->Position());
    const double r = sphere->Radius();
    const double x[3] = {r * f.x[0], r * f.x[1], r * f.x[2]}, z[3] = {r * f.z[0], r * f.z[1], r * f.z[2]};
    result.type = "sphere";
    const double lo = std::max(v0, -0.5 * M_PI), hi = std::min(v1, 0.5 * M_PI);
    result.surface = Revolve(ArcCurve(3, f.origin, x, z, lo, hi), f.origin, f.x, f.y, f.z, u0, u1);
    return result;
  }
  if (auto torus = Handle(Geom_ToroidalSurface)::DownCast(surface)) {
    const Frame f = FrameOf(torus->Position());
    const double big = torus->MajorRadius(), r = torus->MinorRadius();
    double center[3];
    InPlane(f, big, 0.0, center);
    const double x[3] = {r * f.x[0], r * f.x[1], r * f.x[2]}, z[3] = {r * f.z[0], r * f.z[1], r * f.z[2]};
    result.type = "torus";
    result.surface = Revolve(ArcCurve(3, center, x, z, v0, v1), f.origin, f.x, f.y, f.z, u0, u1);
    return result;
  }
  if (auto revolution = Handle(Geom_SurfaceOfRevolution)::DownCast(surface)) {
    const ConvertedCurve profile = ConvertCurve(revolution->BasisCurve(), v0, v1, tolerance);
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
