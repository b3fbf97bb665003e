// Query points for the sign tests: around a shape's vertices and along its
// edges, moved off them in random directions by log-uniform amounts from
// 1e-9 to 1e-1 of the size, plus points near the surface (PointsAround).
#pragma once

#include <TopoDS_Shape.hxx>

#include <vector>

namespace invmap::cadtest {

std::vector<double> PointsNearEdgesAndVertices(const TopoDS_Shape& shape, int perFeature, unsigned seed);

}  // namespace invmap::cadtest
