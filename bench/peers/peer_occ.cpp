// OpenCascade peers: ShapeAnalysis_Surface::ValueOfUV, GeomAPI_ProjectPointOnSurf
// (Extrema_ExtPS, Grad and Tree) and GeomAPI_ProjectPointOnCurve, each
// initialized once per surface or curve and per thread, then Perform per point.
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>

#include <algorithm>
#include <cmath>

#include "bench/peers/occ_bspline.h"
#include "bench/peers/peer.h"

namespace invmap::bench {
namespace {

/// The planar curve as a Geom_BSplineCurve in the plane z = 0 (the 3D
/// projector answers exactly the 2D question there).
Handle(Geom_BSplineCurve) ToOccCurve(const Patch& patch) {
  const int n = patch.counts[0];
  TColgp_Array1OfPnt poles(1, n);
  TColStd_Array1OfReal weights(1, n);
  for (int i = 0; i < n; ++i) {
    poles.SetValue(i + 1, gp_Pnt(patch.points[2 * i], patch.points[2 * i + 1], 0.0));
    weights.SetValue(i + 1, patch.weights.empty() ? 1.0 : patch.weights[i]);
  }
  TColStd_Array1OfReal knots;
  TColStd_Array1OfInteger mults;
  SplitKnots(patch.knots[0], &knots, &mults);
  if (patch.weights.empty()) return new Geom_BSplineCurve(poles, knots, mults, patch.degrees[0]);
  return new Geom_BSplineCurve(poles, weights, knots, mults, patch.degrees[0]);
}

/// Surface worker of ShapeAnalysis_Surface::ValueOfUV: the returned (u, v)
/// and Gap(), the distance from the point to the surface at (u, v).
class ValueOfUVWorker : public PeerWorker {
 public:
  ValueOfUVWorker(const Handle(Geom_Surface)& surface, double precision)
      : surface_(surface), analysis_(new ShapeAnalysis_Surface(surface)), precision_(precision) {
    surface_->Bounds(u0_, u1_, v0_, v1_);
  }
  void Query(const double* point, PeerAnswer* answer) override {
    try {
      const gp_Pnt p(point[0], point[1], point[2]);
      const gp_Pnt2d uv = analysis_->ValueOfUV(p, precision_);
      // ValueOfUV may return parameters slightly outside the surface's
      // bounds, where Gap() measures to the extrapolated surface: the point
      // it stands for on the surface is at the clamped parameters.
      const double u = std::clamp(uv.X(), u0_, u1_), v = std::clamp(uv.Y(), v0_, v1_);
      answer->distance = p.Distance(surface_->Value(u, v));
      answer->failed = !std::isfinite(answer->distance);
    } catch (const Standard_Failure&) {
      answer->failed = true;
    }
  }

 private:
  Handle(Geom_Surface) surface_;
  Handle(ShapeAnalysis_Surface) analysis_;
  double precision_;
  double u0_ = 0, u1_ = 0, v0_ = 0, v1_ = 0;
};

/// Surface worker of GeomAPI_ProjectPointOnSurf (Extrema_ExtPS inside),
/// initialized once with the surface and its bounds; minima only.
class ProjectOnSurfWorker : public PeerWorker {
 public:
  ProjectOnSurfWorker(const Handle(Geom_Surface)& surface, Extrema_ExtAlgo algo) {
    double u0, u1, v0, v1;
    surface->Bounds(u0, u1, v0, v1);
    projector_.Init(surface, u0, u1, v0, v1, algo);
    projector_.SetExtremaFlag(Extrema_ExtFlag_MIN);
  }
  void Query(const double* point, PeerAnswer* answer) override {
    try {
      projector_.Perform(gp_Pnt(point[0], point[1], point[2]));
      if (projector_.IsDone() && projector_.NbPoints() > 0) {
        answer->distance = projector_.LowerDistance();
        answer->failed = false;
      } else {
        answer->failed = true;
      }
    } catch (const Standard_Failure&) {
      answer->failed = true;
    }
  }

