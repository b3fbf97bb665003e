// Change of basis from Lagrange nodal values to Bernstein control points on
// invmap's reference cells (docs/formats.md section 1), for readers of high-order
// meshes. Independent of kernels/: it evaluates the Bernstein basis itself.
#pragma once

#include <array>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::io {

/// Number of control points of a cell of `type` with degree `degree` in
/// every simplex factor.
int BernsteinCount(CellType type, int degree);

/// Reference locations of those control points in docs/formats.md order (unused
/// coordinates 0): a simplex multi-index a sits at a / degree.
std::vector<std::array<double, 3>> BernsteinLattice(CellType type, int degree);

/// Degrees of a cell as Patch::cellDegrees stores them (3 per cell, one per
/// simplex factor, unused 0) for `degree` in every factor.
std::array<int, 3> UniformDegrees(CellType type, int degree);

/// Values of every Bernstein polynomial of a cell of `type` with degree
/// `degree` in every factor at reference point x, in control point order.
std::vector<double> BernsteinBasisAt(CellType type, int degree, const std::array<double, 3>& x);

/// The linear map from the values of a polynomial at a cell's Lagrange nodes
/// to its Bernstein control points of degree `degree` (every factor), built
/// once per element type and applied to every element.
///
/// Complete elements (the nodes are unisolvent for the whole Bernstein space
/// of that degree) use the plain change of basis C = V^-1 L, with V the
/// Bernstein basis at the nodes. Incomplete elements span a subspace given by
/// monomials: their nodal shape functions are evaluated at the Bernstein
/// lattice points, which are then interpolated by the complete space; both
/// steps are exact, so the result is the same polynomial. The matrices are
/// formed and solved in long double (order 4 hexahedra invert a 125 x 125
/// Vandermonde matrix) and rounded to double once.
class LagrangeToBernstein {
 public:
  /// `nodes`: reference coordinates of the Lagrange nodes (docs/formats.md
  /// section 1, unused entries 0). `monomials`: exponents (a, b, c) of the
  /// monomials s^a t^b r^c spanning an incomplete element's space (as many as
  /// nodes); empty for a complete element, whose node count must then equal
  /// BernsteinCount(type, degree). Throws std::invalid_argument when the
  /// nodes do not determine a unique polynomial of the space.
  LagrangeToBernstein(CellType type, int degree, const std::vector<std::array<double, 3>>& nodes,
                      const std::vector<std::array<int, 3>>& monomials = {});

  /// The change of basis of an element known by its shape functions alone
  /// (a library's cell that evaluates them, such as VTK's): `values` holds
  /// the numNodes shape functions at each point of BernsteinLattice(type,
  /// degree), lattice point-major (values[y * numNodes + j] = N_j(y)). Exact
  /// when the shape functions are polynomials of that degree; whether they
  /// are is the caller's to check (BernsteinBasisAt). Throws
  /// std::invalid_argument when the sizes do not match.
  static LagrangeToBernstein FromShapeValues(CellType type, int degree, int numNodes,
                                             const std::vector<double>& values);

  int numNodes() const { return numNodes_; }
  int numControlPoints() const { return numControl_; }
  /// Entry (i, j): weight of node j in control point i.
  double coefficient(int i, int j) const { return matrix_[static_cast<std::size_t>(i) * numNodes_ + j]; }
  /// The node that control point i equals (its row is a unit vector up to
  /// rounding), or -1.
  int copiedNode(int i) const { return copiedNode_[static_cast<std::size_t>(i)]; }

  /// Control points from nodal positions: `nodes` holds numNodes() points of
  /// 3 coordinates each; `control` receives numControlPoints() points of the
  /// first `dim` (1..3) coordinates each. A control point that is a node
  /// (the cell's vertices) is that node's position exactly, so cells that
  /// share vertices share their corner control points bit for bit.
  void Apply(const double* nodes, int dim, double* control) const;

  /// Control values of a field over the element: `nodal` holds numNodes()
  /// rows of `components` values (the element's nodes in order), `control`
  /// receives numControlPoints() rows. A zero coefficient leaves its node
  /// out, so a node without a value (NaN) spoils only the control values it
  /// contributes to.
  void ApplyToValues(const double* nodal, int components, double* control) const;

 private:
  LagrangeToBernstein() = default;
  /// Sets the matrix from C in long double, and marks the rows that copy a node.
  void SetMatrix(const std::vector<long double>& result);

  int numNodes_ = 0;
  int numControl_ = 0;
  std::vector<double> matrix_;  ///< numControl_ x numNodes_, row-major.
  /// Per control point: the node it equals (its row is a unit vector), or -1.
  std::vector<int> copiedNode_;
};

}  // namespace invmap::io
