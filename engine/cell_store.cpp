#include "engine/cell_store.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/parallel.h"
#include "engine/bezier_extraction.h"

namespace invmap::engine {
namespace {

std::string CheckCoordinates(const std::vector<double>& values, const char* field, int stride) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      std::ostringstream msg;
      msg << field << "[" << i / stride << "]: coordinate " << i % stride << " is not finite";
      return msg.str();
    }
    if (std::abs(values[i]) > kernels::kMaxCoordinate) {
      std::ostringstream msg;
      msg << field << "[" << i / stride << "]: coordinate " << i % stride << " is " << values[i]
          << ", outside [-1e100, 1e100] (the range invmap supports)";
      return msg.str();
    }
  }
  return {};
}

/// The geometry's extent (the diagonal of its control points' box, `points`
/// holding `dim` coordinates each): 0 (a single point) or at least kMinExtent.
std::string CheckExtent(const std::vector<double>& points, int dim) {
  double extent2 = 0.0;
  for (int k = 0; k < dim && !points.empty(); ++k) {
    double lo = points[k], hi = points[k];
    for (std::size_t i = k; i < points.size(); i += dim) {
      lo = std::min(lo, points[i]);
      hi = std::max(hi, points[i]);
    }
    // In units of kMinExtent: the squares of lengths near it would underflow.
    extent2 += ((hi - lo) / kernels::kMinExtent) * ((hi - lo) / kernels::kMinExtent);
  }
  if (extent2 == 0.0 || extent2 >= 1.0) return {};
  std::ostringstream msg;
  msg << "the geometry is " << std::sqrt(extent2) * kernels::kMinExtent
      << " across (its box diagonal), below 1e-100 (the smallest extent invmap supports)";
  return msg.str();
}

std::string CheckWeights(const std::vector<double>& weights, std::size_t expected) {
  if (weights.empty()) return {};
  if (weights.size() != expected) {
    std::ostringstream msg;
    msg << "weights: " << weights.size() << " values, expected one per control point (" << expected << ")";
    return msg.str();
  }
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!(weights[i] > 0.0) || !std::isfinite(weights[i])) {
      std::ostringstream msg;
      msg << "weights[" << i << "]: not a finite positive number (" << weights[i] << ")";
      return msg.str();
    }
    if (weights[i] > kernels::kMaxWeight || weights[i] < 1.0 / kernels::kMaxWeight) {
      std::ostringstream msg;
      msg << "weights[" << i << "]: " << weights[i] << " is outside [1e-50, 1e50] (the range invmap supports)";
      return msg.str();
    }
  }
  return {};
}

/// Checks the degrees of one Bezier cell and returns its shape (or a message).
std::string BezierShape(CellType cell, const int* degreeList, int count, int dim, kernels::CellShape* shape) {
  const kernels::CellType type = ToKernelType(cell);
  const int factors = kernels::CellShape::NumFactorsOf(type);
  if (count != factors) {
    return "degrees: " + std::to_string(count) + " values, a " + kernels::CellTypeName(type) + " cell needs " +
           std::to_string(factors);
  }
  std::array<int, kernels::kMaxFactors> degrees{};
  for (int f = 0; f < factors; ++f) {
    degrees[f] = degreeList[f];
    if (degrees[f] < 1 || degrees[f] > kernels::kMaxDegree) {
      return "degrees[" + std::to_string(f) + "]: " + std::to_string(degrees[f]) + ", expected 1 to " +
             std::to_string(kernels::kMaxDegree);
    }
  }
  *shape = kernels::CellShape(type, degrees);
  if (shape->paramDim() > dim) return std::string("cell: a ") + kernels::CellTypeName(type) + " cell needs dimension 3";
  return {};
}

}  // namespace

kernels::CellType ToKernelType(CellType type) { return static_cast<kernels::CellType>(type); }

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

