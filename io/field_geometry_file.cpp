#include "io/field_geometry_file.h"

#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"

namespace invmap::io {

FieldGeometry ReadGeometryWithFields(const std::string& path, const FieldReadOptions& options,
                                     GeometrySource* source) {
  FieldGeometry out;
  const RegisteredReader* reader = FindRegisteredReader(path);
  if (reader != nullptr || LowerExtension(path) == ".msh") {
    // These readers check every value themselves: no lines to record.
    if (source) *source = GeometrySource(path);
    out = reader != nullptr ? reader->read(path, options) : ReadGmshWithFields(path);
  } else {
    out.geometry = ReadGeometryFile(path, source);
  }
  // A reader's own bug, not the file's fault, would show here; still a
  // message rather than a crash in the probe.
  if (std::string problem = CheckFields(out.geometry, out.fields); !problem.empty()) throw InputError(path, 0, problem);
  return out;
}

}  // namespace invmap::io
