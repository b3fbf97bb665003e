// invmap::implicit: adaptive simplicial grids for implicit complexes. A public
// header, installed with invmap.h and part of libinvmap (invmap::invmap).
//
// Given k implicit functions with gradients, a triangle (2D) or tetrahedron
// (3D) grid is refined by longest-refinable-edge bisection until every zero
// set of the complex (surfaces f_i = 0, curves f_i = f_j = 0, points
// f_i = f_j = f_l = 0; or the interfaces of a material partition, or the
// boundary of a CSG solid) is within `epsilon` of its piecewise-linear
// discretization (docs/grids.md).
//
//   std::vector<invmap::implicit::Function> functions = {
//       invmap::implicit::Function::Sphere({0.5, 0.5, 0.5}, 0.3)};
//   invmap::implicit::GridOptions options;
//   options.epsilon = 1e-3;
//   invmap::implicit::GridResult result = invmap::implicit::RefineGrid(
//       invmap::implicit::SimplexMesh::Box({0, 0, 0}, {1, 1, 1}, 3, 1), functions, options);
//   if (!result.error.empty()) { ... }
//   invmap::implicit::ZeroSets zeroSets = invmap::implicit::ExtractZeroSets(result.grid, options);
//
// Nothing here throws: bad arguments give an error message.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace invmap::implicit {

using Vec3 = std::array<double, 3>;

/// Evaluates f at `count` points: point i is xyz[3i .. 3i+2] (z = 0 in 2D);
/// writes values[i] and the gradient gradients[3i .. 3i+2] (its z entry is
/// ignored in 2D). Called from several threads at once on disjoint outputs;
/// must be deterministic.
using EvaluateFn = std::function<void(const double* xyz, std::size_t count, double* values, double* gradients)>;

/// One implicit function f: R^n -> R with its gradient. The built-ins follow
/// docs/grids.md (function objects): positive inside.
struct Function {
  std::string name;  ///< For messages and output labels ("sphere", or the user's).
  EvaluateFn evaluate;

  /// r - |x - c|, or r^2 - |x - c|^2 when `squared`. In 2D (z = 0) a circle.
  static Function Sphere(const Vec3& center, double radius, bool squared = false);
  /// r - dist(x, axis line), or r^2 - dist^2 when `squared`; the axis vector
  /// is normalized.
  static Function Cylinder(const Vec3& axisPoint, const Vec3& axisVector, double radius, bool squared = false);
  /// n . (x - p) with n normalized.
  static Function Plane(const Vec3& point, const Vec3& normal);
  /// minor - |x - nearest point of the core circle| (the core circle has
  /// radius `majorRadius` around the normalized axis through `center`).
  static Function Torus(const Vec3& center, const Vec3& axisVector, double majorRadius, double minorRadius);
  /// a . (x - apex) - cos(apexAngle) |x - apex| with a the normalized axis:
  /// positive inside the cone of half angle `apexAngle` (radians) around +a.
  static Function Cone(const Vec3& apex, const Vec3& axisVector, double apexAngle);
  /// The adaptive-grid paper's scalar field x^5 + x^4 - 2 y^2 of (x - c).
  static Function Quintic(const Vec3& center);
  /// Gyroid sin(sx) cos(sy) + sin(sy) cos(sz) + sin(sz) cos(sx) with s = 2 pi / period.
  static Function Gyroid(double period);
};

/// How the functions make a complex.
enum class Mode {
  Arrangement,        ///< Every zero set: f_i = 0, f_i = f_j = 0, f_i = f_j = f_l = 0.
  MaterialInterface,  ///< Material i is where f_i is the largest; its interfaces f_i = f_j (both largest).
  Csg,                ///< The boundary of a CSG solid (GridOptions::tree, see CsgNode).
};

/// One node of a CSG tree, as in the tree files of
/// docs/grids.md (CSG trees): node 1 is the root; an operand
/// k > 0 is node k, k < 0 is function -k (1-based). Negation uses `a` only.
/// As in those files (and the reference implementation), an operand's region
/// is where it is <= 0: Intersection is max(a, b), Union min(a, b), Negation
/// -a, and the solid is {tree <= 0}. A built-in function is positive inside,
/// so the solid inside a sphere is Negation(sphere).
struct CsgNode {
  enum class Op { Intersection, Union, Negation };
  Op op = Op::Union;
  int a = 0;
  int b = 0;
};

