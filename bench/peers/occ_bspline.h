// invmap's B-spline patches as OpenCascade geometry, for the peers that
// measure OpenCascade (peer_occ.cpp, distance_peers.cpp).
#pragma once

#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>

#include <vector>

#include "invmap/invmap.h"

namespace invmap::bench {

/// OpenCascade's knots: the distinct values and their multiplicities.
void SplitKnots(const std::vector<double>& knots, TColStd_Array1OfReal* values, TColStd_Array1OfInteger* mults);

/// A two-parameter B-spline patch in 3D as a Geom_BSplineSurface: the same
/// poles (u fastest in the patch, Poles(i, j) with i along u), weights,
/// knots and degrees.
Handle(Geom_BSplineSurface) ToOccSurface(const Patch& patch);

}  // namespace invmap::bench
