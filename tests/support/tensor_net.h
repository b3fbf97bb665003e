// A tensor-product Bernstein net evaluated straight from the Bernstein
// definition, independent of the library's kernels: the reference of the
// certificate tests.
#pragma once

#include <cmath>
#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::testing {

inline double Binomial(int n, int k) {
  double b = 1.0;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

/// A tensor Bernstein net of degrees deg[0..dims), first direction fastest.
struct Net {
  int dims;
  int deg[3];
  std::vector<double> c;

  int Size(int d) const { return d < dims ? deg[d] + 1 : 1; }

  double operator()(const double* t) const {
    double sum = 0.0;
    for (int k = 0; k < Size(2); ++k) {
      for (int j = 0; j < Size(1); ++j) {
        for (int i = 0; i < Size(0); ++i) {
          const int idx[3] = {i, j, k};
          double b = 1.0;
          for (int d = 0; d < dims; ++d) {
            b *= Binomial(deg[d], idx[d]) * std::pow(t[d], idx[d]) * std::pow(1 - t[d], deg[d] - idx[d]);
          }
          sum += b * c[i + Size(0) * (j + Size(1) * k)];
        }
      }
    }
    return sum;
  }

  kernels::CellShape Shape() const {
    return dims == 2 ? kernels::CellShape(kernels::CellType::Quad, {deg[0], deg[1], 0})
                     : kernels::CellShape(kernels::CellType::Hex, {deg[0], deg[1], deg[2]});
  }
};

/// Samples t on a grid of `steps` per direction; calls visit(t).
template <typename Visit>
void ForGrid(int dims, int steps, Visit visit) {
  const int total = dims == 2 ? steps * steps : steps * steps * steps;
  for (int s = 0; s < total; ++s) {
    double t[3] = {0, 0, 0};
    int rest = s;
    for (int d = 0; d < dims; ++d) {
      t[d] = static_cast<double>(rest % steps) / (steps - 1);
      rest /= steps;
    }
    visit(t);
  }
}

}  // namespace invmap::testing
