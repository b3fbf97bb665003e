#include "engine/trimmed_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "engine/bezier_extraction.h"
#include "engine/bezier_nets.h"
#include "kernels/cell_map.h"
#include "kernels/own_parameter.h"
#include "kernels/trimmed_cell.h"

namespace invmap::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

BSplinePatch AsBSpline(const SplineCurve& curve, int dim) {
  BSplinePatch spline;
  spline.ambientDim = dim;
  spline.degrees = {curve.degree};
  spline.knots = {curve.knots};
  spline.counts = {static_cast<int>(curve.points.size() / dim)};
  spline.controlPoints = curve.points;
  spline.weights = curve.weights;
  return spline;
}

/// The Bezier pieces of a valid 2D curve of any degree up to
/// TrimRegion::kMaxPieceDegree, one per knot span of positive length: piece
/// control points by blossoming the span's de Boor points at (lo^(p - j),
/// hi^j), in homogeneous coordinates.
struct BezierPieces {
  int degree = 0;
  std::vector<double> lo, hi;    // each piece's knot range
  std::vector<double> points;    // (degree + 1) * 2 per piece
  std::vector<double> weights;   // (degree + 1) per piece, empty when polynomial
};

BezierPieces SplitIntoBezier(const SplineCurve& curve) {
  BezierPieces pieces;
  const int p = curve.degree;
  const int n = static_cast<int>(curve.points.size() / 2);
  const std::vector<double>& u = curve.knots;
  const bool rational = !curve.weights.empty();
  pieces.degree = p;
  double d[kernels::TrimRegion::kMaxPieceDegree + 1][3];
  for (int i = p; i < n; ++i) {
    if (!(u[i + 1] > u[i])) continue;
    pieces.lo.push_back(u[i]);
    pieces.hi.push_back(u[i + 1]);
    for (int j = 0; j <= p; ++j) {
      for (int k = 0; k <= p; ++k) {
        const int c = i - p + k;
        const double w = rational ? curve.weights[c] : 1.0;
        d[k][0] = w * curve.points[2 * c];
        d[k][1] = w * curve.points[2 * c + 1];
        d[k][2] = w;
      }
      for (int r = 1; r <= p; ++r) {
        const double a = r <= p - j ? u[i] : u[i + 1];
        for (int k = p; k >= r; --k) {
          const double left = u[i - p + k], right = u[i + k + 1 - r];
          const double alpha = (a - left) / (right - left);
          for (int m = 0; m < 3; ++m) d[k][m] = (1.0 - alpha) * d[k - 1][m] + alpha * d[k][m];
        }
      }
      pieces.points.push_back(d[p][0] / d[p][2]);
      pieces.points.push_back(d[p][1] / d[p][2]);
      if (rational) pieces.weights.push_back(d[p][2]);
    }
  }
  return pieces;
}

/// Adds the Bezier pieces of one curve to `region`, preceded by a straight
/// segment from *end (the previous curve's end) when it starts elsewhere;
/// *end becomes the curve's end. The loop's first piece sets `start`.
void AddCurvePieces(const SplineCurve& curve, kernels::TrimRegion* region, bool* haveEnd, double* end,
                    double* start) {
  const BezierPieces pieces = SplitIntoBezier(curve);
  const int n = pieces.degree + 1;
  for (std::size_t c = 0; c < pieces.lo.size(); ++c) {
    const double* uv = pieces.points.data() + c * n * 2;
    if (!*haveEnd) {
      start[0] = uv[0];
      start[1] = uv[1];
    } else if (end[0] != uv[0] || end[1] != uv[1]) {
      const double gap[4] = {end[0], end[1], uv[0], uv[1]};
      region->AddPiece(1, gap, nullptr);
    }
    region->AddPiece(pieces.degree, uv, pieces.weights.empty() ? nullptr : pieces.weights.data() + c * n);
    end[0] = uv[2 * (n - 1)];
    end[1] = uv[2 * (n - 1) + 1];
    *haveEnd = true;
  }
}

