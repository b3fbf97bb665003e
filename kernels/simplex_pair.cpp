#include "kernels/simplex_pair.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/affine_simplex.h"

namespace invmap::kernels {
namespace {

using Vec = double[3];

double Dot(const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

void Sub(const double* u, const double* v, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = u[k] - v[k];
}

void Cross(const double* u, const double* v, double* out) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
}

/// The best pair found so far, in the simplices' own reference coordinates.
struct Best {
  double d2 = std::numeric_limits<double>::infinity();
  double refA[2] = {0, 0};
  double refB[2] = {0, 0};

  void Offer(double candidate, const double* ra, const double* rb) {
    if (!(candidate < d2)) return;
    d2 = candidate;
    refA[0] = ra[0];
    refA[1] = ra[1];
    refB[0] = rb[0];
    refB[1] = rb[1];
  }
};

/// Closest points of segments p0 p1 and q0 q1 (Ericson, Real-Time Collision
/// Detection 5.1.9): parameters s on p, t on q, both clamped to [0, 1].
/// Parallel segments (a vanishing determinant) take s = 0 and the t it
/// gives, then s again from that t: one of the equally close pairs.
void SegmentParameters(const double* p0, const double* p1, const double* q0, const double* q1, double* s,
                       double* t) {
  Vec d1, d2, r;
  Sub(p1, p0, d1);
  Sub(q1, q0, d2);
  Sub(p0, q0, r);
  const double a = Dot(d1, d1), e = Dot(d2, d2), f = Dot(d2, r);
  if (!(a > 0.0) && !(e > 0.0)) {
    *s = *t = 0.0;
    return;
  }
  if (!(a > 0.0)) {
    *s = 0.0;
    *t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = Dot(d1, r);
  if (!(e > 0.0)) {
    *t = 0.0;
    *s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = Dot(d1, d2);
  const double denominator = a * e - b * b;
  double ss = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double tt = (b * ss + f) / e;
  if (tt < 0.0) {
    tt = 0.0;
    ss = std::clamp(-c / a, 0.0, 1.0);
  } else if (tt > 1.0) {
    tt = 1.0;
    ss = std::clamp((b - c) / a, 0.0, 1.0);
  }
  *s = ss;
  *t = tt;
}

double PointOnSegment(const double* p0, const double* p1, double s, double* x) {
  for (int k = 0; k < 3; ++k) x[k] = p0[k] + s * (p1[k] - p0[k]);
  return 0.0;
}

double Distance2(const double* u, const double* v) {
  Vec d;
  Sub(u, v, d);
  return Dot(d, d);
}

/// Reference coordinates of a triangle's edge e at parameter s along it:
/// edge 0 runs v0 -> v1, edge 1 v1 -> v2, edge 2 v2 -> v0.
void EdgeToTriangle(int e, double s, double* ref) {
  if (e == 0) {
    ref[0] = s;
    ref[1] = 0.0;
  } else if (e == 1) {
    ref[0] = 1.0 - s;
    ref[1] = s;
  } else {
    ref[0] = 0.0;
    ref[1] = 1.0 - s;
  }
}

/// Segment p0 p1 against triangle v (3D): when the segment crosses the
/// triangle's plane strictly inside the triangle, the crossing point's
/// segment parameter and triangle coordinates. Touching and coplanar cases
/// are left to the vertex and edge pairs, which find them at distance 0.
bool SegmentCrossesTriangle(const double* p0, const double* p1, const double* const* v, double* s, double* ref) {
  Vec e1, e2, n, w0, w1;
  Sub(v[1], v[0], e1);
  Sub(v[2], v[0], e2);
  Cross(e1, e2, n);
  Sub(p0, v[0], w0);
  Sub(p1, v[0], w1);
  const double h0 = Dot(n, w0), h1 = Dot(n, w1);
  if (!((h0 > 0.0 && h1 < 0.0) || (h0 < 0.0 && h1 > 0.0))) return false;
  const double t = h0 / (h0 - h1);
  Vec x, edge, rel, c;
  for (int k = 0; k < 3; ++k) x[k] = p0[k] + t * (p1[k] - p0[k]);
  // Inside when x lies on the inner side of each edge (triple products
  // with the normal), the same sign as n . n.
  double lambda[3];
  for (int i = 0; i < 3; ++i) {
    const double* from = v[(i + 1) % 3];
    const double* to = v[(i + 2) % 3];
    Sub(to, from, edge);
    Sub(x, from, rel);
    Cross(edge, rel, c);
    lambda[i] = Dot(n, c);
    if (lambda[i] < 0.0) return false;
  }
  const double sum = lambda[0] + lambda[1] + lambda[2];
  if (!(sum > 0.0)) return false;
  *s = t;
  ref[0] = lambda[1] / sum;
  ref[1] = lambda[2] / sum;
  return true;
}

/// The candidates of a segment (p0 p1) against a triangle (v): both
/// endpoints against the triangle, the segment against each edge, and a
/// crossing through the interior. `swap` offers them as (triangle, segment).
void SegmentTriangle(const double* p0, const double* p1, const double* const* v, bool swap, Best* best) {
  auto offer = [&](double d2, double s, const double* triRef) {
    const double segRef[2] = {s, 0.0};
    if (swap) {
      best->Offer(d2, triRef, segRef);
    } else {
      best->Offer(d2, segRef, triRef);
    }
  };
  for (int end = 0; end < 2; ++end) {
    const double* p = end == 0 ? p0 : p1;
    double ref[3], closest[3];
    bool onBoundary = false;
    const double d2 = ClosestPointOnSimplex(2, 3, v, p, ref, closest, &onBoundary);
    offer(d2, end, ref);
  }
  for (int e = 0; e < 3; ++e) {
    double s, t;
    const double* q0 = v[e];
    const double* q1 = v[(e + 1) % 3];
    SegmentParameters(p0, p1, q0, q1, &s, &t);
    Vec x, y;
    PointOnSegment(p0, p1, s, x);
    PointOnSegment(q0, q1, t, y);
    double ref[2];
    EdgeToTriangle(e, t, ref);
    offer(Distance2(x, y), s, ref);
  }
  double s, ref[2];
  if (SegmentCrossesTriangle(p0, p1, v, &s, ref)) offer(0.0, s, ref);
}

/// The two quick answers of a pair of disjoint triangles (as in Larsen,
/// Gottschalk, Lin and Manocha's PQP): the nearest vertex of a triangle
/// lying wholly on one side of the other's plane, when it projects inside
/// the other (every point of its triangle is at least that far from the
/// plane); or the closest points of an edge of each whose joining vector
/// v = y - x has both triangles on either side of the slab it spans (each
/// edge's own vertices are, as its closest point; the third vertices are
/// tested), which makes |v| the triangles' distance. False when neither
/// holds: the full enumeration decides.
bool SeparatedTriangles(const double* const* va, const double* const* vb, Best* best) {
  static constexpr double kVertexRef[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (int side = 0; side < 2; ++side) {
    const double* const* onto = side == 0 ? va : vb;
    const double* const* from = side == 0 ? vb : va;
    Vec e1, e2, n;
    Sub(onto[1], onto[0], e1);
    Sub(onto[2], onto[0], e2);
    Cross(e1, e2, n);
    const double n2 = Dot(n, n);
    if (!(n2 > 0.0)) continue;
    double h[3];
    for (int v = 0; v < 3; ++v) {
      Vec r;
      Sub(from[v], onto[0], r);
      h[v] = Dot(r, n);
    }
    const bool above = h[0] > 0.0 && h[1] > 0.0 && h[2] > 0.0;
    const bool below = h[0] < 0.0 && h[1] < 0.0 && h[2] < 0.0;
    if (!above && !below) continue;
    int nearest = 0;
    for (int v = 1; v < 3; ++v) {
      if (std::abs(h[v]) < std::abs(h[nearest])) nearest = v;
    }
    Vec r;
    Sub(from[nearest], onto[0], r);
    const double d11 = Dot(e1, e1), d12 = Dot(e1, e2), d22 = Dot(e2, e2), r1 = Dot(r, e1), r2 = Dot(r, e2);
    const double det = d11 * d22 - d12 * d12;
    if (!(det > 0.0)) continue;
    const double ref[2] = {(d22 * r1 - d12 * r2) / det, (d11 * r2 - d12 * r1) / det};
    if (!(ref[0] >= 0.0 && ref[1] >= 0.0 && ref[0] + ref[1] <= 1.0)) continue;
    const double d2 = h[nearest] * h[nearest] / n2;
    if (side == 0) {
      best->Offer(d2, ref, kVertexRef[nearest]);
    } else {
      best->Offer(d2, kVertexRef[nearest], ref);
    }
    return true;
  }
  for (int ea = 0; ea < 3; ++ea) {
    for (int eb = 0; eb < 3; ++eb) {
      const double* p0 = va[ea];
      const double* p1 = va[(ea + 1) % 3];
      const double* q0 = vb[eb];
      const double* q1 = vb[(eb + 1) % 3];
      double s, t;
      SegmentParameters(p0, p1, q0, q1, &s, &t);
      Vec x, y, v, r;
      PointOnSegment(p0, p1, s, x);
      PointOnSegment(q0, q1, t, y);
      Sub(y, x, v);
      if (!(Dot(v, v) > 0.0)) continue;
      Sub(va[(ea + 2) % 3], x, r);
      if (Dot(r, v) > 0.0) continue;
      Sub(vb[(eb + 2) % 3], y, r);
      if (Dot(r, v) < 0.0) continue;
      double ra[2], rb[2];
      EdgeToTriangle(ea, s, ra);
      EdgeToTriangle(eb, t, rb);
      best->Offer(Dot(v, v), ra, rb);
      return true;
    }
  }
  return false;
}

void EvaluateSimplex(int dim, const double* const* v, const double* ref, double* x) {
  for (int k = 0; k < 3; ++k) {
    x[k] = v[0][k];
    for (int i = 0; i < dim; ++i) x[k] += ref[i] * (v[i + 1][k] - v[0][k]);
  }
}

}  // namespace

double ClosestPointsOfSimplices(int dimA, const double* const* a, int dimB, const double* const* b, int ambientDim,
                                double* refA, double* refB, double* pointA, double* pointB) {
  // Every formula below works in 3D; 2D vertices get z = 0.
  double storage[6][3];
  const double* va[3];
  const double* vb[3];
  for (int i = 0; i <= dimA; ++i) {
    for (int k = 0; k < 3; ++k) storage[i][k] = k < ambientDim ? a[i][k] : 0.0;
    va[i] = storage[i];
  }
  for (int i = 0; i <= dimB; ++i) {
    for (int k = 0; k < 3; ++k) storage[3 + i][k] = k < ambientDim ? b[i][k] : 0.0;
    vb[i] = storage[3 + i];
  }
  Best best;
  if (dimA == 1 && dimB == 1) {
    double s, t;
    SegmentParameters(va[0], va[1], vb[0], vb[1], &s, &t);
    const double ra[2] = {s, 0.0}, rb[2] = {t, 0.0};
    Vec x, y;
    PointOnSegment(va[0], va[1], s, x);
    PointOnSegment(vb[0], vb[1], t, y);
    best.Offer(Distance2(x, y), ra, rb);
  } else if (dimA == 1 && dimB == 2) {
    SegmentTriangle(va[0], va[1], vb, false, &best);
  } else if (dimA == 2 && dimB == 1) {
    SegmentTriangle(vb[0], vb[1], va, true, &best);
  } else {
    // Two triangles: a closest pair has a vertex of one against the other,
    // or an edge against an edge; crossing triangles have an edge of one
    // through the other. Each candidate once: 6 vertices, 9 edge pairs
    // (unless a quick answer settles it).
    const double vertexRef[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const bool settled = SeparatedTriangles(va, vb, &best);
    for (int side = 0; side < 2 && !settled; ++side) {
      const double* const* from = side == 0 ? va : vb;
      const double* const* onto = side == 0 ? vb : va;
      for (int v = 0; v < 3; ++v) {
        double ref[3], closest[3];
        bool onBoundary = false;
        const double d2 = ClosestPointOnSimplex(2, 3, onto, from[v], ref, closest, &onBoundary);
        if (side == 0) {
          best.Offer(d2, vertexRef[v], ref);
        } else {
          best.Offer(d2, ref, vertexRef[v]);
        }
      }
    }
    for (int ea = 0; ea < 3 && !settled; ++ea) {
      for (int eb = 0; eb < 3; ++eb) {
        double s, t;
        const double* p0 = va[ea];
        const double* p1 = va[(ea + 1) % 3];
        const double* q0 = vb[eb];
        const double* q1 = vb[(eb + 1) % 3];
        SegmentParameters(p0, p1, q0, q1, &s, &t);
        Vec x, y;
        PointOnSegment(p0, p1, s, x);
        PointOnSegment(q0, q1, t, y);
        double ra[2], rb[2];
        EdgeToTriangle(ea, s, ra);
        EdgeToTriangle(eb, t, rb);
        best.Offer(Distance2(x, y), ra, rb);
      }
    }
    if (best.d2 > 0.0 && !settled) {
      for (int side = 0; side < 2; ++side) {
        const double* const* from = side == 0 ? va : vb;
        const double* const* onto = side == 0 ? vb : va;
        for (int e = 0; e < 3; ++e) {
          double s, ref[2], fromRef[2];
          if (!SegmentCrossesTriangle(from[e], from[(e + 1) % 3], onto, &s, ref)) continue;
          EdgeToTriangle(e, s, fromRef);
          if (side == 0) {
            best.Offer(0.0, fromRef, ref);
          } else {
            best.Offer(0.0, ref, fromRef);
          }
        }
      }
    }
  }
  for (int i = 0; i < dimA; ++i) refA[i] = std::clamp(best.refA[i], 0.0, 1.0);
  for (int i = 0; i < dimB; ++i) refB[i] = std::clamp(best.refB[i], 0.0, 1.0);
  Vec x, y;
  EvaluateSimplex(dimA, va, refA, x);
  EvaluateSimplex(dimB, vb, refB, y);
  for (int k = 0; k < ambientDim; ++k) {
    pointA[k] = x[k];
    pointB[k] = y[k];
  }
  return Distance2(x, y);
}

double SimplexPlaneGap(int dimA, const double* const* a, int dimB, const double* const* b, int ambientDim) {
  if (ambientDim != 3) return 0.0;
  double gap = 0.0, magnitude = 0.0;
  for (int side = 0; side < 2; ++side) {
    if ((side == 0 ? dimA : dimB) != 2) continue;
    const double* const* u = side == 0 ? a : b;
    const double* const* w = side == 0 ? b : a;
    const int count = (side == 0 ? dimB : dimA) + 1;
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = u[1][k] - u[0][k];
      e2[k] = u[2][k] - u[0][k];
      for (int v = 0; v < 3; ++v) magnitude = std::max(magnitude, std::abs(u[v][k]));
      for (int v = 0; v < count; ++v) magnitude = std::max(magnitude, std::abs(w[v][k]));
    }
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0.0)) continue;
    const double offset = n[0] * u[0][0] + n[1] * u[0][1] + n[2] * u[0][2];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int v = 0; v < count; ++v) {
      const double q = n[0] * w[v][0] + n[1] * w[v][1] + n[2] * w[v][2] - offset;
      lo = std::min(lo, q);
      hi = std::max(hi, q);
    }
    gap = std::max(gap, std::max(lo, -hi) / length);
  }
  // Rounding of the normal and the projections: a few ulps of the
  // coordinates' magnitude (the unit normal's direction errs by ulps of it).
  return std::max(0.0, gap - 64.0 * std::numeric_limits<double>::epsilon() * magnitude);
}

}  // namespace invmap::kernels
