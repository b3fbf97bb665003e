// invmap.read_points: the points of any file the command reads (text, PLY,
// npy, LAS, PCD) as an (N, dim) float64 array, through the same streaming
// readers, so a LAS or PCD scan reaches Manifold.invert without another
// library.
#include "python/point_files_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/point_reader.h"
#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

py::array_t<double> ReadPoints(const std::string& path, std::optional<int> dim) {
  if (dim && *dim != 2 && *dim != 3) throw InputError("dim: " + std::to_string(*dim) + ", expected 2 or 3");
  std::vector<double> xyz;
  int columns = 0;
  {
    py::gil_scoped_release noGil;
    try {
      io::PointReadOptions options;
      options.forcedDim = dim.value_or(0);
      options.keepRaw = false;
      const auto reader = io::OpenPointReader(path, options);
      columns = reader->dim();
      io::PointChunk chunk;
      while (reader->ReadChunk(io::kDefaultChunkPoints, &chunk)) xyz.insert(xyz.end(), chunk.xyz.begin(), chunk.xyz.end());
    } catch (const io::InputError& e) {
      // A file that cannot be opened at all is an OSError, a bad one a ValueError.
      std::error_code error;
      if (!std::filesystem::is_regular_file(path, error)) throw FileError(e.what());
      throw InputError(e.what());
    }
  }
  const std::size_t rows = xyz.size() / static_cast<std::size_t>(columns);
  py::array_t<double> out({rows, static_cast<std::size_t>(columns)});
  if (!xyz.empty()) std::memcpy(out.mutable_data(), xyz.data(), xyz.size() * sizeof(double));
  return out;
}

}  // namespace

void RegisterPointFiles(py::module_& m) {
  m.def("read_points", &ReadPoints, py::arg("path"), py::arg("dim") = py::none(), R"doc(
The points of a point file as an (N, dim) float64 array, in file order:
.xyz/.txt/.csv, .ply, .npy, .las (LAS 1.0 to 1.4, coordinates scaled and
offset as the header says) or .pcd (ascii, binary, binary_compressed), read
as `invmap invert` reads them.

dim: 2 or 3 to take that many coordinates (a 2D geometry's points); None
detects it from the file (LAS: 3; PCD and PLY: 3 when there is a z).

Raises InputError (naming the file and, for text, the line) for a malformed
file or a compressed .laz, FileError when the file cannot be opened.
)doc");
}

}  // namespace invmap::python
