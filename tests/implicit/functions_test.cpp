// The built-in implicit functions: values against their closed forms written
// out independently here, gradients against central finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

double Norm(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

void ExpectMatches(const Function& f, const std::function<double(double, double, double)>& expected, bool planar = false) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const double x[3] = {unit(rng), unit(rng), planar ? 0.0 : unit(rng)};
    double value, gradient[3];
    f.evaluate(x, 1, &value, gradient);
    EXPECT_NEAR(value, expected(x[0], x[1], x[2]), 1e-12) << f.name << " at point " << i;
    const double h = 1e-6;
    for (int a = 0; a < (planar ? 2 : 3); ++a) {
      double plus[3] = {x[0], x[1], x[2]}, minus[3] = {x[0], x[1], x[2]};
      plus[a] += h;
      minus[a] -= h;
      const double slope = (expected(plus[0], plus[1], plus[2]) - expected(minus[0], minus[1], minus[2])) / (2 * h);
      EXPECT_NEAR(gradient[a], slope, 1e-6) << f.name << " d/dx" << a << " at point " << i;
    }
  }
}

TEST(ImplicitFunctions, MatchTheirClosedForms) {
  ExpectMatches(Function::Sphere({0.1, 0.2, -0.3}, 0.7), [](double x, double y, double z) {
    return 0.7 - Norm(x - 0.1, y - 0.2, z + 0.3);
  });
  ExpectMatches(Function::Sphere({0.1, 0.2, -0.3}, 0.7, true), [](double x, double y, double z) {
    return 0.49 - std::pow(Norm(x - 0.1, y - 0.2, z + 0.3), 2);
  });
  // Cylinder along (1, 2, 2) / 3 through (0.1, 0, 0).
  const auto cylinderDistance = [](double x, double y, double z) {
    const double dx = x - 0.1, h = (dx + 2 * y + 2 * z) / 3;
    return Norm(dx - h / 3, y - 2 * h / 3, z - 2 * h / 3);
  };
  ExpectMatches(Function::Cylinder({0.1, 0, 0}, {1, 2, 2}, 0.4),
                [&](double x, double y, double z) { return 0.4 - cylinderDistance(x, y, z); });
  ExpectMatches(Function::Cylinder({0.1, 0, 0}, {1, 2, 2}, 0.4, true),
                [&](double x, double y, double z) { return 0.16 - std::pow(cylinderDistance(x, y, z), 2); });
  ExpectMatches(Function::Plane({0, 0, 0.5}, {0, 3, 4}),
                [](double, double y, double z) { return (3 * y + 4 * (z - 0.5)) / 5; });
  // Torus around z: minor - |(rho - major, z)|.
  ExpectMatches(Function::Torus({0, 0, 0.1}, {0, 0, 2}, 0.6, 0.2), [](double x, double y, double z) {
    return 0.2 - std::hypot(std::hypot(x, y) - 0.6, z - 0.1);
  });
  // Cone around +x with half angle 0.5 at the origin.
  ExpectMatches(Function::Cone({0, 0, 0}, {3, 0, 0}, 0.5),
                [](double x, double y, double z) { return x - std::cos(0.5) * Norm(x, y, z); });
  ExpectMatches(Function::Quintic({0.2, -0.1, 0}),
                [](double x, double y, double) {
                  return std::pow(x - 0.2, 5) + std::pow(x - 0.2, 4) - 2 * (y + 0.1) * (y + 0.1);
                },
                true);
  const double s = 2 * M_PI / 0.8;
  ExpectMatches(Function::Gyroid(0.8), [s](double x, double y, double z) {
    return std::sin(s * x) * std::cos(s * y) + std::sin(s * y) * std::cos(s * z) + std::sin(s * z) * std::cos(s * x);
  });
}

TEST(ImplicitFunctions, BatchesAgreeWithSinglePoints) {
  const Function f = Function::Torus({0, 0, 0}, {1, 1, 0}, 0.5, 0.1);
  std::vector<double> xyz;
  for (int i = 0; i < 30; ++i) xyz.insert(xyz.end(), {0.03 * i, -0.02 * i, 0.01 * i});
  std::vector<double> values(30), gradients(90);
  f.evaluate(xyz.data(), 30, values.data(), gradients.data());
  for (int i = 0; i < 30; ++i) {
    double value, gradient[3];
    f.evaluate(&xyz[3 * i], 1, &value, gradient);
    EXPECT_EQ(values[i], value);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(gradients[3 * i + a], gradient[a]);
  }
}

}  // namespace
}  // namespace invmap::implicit
