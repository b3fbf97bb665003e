#include "io/geometry_file.h"

#include "io/file_io.h"
#include "io/geometry_json.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/mesh_readers.h"
#include "io/ply_mesh.h"
#include "io/reader_registry.h"

namespace invmap::io {

Geometry ReadGeometryFile(const std::string& path, GeometrySource* source) {
  const std::string ext = LowerExtension(path);
  if (const RegisteredReader* reader = FindRegisteredReader(path)) {
    if (source) *source = GeometrySource(path);
    return reader->read(path, {}).geometry;
  }
  if (ext == ".json") return ReadGeometryJson(path, source);
  // The other readers check every value Manifold::Build would (their own
  // errors name the line): their geometry's source records no lines.
  if (source) *source = GeometrySource(path);
  if (ext == ".obj" || ext == ".stl" || ext == ".off") return ReadMeshFile(path);
  if (ext == ".ply") return ReadPlyMesh(path);
  if (ext == ".msh") return ReadGmsh(path);
  throw InputError(
      path, 0,
      (ext.empty() ? std::string("no file extension") : "unknown geometry file extension \"" + ext + "\"") +
          " (supported: .json, .obj, .stl, .off, .ply, .msh" +
          (RegisteredExtensions().empty() ? std::string() : ", " + RegisteredExtensions()) + ")");
}

}  // namespace invmap::io
