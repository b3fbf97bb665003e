// VTK cells and files for the VTU reader's tests: VTK's reference cells of
// each type and order, where the tests place their nodes, and VTK's XML
// writer in each of its encodings.
#pragma once

#include <vtkCell.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <string>

#include "invmap/invmap.h"

namespace invmap::testing {

/// Nodes of a Lagrange or Bezier cell of `order`.
int HigherOrderPoints(int vtkType, int order);

/// A VTK cell of `vtkType` (of `order` for Lagrange and Bezier types, 0
/// for fixed ones), its node count set, with VTK's reference node
/// coordinates (GetParametricCoords).
vtkSmartPointer<vtkCell> MakeReferenceCell(int vtkType, int order);

/// Where the test puts a reference point: curved (a bend of each
/// coordinate) or affine, always non-degenerate, in 3D. VTK's pixels and
/// voxels are axis-aligned by definition: `aligned` scales and shifts only.
std::array<double, 3> Place(const double* r, bool curved, bool aligned = false);

/// The writer's encodings.
enum class Encoding { Ascii, Binary, BinaryZlib, Appended, AppendedRawZlib };

/// Writes `grid` with VTK's XML writer; true on success.
bool Write(vtkUnstructuredGrid* grid, const std::string& path, Encoding encoding);

/// Inverts `count` points that VTK's `cell` (of invmap type `type`) maps
/// random parameters (`seed`, 0.02 inside the reference cell) to, on
/// `manifold` built from that cell alone; expects each found at distance
/// below 1e-10 and, in a volume, at those parameters to 1e-9.
void ExpectVtkPointsRoundTrip(const Manifold& manifold, vtkCell* cell, CellType type, unsigned seed, int count);

}  // namespace invmap::testing
