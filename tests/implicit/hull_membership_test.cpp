// Exact predicates and origin-in-hull membership, checked against references
// computed independently here in exact integer arithmetic (__int128 on
// integer or dyadic inputs small enough that no product overflows).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "implicit/exact_predicates.h"
#include "implicit/hull_membership.h"

namespace invmap::implicit {
namespace {

__extension__ typedef __int128 Int128;

int SignOf(Int128 v) { return (v > 0) - (v < 0); }

/// v * 2^shift as an integer; the test fails if that is not exact or exceeds 2^62.
Int128 Scaled(double v, int shift) {
  const double s = std::ldexp(v, shift);
  EXPECT_EQ(s, std::trunc(s)) << "input " << v << " is not a multiple of 2^-" << shift;
  EXPECT_LE(std::fabs(s), 0x1p62) << "input " << v << " too large for the reference";
  return static_cast<Int128>(static_cast<std::int64_t>(s));
}

/// Exact sign of det[a - c, b - c]; inputs are multiples of 2^-shift below 2^58 once scaled.
int ReferenceOrient2d(const double* a, const double* b, const double* c, int shift) {
  const Int128 ax = Scaled(a[0], shift) - Scaled(c[0], shift), ay = Scaled(a[1], shift) - Scaled(c[1], shift);
  const Int128 bx = Scaled(b[0], shift) - Scaled(c[0], shift), by = Scaled(b[1], shift) - Scaled(c[1], shift);
  return SignOf(ax * by - ay * bx);
}

/// Exact sign of det[a - d, b - d, c - d]; scaled inputs below 2^40.
int ReferenceOrient3d(const double* a, const double* b, const double* c, const double* d, int shift) {
  Int128 u[3], v[3], w[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = Scaled(a[i], shift) - Scaled(d[i], shift);
    v[i] = Scaled(b[i], shift) - Scaled(d[i], shift);
    w[i] = Scaled(c[i], shift) - Scaled(d[i], shift);
  }
  return SignOf(u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
                u[2] * (v[0] * w[1] - v[1] * w[0]));
}

int NaiveOrient2d(const double* a, const double* b, const double* c) {
  const double det = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
  return (det > 0) - (det < 0);
}

int NaiveOrient3d(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0]);
  return (det > 0) - (det < 0);
}

// ---------------------------------------------------------------- predicates

TEST(ExactPredicates, Orient1d) {
  EXPECT_EQ(Orient1d(0.0), 0);
  EXPECT_EQ(Orient1d(-0.0), 0);
  EXPECT_EQ(Orient1d(0x1p-1074), 1);
  EXPECT_EQ(Orient1d(-3.0), -1);
}

// Shewchuk's classic example: a on a 2^-53-spaced grid near (0.5, 0.5),
// b = (12, 12), c = (24, 24). Naive evaluation gets many signs wrong.
TEST(ExactPredicates, Orient2dNearCollinearGrid) {
  const double u = 0x1p-53;
  const double b[2] = {12.0, 12.0}, c[2] = {24.0, 24.0};
  int naiveWrong = 0, checked = 0;
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 256; ++j) {
      const double a[2] = {0.5 + i * u, 0.5 + j * u};
      const int expected = ReferenceOrient2d(a, b, c, 53);
      ASSERT_EQ(Orient2d(a, b, c), expected) << "i=" << i << " j=" << j;
      // Cyclic permutations keep the sign, swaps flip it.
      ASSERT_EQ(Orient2d(b, c, a), expected);
      ASSERT_EQ(Orient2d(c, a, b), expected);
      ASSERT_EQ(Orient2d(b, a, c), -expected);
      ASSERT_EQ(detail::Orient2dExact(a, b, c), expected);
      naiveWrong += NaiveOrient2d(a, b, c) != expected;
      ++checked;
    }
  }
  EXPECT_GT(naiveWrong, checked / 10) << "the grid should defeat naive evaluation";
}

