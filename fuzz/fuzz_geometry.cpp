// libFuzzer target: every geometry reader on arbitrary bytes. A reader may
// accept the input or throw io::InputError; anything else (a crash, another
// exception, a sanitizer report, a hang) is a bug. The format is chosen by
// the first byte so one corpus covers all of them.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>

#include "invmap/invmap.h"
#include "io/geometry_json.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/mesh_readers.h"
#include "io/ply_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    invmap::Geometry geometry;
    switch (data[0] % 6) {
      case 0: {
        std::istringstream in(text);
        geometry = invmap::io::ReadGeometryJson(in, "fuzz.json");
        break;
      }
      case 1: {
        std::istringstream in(text);
        geometry = invmap::io::ReadGmsh(in, "fuzz.msh");
        break;
      }
      case 2:
        geometry = invmap::io::ReadPlyMesh(std::make_unique<std::istringstream>(text), "fuzz.ply");
        break;
      case 3: {
        std::istringstream in(text);
        geometry = invmap::io::ReadObj(in, "fuzz.obj");
        break;
      }
      case 4: {
        std::istringstream in(text);
        geometry = invmap::io::ReadStl(in, "fuzz.stl");
        break;
      }
      default: {
        std::istringstream in(text);
        geometry = invmap::io::ReadOff(in, "fuzz.off");
        break;
      }
    }
    // What a reader accepts must build or be rejected with a message.
    invmap::BuildResult built = invmap::Manifold::Build(geometry);
    (void)built;
  } catch (const invmap::io::InputError&) {
  }
  return 0;
}
