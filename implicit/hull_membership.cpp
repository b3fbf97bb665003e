// Exact membership of the origin in the closed convex hull of a point set.
//
// Everything below decides with signs only: signs of single coordinates, of
// rounded sums/differences of two doubles (exact: rounding is monotone and
// fl(x + y) = 0 only when x + y = 0, subnormals included), and the exact
// predicates Orient2dOrigin, Dot2dSign and Orient3dOrigin. No intermediate
// point is ever constructed, so no rounding can change an answer.
//
// Basis (Gordan's alternative): 0 is NOT in conv(P) iff some w has w.p > 0 for
// every p in P (a strictly separating plane through the origin).
//
// Cheap exits, tried first. A direction w in {+-e_x, +-e_y, +-e_z,
// +-(e_x +- e_y), ..} with w.p > 0 for all p: the sign of w.p is exact for
// these w (one coordinate, or a sum of two), so this certifies "outside";
// most cells of an adaptive grid are decided here, in one branch-free pass.
// Then a point equal to the origin: inside (such a point defeats every w, so
// the order is safe).
//
// 1D: inside iff some value <= 0 and some value >= 0.
//
// 2D (WedgeSweep2d): sweep the points keeping the smallest wedge [R, L]
// (from ray R counterclockwise to ray L) that holds every ray seen so far.
// While its opening is below pi the points seen are strictly separable; as
// soon as a new point makes the opening reach or exceed pi (p opposite to
// the single ray, or p neither inside the wedge nor within pi of either side)
// no open half-plane holds them and the origin is in the hull. The tests are
// Orient2dOrigin(R, p), Orient2dOrigin(p, L) and, for a one-ray wedge,
// Dot2dSign. O(n) predicates.
//
// 3D (GeneralHull3d). Let K = {w : w.p >= 0 for all p} (weak separators).
//  1. If w in K, w != 0, and 0 = sum l_k p_k with l >= 0, sum l = 1, then
//     sum l_k (w.p_k) = 0 forces w.p_k = 0 wherever l_k > 0: the origin is
//     in conv(P) iff it is in conv(P intersect w-perp). So ANY nonzero weak
//     separator reduces the question to 2D, exactly.
//  2. Finding one (QuotientSweep). If P spans R^3, K is a pointed polyhedral
//     cone, and if K != {0} it has an extreme ray w, orthogonal to two
//     independent points p_i, p_j. Then, in the 2D quotient R^3 / span(p_i),
//     the images q_k of all points lie in a closed half-plane (w.q >= 0).
//     Conversely, if for some i the images lie in a closed half-plane whose
//     boundary line carries the image of some p_j != 0, the plane through
//     0, p_i, p_j is a weak separator. The orientation of the quotient is
//     orient_i(x, y) = det[p_i x y] (an alternating form vanishing on p_i),
//     so for each i one sweep over the points, like the 2D one but tracking
//     the smallest cone through the states ray / wedge (opening < pi) / line
//     / closed half-plane / whole plane, decides whether such a half-plane
//     exists and names its boundary point j. The sweep stops at "whole
//     plane", typically after a few points when the origin is inside. If no
//     i admits a half-plane, K = {0}: the origin is interior. Degenerate
//     cases fall out of the same sweep: if P spans only a plane through the
//     origin, every image is on one line (state ray or line); if every point
//     is parallel to p_i, P lies on a line through the origin and the 1D
//     test on a coordinate where that line's direction is nonzero decides.
//     When a sweep reaches "whole plane" from a wedge [R, L] with a point q,
//     one more predicate, det[R L q] <= 0, shows the origin inside the
//     tetrahedron p_i, R, L, q (an exact inside witness that usually ends
//     the search after one or two sweeps).
//     In state "ray", telling q from -q when orient_i = 0 uses the sign of
//     a component of p_i x q against p_i x p_ray (exact 2x2 minors).
//  3. Deciding (DecideOnSeparator). The points on the separating plane
//     (det[p_i p_j p_k] = 0) are projected by dropping a coordinate axis
//     along which the plane's normal p_i x p_j is nonzero (a linear map
//     injective on the plane, so hull membership is preserved; no
//     arithmetic, only a choice of coordinates) and handed to the 2D test.
// Cost: O(n^2) predicates in the worst case, usually a few per point when
// the origin is inside, O(n) when a cheap exit applies. The filtered
// det[p_i p_j q] shares the cross product p_i x p_j across q.
//
// Range: the predicates are exact while products neither underflow nor
// overflow. Points whose coordinates leave [2^-256, 2^256] are rescaled, each
// by its own power of two (hull membership of the origin is invariant under
// positive scaling of individual points). The rescaling is exact, and the
// rescaled coordinates stay in range, when within each point the largest and
// smallest nonzero magnitudes differ by less than 2^290.
#include "implicit/hull_membership.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "implicit/exact_predicates.h"