// Orient2dOrigin and Dot2dSign near degenerate. Consecutive Fibonacci
// numbers give det[(F(n+1), F(n)), (F(n), F(n-1))] = +-1 (Cassini) with
// products near 2^80, far beyond what double products resolve.
TEST(ExactPredicates, Orient2dOriginAndDotNearDegenerate) {
  std::int64_t fib[61] = {0, 1};
  for (int i = 2; i <= 60; ++i) fib[i] = fib[i - 1] + fib[i - 2];
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> index(30, 59), kind(0, 2), sign(0, 1);
  int naiveWrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = index(rng);
    const std::int64_t s = sign(rng) ? 1 : -1, t = sign(rng) ? 1 : -1;
    const std::int64_t ax = s * fib[n + 1], ay = t * fib[n];
    std::int64_t bx, by;
    switch (kind(rng)) {
      case 0:  // Cassini: det = +-1
        bx = s * fib[n];
        by = t * fib[n - 1];
        break;
      case 1:  // exactly parallel
        bx = -ax;
        by = -ay;
        break;
      default:  // Cassini neighbour shifted along a: det = +-1 still
        bx = s * fib[n] + ax;
        by = t * fib[n - 1] + ay;
    }
    // Integers below 2^42 scaled by 2^-20: dyadic, exactly representable.
    const double a[2] = {std::ldexp(double(ax), -20), std::ldexp(double(ay), -20)};
    const double b[2] = {std::ldexp(double(bx), -20), std::ldexp(double(by), -20)};
    const int expected = SignOf(Int128(ax) * by - Int128(ay) * bx);
    ASSERT_EQ(Orient2dOrigin(a, b), expected) << trial;
    ASSERT_EQ(Orient2dOrigin(b, a), -expected) << trial;
    ASSERT_EQ(detail::Orient2dOriginExact(a, b), expected) << trial;
    const double origin[2] = {0.0, 0.0};
    ASSERT_EQ(Orient2d(a, b, origin), expected) << trial;
    const double det = a[0] * b[1] - a[1] * b[0];
    naiveWrong += ((det > 0) - (det < 0)) != expected;
    // Dot product: (F(n+1), F(n)) . (F(n-1), -F(n)) = +-1.
    const std::int64_t px = s * fib[n - 1], py = -t * fib[n];
    const double q[2] = {std::ldexp(double(px), -20), std::ldexp(double(py), -20)};
    const int dotExpected = SignOf(Int128(ax) * px + Int128(ay) * py);
    ASSERT_NE(dotExpected, 0);
    ASSERT_EQ(Dot2dSign(a, q), dotExpected) << trial;
    ASSERT_EQ(Dot2dSign(q, a), dotExpected) << trial;
  }
  EXPECT_GT(naiveWrong, 1000);
}

// d = a + s (b - a) + t (c - a) + one unit in one coordinate: coplanar or
// one unit off the plane, with 38-bit integer coordinates scaled by 2^-30.
TEST(ExactPredicates, Orient3dNearCoplanar) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t{1} << 35), std::int64_t{1} << 35);
  std::uniform_int_distribution<int> small(-3, 3), delta(-1, 1), axis(0, 2);
  int naiveWrong = 0, nonzero = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::int64_t ia[3], ib[3], ic[3], id[3];
    for (int i = 0; i < 3; ++i) {
      ia[i] = coord(rng);
      ib[i] = coord(rng);
      ic[i] = coord(rng);
    }
    const int s = small(rng), t = small(rng);
    for (int i = 0; i < 3; ++i) id[i] = ia[i] + s * (ib[i] - ia[i]) + t * (ic[i] - ia[i]);
    id[axis(rng)] += delta(rng);
    double a[3], b[3], c[3], d[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::ldexp(double(ia[i]), -30);
      b[i] = std::ldexp(double(ib[i]), -30);
      c[i] = std::ldexp(double(ic[i]), -30);
      d[i] = std::ldexp(double(id[i]), -30);
    }
    const int expected = ReferenceOrient3d(a, b, c, d, 30);
    ASSERT_EQ(Orient3d(a, b, c, d), expected) << trial;
    ASSERT_EQ(Orient3d(b, c, a, d), expected) << trial;
    ASSERT_EQ(Orient3d(b, a, c, d), -expected) << trial;
    ASSERT_EQ(Orient3d(a, b, d, c), -expected) << trial;
    ASSERT_EQ(detail::Orient3dExact(a, b, c, d), expected) << trial;
    naiveWrong += NaiveOrient3d(a, b, c, d) != expected;
    nonzero += expected != 0;
  }
  EXPECT_GT(naiveWrong, 0);
  EXPECT_GT(nonzero, 0);
}

