#include "pou/piece_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pou/chart_maps.h"
#include "pou/interval.h"

namespace invmap::pou {
namespace {

/// Boxes one query may examine before its answer is left uncertified. 4096
/// left 2 % of the points around a valence-32 star farther than the surface
/// (docs/manifold.md); the budget costs only the queries that reach it.
constexpr int kBudget = 65536;
/// Half-width (share of the chart's radius) below which a box is not split.
constexpr double kNarrowest = 1e-10;
constexpr int kMaxIterations = 40;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

double Clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

double Dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The jet of theta_v at a box's centre, by coordinate: T (value), J (two
/// columns), H (ss, st, tt).
struct CentreJet {
  double value[3], j0[3], j1[3], h[3][3];
};

CentreJet Unpack(const ThetaJet& jet) {
  CentreJet c;
  for (int k = 0; k < 3; ++k) {
    c.value[k] = jet.x[k].v;
    c.j0[k] = jet.x[k].du;
    c.j1[k] = jet.x[k].dv;
    c.h[k][0] = jet.x[k].duu;
    c.h[k][1] = jet.x[k].duv;
    c.h[k][2] = jet.x[k].dvv;
  }
  return c;
}

/// min over |d_i| <= h_i of |d_0 j0 + d_1 j1 - e|, and where (d_0, d_1).
/// The least point of the convex quadratic is the free minimizer when it
/// lies in the box, else on an edge, where it is the clamped minimizer of
/// the edge's parabola.
double ParallelogramDistance(const double j0[3], const double j1[3], const double e[3], const double h[2],
                             double d[2]) {
  const double a = Dot(j0, j0), b = Dot(j0, j1), c = Dot(j1, j1), p = Dot(j0, e), q = Dot(j1, e);
  const auto distance = [&](double d0, double d1) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double r = d0 * j0[k] + d1 * j1[k] - e[k];
      s += r * r;
    }
    return std::sqrt(s);
  };
  const double det = a * c - b * b;
  if (det > 1e-12 * a * c) {
    const double d0 = (c * p - b * q) / det, d1 = (a * q - b * p) / det;
    if (std::fabs(d0) <= h[0] && std::fabs(d1) <= h[1]) {
      d[0] = d0;
      d[1] = d1;
      return distance(d0, d1);
    }
  }
  double best = std::numeric_limits<double>::infinity();
  const auto consider = [&](double d0, double d1) {
    const double value = distance(d0, d1);
    if (value < best) {
      best = value;
      d[0] = d0;
      d[1] = d1;
    }
  };
  for (double s0 : {-h[0], h[0]}) consider(s0, c > 0.0 ? Clamp((q - b * s0) / c, -h[1], h[1]) : 0.0);
  for (double s1 : {-h[1], h[1]}) consider(a > 0.0 ? Clamp((p - b * s1) / a, -h[0], h[0]) : 0.0, s1);
  return best;
}

/// Bound of |H[d, d]| per coordinate over |d_i| <= h_i, as one Euclidean norm.
double QuadraticReach(const CentreJet& c, const double h[2]) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double q = std::fabs(c.h[k][0]) * h[0] * h[0] + 2.0 * std::fabs(c.h[k][1]) * h[0] * h[1] +
                     std::fabs(c.h[k][2]) * h[1] * h[1];
    sum += q * q;
  }
  return std::sqrt(sum);
}

Interval Around(double centre, double radius) {
  return {interval_detail::Down(centre - radius), interval_detail::Up(centre + radius)};
}

/// Enclosures over a box of the gradient and Hessian (xx, xy, yy) of
/// f = |theta_v - x|^2: 2 sum_k r_k J_k and 2 sum_k (J_k J_k^T + r_k H_k)
/// from the Taylor enclosures of r = theta_v - x, J and H (pou/piece_search.h).
struct FunctionEnclosure {
  Interval grad[2];
  Interval hess[3];
  bool Convex() const {
    if (!(hess[0].lo > 0.0 && hess[2].lo > 0.0)) return false;
    return (Interval(hess[0].lo) * Interval(hess[2].lo)).lo > Square(hess[1]).hi;
  }
};

