#include "pou/bump_bounds.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <vector>

namespace invmap::pou {
namespace {

constexpr int kCells = 2048;
constexpr double kPi = 3.141592653589793;
constexpr double kInner = 0.25, kSpan = 0.75;  // xi changes on [1/4, 1] (pou/bump.h)

/// Cell boundary i of H.
double Boundary(int i) { return i <= 0 ? 0.0 : i >= kCells ? 1.0 : 0.5 * (1.0 - std::cos(kPi * i / kCells)); }

double G(double h) { return 2.0 / std::sqrt(1.0 - h) - 2.0 / std::sqrt(h); }
/// log(sigma (1 - sigma)) at x, without underflow.
double LogL(double x) { return -std::fabs(x) - 2.0 * std::log1p(std::exp(-std::fabs(x))); }

/// xi and its first three derivatives in H at h (0 < h < 1), up to
/// rounding: xi = sigma(g), sigma' = -L, sigma'' = L (1 - 2 sigma),
/// sigma''' = -L (1 - 6 L), with L = sigma (1 - sigma) kept in logarithms.
std::array<double, 4> Values(double h) {
  const double x = G(h), l = std::exp(LogL(x)), t = std::tanh(0.5 * x);  // t = 1 - 2 sigma
  const double gp = std::pow(1.0 - h, -1.5) + std::pow(h, -1.5);
  const double gpp = 1.5 * (std::pow(1.0 - h, -2.5) - std::pow(h, -2.5));
  const double gppp = 3.75 * (std::pow(1.0 - h, -3.5) + std::pow(h, -3.5));
  return {1.0 / (1.0 + std::exp(x)), -l * gp, l * t * gp * gp - l * gpp,
          -l * (1.0 - 6.0 * l) * gp * gp * gp + 3.0 * l * t * gp * gpp - l * gppp};
}

/// Bounds of |xi^(k)| in H over cell [h0, h1] (0 < h0 < h1 < 1), k = 1 to 4:
/// each factor of the chain rule at its largest over the cell (g increases;
/// L is largest where g is nearest 0; the powers of h and 1 - h are
/// monotone), with |sigma''''| <= 2 L |1 - 2 sigma|.
std::array<double, 5> FactorBounds(double h0, double h1) {
  const double x0 = G(h0), x1 = G(h1);
  const double logL = LogL(std::clamp(0.0, x0, x1));
  const double t1 = std::max(std::fabs(std::tanh(0.5 * x0)), std::fabs(std::tanh(0.5 * x1)));  // |1 - 2 sigma|
  const double lMax = std::exp(logL), lMin = std::min(std::exp(LogL(x0)), std::exp(LogL(x1)));
  const double t2 = std::max(std::fabs(1.0 - 6.0 * lMax), std::fabs(1.0 - 6.0 * lMin));  // |1 - 6 L|
  const double gp = std::pow(1.0 - h1, -1.5) + std::pow(h0, -1.5);
  const double gpp = 1.5 * std::max(std::pow(1.0 - h1, -2.5), std::pow(h0, -2.5));
  const double gppp = 3.75 * (std::pow(1.0 - h1, -3.5) + std::pow(h0, -3.5));
  const double gpppp = 13.125 * std::max(std::pow(1.0 - h1, -4.5), std::pow(h0, -4.5));
  // L times powers of g' and other factors, in logarithms: L underflows
  // where the powers overflow.
  const auto term = [&](double factor, double power, double other) {
    if (!(factor > 0.0) || !(other > 0.0)) return 0.0;
    return std::exp(logL + std::log(factor) + power * std::log(gp) + std::log(other));
  };
  std::array<double, 5> d;
  d[0] = 1.0;
  d[1] = term(1.0, 1.0, 1.0);
  d[2] = term(t1, 2.0, 1.0) + term(1.0, 0.0, gpp);
  d[3] = term(t2, 3.0, 1.0) + term(3.0 * t1, 1.0, gpp) + term(1.0, 0.0, gppp);
  d[4] = term(2.0 * t1, 4.0, 1.0) + term(6.0 * t2, 2.0, gpp) + term(3.0 * t1, 0.0, gpp * gpp) +
         term(4.0 * t1, 1.0, gppp) + term(1.0, 0.0, gpppp);
  return d;
}

/// The bounds over cell [h0, h1], derivatives in H: the larger value at the
/// cell's ends plus half its width times the next derivative's bound.
std::array<double, 4> CellBounds(double h0, double h1) {
  const std::array<double, 4> a = Values(h0), b = Values(h1);
  const std::array<double, 5> next = FactorBounds(h0, h1);
  std::array<double, 4> d;
  for (int k = 0; k < 4; ++k) d[k] = std::max(std::fabs(a[k]), std::fabs(b[k])) + 0.5 * (h1 - h0) * next[k + 1];
  d[0] = std::min(d[0], 1.0);
  return d;
}

constexpr int kBlock = 32;  // cells per block of the table's block maxima

struct Table {
  std::vector<std::array<double, 4>> cells, blocks;
  Table() : cells(kCells), blocks(kCells / kBlock) {
    for (int i = 0; i < kCells; ++i) {
      std::array<double, 4>& c = cells[i];
      if (i == 0 || i == kCells - 1) {
        // xi within 6e-7 of an end of H: every derivative is below e^-2000.
        c = {i == 0 ? 1.0 : DBL_MIN, DBL_MIN, DBL_MIN, DBL_MIN};
      } else {
        c = CellBounds(Boundary(i), Boundary(i + 1));
        double scale = 1.0;
        for (int k = 0; k < 4; ++k, scale /= kSpan) {
          // Rounding of the closed forms (pow, exp, log within a few ulps).
          c[k] = std::max(DBL_MIN, c[k] * scale * (1.0 + 1e-10));
        }
      }
      for (int k = 0; k < 4; ++k) blocks[i / kBlock][k] = std::max(blocks[i / kBlock][k], c[k]);
    }
  }
  /// The largest bounds over cells first .. last.
  void Max(int first, int last, double out[4]) const {
    const auto add = [&](const std::array<double, 4>& c) {
      for (int k = 0; k < 4; ++k) out[k] = std::max(out[k], c[k]);
    };
    int i = first;
    for (; i <= last && i % kBlock != 0; ++i) add(cells[i]);
    for (; i + kBlock - 1 <= last; i += kBlock) add(blocks[i / kBlock]);
    for (; i <= last; ++i) add(cells[i]);
  }
};

/// The cell holding h (0 <= h <= 1).
int CellOf(double h) {
  const int i = static_cast<int>(std::floor(std::acos(std::clamp(1.0 - 2.0 * h, -1.0, 1.0)) / kPi * kCells));
  return std::clamp(i, 0, kCells - 1);
}

}  // namespace

BumpDerivativeBounds BoundBump(double t0, double t1) {
  static const Table table;
  BumpDerivativeBounds b;
  if (t1 <= kInner) {
    b.d[0] = 1.0;
    return b;
  }
  if (t0 >= kInner + kSpan) return b;
  const double h0 = std::max(0.0, (t0 - kInner) / kSpan), h1 = std::min(1.0, (t1 - kInner) / kSpan);
  // One cell of margin either way for the rounding of the lookup.
  const int first = std::max(0, CellOf(h0) - 1), last = std::min(kCells - 1, CellOf(h1) + 1);
  table.Max(first, last, b.d);
  if (t0 <= kInner) b.d[0] = 1.0;
  return b;
}

}  // namespace invmap::pou