/// Appends the closed loops of `loops` to `region` (their curves' Bezier
/// pieces, with a straight segment across each gap between consecutive
/// curves) and finishes it.
void BuildTrimRegion(const std::vector<std::vector<SplineCurve>>& loops, kernels::TrimRegion* region) {
  for (const std::vector<SplineCurve>& loop : loops) {
    bool haveEnd = false;
    double end[2] = {0, 0}, start[2] = {0, 0};
    for (const SplineCurve& curve : loop) AddCurvePieces(curve, region, &haveEnd, end, start);
    if (haveEnd && (end[0] != start[0] || end[1] != start[1])) {
      const double gap[4] = {end[0], end[1], start[0], start[1]};
      region->AddPiece(1, gap, nullptr);
    }
  }
  region->Finish();
}

double Dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The diagonal of the box of the patch's control points.
double PatchSize(const Patch& patch) {
  double lo[3] = {kNaN, kNaN, kNaN}, hi[3] = {kNaN, kNaN, kNaN};
  for (std::size_t i = 0; i + 2 < patch.points.size(); i += 3) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = i == 0 ? patch.points[i + k] : std::min(lo[k], patch.points[i + k]);
      hi[k] = i == 0 ? patch.points[i + k] : std::max(hi[k], patch.points[i + k]);
    }
  }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/// True when cell `cell` of `nets` (whose box of own parameters `analytic`
/// holds) is `surface` there: the two within `tolerance` at the corners,
/// the middle and a few points between.
bool AgreesWithCell(const BezierNets& nets, std::int64_t cell, const kernels::AnalyticCell& analytic,
                    double tolerance) {
  const kernels::AnalyticSurface& surface = *analytic.surface;
  const kernels::CellView view = nets.View(cell);
  constexpr double kSamples[][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.5, 0.5}, {0.25, 0.7}, {0.8, 0.3}};
  for (const auto& ref : kSamples) {
    kernels::MapJet jet;
    kernels::EvaluateMap(view, ref, kernels::JetOrder::Value, &jet);
    double own[2], xyz[3];
    for (int d = 0; d < 2; ++d) {
      own[d] = kernels::OwnParameter(analytic.paramLo[d], analytic.paramScale[d], analytic.angular[d], ref[d]);
    }
    surface.Evaluate(own[0], own[1], xyz);
    if (!(std::hypot(xyz[0] - jet.x[0], xyz[1] - jet.x[1], xyz[2] - jet.x[2]) <= tolerance)) return false;
  }
  return true;
}

}  // namespace

std::unique_ptr<kernels::AnalyticSurface> AnalyticSurfaceOf(const Patch& patch) {
  using Kind = AnalyticSurface::Kind;
  const AnalyticSurface& in = patch.analytic;
  if (in.kind == Kind::None) return nullptr;
  auto out = std::make_unique<kernels::AnalyticSurface>();
  const double* axes[3] = {in.xAxis, in.yAxis, in.axis};
  double* outAxes[3] = {out->x, out->y, out->z};
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      const double expected = a == b ? 1.0 : 0.0;
      if (!(std::abs(Dot(axes[a], axes[b]) - expected) <= 1e-12)) return nullptr;
    }
    std::copy(axes[a], axes[a] + 3, outAxes[a]);
  }
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(in.origin[k])) return nullptr;
    out->origin[k] = in.origin[k];
  }
  out->radius = in.radius;
  out->minorRadius = in.minorRadius;
  const bool finite = std::isfinite(in.radius) && std::isfinite(in.minorRadius);
  using Out = kernels::AnalyticSurface::Kind;
  switch (in.kind) {
    case Kind::None:
      return nullptr;
    case Kind::Plane:
      out->kind = Out::Plane;
      return out;
    case Kind::Cylinder:
    case Kind::Sphere:
      out->kind = in.kind == Kind::Cylinder ? Out::Cylinder : Out::Sphere;
      return finite && in.radius > 0.0 ? std::move(out) : nullptr;
    case Kind::Cone:
      out->kind = Out::Cone;
      out->sinAngle = std::sin(in.semiAngle);
      out->cosAngle = std::cos(in.semiAngle);
      return finite && in.radius >= 0.0 && std::abs(in.semiAngle) < 0.5 * M_PI ? std::move(out) : nullptr;
    case Kind::Torus:
      // A spindle or horn torus too: its cells that reach the axis keep
      // their NURBS search (kernels::ClosedFormCovers).
      out->kind = Out::Torus;
      return finite && in.minorRadius > 0.0 && in.radius >= 0.0 ? std::move(out) : nullptr;
  }
  return nullptr;
}

