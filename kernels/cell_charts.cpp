#include "kernels/cell_charts.h"

#include <algorithm>
#include <utility>

#include "kernels/active_set.h"
#include "kernels/simplex_index.h"

namespace invmap::kernels {

CellCharts::CellCharts(const CellView& cell) : shape_(cell.shape) {
  int charts = 1;
  for (int f = 0; f < shape_.numFactors(); ++f) charts *= shape_.factor(f).dim + 1;
  const int n = shape_.numControlPoints();
  const int ad = cell.ambientDim;
  points_.resize(static_cast<size_t>(charts) * n * ad);
  if (cell.weights) weights_.resize(static_cast<size_t>(charts) * n);
  for (int chart = 0; chart < charts; ++chart) {
    for (int c = 0; c < n; ++c) {
      // Swapping entries 0 and o of a multi-index is its own inverse: the
      // chart's control point c is the cell's at the swapped multi-index.
      int source = 0, stride = 1, rest = c;
      for (int f = 0; f < shape_.numFactors(); ++f) {
        const SimplexFactor& fac = shape_.factor(f);
        const SimplexIndex& index = SimplexIndex::Get(fac.dim, fac.degree);
        const int position = rest % index.size();
        rest /= index.size();
        std::array<int, 4> multi = index.multi(position);
        std::swap(multi[0], multi[Origin(chart, f)]);
        source += index.Position(multi) * stride;
        stride *= index.size();
      }
      const size_t to = static_cast<size_t>(chart) * n + c;
      std::copy(cell.points + static_cast<size_t>(source) * ad, cell.points + static_cast<size_t>(source + 1) * ad,
                points_.begin() + static_cast<std::ptrdiff_t>(to * ad));
      if (cell.weights) weights_[to] = cell.weights[source];
    }
  }
  for (int chart = 0; chart < charts; ++chart) {
    CellView view = cell;
    view.points = points_.data() + static_cast<size_t>(chart) * n * ad;
    view.weights = cell.weights ? weights_.data() + static_cast<size_t>(chart) * n : nullptr;
    views_.push_back(view);
  }
}

int CellCharts::Origin(int chart, int f) const {
  for (int g = 0; g < f; ++g) chart /= shape_.factor(g).dim + 1;
  return chart % (shape_.factor(f).dim + 1);
}

int CellCharts::ChartFor(const Barycentric& b) const {
  int chart = 0, radix = 1;
  for (int f = 0; f < shape_.numFactors(); ++f) {
    const int dim = shape_.factor(f).dim;
    const int largest = static_cast<int>(std::max_element(b.lambda[f], b.lambda[f] + dim + 1) - b.lambda[f]);
    chart += largest * radix;
    radix *= dim + 1;
  }
  return chart;
}

Barycentric CellCharts::ToBarycentric(int chart, const double* ref) const {
  Barycentric b;
  for (int f = 0; f < shape_.numFactors(); ++f) {
    FactorBarycentric(shape_, f, ref, b.lambda[f]);
    std::swap(b.lambda[f][0], b.lambda[f][Origin(chart, f)]);
  }
  return b;
}

void CellCharts::FromBarycentric(int chart, const Barycentric& b, double* ref) const {
  for (int f = 0; f < shape_.numFactors(); ++f) {
    const SimplexFactor& fac = shape_.factor(f);
    double lambda[4];
    std::copy(b.lambda[f], b.lambda[f] + 4, lambda);
    std::swap(lambda[0], lambda[Origin(chart, f)]);
    for (int i = 0; i < fac.dim; ++i) ref[fac.offset + i] = lambda[i + 1];
  }
}

}  // namespace invmap::kernels