FunctionEnclosure Enclose(const CentreJet& c, const double x[3], const double h[2], double third,
                          const EvaluationSlack& slack) {
  const double rho = Length(h[0], h[1]);
  const double firstReach = 0.5 * third * rho * rho + slack.first;
  const double secondReach = third * rho + slack.second;
  FunctionEnclosure e;
  for (Interval& i : e.grad) i = Interval(0.0);
  for (Interval& i : e.hess) i = Interval(0.0);
  const Interval two(2.0);
  for (int k = 0; k < 3; ++k) {
    const Interval j0 =
        Around(c.j0[k], std::fabs(c.h[k][0]) * h[0] + std::fabs(c.h[k][1]) * h[1] + firstReach);
    const Interval j1 =
        Around(c.j1[k], std::fabs(c.h[k][1]) * h[0] + std::fabs(c.h[k][2]) * h[1] + firstReach);
    const double valueReach = std::fabs(c.j0[k]) * h[0] + std::fabs(c.j1[k]) * h[1] +
                              0.5 * (std::fabs(c.h[k][0]) * h[0] * h[0] + 2.0 * std::fabs(c.h[k][1]) * h[0] * h[1] +
                                     std::fabs(c.h[k][2]) * h[1] * h[1]) +
                              third * rho * rho * rho / 6.0 + slack.value + slack.first * (h[0] + h[1]) +
                              slack.second * rho * rho;
    const Interval r =
        Around(c.value[k] - x[k], valueReach + 4.0 * kEpsilon * (std::fabs(c.value[k]) + std::fabs(x[k])));
    e.grad[0] = e.grad[0] + two * (r * j0);
    e.grad[1] = e.grad[1] + two * (r * j1);
    e.hess[0] = e.hess[0] + two * (Square(j0) + r * Around(c.h[k][0], secondReach));
    e.hess[1] = e.hess[1] + two * (j0 * j1 + r * Around(c.h[k][1], secondReach));
    e.hess[2] = e.hess[2] + two * (Square(j1) + r * Around(c.h[k][2], secondReach));
  }
  return e;
}

/// The least value over |d_i| <= h_i of g . d + (a d0^2 - 2 b |d0 d1| + e d1^2) / 2,
/// which bounds g . d + d^T M d / 2 from below for every matrix M of the
/// enclosure (a, e the least diagonal entries, b the largest |M01|). In each
/// quadrant it is a quadratic: its least point over the quadrant's part of
/// the box is its stationary point when that is a minimum inside, else on
/// the part's sides, where it is a parabola.
double QuadraticModelMinimum(const double g[2], double a, double b, double e, const double h[2]) {
  double least = 0.0;  // d = 0
  for (int s0 = -1; s0 <= 1; s0 += 2) {
    for (int s1 = -1; s1 <= 1; s1 += 2) {
      const double m01 = -s0 * s1 * b;  // the quadrant's off-diagonal entry
      const double lo[2] = {s0 < 0 ? -h[0] : 0.0, s1 < 0 ? -h[1] : 0.0};
      const double hi[2] = {s0 < 0 ? 0.0 : h[0], s1 < 0 ? 0.0 : h[1]};
      const auto value = [&](double d0, double d1) {
        return g[0] * d0 + g[1] * d1 + 0.5 * (a * d0 * d0 + 2.0 * m01 * d0 * d1 + e * d1 * d1);
      };
      const double det = a * e - m01 * m01;
      if (a > 0.0 && det > 0.0) {
        const double d0 = -(e * g[0] - m01 * g[1]) / det, d1 = -(a * g[1] - m01 * g[0]) / det;
        if (lo[0] <= d0 && d0 <= hi[0] && lo[1] <= d1 && d1 <= hi[1]) least = std::min(least, value(d0, d1));
      }
      // Sides d0 = const: a parabola in d1 with leading coefficient e / 2.
      for (double d0 : {lo[0], hi[0]}) {
        const double slope = g[1] + m01 * d0;
        for (double d1 : {lo[1], hi[1]}) least = std::min(least, value(d0, d1));
        if (e > 0.0) least = std::min(least, value(d0, Clamp(-slope / e, lo[1], hi[1])));
      }
      for (double d1 : {lo[1], hi[1]}) {
        const double slope = g[0] + m01 * d1;
        if (a > 0.0) least = std::min(least, value(Clamp(-slope / a, lo[0], hi[0]), d1));
      }
    }
  }
  return least;
}

}  // namespace