void CellStore::SubdivisionHullPoints(std::int64_t s, std::vector<double>* xyz) const {
  if (isRegion(s)) {
    const AffineRegion& region = subdivisionRegion(s);
    if (region.paramDim == dimension_) return;
    for (int corner = 0; corner < (1 << region.paramDim); ++corner) {
      double x[3] = {0, 0, 0};
      for (int k = 0; k < dimension_; ++k) {
        x[k] = region.b[k];
        for (int d = 0; d < region.paramDim; ++d) {
          x[k] += region.A[k][d] * ((corner >> d) & 1 ? region.hi[d] : region.lo[d]);
        }
      }
      xyz->insert(xyz->end(), x, x + 3);
    }
    return;
  }
  const std::int64_t cell = subdivisions_[s];
  const kernels::CellShape& shape = shapes_[cell];
  if (shape.paramDim() == dimension_) return;
  const double* points = points_.data() + pointOffset_[cell];
  for (int i = 0; i < shape.numControlPoints(); ++i) {
    for (int k = 0; k < 3; ++k) xyz->push_back(k < dimension_ ? points[i * dimension_ + k] : 0.0);
  }
}

void CellStore::AddCell(const kernels::CellShape& shape, const double* points, const double* weights,
                        const CellOrigin& origin) {
  const int n = shape.numControlPoints();
  hasVolumeCells_ = hasVolumeCells_ || shape.paramDim() == dimension_;
  shapes_.push_back(shape);
  pointOffset_.push_back(static_cast<std::int64_t>(points_.size()));
  points_.insert(points_.end(), points, points + static_cast<std::size_t>(n) * dimension_);
  if (weights) {
    weightOffset_.push_back(static_cast<std::int64_t>(weights_.size()));
    weights_.insert(weights_.end(), weights, weights + n);
  } else {
    weightOffset_.push_back(-1);
  }
  origins_.push_back(origin);
  origins_.back().type = shape.type();
}

