// An independent evaluator of partition-of-unity surfaces for the tests:
// the charts written from the definition with complex numbers (the
// transition maps as z -> z^(n/6) style unfoldings, de Casteljau for the
// shape functions, the bump's closed form, the quotient of sums as written),
// sharing no code with pou/. Closest points by dense sampling of every chart
// and a polished Gauss-Newton solve from the best samples.
#pragma once

#include <complex>
#include <cstdint>
#include <vector>

namespace invmap::testing {

class PouReference {
 public:
  PouReference(const std::vector<double>& xyz, const std::vector<std::int64_t>& triangles,
               const std::vector<int>& degrees, const std::vector<double>& nets);
  std::int64_t numCharts() const { return static_cast<std::int64_t>(ring_.size()); }
  double radius(std::int64_t v) const;
  /// theta_v(p); p must lie in the p-domain.
  void Evaluate(std::int64_t v, std::complex<double> p, double out[3]) const;
  /// The distance from x to the surface (and the chart and point reaching it).
  double Closest(const double x[3], std::int64_t* chart, std::complex<double>* p) const;

 private:
  void Shape(std::int64_t v, std::complex<double> p, double out[3]) const;
  std::vector<std::vector<std::int64_t>> ring_;
  std::vector<int> degree_;
  std::vector<std::size_t> offset_;
  std::vector<double> nets_;
};

}  // namespace invmap::testing