PointSearch::PointSearch(const PouSurface& surface, const double x[3], double tolerance, double cutoff, double band)
    : surface_(surface), tolerance_(tolerance), band_(band), distance_(cutoff) {
  for (int k = 0; k < 3; ++k) x_[k] = x[k];
}

void PointSearch::Offer(std::int64_t chart, double u, double v, const double point[3], double f) {
  const double d = std::sqrt(f);
  if (found_ ? !(d < distance_) : !(d <= distance_ + band_)) return;
  found_ = true;
  distance_ = d;
  chart_ = chart;
  u_ = u;
  v_ = v;
  for (int k = 0; k < 3; ++k) point_[k] = point[k];
}

PointSearch::LocalAnswer PointSearch::Solve(std::int64_t chart, const ChartBox& box, double u, double v) const {
  LocalAnswer answer;
  double at[2] = {Clamp(u, box.lo[0], box.hi[0]), Clamp(v, box.lo[1], box.hi[1])};
  const double scale = surface_.radius(chart);
  const auto squared = [&](const double p[3]) {
    return (p[0] - x_[0]) * (p[0] - x_[0]) + (p[1] - x_[1]) * (p[1] - x_[1]) + (p[2] - x_[2]) * (p[2] - x_[2]);
  };
  for (int iteration = 0;; ++iteration) {
    const ThetaJet jet = surface_.Evaluate(chart, at[0], at[1]);
    double g[2] = {0, 0}, h[3] = {0, 0, 0}, gn[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const Jet<double>& j = jet.x[k];
      const double r = j.v - x_[k];
      answer.point[k] = j.v;
      g[0] += 2.0 * r * j.du;
      g[1] += 2.0 * r * j.dv;
      gn[0] += 2.0 * j.du * j.du;
      gn[1] += 2.0 * j.du * j.dv;
      gn[2] += 2.0 * j.dv * j.dv;
      h[0] += 2.0 * r * j.duu;
      h[1] += 2.0 * r * j.duv;
      h[2] += 2.0 * r * j.dvv;
    }
    answer.u = at[0];
    answer.v = at[1];
    answer.f = squared(answer.point);
    answer.grad[0] = g[0];
    answer.grad[1] = g[1];
    if (iteration == kMaxIterations) break;
    for (int i = 0; i < 3; ++i) h[i] += gn[i];
    // Coordinates held on the box: at a bound with the descent pushing out.
    bool free[2];
    for (int i = 0; i < 2; ++i) free[i] = !((at[i] <= box.lo[i] && g[i] > 0) || (at[i] >= box.hi[i] && g[i] < 0));
    if (!free[0] && !free[1]) break;
    double step[2] = {0, 0};
    const auto newton = [&](const double* m) {
      if (free[0] && free[1]) {
        const double det = m[0] * m[2] - m[1] * m[1];
        if (!(m[0] > 0 && det > 0)) return false;
        step[0] = -(m[2] * g[0] - m[1] * g[1]) / det;
        step[1] = -(m[0] * g[1] - m[1] * g[0]) / det;
        return true;
      }
      const int i = free[0] ? 0 : 1;
      const double diagonal = m[2 * i];
      if (!(diagonal > 0)) return false;
      step[i] = -g[i] / diagonal;
      return true;
    };
    if (!newton(h)) {
      // Gauss-Newton where the full Hessian is not positive definite.
      gn[0] += 1e-12 * scale * scale;
      gn[2] += 1e-12 * scale * scale;
      if (!newton(gn)) break;
    }
    // Backtracking on the projected step.
    double next[2] = {at[0], at[1]};
    bool moved = false;
    double fraction = 1.0;
    for (int tries = 0; tries < 40; ++tries, fraction *= 0.5) {
      next[0] = Clamp(at[0] + fraction * step[0], box.lo[0], box.hi[0]);
      next[1] = Clamp(at[1] + fraction * step[1], box.lo[1], box.hi[1]);
      double p[3];
      surface_.EvaluatePoint(chart, next[0], next[1], p);
      if (squared(p) <= answer.f) {
        moved = true;
        break;
      }
    }
    if (!moved) break;
    const double change = Length(next[0] - at[0], next[1] - at[1]);
    at[0] = next[0];
    at[1] = next[1];
    if (change <= 1e-15 * scale) iteration = kMaxIterations - 1;  // one last evaluation
  }
  return answer;
}

