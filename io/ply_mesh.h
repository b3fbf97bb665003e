// Triangle and quad meshes from PLY files as invmap geometries.
#pragma once

#include <istream>
#include <memory>
#include <string>

#include "invmap/invmap.h"

namespace invmap::io {

/// Reads a polygon mesh from a PLY file (any of the three formats).
///
/// Vertices: element "vertex" with scalar properties x, y and optionally z
/// (any numeric type); the geometry's dimension is 3, or 2 when the
/// vertices have no z. Faces: element "face" with a list property
/// "vertex_indices" (or "vertex_index") of 0-based vertex indices. Other
/// elements and properties are ignored.
///
/// Patches (kind Mesh; both hold all the vertices):
///  - patch 0: tri cells: every triangle, plus the fan triangulation
///    (v0, v[i], v[i+1]), i = 1..n-2, of every face with n > 4 vertices,
///    in face order (a fan is right for convex faces only);
///  - patch 1 (patch 0 when there are no tri cells): the quad cells, in face
///    order; the PLY vertex cycle is the finite-element quad order.
/// A cell index is therefore not the PLY face index when faces are mixed.
///
/// Throws InputError (naming the file, and the line for ascii files) for
/// unreadable or malformed files, a missing vertex or face element, a face
/// with fewer than 3 vertices, or a vertex index out of range.
Geometry ReadPlyMesh(const std::string& path);

/// As ReadPlyMesh(path), reading `stream` (owned), named `name` in messages.
Geometry ReadPlyMesh(std::unique_ptr<std::istream> stream, const std::string& name);

}  // namespace invmap::io
