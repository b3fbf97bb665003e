// Geometries for the distance tests: analytic NURBS shapes beside those of
// tests/support/test_geometries.h, and curved B-spline curves and surfaces
// whose distances to each other have several local minima.
#pragma once

#include <array>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::testing {

/// NURBS cylinder of radius r around the z axis, z from -h/2 to h/2 (a
/// degree-2 circle times a line): 4 cells.
Geometry NurbsCylinder(double r, double h);

/// A single-patch geometry of one Bezier line through the given control
/// points (3D), degree = points - 1.
Geometry BezierCurve(const std::vector<std::array<double, 3>>& points);

/// A bilinear plane patch z = 0 over [-s, s]^2 (one Bezier quad of degree 1).
Geometry PlaneSquare(double s);

/// A wavy cubic B-spline curve in 3D along x from 0 to 1: z = amplitude
/// sin(waves 2 pi x), y = 0.1 cos(3 x), `spans` spans.
Geometry WavyCurve(double amplitude, int waves, int spans);

/// A wavy bicubic B-spline surface over [0, 1]^2: z = amplitude
/// sin(wx 2 pi x) cos(wy 2 pi y), `spans` spans per direction, rational
/// (weights between 0.8 and 1.25) when `rational`.
Geometry WavySurface(double amplitude, int wx, int wy, int spans, bool rational);

/// A linear triangle mesh patch of a bumpy sphere (tests/support's
/// BumpySphereMesh) as a geometry.
Geometry MeshGeometry(const Patch& patch);

/// A hexahedral mesh of the box [lo, hi] with n cells per side (linear hexes).
Geometry BoxHexMesh(const std::array<double, 3>& lo, const std::array<double, 3>& hi, int n);

/// Distance from p to the solid box [lo, hi] (0 inside).
double BoxDistance(const std::array<double, 3>& lo, const std::array<double, 3>& hi, const double* p);

}  // namespace invmap::testing
