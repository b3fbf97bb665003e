// libFuzzer target: the finite-element and isogeometric readers on
// arbitrary bytes (Cubit's LS-DYNA BEXT and JSON, gmsh $NodeData, VTU
// through VTK, Exodus through the Exodus library). A reader may accept the
// input or throw io::InputError; anything else is a bug. The first byte
// chooses the reader; VTU and Exodus, which VTK and the Exodus library read
// from files only, go through a scratch file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "fem/cubit_bext_reader.h"
#include "fem/cubit_json_reader.h"
#include "fem/exodus_reader.h"
#include "fem/vtu_reader.h"
#include "invmap/fields.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"

namespace {

/// `bytes` in a scratch file named with `extension`; its path.
std::string ScratchFile(const std::string& bytes, const char* extension) {
  const std::string path = "/tmp/invmap_fuzz_fem_" + std::to_string(::getpid()) + extension;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    invmap::FieldGeometry model;
    switch (data[0] % 5) {
      case 0: {
        std::istringstream in(bytes);
        model = invmap::fem::ReadCubitBext(in, "fuzz.bext");
        break;
      }
      case 1: {
        std::istringstream in(bytes);
        model = invmap::fem::ReadCubitJson(in, "fuzz.json");
        break;
      }
      case 2: {
        std::istringstream in(bytes);
        model = invmap::io::ReadGmshWithFields(in, "fuzz.msh");
        break;
      }
      case 3:
        model = invmap::fem::ReadVtu(ScratchFile(bytes, ".vtu"));
        break;
      default:
        model = invmap::fem::ReadExodus(ScratchFile(bytes, ".exo"), {});
        break;
    }
    // What a reader accepts must fit its fields and build or be rejected.
    if (!invmap::CheckFields(model.geometry, model.fields).empty()) __builtin_trap();
    invmap::BuildResult built = invmap::Manifold::Build(model.geometry);
    (void)built;
  } catch (const invmap::io::InputError&) {
  }
  return 0;
}
