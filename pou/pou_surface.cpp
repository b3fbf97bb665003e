#include "pou/pou_surface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "common/parallel.h"
#include "pou/blend.h"
#include "pou/bump.h"
#include "pou/chart_maps.h"

namespace invmap::pou {
namespace {

ShapeDerivatives<double> ShapeAt(const ShapeNet& net, double x, double y) {
  const ShapeJet s = EvaluateShape(net, x, y);
  ShapeDerivatives<double> d;
  for (int c = 0; c < 3; ++c) {
    d.value[c] = s.value[c];
    d.grad[c][0] = s.grad[c][0];
    d.grad[c][1] = s.grad[c][1];
    for (int h = 0; h < 3; ++h) d.hess[c][h] = s.hess[c][h];
  }
  return d;
}

/// The sector (star triangle) of a chart of valence n that holds the
/// direction of (x, y).
int SectorOf(int n, double x, double y) {
  double a = std::atan2(y, x);
  if (a < 0) a += 2.0 * kPi;
  const int s = static_cast<int>(std::floor(a / (2.0 * kPi / n)));
  return ((s % n) + n) % n;
}

}  // namespace

std::string PouSurface::Build(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                              std::int64_t numTriangles, BaseKind base, int degree) {
  if (std::string e = mesh_.Build(xyz, numVertices, triangles, numTriangles); !e.empty()) return e;
  const std::unique_ptr<BaseSurface> surface = MakeBaseSurface(base, mesh_);
  return FitCharts(*surface, degree);
}

std::string PouSurface::Restore(const std::vector<double>& xyz, const std::vector<std::int64_t>& triangles,
                                const std::vector<int>& degrees, const std::vector<double>& nets) {
  const std::int64_t nv = static_cast<std::int64_t>(xyz.size() / 3);
  if (std::string e = mesh_.Build(xyz.data(), nv, triangles.data(), static_cast<std::int64_t>(triangles.size() / 3));
      !e.empty()) {
    return e;
  }
  if (static_cast<std::int64_t>(degrees.size()) != nv) {
    return "degrees: " + std::to_string(degrees.size()) + " values, expected one per vertex (" + std::to_string(nv) +
           ")";
  }
  degree_ = degrees;
  radius_.resize(nv);
  netOffset_.resize(nv + 1);
  netOffset_[0] = 0;
  for (std::int64_t v = 0; v < nv; ++v) {
    if (degrees[v] < 1 || degrees[v] > kMaxChartDegree) {
      return "degrees[" + std::to_string(v) + "]: " + std::to_string(degrees[v]) + ", expected 1 to " +
             std::to_string(kMaxChartDegree);
    }
    radius_[v] = DomainRadius(mesh_.valence(v));
    netOffset_[v + 1] = netOffset_[v] + 3 * (degrees[v] + 1) * (degrees[v] + 1);
  }
  if (static_cast<std::int64_t>(nets.size()) != netOffset_[nv]) {
    return "chart_control_points: " + std::to_string(nets.size() / 3) + " points, expected " +
           std::to_string(netOffset_[nv] / 3) + " ((degree + 1)^2 per vertex)";
  }
  for (std::size_t i = 0; i < nets.size(); ++i) {
    if (!std::isfinite(nets[i])) return "chart_control_points: a coordinate is not finite";
  }
  nets_ = nets;
  ComputeBounds();
  return {};
}

void PouSurface::ComputeBounds() {
  bounds_.resize(numCharts());
  for (std::int64_t v = 0; v < numCharts(); ++v) bounds_[v] = BoundShape(net(v), kShapeBoundExtension);
}

namespace {

/// The samples of every chart of one valence n and degree d, and their fit:
/// a (2 max(d, 2) + 1)^2 grid over [-R, R]^2, kept where the point's
/// canonical image lies in the star, with the sector (star triangle) and the barycentric
/// coordinates (of the vertex, the next neighbour, the one after) of that
/// image in it.
struct SampleGrid {
  std::vector<double> uv;
  std::vector<int> sector;
  std::vector<double> bary;
  ShapeFitter fitter;
  std::string error;