// c = s a + t b + one unit: det[a b c] near zero with 38-bit coordinates.
TEST(ExactPredicates, Orient3dOriginNearDegenerate) {
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t{1} << 36), std::int64_t{1} << 36);
  std::uniform_int_distribution<int> small(-3, 3), delta(-1, 1), axis(0, 2);
  int naiveWrong = 0;
  const double origin[3] = {0.0, 0.0, 0.0};
  for (int trial = 0; trial < 20000; ++trial) {
    std::int64_t ia[3], ib[3], ic[3];
    const int s = small(rng), t = small(rng);
    for (int i = 0; i < 3; ++i) {
      ia[i] = coord(rng);
      ib[i] = coord(rng);
      ic[i] = s * ia[i] + t * ib[i];
    }
    ic[axis(rng)] += delta(rng);
    double a[3], b[3], c[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::ldexp(double(ia[i]), -7);
      b[i] = std::ldexp(double(ib[i]), -7);
      c[i] = std::ldexp(double(ic[i]), -7);
    }
    const int expected = ReferenceOrient3d(a, b, c, origin, 7);
    ASSERT_EQ(Orient3dOrigin(a, b, c), expected) << trial;
    ASSERT_EQ(Orient3dOrigin(c, a, b), expected) << trial;
    ASSERT_EQ(Orient3dOrigin(b, a, c), -expected) << trial;
    ASSERT_EQ(detail::Orient3dOriginExact(a, b, c), expected) << trial;
    ASSERT_EQ(Orient3d(a, b, c, origin), expected) << trial;
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + b[0] * (c[1] * a[2] - c[2] * a[1]) +
                       c[0] * (a[1] * b[2] - a[2] * b[1]);
    naiveWrong += ((det > 0) - (det < 0)) != expected;
  }
  EXPECT_GT(naiveWrong, 0);
}

// Filtered and exact paths agree on random inputs over a wide exponent range
// (where the filter decides, its answer is proven; this checks the exact path
// against it, including cancellation-free large and tiny magnitudes).
TEST(ExactPredicates, FilterAndExactAgreeOverWideRange) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  // Magnitudes stay inside the documented ranges: 2^+-300 for the origin
  // predicates, 2^+-200 for the general ones.
  std::uniform_int_distribution<int> spread(-50, 50), originExponent(-200, 200), generalExponent(-100, 100);
  for (int trial = 0; trial < 20000; ++trial) {
    double p[4][3];
    for (auto& point : p) {
      for (double& v : point) v = std::ldexp(mantissa(rng), (trial % 2) ? spread(rng) : 0);
    }
    // Origin predicates: each vector may carry its own power of two.
    double q[3][3];
    for (int k = 0; k < 3; ++k) {
      const int e = originExponent(rng);
      for (int i = 0; i < 3; ++i) q[k][i] = std::ldexp(p[k][i], e);
    }
    ASSERT_EQ(Orient3dOrigin(q[0], q[1], q[2]), detail::Orient3dOriginExact(q[0], q[1], q[2])) << trial;
    ASSERT_EQ(Orient2dOrigin(q[0], q[1]), detail::Orient2dOriginExact(q[0], q[1])) << trial;
    // General predicates: one common power of two.
    const int e = generalExponent(rng);
    double g[4][3];
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < 3; ++i) g[k][i] = std::ldexp(p[k][i], e);
    }
    ASSERT_EQ(Orient3d(g[0], g[1], g[2], g[3]), detail::Orient3dExact(g[0], g[1], g[2], g[3])) << trial;
    ASSERT_EQ(Orient2d(g[0], g[1], g[2]), detail::Orient2dExact(g[0], g[1], g[2])) << trial;
  }
}

