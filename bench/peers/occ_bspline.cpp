#include "bench/peers/occ_bspline.h"

#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>

namespace invmap::bench {

void SplitKnots(const std::vector<double>& knots, TColStd_Array1OfReal* values, TColStd_Array1OfInteger* mults) {
  std::vector<double> distinct;
  std::vector<int> count;
  for (double k : knots) {
    if (distinct.empty() || k != distinct.back()) {
      distinct.push_back(k);
      count.push_back(1);
    } else {
      ++count.back();
    }
  }
  values->Resize(1, static_cast<int>(distinct.size()), false);
  mults->Resize(1, static_cast<int>(distinct.size()), false);
  for (std::size_t i = 0; i < distinct.size(); ++i) {
    values->SetValue(static_cast<int>(i) + 1, distinct[i]);
    mults->SetValue(static_cast<int>(i) + 1, count[i]);
  }
}

Handle(Geom_BSplineSurface) ToOccSurface(const Patch& patch) {
  const int nu = patch.counts[0], nv = patch.counts[1];
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double* x = &patch.points[3 * (static_cast<std::size_t>(j) * nu + i)];
      poles.SetValue(i + 1, j + 1, gp_Pnt(x[0], x[1], x[2]));
      weights.SetValue(i + 1, j + 1, patch.weights.empty() ? 1.0 : patch.weights[j * nu + i]);
    }
  }
  TColStd_Array1OfReal uKnots, vKnots;
  TColStd_Array1OfInteger uMults, vMults;
  SplitKnots(patch.knots[0], &uKnots, &uMults);
  SplitKnots(patch.knots[1], &vKnots, &vMults);
  if (patch.weights.empty()) {
    return new Geom_BSplineSurface(poles, uKnots, vKnots, uMults, vMults, patch.degrees[0], patch.degrees[1]);
  }
  return new Geom_BSplineSurface(poles, weights, uKnots, vKnots, uMults, vMults, patch.degrees[0], patch.degrees[1]);
}

}  // namespace invmap::bench
