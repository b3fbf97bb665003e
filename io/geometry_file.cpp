#include "io/geometry_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <system_error>

#include "io/file_io.h"
#include "io/geometry_json.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/mesh_readers.h"
#include "io/ply_mesh.h"

namespace invmap::io {

Geometry ReadGeometryFile(const std::string& path, GeometrySource* source) {
  const std::string ext = LowerExtension(path);
  if (ext == ".json") return ReadGeometryJson(path, source);
  if (ext == ".obj" || ext == ".stl" || ext == ".off") return ReadMeshFile(path, source);
  if (source) *source = GeometrySource(path);
  if (ext == ".ply") return ReadPlyMesh(path);
  if (ext == ".msh") return ReadGmsh(path);
  throw InputError(
      path, 0,
      (ext.empty() ? std::string("no file extension") : "unknown geometry file extension \"" + ext + "\"") +
          " (supported: .json, .obj, .stl, .off, .ply, .msh)");
}

std::string ReadWholeFile(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw InputError(path, 0, "cannot open: no such file");
  if (ec) throw InputError(path, 0, "cannot open: " + ec.message());
  // Opening a directory succeeds on Linux and only the first read fails, so
  // say what is wrong before that.
  if (std::filesystem::is_directory(status)) throw InputError(path, 0, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  return ReadWholeStream(in, path);
}

std::string ReadWholeStream(std::istream& in, const std::string& nameForMessages) {
  std::string bytes;
  // Seekable streams (files) are sized once, which spares the copies of
  // growing a 100 MB string.
  const std::istream::pos_type start = in.tellg();
  if (start != std::istream::pos_type(-1)) {
    if (in.seekg(0, std::ios::end)) {
      const std::istream::pos_type end = in.tellg();
      if (end != std::istream::pos_type(-1) && end >= start) bytes.reserve(static_cast<std::size_t>(end - start));
    }
    in.clear();
    in.seekg(start);
  }
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(nameForMessages, 0, "read error after " + std::to_string(bytes.size()) + " bytes");
  return bytes;
}

}  // namespace invmap::io