TEST(ExactPredicates, ExactZerosAndSymmetries) {
  const double a[3] = {0.1, 0.2, 0.3}, b[3] = {0.4, 0.5, 0.6}, z[3] = {0.0, 0.0, 0.0};
  EXPECT_EQ(Orient3dOrigin(a, a, b), 0);
  EXPECT_EQ(Orient3dOrigin(a, b, z), 0);
  EXPECT_EQ(Orient2dOrigin(a, a), 0);
  EXPECT_EQ(Orient2d(a, b, a), 0);
  EXPECT_EQ(Orient3d(a, b, z, a), 0);
  // Doubling is exact, so these are exactly collinear with the origin.
  const double twice[2] = {0.2, 0.4};
  EXPECT_EQ(Orient2dOrigin(a, twice), 0);
  const double p1[2] = {0.1, 0.3}, p2[2] = {0.2, 0.6};  // 0.6 = 2 * 0.3 exactly
  EXPECT_EQ(Orient2dOrigin(p1, p2), 0);
  const double e0[3] = {1, 0, 0}, e1[3] = {0, 1, 0}, e2[3] = {0, 0, 1};
  EXPECT_EQ(Orient3dOrigin(e0, e1, e2), 1);
  EXPECT_EQ(Orient3d(e0, e1, e2, z), 1);  // Shewchuk: z below the ccw plane e0 e1 e2
}

// ---------------------------------------------------------------- reference hull

using P2 = std::array<std::int64_t, 2>;
using P3 = std::array<std::int64_t, 3>;

Int128 Det2(const P2& a, const P2& b) { return Int128(a[0]) * b[1] - Int128(a[1]) * b[0]; }
Int128 Dot2(const P2& a, const P2& b) { return Int128(a[0]) * b[0] + Int128(a[1]) * b[1]; }

bool SameSignNotAllZero(const Int128* mu, int n) {
  bool pos = false, neg = false;
  for (int i = 0; i < n; ++i) {
    pos |= mu[i] > 0;
    neg |= mu[i] < 0;
  }
  return pos != neg;
}

/// Origin in the closed triangle (or collinear triple) a b c of the plane,
/// with the barycentric numerators (det[b c], det[c a], det[a b]).
bool ReferenceTriangle2d(const P2& a, const P2& b, const P2& c) {
  const Int128 mu[3] = {Det2(b, c), Det2(c, a), Det2(a, b)};
  return SameSignNotAllZero(mu, 3);
}

bool ReferenceSegment2d(const P2& a, const P2& b) { return Det2(a, b) == 0 && Dot2(a, b) <= 0; }

/// Caratheodory: the origin is in conv(P) iff it is a point of P, on a
/// segment or in a triangle of points of P.
bool ReferenceHull2d(const std::vector<P2>& p) {
  const int n = static_cast<int>(p.size());
  for (const P2& q : p) {
    if (q[0] == 0 && q[1] == 0) return true;
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (ReferenceSegment2d(p[i], p[j])) return true;
      for (int k = j + 1; k < n; ++k) {
        if (ReferenceTriangle2d(p[i], p[j], p[k])) return true;
      }
    }
  }
  return false;
}

