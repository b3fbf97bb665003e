#include "cad/register_readers.h"

#include <string>

#include "cad/model.h"
#include "io/input_error.h"
#include "io/reader_registry.h"

namespace invmap::cad {
namespace {

FieldGeometry ReadCadFile(const std::string& path, const io::FieldReadOptions&) {
  LoadResult loaded = Model::Load(path);
  if (!loaded.error.empty()) throw io::InputError(path, 0, loaded.error);
  FieldGeometry model;
  model.geometry = loaded.model->geometry();
  return model;
}

}  // namespace

void RegisterCadReaders() {
  for (const char* extension : {".step", ".stp", ".iges", ".igs", ".brep"}) {
    io::RegisterGeometryReader({extension, nullptr, &ReadCadFile});
  }
}

}  // namespace invmap::cad
