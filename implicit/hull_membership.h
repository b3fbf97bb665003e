// Exact membership of the origin in the closed convex hull of a small point
// set: the zero-crossing test of an adaptive simplicial grid (a cell whose
// Bezier control values' hull misses the origin holds no zero of the proxy
// function, section 3.2 of the adaptive-grid paper).
#pragma once

namespace invmap::implicit {

/// Point counts up to this are handled without heap allocation (a cubic
/// Bezier tetrahedron has 20 control values). Larger counts work but allocate.
inline constexpr int kMaxHullPointsOnStack = 64;

/// True iff 0 lies in the closed hull of values[0..count): some value is <= 0
/// and some is >= 0. False for count <= 0. Inputs must be finite.
bool OriginInConvexHull1d(const double* values, int count);

/// True iff the origin lies in the closed convex hull of the `count` points
/// xy[2 k], xy[2 k + 1] (interleaved x, y). The answer is exact for every
/// configuration: origin on an edge or at a vertex counts as inside;
/// collinear and repeated points are fine. False for count <= 0.
/// Preconditions: finite inputs. Exactness additionally needs, within each
/// point, the ratio of its largest to its smallest nonzero |coordinate| to be
/// below 2^290 (points are rescaled by powers of two when their magnitudes
/// leave [2^-256, 2^256]; beyond that ratio the small coordinate could
/// underflow).
bool OriginInConvexHull2d(const double* xy, int count);

/// True iff the origin lies in the closed convex hull of the `count` points
/// xyz[3 k + 0..2]. Exact for every configuration (origin on a face, an edge
/// or a vertex; coplanar, collinear or repeated points; a point at the
/// origin). False for count <= 0. Same preconditions as the 2D version.
bool OriginInConvexHull3d(const double* xyz, int count);

}  // namespace invmap::implicit
