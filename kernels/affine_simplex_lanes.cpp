#include "kernels/affine_simplex_lanes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/affine_simplex.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

struct Vec {
  double x = 0, y = 0, z = 0;
};

Vec Load(const double* p, int n) { return {p[0], p[1], n > 2 ? p[2] : 0.0}; }
Vec Sub(const Vec& a, const Vec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double Dot(const Vec& a, const Vec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec Cross(const Vec& a, const Vec& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

double Clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

/// Triangle (a, a + e1, a + e2) on lanes [0, count): (s, t) and squared
/// distance. The closest point is the projection onto the plane when it
/// lies in the triangle, otherwise the nearest of the three edges. The
/// projection is ClosestPointOnSimplex's (triple products with the normal,
/// t first, then s along e1), which keeps its digits on thin triangles; the
/// triangle's angle at a is above ClosestPointOnSimplex's threshold for
/// trusting it (Degenerate below leaves the others to the scalar solver).
void TriangleLanes(const Vec& a, const Vec& e1, const Vec& e2, const double* x, const double* y, const double* z,
                   int count, double* sOut, double* tOut, double* d2Out, bool* boundaryOut) {
  const double g11 = Dot(e1, e1), g12 = Dot(e1, e2), g22 = Dot(e2, e2);
  const Vec n = Cross(e1, e2);
  const double inverseNn = 1.0 / Dot(n, n), inverseG11 = 1.0 / g11;
  const Vec f = Sub(e2, e1);
  const double ff = Dot(f, f);
  for (int l = 0; l < count; ++l) {
    const double wx = x[l] - a.x, wy = y[l] - a.y, wz = z[l] - a.z;
    const double r1 = e1.x * wx + e1.y * wy + e1.z * wz;
    const double r2 = e2.x * wx + e2.y * wy + e2.z * wz;
    // Projection onto the plane: t = n . (e1 x w) / |n|^2, s from t.
    const double e1wX = e1.y * wz - e1.z * wy, e1wY = e1.z * wx - e1.x * wz, e1wZ = e1.x * wy - e1.y * wx;
    const double t = (n.x * e1wX + n.y * e1wY + n.z * e1wZ) * inverseNn;
    const double s = (r1 - t * g12) * inverseG11;
    const bool inside = s >= 0 && t >= 0 && s + t <= 1;
    const double px = wx - s * e1.x - t * e2.x, py = wy - s * e1.y - t * e2.y, pz = wz - s * e1.z - t * e2.z;
    const double dPlane = px * px + py * py + pz * pz;
    // Edge a b: (sa, 0).
    const double sa = Clamp01(r1 / g11);
    const double ax = wx - sa * e1.x, ay = wy - sa * e1.y, az = wz - sa * e1.z;
    const double dAb = ax * ax + ay * ay + az * az;
    // Edge a c: (0, ta).
    const double ta = Clamp01(r2 / g22);
    const double cx = wx - ta * e2.x, cy = wy - ta * e2.y, cz = wz - ta * e2.z;
    const double dAc = cx * cx + cy * cy + cz * cz;
    // Edge b c: b + u f = a + (1 - u) e1 + u e2.
    const double bx = wx - e1.x, by = wy - e1.y, bz = wz - e1.z;
    const double u = Clamp01((f.x * bx + f.y * by + f.z * bz) / ff);
    const double qx = bx - u * f.x, qy = by - u * f.y, qz = bz - u * f.z;
    const double dBc = qx * qx + qy * qy + qz * qz;

    double best = dAb, bestS = sa, bestT = 0;
    const bool acBetter = dAc < best;
    best = acBetter ? dAc : best;
    bestS = acBetter ? 0.0 : bestS;
    bestT = acBetter ? ta : bestT;
    const bool bcBetter = dBc < best;
    best = bcBetter ? dBc : best;
    bestS = bcBetter ? 1.0 - u : bestS;
    bestT = bcBetter ? u : bestT;
    sOut[l] = inside ? s : bestS;
    tOut[l] = inside ? t : bestT;
    d2Out[l] = inside ? dPlane : best;
    boundaryOut[l] = !inside;
  }
}

void SegmentLanes(const Vec& a, const Vec& e, const double* x, const double* y, const double* z, int count,
                  double* tOut, double* d2Out, bool* boundaryOut) {
  const double ee = Dot(e, e);
  for (int l = 0; l < count; ++l) {
    const double wx = x[l] - a.x, wy = y[l] - a.y, wz = z[l] - a.z;
    const double raw = (e.x * wx + e.y * wy + e.z * wz) / ee;
    const double t = Clamp01(raw);
    const double px = wx - t * e.x, py = wy - t * e.y, pz = wz - t * e.z;
    tOut[l] = t;
    d2Out[l] = px * px + py * py + pz * pz;
    boundaryOut[l] = !(raw > 0 && raw < 1);
  }
}

/// One chunk of at most kSimplexLaneChunk lanes.
void SolveChunk(int dim, int ambientDim, const double* const* v, const double* x, const double* y, const double* z,
                int count, double* const ref[3], double* dist2, bool* onBoundary) {
  const Vec a = Load(v[0], ambientDim);
  if (dim == 1) {
    SegmentLanes(a, Sub(Load(v[1], ambientDim), a), x, y, z, count, ref[0], dist2, onBoundary);
    return;
  }
  if (dim == 2) {
    TriangleLanes(a, Sub(Load(v[1], ambientDim), a), Sub(Load(v[2], ambientDim), a), x, y, z, count, ref[0], ref[1],
                  dist2, onBoundary);
    return;
  }
  // Tetrahedron: barycentric coordinates; outside, the nearest of the faces.
  const Vec e1 = Sub(Load(v[1], 3), a), e2 = Sub(Load(v[2], 3), a), e3 = Sub(Load(v[3], 3), a);
  const Vec c23 = Cross(e2, e3), c31 = Cross(e3, e1), c12 = Cross(e1, e2);
  const double inverseDet = 1.0 / Dot(e1, c23);
  for (int l = 0; l < count; ++l) {
    const double wx = x[l] - a.x, wy = y[l] - a.y, wz = z[l] - a.z;
    ref[0][l] = (c23.x * wx + c23.y * wy + c23.z * wz) * inverseDet;
    ref[1][l] = (c31.x * wx + c31.y * wy + c31.z * wz) * inverseDet;
    ref[2][l] = (c12.x * wx + c12.y * wy + c12.z * wz) * inverseDet;
    const bool inside = ref[0][l] >= 0 && ref[1][l] >= 0 && ref[2][l] >= 0 && ref[0][l] + ref[1][l] + ref[2][l] <= 1;
    dist2[l] = inside ? 0.0 : std::numeric_limits<double>::infinity();
    onBoundary[l] = !inside;
  }
  // Faces and how their (s, t) map to the tetrahedron's reference coordinates.
  const Vec vertex[4] = {a, Load(v[1], 3), Load(v[2], 3), Load(v[3], 3)};
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  double s[kSimplexLaneChunk], t[kSimplexLaneChunk], d2[kSimplexLaneChunk];
  bool boundary[kSimplexLaneChunk];
  for (int f = 0; f < 4; ++f) {
    const Vec& o = vertex[kFaces[f][0]];
    TriangleLanes(o, Sub(vertex[kFaces[f][1]], o), Sub(vertex[kFaces[f][2]], o), x, y, z, count, s, t, d2, boundary);
    for (int l = 0; l < count; ++l) {
      const bool better = onBoundary[l] && d2[l] < dist2[l];
      const double r0 = f == 0 || f == 1 ? s[l] : f == 2 ? 0.0 : 1.0 - s[l] - t[l];
      const double r1 = f == 0 ? t[l] : f == 1 ? 0.0 : s[l];
      const double r2 = f == 0 ? 0.0 : t[l];
      ref[0][l] = better ? r0 : ref[0][l];
      ref[1][l] = better ? r1 : ref[1][l];
      ref[2][l] = better ? r2 : ref[2][l];
      dist2[l] = better ? d2[l] : dist2[l];
    }
  }
}

/// True when the simplex is too flat for the lane formulas, or lies
/// outside the extents they take unscaled (ClosestPointOnSimplex scales it).
bool Degenerate(int dim, int ambientDim, const double* const* v) {
  if (SimplexUnitScale(dim, ambientDim, v) != 1.0) return true;
  const Vec a = Load(v[0], ambientDim);
  const Vec e1 = Sub(Load(v[1], ambientDim), a);
  if (dim == 1) return !(Dot(e1, e1) > 0);
  const Vec e2 = Sub(Load(v[2], ambientDim), a);
  if (dim == 2) {
    const Vec n = Cross(e1, e2), f = Sub(e2, e1);
    return !(Dot(n, n) > kWellShapedSin2 * Dot(e1, e1) * Dot(e2, e2)) || !(Dot(f, f) > 0);
  }
  const Vec e3 = Sub(Load(v[3], 3), a);
  const double volume = std::fabs(Dot(e1, Cross(e2, e3)));
  const double scale = std::sqrt(Dot(e1, e1) * Dot(e2, e2) * Dot(e3, e3));
  if (!(volume > kDegenerateLaneSimplex * scale)) return true;
  // Every face must be usable by the triangle lanes too.
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (const auto& face : kFaces) {
    const double* corners[3] = {v[face[0]], v[face[1]], v[face[2]]};
    if (Degenerate(2, 3, corners)) return true;
  }
  return false;
}

}  // namespace

void ClosestPointsOnSimplexLanes(int dim, int ambientDim, const double* const* v, const double* const coord[3],
                                 int count, double* const ref[3], double* dist2, bool* onBoundary) {
  if (Degenerate(dim, ambientDim, v)) {
    for (int l = 0; l < count; ++l) {
      const double p[3] = {coord[0][l], coord[1][l], ambientDim > 2 ? coord[2][l] : 0.0};
      double r[3], closest[3];
      dist2[l] = ClosestPointOnSimplex(dim, ambientDim, v, p, r, closest, &onBoundary[l]);
      for (int i = 0; i < dim; ++i) ref[i][l] = r[i];
    }
    return;
  }
  static const double kZeros[kSimplexLaneChunk] = {};
  for (int first = 0; first < count; first += kSimplexLaneChunk) {
    const int n = std::min(kSimplexLaneChunk, count - first);
    double* const chunkRef[3] = {ref[0] + first, dim > 1 ? ref[1] + first : nullptr, dim > 2 ? ref[2] + first : nullptr};
    SolveChunk(dim, ambientDim, v, coord[0] + first, coord[1] + first, ambientDim > 2 ? coord[2] + first : kZeros, n,
               chunkRef, dist2 + first, onBoundary + first);
  }
}

}  // namespace invmap::kernels
