// The minimum of many doubles, folded in several independent chains.
#pragma once

#include <algorithm>

namespace invmap::kernels {

/// Independent comparison chains: one chain waits out each comparison's
/// latency, four keep the pipeline busy. Every chain folds with std::min, so
/// a NaN never enters and the result is the value a sequential fold gives
/// (when +0 and -0 tie, either may come back).
constexpr int kFoldChains = 4;

/// The minimum of `init` and `values[0..n)`.
inline double FoldMin(int n, const double* values, double init) {
  double l[kFoldChains];
  std::fill(l, l + kFoldChains, init);
  int i = 0;
  for (; i + kFoldChains <= n; i += kFoldChains) {
    for (int c = 0; c < kFoldChains; ++c) l[c] = std::min(l[c], values[i + c]);
  }
  for (; i < n; ++i) l[0] = std::min(l[0], values[i]);
  return std::min(std::min(l[0], l[1]), std::min(l[2], l[3]));
}

}  // namespace invmap::kernels
