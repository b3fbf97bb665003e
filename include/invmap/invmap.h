// invmap: closest points, cells and parameters of batches of query points on
// geometries made of parametric cells. A public header: with implicit.h (the
// implicit-complex grids) it is what include/invmap/ installs, and all a
// program of libinvmap (CMake: invmap::invmap) includes.
//
//   invmap::Geometry geometry = ...;                 // patches in memory (docs/formats.md section 2)
//   invmap::BuildResult built = invmap::Manifold::Build(geometry);
//   if (!built.error.empty()) { ... }                // malformed geometry, with the reason
//   invmap::Results results;
//   invmap::Error e = built.manifold.Invert(invmap::PointsView::Interleaved(xyz, n, 3), {}, &results);
//
// Nothing here throws for a bad query point: each point gets a Status.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "invmap/cell_type.h"
#include "invmap/geometry_error.h"

namespace invmap {

/// A B-spline or NURBS curve: the trimming loops and the edges of a
/// TrimmedSurface patch.
struct SplineCurve {
  int degree = 1;
  /// count + degree + 1 non-decreasing knots; the curve is the part over
  /// [knots[degree], knots[count]].
  std::vector<double> knots;
  /// Control points, point-major: 2 coordinates each for a curve in a
  /// surface's parameters, 3 for a curve in space.
  std::vector<double> points;
  /// Optional: one positive weight per control point.
  std::vector<double> weights;
  /// The curve's own parameter is an angle (an arc of a circle or an
  /// ellipse): degree 2, and every knot span [a, b] is one symmetric rational
  /// quadratic arc (end weights equal, middle weight cos((b - a) / 2) times
  /// theirs) whose knots a, b are the angles at its ends. False: the own
  /// parameter is the knot value.
  bool angular = false;
};

/// An edge of a TrimmedSurface patch: a boundary curve of the face, whose
/// points are answers too (searched as curve cells).
struct PatchEdge {
  /// The edge in space (3 coordinates per control point).
  SplineCurve curve;
  /// The same edge in the surface's own parameters (2 coordinates per
  /// control point), over the same own parameter as `curve`: an answer on
  /// the edge reports pcurve's (u, v) there. No points: unknown (the
  /// answer's u and v are NaN).
  SplineCurve pcurve;
};

/// The elementary surface a TrimmedSurface patch's B-spline surface is
/// exactly, in the surface's own parameters (OpenCascade's conventions for
/// Geom_Plane, Geom_CylindricalSurface, Geom_ConicalSurface,
/// Geom_SphericalSurface and Geom_ToroidalSurface; e(u) = cos u xAxis +
/// sin u yAxis):
///  - Plane:    origin + u xAxis + v yAxis;
///  - Cylinder: origin + radius e(u) + v axis;
///  - Cone:     origin + (radius + v sin(semiAngle)) e(u) + v cos(semiAngle) axis;
///  - Sphere:   origin + radius (cos v e(u) + sin v axis), v the latitude;
///  - Torus:    origin + (radius + minorRadius cos v) e(u) + minorRadius sin v axis.
/// An accelerator only: the cells of such a face are then answered in
/// closed form instead of by the NURBS cell's search (docs/cad.md), and
/// the B-spline surface stays the geometry for everything else. It is
/// ignored unless it agrees with the B-spline surface (the frame
/// orthonormal, and the two within 1e-9 of the surface's size at sample
/// points of every cell). Cells where the closed form does not hold keep
/// the NURBS search: those at a cone's apex, those of a spindle torus
/// (minorRadius > radius) that reach its axis, a sphere's beyond the
/// latitudes +-pi/2.
struct AnalyticSurface {
  enum class Kind : std::uint8_t { None, Plane, Cylinder, Cone, Sphere, Torus };
  Kind kind = Kind::None;
  double origin[3] = {0, 0, 0};
  double xAxis[3] = {1, 0, 0};
  double yAxis[3] = {0, 1, 0};  ///< Orthonormal to both others (either handedness).
  double axis[3] = {0, 0, 1};
  double radius = 0.0;       ///< Cylinder, sphere; a cone's at v = 0; a torus's major radius.
  double minorRadius = 0.0;  ///< Torus.
  double semiAngle = 0.0;    ///< Cone (radians).
};

/// One patch of a geometry, as in the geometry file (docs/formats.md section 2).
/// Fields not used by a kind are left empty.
///  - BSpline: degrees, knots, counts, points, optional weights.
///  - Bezier: one cell: cell, degrees, points, optional weights.
///  - Mesh: linear cells sharing vertices: cell, points (the vertices), cells.
///  - BezierCells: many Bezier cells of any types and degrees (a high-order
///    mesh after the change to Bernstein form, e.g. one gmsh physical group):
///    cellTypes, cellDegrees, cellOffsets, points, optional weights.
///  - TrimmedSurface: a trimmed face of a CAD model (docs/cad.md): a
///    B-spline or NURBS surface as for BSpline (degrees [p, q], knots, counts,
///    points, optional weights; 3D only), optional `angular`, restricted to
///    the region of its parameter plane that `trimLoops` enclose, with the
///    face's `edges`. Its cells are the surface's knot spans, numbered as a
///    BSpline patch's (u fastest; spans wholly outside the region have no
///    cell), then the spans of each edge's curve, edge after edge, numbered
///    on from the surface's span count. Surface cells report the surface's
///    own (u, v); edge cells the edge's pcurve (u, v) at the answer.
///    The closest point of a face is either inside its region or on the
///    region's boundary, so every curve of that boundary must be an edge
///    of some TrimmedSurface patch of the geometry (of this one or of the
///    face across it).
///  - PouManifold: a partition-of-unity surface over a closed triangle mesh
///    (include/invmap/pou.h, docs/manifold.md): points (the mesh's vertices),
///    cells (its triangles, 3 indices each), degrees (one bidegree per
///    vertex's chart), chartControlPoints. Its cells are the charts (one per
///    vertex), their parameters the chart's local coordinates (u, v).
struct Patch {
  enum class Kind : std::uint8_t { BSpline, Bezier, Mesh, BezierCells, TrimmedSurface, PouManifold };
  Kind kind = Kind::Bezier;
  /// Bezier and Mesh: the cell type. BSpline: ignored (the parametric
  /// dimension is degrees.size(): line, quad or hex cells).
  CellType cell = CellType::Line;
  /// BSpline: p, (q, (r)). Bezier: one degree per simplex factor
  /// (line [p], tri [p], quad [p, q], tet [p], hex [p, q, r], wedge [p_tri, q_line]).
  std::vector<int> degrees;
  /// BSpline: one non-decreasing knot vector per direction, length counts[i] + degrees[i] + 1.
  std::vector<std::vector<double>> knots;
  /// BSpline: control points per direction, n_u, (n_v, (n_w)).
  std::vector<int> counts;
  /// BSpline, Bezier: control points, point-major, `dimension` values each,
  /// in docs/formats.md order. Mesh: the vertices, the same layout.
  std::vector<double> points;
  /// Optional: one positive weight per control point (rational patch).
  std::vector<double> weights;
  /// Mesh: vertex indices (0-based), cell-major, vertices per cell fixed by
  /// the cell type (line 2, tri 3, quad 4, tet 4, hex 8, wedge 6).
  std::vector<std::int64_t> cells;
  /// BezierCells: the type of each cell.
  std::vector<CellType> cellTypes;
  /// BezierCells: 3 degrees per cell (one per simplex factor as for Bezier,
  /// unused entries 0).
  std::vector<int> cellDegrees;
  /// BezierCells: cellTypes.size() + 1 offsets; cell c's control points (and
  /// weights) are points [cellOffsets[c], cellOffsets[c + 1]) of `points`.
  std::vector<std::int64_t> cellOffsets;
  /// TrimmedSurface: per direction (u, v), 1 when the surface's own parameter
  /// there is an angle (see SplineCurve::angular: degree 2, every knot span
  /// one symmetric arc of every row of control points), 0 when it is the knot
  /// value. Empty: neither.
  std::vector<std::uint8_t> angular;
  /// TrimmedSurface: closed loops in the surface's own parameters, each a
  /// list of 2D curves following each other end to end (a gap between one
  /// curve's end and the next one's start, the last's and the first's
  /// included, is closed by a straight segment). The region is what they
  /// enclose by the even-odd rule, so their orientation does not matter.
  /// No loops: the whole surface.
  std::vector<std::vector<SplineCurve>> trimLoops;
  /// TrimmedSurface: the boundary curves of the face answered from this patch.
  std::vector<PatchEdge> edges;
  /// TrimmedSurface, optional: the elementary surface the B-spline surface
  /// is (see AnalyticSurface; Kind::None: none).
  AnalyticSurface analytic;
  /// PouManifold: the shape functions' control points, chart after chart:
  /// (degrees[v] + 1)^2 points of 3 coordinates for vertex v, x fastest.
  std::vector<double> chartControlPoints;
};

/// A geometry: its ambient dimension (2 or 3) and its patches.
struct Geometry {
  int dimension = 3;
  std::vector<Patch> patches;
};

/// Per-point result status (docs/formats.md section 5 codes).
enum class Status : std::uint8_t {
  Found = 0,    ///< The closest point is in the results.
  None = 1,     ///< No cell within InversionOptions::maxDistance.
  Invalid = 2,  ///< The query point has a NaN or infinite coordinate.
};

/// Batch-level outcome of a call. Per-point problems are never errors.
enum class Error : std::uint8_t {
  Ok = 0,
  InvalidArgument,  ///< Malformed view or options (see the message of LastErrorMessage()).
  OutOfMemory,
  Internal,         ///< A bug: an unexpected exception was caught at the API boundary.
};

/// Floating-point type of query coordinates.
enum class Scalar : std::uint8_t { Float32, Float64 };

/// Non-owning view of N query points of dimension 2 or 3. Coordinate k of
/// point i is at coord[k][i * stride] (elements of type `scalar`).
/// Interleaved xyz: coord[k] = data + k, stride = dim. Separate arrays:
/// coord[k] = array k, stride = 1.
struct PointsView {
  std::size_t count = 0;
  int dim = 3;
  Scalar scalar = Scalar::Float64;
  const void* coord[3] = {nullptr, nullptr, nullptr};
  std::size_t stride = 3;

