// Charts of a cell's reference domain that eliminate a chosen barycentric
// coordinate per factor. The reference coordinates of a simplex factor
// leave out lambda_0 = 1 - sum of the others, which a double then resolves
// only to 1e-16 absolute: a point 1e-17 from that face, or a line factor's
// t within 1e-16 of 1, cannot be written, and derivatives along the face
// come out as differences of the huge ones across it. Where weights lie
// many orders of magnitude apart, a cell crosses a whole control leg within
// such a layer. A chart that eliminates the largest coordinate instead keeps
// every small one as a free coordinate, exact down to the underflow.
#pragma once

#include <array>
#include <vector>

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// Every barycentric coordinate of each factor (unused entries 0).
struct Barycentric {
  double lambda[kMaxFactors][4] = {};
};

/// The cell re-rooted once for every choice of one vertex per factor: chart
/// (o_0, o_1, ..) is the same map with each factor's barycentric coordinates
/// 0 and o_f swapped, so that lambda_{o_f} is the eliminated one. Chart 0
/// is the cell itself. The views stay valid while this object lives.
class CellCharts {
 public:
  explicit CellCharts(const CellView& cell);
  CellCharts(const CellCharts&) = delete;
  CellCharts& operator=(const CellCharts&) = delete;

  const CellView& view(int chart) const { return views_[chart]; }
  /// The chart that eliminates each factor's largest coordinate of `b`.
  int ChartFor(const Barycentric& b) const;
  /// The barycentric coordinates of the chart's reference point `ref`.
  Barycentric ToBarycentric(int chart, const double* ref) const;
  /// The chart's reference coordinates of `b`.
  void FromBarycentric(int chart, const Barycentric& b, double* ref) const;

 private:
  /// The vertex chart `chart` puts at factor f's origin.
  int Origin(int chart, int f) const;

  CellShape shape_;
  std::vector<double> points_;   // every chart's control points, chart-major
  std::vector<double> weights_;  // and weights (empty for a polynomial cell)
  std::vector<CellView> views_;
};

}  // namespace invmap::kernels