bool PointSearch::CloseByTangent(std::int64_t chart, const ChartBox& box, const ChartBox& face, const double start[2],
                                 double jacobian, const EvaluationSlack& slack) {
  double u = start[0], v = start[1];
  if (found_ && chart_ == chart && face.lo[0] <= u_ && u_ <= face.hi[0] && face.lo[1] <= v_ && v_ <= face.hi[1]) {
    u = u_;
    v = v_;
  }
  const LocalAnswer a = Solve(chart, face, u, v);
  Offer(chart, a.u, a.v, a.point, a.f);
  double tangent = a.f;
  const double at[2] = {a.u, a.v};
  for (int i = 0; i < 2; ++i) {
    tangent += std::min(a.grad[i] * (face.lo[i] - at[i]), a.grad[i] * (face.hi[i] - at[i]));
  }
  // Rounding of f and its gradient at the answer (the point's rounding
  // allowance and the gradient's, over the box's width).
  const double residual = std::sqrt(a.f);
  tangent -= 2.0 * residual * slack.value + slack.value * slack.value +
             4.0 * (jacobian * slack.value + residual * slack.first) * (box.hi[0] - box.lo[0] + box.hi[1] - box.lo[1]) +
             16.0 * kEpsilon * a.f;
  return tangent >= Cutoff2();
}

void PointSearch::Seed(std::int64_t chart, double u, double v) {
  const double h = kCoveredRadius * surface_.radius(chart);
  const LocalAnswer answer = Solve(chart, {{-h, -h}, {h, h}}, u, v);
  Offer(chart, answer.u, answer.v, answer.point, answer.f);
}

