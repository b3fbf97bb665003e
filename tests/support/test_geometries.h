// Geometries and query sets for the engine tests: analytic NURBS shapes with
// closed-form distances, B-spline and Bezier geometries for brute-force
// comparison, large linear triangle meshes, and multi-patch mixes. Every
// builder is deterministic (fixed seeds) and returns a valid geometry.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

// The support library is built without the engine's include path; this is
// the same public header that tests include as "invmap/invmap.h".
#include "invmap/invmap.h"
#include "tests/support/patch_reference.h"
#include "tests/support/result_check.h"

namespace invmap::testing {

using Vec3 = std::array<double, 3>;

// ---------------------------------------------------------------------------
// Analytic shapes (rational B-spline patches with exact closed-form distances).

/// NURBS sphere (center c, radius r) as a surface of revolution: u turns
/// around the z axis (full circle, 9 control points, degree 2), v runs along
/// the meridian from the south to the north pole (semicircle, 5 control
/// points, degree 2); the first and last rows of the net are collapsed onto
/// the poles. 4 x 2 cells.
Geometry NurbsSphere(const Vec3& c, double r);
/// | |p - c| - r |.
double SphereDistance(const Vec3& c, double r, const double* p);

/// NURBS torus around the z axis through c (major radius big, minor small):
/// a full circle revolved around a full circle, 9 x 9 control points, 4 x 4
/// cells; non-uniform knot values so parameters are not trivially angles.
Geometry NurbsTorus(const Vec3& c, double big, double small);
/// | sqrt((sqrt(x^2 + y^2) - big)^2 + z^2) - small | with (x, y, z) = p - c.
double TorusDistance(const Vec3& c, double big, double small, const double* p);

/// A plane frame: origin and two orthonormal axes (z components 0 in 2D).
struct Frame {
  Vec3 origin{{0, 0, 0}};
  Vec3 e1{{1, 0, 0}};
  Vec3 e2{{0, 1, 0}};
};
/// A tilted frame in 3D (orthonormal axes from fixed angles).
Frame TiltedFrame(const Vec3& origin);

/// NURBS circle of radius r in the plane of `frame` (dimension 2 or 3): 9
/// control points, degree 2, 4 cells.
Geometry NurbsCircle(int dim, const Frame& frame, double r);
/// Distance from p to that circle.
double CircleDistance(int dim, const Frame& frame, double r, const double* p);

/// NURBS annulus (inner radius r1, outer r2) in the plane of `frame`: u is
/// the circle (degree 2), v runs linearly from r1 to r2 (degree 1); 4 cells.
/// In 2D it is a full-rank (volume-like) patch.
Geometry NurbsAnnulus(int dim, const Frame& frame, double r1, double r2);
/// Distance from p to that (filled) annulus.
double AnnulusDistance(int dim, const Frame& frame, double r1, double r2, const double* p);

// ---------------------------------------------------------------------------
// Brute-force geometries.

/// A knot vector of degree p with `distinct` distinct interior knots at
/// random non-uniform positions in (0, 1), some of multiplicity 2 .. p
/// (about one in `repeatEvery`), clamped ends (multiplicity p + 1) or, when
/// `clamped` is false, simple equally spaced end knots beyond [0, 1].
std::vector<double> RandomKnots(int p, int distinct, int repeatEvery, bool clamped, std::mt19937_64& rng);

/// Greville abscissa of control point i (mean of knots i+1 .. i+p),
/// rescaled so the domain [t_p, t_n] maps to [0, 1].
double Greville(const std::vector<double>& knots, int p, int i);

/// Two wavy B-spline surfaces over hundreds of spans with repeated interior
/// knots: patch 0 polynomial bicubic (about 23 x 17 spans), patch 1 rational
/// degree (2, 3) with unclamped u knots, hovering over patch 0 and tilted.
Geometry WavySurfaces();

/// B-spline curves in dimension 2 (a spiral of degree 3 with 150 spans and a
/// rational degree-2 wiggle) or 3 (an unclamped degree-4 helix, a degree-1
/// polyline spline and a rational degree-5 curve with a C0 knot).
Geometry BSplineCurves(int dim);

/// B-spline volumes: patch 0 a bent, twisted block of degrees (2, 2, 3) with
/// a repeated knot (about 6 x 5 x 4 cells), patch 1 a small rational
/// triquadratic block beside it.
Geometry BSplineVolumes();

/// Curved structured meshes of quadratic Bezier elements, conforming (shared
/// faces have equal control points): 6 x 5 x 4 hexes [2, 2, 2], one Bezier
/// patch per element (hexes = true), or 4 x 4 x 3 cubes of 6 tets [2] each,
/// all in one BezierCells patch.
Geometry QuadraticMesh(bool hexes);

/// Mesh patch of linear cells of `type` over a structured nx x ny x nz grid
/// of vertices f(i / nx, j / ny, k / nz) (tri and quad: nz = 0; line: ny =
/// nz = 0), FE vertex order; tets split each cube into 6 (Kuhn), wedges
/// each quad prism into 2.
Patch GridMesh(CellType type, int dim, int nx, int ny, int nz, const std::function<Vec3(double, double, double)>& f);

/// A conforming mesh of three linear patches under one curved map: 3 x 3 x 2
/// hexes on [0, 1]^3, 3 x 3 x 2 prisms of 2 wedges each on [1, 2] x [0, 1]^2
/// (sharing the hexes' faces at x = 1), and 3 x 3 x 2 cubes of 6 tets on
/// [1, 2] x [0, 1] x [1, 2] (sharing the wedges' triangles at z = 1).
Geometry MixedVolumeMesh();

/// A linear triangle mesh patch: a bumpy sphere (latitude-longitude grid
/// with nLon x nLat quads, 2 triangles each, fans at the poles).
Patch BumpySphereMesh(int nLon, int nLat, const Vec3& c, double r);
/// A linear triangle mesh patch: a wavy height field over an n x n grid
/// (2 n^2 triangles) on [0, 1]^2, or its 2D projection (planar, dim 2).
Patch WavyHeightField(int n, int dim);

/// Mixed 3D geometry: B-spline surface, rational Bezier tri, Bezier quad,
/// linear tri mesh, 3D B-spline curve, bilinear quad mesh, Bezier wedge,
/// linear tet, hex and wedge meshes, Bezier line, rational Bezier tet,
/// polyline mesh, Bezier hex and a BezierCells patch of mixed cell types.
Geometry MixedGeometry3();
/// Mixed 2D geometry: a B-spline surface (full-rank in 2D), a linear tri
/// mesh, a B-spline curve, a quadratic Bezier tri and a Bezier line.
Geometry MixedGeometry2();

// ---------------------------------------------------------------------------
// Queries.

/// How many query points of each kind MakeQueries draws. A base point is a
/// random point of a random cell of a random patch (patches equally likely).
struct QueryMix {
  int on = 0;      ///< The base point itself.
  int near = 0;    ///< Base + random direction * U(0, nearFraction) * size.
  int mid = 0;     ///< Base + random direction * U(0.05, 0.5) * size.
  int far = 0;     ///< Base + random direction * U(1.5, 5) * size.
  int inside = 0;  ///< A random point of a random full-rank cell (volumes).
  double nearFraction = 0.03;
};

/// `count` times the fraction in the environment variable
/// INVMAP_ENGINE_QUERY_FRACTION (default 1, at least 1 point when count > 0):
/// sanitizer builds can run the same tests on fewer points.
int ScaledCount(int count);

/// Queries of the given mix around `cells` (dimension dim, geometry size
/// `size`); every count goes through ScaledCount.
QuerySet MakeQueries(const std::vector<PatchCell>& cells, int dim, double size, const QueryMix& mix,
                     std::uint64_t seed);

/// Uniform random unit vector in dimension dim (z = 0 in 2D).
Vec3 RandomDirection(int dim, std::mt19937_64& rng);

}  // namespace invmap::testing
