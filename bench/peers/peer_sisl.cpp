// SISL peers: s1954 (global closest points on a surface), s1958 (local
// closest point on a surface, from its own nearest-control-point guess) and
// s1953 (global closest points on a curve).
#include <sisl.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "bench/peers/peer.h"

namespace invmap::bench {
namespace {

/// SISL's "computational resolution" argument (documented as unused).
constexpr double kComputationalResolution = 1e-15;

/// Control coefficients in SISL's layout: u fastest (as in the patch), and for
/// a rational patch homogeneous (w x, w y, (w z,) w), which newSurf/newCurve
/// divide back.
std::vector<double> SislCoefficients(const Patch& patch, int dim) {
  const std::size_t n = patch.points.size() / dim;
  std::vector<double> coef;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = patch.weights.empty() ? 1.0 : patch.weights[i];
    for (int k = 0; k < dim; ++k) coef.push_back(w * patch.points[i * dim + k]);
    if (!patch.weights.empty()) coef.push_back(w);
  }
  return coef;
}

/// Euclidean distance of two points of `dim` coordinates.
double Distance(const double* a, const double* b, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) d2 += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(d2);
}

/// The patch as a SISLSurf (copied arrays).
SISLSurf* ToSislSurface(const Patch& patch) {
  std::vector<double> coef = SislCoefficients(patch, 3);
  std::vector<double> uKnots = patch.knots[0], vKnots = patch.knots[1];
  return newSurf(patch.counts[0], patch.counts[1], patch.degrees[0] + 1, patch.degrees[1] + 1, uKnots.data(),
                 vKnots.data(), coef.data(), patch.weights.empty() ? 1 : 2, 3, 1);
}

/// Distance from `point` to the surface at (u, v), by SISL's own evaluator.
double SurfaceDistance(SISLSurf* surface, const double* point, const double* uv) {
  double x[3];
  int leftU = 0, leftV = 0, status = 0;
  double par[2] = {uv[0], uv[1]};
  s1424(surface, 0, 0, par, &leftU, &leftV, x, &status);
  return status < 0 ? std::numeric_limits<double>::quiet_NaN() : Distance(x, point, 3);
}

/// s1954: every closest point; the answer is the nearest of those returned.
class GlobalSurfaceWorker : public PeerWorker {
 public:
  GlobalSurfaceWorker(SISLSurf* surface, double tolerance) : surface_(copySurface(surface)), tolerance_(tolerance) {}
  ~GlobalSurfaceWorker() override { freeSurf(surface_); }
  void Query(const double* point, PeerAnswer* answer) override {
    double p[3] = {point[0], point[1], point[2]};
    int numPoints = 0, numCurves = 0, status = 0;
    double* params = nullptr;
    SISLIntcurve** curves = nullptr;
    s1954(surface_, p, 3, kComputationalResolution, tolerance_, &numPoints, &params, &numCurves, &curves, &status);
    double best = std::numeric_limits<double>::infinity();
    if (status >= 0) {
      for (int i = 0; i < numPoints; ++i) best = std::min(best, SurfaceDistance(surface_, p, params + 2 * i));
      // A continuum of closest points (a circle of the torus seen from its
      // axis) comes back as curves: any of their points will do.
      for (int c = 0; c < numCurves; ++c) {
        if (curves[c]->ipoint > 0) best = std::min(best, SurfaceDistance(surface_, p, curves[c]->epar1));
      }
    }
    answer->failed = !std::isfinite(best);
    answer->distance = best;
    if (params) free(params);
    if (curves) freeIntcrvlist(curves, numCurves);
  }

 private:
  SISLSurf* surface_;
  double tolerance_;
};

/// s1958: a Newton solve from SISL's own guess (the closest control point's
/// parameters, s1960), compared with local solves on the four edge curves.
class LocalSurfaceWorker : public PeerWorker {
 public:
  LocalSurfaceWorker(SISLSurf* surface, double tolerance) : surface_(copySurface(surface)), tolerance_(tolerance) {}
  ~LocalSurfaceWorker() override { freeSurf(surface_); }
  void Query(const double* point, PeerAnswer* answer) override {
    double p[3] = {point[0], point[1], point[2]};
    double uv[2] = {0, 0}, distance = 0.0;
    int status = 0;
    s1958(surface_, p, 3, kComputationalResolution, tolerance_, uv, &distance, &status);
    answer->failed = status < 0;
    // The distance of the returned parameters, by the same evaluator as s1954.
    answer->distance = answer->failed ? std::numeric_limits<double>::quiet_NaN() : SurfaceDistance(surface_, p, uv);
  }

 private:
  SISLSurf* surface_;
  double tolerance_;
};

