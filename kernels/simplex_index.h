// Multi-indices of Bernstein polynomials on a simplex, in docs/formats.md order.
#pragma once

#include <array>
#include <vector>

namespace invmap::kernels {

/// Highest degree of any Bernstein net (products of two degree-kMaxDegree
/// maps, as in the squared-distance nets, reach twice kMaxDegree).
constexpr int kMaxNetDegree = 16;

/// The Bernstein multi-indices of one simplex factor of dimension `dim`
/// (1..3) and degree `degree` (0..kMaxNetDegree).
///
/// A multi-index is stored in full barycentric form a = (a0, a1, .., ad) with
/// a0 = degree - (a1 + .. + ad). They are listed with a1 fastest, then a2,
/// then a3 (docs/formats.md section 1), so position k in this list is the position
/// of the control point in a cell's net.
class SimplexIndex {
 public:
  /// The shared, immutable table for (dim, degree); thread-safe.
  static const SimplexIndex& Get(int dim, int degree);

  int dim() const { return dim_; }
  int degree() const { return degree_; }
  int size() const { return static_cast<int>(multi_.size()); }
  /// Full barycentric multi-index (a0..a_dim) of position k.
  const std::array<int, 4>& multi(int k) const { return multi_[k]; }
  /// Position of the multi-index with free entries (a1..a_dim); entries past
  /// `dim` are ignored. Precondition: the entries sum to at most degree().
  int Position(int a1, int a2 = 0, int a3 = 0) const {
    return position_[a1 + stride_ * (a2 + stride_ * a3)];
  }
  /// Position of a full barycentric multi-index.
  int Position(const std::array<int, 4>& a) const { return Position(a[1], a[2], a[3]); }
  /// Multinomial coefficient degree! / (a0! .. ad!) of position k.
  double multinomial(int k) const { return multinomial_[k]; }

 private:
  SimplexIndex(int dim, int degree);

  int dim_;
  int degree_;
  int stride_;
  std::vector<std::array<int, 4>> multi_;
  std::vector<int> position_;
  std::vector<double> multinomial_;
};

/// Binomial coefficient C(n, k) as a double (exact for n <= 60).
double Binomial(int n, int k);

}  // namespace invmap::kernels