  void Build(int n, int d) {
    const double r = DomainRadius(n);
    // At degree 1 a 3 x 3 grid would keep only the centre and the axes'
    // points once the star no longer holds the square's corners (valence 5
    // and more), where the bilinear twist uv vanishes: 5 x 5 determines it.
    const int steps = 2 * std::max(d, 2);
    for (int j = 0; j <= steps; ++j) {
      for (int i = 0; i <= steps; ++i) {
        const double x = -r + 2.0 * r * i / steps, y = -r + 2.0 * r * j / steps;
        const int s = SectorOf(n, x, y);
        double lu = 0.0, lw = 0.0;
        if (x != 0.0 || y != 0.0) {
          const double a = (std::atan2(y, x) - 2.0 * kPi * s / n) * n / 6.0;
          const double rho = Length(x, y) * kFrameRadius / r;
          const double cx = rho * std::cos(a), cy = rho * std::sin(a);
          lw = std::max(0.0, cy / kFrameRadius);
          lu = std::max(0.0, cx - cy / std::sqrt(3.0));
        }
        const double lv = 1.0 - lu - lw;
        if (lv < -1e-12) continue;
        uv.insert(uv.end(), {x, y});
        sector.push_back(s);
        bary.insert(bary.end(), {std::max(lv, 0.0), lu, lw});
      }
    }
    error = fitter.Factor(d, r, uv);
  }
};

}  // namespace

std::string PouSurface::FitCharts(const BaseSurface& base, int degree) {
  const std::int64_t nv = mesh_.numVertices();
  degree_.resize(nv);
  radius_.resize(nv);
  netOffset_.resize(nv + 1);
  netOffset_[0] = 0;
  std::map<std::pair<int, int>, SampleGrid> grids;
  for (std::int64_t v = 0; v < nv; ++v) {
    degree_[v] = degree > 0 ? degree : AutomaticDegree(mesh_.valence(v));
    radius_[v] = DomainRadius(mesh_.valence(v));
    netOffset_[v + 1] = netOffset_[v] + 3 * (degree_[v] + 1) * (degree_[v] + 1);
    grids[{mesh_.valence(v), degree_[v]}];
  }
  for (auto& [key, grid] : grids) grid.Build(key.first, key.second);
  nets_.assign(netOffset_[nv], 0.0);
  std::vector<std::string> errors(nv);
  ForEachBlock(ExecutionPolicy::Par, nv, 64, [&](std::int64_t begin, std::int64_t end) {
    std::vector<double> xyz, net;
    for (std::int64_t v = begin; v < end; ++v) {
      const int n = mesh_.valence(v);
      const SampleGrid& grid = grids.at({n, degree_[v]});
      if (!grid.error.empty()) {
        errors[v] = "vertex " + std::to_string(v) + " (valence " + std::to_string(n) + "): " + grid.error;
        continue;
      }
      // Each sample's image on the base surface, through its barycentric
      // coordinates in the chart's star triangle.
      xyz.resize(grid.bary.size());
      for (std::size_t i = 0; i < grid.sector.size(); ++i) {
        const std::int64_t t = mesh_.starTriangle(v, grid.sector[i]);
        const int k = mesh_.CornerOf(t, v);
        double bary[3];
        for (int c = 0; c < 3; ++c) bary[(k + c) % 3] = grid.bary[3 * i + c];
        base.Evaluate(t, bary, &xyz[3 * i]);
      }
      grid.fitter.Solve(xyz, &net);
      std::copy(net.begin(), net.end(), nets_.begin() + netOffset_[v]);
    }
  });
  for (const std::string& e : errors) {
    if (!e.empty()) return e;
  }
  ComputeBounds();
  return {};
}

void PouSurface::EvaluateParts(std::int64_t chart, double u, double v, BlendParts* parts) const {
  const int n = mesh_.valence(chart);
  const double r = radius_[chart];
  const JetPoint<double> p{Jet<double>::Variable(u, 0), Jet<double>::Variable(v, 1)};
  ComposeShape(ShapeAt(net(chart), u, v), p, parts->own);
  const bool centre = u == 0.0 && v == 0.0;
  // gamma_v = xi(|p| / R) is 1 inside R / 4 (and |p| has no derivative at 0).
  parts->ownWeight = Length(u, v) < kBumpInner * r ? Jet<double>::Constant(1.0)
                                                       : JetBump((1.0 / r) * JetSqrt(p.x * p.x + p.y * p.y));
  const std::size_t count = parts->edges.size();
  parts->defined.assign(count, 0);
  parts->weights.assign(count, Jet<double>());
  parts->shapes.resize(3 * count);
  for (std::size_t i = 0; i < count && !centre; ++i) {
    if (!parts->active.empty() && !parts->active[i]) continue;
    const int edge = parts->edges[i];
    Jet<double> angle, distance;
    const JetPoint<double> frame = ToFrame(n, ToEdgeDirection(n, edge, p), &angle, &distance);
    const JetPoint<double> other = HalfTurn(frame);
    if (!(std::fabs(angle.v) < FormulaAngle(n)) || !(other.x.v > 0.0)) continue;
    parts->defined[i] = 1;
    const Jet<double> otherDistance = JetSqrt(other.x * other.x + other.y * other.y);
    if (otherDistance.v < kFrameRadius) parts->weights[i] = JetBump((1.0 / kFrameRadius) * otherDistance);
    const std::int64_t z = mesh_.neighbor(chart, edge);
    const JetPoint<double> q = FromFrame(mesh_.valence(z), mesh_.mate(chart, edge), other);
    ComposeShape(ShapeAt(net(z), q.x.v, q.y.v), q, &parts->shapes[3 * i]);
  }
}

ThetaJet BlendParts::Theta() const {
  std::vector<Contribution<double>> others;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!(weights[i].v > 0.0)) continue;
    Contribution<double> c;
    c.weight = weights[i];
    for (int k = 0; k < 3; ++k) c.point[k] = shapes[3 * i + k];
    others.push_back(c);
  }
  ThetaJet out;
  Blend(ownWeight, own, others.data(), static_cast<int>(others.size()), out.x);
  return out;
}