void PointSearch::SearchPiece(std::int64_t chart, const ChartBox& pieceBox, const ShapeMajorants& shapes) {
  const EvaluationSlack slack = SlackOf(surface_, chart);
  const double narrowest = kNarrowest * surface_.radius(chart);
  const auto later = [](const Node& a, const Node& b) { return a.bound > b.bound; };
  heap_.clear();
  heap_.push_back({pieceBox, 0.0});
  bool root = true;
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const Node node = heap_.back();
    heap_.pop_back();
    if (node.bound >= Cutoff2() || OutsideKites(surface_, chart, node.box)) continue;
    if (boxes_ >= kBudget) {
      // Out of budget (a query near a continuum of equally near points, such
      // as the centre of a sphere-like surface): the rest of the piece gets
      // one local solve from its least box's centre, so that a piece never
      // goes unexamined, and the answer is not certified.
      certified_ = false;
      const double u = 0.5 * (node.box.lo[0] + node.box.hi[0]), v = 0.5 * (node.box.lo[1] + node.box.hi[1]);
      const LocalAnswer answer = Solve(chart, pieceBox, u, v);
      Offer(chart, answer.u, answer.v, answer.point, answer.f);
      return;
    }
    ++boxes_;
    const ChartBox& box = node.box;
    const double centre[2] = {0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1])};
    const double h[2] = {0.5 * (box.hi[0] - box.lo[0]), 0.5 * (box.hi[1] - box.lo[1])};
    const double rho = Length(h[0], h[1]);
    ReachingEdges(surface_, chart, box, shapes, &parts_);
    surface_.EvaluateParts(chart, centre[0], centre[1], &parts_);
    const CentreJet c = Unpack(parts_.Theta());
    double e[3], fCentre = 0.0;
    for (int k = 0; k < 3; ++k) {
      e[k] = x_[k] - c.value[k];
      fCentre += e[k] * e[k];
    }
    Offer(chart, centre[0], centre[1], c.value, fCentre);
    double step[2];
    const double flat = ParallelogramDistance(c.j0, c.j1, e, h, step);
    const double start[2] = {Clamp(centre[0] + step[0], box.lo[0], box.hi[0]),
                             Clamp(centre[1] + step[1], box.lo[1], box.hi[1])};
    SampleBox(surface_, chart, box, parts_, slack, &scratch_, &sample_);
    const double third = ThirdDerivativeBound(surface_, chart, box, shapes, sample_);
    double bound = node.bound;
    if (third < HUGE_VAL) {
      // Lower bound: the parallelogram of the linear part, less the rest.
      const double rest = 0.5 * QuadraticReach(c, h) + third * rho * rho * rho / 6.0 + slack.value +
                          slack.first * (h[0] + h[1]) + slack.second * rho * rho +
                          8.0 * kEpsilon *
                              (std::sqrt(fCentre) + std::sqrt(Dot(c.j0, c.j0)) * h[0] +
                               std::sqrt(Dot(c.j1, c.j1)) * h[1] + std::fabs(c.value[0]) + std::fabs(c.value[1]) +
                               std::fabs(c.value[2]));
      const double lower = std::max(0.0, flat - rest);
      bound = std::max(bound, lower * lower * (1.0 - 4.0 * kEpsilon));
      if (bound >= Cutoff2()) continue;
      const FunctionEnclosure f = Enclose(c, x_, h, third, slack);
      // Second-order lower bound: f(c) + grad f(c) . d + d^T Hf(xi) d / 2
      // (Taylor, xi in the box) with Hf in its enclosure, less the rounding
      // of f(c) and its gradient.
      double gradient[2] = {0.0, 0.0};
      for (int k = 0; k < 3; ++k) {
        gradient[0] -= 2.0 * e[k] * c.j0[k];
        gradient[1] -= 2.0 * e[k] * c.j1[k];
      }
      const double residual = std::sqrt(fCentre);
      const double jacobian = std::sqrt(Dot(c.j0, c.j0) + Dot(c.j1, c.j1));
      const double second = fCentre + QuadraticModelMinimum(gradient, f.hess[0].lo, f.hess[1].mag(), f.hess[2].lo, h) -
                            (2.0 * residual * slack.value + slack.value * slack.value +
                             2.0 * (jacobian * slack.value + residual * slack.first) * (h[0] + h[1]) +
                             16.0 * kEpsilon * (fCentre + (residual + jacobian * (h[0] + h[1])) *
                                                              (std::fabs(c.value[0]) + std::fabs(c.value[1]) +
                                                               std::fabs(c.value[2]) + residual)));
      bound = std::max(bound, second);
      if (bound >= Cutoff2()) continue;
      // Where f is convex on the box, its least point there; where it falls
      // toward one side all over the box (the box's least point lies on that
      // side) and is convex along the side, its least point on the side; at a
      // corner where it falls toward both. f lies above its tangent plane at
      // that point over the box or side; when the plane stays above the
      // cut-off, the box is closed.
      ChartBox face = box;
      bool closable = f.Convex();
      if (!closable) {
        bool fixed[2] = {false, false};
        for (int i = 0; i < 2; ++i) {
          if (f.grad[i].hi < 0.0) {
            face.lo[i] = box.hi[i];
            fixed[i] = true;
          } else if (f.grad[i].lo > 0.0) {
            face.hi[i] = box.lo[i];
            fixed[i] = true;
          }
        }
        closable = (fixed[0] && fixed[1]) || (fixed[0] && f.hess[2].lo > 0.0) || (fixed[1] && f.hess[0].lo > 0.0);
      }
      const double boxJacobian = jacobian + 2.0 * QuadraticReach(c, h) / rho;
      if (closable && CloseByTangent(chart, box, face, start, boxJacobian, slack)) continue;
    }
    if (root) {
      // A first local solve over the whole piece lowers the cut-off early.
      const LocalAnswer a = Solve(chart, box, start[0], start[1]);
      Offer(chart, a.u, a.v, a.point, a.f);
      root = false;
    }
    if (std::max(h[0], h[1]) < narrowest) {
      certified_ = false;
      continue;
    }
    // Split across the side whose image is longest (both when they are close).
    const double long0 = std::sqrt(Dot(c.j0, c.j0)) * h[0], long1 = std::sqrt(Dot(c.j1, c.j1)) * h[1];
    const bool split0 = long0 >= 0.5 * long1, split1 = long1 >= 0.5 * long0;
    for (int i = 0; i <= (split0 ? 1 : 0); ++i) {
      for (int j = 0; j <= (split1 ? 1 : 0); ++j) {
        Node child{box, bound};
        if (split0) (i == 0 ? child.box.hi[0] : child.box.lo[0]) = centre[0];
        if (split1) (j == 0 ? child.box.hi[1] : child.box.lo[1]) = centre[1];
        heap_.push_back(child);
        std::push_heap(heap_.begin(), heap_.end(), later);
      }
    }
  }
}

}  // namespace invmap::pou
