// Closed-form closest points of many query points on one affine simplex
// (segment, triangle, tetrahedron), structure of arrays: the lane loops have
// no branches, so the compiler turns them into SIMD code. The batch driver
// solves all the points of a bucket against each affine candidate this way.
#pragma once

namespace invmap::kernels {

/// Lanes processed per call of the inner loops (the callers' chunk size).
inline constexpr int kSimplexLaneChunk = 64;

/// Closest points to `count` query points, lane l being (coord[0][l],
/// coord[1][l], coord[2][l]) (coord[2] unused in 2D), on the simplex with
/// vertices v[0..dim] (`ambientDim` coordinates each). Per lane writes the
/// reference coordinates ref[i][l] (i < dim: the barycentric coordinates of
/// vertices 1..dim, as ClosestPointOnSimplex), the squared distance dist2[l]
/// and whether the point is on the simplex's boundary (onBoundary[l]). A
/// point inside a tetrahedron is its own closest point. A degenerate simplex
/// (nearly coincident or collinear vertices) is solved lane by lane by
/// ClosestPointOnSimplex.
void ClosestPointsOnSimplexLanes(int dim, int ambientDim, const double* const* v, const double* const coord[3],
                                 int count, double* const ref[3], double* dist2, bool* onBoundary);

}  // namespace invmap::kernels
