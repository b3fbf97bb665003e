// The first step of the engine's build: every patch of a validated geometry
// turned into Bezier cells (control nets copied into flat arrays), with the
// way back from each cell to its patch and parameters.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/bezier_extraction.h"
#include "engine/trimmed_patch.h"
#include "invmap/invmap.h"
#include "kernels/cell_map.h"
#include "kernels/cell_shape.h"

namespace invmap::engine {

/// Where a cell came from and how its reference coordinates map to the
/// parameters reported for it: param_i = paramLo[i] + paramScale[i] * ref_i
/// (knot values for B-spline cells; identity for Bezier and mesh cells),
/// or the angle there for directions that are angular (trimmed surfaces,
/// kernels/own_parameter.h); see CellStore::ReportedParameters.
struct CellOrigin {
  std::int32_t patch = 0;
  /// The cell's type: its reference domain and number of parameters.
  kernels::CellType type = kernels::CellType::Line;
  std::int64_t indexInPatch = 0;
  double paramLo[3] = {0, 0, 0};
  double paramScale[3] = {1, 1, 1};
  /// True when the patch's cells tile one parameter domain (B-spline
  /// patches), so a parameter of one cell means a place near another.
  bool sharedParameters = false;
  /// With sharedParameters: the cell's place in its patch's grid of spans.
  std::array<std::int32_t, 3> span{0, 0, 0};
  /// Bit d set: parameter d is an angle (kernels::OwnParameter).
  std::uint8_t angular = 0;
  /// Edge cells of a trimmed surface: the edge's index in
  /// BezierNets::trimmed.edges (its pcurve gives the reported parameters);
  /// -1 otherwise.
  std::int32_t edge = -1;
};

/// The B-spline fields of a BSpline or TrimmedSurface patch (degrees, knots,
/// counts, points, weights) in `dim` coordinates, for ExtractBezierCells.
BSplinePatch SplineOf(const Patch& patch, int dim);

/// Vertices per linear mesh cell, and the finite-element to Bezier order
/// (docs/formats.md: quads and hexes list their faces counter-clockwise,
/// Bezier nets are tensor products with the first coordinate fastest):
/// corner k of the cell's net is its vertex bezierFromFe[k].
struct MeshCellLayout {
  int vertices;
  int bezierFromFe[8];
};

/// The layout of a mesh cell of `type`.
MeshCellLayout LayoutOf(CellType type);

/// The cells of one B-spline patch: a grid of spans, first direction fastest.
struct SplineGrid {
  std::int64_t firstCell = 0;          ///< Index of the patch's first cell.
  std::array<int, 3> spans{1, 1, 1};   ///< Spans per direction (1 past paramDim).
  int paramDim = 0;
};

/// Every cell of a geometry as a Bezier net. Cells of a patch are
/// contiguous and in the patch's order (B-spline spans first direction
/// fastest, Bezier cells and mesh cells as listed; a trimmed surface's
/// spans inside or across its region, then its edges' spans).
struct BezierNets {
  int dimension = 3;
  std::size_t numPatches = 0;
  /// numPatches + 1 entries: patch p's cells are [patchFirst[p], patchFirst[p + 1]).
  std::vector<std::int64_t> patchFirst;
  /// Per patch: its grid of spans (zeros unless a B-spline patch).
  std::vector<std::array<int, 3>> splineSpans;
  /// The B-spline patches' grids, in patch order (not trimmed surfaces':
  /// spans outside their region have no cell).
  std::vector<SplineGrid> splineGrids;
  std::vector<kernels::CellShape> shapes;
  std::vector<std::int64_t> pointOffset;   ///< First coordinate of each cell in `points`.
  std::vector<std::int64_t> weightOffset;  ///< First weight of each cell in `weights`, -1 if polynomial.
  std::vector<double> points;
  std::vector<double> weights;
  std::vector<CellOrigin> origins;
  /// True when some cell is a volume (paramDim == dimension).
  bool hasVolumeCells = false;
  /// The trimmed surfaces' regions, crossing cells and edges (empty without).
  TrimmedFaces trimmed;

  /// Appends one Bezier cell (control points and weights copied) and its origin.
  void Add(const kernels::CellShape& shape, const double* cellPoints, const double* cellWeights,
           const CellOrigin& origin);
  std::int64_t size() const { return static_cast<std::int64_t>(shapes.size()); }
  /// Cell `cell` as the kernels read it; valid while these arrays are not
  /// resized (moving them keeps it valid).
  kernels::CellView View(std::int64_t cell) const;
  /// Heap memory of the arrays.
  std::size_t MemoryBytes() const;
};

/// Converts every patch of `geometry` to Bezier cells: B-splines by Bezier
/// extraction (engine/bezier_extraction.h), Bezier patches and BezierCells
/// as they are, mesh cells from their vertices (reordered from the
/// finite-element vertex order to the Bezier net's), trimmed surfaces by
/// AddTrimmedSurfaceCells (engine/trimmed_patch.h). Precondition:
/// ValidateGeometry(geometry) found no problem.
BezierNets ToBezierNets(const Geometry& geometry);

}  // namespace invmap::engine
