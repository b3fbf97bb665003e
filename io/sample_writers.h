// Writers for what `invmap generate` produces: geometry files and point clouds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::io {

/// Writes `geometry` as the JSON geometry file of FORMATS.md section 2
/// (bspline, bezier and mesh patches; %.17g numbers so values round-trip).
/// Throws InputError (kind Output) when the file cannot be written or a patch
/// kind has no JSON form (BezierCells: write it as gmsh instead).
void WriteGeometryJson(const Geometry& geometry, const std::string& path);

/// Writes a geometry whose patches are all triangle meshes as one binary
/// little-endian PLY mesh (double vertices, int vertex_indices lists).
void WritePlyMesh(const Geometry& geometry, const std::string& path);

/// Writes a gmsh 4.1 ascii mesh of one element type: `nodes` (x, y, z each),
/// `connectivity` (nodesPerElement 0-based node indices per element, in
/// gmsh's node order), all in one volume entity without physical groups.
void WriteGmshMesh(const std::string& path, const std::vector<double>& nodes, int gmshElementType,
                   int nodesPerElement, int elementDim, const std::vector<std::int64_t>& connectivity);

/// Writes `count` points (`dim` interleaved coordinates each) by extension:
/// .xyz/.txt (space separated), .csv (header x,y(,z)), .npy (float64, (N, dim)),
/// .ply (binary little endian, double x y (z)). %.17g in text formats.
void WritePoints(const std::string& path, const double* xyz, std::size_t count, int dim);

}  // namespace invmap::io