  static PointsView Interleaved(const double* xyz, std::size_t count, int dim);
  static PointsView Interleaved(const float* xyz, std::size_t count, int dim);
  /// z is ignored (may be null) when dim == 2.
  static PointsView Separate(const double* x, const double* y, const double* z, std::size_t count, int dim);
  static PointsView Separate(const float* x, const float* y, const float* z, std::size_t count, int dim);
};

/// Options of a batch inversion.
struct InversionOptions {
  /// Gap tolerance (model units): points farther than this from every cell
  /// get Status::None. Default: unlimited. Any D >= 0 is exact on the near
  /// side: a point at distance <= D is always found (D = 0 finds every point
  /// on the geometry, and every point inside a volume, at distance 0). A
  /// point is None only when every cell is certified farther than D; a
  /// cell's distance is computed to 1e-11 of its size, so a found point may
  /// report a distance up to that much beyond D.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// Worker threads; 0 means all cores, and more than the cores this process
  /// may use runs as many as the cores. Results do not depend on it.
  int threads = 0;
  /// Query points per spatial bucket (a bucket shares one BVH traversal).
  /// Cost: larger buckets cull less precisely; smaller ones traverse more.
  int bucketSize = 32;
  /// Optional: every point searched on its own, from a start of its own,
  /// so that its answer is a function of the point and the geometry only,
  /// bit for bit, whatever batch (chunk, Dask partition) it comes in. By
  /// default a point's solve starts from its spatial neighbour's answer and
  /// its bucket shares one candidate list: the same minimum to the solve's
  /// tolerance, but its last digits (and which of two equally near cells is
  /// reported) depend on the batch. Cost: see docs/limitations.md.
  bool pointwise = false;
};

/// Results of a batch, structure of arrays, one entry per query point in
/// input order (length N each; params and closest hold 3 values per point).
struct Results {
  std::vector<Status> status;
  std::vector<std::int32_t> patch;   ///< -1 when not found.
  std::vector<std::int64_t> cell;    ///< Cell index within the patch; -1 when not found.
  /// Parameters (u, v, w) of the closest point, 3 per point: B-spline
  /// patches report knot values, Bezier and mesh cells reference coordinates
  /// (docs/formats.md section 2); unused ones are NaN.
  std::vector<double> params;
  /// Closest point, 3 per point (z = 0 in 2D); NaN when not found.
  std::vector<double> closest;
  std::vector<double> distance;      ///< Euclidean distance; NaN when not found.
  std::vector<std::int32_t> iterations;  ///< Newton iterations spent on the point.
};

/// Counts describing a built manifold.
struct ManifoldInfo {
  int dimension = 3;
  std::size_t patches = 0;
  std::size_t cells = 0;
  /// Cells per (type, degrees): e.g. "quad 3x3" -> 1024.
  std::vector<std::pair<std::string, std::size_t>> cellsByShape;
  /// Box of the cells' control points: holds the geometry (convex hull
  /// property), and reaches beyond it where a cell bulges less than its net.
  double boundsLo[3] = {0, 0, 0};
  double boundsHi[3] = {0, 0, 0};
  std::size_t memoryBytes = 0;  ///< Heap memory of the built manifold (cells, bounds, BVH).
};

class Manifold;
struct ManifoldAccess;

/// Result of Manifold::Build: a manifold, or what is wrong with the geometry.
struct BuildResult;

/// An immutable geometry ready for queries: Bezier cells with their bounds and
/// a BVH. Thread-safe to query from many threads; movable, not copyable.
class Manifold {
 public:
  /// Builds from patches in memory. Never throws: a malformed geometry gives
  /// BuildResult::problem, the patch, field and element at fault, and
  /// BuildResult::error, its text (e.g. "patch 2: knots[1]: decreasing at
  /// index 4 (0.5 > 0.25)"). Every geometry is checked here, whatever
  /// produced it.
  static BuildResult Build(const Geometry& geometry);
  /// The same manifold, from a geometry the caller no longer needs: the
  /// build may take its arrays instead of copying them. A geometry of
  /// triangle meshes alone (Mesh patches of Tri cells in 3D) gives up its
  /// vertices and indices, which the manifold keeps (as 32-bit indices)
  /// while the geometry's 64-bit ones are freed before the search tree is
  /// built: on a large mesh that takes the geometry as read, about 37 bytes
  /// a triangle, off the build's peak (docs/limitations.md, "Memory").
  /// Afterwards `geometry` is valid, its patches and their kinds are there,
  /// but their `points` and `cells` may be empty; a geometry that fails
  /// validation (BuildResult::problem) is left as it was. Answers are those
  /// of Build(const Geometry&).
  static BuildResult Build(Geometry&& geometry);