std::string CellStore::Build(const Geometry& geometry, int maxThreads) {
  dimension_ = geometry.dimension;
  numPatches_ = geometry.patches.size();
  splineSpans_.assign(numPatches_, {0, 0, 0});
  if (dimension_ != 2 && dimension_ != 3) {
    return "dimension: " + std::to_string(dimension_) + ", expected 2 or 3";
  }
  const int dim = dimension_;
  // The cell grids of the B-spline patches, searched for affine regions once
  // the solvers exist.
  struct SplineGrid {
    std::int64_t firstCell;
    std::array<int, 3> spans;
    int paramDim;
  };
  std::vector<SplineGrid> splineGrids;
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    const Patch& patch = geometry.patches[p];
    patchFirst_.push_back(static_cast<std::int64_t>(shapes_.size()));
    const std::string where = "patch " + std::to_string(p) + ": ";
    CellOrigin origin;
    origin.patch = static_cast<std::int32_t>(p);
    if (std::string e = CheckCoordinates(patch.points, patch.kind == Patch::Kind::Mesh ? "vertices" : "control_points", dim);
        !e.empty()) {
      return where + e;
    }
    switch (patch.kind) {
      case Patch::Kind::BSpline: {
        BSplinePatch spline;
        spline.ambientDim = dim;
        spline.degrees = patch.degrees;
        spline.knots = patch.knots;
        spline.counts = patch.counts;
        spline.controlPoints = patch.points;
        spline.weights = patch.weights;
        if (std::string e = ValidateBSplinePatch(spline); !e.empty()) return where + e;
        if (static_cast<int>(spline.degrees.size()) > dim) {
          return where + "degrees: a " + std::to_string(spline.degrees.size()) + "-parameter patch needs dimension 3";
        }
        const ExtractedCells cells = ExtractBezierCells(spline);
        const kernels::CellShape shape(cells.type, cells.degrees);
        splineGrids.push_back({static_cast<std::int64_t>(shapes_.size()), cells.spans, cells.paramDim});
        splineSpans_[p] = cells.spans;
        for (int c = 0; c < cells.numCells; ++c) {
          origin.indexInPatch = c;
          origin.sharedParameters = true;
          origin.span = {c % cells.spans[0], c / cells.spans[0] % cells.spans[1],
                         c / (cells.spans[0] * cells.spans[1])};
          for (int d = 0; d < cells.paramDim; ++d) {
            const double lo = cells.spanLo[static_cast<std::size_t>(c) * cells.paramDim + d];
            const double hi = cells.spanHi[static_cast<std::size_t>(c) * cells.paramDim + d];
            origin.paramLo[d] = lo;
            origin.paramScale[d] = hi - lo;
          }
          const std::size_t first = static_cast<std::size_t>(c) * cells.pointsPerCell;
          AddCell(shape, cells.points.data() + first * dim, cells.weights.empty() ? nullptr : cells.weights.data() + first,
                  origin);
        }
        break;
      }
      case Patch::Kind::Bezier: {
        kernels::CellShape shape;
        if (std::string e = BezierShape(patch.cell, patch.degrees.data(), static_cast<int>(patch.degrees.size()), dim,
                                        &shape);
            !e.empty()) {
          return where + e;
        }
        const std::size_t n = shape.numControlPoints();
        if (patch.points.size() != n * dim) {
          return where + "control_points: " + std::to_string(patch.points.size() / dim) + " points, expected " +
                 std::to_string(n);
        }
        if (std::string e = CheckWeights(patch.weights, n); !e.empty()) return where + e;
        origin.indexInPatch = 0;
        AddCell(shape, patch.points.data(), patch.weights.empty() ? nullptr : patch.weights.data(), origin);
        break;
      }
      case Patch::Kind::BezierCells: {
        const std::size_t numCells = patch.cellTypes.size();
        if (patch.cellDegrees.size() != 3 * numCells || patch.cellOffsets.size() != numCells + 1) {
          return where + "cellDegrees and cellOffsets: expected 3 and 1 values per cell (plus one offset)";
        }
        const std::int64_t numPoints = static_cast<std::int64_t>(patch.points.size() / dim);
        if (std::string e = CheckWeights(patch.weights, static_cast<std::size_t>(numPoints)); !e.empty()) return where + e;
        for (std::size_t c = 0; c < numCells; ++c) {
          const std::string cellWhere = where + "cells[" + std::to_string(c) + "]: ";
          kernels::CellShape shape;
          const int factors = kernels::CellShape::NumFactorsOf(ToKernelType(patch.cellTypes[c]));
          if (std::string e = BezierShape(patch.cellTypes[c], &patch.cellDegrees[3 * c], factors, dim, &shape);
              !e.empty()) {
            return cellWhere + e;
          }
          const std::int64_t first = patch.cellOffsets[c], last = patch.cellOffsets[c + 1];
          if (first < 0 || last > numPoints || last - first != shape.numControlPoints()) {
            return cellWhere + "control points [" + std::to_string(first) + ", " + std::to_string(last) +
                   "), expected " + std::to_string(shape.numControlPoints()) + " within the " +
                   std::to_string(numPoints) + " points";
          }
          origin.indexInPatch = static_cast<std::int64_t>(c);
          AddCell(shape, patch.points.data() + first * dim, patch.weights.empty() ? nullptr : patch.weights.data() + first,
                  origin);
        }
        break;
      }
      case Patch::Kind::Mesh: {
        const kernels::CellType type = ToKernelType(patch.cell);
        const kernels::CellShape shape(type, {1, 1, 1});
        if (shape.paramDim() > dim) return where + "cell: a " + kernels::CellTypeName(type) + " mesh needs dimension 3";
        if (!patch.weights.empty()) return where + "weights: a mesh has no weights";
        const MeshCellLayout layout = LayoutOf(patch.cell);
        if (patch.points.size() % dim != 0) return where + "vertices: coordinate count not a multiple of the dimension";
        const std::int64_t numVertices = static_cast<std::int64_t>(patch.points.size() / dim);
        if (patch.cells.size() % layout.vertices != 0) {
          return where + "cells: " + std::to_string(patch.cells.size()) + " indices, not a multiple of " +
                 std::to_string(layout.vertices);
        }
        const std::size_t numCells = patch.cells.size() / layout.vertices;
        double corner[8 * 3];
        for (std::size_t c = 0; c < numCells; ++c) {
          for (int v = 0; v < layout.vertices; ++v) {
            const std::int64_t index = patch.cells[c * layout.vertices + layout.bezierFromFe[v]];
            if (index < 0 || index >= numVertices) {
              return where + "cells[" + std::to_string(c) + "]: vertex index " + std::to_string(index) +
                     " out of range [0, " + std::to_string(numVertices) + ")";
            }
            for (int k = 0; k < dim; ++k) corner[v * dim + k] = patch.points[static_cast<std::size_t>(index) * dim + k];
          }
          origin.indexInPatch = static_cast<std::int64_t>(c);
          AddCell(shape, corner, nullptr, origin);
        }
        break;
      }
    }
  }

  patchFirst_.push_back(static_cast<std::int64_t>(shapes_.size()));
  if (std::string e = CheckExtent(points_, dim); !e.empty()) return e;

  // The arrays are final: build the solvers (bounds, nets) in parallel.
  const std::int64_t count = static_cast<std::int64_t>(shapes_.size());
  solvers_.resize(count);
  ForEachBlock(
      ExecutionPolicy::Par, count, 256,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c) {
          kernels::CellView view;
          view.shape = shapes_[c];
          view.ambientDim = dim;
          view.points = points_.data() + pointOffset_[c];
          view.weights = weightOffset_[c] >= 0 ? weights_.data() + weightOffset_[c] : nullptr;
          solvers_[c] = kernels::CellSolver(view);
        }
      },
      maxThreads);

  if (hasVolumeCells_) tetAdjacency_.Build(solvers_, maxThreads);

  // Algorithm 6: affine regions, and the subdivisions the BVH is built over.
  double coordinateMagnitude = 0.0;
  for (double x : points_) coordinateMagnitude = std::max(coordinateMagnitude, std::fabs(x));
  for (const SplineGrid& grid : splineGrids) {
    const std::int64_t cells = static_cast<std::int64_t>(grid.spans[0]) * grid.spans[1] * grid.spans[2];
    double diagonal2 = 0.0;
    for (int k = 0; k < dim; ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::int64_t c = grid.firstCell; c < grid.firstCell + cells; ++c) {
        lo = std::min(lo, solvers_[c].boxLo()[k]);
        hi = std::max(hi, solvers_[c].boxHi()[k]);
      }
      diagonal2 += (hi - lo) * (hi - lo);
    }
    // Cells whose maps agree to well below the solver's tolerance share a
    // region; the second term covers the rounding of large coordinates.
    const double tolerance = 1e-12 * std::sqrt(diagonal2) + 1e-15 * coordinateMagnitude;
    FindAffineRegions(*this, grid.firstCell, grid.spans.data(), grid.paramDim, tolerance, &regions_);
  }
  regionOfCell_.assign(static_cast<std::size_t>(count), -1);
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    const AffineRegion& region = regions_[r];
    std::int64_t extent[3] = {1, 1, 1};
    for (int d = 0; d < region.paramDim; ++d) extent[d] = static_cast<std::int64_t>(region.breaks[d].size()) - 1;
    for (std::int64_t k = 0; k < extent[2]; ++k)
      for (std::int64_t j = 0; j < extent[1]; ++j)
        for (std::int64_t i = 0; i < extent[0]; ++i)
          regionOfCell_[region.firstCell + i * region.cellStride[0] + j * region.cellStride[1] +
                        k * region.cellStride[2]] = static_cast<std::int32_t>(r);
  }
  for (std::int64_t c = 0; c < count; ++c) {
    const std::int32_t r = regionOfCell_[c];
    if (r < 0) {
      subdivisions_.push_back(c);
    } else if (regions_[r].firstCell == c) {
      subdivisions_.push_back(-1 - static_cast<std::int64_t>(r));
    }
  }
  return {};
}

