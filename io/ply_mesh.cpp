#include "io/ply_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "io/input_error.h"
#include "io/mesh_readers.h"
#include "io/ply.h"
#include "kernels/cell_shape.h"

namespace invmap::io {
namespace {

/// Index of the scalar property `name` of `element`; throws when missing
/// (unless `optional`, then -1) or when it is a list.
int ScalarProperty(const PlyReader& reader, const PlyElement& element, const char* name, bool optional) {
  const int p = element.FindProperty(name);
  if (p < 0 && !optional) {
    throw InputError(reader.name(), 0, "element '" + element.name + "' has no property '" + name + "'");
  }
  if (p >= 0 && element.properties[static_cast<std::size_t>(p)].isList) {
    throw InputError(reader.name(), 0, "property '" + std::string(name) + "' is a list, expected a number");
  }
  return p;
}

/// Smallest bytes a face record of three vertex indices (list property
/// `indices`) takes: ascii, "3 0 0 0" and its newline; binary, every
/// property at its size, the indices' list with its count and 3 entries,
/// other lists empty.
std::int64_t MinTriangleRecordBytes(const PlyHeader& header, const PlyElement& faces, int indices) {
  if (header.format == PlyFormat::Ascii) return 8;
  std::int64_t bytes = 0;
  for (std::size_t p = 0; p < faces.properties.size(); ++p) {
    const PlyProperty& property = faces.properties[p];
    bytes += PlyTypeSize(property.isList ? property.countType : property.type);
    if (static_cast<int>(p) == indices) bytes += 3 * PlyTypeSize(property.type);
  }
  return bytes;
}

Geometry ReadMesh(PlyReader& reader) {
  const PlyHeader& header = reader.header();
  const int vertexElement = header.FindElement("vertex");
  const int faceElement = header.FindElement("face");
  if (vertexElement < 0) throw InputError(reader.name(), 0, "no 'vertex' element");
  if (faceElement < 0) throw InputError(reader.name(), 0, "no 'face' element (not a mesh)");
  const PlyElement& vertices = header.elements[static_cast<std::size_t>(vertexElement)];
  const PlyElement& faces = header.elements[static_cast<std::size_t>(faceElement)];
  const int px = ScalarProperty(reader, vertices, "x", false);
  const int py = ScalarProperty(reader, vertices, "y", false);
  const int pz = ScalarProperty(reader, vertices, "z", true);
  int pIndices = faces.FindProperty("vertex_indices");
  if (pIndices < 0) pIndices = faces.FindProperty("vertex_index");
  if (pIndices < 0 || !faces.properties[static_cast<std::size_t>(pIndices)].isList) {
    throw InputError(reader.name(), 0, "element 'face' has no list property 'vertex_indices' or 'vertex_index'");
  }
  if (faces.count == 0) throw InputError(reader.name(), 0, "the mesh has no faces");
  const int dim = pz >= 0 ? 3 : 2;

  std::vector<double> points;
  if (reader.countsChecked()) {
    // The reader checked the count against a record of one byte a value
    // (ascii: a digit and a separator per record); an ascii vertex has at
    // least that for each of its properties.
    std::int64_t count = vertices.count;
    if (header.format == PlyFormat::Ascii) {
      count = std::min(count, reader.dataBytes() / (2 * static_cast<std::int64_t>(vertices.properties.size())));
    }
    points.reserve(static_cast<std::size_t>(count) * static_cast<std::size_t>(dim));
  }
  // Reserved at the first triangle, from the faces left (ReserveTriangles).
  std::vector<std::int64_t> tris;
  const std::int64_t minTriangleBytes = MinTriangleRecordBytes(header, faces, pIndices);
  std::vector<std::int64_t> quads;
  std::vector<std::int64_t> polygon;  // the face being read
  PlyRecord record;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    reader.SkipToElement(e);
    if (e == static_cast<std::size_t>(vertexElement)) {
      while (reader.ReadRecord(&record)) {
        for (const int p : {px, py, pz}) {
          if (p < 0) continue;
          const double value = record.Scalar(static_cast<std::size_t>(p));
          // A cell with a NaN corner has no geometry to search.
          if (!std::isfinite(value)) {
            throw InputError(
                reader.name(), reader.line(),
                "vertex " + std::to_string(reader.recordIndex() - 1) + " has a coordinate that is not finite");
          }
          // The engine checks the range again; here the message names the record.
          if (std::abs(value) > kernels::kMaxCoordinate) {
            char text[32];
            std::snprintf(text, sizeof(text), "%.17g", value);
            throw InputError(reader.name(), reader.line(),
                             "vertex " + std::to_string(reader.recordIndex() - 1) + ": coordinate " + text +
                                 " is outside [-1e100, 1e100] (the range invmap supports)");
          }
          points.push_back(value);
        }
      }
    } else if (e == static_cast<std::size_t>(faceElement)) {
      while (reader.ReadRecord(&record)) {
        const std::int64_t face = reader.recordIndex() - 1;
        const std::size_t n = record.ListSize(static_cast<std::size_t>(pIndices));
        const double* list = record.List(static_cast<std::size_t>(pIndices));
        if (n < 3) {
          throw InputError(
              reader.name(), reader.line(),
              "face " + std::to_string(face) + " has " + std::to_string(n) + " vertices (at least 3 needed)");
        }
        std::int64_t index[4];
        const auto vertexAt = [&](std::size_t i) {
          const double v = list[i];
          if (!(v >= 0 && v < static_cast<double>(vertices.count)) || v != std::floor(v)) {
            char text[32];
            std::snprintf(text, sizeof(text), "%.17g", v);
            throw InputError(reader.name(), reader.line(),
                             "face " + std::to_string(face) + ": vertex index " + text + " is not in [0, " +
                                 std::to_string(vertices.count) + ")");
          }
          return static_cast<std::int64_t>(v);
        };
        if (n == 4) {
          for (std::size_t i = 0; i < 4; ++i) index[i] = vertexAt(i);
          quads.insert(quads.end(), index, index + 4);
          continue;
        }
        polygon.clear();
        for (std::size_t i = 0; i < n; ++i) polygon.push_back(vertexAt(i));
        ReserveTriangles(faces.count - face, reader.dataBytes(), minTriangleBytes, &tris);
        AppendPolygon(polygon.data(), n, &tris);
      }
    }
  }

  reader.ExpectEnd();
  Geometry geometry;
  geometry.dimension = dim;
  for (auto* cells : {&tris, &quads}) {
    if (cells->empty()) continue;
    Patch patch;
    patch.kind = Patch::Kind::Mesh;
    patch.cell = cells == &tris ? CellType::Tri : CellType::Quad;
    patch.cells = std::move(*cells);
    geometry.patches.push_back(std::move(patch));
  }
  // Every patch holds all the vertices; only the last takes them by move.
  for (std::size_t i = 0; i + 1 < geometry.patches.size(); ++i) geometry.patches[i].points = points;
  geometry.patches.back().points = std::move(points);
  return geometry;
}

}  // namespace

Geometry ReadPlyMesh(const std::string& path) {
  PlyReader reader(path);
  return ReadMesh(reader);
}

Geometry ReadPlyMesh(std::unique_ptr<std::istream> stream, const std::string& name) {
  PlyReader reader(std::move(stream), name);
  return ReadMesh(reader);
}

}  // namespace invmap::io
