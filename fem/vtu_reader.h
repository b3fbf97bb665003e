// VTK XML unstructured grids (.vtu), read through VTK 9's own reader.
#pragma once

#include <string>

#include "invmap/fields.h"

namespace invmap::fem {

/// Reads a .vtu file (ascii, binary, appended, compressed: whatever VTK's
/// vtkXMLUnstructuredGridReader reads) into one BezierCells patch holding
/// every cell in file order, so a cell's index is its VTK cell id; and its
/// numeric point data arrays as node fields (as many components as the
/// array). Cells: VTK's linear lines, triangles, quads, pixels, tetrahedra,
/// hexahedra, voxels and wedges, its quadratic and cubic types
/// (VTK_QUADRATIC_*, VTK_BIQUADRATIC_*, VTK_TRIQUADRATIC_HEXAHEDRON,
/// VTK_CUBIC_LINE) and its Lagrange and Bezier curves, triangles,
/// quadrilaterals, tetrahedra, hexahedra and wedges of any order up to 8
/// (HigherOrderDegrees honoured). Each becomes a Bezier cell through an
/// exact change of basis learned from VTK's own shape functions, so the
/// reported parameters are VTK's parametric coordinates. When the point
/// data has a RationalWeights attribute, VTK's Bezier cells are rational
/// with those weights (the patch is then rational, other cells weight 1)
/// and that array is not a field. The geometry is 2D when no cell is a
/// volume and every z is 0.
/// Throws InputError naming the file and, for a bad cell, its id: VTK's
/// message when it cannot read the file, a cell type invmap does not read
/// (vertices, polygons, pyramids, polyhedra), a point id out of range, a
/// coordinate that is not finite, a rational weight of a Bezier cell that
/// is not positive and finite, a weights array that is not one value per
/// point, no cells. Arrays with an empty or repeated
/// name, and non-numeric arrays, are skipped.
FieldGeometry ReadVtu(const std::string& path);

}  // namespace invmap::fem