std::int64_t CellStore::SplineNeighbor(std::int64_t cell, const int* step) const {
  const CellOrigin& origin = origins_[cell];
  if (!origin.sharedParameters) return -1;
  const std::array<int, 3>& spans = splineSpans_[origin.patch];
  // Cells follow their patch's span grid, first direction fastest.
  std::int64_t index = 0, stride = 1;
  for (int d = 0; d < 3; ++d) {
    const std::int64_t span = origin.span[d] + step[d];
    if (span < 0 || span >= spans[d]) return -1;
    index += span * stride;
    stride *= spans[d];
  }
  return patchFirst_[origin.patch] + index;
}

std::size_t CellStore::MemoryBytes() const {
  std::size_t bytes = points_.capacity() * sizeof(double) + weights_.capacity() * sizeof(double) +
                      shapes_.capacity() * sizeof(kernels::CellShape) +
                      (pointOffset_.capacity() + weightOffset_.capacity()) * sizeof(std::int64_t) +
                      origins_.capacity() * sizeof(CellOrigin) + solvers_.capacity() * sizeof(kernels::CellSolver) +
                      regions_.capacity() * sizeof(AffineRegion) + regionOfCell_.capacity() * sizeof(std::int32_t) +
                      subdivisions_.capacity() * sizeof(std::int64_t) + tetAdjacency_.MemoryBytes();
  for (const AffineRegion& r : regions_)
    for (const std::vector<double>& breaks : r.breaks) bytes += breaks.capacity() * sizeof(double);
  for (const kernels::CellSolver& s : solvers_) bytes += s.NetMemoryBytes();
  return bytes;
}

}  // namespace invmap::engine