/// s1953 on a planar curve: every closest point, the nearest returned.
class GlobalCurveWorker : public PeerWorker {
 public:
  GlobalCurveWorker(SISLCurve* curve, double tolerance) : curve_(copyCurve(curve)), tolerance_(tolerance) {}
  ~GlobalCurveWorker() override { freeCurve(curve_); }
  void Query(const double* point, PeerAnswer* answer) override {
    double p[2] = {point[0], point[1]};
    int numPoints = 0, numCurves = 0, status = 0;
    double* params = nullptr;
    SISLIntcurve** curves = nullptr;
    s1953(curve_, p, 2, kComputationalResolution, tolerance_, &numPoints, &params, &numCurves, &curves, &status);
    double best = std::numeric_limits<double>::infinity();
    if (status >= 0) {
      for (int i = 0; i < numPoints; ++i) best = std::min(best, Distance2D(p, params[i]));
      for (int c = 0; c < numCurves; ++c) {
        if (curves[c]->ipoint > 0) best = std::min(best, Distance2D(p, curves[c]->epar1[0]));
      }
    }
    answer->failed = !std::isfinite(best);
    answer->distance = best;
    if (params) free(params);
    if (curves) freeIntcrvlist(curves, numCurves);
  }

 private:
  double Distance2D(const double* p, double t) {
    double x[2];
    int left = 0, status = 0;
    s1221(curve_, 0, t, &left, x, &status);
    return status < 0 ? std::numeric_limits<double>::quiet_NaN() : Distance(x, p, 2);
  }
  SISLCurve* curve_;
  double tolerance_;
};

/// Which SISL call a SurfaceMethod runs.
enum class SurfaceCall { Global1954, Local1958 };

class SurfaceMethod : public PeerMethod {
 public:
  SurfaceMethod(const Patch& patch, SurfaceCall call, double tolerance)
      : surface_(ToSislSurface(patch)), call_(call), tolerance_(tolerance) {}
  ~SurfaceMethod() override { freeSurf(surface_); }
  std::string name() const override {
    return call_ == SurfaceCall::Global1954 ? "SISL s1954 (global)" : "SISL s1958 (local)";
  }
  // Each worker owns a copy of the surface because s1954 caches boxes and
  // directions in the SISLSurf; the harness counts threaded answers that
  // differ from the 1-thread ones, which would reveal other shared state.
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override {
    if (call_ == SurfaceCall::Global1954) return std::make_unique<GlobalSurfaceWorker>(surface_, tolerance_);
    return std::make_unique<LocalSurfaceWorker>(surface_, tolerance_);
  }
  std::string note() const override {
    return call_ == SurfaceCall::Global1954 ? "aepsge = 1e-9 x size"
                                            : "aepsge = 1e-9 x size; SISL's own start (nearest control point, s1960) "
                                              "and local solves on the four edges (s1957)";
  }

 private:
  SISLSurf* surface_;
  SurfaceCall call_;
  double tolerance_;
};

class CurveMethod : public PeerMethod {
 public:
  CurveMethod(const Patch& patch, double tolerance) : tolerance_(tolerance) {
    std::vector<double> coef = SislCoefficients(patch, 2);
    std::vector<double> knots = patch.knots[0];
    curve_ = newCurve(patch.counts[0], patch.degrees[0] + 1, knots.data(), coef.data(), patch.weights.empty() ? 1 : 2,
                      2, 1);
  }
  ~CurveMethod() override { freeCurve(curve_); }
  std::string name() const override { return "SISL s1953 (global, curve)"; }
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override { return std::make_unique<GlobalCurveWorker>(curve_, tolerance_); }
  std::string note() const override { return "aepsge = 1e-9 x size"; }

 private:
  SISLCurve* curve_ = nullptr;
  double tolerance_;
};


}  // namespace

std::string SislVersion() { return std::string("SISL ") + INVMAP_SISL_VERSION; }

PeerList MakeSislPeers(const GeometryCase& geometryCase) {
  PeerList peers;
  const Patch& patch = geometryCase.geometry.patches[0];
  if (geometryCase.kind == CaseKind::SplineSurface) {
    const double tolerance = 1e-9 * ControlBoxSize(patch, 3);
    for (SurfaceCall call : {SurfaceCall::Global1954, SurfaceCall::Local1958}) {
      peers.push_back([&patch, call, tolerance] { return std::make_unique<SurfaceMethod>(patch, call, tolerance); });
    }
  } else if (geometryCase.kind == CaseKind::SplineCurve) {
    const double tolerance = 1e-9 * ControlBoxSize(patch, 2);
    peers.push_back([&patch, tolerance] { return std::make_unique<CurveMethod>(patch, tolerance); });
  }
  return peers;
}

}  // namespace invmap::bench