namespace invmap::implicit {
namespace {

constexpr double kEpsilon = 0x1p-53;
constexpr double kRangeLow = 0x1p-256;
constexpr double kRangeHigh = 0x1p256;
// Filter of the 2x2 minor a.x b.y - a.y b.x (see Orient2dOrigin).
constexpr double kMinorErrBound = 2.0 * kEpsilon;

/// Per-call scratch: kPerPoint values per point on the stack up to
/// kMaxHullPointsOnStack points, on the heap beyond. Not initialized.
template <typename T, int kPerPoint>
class Scratch {
 public:
  explicit Scratch(int count) {
    if (count > kMaxHullPointsOnStack) heap_.resize(static_cast<std::size_t>(count) * kPerPoint);
  }
  T* data() { return heap_.empty() ? stack_ : heap_.data(); }

 private:
  T stack_[kMaxHullPointsOnStack * kPerPoint];
  std::vector<T> heap_;
};

/// out = each point of p scaled by the power of two that brings its largest
/// |coordinate| into [0.5, 1). Exact unless a coordinate is more than 2^1021
/// times smaller than its point's largest one.
void NormalizePoints(const double* p, int count, int dim, double* out) {
  for (int k = 0; k < count; ++k) {
    double largest = 0.0;
    for (int c = 0; c < dim; ++c) largest = std::fmax(largest, std::fabs(p[k * dim + c]));
    int exponent = 0;
    if (largest != 0.0) std::frexp(largest, &exponent);
    for (int c = 0; c < dim; ++c) out[k * dim + c] = std::ldexp(p[k * dim + c], -exponent);
  }
}

/// The cheap "outside" exit: true if one of the directions e_u (axes) or
/// e_u +- e_v (face diagonals), or its opposite, has a strictly positive dot
/// product with every point. Rounded sums and differences of two doubles
/// have exact signs, so this is exact. Branch-free min/max over the points.
template <int kDim>
bool SeparatedAlongFixedDirection(const double* p, int count) {
  constexpr int kDirections = kDim == 2 ? 4 : 9;
  double low[kDirections], high[kDirections];
  for (int d = 0; d < kDirections; ++d) {
    low[d] = HUGE_VAL;
    high[d] = -HUGE_VAL;
  }
  for (int k = 0; k < count; ++k) {
    const double* q = p + kDim * k;
    double s[kDirections];
    if constexpr (kDim == 2) {
      s[0] = q[0];
      s[1] = q[1];
      s[2] = q[0] + q[1];
      s[3] = q[0] - q[1];
    } else {
      s[0] = q[0];
      s[1] = q[1];
      s[2] = q[2];
      s[3] = q[0] + q[1];
      s[4] = q[0] - q[1];
      s[5] = q[1] + q[2];
      s[6] = q[1] - q[2];
      s[7] = q[2] + q[0];
      s[8] = q[2] - q[0];
    }
    for (int d = 0; d < kDirections; ++d) {
      low[d] = std::min(low[d], s[d]);
      high[d] = std::max(high[d], s[d]);
    }
  }
  bool separated = false;
  for (int d = 0; d < kDirections; ++d) separated |= (low[d] > 0.0) | (high[d] < 0.0);
  return separated;
}

/// Whether some point is the origin, and whether some nonzero coordinate
/// leaves [kRangeLow, kRangeHigh] (then the points are rescaled).
struct PointFacts {
  bool anyZero = false;
  bool needsRescale = false;
};

/// One pass over count points of dim coordinates for PointFacts.
PointFacts ScanPoints(const double* p, int count, int dim) {
  PointFacts facts;
  double maxAbs = 0.0, minAbsNonzero = HUGE_VAL;
  for (int k = 0; k < count; ++k) {
    bool zero = true;
    for (int c = 0; c < dim; ++c) {
      const double a = std::fabs(p[k * dim + c]);
      zero &= a == 0.0;
      maxAbs = std::max(maxAbs, a);
      minAbsNonzero = std::min(minAbsNonzero, a == 0.0 ? HUGE_VAL : a);
    }
    facts.anyZero |= zero;
  }
  facts.needsRescale = maxAbs > kRangeHigh || minAbsNonzero < kRangeLow;
  return facts;
}

/// The 2D sweep of the header comment on interleaved points (no cheap exits).
bool WedgeSweep2d(const double* xy, int count) {
  const double* right = xy;  // clockwise end of the wedge
  const double* left = xy;   // counterclockwise end
  if (right[0] == 0.0 && right[1] == 0.0) return true;
  bool singleRay = true;  // the wedge is one ray (right and left coincide)
  for (int k = 1; k < count; ++k) {
    const double* p = xy + 2 * k;
    if (p[0] == 0.0 && p[1] == 0.0) return true;
    if (singleRay) {
      const int s = Orient2dOrigin(right, p);
      if (s > 0) {
        left = p;
        singleRay = false;
      } else if (s < 0) {
        right = p;
        singleRay = false;
      } else if (Dot2dSign(right, p) < 0) {
        return true;  // p opposite to the ray: the origin is on the segment
      }
      continue;
    }
    const int sRight = Orient2dOrigin(right, p);
    const int sLeft = Orient2dOrigin(p, left);
    if (sRight >= 0 && sLeft >= 0) continue;  // p in the closed wedge
    if (sRight > 0) {
      left = p;  // p beyond left, within pi of right
    } else if (sLeft > 0) {
      right = p;  // p beyond right, within pi of left
    } else {
      return true;  // the opening would reach pi: no open half-plane holds them all
    }
  }
  return false;
}

/// The plane through the origin, a and b, for signs of det[a b q] = q . (a x b)
/// with the cross product computed once and reused for every q.
struct OriginPlane {
  const double* a = nullptr;
  const double* b = nullptr;
  double normal[3] = {0.0, 0.0, 0.0};  ///< a x b, rounded
  double bound[3] = {0.0, 0.0, 0.0};   ///< per component, |first product| + |second product|

