#include "io/sample_writers.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "io/file_io.h"
#include "io/input_error.h"

namespace invmap::io {
namespace {

const char* CellName(CellType type) {
  static const char* const kNames[] = {"line", "tri", "quad", "tet", "hex", "wedge"};
  return kNames[static_cast<int>(type)];
}

/// Points as a list of [x, y(, z)] lists.
nlohmann::json PointList(const std::vector<double>& flat, int dim) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i + dim <= flat.size(); i += dim) {
    nlohmann::json point = nlohmann::json::array();
    for (int k = 0; k < dim; ++k) point.push_back(flat[i + k]);
    list.push_back(std::move(point));
  }
  return list;
}

void AppendNumber(std::string* out, double value) {
  char text[32];
  const int n = std::snprintf(text, sizeof text, "%.17g", value);
  out->append(text, n);
}

}  // namespace

void WriteGeometryJson(const Geometry& geometry, const std::string& path) {
  nlohmann::json doc;
  doc["format"] = "invmap-geometry";
  doc["version"] = 1;
  doc["dimension"] = geometry.dimension;
  doc["patches"] = nlohmann::json::array();
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    const Patch& patch = geometry.patches[p];
    nlohmann::json j;
    switch (patch.kind) {
      case Patch::Kind::BSpline:
        j["kind"] = "bspline";
        j["degrees"] = patch.degrees;
        j["knots"] = patch.knots;
        j["counts"] = patch.counts;
        j["control_points"] = PointList(patch.points, geometry.dimension);
        break;
      case Patch::Kind::Bezier:
        j["kind"] = "bezier";
        j["cell"] = CellName(patch.cell);
        j["degrees"] = patch.degrees;
        j["control_points"] = PointList(patch.points, geometry.dimension);
        break;
      case Patch::Kind::Mesh: {
        j["kind"] = "mesh";
        j["cell"] = CellName(patch.cell);
        j["vertices"] = PointList(patch.points, geometry.dimension);
        const std::size_t perCell = patch.cell == CellType::Line ? 2
                                    : patch.cell == CellType::Tri ? 3
                                    : patch.cell == CellType::Hex ? 8
                                    : patch.cell == CellType::Wedge ? 6 : 4;
        nlohmann::json cells = nlohmann::json::array();
        for (std::size_t c = 0; c + perCell <= patch.cells.size(); c += perCell) {
          cells.push_back(std::vector<std::int64_t>(patch.cells.begin() + c, patch.cells.begin() + c + perCell));
        }
        j["cells"] = std::move(cells);
        break;
      }
      case Patch::Kind::PouManifold: {
        j["kind"] = "pou_manifold";
        j["vertices"] = PointList(patch.points, 3);
        nlohmann::json cells = nlohmann::json::array();
        for (std::size_t c = 0; c + 3 <= patch.cells.size(); c += 3) {
          cells.push_back(std::vector<std::int64_t>(patch.cells.begin() + c, patch.cells.begin() + c + 3));
        }
        j["cells"] = std::move(cells);
        j["degrees"] = patch.degrees;
        j["chart_control_points"] = PointList(patch.chartControlPoints, 3);
        break;
      }
      case Patch::Kind::BezierCells:
        throw InputError(path, 0, "patch " + std::to_string(p) + " holds many Bezier cells, which the JSON format cannot express",
                         InputError::Kind::Output);
    }
    if (!patch.weights.empty()) j["weights"] = patch.weights;
    doc["patches"].push_back(std::move(j));
  }
  AtomicOutput out(path);
  // nlohmann prints doubles with enough digits to round-trip.
  out.Write(doc.dump(1));
  out.Write("\n");
  out.Commit();
}

void WritePlyMesh(const Geometry& geometry, const std::string& path) {
  if (LowerExtension(path) != ".ply") {
    throw InputError(path, 0, "triangle meshes are written as PLY: use a .ply file name", InputError::Kind::Output);
  }
  std::vector<double> vertices;
  std::vector<std::int64_t> triangles;
  for (const Patch& patch : geometry.patches) {
    if (patch.kind != Patch::Kind::Mesh || patch.cell != CellType::Tri) {
      throw InputError(path, 0, "only triangle meshes can be written as PLY", InputError::Kind::Output);
    }
    const std::int64_t base = static_cast<std::int64_t>(vertices.size() / 3);
    vertices.insert(vertices.end(), patch.points.begin(), patch.points.end());
    for (std::int64_t index : patch.cells) triangles.push_back(base + index);
  }
  AtomicOutput out(path);
  out.Write("ply\nformat binary_little_endian 1.0\ncomment written by invmap generate\nelement vertex " +
            std::to_string(vertices.size() / 3) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
            std::to_string(triangles.size() / 3) + "\nproperty list uchar int vertex_indices\nend_header\n");
  for (double v : vertices) {
    char bytes[8];
    StoreLittleEndian(bytes, v);
    out.Write(bytes, 8);
  }
  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    char record[13];
    record[0] = 3;
    for (int k = 0; k < 3; ++k) StoreLittleEndian(record + 1 + 4 * k, static_cast<std::int32_t>(triangles[t + k]));
    out.Write(record, sizeof record);
  }
  out.Commit();
}