P3 Cross(const P3& a, const P3& b) {
  // Only used with coordinates below 2^31 (the products fit in 64 bits).
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Int128 Det3(const P3& a, const P3& b, const P3& c) {
  return Int128(a[0]) * (Int128(b[1]) * c[2] - Int128(b[2]) * c[1]) +
         Int128(a[1]) * (Int128(b[2]) * c[0] - Int128(b[0]) * c[2]) +
         Int128(a[2]) * (Int128(b[0]) * c[1] - Int128(b[1]) * c[0]);
}

bool ReferenceHull3d(const std::vector<P3>& p) {
  const int n = static_cast<int>(p.size());
  for (const P3& q : p) {
    if (q[0] == 0 && q[1] == 0 && q[2] == 0) return true;
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const P3 ij = Cross(p[i], p[j]);
      const Int128 dot = Int128(p[i][0]) * p[j][0] + Int128(p[i][1]) * p[j][1] + Int128(p[i][2]) * p[j][2];
      if (ij[0] == 0 && ij[1] == 0 && ij[2] == 0 && dot <= 0) return true;
      for (int k = j + 1; k < n; ++k) {
        if (Det3(p[i], p[j], p[k]) == 0) {
          // Triangle in a plane through the origin: project along an axis
          // where the plane's normal is nonzero (injective on the plane).
          P3 normal = ij;
          if (normal == P3{0, 0, 0}) normal = Cross(p[i], p[k]);
          if (normal == P3{0, 0, 0}) normal = Cross(p[j], p[k]);
          if (normal == P3{0, 0, 0}) continue;  // collinear: segments cover it
          int drop = 0;
          while (normal[drop] == 0) ++drop;
          const int u = (drop + 1) % 3, v = (drop + 2) % 3;
          if (ReferenceTriangle2d({p[i][u], p[i][v]}, {p[j][u], p[j][v]}, {p[k][u], p[k][v]})) return true;
        }
        for (int l = k + 1; l < n; ++l) {
          const Int128 mu[4] = {Det3(p[j], p[k], p[l]), -Det3(p[i], p[k], p[l]), Det3(p[i], p[j], p[l]),
                                -Det3(p[i], p[j], p[k])};
          if (SameSignNotAllZero(mu, 4)) return true;
        }
      }
    }
  }
  return false;
}

std::vector<double> ToDoubles2(const std::vector<P2>& p) {
  std::vector<double> out;
  for (const P2& q : p) out.insert(out.end(), {double(q[0]), double(q[1])});
  return out;
}

std::vector<double> ToDoubles3(const std::vector<P3>& p) {
  std::vector<double> out;
  for (const P3& q : p) out.insert(out.end(), {double(q[0]), double(q[1]), double(q[2])});
  return out;
}

/// Scales each point by its own power of two: the answer must not change.
std::vector<double> ScalePoints(std::vector<double> xs, int dim, std::mt19937_64& rng, int maxExponent) {
  std::uniform_int_distribution<int> exponent(-maxExponent, maxExponent);
  for (std::size_t k = 0; k < xs.size(); k += dim) {
    const int e = exponent(rng);
    for (int c = 0; c < dim; ++c) xs[k + c] = std::ldexp(xs[k + c], e);
  }
  return xs;
}

bool Hull2d(const std::vector<double>& xy) { return OriginInConvexHull2d(xy.data(), int(xy.size() / 2)); }
bool Hull3d(const std::vector<double>& xyz) { return OriginInConvexHull3d(xyz.data(), int(xyz.size() / 3)); }

// ---------------------------------------------------------------- hull: fixed cases

TEST(HullMembership, OneDimensional) {
  const double none[1] = {0.0};
  EXPECT_FALSE(OriginInConvexHull1d(none, 0));
  const double zero[] = {0.0}, negZero[] = {-0.0}, pos[] = {1.0}, neg[] = {-2.0};
  EXPECT_TRUE(OriginInConvexHull1d(zero, 1));
  EXPECT_TRUE(OriginInConvexHull1d(negZero, 1));
  EXPECT_FALSE(OriginInConvexHull1d(pos, 1));
  EXPECT_FALSE(OriginInConvexHull1d(neg, 1));
  const double mixed[] = {3.0, 1e-300, -0x1p-1074};
  EXPECT_TRUE(OriginInConvexHull1d(mixed, 3));
  const double positive[] = {3.0, 1e-300, 0x1p-1074, 2.0};
  EXPECT_FALSE(OriginInConvexHull1d(positive, 4));
  const double touching[] = {3.0, 0.0, 5.0};
  EXPECT_TRUE(OriginInConvexHull1d(touching, 3));
}

