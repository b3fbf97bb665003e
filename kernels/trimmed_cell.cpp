#include "kernels/trimmed_cell.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::kernels {

TrimRegion::Side TrimmedCell::ClassifySubdomain(const double* lo, const double* hi) const {
  // The own parameters are monotone in each reference coordinate, so the
  // reference box maps onto the own box of its corners; widened by the
  // rounding of the map, it holds the true image.
  double ownLo[2], ownHi[2];
  ToOwn(lo, ownLo);
  ToOwn(hi, ownHi);
  for (int d = 0; d < 2; ++d) {
    const double margin =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(ownLo[d]), std::abs(ownHi[d]));
    ownLo[d] -= margin;
    ownHi[d] += margin;
  }
  return region->ClassifyBox(ownLo, ownHi, near);
}

bool TrimmedCell::Admits(const double* ref) const {
  double own[2];
  ToOwn(ref, own);
  return region->ClassifyPoint(own) != TrimRegion::Side::Outside;
}

}  // namespace invmap::kernels
