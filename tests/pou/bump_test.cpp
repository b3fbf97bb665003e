// The bump xi: its derivatives against differences of an independent long
// double evaluation; the bounds of its derivatives over intervals
// (pou/bump_bounds.h) hold sampled values and are close to the largest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pou/bump.h"
#include "pou/bump_bounds.h"

namespace invmap::pou {
namespace {

long double Xi(long double t) {
  if (t <= 0.25L) return 1.0L;
  if (t >= 1.0L) return 0.0L;
  const long double h = (t - 0.25L) / 0.75L;
  return 1.0L / (1.0L + std::exp(2.0L * (1.0L / std::sqrt(1.0L - h) - 1.0L / std::sqrt(h))));
}

TEST(BumpTest, DerivativesMatchDifferences) {
  for (double t = 0.26; t < 0.99; t += 0.01) {
    const BumpValues b = Bump(t);
    const long double h = 1e-5L;
    const long double d1 = (Xi(t + h) - Xi(t - h)) / (2 * h);
    const long double d2 = (Xi(t + h) - 2 * Xi(t) + Xi(t - h)) / (h * h);
    EXPECT_NEAR(b.f, static_cast<double>(Xi(t)), 1e-14) << t;
    EXPECT_NEAR(b.f1, static_cast<double>(d1), 1e-6 * (1 + std::fabs(b.f1))) << t;
    EXPECT_NEAR(b.f2, static_cast<double>(d2), 1e-3 * (1 + std::fabs(b.f2))) << t;
  }
}

// The third derivative by central differences of the closed form's second
// (h = 1e-6: the truncation, h^2 |xi^(5)| / 6, stays far below 1e-4 of it).
double Third(double t) {
  const double h = 1e-6;
  return (Bump(t + h).f2 - Bump(t - h).f2) / (2 * h);
}

TEST(BumpBoundsTest, HoldSampledDerivatives) {
  std::mt19937_64 random(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const double a = 0.2 + 0.85 * unit(random), w = 0.3 * unit(random) * unit(random);
    const BumpDerivativeBounds bound = BoundBump(a, a + w);
    for (int s = 0; s <= 20; ++s) {
      const double t = a + w * s / 20.0;
      const BumpValues b = Bump(t);
      ASSERT_LE(std::fabs(b.f), bound.d[0]) << t;
      ASSERT_LE(std::fabs(b.f1), bound.d[1]) << t;
      ASSERT_LE(std::fabs(b.f2), bound.d[2]) << t;
      if (t > 0.2501 && t < 0.9999) {
        ASSERT_LE(std::fabs(Third(t)), bound.d[3] * (1 + 1e-4) + 1e-9) << t;
      }
    }
  }
}

TEST(BumpBoundsTest, CloseToTheLargestValues) {
  double most[4] = {0, 0, 0, 0};
  for (int i = 1; i < 200000; ++i) {
    const double t = 0.25 + 0.75 * i / 200000;
    const BumpValues b = Bump(t);
    most[1] = std::max(most[1], std::fabs(b.f1));
    most[2] = std::max(most[2], std::fabs(b.f2));
    most[3] = std::max(most[3], std::fabs(Third(t)));
  }
  const BumpDerivativeBounds bound = BoundBump(0.25, 1.0);
  EXPECT_EQ(bound.d[0], 1.0);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_GE(bound.d[k], most[k]) << k;
    EXPECT_LE(bound.d[k], 1.5 * most[k]) << k;
  }
  // xi is constant outside (1/4, 1).
  const BumpDerivativeBounds inside = BoundBump(0.0, 0.25), outside = BoundBump(1.0, 2.0);
  EXPECT_EQ(inside.d[0], 1.0);
  EXPECT_EQ(outside.d[0], 0.0);
  for (int k = 1; k <= 3; ++k) EXPECT_EQ(inside.d[k] + outside.d[k], 0.0);
}

}  // namespace
}  // namespace invmap::pou
