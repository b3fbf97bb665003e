#include "pou/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "common/parallel.h"

namespace invmap::pou {
namespace {

constexpr int kGrid = 4;              // pieces per side of a chart's square
constexpr double kNarrowest = 1e-9;   // share of R below which a box is not split
constexpr int kMaxIterations = 40;
/// Boxes one query's search may enclose before it gives up (the best point
/// found is kept, marked not certified).
constexpr int kBudget = 20000;

/// A box of R^3 that holds chart v's image: the control points of its shape
/// function and of its neighbours' (theta_v is a convex combination of
/// their values at points of their squares).
void ChartHull(const PouSurface& s, std::int64_t v, double lo[3], double hi[3]) {
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::numeric_limits<double>::infinity();
    hi[c] = -std::numeric_limits<double>::infinity();
  }
  const auto add = [&](std::int64_t z) {
    const ShapeNet net = s.net(z);
    const int count = (net.degree + 1) * (net.degree + 1);
    for (int i = 0; i < count; ++i)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], net.points[3 * i + c]);
        hi[c] = std::max(hi[c], net.points[3 * i + c]);
      }
  };
  add(v);
  for (int i = 0; i < s.valence(v); ++i) add(s.mesh().neighbor(v, i));
  for (int c = 0; c < 3; ++c) {
    // The control points' combination is computed in double: widen for it.
    const double pad = 1e-13 * std::max(std::fabs(lo[c]), std::fabs(hi[c]));
    lo[c] -= pad;
    hi[c] += pad;
  }
}

double Clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

ChartBox PieceSquare(const PouSurface& s, std::int64_t chart) {
  const double h = kPieceHalfSide * s.radius(chart);
  return {{-h, -h}, {h, h}};
}

/// A box of R^3 holding theta_v over `box`: the union of the value
/// enclosures of a 4 x 4 grid of cells (the enclosure of a box this wide
/// alone is far looser), intersected with the chart's hull.
void PieceBounds(const PouSurface& s, std::int64_t v, const ChartBox& box, const double hullLo[3],
                 const double hullHi[3], double lo[3], double hi[3]) {
  constexpr int kCells = 4;
  double cellLo[3], cellHi[3];
  for (int c = 0; c < 3; ++c) {
    cellLo[c] = std::numeric_limits<double>::infinity();
    cellHi[c] = -std::numeric_limits<double>::infinity();
  }
  const double hx = (box.hi[0] - box.lo[0]) / kCells, hy = (box.hi[1] - box.lo[1]) / kCells;
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      const ChartBox cell{{box.lo[0] + i * hx, box.lo[1] + j * hy},
                          {i + 1 == kCells ? box.hi[0] : box.lo[0] + (i + 1) * hx,
                           j + 1 == kCells ? box.hi[1] : box.lo[1] + (j + 1) * hy}};
      const ThetaEnclosure e = Enclose(s, v, cell);
      for (int c = 0; c < 3; ++c) {
        cellLo[c] = std::min(cellLo[c], e.x[c].v.lo);
        cellHi[c] = std::max(cellHi[c], e.x[c].v.hi);
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    const bool finite = std::isfinite(cellLo[c]) && std::isfinite(cellHi[c]);
    lo[c] = finite ? std::max(hullLo[c], cellLo[c]) : hullLo[c];
    hi[c] = finite ? std::min(hullHi[c], cellHi[c]) : hullHi[c];
  }
}

}  // namespace

std::vector<SurfacePiece> MakePieces(const PouSurface& surface) {
  const std::int64_t n = surface.numCharts();
  std::vector<SurfacePiece> pieces(n * kGrid * kGrid);
  ForEachBlock(ExecutionPolicy::Par, n, 64, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v) {
      const ChartBox square = PieceSquare(surface, v);
      const double step = (square.hi[0] - square.lo[0]) / kGrid;
      double hullLo[3], hullHi[3];
      ChartHull(surface, v, hullLo, hullHi);
      for (int j = 0; j < kGrid; ++j) {
        for (int i = 0; i < kGrid; ++i) {
          SurfacePiece& piece = pieces[(v * kGrid + j) * kGrid + i];
          piece.chart = v;
          piece.box = {{square.lo[0] + i * step, square.lo[1] + j * step},
                       {i + 1 == kGrid ? square.hi[0] : square.lo[0] + (i + 1) * step,
                        j + 1 == kGrid ? square.hi[1] : square.lo[1] + (j + 1) * step}};
          PieceBounds(surface, v, piece.box, hullLo, hullHi, piece.lo, piece.hi);
        }
      }
    }
  });
  return pieces;
}

