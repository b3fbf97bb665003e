// Exodus II files (.exo, .e) through the Exodus library: Lagrange and
// serendipity elements with their nodal variables, and Coreform Cubit's
// Exodus Bezier extraction (docs/fields.md).
#pragma once

#include <string>

#include "invmap/fields.h"
#include "io/reader_registry.h"

namespace invmap::fem {

/// Reads an Exodus II file: one BezierCells patch per element block, in the
/// file's block order, cells in block order (a cell's index is the
/// element's position in its block, from 0). Element types: BAR2/3, TRI3/6
/// (and TRISHELL), QUAD4/8/9 (and SHELL4/8/9), TET4/10, HEX8/20/27,
/// WEDGE6/15, by Exodus's node numbering; serendipity elements (QUAD8,
/// HEX20, WEDGE15) become the complete quadratic Bezier cell their space
/// determines (exodus_elements.h). Reported parameters are the reference
/// coordinates in [0, 1] (docs/formats.md section 1) with node 1 at the
/// origin. Nodal variables at time step options.timeStep (1-based; 0: the
/// last) become scalar node fields under their own names (Exodus stores a
/// vector's components as separate variables, e.g. displ_x, displ_y).
/// A file whose blocks are Cubit's Bezier extraction (BEX_CURVE, BEX_QUAD,
/// BEX_HEX) is read by ReadExodusBezierExtraction. Throws InputError naming
/// the file and the block (and element) at fault: an unreadable file, a type
/// invmap does not read, a node id out of range, a time step the file does
/// not have.
FieldGeometry ReadExodus(const std::string& path, const io::FieldReadOptions& options);

}  // namespace invmap::fem
