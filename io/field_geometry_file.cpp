#include "io/field_geometry_file.h"

#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"

namespace invmap::io {

FieldGeometry ReadGeometryWithFields(const std::string& path, const FieldReadOptions& options) {
  FieldGeometry out;
  if (const RegisteredReader* reader = FindRegisteredReader(path)) {
    out = reader->read(path, options);
  } else if (LowerExtension(path) == ".msh") {
    out = ReadGmshWithFields(path);
  } else {
    out.geometry = ReadGeometryFile(path);
  }
  // A reader's own bug, not the file's fault, would show here; still a
  // message rather than a crash in the probe.
  if (std::string problem = CheckFields(out.geometry, out.fields); !problem.empty()) throw InputError(path, 0, problem);
  return out;
}

}  // namespace invmap::io
