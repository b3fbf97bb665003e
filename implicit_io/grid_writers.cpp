#include "implicit_io/grid_writers.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "implicit_io/text_output.h"
#include "io/file_io.h"

namespace invmap::io {
namespace {

/// Throws std::invalid_argument when the grid's arrays or the names disagree in size.
void CheckGrid(const implicit::Grid& grid, const std::vector<std::string>& functionNames) {
  const implicit::SimplexMesh& mesh = grid.mesh;
  if (mesh.dimension != 2 && mesh.dimension != 3) {
    throw std::invalid_argument("grid dimension " + std::to_string(mesh.dimension) + ", expected 2 or 3");
  }
  if (mesh.vertices.size() % 3 != 0) throw std::invalid_argument("grid vertices: length not a multiple of 3");
  if (mesh.cells.size() % static_cast<std::size_t>(mesh.dimension + 1) != 0) {
    throw std::invalid_argument("grid cells: length not a multiple of dimension + 1");
  }
  if (grid.functionCount < 0 ||
      grid.values.size() != mesh.numVertices() * static_cast<std::size_t>(grid.functionCount)) {
    throw std::invalid_argument("grid values: " + std::to_string(grid.values.size()) + ", expected " +
                                std::to_string(grid.functionCount) + " per vertex");
  }
  if (!grid.active.empty() && grid.active.size() != mesh.numCells()) {
    throw std::invalid_argument("grid active: " + std::to_string(grid.active.size()) + " flags for " +
                                std::to_string(mesh.numCells()) + " cells");
  }
  if (!functionNames.empty() && functionNames.size() != static_cast<std::size_t>(grid.functionCount)) {
    throw std::invalid_argument(std::to_string(functionNames.size()) + " function names for " +
                                std::to_string(grid.functionCount) + " functions");
  }
}

/// "f<i> <name>" (or "f<i>"), the label of function i's data in the grid files.
std::string FunctionLabel(const std::vector<std::string>& functionNames, int i) {
  std::string label = "f" + std::to_string(i);
  if (!functionNames.empty() && !functionNames[static_cast<std::size_t>(i)].empty()) {
    label += " " + functionNames[static_cast<std::size_t>(i)];
  }
  return label;
}

/// `label` fit for a gmsh string tag: no quotes or line breaks.
std::string GmshString(const std::string& label) {
  std::string s = label;
  for (char& c : s) {
    if (c == '"') c = '\'';
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  return "\"" + s + "\"";
}

/// `text` escaped for an XML attribute value.
std::string XmlAttribute(const std::string& text) {
  std::string s;
  for (const char c : text) {
    switch (c) {
      case '&':
        s += "&amp;";
        break;
      case '<':
        s += "&lt;";
        break;
      case '>':
        s += "&gt;";
        break;
      case '"':
        s += "&quot;";
        break;
      default:
        s += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return s;
}

/// Writes a gmsh $NodeData or $ElementData section: `count` values,
/// value(i) for tag i + 1.
template <class ValueAt>
void WriteGmshData(AtomicOutput& out, const char* section, const std::string& label, std::size_t count,
                   ValueAt valueAt) {
  out.Write(std::string("$") + section + "\n1\n" + GmshString(label) + "\n1\n0\n3\n0\n1\n" + std::to_string(count) +
            "\n");
  for (std::size_t i = 0; i < count; ++i) {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutInteger(start, static_cast<std::int64_t>(i + 1));
    *p++ = ' ';
    p = PutDouble(p, valueAt(i));
    *p++ = '\n';
    out.Advance(static_cast<std::size_t>(p - start));
  }
  out.Write(std::string("$End") + section + "\n");
}

/// Writes one appended VTK data block: its byte count (UInt64), then
/// `count` values of type T, value(i) each, little endian.
template <class T, class ValueAt>
void WriteVtkBlock(AtomicOutput& out, std::size_t count, ValueAt valueAt) {
  char header[8];
  StoreLittleEndian<std::uint64_t>(header, static_cast<std::uint64_t>(count) * sizeof(T));
  out.Write(header, sizeof header);
  constexpr std::size_t kChunk = std::size_t{1} << 14;
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t m = std::min(kChunk, count - start);
    char* p = out.Reserve(m * sizeof(T));
    for (std::size_t i = 0; i < m; ++i) StoreLittleEndian<T>(p + i * sizeof(T), valueAt(start + i));
    out.Advance(m * sizeof(T));
  }
}

}  // namespace

void WriteGridMsh(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path) {
  CheckGrid(grid, functionNames);
  const implicit::SimplexMesh& mesh = grid.mesh;
  const int dim = mesh.dimension;
  const std::size_t per = static_cast<std::size_t>(dim + 1);
  const std::size_t numVertices = mesh.numVertices(), numCells = mesh.numCells();
  const double* xyz = mesh.vertices.data();

  implicit::Vec3 lo = {0, 0, 0}, hi = {0, 0, 0};
  for (std::size_t v = 0; v < numVertices; ++v) {
    for (int a = 0; a < 3; ++a) {
      const double x = xyz[3 * v + a];
      lo[a] = v == 0 ? x : std::min(lo[a], x);
      hi[a] = v == 0 ? x : std::max(hi[a], x);
    }
  }

  AtomicOutput out(path);
  out.Write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n");
  out.Write(dim == 3 ? "0 0 0 1\n" : "0 0 1 0\n");
  {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutText(start, "1");
    for (const double x : {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]}) {
      *p++ = ' ';
      p = PutDouble(p, x);
    }
    p = PutText(p, " 0 0\n$EndEntities\n");
    out.Advance(static_cast<std::size_t>(p - start));
  }

  const std::string nv = std::to_string(numVertices), nc = std::to_string(numCells), d = std::to_string(dim);
  if (numVertices == 0) {
    out.Write("$Nodes\n0 0 0 0\n$EndNodes\n");
  } else {
    out.Write("$Nodes\n1 " + nv + " 1 " + nv + "\n" + d + " 1 0 " + nv + "\n");
    for (std::size_t v = 0; v < numVertices; ++v) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutInteger(start, static_cast<std::int64_t>(v + 1));
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    for (std::size_t v = 0; v < numVertices; ++v) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutDouble(start, xyz[3 * v]);
      *p++ = ' ';
      p = PutDouble(p, xyz[3 * v + 1]);
      *p++ = ' ';
      p = PutDouble(p, xyz[3 * v + 2]);
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    out.Write("$EndNodes\n");
  }

  if (numCells == 0) {
    out.Write("$Elements\n0 0 0 0\n$EndElements\n");
  } else {
    out.Write("$Elements\n1 " + nc + " 1 " + nc + "\n" + d + " 1 " + (dim == 3 ? "4 " : "2 ") + nc + "\n");
    const std::uint32_t* cells = mesh.cells.data();
    for (std::size_t c = 0; c < numCells; ++c) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutInteger(start, static_cast<std::int64_t>(c + 1));
      for (std::size_t j = 0; j < per; ++j) {
        *p++ = ' ';
        p = PutInteger(p, static_cast<std::int64_t>(cells[c * per + j]) + 1);
      }
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    out.Write("$EndElements\n");
  }

  const std::size_t k = static_cast<std::size_t>(grid.functionCount);
  for (int i = 0; i < grid.functionCount; ++i) {
    const double* values = grid.values.data() + i;
    WriteGmshData(out, "NodeData", FunctionLabel(functionNames, i), numVertices,
                  [&](std::size_t v) { return values[v * k]; });
  }
  if (!grid.active.empty()) {
    WriteGmshData(out, "ElementData", "active", numCells, [&](std::size_t c) { return grid.active[c] ? 1.0 : 0.0; });
  }
  out.Commit();
}

void WriteGridVtu(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path) {
  CheckGrid(grid, functionNames);
  const implicit::SimplexMesh& mesh = grid.mesh;
  const std::size_t per = static_cast<std::size_t>(mesh.dimension + 1);
  const std::size_t numVertices = mesh.numVertices(), numCells = mesh.numCells();
  const std::size_t k = static_cast<std::size_t>(grid.functionCount);
  const bool hasActive = !grid.active.empty();

  // Offsets of the appended blocks, in writing order: functions, active,
  // points, connectivity, offsets, types; each is an 8-byte count then data.
  std::uint64_t offset = 0;
  const auto next = [&](std::uint64_t bytes) {
    const std::uint64_t at = offset;
    offset += 8 + bytes;
    return std::to_string(at);
  };
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(numVertices) + "\" NumberOfCells=\"" + std::to_string(numCells) + "\">\n";
  xml += "      <PointData>\n";
  for (std::size_t i = 0; i < k; ++i) {
    xml += "        <DataArray type=\"Float64\" Name=\"" +
           XmlAttribute(FunctionLabel(functionNames, static_cast<int>(i))) +
           "\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" + next(8 * numVertices) + "\"/>\n";
  }
  xml += "      </PointData>\n      <CellData>\n";
  if (hasActive) {
    xml += "        <DataArray type=\"UInt8\" Name=\"active\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" +
           next(numCells) + "\"/>\n";
  }
  xml += "      </CellData>\n      <Points>\n";
  xml += "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
         next(24 * numVertices) + "\"/>\n";
  xml += "      </Points>\n      <Cells>\n";
  xml += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"" +
         next(8 * per * numCells) + "\"/>\n";
  xml += "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" + next(8 * numCells) +
         "\"/>\n";
  xml += "        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" + next(numCells) + "\"/>\n";
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  AtomicOutput out(path);
  out.Write(xml);
  for (std::size_t i = 0; i < k; ++i) {
    const double* values = grid.values.data() + i;
    WriteVtkBlock<double>(out, numVertices, [&](std::size_t v) { return values[v * k]; });
  }
  if (hasActive) {
    WriteVtkBlock<std::uint8_t>(out, numCells,
                                [&](std::size_t c) { return static_cast<std::uint8_t>(grid.active[c] ? 1 : 0); });
  }
  WriteVtkBlock<double>(out, 3 * numVertices, [&](std::size_t i) { return mesh.vertices[i]; });
  WriteVtkBlock<std::int64_t>(out, per * numCells, [&](std::size_t i) { return std::int64_t{mesh.cells[i]}; });
  WriteVtkBlock<std::int64_t>(out, numCells,
                              [&](std::size_t c) { return static_cast<std::int64_t>((c + 1) * per); });
  const std::uint8_t cellType = mesh.dimension == 3 ? 10 : 5;  // VTK_TETRA, VTK_TRIANGLE.
  WriteVtkBlock<std::uint8_t>(out, numCells, [&](std::size_t) { return cellType; });
  out.Write("\n  </AppendedData>\n</VTKFile>\n");
  out.Commit();
}

void WriteGridStats(const implicit::GridStats& stats, const std::string& path) {
  nlohmann::ordered_json json;
  json["cells"] = stats.cells;
  json["active_cells"] = stats.activeCells;
  json["vertices"] = stats.vertices;
  json["min_radius_ratio"] = stats.minRadiusRatio;
  json["min_radius_ratio_active"] = stats.minRadiusRatioActive;
  json["seconds"] = stats.seconds;
  AtomicOutput out(path);
  out.Write(json.dump(2) + "\n");
  out.Commit();
}

}  // namespace invmap::io
