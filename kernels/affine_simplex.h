// Closed-form closest points on affine simplices (7.3.2.2: an affine map needs
// no Newton iterations): segments, triangles and tetrahedra in 2D or 3D.
#pragma once

namespace invmap::kernels {

/// Closest point to `p` on the simplex with vertices v[0..dim] (`ambientDim`
/// coordinates each): writes its reference coordinates (the barycentric
/// coordinates of vertices 1..dim, docs/formats.md section 1) to `ref` and the
/// point to `closest`; returns the squared distance and sets `onBoundary`.
/// Degenerate simplices (coincident or collinear vertices) are handled: the
/// answer is a closest point of the degenerate set.
/// Exact over the whole supported range (docs/limitations.md, "Ranges"): a
/// simplex whose extent lies outside [2^-100, 2^100] is solved scaled by a
/// power of two (SimplexUnitScale), where the closed forms' products of up to
/// six edge lengths neither overflow nor underflow.
double ClosestPointOnSimplex(int dim, int ambientDim, const double* const* v, const double* p, double* ref,
                             double* closest, bool* onBoundary);

/// 1 when the simplex's extent (its largest coordinate difference from
/// v[0]) lies in [2^-100, 2^100] or is 0; otherwise the power of two that
/// brings it into [1/2, 1).
double SimplexUnitScale(int dim, int ambientDim, const double* const* v);

}  // namespace invmap::kernels
