#include "tests/support/pou_reference.h"

#include <algorithm>
#include <cmath>

namespace invmap::testing {
namespace {

using Complex = std::complex<double>;
const double kPi = std::acos(-1.0);
const double kHalfRoot3 = std::sqrt(3.0) / 2.0;

double Xi(double t) {
  if (t <= 0.25) return 1.0;
  if (t >= 1.0) return 0.0;
  const double h = (t - 0.25) / 0.75;
  const double s = 1.0 / std::sqrt(1.0 - h) - 1.0 / std::sqrt(h);
  return 1.0 / (1.0 + std::exp(2.0 * s));
}

}  // namespace

PouReference::PouReference(const std::vector<double>& xyz, const std::vector<std::int64_t>& triangles,
                           const std::vector<int>& degrees, const std::vector<double>& nets)
    : degree_(degrees), nets_(nets) {
  const std::size_t nv = xyz.size() / 3;
  // Each triangle (a, b, c) turns from b to c around a; the ring of v starts
  // at the vertex after v in the first triangle holding v.
  std::vector<std::vector<std::pair<std::int64_t, std::int64_t>>> turns(nv);
  for (std::size_t t = 0; t < triangles.size() / 3; ++t)
    for (int k = 0; k < 3; ++k)
      turns[triangles[3 * t + k]].push_back({triangles[3 * t + (k + 1) % 3], triangles[3 * t + (k + 2) % 3]});
  ring_.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    std::int64_t current = turns[v][0].first;
    for (std::size_t i = 0; i < turns[v].size(); ++i) {
      ring_[v].push_back(current);
      for (const auto& turn : turns[v])
        if (turn.first == current) {
          current = turn.second;
          break;
        }
    }
  }
  offset_.push_back(0);
  for (int d : degrees) offset_.push_back(offset_.back() + 3 * (d + 1) * (d + 1));
}

double PouReference::radius(std::int64_t v) const { return std::cos(kPi / ring_[v].size()); }

void PouReference::Shape(std::int64_t v, Complex p, double out[3]) const {
  const int d = degree_[v];
  const double r = radius(v);
  const double s = (p.real() + r) / (2 * r), t = (p.imag() + r) / (2 * r);
  const double* net = &nets_[offset_[v]];
  for (int c = 0; c < 3; ++c) {
    std::vector<double> column(d + 1);
    for (int k = 0; k <= d; ++k) {
      std::vector<double> row(d + 1);
      for (int j = 0; j <= d; ++j) row[j] = net[3 * (j + (d + 1) * k) + c];
      for (int level = d; level > 0; --level)
        for (int j = 0; j < level; ++j) row[j] = (1 - s) * row[j] + s * row[j + 1];
      column[k] = row[0];
    }
    for (int level = d; level > 0; --level)
      for (int k = 0; k < level; ++k) column[k] = (1 - t) * column[k] + t * column[k + 1];
    out[c] = column[0];
  }
}

void PouReference::Evaluate(std::int64_t v, Complex p, double out[3]) const {
  const int n = static_cast<int>(ring_[v].size());
  const double r = radius(v);
  double sum[3], point[3];
  const double own = Xi(std::abs(p) / r);
  Shape(v, p, point);
  double total = own;
  for (int c = 0; c < 3; ++c) sum[c] = own * point[c];
  for (int i = 0; i < n && std::abs(p) > 0; ++i) {
    const Complex turned = p * std::polar(1.0, -2 * kPi * i / n);
    const double a = std::arg(turned);
    if (std::fabs(a) >= 3 * kPi / n) continue;
    const Complex frame = std::polar(std::abs(turned) * kHalfRoot3 / r, a * n / 6.0);
    const Complex other = 1.0 - frame;
    if (std::abs(other) >= kHalfRoot3) continue;
    const std::int64_t u = ring_[v][i];
    const int m = static_cast<int>(ring_[u].size());
    const int j = static_cast<int>(std::find(ring_[u].begin(), ring_[u].end(), v) - ring_[u].begin());
    const Complex q = std::polar(std::abs(other) * radius(u) / kHalfRoot3, std::arg(other) * 6.0 / m + 2 * kPi * j / m);
    const double w = Xi(std::abs(other) / kHalfRoot3);
    Shape(u, q, point);
    total += w;
    for (int c = 0; c < 3; ++c) sum[c] += w * point[c];
  }
  for (int c = 0; c < 3; ++c) out[c] = sum[c] / total;
}

double PouReference::Closest(const double x[3], std::int64_t* chart, Complex* at) const {
  struct Candidate {
    double d2;
    std::int64_t v;
    Complex p;
  };
  std::vector<Candidate> best;
  const auto d2At = [&](std::int64_t v, Complex p) {
    double y[3];
    Evaluate(v, p, y);
    return (y[0] - x[0]) * (y[0] - x[0]) + (y[1] - x[1]) * (y[1] - x[1]) + (y[2] - x[2]) * (y[2] - x[2]);
  };
  constexpr int kGrid = 24;
  for (std::int64_t v = 0; v < numCharts(); ++v) {
    const double reach = 0.7 * radius(v);
    for (int j = 0; j <= kGrid; ++j)
      for (int i = 0; i <= kGrid; ++i) {
        const Complex p(-reach + 2 * reach * i / kGrid, -reach + 2 * reach * j / kGrid);
        if (std::abs(p) > reach) continue;
        best.push_back({d2At(v, p), v, p});
      }
  }
  std::sort(best.begin(), best.end(), [](const Candidate& a, const Candidate& b) { return a.d2 < b.d2; });
  best.resize(std::min<std::size_t>(best.size(), 12));
  double result = 1e300;
  for (Candidate c : best) {
    // Gauss-Newton with a difference Jacobian, staying inside the p-domain.
    const double h = 1e-7 * radius(c.v);
    for (int it = 0; it < 60; ++it) {
      double y[3], yu[3], yv[3];
      Evaluate(c.v, c.p, y);
      Evaluate(c.v, c.p + Complex(h, 0), yu);
      Evaluate(c.v, c.p + Complex(0, h), yv);
      double a = 0, b = 0, d = 0, gu = 0, gv = 0;
      for (int k = 0; k < 3; ++k) {
        const double ju = (yu[k] - y[k]) / h, jv = (yv[k] - y[k]) / h, res = y[k] - x[k];
        a += ju * ju;
        b += ju * jv;
        d += jv * jv;
        gu += ju * res;
        gv += jv * res;
      }
      const double det = a * d - b * b;
      if (!(det > 0)) break;
      Complex step(-(d * gu - b * gv) / det, -(a * gv - b * gu) / det);
      double f = d2At(c.v, c.p);
      bool moved = false;
      for (int tries = 0; tries < 30; ++tries, step *= 0.5) {
        const Complex next = c.p + step;
        if (std::abs(next) < 0.9 * radius(c.v) && d2At(c.v, next) < f) {
          c.p = next;
          moved = true;
          break;
        }
      }
      if (!moved) break;
    }
    c.d2 = d2At(c.v, c.p);
    if (c.d2 < result) {
      result = c.d2;
      *chart = c.v;
      *at = c.p;
    }
  }
  return std::sqrt(result);
}

}  // namespace invmap::testing
