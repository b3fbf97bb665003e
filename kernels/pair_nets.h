// Bernstein nets of the squared distance between two cells, over a pair of
// subdomains, kept factored: each side holds a few nets of its own (doubled)
// degree, and the joint net over the product of the two domains, whose
// coefficients bound the distance from below, is never stored.
//
// With the cells written homogeneously (x = N_a / W_a, y = N_b / W_b, each
// net built around its own control box's centre and turned into the common
// frame) and d the centres' difference there,
//   |x - y|^2 W_a^2 W_b^2 = Q = |d|^2 WW + a_0 (x) b_W + a_W (x) b_0 - 2 sum_k a_k (x) b_k,
//   a_0 = NN_a + 2 d . NW_a,  a_k = NW_a,k,  a_W = WW_a,
//   b_0 = NN_b - 2 d . NW_b,  b_k = NW_b,k,  b_W = WW_b,
// where (x) is the tensor product of a net of A's domain and one of B's (the
// constant |d|^2 WW is added to the bounds, never to the nets, whose
// rounding would otherwise grow with the models' separation squared): the
// joint net's coefficient (i, j) is the sum of products of coefficients i
// of A's nets and j of B's. The weight WW = a_W (x) b_W has positive
// coefficients, so min over (i, j) of Q_ij / WW_ij bounds the squared
// distance from below over the pair of subdomains. Splitting a subdomain
// splits one side's nets only; derivatives act on one side's nets only.
#pragma once

#include <vector>

#include "kernels/pair_problem.h"

namespace invmap::kernels {

class PairNets {
 public:
  /// Both sides need their DistanceNets.
  PairNets(const PairSide& a, const PairSide& b);

  /// Nets per side: a_0 (or b_0), one per ambient coordinate, the weight.
  int terms() const { return terms_; }
  /// The nets' shape on side s (the cell's degrees doubled).
  const CellShape& shape(int side) const { return shape_[side]; }
  /// Coefficients of one net of side s.
  int size(int side) const { return size_[side]; }
  /// Values of one side's nets together (terms() nets of size(side)).
  int sideLength(int side) const { return terms_ * size_[side]; }
  bool rational() const { return rational_; }
  /// True when side s is rational (else its WW net is 1).
  bool rational(int side) const { return side_[side]->nets->rational(); }

  /// The nets of the whole domains.
  void BuildRoot(double* sideA, double* sideB) const;
  /// The same nets in each cell's own frame (DistanceNets' NN, NW_k, WW:
  /// no rotation, no offset), which no motion changes: a subdomain's own
  /// nets, split as its placed ones are, give its placed nets at any later
  /// motion through Place (trackers keep subdomains so).
  void BuildRootOwn(double* sideA, double* sideB) const;
  /// Side s's nets in the common frame of this pair's motions from its own
  /// nets `own` (sideLength(s) values each): what BuildRoot does to the
  /// whole domain's. Splits and this map are linear and commute; their
  /// roundings are of the same size either way (convex combinations, a
  /// rotation and the offset's term), within RoundingSlack.
  void Place(int side, const double* own, double* out) const;
  /// Nets of side `side` on half of its subdomain (SplitNet of every net).
  void Split(int side, int factor, int vi, int vj, const double* in, double* out) const;

  /// min over (i, j) of Q_ij / WW_ij; argA, argB (optional) receive the
  /// coefficient indices that reach it.
  double LowerBound(const double* sideA, const double* sideB, std::vector<double>* scratch, int* argA = nullptr,
                    int* argB = nullptr) const;
  /// max over (i, j) of Q_ij / WW_ij: an upper bound of the squared
  /// distance over the pair of subdomains.
  double UpperBound(const double* sideA, const double* sideB) const;
  /// A lower bound of WW over the subdomains.
  double LeastWeight(const double* sideA, const double* sideB) const;
  /// An upper bound of WW over the subdomains (its largest coefficient).
  double LargestWeight(const double* sideA, const double* sideB) const;
  /// The rounding of the quotients Q_ij / WW_ij (squared distance units).
  double RoundingSlack() const { return slack_; }
  /// A's net centre minus B's, in the common frame (3 values): side A's map
  /// is its centre plus NW_A / WW_A, B's its centre plus NW_B / WW_B.
  const double* offset() const { return offset_; }

  /// Bounds of the Hessian of g = Q - level WW over the joint parameters (n
  /// x n, row-major, both triangles): the least and largest coefficient of
  /// each entry's joint net, which hold every value of that entry over the
  /// subdomains. Entries whose net is not finite get [-inf, inf]. With
  /// `boxed`, a cheaper enclosure that reads one side's nets through their
  /// ranges only (exact per coefficient of the other side): looser, but
  /// costs the sum of the nets' sizes instead of their product.
  void HessianRanges(const double* sideA, const double* sideB, double level, bool boxed, double* lo, double* hi,
                     std::vector<double>* scratch) const;
  /// Where the joint net bends most next to its least coefficient (argA,
  /// argB, from LowerBound): over every edge (vi, vj) of every simplex
  /// factor of either side, the largest absolute second difference of the
  /// quotients Q / WW along that edge through the coefficient (one-sided at
  /// the net's boundary). The net's least coefficient lies below the
  /// distance's least value by about those differences there, so splitting
  /// along that edge raises the bound most; along a valley of equal
  /// distances that runs along a parameter (a point of one model on the
  /// axis of the other's torus) the difference is zero, and the splits go
  /// across the valley. False when the net is linear along every edge there.
  bool MostBentEdgeAt(const double* sideA, const double* sideB, int argA, int argB, int* side, int* factor,
                      int* vi, int* vj) const;
  /// Bounds of the gradient of g = Q - level WW over the subdomains (n
  /// values each, in their own coordinates): each entry's joint net's least
  /// and largest coefficient.
  void GradientRanges(const double* sideA, const double* sideB, double level, double* lo, double* hi,
                      std::vector<double>* scratch) const;
  /// The same bounds for u^T H w over the columns u, w of `basis` (n x n,
  /// column c at basis[c n]): each entry from the joint net of its own
  /// directional second derivative, so a direction along which g does not
  /// change anywhere (a valley of equal distances) gets exactly zero, where
  /// combining the entries' separate bounds could not tell.
  void HessianRangesInBasis(const double* sideA, const double* sideB, double level, const double* basis, double* lo,
                            double* hi, std::vector<double>* scratch) const;

 private:
  const PairSide* side_[2];
  int ambientDim_ = 3;
  int terms_ = 0;
  CellShape shape_[2];
  int size_[2] = {0, 0};
  bool rational_ = false;
  double slack_ = 0.0;
  double rotation_[2][3][3] = {};
  double offset_[3] = {0, 0, 0};  ///< d: A's net centre minus B's, common frame.
  double shift_ = 0.0;            ///< |d|^2, which the nets leave out.
};

}  // namespace invmap::kernels
