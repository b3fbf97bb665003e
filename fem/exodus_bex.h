// Coreform Cubit's Exodus Bezier extraction files (docs/fields.md, "Cubit
// Bezier extraction").
#pragma once

#include <vector>

#include "fem/exodus_file.h"
#include "invmap/fields.h"

namespace invmap::fem {

/// Reads an Exodus file whose element blocks are Cubit's Bezier extraction
/// (element types BEX_CURVE, BEX_QUAD, BEX_HEX): the nodes are the spline's
/// control points, stored multiplied by their weight (the nodal attribute
/// bex_weight; weight 1 without it); each element's connectivity lists its
/// n control points and then the n coefficient vectors (both 1-based) of
/// the extraction operator's rows; the block attribute bex_elem_degrees
/// gives the degrees; the blob bex_cv_blob holds the coefficient vectors
/// (attribute bex_dense_cv_info: pairs of vector count and length; variable
/// bex_dense_cv_blocks: the vectors one after the other). One patch per
/// block, cells in block order (extraction_cells.h builds them). The
/// simplex types BEX_TRIANGLE, BEX_TETRA and BEX_WEDGE are refused: the
/// order of their Bernstein coefficients is not documented. No fields.
FieldGeometry ReadExodusBezierExtraction(const ExodusFile& file, const std::vector<ExodusBlock>& blocks);

}  // namespace invmap::fem