 private:
  GeomAPI_ProjectPointOnSurf projector_;
};

/// Curve worker of GeomAPI_ProjectPointOnCurve, initialized once with the
/// curve and its parameter range.
class ProjectOnCurveWorker : public PeerWorker {
 public:
  explicit ProjectOnCurveWorker(const Handle(Geom_Curve)& curve) {
    projector_.Init(curve, curve->FirstParameter(), curve->LastParameter());
  }
  void Query(const double* point, PeerAnswer* answer) override {
    try {
      projector_.Perform(gp_Pnt(point[0], point[1], 0.0));
      if (projector_.NbPoints() > 0) {
        answer->distance = projector_.LowerDistance();
        answer->failed = false;
      } else {
        answer->failed = true;
      }
    } catch (const Standard_Failure&) {
      answer->failed = true;
    }
  }

 private:
  GeomAPI_ProjectPointOnCurve projector_;
};

/// Which OpenCascade call a SurfaceMethod runs.
enum class SurfaceCall { ValueOfUV, ProjectGrad, ProjectTree };

class SurfaceMethod : public PeerMethod {
 public:
  SurfaceMethod(const Patch& patch, SurfaceCall call, double precision)
      : surface_(ToOccSurface(patch)), call_(call), precision_(precision) {}
  std::string name() const override {
    switch (call_) {
      case SurfaceCall::ValueOfUV:
        return "OpenCascade ShapeAnalysis_Surface::ValueOfUV";
      case SurfaceCall::ProjectGrad:
        return "OpenCascade GeomAPI_ProjectPointOnSurf (Extrema_ExtPS, Grad)";
      case SurfaceCall::ProjectTree:
        return "OpenCascade GeomAPI_ProjectPointOnSurf (Extrema_ExtPS, Tree)";
    }
    return {};
  }
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override {
    // Each thread gets its own copy of the surface: nothing mutable is shared.
    Handle(Geom_Surface) copy = Handle(Geom_Surface)::DownCast(surface_->Copy());
    if (call_ == SurfaceCall::ValueOfUV) return std::make_unique<ValueOfUVWorker>(copy, precision_);
    return std::make_unique<ProjectOnSurfWorker>(
        copy, call_ == SurfaceCall::ProjectGrad ? Extrema_ExtAlgo_Grad : Extrema_ExtAlgo_Tree);
  }
  std::string note() const override {
    if (call_ == SurfaceCall::ValueOfUV) {
      return "preci = 1e-9 x size; distance at the returned (u, v) clamped to the bounds (it returns parameters "
             "up to about 1e-9 outside, where Gap() measures to the extended surface)";
    }
    return "Init once per surface and thread, Extrema_ExtFlag_MIN, Perform per point";
  }

 private:
  Handle(Geom_BSplineSurface) surface_;
  SurfaceCall call_;
  double precision_;
};

class CurveMethod : public PeerMethod {
 public:
  explicit CurveMethod(const Patch& patch) : curve_(ToOccCurve(patch)) {}
  std::string name() const override { return "OpenCascade GeomAPI_ProjectPointOnCurve"; }
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override {
    return std::make_unique<ProjectOnCurveWorker>(Handle(Geom_Curve)::DownCast(curve_->Copy()));
  }
  std::string note() const override { return "curve in the plane z = 0; Init once per thread, Perform per point"; }

 private:
  Handle(Geom_BSplineCurve) curve_;
};


}  // namespace

std::string OccVersion() { return std::string("OpenCascade ") + OCC_VERSION_COMPLETE; }

PeerList MakeOccPeers(const GeometryCase& geometryCase) {
  PeerList peers;
  const Patch& patch = geometryCase.geometry.patches[0];
  if (geometryCase.kind == CaseKind::SplineSurface) {
    const double precision = 1e-9 * ControlBoxSize(patch, 3);
    for (SurfaceCall call : {SurfaceCall::ValueOfUV, SurfaceCall::ProjectGrad, SurfaceCall::ProjectTree}) {
      peers.push_back([&patch, call, precision] { return std::make_unique<SurfaceMethod>(patch, call, precision); });
    }
  } else if (geometryCase.kind == CaseKind::SplineCurve) {
    peers.push_back([&patch] { return std::make_unique<CurveMethod>(patch); });
  }
  return peers;
}

}  // namespace invmap::bench
