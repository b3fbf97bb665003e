// Closest points on elementary surfaces (planes, cylinders, cones, spheres,
// ring tori) over a box of their own parameters, in closed form: what a
// cell of a CAD face on such a surface needs instead of the NURBS cell's
// local solve and branch and bound (docs/how-it-works.md, "Elementary
// surfaces in closed form").
//
// Why the closed forms are global over a box. Write the query point in the
// surface's frame: azimuth phi, distance rho from the axis, height h. On a
// cylinder, a cone, a sphere and a torus the squared distance is
// g(v) - 2 rho r(v) cos(u - phi), with r(v) the radius of the parallel at
// v: >= 0 on a cylinder, a sphere and a ring torus; of one sign on a
// cone's box that does not hold the apex and on a spindle torus's box that
// does not reach the axis (the boxes that do keep the NURBS search). So
// for every v the best u is the angle of [u0, u1] nearest phi (the
// opposite azimuth where r(v) < 0), circularly, whatever v is, and the
// box's minimum is that u and the best v in its meridian half-plane: a clamp onto the generator
// (cylinder, cone), the angle of [v0, v1] nearest the point's direction
// from the tube's centre (torus) or from the centre (sphere, where the
// latitude's range keeps cos v >= 0). A plane is a projection and a clamp
// (its axes are orthonormal). Every one of them is the exact minimum over
// the closed box.
//
// A trimmed cell (kernels/trimmed_cell.h) answers only inside its face's
// region, whose boundary the face's edges answer. Its closest point is the
// box's minimum when the region holds it, else a stationary point of the
// distance on the surface that the region holds (the closed forms list them
// all: plane 1, cylinder 2, cone 2, sphere 2, torus 4), else it has none of
// its own. A box wider than a turn holds each point of the surface at more
// than one turn of its angles: the region is asked about every one. Where
// the stationary points are not isolated (a point on the
// axis, at a sphere's centre, on a torus's centre circle) or the surface is
// singular in the box (a cone's apex, a spindle torus's points on its
// axis), the closed form declines and the NURBS cell's certified search
// answers.
#pragma once

#include <cstdint>

#include "kernels/cell_solver.h"
#include "kernels/trimmed_cell.h"

namespace invmap::kernels {

/// An elementary surface in its own parameters (u, v) (OpenCascade's):
///  - Plane:    origin + u x + v y;
///  - Cylinder: origin + radius e(u) + v z, e(u) = cos u x + sin u y;
///  - Cone:     origin + (radius + v sinAngle) e(u) + v cosAngle z;
///  - Sphere:   origin + radius (cos v e(u) + sin v z), v in [-pi/2, pi/2];
///  - Torus:    origin + (radius + minorRadius cos v) e(u) + minorRadius sin v z
///              (a ring torus, or a spindle one: minorRadius > radius).
/// x, y, z orthonormal (y need not be z cross x: a left-handed frame is fine).
struct AnalyticSurface {
  enum class Kind : std::uint8_t { Plane, Cylinder, Cone, Sphere, Torus };
  Kind kind = Kind::Plane;
  double origin[3] = {0, 0, 0};
  double x[3] = {1, 0, 0};
  double y[3] = {0, 1, 0};
  double z[3] = {0, 0, 1};
  double radius = 0.0;
  double minorRadius = 0.0;
  double sinAngle = 0.0;
  double cosAngle = 1.0;

  /// The point at own parameters (u, v).
  void Evaluate(double u, double v, double* xyz) const;
};

/// One cell of a face on an elementary surface: the surface, the cell's box
/// of own parameters (own = OwnParameter(paramLo, paramScale, angular, ref),
/// as for the NURBS cell), and the face's region when its loops cross it.
struct AnalyticCell {
  const AnalyticSurface* surface = nullptr;
  double paramLo[2] = {0, 0};
  double paramScale[2] = {1, 1};
  bool angular[2] = {false, false};
  const TrimmedCell* trim = nullptr;
};

/// True when the closed form holds over the whole of `cell`'s box: not a
/// cone's box that holds its apex (or comes within a rounding of it), nor
/// a spindle torus's that reaches its axis, nor a sphere's reaching past
/// the latitudes +-pi/2. Such cells keep the NURBS search.
bool ClosedFormCovers(const AnalyticCell& cell);

/// The own parameters of the foot of `point` on the whole surface (its
/// nearest point, or one of them; the turn of an angle nearest the
/// cell's box, a cone's nappe the box's), which may lie beyond the cell's
/// box: where the point's answer on the face probably is.
void SurfaceFoot(const AnalyticCell& cell, const double* point, double* own);

/// The closest point of `cell` to `point` (3 coordinates), as
/// CellSolver::Solve answers it for the NURBS cell: ref (the cell's
/// reference coordinates), closest (the surface at its own parameters),
/// distance, status Converged (inside the box) or ProjectedToBoundary, or
/// Farther when the cell has no point within `bound2` (squared; equality
/// admitted) or, trimmed, no candidate of its own. False, with `result`
/// untouched, where the closed form does not apply to this point (see the
/// file's comment): the caller solves the NURBS cell.
bool SolveAnalyticCell(const AnalyticCell& cell, const double* point, double bound2, CellSolveResult* result);

}  // namespace invmap::kernels
