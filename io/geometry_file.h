// Geometry input by file extension.
#pragma once

#include <string>

#include "invmap/invmap.h"

namespace invmap::io {

/// Reads any supported geometry file, chosen by its extension (case-insensitive):
///  - .json: the invmap geometry file (FORMATS.md section 2, ReadGeometryJson);
///  - .obj, .stl, .off: triangle and quad meshes (ReadMeshFile);
///  - .ply: polygon meshes (ReadPlyMesh);
///  - .msh: gmsh meshes, linear and high-order (ReadGmsh);
///  - the extensions other targets register (io/reader_registry.h): VTK
///    .vtu, Exodus .exo and .e, Cubit's .bext, .bxt and Bezier extraction
///    JSON (fem/register_readers.h), consulted first.
/// Throws InputError naming the file (and, for text formats, the line) for a
/// missing, unreadable or invalid file, and for an unknown extension (the
/// message lists the supported ones).
Geometry ReadGeometryFile(const std::string& path);

}  // namespace invmap::io