void PointSearch::Offer(std::int64_t c, double pu, double pv, const double p[3], double f) {
  const double d = std::sqrt(f);
  if (found && !(d < distance)) return;
  if (!found && !(d <= distance)) return;
  found = true;
  distance = d;
  chart = c;
  u = pu;
  v = pv;
  for (int k = 0; k < 3; ++k) point[k] = p[k];
}

void PointSearch::SolveOnBox(std::int64_t c, const ChartBox& box, double* pu, double* pv, double* f, double grad[2],
                             double p[3]) const {
  double at[2] = {Clamp(*pu, box.lo[0], box.hi[0]), Clamp(*pv, box.lo[1], box.hi[1])};
  const double scale = surface->radius(c);
  for (int iteration = 0;; ++iteration) {
    const ThetaJet jet = surface->Evaluate(c, at[0], at[1]);
    double g[2] = {0, 0}, h[3] = {0, 0, 0}, gn[3] = {0, 0, 0};
    *f = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Jet<double>& t = jet.x[k];
      const double r = t.v - x[k];
      p[k] = t.v;
      *f += r * r;
      g[0] += 2.0 * r * t.du;
      g[1] += 2.0 * r * t.dv;
      gn[0] += 2.0 * t.du * t.du;
      gn[1] += 2.0 * t.du * t.dv;
      gn[2] += 2.0 * t.dv * t.dv;
      h[0] += 2.0 * r * t.duu;
      h[1] += 2.0 * r * t.duv;
      h[2] += 2.0 * r * t.dvv;
    }
    grad[0] = g[0];
    grad[1] = g[1];
    if (iteration == kMaxIterations) break;
    for (int i = 0; i < 3; ++i) h[i] += gn[i];
    // Coordinates held on the box: at a bound with the descent pushing out.
    bool free[2];
    for (int i = 0; i < 2; ++i) free[i] = !((at[i] <= box.lo[i] && g[i] > 0) || (at[i] >= box.hi[i] && g[i] < 0));
    double step[2] = {0, 0};
    const auto solve = [&](const double* m) {
      if (free[0] && free[1]) {
        const double det = m[0] * m[2] - m[1] * m[1];
        if (!(m[0] > 0 && det > 0)) return false;
        step[0] = -(m[2] * g[0] - m[1] * g[1]) / det;
        step[1] = -(m[0] * g[1] - m[1] * g[0]) / det;
      } else {
        for (int i = 0; i < 2; ++i) {
          if (!free[i]) continue;
          const double d = m[2 * i];
          if (!(d > 0)) return false;
          step[i] = -g[i] / d;
        }
      }
      return true;
    };
    if (!free[0] && !free[1]) break;
    if (!solve(h)) {
      gn[0] += 1e-12 * scale * scale;
      gn[2] += 1e-12 * scale * scale;
      if (!solve(gn)) break;
    }
    // Backtracking on the projected step.
    double t = 1.0;
    bool moved = false;
    double next[2] = {at[0], at[1]};
    for (int tries = 0; tries < 40; ++tries, t *= 0.5) {
      next[0] = Clamp(at[0] + t * step[0], box.lo[0], box.hi[0]);
      next[1] = Clamp(at[1] + t * step[1], box.lo[1], box.hi[1]);
      double q[3];
      surface->EvaluatePoint(c, next[0], next[1], q);
      const double fn = (q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]) + (q[2] - x[2]) * (q[2] - x[2]);
      if (fn <= *f) {
        moved = true;
        break;
      }
    }
    if (!moved) break;
    const double change = std::hypot(next[0] - at[0], next[1] - at[1]);
    at[0] = next[0];
    at[1] = next[1];
    if (change <= 1e-15 * scale) iteration = kMaxIterations - 1;  // one last evaluation
  }
  *pu = at[0];
  *pv = at[1];
}

void PointSearch::Seed(std::int64_t startChart, double u0, double v0) {
  double pu = u0, pv = v0, f, g[2], p[3];
  SolveOnBox(startChart, PieceSquare(*surface, startChart), &pu, &pv, &f, g, p);
  Offer(startChart, pu, pv, p, f);
}