  Manifold();
  ~Manifold();
  Manifold(Manifold&&) noexcept;
  Manifold& operator=(Manifold&&) noexcept;
  Manifold(const Manifold&) = delete;
  Manifold& operator=(const Manifold&) = delete;

  /// True once built (a default-constructed manifold is empty).
  bool valid() const;
  ManifoldInfo Info() const;

  /// Number of cells of patch `patch` (0 for an out-of-range patch).
  std::int64_t NumCells(int patch) const;

  /// A point of cell `cell` of patch `patch`: `sample` in [0, 1]^3 is mapped
  /// onto the cell's reference domain (uniformly for tensor products; simplex
  /// factors fold the unit square/cube onto the simplex), and the cell is
  /// evaluated there. Writes the reported parameters (3, NaN where unused)
  /// and the point (3, z = 0 in 2D). Returns false for out-of-range indices.
  bool PointAt(int patch, std::int64_t cell, const double sample[3], double params[3], double point[3]) const;

  /// Closest points of every query point. `results` is resized to the
  /// number of points. Returns Error::Ok, or a batch-level error with a
  /// message in `message` (optional). Never throws.
  Error Invert(const PointsView& points, const InversionOptions& options, Results* results,
               std::string* message = nullptr) const;

 private:
  friend struct ManifoldAccess;  // the engine's own systems (distance queries) read the built parts
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct BuildResult {
  Manifold manifold;
  /// What is wrong with the geometry; no error (empty message) on success.
  /// An error of the build itself (out of memory) has no place: patch -1,
  /// field None.
  GeometryError problem;
  std::string error;  ///< Describe(problem): empty on success.
  /// Why it failed: InvalidArgument for a malformed geometry (`problem`
  /// says where), OutOfMemory, or Internal (a bug); Ok on success.
  Error code = Error::Ok;
};

/// Library version, "major.minor.patch".
const char* Version();

}  // namespace invmap
