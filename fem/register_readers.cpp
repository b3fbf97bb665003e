#include "fem/register_readers.h"

#include "fem/cubit_bext_reader.h"
#include "fem/cubit_json_reader.h"
#include "fem/exodus_reader.h"
#include "fem/vtu_reader.h"
#include "io/reader_registry.h"

namespace invmap::fem {
namespace {

FieldGeometry ReadVtuFile(const std::string& path, const io::FieldReadOptions&) { return ReadVtu(path); }
FieldGeometry ReadBextFile(const std::string& path, const io::FieldReadOptions&) { return ReadCubitBext(path); }
FieldGeometry ReadCubitJsonFile(const std::string& path, const io::FieldReadOptions&) { return ReadCubitJson(path); }

}  // namespace

void RegisterFemReaders() {
  io::RegisterGeometryReader({".vtu", nullptr, &ReadVtuFile});
  io::RegisterGeometryReader({".exo", nullptr, &ReadExodus});
  io::RegisterGeometryReader({".e", nullptr, &ReadExodus});
  io::RegisterGeometryReader({".bext", nullptr, &ReadBextFile});
  io::RegisterGeometryReader({".bxt", nullptr, &ReadBextFile});
  io::RegisterGeometryReader({".json", &LooksLikeCubitJson, &ReadCubitJsonFile});
}

}  // namespace invmap::fem
