// Sample geometries of `invmap generate`, shared by the demos, tests and benchmarks.
#pragma once

#include <cstdint>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::samples {

/// A wavy bicubic B-spline surface over [0, 1]^2 with `spans` x `spans`
/// knot spans and a crease (a triple knot, C0) along u = 0.5. Dimension 3.
Geometry WavySurface(int spans);

/// A NURBS torus (biquadratic, rational, 9 x 9 control points) around the z
/// axis with major radius `major` and tube radius `minor`. Dimension 3.
Geometry NurbsTorus(double major, double minor);

/// A planar cubic NURBS curve with tight turns (high curvature), non-uniform
/// knots and varying weights. Dimension 2.
Geometry NurbsCurve2D();

/// A quadratic tetrahedral mesh of a curved solid (a bent, twisted beam):
/// `resolution`^3 cubes of 6 tets each, every node placed by a smooth curved
/// map. Returned as Lagrange nodes in gmsh's 10-node order, for writing.
struct QuadraticTetMesh {
  std::vector<double> nodes;            ///< x, y, z per node.
  std::vector<std::int64_t> tets;       ///< 10 node indices per tet (gmsh tet10 order).
};
QuadraticTetMesh CurvedTetMesh(int resolution);

/// The same mesh as a BezierCells patch (Bernstein control points).
Geometry ToBezierGeometry(const QuadraticTetMesh& mesh);

/// A closed triangle mesh of a bumpy sphere with at least `minTriangles`
/// triangles (a subdivided icosahedron: 20 * 4^k triangles). Dimension 3.
Geometry BumpySphere(std::int64_t minTriangles);

}  // namespace invmap::samples
