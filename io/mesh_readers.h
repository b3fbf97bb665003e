// Readers of triangle and quad surface meshes: OBJ, STL and OFF. (PLY meshes
// are read by io/ply_mesh.h, gmsh meshes by io/gmsh_reader.h.)
//
// Every reader returns a Geometry of dimension 3 with one Mesh patch per cell
// type present: the tri patch first (patch 0), then the quad patch if the
// file has quads. Cells are numbered within their patch in the order the
// file lists faces of that type; a polygon of n > 4 vertices becomes
// triangles at its place among the triangles (AppendPolygon). Each patch
// carries every vertex of the file, in file order (STL: in order of first
// appearance after merging), so vertex
// indices are the same in both patches. Reported parameters are the reference
// coordinates of the tri (s, t) or quad (s, t) cell (docs/formats.md section 2),
// with the face's vertices in file order as the cell's vertices 0, 1, 2 (, 3).
//
// A file without any face is an error (it is most likely a point cloud), as
// is any coordinate that is not a finite number or lies outside [-1e100,
// 1e100]. Every error is an InputError naming the file and, for text
// formats, the 1-based line. Files are streamed, a line (or a binary
// record) at a time: memory is that of the mesh read, whatever the file's
// size, and an endless input fails at its first overlong line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::io {

/// Appends the triangles of a face of n >= 3 vertex indices (n != 4: a
/// quad is a cell of its own) to `tris`, 3 indices each: a triangle as it
/// is; a polygon as the fan (v0, v[i], v[i+1]), i = 1 .. n - 2, in that
/// order, without the fan triangles that repeat a vertex index (no area)
/// or an earlier one: a face of 3 million indices of a few vertices gave 3
/// million triangles, it now gives as many as it has distinct ones. The
/// segment a left-out triangle stands for is kept as one triangle
/// (v0, x, x) after the fan, once per vertex x, only where no kept
/// triangle has it as an edge, so the face covers the same points. Every
/// reader of polygon meshes (OBJ, OFF, PLY) shares it.
void AppendPolygon(const std::int64_t* v, std::size_t n, std::vector<std::int64_t>* tris);

/// Reserves room in `tris` for the triangles of `faces` faces a header
/// declares, but for no more than `bytes` of the file can hold at
/// `minTriangleBytes` a triangle face (a header's count is only a claim:
/// the reservation stays within a few times the file's size); nothing when
/// the size is unknown (bytes < 0) or once `tris` has room. A face of more
/// than 3 vertices that becomes several triangles grows the array as
/// usual.
void ReserveTriangles(std::int64_t faces, std::int64_t bytes, std::int64_t minTriangleBytes,
                      std::vector<std::int64_t>* tris);

/// Reads the mesh at `path`, chosen by its extension (.obj, .stl, .off; case
/// insensitive). Throws InputError for an unknown extension or a bad file.
Geometry ReadMeshFile(const std::string& path);

/// Wavefront OBJ: `v x y z [w]` lines (further values such as w or vertex
/// colours are ignored) and `f` lines with v, v/vt, v/vt/vn or v//vn
/// references, 1-based or negative (relative: -1 is the last vertex defined
/// so far). Other statements (vt, vn, g, o, s, usemtl, l, curves, ...) and
/// `#` comments are ignored.
Geometry ReadObj(std::istream& in, const std::string& nameForMessages);

/// STL, binary or ASCII. A file is binary exactly when its size is
/// 84 + 50 x (the triangle count at byte 80), whatever its first bytes say
/// (binary headers often begin with "solid"); decided from the header and
/// the size before the rest is read. A stream of unknown size (a pipe) is
/// ASCII when it starts with "solid", else binary, and must then end right
/// after the triangles its header counts. Identical vertices (bit for bit,
/// with -0 equal to 0) are merged so that triangles share vertices; vertex
/// order is order of first appearance. Binary problems name no line; ASCII
/// ones do. Facet normals are ignored (writers put NaN there for degenerate
/// triangles).
Geometry ReadStl(std::istream& in, const std::string& nameForMessages);

/// OFF: an optional `OFF` header (also COFF, NOFF, CNOFF, STOFF and the like,
/// whose extra per-vertex values are ignored), the vertex, face and edge
/// counts, one vertex per line, then one face per line as `n i0 .. i(n-1)`
/// with 0-based indices (trailing face colours are ignored). `#` starts a
/// comment. Counts are checked against the file size before anything is
/// allocated.
Geometry ReadOff(std::istream& in, const std::string& nameForMessages);

}  // namespace invmap::io
