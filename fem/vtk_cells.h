// VTK cell types as invmap cells: which reference cell each VTK type is,
// and the change of basis from its nodes to Bernstein control points,
// learned from VTK's own shape functions (vtkCell::InterpolateFunctions),
// so that node order and polynomial space are exactly VTK's.
#pragma once

#include <map>
#include <string>
#include <tuple>

#include "invmap/invmap.h"
#include "io/lagrange_to_bernstein.h"

class vtkUnstructuredGrid;

namespace invmap::fem {

/// The invmap reference cell of a VTK cell type (VTK_LINE .. VTK_BEZIER_WEDGE);
/// false for types invmap does not read (vertices, polygons, pyramids,
/// polyhedra, ...).
bool VtkCellTypeToInvmap(int vtkType, CellType* type);

/// VTK's name of a cell type ("VTK_QUADRATIC_TETRA"), for messages.
std::string VtkCellTypeName(int vtkType);

/// A VTK cell type's change of basis and the Bezier degree it needs.
struct VtkCellConversion {
  CellType type;
  int degree;
  io::LagrangeToBernstein converter;
};

/// Changes of basis per VTK cell layout, built at the first cell of each.
class VtkCellConversions {
 public:
  /// The conversion of cell `cellId` of `grid`, identified by its VTK type,
  /// node count and per-direction orders (`orders`: the grid's
  /// HigherOrderDegrees of the cell, -1 when it has none). Built at the
  /// first cell of each kind from VTK's shape functions sampled at the
  /// Bernstein lattice of the smallest degree that reproduces them (checked
  /// at 32 further points to 1e-10), up to degree 8. Null when none does
  /// (a rational cell) or the type is not one invmap reads.
  const VtkCellConversion* Find(vtkUnstructuredGrid* grid, long long cellId, const int orders[3]);

 private:
  using Key = std::tuple<int, int, int, int, int>;
  std::map<Key, VtkCellConversion> conversions_;
  std::map<Key, bool> failed_;
};

}  // namespace invmap::fem