EdgeParameters::EdgeParameters(const SplineCurve& pcurve) {
  if (pcurve.points.empty()) return;
  angular_ = pcurve.angular;
  BezierPieces pieces = SplitIntoBezier(pcurve);
  degree_ = pieces.degree;
  spanLo_ = std::move(pieces.lo);
  spanHi_ = std::move(pieces.hi);
  points_ = std::move(pieces.points);
  weights_ = std::move(pieces.weights);
}

void EdgeParameters::At(double own, double* uv) const {
  if (spanLo_.empty() || !std::isfinite(own)) {
    uv[0] = uv[1] = kNaN;
    return;
  }
  // The piece whose knot range holds `own` (angular ranges are angles too).
  const std::size_t piece =
      std::min<std::size_t>(std::upper_bound(spanLo_.begin(), spanLo_.end(), own) - spanLo_.begin(), spanLo_.size()) -
      (own >= spanLo_.front() ? 1 : 0);
  const double lo = spanLo_[piece], scale = spanHi_[piece] - spanLo_[piece];
  const double w = kernels::ReferenceOfOwn(lo, scale, angular_, own);
  // de Casteljau on the homogeneous control points.
  const int n = degree_ + 1;
  double h[3 * (kernels::TrimRegion::kMaxPieceDegree + 1)];
  for (int i = 0; i < n; ++i) {
    const double weight = weights_.empty() ? 1.0 : weights_[piece * n + i];
    h[3 * i] = weight * points_[(piece * n + i) * 2];
    h[3 * i + 1] = weight * points_[(piece * n + i) * 2 + 1];
    h[3 * i + 2] = weight;
  }
  for (int level = 1; level < n; ++level) {
    for (int i = 0; i < n - level; ++i) {
      for (int k = 0; k < 3; ++k) h[3 * i + k] = (1.0 - w) * h[3 * i + k] + w * h[3 * (i + 1) + k];
    }
  }
  uv[0] = h[0] / h[2];
  uv[1] = h[1] / h[2];
}

std::size_t EdgeParameters::MemoryBytes() const {
  return (spanLo_.capacity() + spanHi_.capacity() + points_.capacity() + weights_.capacity()) * sizeof(double);
}

std::size_t TrimmedFaces::MemoryBytes() const {
  std::size_t bytes = regions.capacity() * sizeof(regions[0]) + crossingCells.capacity() * sizeof(crossingCells[0]) +
                      edges.capacity() * sizeof(EdgeParameters) + spanCells.capacity() * sizeof(spanCells[0]);
  for (const auto& region : regions) bytes += sizeof(kernels::TrimRegion) + region->MemoryBytes();
  for (const auto& [cell, trim] : crossingCells) bytes += sizeof(kernels::TrimmedCell) + trim->near.MemoryBytes();
  for (const EdgeParameters& edge : edges) bytes += edge.MemoryBytes();
  for (const std::vector<std::int64_t>& spans : spanCells) bytes += spans.capacity() * sizeof(std::int64_t);
  bytes += analyticSurfaces.size() * sizeof(kernels::AnalyticSurface) +
           analyticCells.capacity() * sizeof(analyticCells[0]) + analyticSurfaces.capacity() * sizeof(void*);
  return bytes;
}

