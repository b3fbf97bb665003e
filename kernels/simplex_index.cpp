#include "kernels/simplex_index.h"

#include <memory>
#include <mutex>

namespace invmap::kernels {

double Binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double c = 1.0;
  for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

SimplexIndex::SimplexIndex(int dim, int degree)
    : dim_(dim), degree_(degree), stride_(degree + 1) {
  position_.assign(static_cast<size_t>(stride_) * stride_ * stride_, -1);
  const int a2Max = dim >= 2 ? degree : 0;
  const int a3Max = dim >= 3 ? degree : 0;
  for (int a3 = 0; a3 <= a3Max; ++a3) {
    for (int a2 = 0; a2 + a3 <= a2Max; ++a2) {
      for (int a1 = 0; a1 + a2 + a3 <= degree; ++a1) {
        const std::array<int, 4> a{degree - a1 - a2 - a3, a1, a2, a3};
        position_[a1 + stride_ * (a2 + stride_ * a3)] = static_cast<int>(multi_.size());
        multi_.push_back(a);
        // degree! / (a0! a1! a2! a3!) as a product of binomials.
        double m = Binomial(degree, a[0]);
        int rest = degree - a[0];
        for (int k = 1; k <= dim; ++k) {
          m *= Binomial(rest, a[k]);
          rest -= a[k];
        }
        multinomial_.push_back(m);
      }
    }
  }
}

const SimplexIndex& SimplexIndex::Get(int dim, int degree) {
  // Built once, on first use, for every (dim, degree): the tables are small.
  static std::once_flag once;
  static std::unique_ptr<SimplexIndex> tables[3][kMaxNetDegree + 1];
  std::call_once(once, [] {
    for (int d = 1; d <= 3; ++d) {
      for (int p = 0; p <= kMaxNetDegree; ++p) tables[d - 1][p].reset(new SimplexIndex(d, p));
    }
  });
  return *tables[dim - 1][degree];
}

}  // namespace invmap::kernels
