// Independent global closest-point reference over a whole geometry, for the
// engine tests: every cell from tests/support/patch_reference.h, culled by
// conservative boxes in a simple bounding-volume tree of the tests' own, then
// solved exactly (linear triangles and segments) or by the lattice search of
// BruteForceReference (tests/support/reference_cell.h).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

// The support library is built without the engine's include path; this is
// the same public header that tests include as "invmap/invmap.h".
#include "invmap/invmap.h"
#include "tests/support/patch_reference.h"

namespace invmap::testing {

/// The reference's answer for one query point.
struct ReferenceAnswer {
  double distance = std::numeric_limits<double>::infinity();
  std::int32_t patch = -1;  ///< -1 when unknown (analytic references).
  std::int64_t cell = -1;
  std::array<double, 3> params{{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::quiet_NaN()}};
  std::array<double, 3> x{{0, 0, 0}};
  int cellsSolved = 0;  ///< Cells whose exact distance was computed (diagnostics).
};

/// Tuning of ReferenceGeometry.
struct ReferenceOptions {
  /// Lattice divisions of BruteForceReference for curve, surface and volume
  /// cells. Cells of B-spline patches with many spans are only mildly curved,
  /// so coarser lattices than BruteForceReference's defaults suffice; a
  /// lattice that misses a basin shows up as the reference being farther
  /// than invmap (which the checks report).
  int divisions[3] = {128, 24, 10};
  /// Culling: tensor-product cells are split into this many pieces per
  /// direction (curve, surface, volume) by de Casteljau subdivision, and each
  /// piece's control-point box is a leaf of the tree. Tighter boxes spare
  /// exact solves for far points, whose distance varies little over the
  /// geometry.
  int subdivisions[3] = {8, 4, 2};
};

/// Global closest point on a geometry by exhaustive, conservatively culled
/// search: best-first over the tree of leaf boxes, exact distance of a cell
/// the first time one of its leaves is reached, stop when the next box is
/// not closer than the best distance. Boxes hold the cells (convex hull
/// property of control nets with positive weights), so no cell that could be
/// closer is skipped.
/// Not thread-safe (the lattice searches keep scratch); build one per thread.
class ReferenceGeometry {
 public:
  explicit ReferenceGeometry(const Geometry& geometry, ReferenceOptions options = {});
  ~ReferenceGeometry();
  ReferenceGeometry(ReferenceGeometry&&) noexcept;
  ReferenceGeometry& operator=(ReferenceGeometry&&) noexcept;

  /// Closest point of the geometry to `point` (dimension coordinates, finite).
  ReferenceAnswer Closest(const double* point);

  /// The cells, in patch then cell order.
  const std::vector<PatchCell>& cells() const;
  /// GeometrySize of the geometry.
  double size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Closest point to p on triangle (a, b, c) (3 coordinates each; use z = 0 in
/// 2D), by Voronoi regions (Ericson, Real-Time Collision Detection 5.1.5).
/// Writes its barycentric coordinates s (of b) and t (of c) and the point x.
/// Degenerate triangles fall back to the closest of the three edges.
void ClosestOnTriangle(const double* p, const double* a, const double* b, const double* c, double* s, double* t,
                       double* x);

/// Closest point to p on segment (a, b); writes the parameter s and x.
void ClosestOnSegment(const double* p, const double* a, const double* b, double* s, double* x);

}  // namespace invmap::testing
