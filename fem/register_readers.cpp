#include "fem/register_readers.h"

#include "fem/vtu_reader.h"
#include "io/reader_registry.h"

namespace invmap::fem {
namespace {

FieldGeometry ReadVtuFile(const std::string& path, const io::FieldReadOptions&) { return ReadVtu(path); }

}  // namespace

void RegisterFemReaders() {
  io::RegisterGeometryReader({".vtu", nullptr, &ReadVtuFile});
}

}  // namespace invmap::fem
