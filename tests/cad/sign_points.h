// Helpers of the sign tests: query points, and where the model's own
// precision leaves the side of a point to the model.
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <vector>

namespace invmap::cadtest {

/// Points around the shape's vertices and along its edges, moved off them
/// in random directions by log-uniform amounts from 1e-9 to 1e-1 of the
/// size, plus points near the surface (PointsAround).
std::vector<double> PointsNearEdgesAndVertices(const TopoDS_Shape& shape, int perFeature, unsigned seed);

/// True when `closest` (a point's closest point, on `face`) lies within the
/// model's own precision of an edge of the face and the point is that near
/// too: the side there is the model's to say, not a reference's (a
/// boolean's intersection edge is a curve within its tolerance of the exact
/// one, and the point may lie between the two).
bool WithinModelPrecisionOfAnEdge(const TopoDS_Face& face, double distance, const double* closest);

}  // namespace invmap::cadtest
