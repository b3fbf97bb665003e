// Scalar Bernstein nets on a cell's reference domain: products, subdivision,
// derivatives and a convexity test, all exact linear rules on coefficients.
#pragma once

#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// Number of coefficients of a scalar net on `shape` (= its control points).
inline int NetSize(const CellShape& shape) { return shape.numControlPoints(); }

/// Product of two scalar nets on the same cell type: `out` gets the net of
/// shape a with degrees a + b. `out` must hold NetSize of the product shape.
void MultiplyNets(const CellShape& a, const double* netA, const CellShape& b, const double* netB, double* out);

/// The net of the same polynomial on half of the domain: factor `factor` of
/// the reference domain is bisected at the midpoint of its edge (i, j)
/// (barycentric vertex indices), and the half that keeps vertex i (vertex j
/// moves to the midpoint) is returned in the factor's new local coordinates.
/// For a line factor, edge (0, 1) keeping 0 is [0, 1/2]. Exact (dyadic) rules.
/// `in` and `out` must not overlap.
void SplitNet(const CellShape& shape, int factor, int i, int j, const double* in, double* out);

/// The edge (vi, vj) of factor `factor`'s simplex along which the positive
/// net `w` changes by the largest ratio between neighbouring coefficients
/// (multi-indices one unit moved from vi to vj), and that ratio (1 when `w`
/// is constant; then the edge is (0, 1) of factor 0).
double SteepestRatioEdge(const CellShape& shape, const double* w, int* factor, int* vi, int* vj);

/// The same for the largest absolute difference between neighbouring
/// coefficients of `values` (0 and edge (0, 1) of factor 0 when constant).
double SteepestDifferenceEdge(const CellShape& shape, const double* values, int* factor, int* vi, int* vj);

/// The line factor `factor` of a tensor product of lines (every factor's
/// dim is 1) along which the net q - level ww (q alone when `ww` is null)
/// bends most: the largest absolute second difference of three
/// coefficients in a row along it, and that difference (0 and factor 0
/// when the net is linear along every line).
/// A net's least coefficient stays below its function's least value by
/// about its second differences, so this is the line whose split tightens
/// that bound most.
double MostBentLine(const CellShape& shape, const double* q, const double* ww, double level, int* factor);

/// The net of the derivative along free coordinate `dir` (0-based, local to
/// `factor`) of a scalar net; the result has that factor's degree lowered by
/// one (`outShape`). Precondition: the factor's degree is at least 1.
void DifferentiateNet(const CellShape& shape, int factor, int dir, const double* in, double* out,
                      CellShape* outShape);

/// Consecutive rows of one Hessian entry's net that apply the same rule at
/// consecutive places: row k of the run (k < length) is
/// sum over t < terms of weight[t] * f[first + k + offset[t]], summed in order
/// of t (offsets ascending, as the sparse rule of a row lists them). Runs turn
/// per-row index lists into strided loops: a line factor's differences give
/// one run per line of the net, or a single run for the whole net.
struct HessianRun {
  /// Most terms in a row: two differences of two terms each.
  static constexpr int kMaxTerms = 4;
  int first = 0;
  int length = 0;
  int terms = 0;
  int offset[kMaxTerms] = {};
  double weight[kMaxTerms] = {};
};

/// Rounding carried by a net's coefficients: coefficient i is off by at most
/// scale * weights[i]. No weights: the coefficients are taken as exact.
struct NetNoise {
  const double* weights = nullptr;
  double scale = 0.0;
};

/// The second-derivative nets of every net of one shape, as runs of short
/// difference rules on its coefficients, and the convexity test built on
/// them. Shared by all cells of a shape (Get is thread-safe; immutable).
class HessianStencil {
 public:
  static const HessianStencil& Get(const CellShape& shape);

  /// True when the function with net `f` is strictly convex on the whole
  /// domain of the net, proved from the intervals [lo_ab, hi_ab] of the
  /// second-derivative nets' coefficients (which hold every Hessian's
  /// entries) by IntervalMatrixIsPositive. With `noise`, each coefficient of
  /// those nets is widened by the rounding its rule gathers from f's.
  bool IsConvex(const double* f, const NetNoise& noise = NetNoise{}) const;

  /// The least and largest coefficient of every second-derivative net of
  /// `f` (entries a <= b of lo and hi; entries of identically zero nets
  /// are 0): bounds of the Hessian of f over the whole domain. An entry with
  /// a row that is not finite (overflow) gets [-infinity, +infinity].
  void HessianRanges(const double* f, double lo[3][3], double hi[3][3]) const;

 private:
  explicit HessianStencil(const CellShape& shape);

  /// The rows of entry (a, b), a <= b; empty when the entry is identically zero.
  struct Entry {
    std::vector<HessianRun> runs;
  };
  /// Min and max of the rows of `entry`, each widened by its rounding under
  /// `noise` ([-inf, +inf] when a row is not finite); false as soon as a row
  /// is <= 0 or not finite when `positive` is asked for (a diagonal entry
  /// that already fails).
  static bool RowRange(const Entry& entry, const double* f, const NetNoise& noise, bool positive, double* lo,
                       double* hi);

  int paramDim_ = 0;
  Entry entries_[3][3];  // a <= b only
};

}  // namespace invmap::kernels
