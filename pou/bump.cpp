#include "pou/bump.h"

#include <cmath>

namespace invmap::pou {
namespace {

constexpr double kSpan = kBumpOuter - kBumpInner;

}  // namespace

BumpValues Bump(double t) {
  const double h = (t - kBumpInner) / kSpan;
  if (!(h > 0.0)) return {1.0, 0.0, 0.0};
  if (!(h < 1.0)) return {0.0, 0.0, 0.0};
  const double g = 2.0 / std::sqrt(1.0 - h) - 2.0 / std::sqrt(h);  // 2 s
  BumpValues b;
  b.f = 1.0 / (1.0 + std::exp(g));
  // xi (1 - xi) in logarithms, so that tiny values times the huge powers of
  // 1/h near the ends neither underflow to 0 * inf nor overflow.
  const double logW = -std::fabs(g) - 2.0 * std::log1p(std::exp(-std::fabs(g)));
  const double gp = std::pow(1.0 - h, -1.5) + std::pow(h, -1.5);
  const double gpp = 1.5 * (std::pow(1.0 - h, -2.5) - std::pow(h, -2.5));
  const double dxi = -std::exp(logW + std::log(gp));
  const double wgp2 = std::exp(logW + 2.0 * std::log(gp));
  const double wgpp = gpp == 0.0 ? 0.0 : std::copysign(std::exp(logW + std::log(std::fabs(gpp))), gpp);
  const double ddxi = (1.0 - 2.0 * b.f) * wgp2 - wgpp;
  b.f1 = dxi / kSpan;
  b.f2 = ddxi / (kSpan * kSpan);
  return b;
}

}  // namespace invmap::pou
