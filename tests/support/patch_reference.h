// Independent reading of the public patch model (docs/formats.md sections 1 and 2)
// for the engine tests: the Bezier cells of every patch, built by the tests'
// own code, and the evaluation of a patch at the (patch, cell, params) that
// invmap reports.
//
// Nothing here calls invmap's engine: B-spline patches are converted by
// interpolating Cox-de Boor values (tests/support/bspline_reference.h), not
// by knot insertion as engine/bezier_extraction does, and mesh cells are
// evaluated with finite-element shape functions in FE vertex order, not
// through a Bezier net. A shared misreading of the format would otherwise go
// unnoticed.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

// The support library is built without the engine's include path; this is
// the same public header that tests include as "invmap/invmap.h".
#include "invmap/invmap.h"
#include "tests/support/reference_cell.h"

namespace invmap::testing {

/// One Bezier cell of a geometry and the way back to its patch.
struct PatchCell {
  RefCell cell;
  std::int32_t patch = 0;
  /// Cell index within the patch (docs/formats.md numbering: non-empty knot spans
  /// u fastest; 0 for a Bezier patch; file order for a mesh).
  std::int64_t index = 0;
  /// Reported parameters: params[i] = paramLo[i] + paramScale[i] * ref[i]
  /// (knot values for B-spline cells, the identity otherwise).
  std::array<double, 3> paramLo{{0, 0, 0}};
  std::array<double, 3> paramScale{{1, 1, 1}};
  /// True for a linear mesh triangle or segment: the reference solves those
  /// exactly instead of by lattice search.
  bool linearSimplex = false;
};

/// The reference cell type matching a public one (docs/formats.md section 1).
kernels::CellType ToRefType(CellType type);

/// Knot indices i in [degree, count) with knots[i] < knots[i + 1]: the
/// non-empty spans of the parameter domain [t_p, t_n], in order.
std::vector<int> NonEmptySpans(const std::vector<double>& knots, int degree, int count);

/// Bezier cells of patch `patch` in the patch's cell order. B-spline spans
/// are converted by interpolation of the Cox-de Boor piece at degree + 1
/// nodes per direction (in homogeneous coordinates when rational); Bezier
/// patches are copied; linear mesh cells get a degree-1 net reordered from
/// the FE vertex order. Precondition: the patch is valid.
std::vector<PatchCell> PatchCells(const Geometry& geometry, int patch);

/// PatchCells of every patch, patch after patch.
std::vector<PatchCell> GeometryCells(const Geometry& geometry);

/// Axis-aligned box of every control point and mesh vertex (z = 0 in 2D).
void GeometryControlBox(const Geometry& geometry, double lo[3], double hi[3]);

/// Diagonal of GeometryControlBox: the length scale of the tests' tolerances.
double GeometrySize(const Geometry& geometry);

/// Evaluates patch `patch` at the reported cell and parameters into x
/// (dimension values; the rest set to 0): B-spline patches by Cox-de Boor with
/// the polynomial piece of the cell's spans at the global knot values,
/// Bezier patches by RefEvaluate, mesh cells by the linear finite-element map
/// in FE vertex order. Returns "" on success, otherwise why (patch, cell,
/// params) is not a valid answer: an index out of range, a used parameter
/// that is NaN or outside the cell's domain by more than `paramTol` (relative
/// to the cell's extent in that parameter), an unused one that is not NaN.
std::string EvaluateReported(const Geometry& geometry, std::int32_t patch, std::int64_t cell,
                             const double* params, double paramTol, double* x);

/// Number of cells of each patch as docs/formats.md counts them.
std::vector<std::int64_t> CellCounts(const Geometry& geometry);

}  // namespace invmap::testing
