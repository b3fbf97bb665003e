// Coreform Cubit's Bezier extraction JSON (`export uspline ... json`), in the
// form Cubit writes today ("the current json format" of its manual).
#pragma once

#include <istream>
#include <string>

#include "invmap/fields.h"

namespace invmap::fem {

/// True when the JSON file at `path` is Cubit's (its first key is one of
/// Cubit's: patch_id, dim, num_elems, is_rational, nodes, elements,
/// coefficients, ..., or of the new format's control_points, elements,
/// extraction_coefficients, cell_sets), not invmap's geometry file. Reads
/// the first bytes only; never throws.
bool LooksLikeCubitJson(const std::string& path);

/// Reads Cubit's current Bezier extraction JSON: "nodes" (x, y, z, w per
/// control point: Cartesian coordinates and weight, as in Cubit's LS-DYNA
/// export, of which this is the JSON version; the weights are used when
/// "is_rational" is true), "elements" with "element_block_info" (per block:
/// "element_type", "num_elems", "num_nodes", "num_coefficient_vectors",
/// "deg_s", "deg_t", "deg_u", -1 for an unused direction) and
/// "element_blocks" (per element, in block order: "us_cid", "node_ids",
/// "coeff_vector_ids", 0-based), "coefficients" with
/// "dense_coefficient_vectors" (each {"components": [...]}), and
/// "block_elem_map" (Cubit's blocks: "block_id", "block_name", "elem_ids",
/// the elements' us_cid). One BezierCells patch per block of block_elem_map
/// (cells in elem_ids order), or one patch of every element in file order
/// when the map is absent or empty. Elements are tensor-product Bezier
/// curves, quadrilaterals or hexahedra by their number of degrees
/// (extraction_cells.h). The new format (control_points,
/// extraction_coefficients, cell_sets) is refused: its fields are not
/// defined in the manual available to us. Sparse coefficient vectors are
/// refused. No fields. Throws InputError naming the file, the line of a
/// syntax error, or the JSON path of a bad value.
FieldGeometry ReadCubitJson(const std::string& path);
FieldGeometry ReadCubitJson(std::istream& in, const std::string& name);

}  // namespace invmap::fem