void AddTrimmedSurfaceCells(const Patch& patch, std::size_t p, BezierNets* nets) {
  const int dim = nets->dimension;
  TrimmedFaces& faces = nets->trimmed;
  faces.spanCells.resize(nets->numPatches);
  const bool angular[2] = {patch.angular.size() == 2 && patch.angular[0] != 0,
                           patch.angular.size() == 2 && patch.angular[1] != 0};

  auto region = std::make_unique<kernels::TrimRegion>();
  BuildTrimRegion(patch.trimLoops, region.get());
  std::unique_ptr<kernels::AnalyticSurface> analytic = AnalyticSurfaceOf(patch);
  const double agreement = 1e-9 * PatchSize(patch);
  std::vector<std::pair<std::int64_t, kernels::AnalyticCell>> analyticCells;
  const bool trimmed = region->numPieces() > 0;

  // The surface's cells: those wholly outside the region are left out,
  // those wholly inside are plain cells, the others search within it.
  const ExtractedCells cells = ExtractBezierCells(SplineOf(patch, dim));
  const kernels::CellShape shape(cells.type, cells.degrees);
  nets->splineSpans[p] = cells.spans;
  std::vector<std::int64_t>& spanCells = faces.spanCells[p];
  spanCells.assign(static_cast<std::size_t>(cells.numCells), -1);
  CellOrigin origin;
  origin.patch = static_cast<std::int32_t>(p);
  origin.sharedParameters = true;
  origin.angular = static_cast<std::uint8_t>((angular[0] ? 1 : 0) | (angular[1] ? 2 : 0));
  for (int c = 0; c < cells.numCells; ++c) {
    double lo[2], hi[2];
    for (int d = 0; d < 2; ++d) {
      lo[d] = cells.spanLo[2 * c + d];
      hi[d] = cells.spanHi[2 * c + d];
      origin.paramLo[d] = lo[d];
      origin.paramScale[d] = hi[d] - lo[d];
    }
    // A cell's own box is its knot box: angular knots are the arcs' angles.
    kernels::TrimPieces near;
    kernels::TrimRegion::Side side = kernels::TrimRegion::Side::Inside;
    if (trimmed) {
      near = region->PiecesFor(lo, hi);
      side = region->ClassifyBox(lo, hi, near);
    }
    if (side == kernels::TrimRegion::Side::Outside) continue;
    origin.indexInPatch = c;
    origin.span = {c % cells.spans[0], c / cells.spans[0], 0};
    const std::int64_t cell = nets->size();
    const std::size_t first = static_cast<std::size_t>(c) * cells.pointsPerCell;
    nets->Add(shape, cells.points.data() + first * dim, cells.weights.empty() ? nullptr : cells.weights.data() + first,
              origin);
    spanCells[c] = cell;
    kernels::AnalyticCell onSurface;
    if (analytic) {
      onSurface.surface = analytic.get();
      for (int d = 0; d < 2; ++d) {
        onSurface.paramLo[d] = origin.paramLo[d];
        onSurface.paramScale[d] = origin.paramScale[d];
        onSurface.angular[d] = angular[d];
      }
      if (!AgreesWithCell(*nets, cell, onSurface, agreement)) analytic.reset();
    }
    if (side == kernels::TrimRegion::Side::Crossing) {
      auto trim = std::make_unique<kernels::TrimmedCell>();
      onSurface.trim = trim.get();
      trim->region = region.get();
      for (int d = 0; d < 2; ++d) {
        trim->paramLo[d] = origin.paramLo[d];
        trim->paramScale[d] = origin.paramScale[d];
        trim->angular[d] = angular[d];
      }
      trim->near = std::move(near);
      faces.crossingCells.emplace_back(cell, std::move(trim));
    }
    if (analytic && kernels::ClosedFormCovers(onSurface)) analyticCells.emplace_back(cell, onSurface);
  }
  faces.regions.push_back(std::move(region));
  if (analytic) {
    faces.analyticCells.insert(faces.analyticCells.end(), analyticCells.begin(), analyticCells.end());
    faces.analyticSurfaces.push_back(std::move(analytic));
  }

  // The edges: curve cells, numbered on after the surface's spans.
  std::int64_t next = cells.numCells;
  for (const PatchEdge& edge : patch.edges) {
    const ExtractedCells curve = ExtractBezierCells(AsBSpline(edge.curve, dim));
    const kernels::CellShape curveShape(curve.type, curve.degrees);
    CellOrigin edgeOrigin;
    edgeOrigin.patch = static_cast<std::int32_t>(p);
    edgeOrigin.angular = edge.curve.angular ? 1 : 0;
    edgeOrigin.edge = static_cast<std::int32_t>(faces.edges.size());
    faces.edges.emplace_back(edge.pcurve);
    for (int c = 0; c < curve.numCells; ++c) {
      edgeOrigin.indexInPatch = next++;
      edgeOrigin.paramLo[0] = curve.spanLo[c];
      edgeOrigin.paramScale[0] = curve.spanHi[c] - curve.spanLo[c];
      const std::size_t first = static_cast<std::size_t>(c) * curve.pointsPerCell;
      nets->Add(curveShape, curve.points.data() + first * dim,
                curve.weights.empty() ? nullptr : curve.weights.data() + first, edgeOrigin);
    }
  }
}

}  // namespace invmap::engine
