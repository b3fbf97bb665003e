#include "python/cad_binding.h"

#include <pybind11/stl.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

/// "invmapC" plus the format version, then the extension's length (one
/// byte), the extension and the file's bytes.
constexpr char kMagic[8] = {'i', 'n', 'v', 'm', 'a', 'p', 'C', '1'};

std::string Extension(const std::string& path) { return std::filesystem::path(path).extension().string(); }

}  // namespace

bool IsCadPath(const std::string& path) { return cad::IsCadFile(path); }

CadSource LoadCad(const std::string& path) {
  cad::LoadResult loaded = cad::Model::Load(path);
  if (!loaded.error.empty()) {
    const std::string message = path + ": " + loaded.error;
    if (loaded.fileError) throw FileError(message);
    throw InputError(message);
  }
  CadSource source;
  source.model = std::move(loaded.model);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const std::string extension = Extension(path);
  source.state.assign(kMagic, sizeof(kMagic));
  source.state += static_cast<char>(extension.size());
  source.state += extension;
  source.state += bytes.str();
  return source;
}

bool IsCadState(const std::string& state) {
  return state.size() >= sizeof(kMagic) && std::memcmp(state.data(), kMagic, sizeof(kMagic)) == 0;
}

CadSource LoadCadState(const std::string& state) {
  if (!IsCadState(state) || state.size() < sizeof(kMagic) + 1) throw InputError("CAD state: not a CAD model's state");
  const std::size_t length = static_cast<unsigned char>(state[sizeof(kMagic)]);
  if (state.size() < sizeof(kMagic) + 1 + length) throw InputError("CAD state: truncated");
  const std::string extension = state.substr(sizeof(kMagic) + 1, length);
  // The readers take paths: the bytes go through a file of this process's own.
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("invmap_cad_" + std::to_string(getpid()) + "_" +
                                      std::to_string(reinterpret_cast<std::uintptr_t>(&state)) + extension);
  {
    std::ofstream out(path, std::ios::binary);
    out.write(state.data() + sizeof(kMagic) + 1 + length,
              static_cast<std::streamsize>(state.size() - sizeof(kMagic) - 1 - length));
  }
  cad::LoadResult loaded = cad::Model::Load(path.string());
  std::filesystem::remove(path);
  if (!loaded.error.empty()) throw InputError("pickled CAD model: " + loaded.error);
  CadSource source;
  source.model = std::move(loaded.model);
  source.state = state;
  return source;
}

py::dict CadInfo(const cad::Model& model) {
  const cad::ModelInfo info = model.Info();
  py::dict bySurface;
  for (const auto& [type, count] : info.facesBySurface) bySurface[py::str(type)] = count;
  py::list openParts;
  for (const std::string& part : info.openParts) openParts.append(part);
  py::dict out;
  out["format"] = info.format;
  out["faces"] = info.faces;
  out["faces_by_surface"] = bySurface;
  out["edges"] = info.edges;
  out["vertices"] = info.vertices;
  out["shells"] = info.shells;
  out["solids"] = info.solids;
  out["open_parts"] = openParts;
  out["approximated_faces"] = info.approximatedFaces;
  out["approximation_tolerance"] = info.approximationTolerance;
  out["approximation_deviation"] = info.approximationDeviation;
  out["model_bounds_lo"] = py::make_tuple(info.boundsLo[0], info.boundsLo[1], info.boundsLo[2]);
  out["model_bounds_hi"] = py::make_tuple(info.boundsHi[0], info.boundsHi[1], info.boundsHi[2]);
  return out;
}

std::vector<double> SignedDistances(const cad::Model& model, const double* xyz, std::size_t count,
                                    const Results& results, int threads) {
  if (const std::string unsupported = model.SignedUnsupported(); !unsupported.empty()) {
    throw InputError("signed: " + unsupported);
  }
  std::vector<double> out(count);
  model.SignDistances(xyz, count, results, out.data(), threads);
  return out;
}

}  // namespace invmap::python
