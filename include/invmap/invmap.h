// invmap: closest points, cells and parameters of batches of query points on
// geometries made of parametric cells. A public header: with implicit.h (the
// implicit-complex grids) it is what include/invmap/ installs, and all a
// program of libinvmap (CMake: invmap::invmap) includes.
//
//   invmap::Geometry geometry = ...;                 // patches in memory (FORMATS.md section 2)
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

namespace invmap {

/// Reference cell types (FORMATS.md section 1).
enum class CellType : std::uint8_t { Line, Tri, Quad, Tet, Hex, Wedge };

/// One patch of a geometry, as in the geometry file (FORMATS.md section 2).
/// Fields not used by a kind are left empty.
///  - BSpline: degrees, knots, counts, points, optional weights.
///  - Bezier: one cell: cell, degrees, points, optional weights.
///  - Mesh: linear cells sharing vertices: cell, points (the vertices), cells.
///  - BezierCells: many Bezier cells of any types and degrees (a high-order
///    mesh after the change to Bernstein form, e.g. one gmsh physical group):
///    cellTypes, cellDegrees, cellOffsets, points, optional weights.
struct Patch {
  enum class Kind : std::uint8_t { BSpline, Bezier, Mesh, BezierCells };
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
  /// in FORMATS.md order. Mesh: the vertices, the same layout.
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
};

/// A geometry: its ambient dimension (2 or 3) and its patches.
struct Geometry {
  int dimension = 3;
  std::vector<Patch> patches;
};

/// Per-point result status (FORMATS.md section 4 codes).
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
  /// get Status::None. Default: unlimited.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// Worker threads; 0 means all cores. Results do not depend on it.
  int threads = 0;
  /// Query points per spatial bucket (a bucket shares one BVH traversal).
  /// Cost: larger buckets cull less precisely; smaller ones traverse more.
  int bucketSize = 32;
};

/// Results of a batch, structure of arrays, one entry per query point in
/// input order (length N each; params and closest hold 3 values per point).
struct Results {
  std::vector<Status> status;
  std::vector<std::int32_t> patch;   ///< -1 when not found.
  std::vector<std::int64_t> cell;    ///< Cell index within the patch; -1 when not found.
  /// Parameters (u, v, w) of the closest point, 3 per point: B-spline
  /// patches report knot values, Bezier and mesh cells reference coordinates
  /// (FORMATS.md section 2); unused ones are NaN.
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

/// Result of Manifold::Build: a manifold, or an error message naming the
/// patch and field that is wrong.
struct BuildResult;

/// An immutable geometry ready for queries: Bezier cells with their bounds and
/// a BVH. Thread-safe to query from many threads; movable, not copyable.
class Manifold {
 public:
  /// Builds from patches in memory. Never throws: a malformed geometry gives
  /// an error message (e.g. "patch 2: knots[1]: decreasing at index 4").
  static BuildResult Build(const Geometry& geometry);

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
  std::string error;  ///< Empty on success.
};

/// Library version, "major.minor.patch".
const char* Version();

}  // namespace invmap