/// A conforming triangle (dimension 2) or tetrahedron (dimension 3) mesh.
struct SimplexMesh {
  int dimension = 3;
  std::vector<double> vertices;        ///< 3 per vertex (z = 0 in 2D).
  std::vector<std::uint32_t> cells;    ///< dimension + 1 vertex indices per cell.

  std::size_t numVertices() const { return vertices.size() / 3; }
  std::size_t numCells() const { return dimension > 0 ? cells.size() / static_cast<std::size_t>(dimension + 1) : 0; }

  /// The box [lo, hi] cut into resolution^n squares (2 triangles each) or
  /// cubes (6 tetrahedra each, sharing the cube's main diagonal), conforming.
  /// lo[2], hi[2] are ignored in 2D.
  static SimplexMesh Box(const Vec3& lo, const Vec3& hi, int dimension, int resolution);
};

/// Options of RefineGrid and ExtractZeroSets.
struct GridOptions {
  Mode mode = Mode::Arrangement;
  /// Distance threshold (model units): a cell is refined while the bound of
  /// the distance from a zero set to its linear discretization exceeds it.
  double epsilon = 1e-4;
  /// Stop refining once the grid has this many cells (the result is then
  /// coarser than epsilon; GridStats::reachedMaxCells says so).
  std::int64_t maxCells = std::numeric_limits<std::int64_t>::max();
  /// Worker threads; 0 means all cores. The grid does not depend on it.
  int threads = 0;
  /// Mode::Csg: the tree (node 1 is the root).
  std::vector<CsgNode> tree;
};

/// Figures of a refinement.
struct GridStats {
  std::int64_t cells = 0;
  std::int64_t activeCells = 0;  ///< Cells passing the zero-crossing test of the mode.
  std::int64_t vertices = 0;
  /// Smallest radius ratio (n * inradius / circumradius, 1 for a regular
  /// simplex) over all cells, and over active cells (1 when there are none).
  double minRadiusRatio = 1;
  double minRadiusRatioActive = 1;
  double seconds = 0;            ///< Refinement time (wall clock).
  bool reachedMaxCells = false;
};

/// A refined grid with the function values at its vertices.
struct Grid {
  SimplexMesh mesh;
  int functionCount = 0;
  /// functionCount values per vertex: values[v * functionCount + i] = f_i(vertex v).
  std::vector<double> values;
  /// One per cell: 1 when the cell passes the mode's zero-crossing test
  /// (arrangement: some function's proxy changes sign; material interface:
  /// some difference of two candidate materials does; CSG: the tree's
  /// interval over the cell contains 0).
  std::vector<std::uint8_t> active;
  GridStats stats;
};

struct GridResult {
  Grid grid;
  std::string error;  ///< Empty on success.
};

/// Refines `initial` for `functions` (at least one) and `options`.
GridResult RefineGrid(const SimplexMesh& initial, const std::vector<Function>& functions, const GridOptions& options);

/// The complex's zero sets from the grid's piecewise-linear interpolant.
/// Each primitive carries up to 4 function indices (0-based, ascending, -1
/// unused): arrangement: a surface of f_i (i), a curve f_i = f_j (i, j), a
/// point (i, j, l); material interface: an interface (i, j), a junction curve
/// (i, j, l), a point (i, j, l, m); CSG: the same as arrangement, restricted
/// to the solid's boundary. In 2D the codimension-1 sets are segments
/// (labelled as 3D surfaces are) and the codimension-2 sets points.
/// Orientation: a triangle's normal is (b - a) x (c - a); a 2D segment's is
/// its direction turned clockwise. Arrangement: towards increasing f_i;
/// material interface (i, j): from material i into material j; CSG: out of
/// the solid. Vertices on shared grid edges are shared, so a closed surface
/// is watertight. A value exactly 0 counts as positive.
struct ZeroSets {
  int dimension = 3;
  std::vector<double> vertices;                    ///< 3 per vertex.
  std::vector<std::uint32_t> triangles;            ///< 3D: surface triangles.
  std::vector<std::array<int, 4>> triangleLabels;
  std::vector<std::uint32_t> segments;             ///< Curve segments.
  std::vector<std::array<int, 4>> segmentLabels;
  std::vector<std::uint32_t> points;               ///< Isolated points of the complex.
  std::vector<std::array<int, 4>> pointLabels;
};

ZeroSets ExtractZeroSets(const Grid& grid, const GridOptions& options);

}  // namespace invmap::implicit
