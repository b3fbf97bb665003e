// The meshes and fields of the probe benchmark: conforming linear and
// quadratic tetrahedra and hexahedra filling a sheared box, as VTK grids in
// VTK's node order, with a node field that every element interpolates
// exactly (a polynomial of the elements' degree on straight-sided
// elements), so that a probe's right answer is known at every point.
#pragma once

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <string>

namespace invmap::bench {

/// Which mesh.
struct ProbeMeshKind {
  bool hexes = false;  ///< Hexahedra (VTK_HEXAHEDRON, VTK_QUADRATIC_HEXAHEDRON); else tetrahedra.
  int order = 1;       ///< 1 or 2.
};

/// The box [0, 1]^3 sheared by a fixed affine map.
std::array<double, 3> BoxPoint(const std::array<double, 3>& u);

/// The exact field: a polynomial of total degree `degree` at x.
double ExactField(const std::array<double, 3>& x, int degree);

/// `cells` cubes per direction, 6 tetrahedra or 1 hexahedron each; the
/// tetrahedra's vertices are jittered (elements stay straight-sided, so
/// each is affine), quadratic elements get their edge midpoints shared
/// between neighbours. Point data "f" is ExactField of the order.
vtkSmartPointer<vtkUnstructuredGrid> MakeProbeMesh(const ProbeMeshKind& kind, int cells);

/// "linear tets", "quadratic hexes", ...
std::string ProbeMeshName(const ProbeMeshKind& kind);

}  // namespace invmap::bench