TEST(HullMembership, TwoDimensionalFixedCases) {
  EXPECT_FALSE(OriginInConvexHull2d(nullptr, 0));
  EXPECT_TRUE(Hull2d({0, 0}));
  EXPECT_FALSE(Hull2d({1, -1}));
  EXPECT_TRUE(Hull2d({-1, -1, 2, -1, -1, 2}));      // triangle around the origin
  EXPECT_TRUE(Hull2d({-1, -1, 1, 1, 0, 5}));        // origin on an edge
  EXPECT_TRUE(Hull2d({0, 0, 1, 2, 3, 1}));          // origin at a vertex
  EXPECT_FALSE(Hull2d({1, 2, 2, 4, 3, 6}));         // collinear, one side
  EXPECT_TRUE(Hull2d({1, 2, 2, 4, -1, -2}));        // collinear, both sides
  EXPECT_FALSE(Hull2d({1, 0, -1, 1, 3, -1}));       // collinear on x + 2y = 1
  EXPECT_FALSE(Hull2d({1, 1, 1, 1, 1, 1, 1, 1}));   // repeated
  EXPECT_TRUE(Hull2d({1, -1, 1, -1, -1, 1}));       // repeated, origin on the segment
  EXPECT_TRUE(Hull2d({3, 1, 3, 1, -3, -1, 3, 1}));  // repeated, origin on the segment
  // Edge (-3, 1 +- ulp) - (3, -1) passing one ulp above / below the origin, apex (1, 3).
  EXPECT_FALSE(Hull2d({-3, std::nextafter(1.0, 2.0), 3, -1, 1, 3}));
  EXPECT_TRUE(Hull2d({-3, std::nextafter(1.0, 0.0), 3, -1, 1, 3}));
  EXPECT_TRUE(Hull2d({-3, 1, 3, -1, 1, 3}));
  // The same with each point scaled by its own (huge or tiny) power of two:
  // the rescaling path, same answers.
  const double up = std::nextafter(1.0, 2.0), down = std::nextafter(1.0, 0.0);
  EXPECT_FALSE(Hull2d({-3 * 0x1p600, up * 0x1p600, 3 * 0x1p-700, -0x1p-700, 0x1p10, 3 * 0x1p10}));
  EXPECT_TRUE(Hull2d({-3 * 0x1p600, down * 0x1p600, 3 * 0x1p-700, -0x1p-700, 0x1p10, 3 * 0x1p10}));
  EXPECT_TRUE(Hull2d({-3 * 0x1p600, 0x1p600, 3 * 0x1p-700, -0x1p-700, 0x1p10, 3 * 0x1p10}));
}

