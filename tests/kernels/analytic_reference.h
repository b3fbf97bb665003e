// The independent reference of the closed-form tests on elementary surfaces
// (kernels/analytic_surface.h): the squared distance sampled densely over a
// box of own parameters and refined around its best sample; and a square
// of own parameters as a face's region.
#pragma once

#include <algorithm>
#include <limits>

#include "kernels/analytic_surface.h"
#include "kernels/trim_region.h"

namespace invmap::kernels::reference {

inline double Distance2(const AnalyticSurface& s, double u, double v, const double* p) {
  double x[3];
  s.Evaluate(u, v, x);
  return (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) + (x[2] - p[2]) * (x[2] - p[2]);
}

/// The least squared distance over the box [lo, hi] by a 161 x 161 grid,
/// then four rounds of a 21 x 21 grid around the best sample, each a fifth
/// as wide; `at` (when given) gets the best sample's parameters.
inline double SampledMinimum2(const AnalyticSurface& s, const double* lo, const double* hi, const double* p,
                              double* at = nullptr) {
  double best = std::numeric_limits<double>::infinity(), where[2] = {lo[0], lo[1]};
  double half[2] = {0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])};
  const auto scan = [&](const double* centre, int n) {
    const double c[2] = {centre[0], centre[1]};
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        const double u = std::clamp(c[0] - half[0] + 2.0 * half[0] * i / n, lo[0], hi[0]);
        const double v = std::clamp(c[1] - half[1] + 2.0 * half[1] * j / n, lo[1], hi[1]);
        const double d2 = Distance2(s, u, v, p);
        if (d2 < best) {
          best = d2;
          where[0] = u;
          where[1] = v;
        }
      }
    }
  };
  const double middle[2] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])};
  scan(middle, 160);
  // Around the best sample, one step of the grid before each way.
  for (int d = 0; d < 2; ++d) half[d] = (hi[d] - lo[d]) / 160.0;
  for (int round = 0; round < 4; ++round) {
    scan(where, 20);
    for (double& h : half) h *= 0.2;
  }
  if (at) std::copy(where, where + 2, at);
  return best;
}

/// The square [c - h, c + h] in (u, v) as a region of four straight pieces.
inline void AddSquare(const double* c, double h, TrimRegion* region) {
  const double corners[5][2] = {{c[0] - h, c[1] - h}, {c[0] + h, c[1] - h}, {c[0] + h, c[1] + h}, {c[0] - h, c[1] + h},
                                {c[0] - h, c[1] - h}};
  for (int k = 0; k < 4; ++k) {
    const double piece[4] = {corners[k][0], corners[k][1], corners[k + 1][0], corners[k + 1][1]};
    region->AddPiece(1, piece, nullptr);
  }
  region->Finish();
}

}  // namespace invmap::kernels::reference
