#include "engine/bezier_nets.h"

#include <algorithm>

#include "engine/bezier_extraction.h"

namespace invmap::engine {

MeshCellLayout LayoutOf(CellType type) {
  switch (type) {
    case CellType::Line:
      return {2, {0, 1}};
    case CellType::Tri:
      return {3, {0, 1, 2}};
    case CellType::Quad:
      return {4, {0, 1, 3, 2}};
    case CellType::Tet:
      return {4, {0, 1, 2, 3}};
    case CellType::Hex:
      return {8, {0, 1, 3, 2, 4, 5, 7, 6}};
    case CellType::Wedge:
      return {6, {0, 1, 2, 3, 4, 5}};
  }
  return {0, {}};
}

BSplinePatch SplineOf(const Patch& patch, int dim) {
  BSplinePatch spline;
  spline.ambientDim = dim;
  spline.degrees = patch.degrees;
  spline.knots = patch.knots;
  spline.counts = patch.counts;
  spline.controlPoints = patch.points;
  spline.weights = patch.weights;
  return spline;
}

namespace {

/// The Bezier cells of a B-spline patch, one per non-empty span.
void AddSplineCells(const Patch& patch, std::size_t p, CellOrigin origin, BezierNets* nets) {
  const int dim = nets->dimension;
  const ExtractedCells cells = ExtractBezierCells(SplineOf(patch, dim));
  const kernels::CellShape shape(cells.type, cells.degrees);
  nets->splineGrids.push_back({nets->size(), cells.spans, cells.paramDim});
  nets->splineSpans[p] = cells.spans;
  for (int c = 0; c < cells.numCells; ++c) {
    origin.indexInPatch = c;
    origin.sharedParameters = true;
    origin.span = {c % cells.spans[0], c / cells.spans[0] % cells.spans[1], c / (cells.spans[0] * cells.spans[1])};
    for (int d = 0; d < cells.paramDim; ++d) {
      const double lo = cells.spanLo[static_cast<std::size_t>(c) * cells.paramDim + d];
      const double hi = cells.spanHi[static_cast<std::size_t>(c) * cells.paramDim + d];
      origin.paramLo[d] = lo;
      origin.paramScale[d] = hi - lo;
    }
    const std::size_t first = static_cast<std::size_t>(c) * cells.pointsPerCell;
    nets->Add(shape, cells.points.data() + first * dim, cells.weights.empty() ? nullptr : cells.weights.data() + first,
              origin);
  }
}

/// The one cell of a Bezier patch.
void AddBezierCell(const Patch& patch, const CellOrigin& origin, BezierNets* nets) {
  std::array<int, kernels::kMaxFactors> degrees{};
  std::copy(patch.degrees.begin(), patch.degrees.end(), degrees.begin());
  nets->Add(kernels::CellShape(patch.cell, degrees), patch.points.data(),
            patch.weights.empty() ? nullptr : patch.weights.data(), origin);
}

/// The cells of a BezierCells patch, each with its own type and degrees.
void AddBezierCells(const Patch& patch, CellOrigin origin, BezierNets* nets) {
  const int dim = nets->dimension;
  for (std::size_t c = 0; c < patch.cellTypes.size(); ++c) {
    const int factors = kernels::CellShape::NumFactorsOf(patch.cellTypes[c]);
    std::array<int, kernels::kMaxFactors> degrees{};
    for (int f = 0; f < factors; ++f) degrees[f] = patch.cellDegrees[3 * c + f];
    const std::int64_t first = patch.cellOffsets[c];
    origin.indexInPatch = static_cast<std::int64_t>(c);
    nets->Add(kernels::CellShape(patch.cellTypes[c], degrees), patch.points.data() + first * dim,
              patch.weights.empty() ? nullptr : patch.weights.data() + first, origin);
  }
}

/// The linear cells of a mesh patch, their corners copied from the vertices.
void AddMeshCells(const Patch& patch, CellOrigin origin, BezierNets* nets) {
  const int dim = nets->dimension;
  const kernels::CellShape shape(patch.cell, {1, 1, 1});
  const MeshCellLayout layout = LayoutOf(patch.cell);
  const std::size_t numCells = patch.cells.size() / layout.vertices;
  double corner[8 * 3];
  for (std::size_t c = 0; c < numCells; ++c) {
    for (int v = 0; v < layout.vertices; ++v) {
      const std::int64_t index = patch.cells[c * layout.vertices + layout.bezierFromFe[v]];
      for (int k = 0; k < dim; ++k) corner[v * dim + k] = patch.points[static_cast<std::size_t>(index) * dim + k];
    }
    origin.indexInPatch = static_cast<std::int64_t>(c);
    nets->Add(shape, corner, nullptr, origin);
  }
}

}  // namespace

void BezierNets::Add(const kernels::CellShape& shape, const double* cellPoints, const double* cellWeights,
                     const CellOrigin& origin) {
  const int n = shape.numControlPoints();
  hasVolumeCells = hasVolumeCells || shape.paramDim() == dimension;
  shapes.push_back(shape);
  pointOffset.push_back(static_cast<std::int64_t>(points.size()));
  points.insert(points.end(), cellPoints, cellPoints + static_cast<std::size_t>(n) * dimension);
  if (cellWeights) {
    weightOffset.push_back(static_cast<std::int64_t>(weights.size()));
    weights.insert(weights.end(), cellWeights, cellWeights + n);
  } else {
    weightOffset.push_back(-1);
  }
  origins.push_back(origin);
  origins.back().type = shape.type();
}

kernels::CellView BezierNets::View(std::int64_t cell) const {
  kernels::CellView view;
  view.shape = shapes[cell];
  view.ambientDim = dimension;
  view.points = points.data() + pointOffset[cell];
  view.weights = weightOffset[cell] >= 0 ? weights.data() + weightOffset[cell] : nullptr;
  return view;
}

std::size_t BezierNets::MemoryBytes() const {
  return points.capacity() * sizeof(double) + weights.capacity() * sizeof(double) +
         shapes.capacity() * sizeof(kernels::CellShape) +
         (pointOffset.capacity() + weightOffset.capacity()) * sizeof(std::int64_t) +
         origins.capacity() * sizeof(CellOrigin) + trimmed.MemoryBytes();
}

BezierNets ToBezierNets(const Geometry& geometry) {
  BezierNets nets;
  nets.dimension = geometry.dimension;
  nets.numPatches = geometry.patches.size();
  nets.splineSpans.assign(nets.numPatches, {0, 0, 0});
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    const Patch& patch = geometry.patches[p];
    nets.patchFirst.push_back(nets.size());
    CellOrigin origin;
    origin.patch = static_cast<std::int32_t>(p);
    switch (patch.kind) {
      case Patch::Kind::BSpline:
        AddSplineCells(patch, p, origin, &nets);
        break;
      case Patch::Kind::Bezier:
        AddBezierCell(patch, origin, &nets);
        break;
      case Patch::Kind::BezierCells:
        AddBezierCells(patch, origin, &nets);
        break;
      case Patch::Kind::Mesh:
        AddMeshCells(patch, origin, &nets);
        break;
      case Patch::Kind::TrimmedSurface:
        AddTrimmedSurfaceCells(patch, p, &nets);
        break;
      case Patch::Kind::PouManifold:
        break;  // no Bezier cells: its charts are searched by engine/pou_patches.h
    }
  }
  nets.patchFirst.push_back(nets.size());
  return nets;
}

}  // namespace invmap::engine