TEST(HullMembership, ThreeDimensionalFixedCases) {
  EXPECT_FALSE(OriginInConvexHull3d(nullptr, 0));
  EXPECT_TRUE(Hull3d({0, 0, 0}));
  EXPECT_TRUE(Hull3d({1, 2, 3, 0, 0, 0}));
  EXPECT_FALSE(Hull3d({1, 2, 3}));
  EXPECT_TRUE(Hull3d({-1, -1, -1, 3, -1, -1, -1, 3, -1, -1, -1, 3}));  // tetrahedron around 0
  EXPECT_TRUE(Hull3d({-1, -1, 0, 2, -1, 0, -1, 2, 0, 0, 0, 1}));       // origin on a face
  EXPECT_TRUE(Hull3d({-1, -2, -3, 1, 2, 3, 1, 0, 0, 0, 5, 1}));        // origin on an edge
  EXPECT_TRUE(Hull3d({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}));           // at a vertex
  EXPECT_FALSE(Hull3d({1, 2, 3, 2, 4, 6, 3, 6, 9}));                   // collinear, one side
  EXPECT_TRUE(Hull3d({1, 2, 3, 2, 4, 6, -3, -6, -9}));                 // collinear, both sides
  EXPECT_TRUE(Hull3d({1, -1, 0, 0, 1, -1, -1, 0, 1}));                 // coplanar through 0, inside
  EXPECT_FALSE(Hull3d({1, -1, 0, 0, 1, -1, 1, 0, -1}));                // coplanar through 0, outside
  EXPECT_TRUE(Hull3d({1, -1, 0, 0, 1, -1, 1, 0, -1, -1, 0, 1}));       // origin on the triangle's edge
  EXPECT_FALSE(Hull3d({1, 0, 1, 0, 1, 1, -1, -1, 1}));                 // coplanar z = 1
  EXPECT_FALSE(Hull3d({2, 0, 0, 2, 0, 0, 0, 3, -3, 0, 3, -3}));        // repeated, outside
  // Face (-1,-1,d) (2,-1,0) (-1,2,0) and apex (0,0,1): the face passes d/3 above or below 0.
  const double up = 0x1p-60;
  EXPECT_FALSE(Hull3d({-1, -1, up, 2, -1, 0, -1, 2, 0, 0, 0, 1}));
  EXPECT_TRUE(Hull3d({-1, -1, -up, 2, -1, 0, -1, 2, 0, 0, 0, 1}));
  EXPECT_FALSE(Hull3d({-1, -1, 0x1p-250, 2, -1, 0, -1, 2, 0, 0, 0, 1}));
  EXPECT_FALSE(Hull3d({-1, -1, 0x1p-285, 2, -1, 0, -1, 2, 0, 0, 0, 1}));  // rescaled
  EXPECT_TRUE(Hull3d({-1, -1, -0x1p-285, 2, -1, 0, -1, 2, 0, 0, 0, 1}));
  // Same configurations at extreme magnitudes (rescaling path).
  for (double scale : {0x1p700, 0x1p-700, 0x1p-1000}) {
    EXPECT_FALSE(Hull3d({-scale, -scale, up * scale, 2 * scale, -scale, 0, -scale, 2 * scale, 0, 0, 0, 1}));
    EXPECT_TRUE(Hull3d({-scale, -scale, -up * scale, 2 * scale, -scale, 0, -scale, 2 * scale, 0, 0, 0, 1}));
  }
}

// ---------------------------------------------------------------- hull: random vs reference

TEST(HullMembership, Random2dAgainstCaratheodory) {
  std::mt19937_64 rng(23);
  int inside = 0, total = 0;
  for (int range : {1, 2, 3, 1000}) {
    std::uniform_int_distribution<std::int64_t> coord(-range, range);
    for (int trial = 0; trial < 3000; ++trial) {
      const int n = 1 + trial % 12;
      std::vector<P2> p(n);
      const std::int64_t sx = coord(rng) / 2, sy = coord(rng) / 2;  // shift: origin often outside
      for (P2& q : p) q = {coord(rng) + sx, coord(rng) + sy};
      const bool expected = ReferenceHull2d(p);
      const std::vector<double> xy = ToDoubles2(p);
      ASSERT_EQ(Hull2d(xy), expected) << "range " << range << " trial " << trial;
      ASSERT_EQ(Hull2d(ScalePoints(xy, 2, rng, 40)), expected) << "range " << range << " trial " << trial;
      ASSERT_EQ(Hull2d(ScalePoints(xy, 2, rng, 700)), expected) << "range " << range << " trial " << trial;
      inside += expected;
      ++total;
    }
  }
  EXPECT_GT(inside, total / 5);
  EXPECT_LT(inside, total * 4 / 5);
}

TEST(HullMembership, Random3dAgainstCaratheodory) {
  std::mt19937_64 rng(29);
  int inside = 0, total = 0;
  for (int range : {1, 2, 3, 1000}) {
    std::uniform_int_distribution<std::int64_t> coord(-range, range);
    for (int trial = 0; trial < 2000; ++trial) {
      const int n = 1 + trial % 10;
      std::vector<P3> p(n);
      const std::int64_t sx = coord(rng) / 2, sy = coord(rng) / 2, sz = coord(rng) / 2;
      for (P3& q : p) q = {coord(rng) + sx, coord(rng) + sy, coord(rng) + sz};
      const bool expected = ReferenceHull3d(p);
      const std::vector<double> xyz = ToDoubles3(p);
      ASSERT_EQ(Hull3d(xyz), expected) << "range " << range << " trial " << trial;
      ASSERT_EQ(Hull3d(ScalePoints(xyz, 3, rng, 40)), expected) << "range " << range << " trial " << trial;
      ASSERT_EQ(Hull3d(ScalePoints(xyz, 3, rng, 700)), expected) << "range " << range << " trial " << trial;
      inside += expected;
      ++total;
    }
  }
  EXPECT_GT(inside, total / 5);
  EXPECT_LT(inside, total * 4 / 5);
}

