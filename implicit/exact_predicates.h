// Exact orientation predicates on double inputs: a floating-point filter with
// a proven error bound, then an exact evaluation with floating-point
// expansions (Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates", 1997) when the filter cannot decide.
#pragma once

namespace invmap::implicit {

// Range of validity. The expansion arithmetic is exact as long as no product
// underflows or overflows. That holds when every nonzero input coordinate has
// a magnitude in [2^-300, 2^300] for the *Origin predicates and in
// [2^-200, 2^200] for Orient2d/Orient3d (their filters form differences,
// which can be much smaller than the inputs). Inputs must be finite. Zero
// coordinates are always fine.

/// Sign (-1, 0, +1) of a.
int Orient1d(double a);

/// Sign of det[a - c, b - c] with a, b, c points of the plane (x, y):
/// +1 when a, b, c turn counterclockwise, -1 clockwise, 0 when collinear.
/// Each pointer addresses two doubles.
int Orient2d(const double* a, const double* b, const double* c);

/// Sign of det[a - d, b - d, c - d] (rows a - d, b - d, c - d): +1 when d
/// lies below the plane through a, b, c oriented counterclockwise seen from
/// above (Shewchuk's convention), -1 above, 0 coplanar. Each pointer
/// addresses three doubles.
int Orient3d(const double* a, const double* b, const double* c, const double* d);

/// Sign of det[a b] = a.x b.y - a.y b.x, i.e. Orient2d(a, b, origin).
int Orient2dOrigin(const double* a, const double* b);

/// Sign of det[a b c] = a . (b x c), i.e. Orient3d(a, b, c, origin).
int Orient3dOrigin(const double* a, const double* b, const double* c);

/// Sign of the dot product a.x b.x + a.y b.y (exact; it is
/// Orient2dOrigin(a, rot90(b)) with rot90(b) = (-b.y, b.x)).
int Dot2dSign(const double* a, const double* b);

namespace detail {
/// Exact evaluations without the filter (for tests and for callers that run
/// their own filter). Same signs as the functions above.
int Orient2dOriginExact(const double* a, const double* b);
int Orient3dOriginExact(const double* a, const double* b, const double* c);
int Orient2dExact(const double* a, const double* b, const double* c);
int Orient3dExact(const double* a, const double* b, const double* c, const double* d);

/// Filter constant of Orient3dOrigin: with
///   det  = a.x (b.y c.z - b.z c.y) + b.x (c.y a.z - c.z a.y) + c.x (a.y b.z - a.z b.y)
///   perm = |a.x| (|b.y c.z| + |b.z c.y|) + |b.x| (..) + |c.x| (..)
/// both evaluated left to right in double, sign(det) is exact whenever
/// |det| > kOrient3dOriginErrBound * perm. The first-order error is 5 eps perm
/// (2 eps per 2x2 minor, 1 for the outer product, 2 for the two additions);
/// 8 eps leaves room for second-order terms and for the rounding of perm.
inline constexpr double kOrient3dOriginErrBound = 8.0 * 1.1102230246251565e-16;  // 8 * 2^-53
}  // namespace detail

}  // namespace invmap::implicit
