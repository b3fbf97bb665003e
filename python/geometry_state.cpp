#include "python/geometry_state.h"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "python/byte_state.h"

namespace invmap::python {
namespace {

/// "invmapG" plus the format version: a later version may add fields, and an
/// old reader must then refuse rather than misread.
constexpr char kMagic[8] = {'i', 'n', 'v', 'm', 'a', 'p', 'G', '2'};  // G2: patches carry chartControlPoints
/// Read back as another value when the writer had the other byte order.
constexpr std::uint32_t kByteOrderMark = 0x01020304u;

}  // namespace

std::string SerializeGeometry(const Geometry& geometry) {
  std::string out(kMagic, sizeof(kMagic));
  StateWriter w(&out);
  w.Value(kByteOrderMark);
  w.Value<std::int32_t>(geometry.dimension);
  w.Value<std::uint64_t>(geometry.patches.size());
  for (const Patch& patch : geometry.patches) {
    w.Value(static_cast<std::uint8_t>(patch.kind));
    w.Value(static_cast<std::uint8_t>(patch.cell));
    w.Vector(patch.degrees);
    w.Value<std::uint64_t>(patch.knots.size());
    for (const std::vector<double>& knots : patch.knots) w.Vector(knots);
    w.Vector(patch.counts);
    w.Vector(patch.points);
    w.Vector(patch.weights);
    w.Vector(patch.cells);
    w.Vector(patch.cellTypes);
    w.Vector(patch.cellDegrees);
    w.Vector(patch.cellOffsets);
    w.Vector(patch.chartControlPoints);
  }
  return out;
}

Geometry DeserializeGeometry(const std::string& state) {
  if (state.size() < sizeof(kMagic) || std::memcmp(state.data(), kMagic, sizeof(kMagic)) != 0) {
    throw std::invalid_argument("geometry state: not an invmap geometry of this version");
  }
  StateReader r(state.data() + sizeof(kMagic), state.size() - sizeof(kMagic), "geometry state");
  if (r.Value<std::uint32_t>() != kByteOrderMark) {
    throw std::invalid_argument("geometry state: written on a machine of the other byte order");
  }
  Geometry geometry;
  geometry.dimension = r.Value<std::int32_t>();
  const std::uint64_t numPatches = r.Value<std::uint64_t>();
  for (std::uint64_t p = 0; p < numPatches; ++p) {
    Patch patch;
    const auto kind = r.Value<std::uint8_t>();
    const auto cell = r.Value<std::uint8_t>();
    if (kind > static_cast<std::uint8_t>(Patch::Kind::PouManifold) ||
        cell > static_cast<std::uint8_t>(CellType::Wedge)) {
      throw std::invalid_argument("geometry state: patch " + std::to_string(p) + ": unknown kind or cell type");
    }
    patch.kind = static_cast<Patch::Kind>(kind);
    patch.cell = static_cast<CellType>(cell);
    patch.degrees = r.Vector<int>();
    const std::uint64_t numKnotVectors = r.Value<std::uint64_t>();
    // No reserve: a corrupt count then fails as truncated instead of allocating.
    for (std::uint64_t k = 0; k < numKnotVectors; ++k) patch.knots.push_back(r.Vector<double>());
    patch.counts = r.Vector<int>();
    patch.points = r.Vector<double>();
    patch.weights = r.Vector<double>();
    patch.cells = r.Vector<std::int64_t>();
    patch.cellTypes = r.Vector<CellType>();
    for (CellType type : patch.cellTypes) {
      if (static_cast<std::uint8_t>(type) > static_cast<std::uint8_t>(CellType::Wedge)) {
        throw std::invalid_argument("geometry state: patch " + std::to_string(p) + ": unknown cell type");
      }
    }
    patch.cellDegrees = r.Vector<int>();
    patch.cellOffsets = r.Vector<std::int64_t>();
    patch.chartControlPoints = r.Vector<double>();
    geometry.patches.push_back(std::move(patch));
  }
  if (!r.AtEnd()) throw std::invalid_argument("geometry state: unexpected bytes after the last patch");
  return geometry;
}

}  // namespace invmap::python
