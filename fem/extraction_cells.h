// Bezier cells from Bezier extraction (Borden et al. 2011; Coreform
// Cubit's exports): a spline's control points and, per element, the
// extraction operator's rows (coefficient vectors) of the spline functions
// that touch it. Shared by the readers of Cubit's LS-DYNA, JSON and Exodus
// Bezier extraction files.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::fem {

/// A spline in Bezier extraction form.
struct ExtractedSpline {
  /// Control points, 3 Cartesian coordinates each.
  std::vector<double> points;
  /// One weight per control point; empty for a polynomial spline.
  std::vector<double> weights;
  /// The coefficient vectors: each the Bernstein coefficients of one spline
  /// function over one element (a row of an element's extraction operator).
  std::vector<std::vector<double>> coefficientVectors;
};

/// One element: its cell type and degrees, and for each spline function
/// supported on it the control point and the coefficient vector (0-based).
struct ExtractionElement {
  CellType type = CellType::Quad;
  std::array<int, 3> degrees{0, 0, 0};  ///< Per direction (lines: 1, quads: 2, hexes: 3 used).
  std::vector<std::int64_t> points;
  std::vector<std::int64_t> coefficientVectors;
  /// How messages name it, e.g. "element block 1, element 3".
  std::string where;
};

/// The element's Bezier cell: control point j is sum_i C_ij w_i P_i / W_j
/// with W_j = sum_i C_ij w_i its weight (C the element's extraction
/// operator, row i the coefficient vector of its i-th function), so the
/// cell equals the spline on the element exactly, rational or not. Control
/// points are listed as the coefficient vectors list Bernstein
/// coefficients: tensor products with the first direction fastest
/// (docs/formats.md section 1). Appends the cell to `patch` (a BezierCells
/// patch; rational when the spline has weights). Throws InputError naming
/// `file` and the element for an index out of range, a coefficient vector
/// of the wrong length for the degrees, or a Bezier weight that is not
/// positive.
void AddExtractedCell(const ExtractedSpline& spline, const ExtractionElement& element, int dim,
                      const std::string& file, Patch* patch);

/// Starts an empty BezierCells patch (cellOffsets {0}).
Patch EmptyCellsPatch();

/// 2 when no element is a volume and every control point has z == 0, else 3.
int ExtractedDimension(const ExtractedSpline& spline, const std::vector<ExtractionElement>& elements);

}  // namespace invmap::fem
