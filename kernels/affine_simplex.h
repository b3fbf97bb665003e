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
double ClosestPointOnSimplex(int dim, int ambientDim, const double* const* v, const double* p, double* ref,
                             double* closest, bool* onBoundary);

}  // namespace invmap::kernels
