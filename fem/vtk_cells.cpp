#include "fem/vtk_cells.h"

#include <vtkCell.h>
#include <vtkCellType.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::fem {
namespace {

struct VtkTypeEntry {
  int vtkType;
  const char* name;
  CellType type;
};

constexpr VtkTypeEntry kVtkTypes[] = {
    {VTK_LINE, "VTK_LINE", CellType::Line},
    {VTK_TRIANGLE, "VTK_TRIANGLE", CellType::Tri},
    {VTK_PIXEL, "VTK_PIXEL", CellType::Quad},
    {VTK_QUAD, "VTK_QUAD", CellType::Quad},
    {VTK_TETRA, "VTK_TETRA", CellType::Tet},
    {VTK_VOXEL, "VTK_VOXEL", CellType::Hex},
    {VTK_HEXAHEDRON, "VTK_HEXAHEDRON", CellType::Hex},
    {VTK_WEDGE, "VTK_WEDGE", CellType::Wedge},
    {VTK_QUADRATIC_EDGE, "VTK_QUADRATIC_EDGE", CellType::Line},
    {VTK_QUADRATIC_TRIANGLE, "VTK_QUADRATIC_TRIANGLE", CellType::Tri},
    {VTK_QUADRATIC_QUAD, "VTK_QUADRATIC_QUAD", CellType::Quad},
    {VTK_QUADRATIC_TETRA, "VTK_QUADRATIC_TETRA", CellType::Tet},
    {VTK_QUADRATIC_HEXAHEDRON, "VTK_QUADRATIC_HEXAHEDRON", CellType::Hex},
    {VTK_QUADRATIC_WEDGE, "VTK_QUADRATIC_WEDGE", CellType::Wedge},
    {VTK_BIQUADRATIC_QUAD, "VTK_BIQUADRATIC_QUAD", CellType::Quad},
    {VTK_TRIQUADRATIC_HEXAHEDRON, "VTK_TRIQUADRATIC_HEXAHEDRON", CellType::Hex},
    {VTK_QUADRATIC_LINEAR_QUAD, "VTK_QUADRATIC_LINEAR_QUAD", CellType::Quad},
    {VTK_QUADRATIC_LINEAR_WEDGE, "VTK_QUADRATIC_LINEAR_WEDGE", CellType::Wedge},
    {VTK_BIQUADRATIC_QUADRATIC_WEDGE, "VTK_BIQUADRATIC_QUADRATIC_WEDGE", CellType::Wedge},
    {VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, "VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON", CellType::Hex},
    {VTK_BIQUADRATIC_TRIANGLE, "VTK_BIQUADRATIC_TRIANGLE", CellType::Tri},
    {VTK_CUBIC_LINE, "VTK_CUBIC_LINE", CellType::Line},
    {VTK_LAGRANGE_CURVE, "VTK_LAGRANGE_CURVE", CellType::Line},
    {VTK_LAGRANGE_TRIANGLE, "VTK_LAGRANGE_TRIANGLE", CellType::Tri},
    {VTK_LAGRANGE_QUADRILATERAL, "VTK_LAGRANGE_QUADRILATERAL", CellType::Quad},
    {VTK_LAGRANGE_TETRAHEDRON, "VTK_LAGRANGE_TETRAHEDRON", CellType::Tet},
    {VTK_LAGRANGE_HEXAHEDRON, "VTK_LAGRANGE_HEXAHEDRON", CellType::Hex},
    {VTK_LAGRANGE_WEDGE, "VTK_LAGRANGE_WEDGE", CellType::Wedge},
    {VTK_BEZIER_CURVE, "VTK_BEZIER_CURVE", CellType::Line},
    {VTK_BEZIER_TRIANGLE, "VTK_BEZIER_TRIANGLE", CellType::Tri},
    {VTK_BEZIER_QUADRILATERAL, "VTK_BEZIER_QUADRILATERAL", CellType::Quad},
    {VTK_BEZIER_TETRAHEDRON, "VTK_BEZIER_TETRAHEDRON", CellType::Tet},
    {VTK_BEZIER_HEXAHEDRON, "VTK_BEZIER_HEXAHEDRON", CellType::Hex},
    {VTK_BEZIER_WEDGE, "VTK_BEZIER_WEDGE", CellType::Wedge},
};

/// Names of the VTK types invmap does not read, for messages.
constexpr std::pair<int, const char*> kOtherVtkTypes[] = {
    {VTK_EMPTY_CELL, "VTK_EMPTY_CELL"},
    {VTK_VERTEX, "VTK_VERTEX"},
    {VTK_POLY_VERTEX, "VTK_POLY_VERTEX"},
    {VTK_POLY_LINE, "VTK_POLY_LINE"},
    {VTK_TRIANGLE_STRIP, "VTK_TRIANGLE_STRIP"},
    {VTK_POLYGON, "VTK_POLYGON"},
    {VTK_PYRAMID, "VTK_PYRAMID"},
    {VTK_PENTAGONAL_PRISM, "VTK_PENTAGONAL_PRISM"},
    {VTK_HEXAGONAL_PRISM, "VTK_HEXAGONAL_PRISM"},
    {VTK_QUADRATIC_PYRAMID, "VTK_QUADRATIC_PYRAMID"},
    {VTK_QUADRATIC_POLYGON, "VTK_QUADRATIC_POLYGON"},
    {VTK_TRIQUADRATIC_PYRAMID, "VTK_TRIQUADRATIC_PYRAMID"},
    {VTK_LAGRANGE_PYRAMID, "VTK_LAGRANGE_PYRAMID"},
    {VTK_BEZIER_PYRAMID, "VTK_BEZIER_PYRAMID"},
    {VTK_CONVEX_POINT_SET, "VTK_CONVEX_POINT_SET"},
    {VTK_POLYHEDRON, "VTK_POLYHEDRON"},
};

/// Deterministic points of a cell's reference domain (a fixed sequence
/// folded into simplices), where VTK's and the Bernstein basis are compared.
std::array<double, 3> CheckPoint(CellType type, int i) {
  // Weyl sequence: well spread and reproducible.
  std::array<double, 3> x{std::fmod(0.1234 + i * 0.7548776662, 1.0), std::fmod(0.5678 + i * 0.5698402910, 1.0),
                          std::fmod(0.9012 + i * 0.4342010779, 1.0)};
  const auto fold = [](double* a, int n) {
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += a[k];
    if (sum > 1.0) {
      for (int k = 0; k < n; ++k) a[k] *= 0.999 / sum;
    }
  };
  if (type == CellType::Tri || type == CellType::Wedge) fold(x.data(), 2);
  if (type == CellType::Tet) fold(x.data(), 3);
  return x;
}

/// VTK's shape functions of `cell` at reference point x.
std::vector<double> VtkShape(vtkCell* cell, const std::array<double, 3>& x) {
  // VTK writes the shape functions of the order it infers (from the
  // HigherOrderDegrees, which the reader bounds by 8, or from the node
  // count), which need not be as many as the cell's nodes on a malformed
  // file: fuzzing found VTK writing past room for the nodes alone. Room for
  // any order up to 8 and twice the nodes, then the cell's own.
  const auto n = static_cast<std::size_t>(cell->GetNumberOfPoints());
  constexpr std::size_t kMostOfAnOrder = (kernels::kMaxDegree + 1) * (kernels::kMaxDegree + 1) * (kernels::kMaxDegree + 1);
  std::vector<double> weights(2 * n + kMostOfAnOrder);
  double pcoords[3] = {x[0], x[1], x[2]};
  cell->InterpolateFunctions(pcoords, weights.data());
  weights.resize(n);
  return weights;
}

/// The change of basis of `cell` at degree `degree`, if it reproduces VTK's
/// shape functions there.
std::optional<io::LagrangeToBernstein> TryDegree(vtkCell* cell, CellType type, int degree) {
  const int n = static_cast<int>(cell->GetNumberOfPoints());
  const std::vector<std::array<double, 3>> lattice = io::BernsteinLattice(type, degree);
  std::vector<double> values;
  values.reserve(lattice.size() * static_cast<std::size_t>(n));
  for (const auto& y : lattice) {
    const std::vector<double> w = VtkShape(cell, y);
    values.insert(values.end(), w.begin(), w.end());
  }
  io::LagrangeToBernstein converter = io::LagrangeToBernstein::FromShapeValues(type, degree, n, values);
  constexpr int kChecks = 32;
  constexpr double kTolerance = 1e-10;
  for (int i = 0; i < kChecks; ++i) {
    const std::array<double, 3> x = CheckPoint(type, i);
    const std::vector<double> w = VtkShape(cell, x);
    const std::vector<double> b = io::BernsteinBasisAt(type, degree, x);
    for (int j = 0; j < n; ++j) {
      double sum = 0.0;
      for (int c = 0; c < converter.numControlPoints(); ++c) sum += b[c] * converter.coefficient(c, j);
      if (!(std::abs(sum - w[j]) <= kTolerance)) return std::nullopt;
    }
  }
  return converter;
}

}  // namespace