ThetaJet PouSurface::Evaluate(std::int64_t chart, double u, double v) const {
  const int n = mesh_.valence(chart);
  const double r = radius_[chart];
  const JetPoint<double> p{Jet<double>::Variable(u, 0), Jet<double>::Variable(v, 1)};
  ThetaJet out;
  Jet<double> own[3];
  ComposeShape(ShapeAt(net(chart), u, v), p, own);
  if (Length(u, v) < kOwnOnly * r) {
    for (int c = 0; c < 3; ++c) out.x[c] = own[c];
    return out;
  }
  const Jet<double> ownWeight = JetBump((1.0 / r) * JetSqrt(p.x * p.x + p.y * p.y));
  Contribution<double> others[2];
  int count = 0;
  const int sector = SectorOf(n, u, v);
  for (int edge : {sector, (sector + 1) % n}) {
    Jet<double> angle, distance;
    const JetPoint<double> frame = ToFrame(n, ToEdgeDirection(n, edge, p), &angle, &distance);
    if (!(std::fabs(angle.v) < 3.0 * kPi / n)) continue;
    const JetPoint<double> other = HalfTurn(frame);
    const Jet<double> otherDistance = JetSqrt(other.x * other.x + other.y * other.y);
    if (!(otherDistance.v < kFrameRadius)) continue;
    const std::int64_t z = mesh_.neighbor(chart, edge);
    const JetPoint<double> q = FromFrame(mesh_.valence(z), mesh_.mate(chart, edge), other);
    Contribution<double>& c = others[count];
    c.weight = JetBump((1.0 / kFrameRadius) * otherDistance);
    if (c.weight.v == 0.0) continue;
    ComposeShape(ShapeAt(net(z), q.x.v, q.y.v), q, c.point);
    ++count;
  }
  Blend(ownWeight, own, others, count, out.x);
  return out;
}