  OriginPlane() = default;
  OriginPlane(const double* pa, const double* pb) : a(pa), b(pb) {
    // Component c is a[u] b[v] - a[v] b[u] with (u, v) = (c + 1, c + 2) mod 3.
    const double x1 = a[1] * b[2], x2 = a[2] * b[1];
    const double y1 = a[2] * b[0], y2 = a[0] * b[2];
    const double z1 = a[0] * b[1], z2 = a[1] * b[0];
    normal[0] = x1 - x2;
    normal[1] = y1 - y2;
    normal[2] = z1 - z2;
    bound[0] = std::fabs(x1) + std::fabs(x2);
    bound[1] = std::fabs(y1) + std::fabs(y2);
    bound[2] = std::fabs(z1) + std::fabs(z2);
  }

  /// Exact sign of det[a b q]: the filter of Orient3dOrigin with the minors
  /// shared across q (same evaluation order, same error bound), then the
  /// exact expansion.
  int Sign(const double* q) const {
    const double det = q[0] * normal[0] + q[1] * normal[1] + q[2] * normal[2];
    const double perm =
        std::fabs(q[0]) * bound[0] + std::fabs(q[1]) * bound[1] + std::fabs(q[2]) * bound[2];
    const double errBound = detail::kOrient3dOriginErrBound * perm;
    if (det > errBound) return 1;
    if (-det > errBound) return -1;
    return detail::Orient3dOriginExact(a, b, q);
  }

  /// Index (0, 1, 2) of a nonzero component of a x b, or -1 if a x b = 0
  /// (a, b and the origin collinear).
  int NonzeroAxis() const {
    for (int c = 0; c < 3; ++c) {
      if (std::fabs(normal[c]) > kMinorErrBound * bound[c]) return c;
    }
    for (int c = 0; c < 3; ++c) {
      if (CrossComponentSign(a, b, c) != 0) return c;
    }
    return -1;
  }