void WriteGmshMesh(const std::string& path, const std::vector<double>& nodes, int gmshElementType, int nodesPerElement,
                   int elementDim, const std::vector<std::int64_t>& connectivity) {
  const std::size_t numNodes = nodes.size() / 3;
  const std::size_t numElements = connectivity.size() / nodesPerElement;
  AtomicOutput out(path);
  std::string text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // One entity of the elements' dimension, no physical groups.
  text += "$Entities\n";
  text += elementDim == 3 ? "0 0 0 1\n1 0 0 0 0 0 0 0 0\n" : elementDim == 2 ? "0 0 1 0\n1 0 0 0 0 0 0 0 0\n"
                                                                              : "0 1 0 0\n1 0 0 0 0 0 0 0 0\n";
  text += "$EndEntities\n$Nodes\n1 " + std::to_string(numNodes) + " 1 " + std::to_string(numNodes) + "\n" +
          std::to_string(elementDim) + " 1 0 " + std::to_string(numNodes) + "\n";
  out.Write(text);
  for (std::size_t i = 0; i < numNodes; ++i) out.Write(std::to_string(i + 1) + "\n");
  for (std::size_t i = 0; i < numNodes; ++i) {
    std::string line;
    for (int k = 0; k < 3; ++k) {
      if (k) line += ' ';
      AppendNumber(&line, nodes[3 * i + k]);
    }
    line += '\n';
    out.Write(line);
  }
  out.Write("$EndNodes\n$Elements\n1 " + std::to_string(numElements) + " 1 " + std::to_string(numElements) + "\n" +
            std::to_string(elementDim) + " 1 " + std::to_string(gmshElementType) + " " + std::to_string(numElements) +
            "\n");
  for (std::size_t e = 0; e < numElements; ++e) {
    std::string line = std::to_string(e + 1);
    for (int v = 0; v < nodesPerElement; ++v) line += " " + std::to_string(connectivity[e * nodesPerElement + v] + 1);
    line += '\n';
    out.Write(line);
  }
  out.Write("$EndElements\n");
  out.Commit();
}

void WritePoints(const std::string& path, const double* xyz, std::size_t count, int dim) {
  const std::string ext = LowerExtension(path);
  AtomicOutput out(path);
  if (ext == ".npy") {
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(count) + ", " +
                         std::to_string(dim) + "), }";
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a
    // multiple of 64 and ended by a newline.
    const std::size_t total = 10 + header.size() + 1;
    header.append((64 - total % 64) % 64, ' ');
    header += '\n';
    const char magic[8] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
    out.Write(magic, 8);
    char length[2];
    StoreLittleEndian(length, static_cast<std::uint16_t>(header.size()));
    out.Write(length, 2);
    out.Write(header);
    for (std::size_t i = 0; i < count * dim; ++i) {
      char bytes[8];
      StoreLittleEndian(bytes, xyz[i]);
      out.Write(bytes, 8);
    }
  } else if (ext == ".ply") {
    std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) +
                         "\nproperty double x\nproperty double y\n";
    if (dim == 3) header += "property double z\n";
    out.Write(header + "end_header\n");
    for (std::size_t i = 0; i < count * dim; ++i) {
      char bytes[8];
      StoreLittleEndian(bytes, xyz[i]);
      out.Write(bytes, 8);
    }
  } else if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    const char separator = ext == ".csv" ? ',' : ' ';
    if (ext == ".csv") out.Write(dim == 3 ? "x,y,z\n" : "x,y\n");
    std::string line;
    for (std::size_t i = 0; i < count; ++i) {
      line.clear();
      for (int k = 0; k < dim; ++k) {
        if (k) line += separator;
        AppendNumber(&line, xyz[i * dim + k]);
      }
      line += '\n';
      out.Write(line);
    }
  } else {
    throw InputError(path, 0, "unknown point file extension (use .xyz, .txt, .csv, .npy or .ply)",
                     InputError::Kind::Output);
  }
  out.Commit();
}

}  // namespace invmap::io
