// The initial grid of `invmap grid`: a linear tetrahedron or triangle mesh
// from a gmsh file.
#pragma once

#include <string>

#include "invmap/implicit.h"

namespace invmap::io {

/// Reads an initial grid from a gmsh MSH 4.1 file (io::ReadGmsh): linear
/// tetrahedra (3D), or linear triangles when every node has z == 0 (2D).
/// Lower-dimensional elements (lines; triangles in a tetrahedral mesh) are
/// boundary tags and are skipped; points are skipped by ReadGmsh. Vertices
/// with exactly equal coordinates are merged into one (ReadGmsh gives each
/// cell its own copies), in order of first use. Every cell is made
/// positively oriented (two vertices are swapped when its signed volume or
/// area is negative).
///
/// Throws InputError naming the file for everything ReadGmsh rejects, for an
/// element of another type or order (the message names it), for a file with
/// no tetrahedra or triangles, for more than 2^32 - 1 vertices, and for a
/// cell of zero volume (area), naming the cell's 0-based index among the
/// kept cells.
implicit::SimplexMesh ReadSimplexMeshMsh(const std::string& path);

}  // namespace invmap::io
