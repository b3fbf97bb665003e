#include "engine/geometry_validation.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "kernels/cell_shape.h"
#include "kernels/trim_region.h"
#include "pou/closed_mesh.h"
#include "pou/shape_function.h"

namespace invmap::engine {
namespace {

using kernels::kMaxCoordinate;
using kernels::kMaxDegree;
using kernels::kMaxWeight;
using kernels::kMinExtent;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Shortest text that reads back as `value` ("0.1", not "0.10000000000000001"),
/// so that messages quote values as they were written.
std::string Number(double value) {
  char buffer[32];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string Index(std::int64_t i) { return "[" + std::to_string(i) + "]"; }

bool IsKnownCellType(CellType type) { return static_cast<int>(type) < static_cast<int>(std::size(kCellTypes)); }

/// How the degrees of a Bezier cell of each type are listed, for messages.
const char* DegreeForm(CellType type) {
  switch (type) {
    case CellType::Quad:
      return "[p, q]";
    case CellType::Hex:
      return "[p, q, r]";
    case CellType::Wedge:
      return "[p_tri, q_line]";
    default:
      return "[p]";
  }
}

/// Knots whose differences overflow: the basis functions divide by them.
constexpr const char* kKnotWidthProblem = "is wider than a double can hold (its differences overflow)";

/// Why the knots of an angular direction or curve (degree `degree`) are not
/// arcs of less than a half turn (kernels/own_parameter.h), or "".
std::string AngularSpansProblem(const std::vector<double>& knots, int degree) {
  if (degree != 2) return "angular, so degree 2 (rational quadratic arcs) expected, not " + std::to_string(degree);
  for (std::size_t i = 1; i < knots.size(); ++i) {
    if (knots[i] - knots[i - 1] >= M_PI) {
      return "angular knot span [" + Number(knots[i - 1]) + ", " + Number(knots[i]) + "] is not shorter than pi";
    }
  }
  return {};
}

/// Why a curve of a TrimmedSurface with `dim` coordinates per control
/// point (2: a trimming curve or a pcurve, 3: an edge) is malformed, or "".
std::string SplineCurveProblem(const SplineCurve& curve, int dim) {
  // Curves in the parameter plane (loops, pcurves) are only bounded and
  // evaluated, never solved on: any degree OpenCascade writes. Curves in
  // space become curve cells, up to the kernels' degree.
  const int maxDegree = dim == 2 ? kernels::TrimRegion::kMaxPieceDegree : kMaxDegree;
  const int p = curve.degree;
  if (p < 1 || p > maxDegree) return "degree " + std::to_string(p) + ", expected 1 to " + std::to_string(maxDegree);
  if (curve.points.size() % dim != 0) {
    return "points: " + std::to_string(curve.points.size()) + " values, not a multiple of " + std::to_string(dim);
  }
  const std::size_t n = curve.points.size() / dim;
  if (n < static_cast<std::size_t>(p) + 1) {
    return std::to_string(n) + " control points, a degree " + std::to_string(p) + " curve needs " +
           std::to_string(p + 1);
  }
  if (curve.knots.size() != n + p + 1) {
    return "knots: length " + std::to_string(curve.knots.size()) + ", expected control points + degree + 1 = " +
           std::to_string(n + p + 1);
  }
  for (std::size_t i = 0; i < curve.knots.size(); ++i) {
    if (!std::isfinite(curve.knots[i])) return "knots" + Index(static_cast<std::int64_t>(i)) + ": not finite";
    if (i > 0 && curve.knots[i] < curve.knots[i - 1]) return "knots: decreasing at index " + std::to_string(i);
  }
  if (!(curve.knots[p] < curve.knots[n])) return "knots: empty parameter domain";
  if (!std::isfinite(curve.knots.back() - curve.knots.front())) {
    return "knots: [" + Number(curve.knots.front()) + ", " + Number(curve.knots.back()) + "] " + kKnotWidthProblem;
  }
  for (std::size_t i = 0; i < curve.points.size(); ++i) {
    if (!std::isfinite(curve.points[i]) || std::abs(curve.points[i]) > kMaxCoordinate) {
      return "points" + Index(static_cast<std::int64_t>(i / dim)) +
             ": coordinate not finite or outside [-1e100, 1e100]";
    }
  }
  if (!curve.weights.empty()) {
    if (curve.weights.size() != n) {
      return "weights: " + std::to_string(curve.weights.size()) + " values, expected " + std::to_string(n);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double w = curve.weights[i];
      if (!(w >= 1.0 / kMaxWeight && w <= kMaxWeight)) {
        return "weights" + Index(static_cast<std::int64_t>(i)) + ": not in [1e-50, 1e50]";
      }
    }
  }
  if (curve.angular) return AngularSpansProblem(curve.knots, curve.degree);
  return {};
}

/// The box of the points the cells use, grown one point at a time (empty:
/// lo above hi).
struct Extent {
  double lo[3] = {kInf, kInf, kInf};
  double hi[3] = {-kInf, -kInf, -kInf};

  void Add(const double* x, int dim) {
    for (int k = 0; k < dim; ++k) {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  }
  bool empty() const { return lo[0] > hi[0]; }
};

/// The checks of one patch, each returning its first problem or none.
class PatchCheck {
 public:
  PatchCheck(const Patch& patch, std::int64_t index, int dim) : patch_(patch), index_(index), dim_(dim) {}

  /// Every check of the patch; on success adds the points its cells use to `extent`.
  GeometryError Run(Extent* extent) const;

 private:
  GeometryError Fail(GeometryField field, std::int64_t element, std::int64_t item, std::string message) const {
    return GeometryError{index_, field, element, item, std::move(message)};
  }
  GeometryField PointsField() const {
    return patch_.kind == Patch::Kind::Mesh || patch_.kind == Patch::Kind::PouManifold ? GeometryField::Vertices
                                                                                          : GeometryField::ControlPoints;
  }
  std::int64_t NumPoints() const { return static_cast<std::int64_t>(patch_.points.size() / dim_); }

  GeometryError Coordinates() const;
  GeometryError Weights(std::int64_t expected) const;
  GeometryError BSpline() const;
  GeometryError Bezier() const;
  GeometryError Mesh() const;
  GeometryError BezierCells() const;
  GeometryError TrimmedSurface() const;
  GeometryError PouManifold() const;
  /// Patch::cells as rows of `perCell` indices of the patch's points.
  GeometryError VertexIndices(std::size_t perCell, const char* cellName) const;
  /// The degrees of one Bezier cell of the known type `type`, `count` of
  /// them listed in `degrees`: its shape in *shape, or a message (without
  /// the place) with the index of the degree at fault in *badDegree (-1
  /// when the count is wrong).
  std::string CellDegrees(CellType type, const int* degrees, std::size_t count, kernels::CellShape* shape,
                          std::int64_t* badDegree) const;
  void AddUsedPoints(Extent* extent) const;

  const Patch& patch_;
  std::int64_t index_;
  int dim_;
};

GeometryError PatchCheck::Run(Extent* extent) const {
  if (static_cast<int>(patch_.kind) > static_cast<int>(Patch::Kind::PouManifold)) {
    return Fail(GeometryField::Kind, -1, -1, "unknown patch kind " + std::to_string(static_cast<int>(patch_.kind)));
  }
  if (patch_.kind != Patch::Kind::BSpline && patch_.kind != Patch::Kind::BezierCells &&
      patch_.kind != Patch::Kind::TrimmedSurface && patch_.kind != Patch::Kind::PouManifold &&
      !IsKnownCellType(patch_.cell)) {
    return Fail(GeometryField::Cell, -1, -1, "unknown cell type " + std::to_string(static_cast<int>(patch_.cell)));
  }
  if (GeometryError e = Coordinates()) return e;
  GeometryError e;
  switch (patch_.kind) {
    case Patch::Kind::BSpline:
      e = BSpline();
      break;
    case Patch::Kind::Bezier:
      e = Bezier();
      break;
    case Patch::Kind::Mesh:
      e = Mesh();
      break;
    case Patch::Kind::BezierCells:
      e = BezierCells();
      break;
    case Patch::Kind::TrimmedSurface:
      e = TrimmedSurface();
      break;
    case Patch::Kind::PouManifold:
      e = PouManifold();
      break;
  }
  if (!e) AddUsedPoints(extent);
  return e;
}

GeometryError PatchCheck::Coordinates() const {
  const std::vector<double>& x = patch_.points;
  if (x.size() % dim_ != 0) {
    return Fail(PointsField(), -1, -1,
                std::to_string(x.size()) + " coordinates, not a whole number of points of dimension " +
                    std::to_string(dim_));
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::int64_t point = static_cast<std::int64_t>(i / dim_), k = static_cast<std::int64_t>(i % dim_);
    if (!std::isfinite(x[i])) {
      return Fail(PointsField(), point, k, "coordinate " + std::to_string(k) + " is not finite (" + Number(x[i]) + ")");
    }
    if (std::abs(x[i]) > kMaxCoordinate) {
      return Fail(PointsField(), point, k,
                  "coordinate " + std::to_string(k) + " is " + Number(x[i]) +
                      ", outside [-1e100, 1e100] (the range invmap supports)");
    }
  }
  return {};
}

GeometryError PatchCheck::Weights(std::int64_t expected) const {
  const std::vector<double>& w = patch_.weights;
  if (w.empty()) return {};
  if (static_cast<std::int64_t>(w.size()) != expected) {
    return Fail(GeometryField::Weights, -1, -1,
                std::to_string(w.size()) + " values, expected one per control point (" + std::to_string(expected) +
                    ")");
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    const std::int64_t element = static_cast<std::int64_t>(i);
    if (!std::isfinite(w[i])) return Fail(GeometryField::Weights, element, -1, Number(w[i]) + " is not finite");
    if (!(w[i] > 0.0)) return Fail(GeometryField::Weights, element, -1, Number(w[i]) + " is not positive");
    if (w[i] > kMaxWeight || w[i] < 1.0 / kMaxWeight) {
      return Fail(GeometryField::Weights, element, -1,
                  Number(w[i]) + " is outside [1e-50, 1e50] (the range invmap supports)");
    }
  }
  return {};
}

GeometryError PatchCheck::BSpline() const {
  const std::size_t paramDim = patch_.degrees.size();
  const std::string directions = std::to_string(paramDim);
  if (paramDim < 1 || paramDim > 3) {
    return Fail(GeometryField::Degrees, -1, -1,
                directions + " values, expected 1 to 3 (one per parametric direction)");
  }
  if (static_cast<int>(paramDim) > dim_) {
    return Fail(GeometryField::Degrees, -1, -1, "a " + directions + "-parameter patch needs dimension 3");
  }
  if (patch_.counts.size() != paramDim) {
    return Fail(GeometryField::Counts, -1, -1,
                std::to_string(patch_.counts.size()) + " values, expected one per degree (" + directions + ")");
  }
  if (patch_.knots.size() != paramDim) {
    return Fail(GeometryField::Knots, -1, -1,
                std::to_string(patch_.knots.size()) + " knot vectors, expected one per degree (" + directions + ")");
  }
  // A double: absurd counts must not overflow (they are only compared with
  // the points present).
  double expectedPoints = 1.0;
  std::string product;
  for (std::size_t d = 0; d < paramDim; ++d) {
    const std::int64_t dir = static_cast<std::int64_t>(d);
    const std::string i = Index(dir);
    const std::int64_t p = patch_.degrees[d], n = patch_.counts[d];
    const std::vector<double>& knots = patch_.knots[d];
    if (p < 1 || p > kMaxDegree) {
      return Fail(GeometryField::Degrees, dir, -1,
                  std::to_string(p) + ", expected 1 to " + std::to_string(kMaxDegree) +
                      (p > kMaxDegree ? " (the highest degree invmap supports)" : ""));
    }
    if (n < p + 1) {
      return Fail(GeometryField::Counts, dir, -1,
                  std::to_string(n) + ", expected at least degrees" + i + " + 1 = " + std::to_string(p + 1));
    }
    if (static_cast<std::int64_t>(knots.size()) != n + p + 1) {
      return Fail(GeometryField::Knots, dir, -1,
                  "length " + std::to_string(knots.size()) + ", expected counts" + i + " + degrees" + i +
                      " + 1 = " + std::to_string(n + p + 1));
    }
    for (std::size_t k = 0; k < knots.size(); ++k) {
      const std::int64_t knot = static_cast<std::int64_t>(k);
      if (!std::isfinite(knots[k])) {
        return Fail(GeometryField::Knots, dir, knot,
                    "knot " + std::to_string(k) + " is not finite (" + Number(knots[k]) + ")");
      }
      if (k > 0 && knots[k - 1] > knots[k]) {
        return Fail(GeometryField::Knots, dir, knot,
                    "decreasing at index " + std::to_string(k) + " (" + Number(knots[k - 1]) + " > " +
                        Number(knots[k]) + ")");
      }
    }
    // The B-spline is defined on [t_p, t_n]; with no room there it has no cell.
    if (!(knots[p] < knots[n])) {
      return Fail(GeometryField::Knots, dir, -1,
                  "empty parameter domain [knots" + i + Index(p) + ", knots" + i + Index(n) + "] = [" +
                      Number(knots[p]) + ", " + Number(knots[n]) + "]");
    }
    if (!std::isfinite(knots.back() - knots.front())) {
      return Fail(GeometryField::Knots, dir, -1,
                  "[" + Number(knots.front()) + ", " + Number(knots.back()) + "] " + kKnotWidthProblem);
    }
    expectedPoints *= static_cast<double>(n);
    product += (d > 0 ? " x " : "") + std::to_string(n);
  }
  if (static_cast<double>(NumPoints()) != expectedPoints) {
    return Fail(GeometryField::ControlPoints, -1, -1,
                std::to_string(NumPoints()) + " points, expected " + Number(expectedPoints) + " (counts " + product +
                    ")");
  }
  return Weights(NumPoints());
}

std::string PatchCheck::CellDegrees(CellType type, const int* degrees, std::size_t count, kernels::CellShape* shape,
                                    std::int64_t* badDegree) const {
  const int factors = kernels::CellShape::NumFactorsOf(type);
  *badDegree = -1;
  if (count != static_cast<std::size_t>(factors)) {
    return std::to_string(count) + " values, a " + CellTypeName(type) + " cell needs " + std::to_string(factors) +
           " " + DegreeForm(type);
  }
  std::array<int, kernels::kMaxFactors> list{};
  for (int f = 0; f < factors; ++f) {
    list[f] = degrees[f];
    if (list[f] < 1 || list[f] > kMaxDegree) {
      *badDegree = f;
      return std::to_string(list[f]) + ", expected 1 to " + std::to_string(kMaxDegree) +
             (list[f] > kMaxDegree ? " (the highest degree invmap supports)" : "");
    }
  }
  *shape = kernels::CellShape(type, list);
  return {};
}

GeometryError PatchCheck::Bezier() const {
  kernels::CellShape shape;
  std::int64_t badDegree = -1;
  if (std::string m = CellDegrees(patch_.cell, patch_.degrees.data(), patch_.degrees.size(), &shape, &badDegree);
      !m.empty()) {
    return Fail(GeometryField::Degrees, badDegree, -1, m);
  }
  if (shape.paramDim() > dim_) {
    return Fail(GeometryField::Cell, -1, -1, std::string("a ") + CellTypeName(patch_.cell) + " cell needs dimension 3");
  }
  const std::int64_t n = shape.numControlPoints();
  if (NumPoints() != n) {
    std::string degrees;
    for (std::size_t d = 0; d < patch_.degrees.size(); ++d) {
      degrees += (d > 0 ? ", " : "") + std::to_string(patch_.degrees[d]);
    }
    return Fail(GeometryField::ControlPoints, -1, -1,
                std::to_string(NumPoints()) + " points, expected " + std::to_string(n) + " for a " +
                    CellTypeName(patch_.cell) + " cell of degrees [" + degrees + "]");
  }
  return Weights(n);
}

GeometryError PatchCheck::Mesh() const {
  const CellTypeTraits& traits = TraitsOf(patch_.cell);
  if (traits.paramDim > dim_) {
    return Fail(GeometryField::Cell, -1, -1, std::string("a ") + traits.name + " mesh needs dimension 3");
  }
  if (!patch_.weights.empty()) return Fail(GeometryField::Weights, -1, -1, "a mesh has no weights");
  return VertexIndices(static_cast<std::size_t>(traits.vertices), traits.name);
}

GeometryError PatchCheck::VertexIndices(std::size_t perCell, const char* cellName) const {
  if (patch_.cells.size() % perCell != 0) {
    return Fail(GeometryField::Cells, -1, -1,
                std::to_string(patch_.cells.size()) + " vertex indices, not a whole number of " + cellName +
                    " cells (" + std::to_string(perCell) + " each)");
  }
  const std::int64_t numVertices = NumPoints();
  for (std::size_t i = 0; i < patch_.cells.size(); ++i) {
    const std::int64_t index = patch_.cells[i];
    if (index >= 0 && index < numVertices) continue;
    const std::int64_t cell = static_cast<std::int64_t>(i / perCell), vertex = static_cast<std::int64_t>(i % perCell);
    if (index < 0) {
      return Fail(GeometryField::Cells, cell, vertex,
                  "vertex index " + std::to_string(index) + " is negative (indices are 0-based)");
    }
    return Fail(GeometryField::Cells, cell, vertex,
                "vertex index " + std::to_string(index) + " out of range (the patch has " +
                    std::to_string(numVertices) + " vertices)");
  }
  return {};
}

GeometryError PatchCheck::BezierCells() const {
  const std::size_t numCells = patch_.cellTypes.size();
  if (patch_.cellDegrees.size() != 3 * numCells) {
    return Fail(GeometryField::CellDegrees, -1, -1,
                std::to_string(patch_.cellDegrees.size()) + " values, expected 3 per cell (" +
                    std::to_string(3 * numCells) + ")");
  }
  if (patch_.cellOffsets.size() != numCells + 1) {
    return Fail(GeometryField::CellOffsets, -1, -1,
                std::to_string(patch_.cellOffsets.size()) + " values, expected one per cell and one more (" +
                    std::to_string(numCells + 1) + ")");
  }
  const std::int64_t numPoints = NumPoints();
  if (GeometryError e = Weights(numPoints)) return e;
  for (std::size_t c = 0; c < numCells; ++c) {
    const std::int64_t cell = static_cast<std::int64_t>(c);
    const CellType type = patch_.cellTypes[c];
    if (!IsKnownCellType(type)) {
      return Fail(GeometryField::Cells, cell, -1, "unknown cell type " + std::to_string(static_cast<int>(type)));
    }
    kernels::CellShape shape;
    std::int64_t badDegree = -1;
    const int factors = kernels::CellShape::NumFactorsOf(type);
    if (std::string m = CellDegrees(type, &patch_.cellDegrees[3 * c], static_cast<std::size_t>(factors), &shape,
                                    &badDegree);
        !m.empty()) {
      return Fail(GeometryField::Cells, cell, -1, "degrees" + Index(badDegree) + ": " + m);
    }
    if (shape.paramDim() > dim_) {
      return Fail(GeometryField::Cells, cell, -1, std::string("a ") + CellTypeName(type) + " cell needs dimension 3");
    }
    const std::int64_t first = patch_.cellOffsets[c], last = patch_.cellOffsets[c + 1];
    if (first < 0 || last > numPoints || last - first != shape.numControlPoints()) {
      return Fail(GeometryField::Cells, cell, -1,
                  "control points [" + std::to_string(first) + ", " + std::to_string(last) + "), expected " +
                      std::to_string(shape.numControlPoints()) + " within the " + std::to_string(numPoints) +
                      " points");
    }
  }
  return {};
}

GeometryError PatchCheck::TrimmedSurface() const {
  if (dim_ != 3) return Fail(GeometryField::Kind, -1, -1, "a trimmed surface needs dimension 3");
  if (patch_.degrees.size() != 2) {
    return Fail(GeometryField::Degrees, -1, -1,
                std::to_string(patch_.degrees.size()) + " values, a trimmed surface has 2 directions");
  }
  if (GeometryError e = BSpline()) return e;
  if (!patch_.angular.empty() && patch_.angular.size() != 2) {
    return Fail(GeometryField::Angular, -1, -1,
                std::to_string(patch_.angular.size()) + " values, expected 2 (u, v) or none");
  }
  for (std::size_t d = 0; d < patch_.angular.size(); ++d) {
    if (patch_.angular[d] == 0) continue;
    if (std::string m = AngularSpansProblem(patch_.knots[d], patch_.degrees[d]); !m.empty()) {
      return Fail(GeometryField::Knots, static_cast<std::int64_t>(d), -1, m);
    }
  }
  for (std::size_t l = 0; l < patch_.trimLoops.size(); ++l) {
    for (std::size_t c = 0; c < patch_.trimLoops[l].size(); ++c) {
      if (std::string m = SplineCurveProblem(patch_.trimLoops[l][c], 2); !m.empty()) {
        return Fail(GeometryField::TrimLoops, static_cast<std::int64_t>(l), static_cast<std::int64_t>(c),
                    "curve " + std::to_string(c) + ": " + m);
      }
    }
  }
  for (std::size_t e = 0; e < patch_.edges.size(); ++e) {
    const PatchEdge& edge = patch_.edges[e];
    if (std::string m = SplineCurveProblem(edge.curve, 3); !m.empty()) {
      return Fail(GeometryField::Edges, static_cast<std::int64_t>(e), -1, "curve: " + m);
    }
    if (edge.pcurve.points.empty()) continue;  // unknown: its answers' (u, v) are NaN
    if (std::string m = SplineCurveProblem(edge.pcurve, 2); !m.empty()) {
      return Fail(GeometryField::Edges, static_cast<std::int64_t>(e), -1, "pcurve: " + m);
    }
  }
  return {};
}

GeometryError PatchCheck::PouManifold() const {
  if (dim_ != 3) return Fail(GeometryField::Kind, -1, -1, "a pou_manifold is a surface of R^3: it needs dimension 3");
  if (!patch_.weights.empty()) return Fail(GeometryField::Weights, -1, -1, "a pou_manifold has no weights");
  if (GeometryError e = VertexIndices(3, "tri")) return e;
  const std::int64_t numVertices = NumPoints();
  if (static_cast<std::int64_t>(patch_.degrees.size()) != numVertices) {
    return Fail(GeometryField::Degrees, -1, -1,
                std::to_string(patch_.degrees.size()) + " values, expected one per vertex (" +
                    std::to_string(numVertices) + ")");
  }
  std::size_t expected = 0;
  for (std::size_t v = 0; v < patch_.degrees.size(); ++v) {
    const int d = patch_.degrees[v];
    if (d < 1 || d > pou::kMaxChartDegree) {
      return Fail(GeometryField::Degrees, static_cast<std::int64_t>(v), -1,
                  std::to_string(d) + ", expected 1 to " + std::to_string(pou::kMaxChartDegree));
    }
    expected += static_cast<std::size_t>(d + 1) * static_cast<std::size_t>(d + 1);
  }
  const std::vector<double>& nets = patch_.chartControlPoints;
  if (nets.size() != 3 * expected) {
    return Fail(GeometryField::ChartControlPoints, -1, -1,
                std::to_string(nets.size()) + " coordinates, expected " + std::to_string(3 * expected) +
                    " (3 for each of the (degree + 1)^2 control points of every vertex's chart)");
  }
  for (std::size_t i = 0; i < nets.size(); ++i) {
    const std::int64_t point = static_cast<std::int64_t>(i / 3), k = static_cast<std::int64_t>(i % 3);
    if (!std::isfinite(nets[i]) || std::abs(nets[i]) > kMaxCoordinate) {
      return Fail(GeometryField::ChartControlPoints, point, k,
                  "coordinate " + std::to_string(k) + " is " + Number(nets[i]) +
                      ", not a finite number within [-1e100, 1e100]");
    }
  }
  // The gluing data needs a closed, oriented, manifold mesh; the message
  // names the vertex, edge or triangle at fault.
  pou::ClosedMesh mesh;
  if (std::string m = mesh.Build(patch_.points.data(), numVertices, patch_.cells.data(),
                                 static_cast<std::int64_t>(patch_.cells.size() / 3));
      !m.empty()) {
    return Fail(GeometryField::Cells, -1, -1, std::move(m));
  }
  return {};
}

void PatchCheck::AddUsedPoints(Extent* extent) const {
  const double* x = patch_.points.data();
  switch (patch_.kind) {
    case Patch::Kind::Mesh:
      for (const std::int64_t v : patch_.cells) extent->Add(x + v * dim_, dim_);
      return;
    case Patch::Kind::BezierCells:
      for (std::size_t c = 0; c + 1 < patch_.cellOffsets.size(); ++c) {
        for (std::int64_t i = patch_.cellOffsets[c]; i < patch_.cellOffsets[c + 1]; ++i) {
          extent->Add(x + i * dim_, dim_);
        }
      }
      return;
    default:
      for (std::int64_t i = 0; i < NumPoints(); ++i) extent->Add(x + i * dim_, dim_);
      return;
  }
}

/// The geometry's extent (the diagonal of the box of the points its cells
/// use): 0 (a single point) or at least kMinExtent. No cell at all is an
/// error too: every point would be "none", a mistake (an empty file or
/// list), not a geometry.
GeometryError CheckExtent(const Extent& extent, int dim) {
  if (extent.empty()) {
    return GeometryError{-1, GeometryField::None, -1, -1,
                         "the geometry has no cells (no patches, or only empty ones): nothing to invert onto"};
  }
  double span[3] = {0.0, 0.0, 0.0};
  double largest = 0.0;
  for (int k = 0; k < dim; ++k) {
    span[k] = extent.hi[k] - extent.lo[k];
    largest = std::max(largest, span[k]);
  }
  // The diagonal is at least its largest side; it is measured in units of
  // that side, so that no square underflows (squares in absolute units, or
  // in units of kMinExtent, vanish below about 1e-254 and took a geometry
  // 1e-280 across for a single point).
  if (largest == 0.0 || largest >= kMinExtent) return {};
  double sum = 0.0;
  for (int k = 0; k < dim; ++k) sum += (span[k] / largest) * (span[k] / largest);
  const double diagonal = largest * std::sqrt(sum);
  if (diagonal >= kMinExtent) return {};
  std::ostringstream message;
  message << "the geometry is " << diagonal << " across (its box diagonal), below 1e-100 (the smallest extent invmap supports)";
  return GeometryError{-1, GeometryField::None, -1, -1, message.str()};
}

}  // namespace

GeometryError ValidateGeometry(const Geometry& geometry) {
  const int dim = geometry.dimension;
  if (dim != 2 && dim != 3) {
    return GeometryError{-1, GeometryField::Dimension, -1, -1, std::to_string(dim) + ", expected 2 or 3"};
  }
  Extent extent;
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    if (GeometryError e = PatchCheck(geometry.patches[p], static_cast<std::int64_t>(p), dim).Run(&extent)) return e;
  }
  return CheckExtent(extent, dim);
}

}  // namespace invmap::engine
