// Closed-form closest points between two affine simplices (segments and
// triangles, in 2D or 3D): the pair kernel of triangle meshes and polylines,
// where a joint Newton solve would be wasted work.
#pragma once

namespace invmap::kernels {

/// Closest points of the affine simplices A (vertices a[0..dimA]) and B
/// (b[0..dimB]), dimA and dimB 1 (segment) or 2 (triangle), `ambientDim`
/// coordinates per vertex (2 or 3). Writes the reference coordinates of each
/// closest point (docs/formats.md: x = v0 + s (v1 - v0) [+ t (v2 - v0)])
/// and the points; returns the squared distance. Simplices that cross or
/// touch give 0 and a common point (up to rounding). Degenerate simplices
/// (coincident or collinear vertices) are handled: the answer is a closest
/// pair of the degenerate sets. Where several pairs are equally close
/// (parallel segments, a triangle's face parallel to another), any one of
/// them is returned.
double ClosestPointsOfSimplices(int dimA, const double* const* a, int dimB, const double* const* b, int ambientDim,
                                double* refA, double* refB, double* pointA, double* pointB);

/// A lower bound of the distance between the same simplices, cheap next to
/// ClosestPointsOfSimplices: the largest gap between their projections on a
/// triangle's normal (3D triangles only; 0 otherwise), less its rounding.
/// Two nearly parallel faces, the common case between meshes' nearby
/// triangles, are bounded almost exactly.
double SimplexPlaneGap(int dimA, const double* const* a, int dimB, const double* const* b, int ambientDim);

}  // namespace invmap::kernels
