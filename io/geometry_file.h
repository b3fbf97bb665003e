// Geometry input by file extension.
#pragma once

#include <string>

#include "invmap/invmap.h"
#include "io/geometry_source.h"

namespace invmap::io {

/// Reads any supported geometry file, chosen by its extension (case-insensitive):
///  - .json: the invmap geometry file (docs/formats.md section 2, ReadGeometryJson);
///  - .obj, .stl, .off: triangle and quad meshes (ReadMeshFile);
///  - .ply: polygon meshes (ReadPlyMesh);
///  - .msh: gmsh meshes, linear and high-order (ReadGmsh);
///  - the extensions other targets register (io/reader_registry.h): VTK
///    .vtu, Exodus .exo and .e, Cubit's .bext, .bxt and Bezier extraction
///    JSON (fem/register_readers.h), consulted first.
/// Throws InputError naming the file (and, for text formats, the line) for a
/// missing, unreadable or malformed file, and for an unknown extension (the
/// message lists the supported ones). `source`, when not null, receives
/// where the patches' parts were read (the readers that record them: .json,
/// and the vertices of .obj, .off and ASCII .stl),
/// so that a problem Manifold::Build finds names the file and line:
///   io::GeometrySource source;
///   const Geometry geometry = io::ReadGeometryFile(path, &source);
///   BuildResult built = Manifold::Build(geometry);
///   source.Check(built.problem);  // throws InputError "g.json:12: patches[3]..."
Geometry ReadGeometryFile(const std::string& path, GeometrySource* source = nullptr);

}  // namespace invmap::io