bool VtkCellTypeToInvmap(int vtkType, CellType* type) {
  for (const VtkTypeEntry& entry : kVtkTypes) {
    if (entry.vtkType == vtkType) {
      *type = entry.type;
      return true;
    }
  }
  return false;
}

std::string VtkCellTypeName(int vtkType) {
  for (const VtkTypeEntry& entry : kVtkTypes) {
    if (entry.vtkType == vtkType) return entry.name;
  }
  for (const auto& [value, name] : kOtherVtkTypes) {
    if (value == vtkType) return name;
  }
  return "an unknown VTK cell type";
}

const VtkCellConversion* VtkCellConversions::Find(vtkUnstructuredGrid* grid, long long cellId, const int orders[3]) {
  const int vtkType = grid->GetCellType(cellId);
  vtkIdType numPoints = 0;
  const vtkIdType* points = nullptr;
  grid->GetCellPoints(cellId, numPoints, points);
  const Key key{vtkType, static_cast<int>(numPoints), orders[0], orders[1], orders[2]};
  if (const auto it = conversions_.find(key); it != conversions_.end()) return &it->second;
  if (failed_.count(key) != 0) return nullptr;
  CellType type = CellType::Line;
  const int n = static_cast<int>(numPoints);
  vtkCell* cell = grid->GetCell(cellId);
  if (VtkCellTypeToInvmap(vtkType, &type) && n > 0) {
    // The smallest degree whose control net has room for every node.
    int degree = 1;
    while (degree < kernels::kMaxDegree && io::BernsteinCount(type, degree) < n) ++degree;
    for (; degree <= kernels::kMaxDegree; ++degree) {
      if (std::optional<io::LagrangeToBernstein> converter = TryDegree(cell, type, degree)) {
        return &conversions_.emplace(key, VtkCellConversion{type, degree, std::move(*converter)}).first->second;
      }
    }
  }
  failed_[key] = true;
  return nullptr;
}

}  // namespace invmap::fem