  /// Exact sign of component c of x x y.
  static int CrossComponentSign(const double* x, const double* y, int c) {
    const int u = (c + 1) % 3, v = (c + 2) % 3;
    const double x2[2] = {x[u], x[v]};
    const double y2[2] = {y[u], y[v]};
    return Orient2dOrigin(x2, y2);
  }
};

/// All points nonzero and on one line through the origin.
bool CollinearHull(const double* p, int count) {
  int axis = 0;
  while (axis < 2 && p[axis] == 0.0) ++axis;
  bool nonPositive = false, nonNegative = false;
  for (int k = 0; k < count; ++k) {
    const double v = p[3 * k + axis];
    nonPositive |= v <= 0.0;
    nonNegative |= v >= 0.0;
  }
  return nonPositive && nonNegative;
}

constexpr int kNoSeparator = -2;  ///< QuotientSweep: the quotient points span the plane
constexpr int kAllParallel = -1;  ///< QuotientSweep: every point is parallel to p_i
constexpr int kInsideWitness = -3;  ///< QuotientSweep: found a tetrahedron holding the origin

/// Step 2 of the header comment for point i: sweeps the images q_k of the
/// points in R^3 / span(p_i), whose orientation is
/// orient_i(x, y) = det[p_i x y], keeping the smallest cone that holds them
/// while it is not the whole plane. Returns the index j of a point such that
/// the plane through 0, p_i, p_j is a weak separator (all det[p_i p_j p_k]
/// >= 0 or all <= 0), kNoSeparator if no weak separator is orthogonal to
/// p_i, kInsideWitness if it met four points whose tetrahedron holds the
/// origin, or kAllParallel.
int QuotientSweep(const double* p, int count, int i) {
  const double* a = p + 3 * i;
  // The first point with a nonzero image starts the cone as a single ray.
  int first = 0;
  OriginPlane planeR;
  int rayAxis = -1;
  for (; first < count; ++first) {
    if (first == i) continue;
    planeR = OriginPlane(a, p + 3 * first);
    rayAxis = planeR.NonzeroAxis();
    if (rayAxis >= 0) break;
  }
  if (first == count) return kAllParallel;

  enum class Cone { kRay, kWedge, kLine, kHalfPlane };
  Cone cone = Cone::kRay;
  int right = first;  // the ray, the wedge's clockwise end, or the boundary line
  OriginPlane planeL;  // the wedge's counterclockwise end
  int left = first;
  int side = 0;  // kHalfPlane: the cone is {x : side * orient_i(right, x) >= 0}
  for (int k = first + 1; k < count; ++k) {
    if (k == i) continue;
    const double* q = p + 3 * k;
    switch (cone) {
      case Cone::kRay: {
        const int s = planeR.Sign(q);  // orient_i(right, q)
        if (s > 0) {
          left = k;
          planeL = OriginPlane(a, q);
          cone = Cone::kWedge;
        } else if (s < 0) {
          left = right;
          planeL = planeR;
          right = k;
          planeR = OriginPlane(a, q);
          cone = Cone::kWedge;
        } else {
          // q = c p_right + t p_i: c has the sign of (p_i x q) / (p_i x p_right)
          // along an axis where the latter is nonzero; c = 0 means q's image is 0.
          const int c = OriginPlane::CrossComponentSign(a, q, rayAxis) *
                        OriginPlane::CrossComponentSign(a, p + 3 * right, rayAxis);
          if (c < 0) cone = Cone::kLine;
        }
        break;
      }
      case Cone::kWedge: {
        const int sRight = planeR.Sign(q);   // orient_i(right, q)
        const int sLeft = -planeL.Sign(q);   // orient_i(q, left)
        if (sRight >= 0 && sLeft >= 0) break;  // in the closed wedge (or image 0)
        if (sRight > 0) {
          left = k;
          planeL = OriginPlane(a, q);
        } else if (sLeft > 0) {
          right = k;
          planeR = OriginPlane(a, q);
        } else if (sRight == 0) {
          side = 1;  // q opposite right: the half-plane left of right's line
          cone = Cone::kHalfPlane;
        } else if (sLeft == 0) {
          right = left;  // q opposite left: the half-plane right of left's line
          planeR = planeL;
          side = -1;
          cone = Cone::kHalfPlane;
        } else {
          // Every gap between the rays is below pi. Inside witness: with
          // (a, b, c, d) = (p_i, p_right, p_left, q), the numerators
          // mu = (det[b c d], -det[a c d], det[a b d], -det[a b c]) satisfy
          // sum mu_k v_k = 0; the last three are sLeft < 0, sRight < 0 and
          // -orient_i(right, left) < 0, so det[b c d] <= 0 puts the origin
          // in the tetrahedron. Otherwise +p_i, not -p_i, is in the cone of
          // b, c, d and nothing is concluded.
          if (Orient3dOrigin(p + 3 * right, p + 3 * left, q) <= 0) return kInsideWitness;
          return kNoSeparator;
        }
        break;
      }
      case Cone::kLine: {
        const int s = planeR.Sign(q);
        if (s != 0) {
          side = s;
          cone = Cone::kHalfPlane;
        }
        break;
      }
      case Cone::kHalfPlane: {
        const int s = planeR.Sign(q);
        if (s != 0 && s != side) return kNoSeparator;
        break;
      }
    }
  }
  return right;
}

/// Step 3: the plane through 0, p_i, p_j is a weak separator; the origin is
/// in the hull iff it is in the hull of the points on that plane.
bool DecideOnSeparator(const double* p, int count, int i, int j) {
  const OriginPlane plane(p + 3 * i, p + 3 * j);
  const int dropAxis = plane.NonzeroAxis();
  const int u = (dropAxis + 1) % 3, v = (dropAxis + 2) % 3;
  Scratch<double, 2> projected(count);
  double* q = projected.data();
  int m = 0;
  for (int k = 0; k < count; ++k) {
    if (k != i && k != j && plane.Sign(p + 3 * k) != 0) continue;
    q[2 * m] = p[3 * k + u];
    q[2 * m + 1] = p[3 * k + v];
    ++m;
  }
  return OriginInConvexHull2d(q, m);
}

/// Steps 2 and 3 of the header comment; no point is the origin.
bool GeneralHull3d(const double* p, int count) {
  for (int i = 0; i < count; ++i) {
    const int j = QuotientSweep(p, count, i);
    if (j == kNoSeparator) continue;
    if (j == kInsideWitness) return true;
    if (j == kAllParallel) return CollinearHull(p, count);
    return DecideOnSeparator(p, count, i, j);
  }
  return true;  // no weak separator: the origin is interior
}

}  // namespace

bool OriginInConvexHull1d(const double* values, int count) {
  bool nonPositive = false, nonNegative = false;
  for (int k = 0; k < count; ++k) {
    nonPositive |= values[k] <= 0.0;
    nonNegative |= values[k] >= 0.0;
  }
  return nonPositive && nonNegative;
}

bool OriginInConvexHull2d(const double* xy, int count) {
  if (count <= 0) return false;
  // A point at the origin defeats every fixed direction, so testing it
  // after them is safe.
  if (SeparatedAlongFixedDirection<2>(xy, count)) return false;
  const PointFacts facts = ScanPoints(xy, count, 2);
  if (facts.anyZero) return true;
  if (!facts.needsRescale) return WedgeSweep2d(xy, count);
  Scratch<double, 2> scaled(count);
  NormalizePoints(xy, count, 2, scaled.data());
  return WedgeSweep2d(scaled.data(), count);
}

bool OriginInConvexHull3d(const double* xyz, int count) {
  if (count <= 0) return false;
  if (SeparatedAlongFixedDirection<3>(xyz, count)) return false;
  const PointFacts facts = ScanPoints(xyz, count, 3);
  if (facts.anyZero) return true;
  if (!facts.needsRescale) return GeneralHull3d(xyz, count);
  Scratch<double, 3> scaled(count);
  NormalizePoints(xyz, count, 3, scaled.data());
  return GeneralHull3d(scaled.data(), count);
}

}  // namespace invmap::implicit