// Points in (or one unit off) planes and lines through the origin, with
// 31-bit coordinates so that naive determinants would round.
TEST(HullMembership, Random3dNearDegenerateAgainstCaratheodory) {
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t{1} << 28), std::int64_t{1} << 28);
  std::uniform_int_distribution<int> small(-2, 2), delta(-1, 1), axis(0, 2), kind(0, 2);
  int inside = 0, total = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const int n = 2 + trial % 8;
    const P3 a = {coord(rng), coord(rng), coord(rng)}, b = {coord(rng), coord(rng), coord(rng)};
    std::vector<P3> p(n);
    const int k = kind(rng);  // 0: plane span(a, b); 1: line span(a); 2: mixed
    for (P3& q : p) {
      const int s = small(rng), t = (k == 1) ? 0 : small(rng);
      for (int i = 0; i < 3; ++i) q[i] = s * a[i] + t * b[i];
      if (k == 2 || delta(rng) == 0) q[axis(rng)] += delta(rng);
    }
    const bool expected = ReferenceHull3d(p);
    const std::vector<double> xyz = ToDoubles3(p);
    ASSERT_EQ(Hull3d(xyz), expected) << "trial " << trial;
    ASSERT_EQ(Hull3d(ScalePoints(xyz, 3, rng, 60)), expected) << "trial " << trial;
    inside += expected;
    ++total;
  }
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, total);
}

TEST(HullMembership, Random2dNearDegenerateAgainstCaratheodory) {
  std::mt19937_64 rng(37);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
  std::uniform_int_distribution<int> small(-3, 3), delta(-1, 1), axis(0, 1);
  int inside = 0, total = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 2 + trial % 6;
    const P2 a = {coord(rng), coord(rng)};
    std::vector<P2> p(n);
    for (P2& q : p) {
      const int s = small(rng);
      q = {s * a[0], s * a[1]};
      q[axis(rng)] += delta(rng);
    }
    const bool expected = ReferenceHull2d(p);
    ASSERT_EQ(Hull2d(ToDoubles2(p)), expected) << "trial " << trial;
    inside += expected;
    ++total;
  }
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, total);
}

// 20 points (cubic Bezier tetrahedron) and 64 points (the documented bound)
// and 100 points (heap path): integer coordinates in a small range keep
// degeneracies frequent; the reference is Caratheodory on the same points.
TEST(HullMembership, LargeCountsAgainstCaratheodory) {
  std::mt19937_64 rng(41);
  std::uniform_int_distribution<std::int64_t> coord(-6, 6);
  for (int n : {20, 64, 100}) {
    const int trials = n == 20 ? 60 : (n == 64 ? 4 : 2);
    for (int trial = 0; trial < trials; ++trial) {
      std::vector<P3> p(n);
      // Push the cloud off the origin by 5 or 6 units along a random axis,
      // so both answers occur.
      const int shiftAxis = trial % 3;
      const std::int64_t shift = 5 + trial % 2;
      for (P3& q : p) {
        q = {coord(rng), coord(rng), coord(rng)};
        q[shiftAxis] = std::abs(q[shiftAxis]) + shift - 6;
      }
      const bool expected = ReferenceHull3d(p);
      ASSERT_EQ(Hull3d(ToDoubles3(p)), expected) << "n " << n << " trial " << trial;
    }
  }
}

}  // namespace
}  // namespace invmap::implicit