void PointSearch::SearchPiece(const SurfacePiece& piece) {
  struct Node {
    ChartBox box;
    double bound;
    bool operator<(const Node& other) const { return bound > other.bound; }  // least bound on top
  };
  const std::int64_t c = piece.chart;
  const double narrowest = kNarrowest * surface->radius(c);
  std::priority_queue<Node> queue;
  queue.push({piece.box, 0.0});
  while (!queue.empty()) {
    if (boxes >= kBudget) {
      certified = false;
      return;
    }
    const Node node = queue.top();
    queue.pop();
    const double cutoff = Cutoff2();
    if (node.bound >= cutoff) continue;
    const ChartBox& box = node.box;
    const ThetaEnclosure e = Enclose(*surface, c, box);
    ++boxes;
    double bound0 = 0.0;
    Interval residual[3];
    for (int k = 0; k < 3; ++k) {
      residual[k] = e.x[k].v - Interval(x[k]);
      const double gap = residual[k].lo > 0 ? residual[k].lo : residual[k].hi < 0 ? -residual[k].hi : 0.0;
      bound0 += gap * gap;
    }
    bound0 *= 1.0 - 1e-15;
    if (bound0 >= cutoff) continue;
    const double centre[2] = {box.mid(0), box.mid(1)};
    const double half[2] = {0.5 * (box.hi[0] - box.lo[0]), 0.5 * (box.hi[1] - box.lo[1])};
    double atCentre[3];
    surface->EvaluatePoint(c, centre[0], centre[1], atCentre);
    double fc = 0.0;
    for (int k = 0; k < 3; ++k) fc += (atCentre[k] - x[k]) * (atCentre[k] - x[k]);
    Offer(c, centre[0], centre[1], atCentre, fc);
    // Mean-value form: f(p) >= f(c) - sum_i |grad_i f|_max h_i.
    Interval g[2] = {Interval(0.0), Interval(0.0)};
    for (int k = 0; k < 3; ++k) {
      g[0] = g[0] + Interval(2.0) * (residual[k] * e.x[k].du);
      g[1] = g[1] + Interval(2.0) * (residual[k] * e.x[k].dv);
    }
    const double bound1 = (fc - (g[0].mag() * half[0] + g[1].mag() * half[1])) * (1.0 - 1e-14) - 1e-300;
    const double bound = std::max(bound0, bound1);
    const double cutoffNow = Cutoff2();
    if (bound >= cutoffNow) continue;
    // Convexity: the Hessian of f over the box, 2 (J^T J + sum_k r_k H_k).
    Interval a(0.0), b(0.0), d(0.0);
    for (int k = 0; k < 3; ++k) {
      const Jet<Interval>& t = e.x[k];
      a = a + Interval(2.0) * (Square(t.du) + residual[k] * t.duu);
      b = b + Interval(2.0) * (t.du * t.dv + residual[k] * t.duv);
      d = d + Interval(2.0) * (Square(t.dv) + residual[k] * t.dvv);
    }
    const bool convex = a.lo > 0 && d.lo > 0 && (Interval(a.lo) * Interval(d.lo)).lo > Square(b).hi;
    if (convex) {
      double pu = centre[0], pv = centre[1];
      if (found && chart == c && box.contains(u, v)) {
        pu = u;
        pv = v;
      }
      double f, grad[2], p[3];
      SolveOnBox(c, box, &pu, &pv, &f, grad, p);
      Offer(c, pu, pv, p, f);
      // f is convex on the box, so it lies above its tangent plane at (pu, pv).
      double tangent = f;
      for (int i = 0; i < 2; ++i) {
        const double at = i == 0 ? pu : pv;
        tangent += std::min(grad[i] * (box.lo[i] - at), grad[i] * (box.hi[i] - at));
      }
      tangent -= 1e-14 * (f + 1e-300);
      if (tangent >= Cutoff2()) continue;
    }
    if (half[0] < narrowest && half[1] < narrowest) {
      certified = false;
      continue;
    }
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        const ChartBox child{{i == 0 ? box.lo[0] : centre[0], j == 0 ? box.lo[1] : centre[1]},
                            {i == 0 ? centre[0] : box.hi[0], j == 0 ? centre[1] : box.hi[1]}};
        queue.push({child, bound});
      }
    }
  }
}

}  // namespace invmap::pou
