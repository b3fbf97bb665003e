// The public API of include/invmap/pou.h.
#include <cmath>
#include <exception>
#include <map>
#include <new>
#include <tuple>

#include "invmap/pou.h"
#include "pou/chart_maps.h"
#include "pou/pou_surface.h"

namespace invmap {

std::string BuildPouManifold(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                             std::int64_t numTriangles, const PouOptions& options, Patch* out) {
  try {
    if (options.degree < 0 || options.degree > 8) {
      return "degree: " + std::to_string(options.degree) + ", expected 1 to 8 (or 0 for automatic)";
    }
    const pou::BaseKind base = options.base == PouBase::Flat          ? pou::BaseKind::Flat
                               : options.base == PouBase::PnTriangles ? pou::BaseKind::PnTriangles
                                                                      : pou::BaseKind::Loop;
    pou::PouSurface surface;
    if (std::string e = surface.Build(xyz, numVertices, triangles, numTriangles, base, options.degree); !e.empty()) {
      return e;
    }
    Patch patch;
    patch.kind = Patch::Kind::PouManifold;
    patch.cell = CellType::Tri;
    patch.points = surface.mesh().positions();
    patch.cells = surface.mesh().triangles();
    patch.degrees = surface.degrees();
    patch.chartControlPoints = surface.nets();
    *out = std::move(patch);
    return {};
  } catch (const std::bad_alloc&) {
    return "out of memory while building the surface";
  } catch (const std::exception& e) {
    return std::string("building the surface failed: ") + e.what();
  }
}

struct PouCharts::Impl {
  pou::PouSurface surface;
};

PouCharts::PouCharts() = default;
PouCharts::~PouCharts() = default;
PouCharts::PouCharts(PouCharts&&) noexcept = default;
PouCharts& PouCharts::operator=(PouCharts&&) noexcept = default;

std::string PouCharts::Create(const Patch& patch, PouCharts* out) {
  try {
    if (patch.kind != Patch::Kind::PouManifold) return "the patch is not a pou_manifold";
    if (patch.points.size() % 3 != 0) return "vertices: coordinate count not a multiple of 3";
    if (patch.cells.size() % 3 != 0) return "cells: index count not a multiple of 3 (triangles)";
    auto impl = std::make_unique<Impl>();
    if (std::string e = impl->surface.Restore(patch.points, patch.cells, patch.degrees, patch.chartControlPoints);
        !e.empty()) {
      return e;
    }
    out->impl_ = std::move(impl);
    return {};
  } catch (const std::bad_alloc&) {
    return "out of memory while reading the surface";
  }
}

std::int64_t PouCharts::NumCharts() const { return impl_ ? impl_->surface.numCharts() : 0; }
int PouCharts::Valence(std::int64_t chart) const { return impl_->surface.valence(chart); }
double PouCharts::Radius(std::int64_t chart) const { return impl_->surface.radius(chart); }

bool PouCharts::Evaluate(std::int64_t chart, double u, double v, ChartJet* out) const {
  if (!impl_ || chart < 0 || chart >= NumCharts() || !(std::hypot(u, v) < Radius(chart))) return false;
  const pou::ThetaJet jet = impl_->surface.Evaluate(chart, u, v);
  for (int c = 0; c < 3; ++c) {
    const pou::Jet<double>& j = jet.x[c];
    out->point[c] = j.v;
    out->du[c] = j.du;
    out->dv[c] = j.dv;
    out->duu[c] = j.duu;
    out->duv[c] = j.duv;
    out->dvv[c] = j.dvv;
  }
  return true;
}

void PouCharts::Tessellate(int resolution, std::vector<double>* xyz, std::vector<std::int64_t>* triangles) const {
  xyz->clear();
  triangles->clear();
  if (!impl_ || resolution < 1) return;
  const pou::PouSurface& s = impl_->surface;
  const pou::ClosedMesh& mesh = s.mesh();
  const int n = resolution;
  // Shared samples: mesh vertices, points inside edges (keyed by the edge's
  // ends in increasing order and the step from the lower one), then points
  // inside triangles.
  std::map<std::tuple<std::int64_t, std::int64_t, int>, std::int64_t> edgePoints;
  std::vector<std::int64_t> vertexPoint(mesh.numVertices(), -1);
  const auto evaluate = [&](std::int64_t t, const double bary[3]) {
    // Through the chart of the triangle's corner with the largest coordinate.
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (bary[i] > bary[k]) k = i;
    const std::int64_t v = mesh.triangles()[3 * t + k];
    int sector = 0;
    while (mesh.starTriangle(v, sector) != t) ++sector;
    const double lu = bary[(k + 1) % 3], lw = bary[(k + 2) % 3];
    const double cx = lu + 0.5 * lw, cy = pou::kFrameRadius * lw;
    double p[3];
    if (cx == 0.0 && cy == 0.0) {
      s.EvaluatePoint(v, 0.0, 0.0, p);
    } else {
      const pou::JetPoint<double> c{pou::Jet<double>::Constant(cx), pou::Jet<double>::Constant(cy)};
      const pou::JetPoint<double> q = pou::FromFrame(s.valence(v), sector, c);
      s.EvaluatePoint(v, q.x.v, q.y.v, p);
    }
    xyz->insert(xyz->end(), p, p + 3);
    return static_cast<std::int64_t>(xyz->size() / 3 - 1);
  };
  for (std::int64_t t = 0; t < mesh.numTriangles(); ++t) {
    const std::int64_t* corner = &mesh.triangles()[3 * t];
    // Index of lattice point (i, j): bary (n - i - j, i, j) / n.
    std::vector<std::int64_t> index((n + 1) * (n + 1), -1);
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i + j <= n; ++i) {
        const int a[3] = {n - i - j, i, j};
        const double bary[3] = {double(a[0]) / n, double(a[1]) / n, double(a[2]) / n};
        int zeros = 0, at = -1;
        for (int c = 0; c < 3; ++c) {
          if (a[c] == 0) ++zeros;
          if (a[c] == n) at = c;
        }
        std::int64_t id;
        if (at >= 0) {
          std::int64_t& shared = vertexPoint[corner[at]];
          if (shared < 0) shared = evaluate(t, bary);
          id = shared;
        } else if (zeros == 1) {
          int e0 = 0;
          while (a[e0] == 0 || a[(e0 + 1) % 3] == 0) ++e0;  // the edge (e0, e0 + 1) holds the point
          const int e1 = (e0 + 1) % 3;
          const bool lowFirst = corner[e0] < corner[e1];
          const std::int64_t lo = lowFirst ? corner[e0] : corner[e1], hi = lowFirst ? corner[e1] : corner[e0];
          const int fromLow = lowFirst ? a[e1] : a[e0];
          const auto key = std::make_tuple(lo, hi, fromLow);
          const auto found = edgePoints.find(key);
          id = found != edgePoints.end() ? found->second : (edgePoints[key] = evaluate(t, bary));
        } else {
          id = evaluate(t, bary);
        }
        index[i + (n + 1) * j] = id;
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i + j < n; ++i) {
        const std::int64_t a = index[i + (n + 1) * j], b = index[i + 1 + (n + 1) * j], c = index[i + (n + 1) * (j + 1)];
        triangles->insert(triangles->end(), {a, b, c});
        if (i + j + 1 < n) {
          const std::int64_t d = index[i + 1 + (n + 1) * (j + 1)];
          triangles->insert(triangles->end(), {b, d, c});
        }
      }
    }
  }
}

}  // namespace invmap
