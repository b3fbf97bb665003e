// Geometry input by file extension, and the whole-file reads the geometry
// readers share.
#pragma once

#include <iosfwd>
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

/// The whole content of the file at `path`, bytes as stored. Throws InputError
/// when the path does not exist, is a directory or cannot be read; an empty
/// file gives an empty string (each format decides what that means).
std::string ReadWholeFile(const std::string& path);

/// The rest of `in`, bytes as stored. Throws InputError naming
/// `nameForMessages` when the stream fails before its end.
std::string ReadWholeStream(std::istream& in, const std::string& nameForMessages);

}  // namespace invmap::io