void PouSurface::EvaluatePoint(std::int64_t chart, double u, double v, double out[3]) const {
  // Evaluate's formulas on values alone (the maps' jets carry no derivatives).
  const int n = mesh_.valence(chart);
  const double r = radius_[chart];
  EvaluateShapePoint(net(chart), u, v, out);
  if (Length(u, v) < kOwnOnly * r) return;
  const JetPoint<double> p{Jet<double>::Constant(u), Jet<double>::Constant(v)};
  double total = Bump(Length(u, v) / r).f, weight[2], point[2][3];
  int count = 0;
  const int sector = SectorOf(n, u, v);
  for (int edge : {sector, (sector + 1) % n}) {
    Jet<double> angle, distance;
    const JetPoint<double> frame = ToFrame(n, ToEdgeDirection(n, edge, p), &angle, &distance);
    if (!(std::fabs(angle.v) < 3.0 * kPi / n)) continue;
    const JetPoint<double> other = HalfTurn(frame);
    const double otherDistance = std::sqrt(other.x.v * other.x.v + other.y.v * other.y.v);
    if (!(otherDistance < kFrameRadius)) continue;
    weight[count] = Bump(otherDistance / kFrameRadius).f;
    if (weight[count] == 0.0) continue;
    const std::int64_t z = mesh_.neighbor(chart, edge);
    const JetPoint<double> q = FromFrame(mesh_.valence(z), mesh_.mate(chart, edge), other);
    EvaluateShapePoint(net(z), q.x.v, q.y.v, point[count]);
    total += weight[count];
    ++count;
  }
  double blended[3] = {out[0], out[1], out[2]};
  for (int i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) blended[c] += weight[i] / total * (point[i][c] - out[c]);
  }
  for (int c = 0; c < 3; ++c) out[c] = blended[c];
}

bool PouSurface::Transition(std::int64_t chart, int edge, double x, double y, double* qx, double* qy) const {
  const int n = mesh_.valence(chart);
  if (x == 0.0 && y == 0.0) return false;
  const JetPoint<double> p{Jet<double>::Constant(x), Jet<double>::Constant(y)};
  Jet<double> angle, distance;
  const JetPoint<double> frame = ToFrame(n, ToEdgeDirection(n, edge, p), &angle, &distance);
  if (!(std::fabs(angle.v) < 3.0 * kPi / n)) return false;
  const JetPoint<double> other = HalfTurn(frame);
  if (!(Length(other.x.v, other.y.v) < kFrameRadius) || !(distance.v < kFrameRadius)) return false;
  const std::int64_t z = mesh_.neighbor(chart, edge);
  const JetPoint<double> q = FromFrame(mesh_.valence(z), mesh_.mate(chart, edge), other);
  *qx = q.x.v;
  *qy = q.y.v;
  return true;
}

ChartPoint PouSurface::Owner(std::int64_t chart, double u, double v) const {
  ChartPoint best{chart, u, v};
  const int n = mesh_.valence(chart);
  double bestDistance = Length(u, v) * kFrameRadius / radius_[chart];
  if (bestDistance < 0.5) return best;  // nearer to the vertex than to any neighbour
  const int sector = SectorOf(n, u, v);
  for (int edge : {sector, (sector + 1) % n}) {
    const JetPoint<double> p{Jet<double>::Constant(u), Jet<double>::Constant(v)};
    Jet<double> angle, distance;
    const JetPoint<double> frame = ToFrame(n, ToEdgeDirection(n, edge, p), &angle, &distance);
    const double d = Length(1.0 - frame.x.v, frame.y.v);
    double qx, qy;
    if (d < bestDistance && Transition(chart, edge, u, v, &qx, &qy)) {
      bestDistance = d;
      best = {mesh_.neighbor(chart, edge), qx, qy};
    }
  }
  return best;
}

}  // namespace invmap::pou
