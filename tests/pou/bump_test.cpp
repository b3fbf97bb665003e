// The bump xi: its derivatives against differences of an independent long
// double evaluation, the shape the interval ranges rely on (xi decreasing,
// xi' with one minimum at 5/8, xi'' with one minimum on (1/4, 5/8) and one
// maximum on (5/8, 1)), and ranges over intervals that hold sampled values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "pou/bump.h"

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

TEST(BumpTest, ShapeTheRangesRelyOn) {
  // Signs of xi' and of the changes of xi' and xi'' on a fine grid.
  const int n = 20000;
  std::vector<double> f1(n + 1), f2(n + 1);
  for (int i = 0; i <= n; ++i) {
    const double t = 0.25 + 0.75 * i / n;
    f1[i] = Bump(t).f1;
    f2[i] = Bump(t).f2;
    EXPECT_LE(f1[i], 0.0);
  }
  int f1Turns = 0, f2Turns = 0;
  for (int i = 2; i <= n; ++i) {
    const double a = f1[i - 1] - f1[i - 2], b = f1[i] - f1[i - 1];
    if ((a < 0) != (b < 0) && std::fabs(b) > 1e-12 && std::fabs(a) > 1e-12) ++f1Turns;
    const double c = f2[i - 1] - f2[i - 2], d = f2[i] - f2[i - 1];
    if ((c < 0) != (d < 0) && std::fabs(d) > 1e-12 && std::fabs(c) > 1e-12) ++f2Turns;
  }
  EXPECT_EQ(f1Turns, 1);  // the minimum of xi'
  EXPECT_EQ(f2Turns, 2);  // the minimum and the maximum of xi''
  double least = 0;
  int at = 0;
  for (int i = 0; i <= n; ++i)
    if (f1[i] < least) least = f1[i], at = i;
  EXPECT_NEAR(0.25 + 0.75 * at / n, 0.625, 1e-4);
}

TEST(BumpTest, RangesHoldSampledValues) {
  std::mt19937_64 random(2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const double a = 0.2 + 0.85 * unit(random), w = 0.3 * unit(random) * unit(random);
    const BumpRanges r = Bump(Interval(a, a + w));
    for (int s = 0; s <= 20; ++s) {
      const BumpValues b = Bump(a + w * s / 20.0);
      ASSERT_TRUE(r.f.contains(b.f) && r.f1.contains(b.f1) && r.f2.contains(b.f2)) << a << " " << w;
    }
  }
}

}  // namespace
}  // namespace invmap::pou
