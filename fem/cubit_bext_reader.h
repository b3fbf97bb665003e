// Coreform Cubit's LS-DYNA Bezier extraction files ("B E X T 2.0", the
// geometry files of LS-DYNA's *IGA_INCLUDE_BEZIER; Cubit writes them with
// `export uspline ... bext`).
#pragma once

#include <istream>
#include <string>

#include "invmap/fields.h"

namespace invmap::fem {

/// Reads the ASCII form: the line "B E X T 2.0", then per patch its header
/// (patch id, control point count, element count, coefficient vector
/// count, weight flag), one line per control point (x y z w: Cartesian
/// coordinates and weight, used when the flag is 1), the number of element
/// blocks, one header line per block (element type, element count, control
/// points and coefficient vectors per element, then one degree per
/// parametric direction: 1, 2 or 3 of them), each element's control point
/// ids and then its coefficient vector ids (1-based, lines of at most 10),
/// the number of dense and of sparse coefficient vector blocks, one line
/// (vector count, length) per dense block, and the vectors' components
/// (lines of at most 5, each vector on new lines). Lines starting with "$#"
/// are comments. Element type 1 is the only one read (tensor-product Bezier
/// elements: curves, quadrilaterals, hexahedra by the number of degrees;
/// Bernstein coefficients first direction fastest); sparse blocks and the
/// binary form are refused. One BezierCells patch per file patch, its
/// elements in file order (extraction_cells.h). No fields. Throws
/// InputError naming the file and line.
FieldGeometry ReadCubitBext(const std::string& path);
FieldGeometry ReadCubitBext(std::istream& in, const std::string& name);

}  // namespace invmap::fem
