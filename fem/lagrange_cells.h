// A patch of Bezier cells built from Lagrange (or serendipity) elements
// that share nodes, and the node fields over it: shared by the VTK and
// Exodus readers, which differ only in how they learn each element's change
// of basis. Rational elements (VTK's Bezier cells with rational weights)
// are changed in homogeneous coordinates.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "invmap/fields.h"
#include "invmap/invmap.h"
#include "io/lagrange_to_bernstein.h"

namespace invmap::fem {

/// Collects elements into one BezierCells patch. Each element's control
/// points are its nodes through its change of basis (a node that is a
/// control point, every vertex, is copied bit for bit); the converters must
/// outlive the builder.
class LagrangePatchBuilder {
 public:
  /// `nodes`: 3 coordinates per node of the file.
  explicit LagrangePatchBuilder(const std::vector<double>& nodes) : nodes_(nodes) {}

  /// Appends an element of `type` whose Bezier cell has `degree` in every
  /// factor; `elementNodes` holds converter.numNodes() node indices, checked
  /// by the caller.
  void AddElement(CellType type, int degree, const io::LagrangeToBernstein& converter,
                  const std::int64_t* elementNodes);

  /// Appends a rational element: `nodeWeights` holds the weight of each of
  /// its converter.numNodes() nodes (positive, checked by the caller), in
  /// the element's node order. Control point i is sum_j C_ij w_j x_j / W_i
  /// with weight W_i = sum_j C_ij w_j (C the change of basis): the change
  /// of basis in homogeneous coordinates, so the cell is the element's
  /// rational map exactly, degree elevation included. The patch becomes
  /// rational; its polynomial elements get weights 1.
  void AddRationalElement(CellType type, int degree, const io::LagrangeToBernstein& converter,
                          const std::int64_t* elementNodes, const double* nodeWeights);

  std::size_t numElements() const { return elements_.size(); }

  /// The patch of every element added, in order, for a geometry of
  /// dimension `dim` (2 keeps x and y).
  Patch MakePatch(int dim) const;

  /// A nodal field (`components` values per node of the file) as the
  /// patch's control values, element by element through the same changes
  /// of basis (of a rational element in homogeneous coordinates, so that
  /// the cell's rational basis interpolates it as the element's own
  /// rational shape functions do).
  std::vector<double> ConvertField(const std::vector<double>& nodal, int components) const;

 private:
  struct Element {
    CellType type;
    int degree;
    const io::LagrangeToBernstein* converter;
    std::size_t firstNode;  ///< Offset in elementNodes_.
    std::ptrdiff_t firstWeight;  ///< Offset in nodeWeights_; -1 for a polynomial element.
  };

  const std::vector<double>& nodes_;
  std::vector<Element> elements_;
  std::vector<std::int64_t> elementNodes_;
  std::vector<double> nodeWeights_;
};

/// Parametric dimension of a cell type (1, 2 or 3).
int ParamDimOf(CellType type);

/// 2 when no element is a volume and every node has z == 0, else 3 (the
/// gmsh reader's rule).
int GeometryDimension(const std::vector<double>& nodes, bool anyVolume);

}  // namespace invmap::fem
