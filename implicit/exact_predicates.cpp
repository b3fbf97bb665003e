// Exact orientation predicates: a floating-point filter, then exact expansion
// arithmetic.
//
// An expansion is a sum x_0 + x_1 + .. + x_{n-1} of doubles, nonoverlapping
// and in increasing order of magnitude (Shewchuk 1997, section 2). TwoSum and
// TwoProduct return a rounded result and its exact error, so a sum of
// products of doubles can be represented exactly; the sign of a
// nonoverlapping expansion is the sign of its largest (last) nonzero
// component. Only GrowExpansion (Shewchuk's Theorem 10) and ScaleExpansion
// (Theorem 19) are used; both keep the nonoverlapping property for any input
// and need no assumption on the rounding tie-breaking rule. The exact paths
// are only taken when the filter fails (near-degenerate or exactly degenerate
// inputs), so they favour simplicity over speed.
//
// The file must not be compiled with FMA contraction or -ffast-math: the
// error-free transformations rely on every + - * being rounded exactly once
// (the project builds with -ffp-contract=off).
#include "implicit/exact_predicates.h"

#include <cmath>

namespace invmap::implicit {
namespace {

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff
// Shewchuk's filter bounds (section 4.2 of the paper).
constexpr double kCcwErrBoundA = (3.0 + 16.0 * kEpsilon) * kEpsilon;
constexpr double kO3dErrBoundA = (7.0 + 56.0 * kEpsilon) * kEpsilon;
// det = fl(fl(a.x b.y) - fl(a.y b.x)) has error at most
// eps (1 + eps) / (1 - eps)^2 (|a.x b.y| + |a.y b.x|)_rounded < 2 eps (...).
constexpr double kOrient2dOriginErrBound = 2.0 * kEpsilon;

inline int SignOf(double x) { return (x > 0.0) - (x < 0.0); }

/// What FilteredDifferenceSign returns when the rounded products cannot
/// decide the sign.
constexpr int kUndecided = 2;

/// The sign of left - right, two rounded products, when rounding cannot have
/// changed it: products of opposite signs (or a zero product) cannot cancel,
/// since rounding keeps signs; otherwise the difference is decided when it
/// exceeds `errBound` times the products' magnitudes.
int FilteredDifferenceSign(double left, double right, double errBound) {
  const double det = left - right;
  double sum;
  if (left > 0.0) {
    if (right <= 0.0) return SignOf(det);
    sum = left + right;
  } else if (left < 0.0) {
    if (right >= 0.0) return SignOf(det);
    sum = -left - right;
  } else {
    return SignOf(det);
  }
  const double bound = errBound * sum;
  if (det > bound || -det > bound) return SignOf(det);
  return kUndecided;
}

/// x + y = a + b exactly, x = fl(a + b).
inline void TwoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bVirtual = x - a;
  const double aVirtual = x - bVirtual;
  const double bRoundoff = b - bVirtual;
  const double aRoundoff = a - aVirtual;
  y = aRoundoff + bRoundoff;
}

/// x + y = a * b exactly, x = fl(a * b) (exact unless the product underflows).
inline void TwoProduct(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

/// A fixed-capacity expansion that other expansions are added to.
/// kCapacity bounds the number of components of any sum formed here (at most
/// 4 triple products x 6 terms x 4 components = 96 for Orient3dExact).
class Accumulator {
 public:
  static constexpr int kCapacity = 128;

  /// Adds the expansion e[0..n) (or its negation) component by component;
  /// each step is GrowExpansion with zero elimination.
  void Add(const double* e, int n, bool negate) {
    for (int i = 0; i < n; ++i) Grow(negate ? -e[i] : e[i]);
  }

  /// Sign of the sum: that of the largest nonzero component.
  int Sign() const {
    for (int i = size_ - 1; i >= 0; --i) {
      if (comp_[i] != 0.0) return SignOf(comp_[i]);
    }
    return 0;
  }

 private:
  void Grow(double b) {
    if (b == 0.0) return;
    double q = b;
    int out = 0;
    // Writing to comp_[out] with out <= i never overwrites an unread entry.
    for (int i = 0; i < size_; ++i) {
      double sum, err;
      TwoSum(q, comp_[i], sum, err);
      q = sum;
      if (err != 0.0) comp_[out++] = err;
    }
    if (q != 0.0) comp_[out++] = q;
    size_ = out;
  }

  double comp_[kCapacity];
  int size_ = 0;
};

/// h = e * b exactly (ScaleExpansion with zero elimination); e has n >= 1
/// components, h has room for 2 n. Returns the length of h (0 if the product
/// is zero).
int ScaleExpansion(const double* e, int n, double b, double* h) {
  int out = 0;
  double q, err;
  TwoProduct(e[0], b, q, err);
  if (err != 0.0) h[out++] = err;
  for (int i = 1; i < n; ++i) {
    double prodHi, prodLo, sum;
    TwoProduct(e[i], b, prodHi, prodLo);
    TwoSum(q, prodLo, sum, err);
    if (err != 0.0) h[out++] = err;
    // Shewchuk uses FastTwoSum here (|prodHi| >= |sum|); TwoSum gives the same.
    TwoSum(prodHi, sum, q, err);
    if (err != 0.0) h[out++] = err;
  }
  if (q != 0.0) h[out++] = q;
  return out;
}

/// Adds sign * a * b * c exactly to acc.
void AddTripleProduct(Accumulator& acc, double a, double b, double c, bool negate) {
  double ab[2];
  TwoProduct(a, b, ab[1], ab[0]);
  double abc[4];
  const int n = ScaleExpansion(ab, 2, c, abc);
  acc.Add(abc, n, negate);
}

/// Adds sign * a * b exactly to acc.
void AddProduct(Accumulator& acc, double a, double b, bool negate) {
  double ab[2];
  TwoProduct(a, b, ab[1], ab[0]);
  acc.Add(ab, 2, negate);
}

/// Adds det[a b c] = a . (b x c) exactly to acc (negated if asked).
void AddDet3(Accumulator& acc, const double* a, const double* b, const double* c, bool negate) {
  AddTripleProduct(acc, a[0], b[1], c[2], negate);
  AddTripleProduct(acc, a[0], b[2], c[1], !negate);
  AddTripleProduct(acc, a[1], b[2], c[0], negate);
  AddTripleProduct(acc, a[1], b[0], c[2], !negate);
  AddTripleProduct(acc, a[2], b[0], c[1], negate);
  AddTripleProduct(acc, a[2], b[1], c[0], !negate);
}

}  // namespace

namespace detail {

int Orient2dOriginExact(const double* a, const double* b) {
  Accumulator acc;
  AddProduct(acc, a[0], b[1], false);
  AddProduct(acc, a[1], b[0], true);
  return acc.Sign();
}

int Orient3dOriginExact(const double* a, const double* b, const double* c) {
  Accumulator acc;
  AddDet3(acc, a, b, c, false);
  return acc.Sign();
}

int Orient2dExact(const double* a, const double* b, const double* c) {
  // det[a - c, b - c] = det[a b] + det[b c] + det[c a] (multilinearity).
  Accumulator acc;
  AddProduct(acc, a[0], b[1], false);
  AddProduct(acc, a[1], b[0], true);
  AddProduct(acc, b[0], c[1], false);
  AddProduct(acc, b[1], c[0], true);
  AddProduct(acc, c[0], a[1], false);
  AddProduct(acc, c[1], a[0], true);
  return acc.Sign();
}

int Orient3dExact(const double* a, const double* b, const double* c, const double* d) {
  // det[a - d, b - d, c - d] = det[a b c] - det[d b c] - det[a d c] - det[a b d]
  //                          = det[a b c] - det[b c d] + det[a c d] - det[a b d]
  // (multilinearity; terms with d twice vanish). Working on the inputs
  // avoids the extra components of exact differences.
  Accumulator acc;
  AddDet3(acc, a, b, c, false);
  AddDet3(acc, b, c, d, true);
  AddDet3(acc, a, c, d, false);
  AddDet3(acc, a, b, d, true);
  return acc.Sign();
}

}  // namespace detail

int Orient1d(double a) { return SignOf(a); }

int Orient2dOrigin(const double* a, const double* b) {
  const int sign = FilteredDifferenceSign(a[0] * b[1], a[1] * b[0], kOrient2dOriginErrBound);
  return sign != kUndecided ? sign : detail::Orient2dOriginExact(a, b);
}

int Dot2dSign(const double* a, const double* b) {
  const double rotated[2] = {-b[1], b[0]};
  return Orient2dOrigin(a, rotated);
}

int Orient3dOrigin(const double* a, const double* b, const double* c) {
  const double byCz = b[1] * c[2], bzCy = b[2] * c[1];
  const double cyAz = c[1] * a[2], czAy = c[2] * a[1];
  const double ayBz = a[1] * b[2], azBy = a[2] * b[1];
  const double det = a[0] * (byCz - bzCy) + b[0] * (cyAz - czAy) + c[0] * (ayBz - azBy);
  const double perm = std::fabs(a[0]) * (std::fabs(byCz) + std::fabs(bzCy)) +
                      std::fabs(b[0]) * (std::fabs(cyAz) + std::fabs(czAy)) +
                      std::fabs(c[0]) * (std::fabs(ayBz) + std::fabs(azBy));
  const double bound = detail::kOrient3dOriginErrBound * perm;
  if (det > bound || -det > bound) return SignOf(det);
  return detail::Orient3dOriginExact(a, b, c);
}

int Orient2d(const double* a, const double* b, const double* c) {
  const int sign = FilteredDifferenceSign((a[0] - c[0]) * (b[1] - c[1]), (a[1] - c[1]) * (b[0] - c[0]), kCcwErrBoundA);
  return sign != kUndecided ? sign : detail::Orient2dExact(a, b, c);
}

int Orient3d(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double perm = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                      (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                      (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  const double bound = kO3dErrBoundA * perm;
  if (det > bound || -det > bound) return SignOf(det);
  return detail::Orient3dExact(a, b, c, d);
}

}  // namespace invmap::implicit
