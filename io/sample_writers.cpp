#include "io/sample_writers.h"

#include <charconv>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// %.17g: enough digits to round-trip (the point formats' contract).
void AppendNumber(std::string* out, double value) {
  char text[32];
  const int n = std::snprintf(text, sizeof text, "%.17g", value);
  out->append(text, n);
}

/// The shortest decimal that reads back as `value` (JSON).
void AppendShortest(std::string* out, double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  out->append(text, result.ptr);
}

/// Appends a JSON list of numbers: [a, b, c].
template <typename T>
void AppendList(std::string* out, const T* values, std::size_t count) {
  out->push_back('[');
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) out->append(", ");
    if constexpr (std::is_floating_point_v<T>) {
      AppendShortest(out, values[i]);
    } else {
      out->append(std::to_string(values[i]));
    }
  }
  out->push_back(']');
}

/// Writes `"name": [` then rows of `width` values, one a line, then `]`.
template <typename T>
void WriteRows(AtomicOutput& out, const char* name, const std::vector<T>& values, std::size_t width) {
  out.Write(std::string("   \"") + name + "\": [");
  std::string line;
  for (std::size_t row = 0; row * width < values.size(); ++row) {
    line.assign(row == 0 ? "\n    " : ",\n    ");
    AppendList(&line, values.data() + row * width, width);
    out.Write(line);
  }
  out.Write(values.empty() ? "]" : "\n   ]");
}

/// Throws the InputError of kind Output naming `path`.
[[noreturn]] void FailOutput(const std::string& path, const std::string& what) {
  throw InputError(path, 0, what, InputError::Kind::Output);
}

/// `path` when it names a .ply file (checked before the file is made).
const std::string& PlyPath(const std::string& path) {
  if (LowerExtension(path) != ".ply") FailOutput(path, "triangle meshes are written as PLY: use a .ply file name");
  return path;
}

/// `path` when its extension names a point format (checked before the file is made).
const std::string& PointPath(const std::string& path) {
  if (!IsPointCloudFileName(path)) FailOutput(path, "unknown point file extension (use .xyz, .txt, .csv, .npy or .ply)");
  return path;
}

}  // namespace

bool IsPointCloudFileName(const std::string& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".npy" || ext == ".ply" || ext == ".xyz" || ext == ".txt" || ext == ".csv";
}

void WriteGeometryJson(const Geometry& geometry, const std::string& path) {
  const int dim = geometry.dimension;
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    if (geometry.patches[p].kind == Patch::Kind::BezierCells) {
      FailOutput(path, "patch " + std::to_string(p) + " holds many Bezier cells, which the JSON format cannot express");
    }
    if (geometry.patches[p].kind == Patch::Kind::TrimmedSurface) {
      FailOutput(path, "patch " + std::to_string(p) + " is a trimmed CAD face, which the JSON format cannot express");
    }
  }
  AtomicOutput out(path);
  out.Write("{\n \"format\": \"invmap-geometry\",\n \"version\": 1,\n \"dimension\": " + std::to_string(dim) +
            ",\n \"patches\": [");
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    const Patch& patch = geometry.patches[p];
    std::string head = p == 0 ? "\n  {\n" : ",\n  {\n";
    switch (patch.kind) {
      case Patch::Kind::BSpline: {
        head += "   \"kind\": \"bspline\",\n   \"degrees\": ";
        AppendList(&head, patch.degrees.data(), patch.degrees.size());
        head += ",\n   \"knots\": [";
        for (std::size_t d = 0; d < patch.knots.size(); ++d) {
          if (d > 0) head += ", ";
          AppendList(&head, patch.knots[d].data(), patch.knots[d].size());
        }
        head += "],\n   \"counts\": ";
        AppendList(&head, patch.counts.data(), patch.counts.size());
        head += ",\n";
        out.Write(head);
        WriteRows(out, "control_points", patch.points, static_cast<std::size_t>(dim));
        break;
      }
      case Patch::Kind::Bezier:
        head += std::string("   \"kind\": \"bezier\",\n   \"cell\": \"") + CellTypeName(patch.cell) + "\",\n   \"degrees\": ";
        AppendList(&head, patch.degrees.data(), patch.degrees.size());
        head += ",\n";
        out.Write(head);
        WriteRows(out, "control_points", patch.points, static_cast<std::size_t>(dim));
        break;
      case Patch::Kind::Mesh:
        head += std::string("   \"kind\": \"mesh\",\n   \"cell\": \"") + CellTypeName(patch.cell) + "\",\n";
        out.Write(head);
        WriteRows(out, "vertices", patch.points, static_cast<std::size_t>(dim));
        out.Write(",\n");
        WriteRows(out, "cells", patch.cells, static_cast<std::size_t>(TraitsOf(patch.cell).vertices));
        break;
      case Patch::Kind::PouManifold:
        head += "   \"kind\": \"pou_manifold\",\n";
        out.Write(head);
        WriteRows(out, "vertices", patch.points, 3);
        out.Write(",\n");
        WriteRows(out, "cells", patch.cells, 3);
        head = ",\n   \"degrees\": ";
        AppendList(&head, patch.degrees.data(), patch.degrees.size());
        head += ",\n";
        out.Write(head);
        WriteRows(out, "chart_control_points", patch.chartControlPoints, 3);
        break;
      case Patch::Kind::BezierCells:
      case Patch::Kind::TrimmedSurface:
        break;  // refused above
    }
    if (!patch.weights.empty()) {
      std::string weights = ",\n   \"weights\": ";
      AppendList(&weights, patch.weights.data(), patch.weights.size());
      out.Write(weights);
    }
    out.Write("\n  }");
  }
  out.Write(geometry.patches.empty() ? "]\n}\n" : "\n ]\n}\n");
  out.Commit();
}

PlyTriangleMeshWriter::PlyTriangleMeshWriter(const std::string& path, std::int64_t numVertices,
                                             std::int64_t numTriangles)
    : out_(PlyPath(path)), numVertices_(numVertices), numTriangles_(numTriangles) {
  if (numVertices > std::numeric_limits<std::int32_t>::max()) {
    FailOutput(path, std::to_string(numVertices) + " vertices: more than PLY's int vertex indices can number");
  }
  out_.Write("ply\nformat binary_little_endian 1.0\ncomment written by invmap generate\nelement vertex " +
             std::to_string(numVertices) + "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
             std::to_string(numTriangles) + "\nproperty list uchar int vertex_indices\nend_header\n");
}

void PlyTriangleMeshWriter::Vertex(double x, double y, double z) {
  if (vertices_++ >= numVertices_) throw std::logic_error("PlyTriangleMeshWriter: more vertices than declared");
  char record[24];
  StoreLittleEndian(record, x);
  StoreLittleEndian(record + 8, y);
  StoreLittleEndian(record + 16, z);
  out_.Write(record, sizeof record);
}

void PlyTriangleMeshWriter::Triangle(std::int64_t a, std::int64_t b, std::int64_t c) {
  if (vertices_ != numVertices_ || triangles_++ >= numTriangles_) {
    throw std::logic_error("PlyTriangleMeshWriter: a triangle before every vertex, or more than declared");
  }
  char record[13];
  record[0] = 3;
  StoreLittleEndian(record + 1, static_cast<std::int32_t>(a));
  StoreLittleEndian(record + 5, static_cast<std::int32_t>(b));
  StoreLittleEndian(record + 9, static_cast<std::int32_t>(c));
  out_.Write(record, sizeof record);
}

void PlyTriangleMeshWriter::Finish() {
  if (vertices_ != numVertices_ || triangles_ != numTriangles_) {
    throw std::logic_error("PlyTriangleMeshWriter: fewer vertices or triangles than declared");
  }
  out_.Commit();
}

void WritePlyMesh(const Geometry& geometry, const std::string& path) {
  std::int64_t numVertices = 0, numTriangles = 0;
  for (const Patch& patch : geometry.patches) {
    if (patch.kind != Patch::Kind::Mesh || patch.cell != CellType::Tri) {
      FailOutput(path, "only triangle meshes can be written as PLY");
    }
    numVertices += static_cast<std::int64_t>(patch.points.size() / 3);
    numTriangles += static_cast<std::int64_t>(patch.cells.size() / 3);
  }
  PlyTriangleMeshWriter writer(path, numVertices, numTriangles);
  for (const Patch& patch : geometry.patches) {
    for (std::size_t i = 0; i + 3 <= patch.points.size(); i += 3) {
      writer.Vertex(patch.points[i], patch.points[i + 1], patch.points[i + 2]);
    }
  }
  std::int64_t base = 0;
  for (const Patch& patch : geometry.patches) {
    for (std::size_t t = 0; t + 3 <= patch.cells.size(); t += 3) {
      writer.Triangle(base + patch.cells[t], base + patch.cells[t + 1], base + patch.cells[t + 2]);
    }
    base += static_cast<std::int64_t>(patch.points.size() / 3);
  }
  writer.Finish();
}

GmshMeshWriter::GmshMeshWriter(const std::string& path, std::int64_t numNodes, int gmshElementType,
                               int nodesPerElement, int elementDim, std::int64_t numElements)
    : out_(path), numNodes_(numNodes), numElements_(numElements), gmshElementType_(gmshElementType),
      nodesPerElement_(nodesPerElement), elementDim_(elementDim) {
  std::string text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // One entity of the elements' dimension, no physical groups.
  text += "$Entities\n";
  text += elementDim == 3 ? "0 0 0 1\n1 0 0 0 0 0 0 0 0\n" : elementDim == 2 ? "0 0 1 0\n1 0 0 0 0 0 0 0 0\n"
                                                                              : "0 1 0 0\n1 0 0 0 0 0 0 0 0\n";
  text += "$EndEntities\n$Nodes\n1 " + std::to_string(numNodes) + " 1 " + std::to_string(numNodes) + "\n" +
          std::to_string(elementDim) + " 1 0 " + std::to_string(numNodes) + "\n";
  out_.Write(text);
  // The entity's node tags come before its coordinates.
  for (std::int64_t i = 0; i < numNodes; ++i) {
    line_ = std::to_string(i + 1);
    line_ += '\n';
    out_.Write(line_);
  }
}

void GmshMeshWriter::Node(double x, double y, double z) {
  if (nodes_++ >= numNodes_) throw std::logic_error("GmshMeshWriter: more nodes than declared");
  line_.clear();
  AppendNumber(&line_, x);
  line_ += ' ';
  AppendNumber(&line_, y);
  line_ += ' ';
  AppendNumber(&line_, z);
  line_ += '\n';
  out_.Write(line_);
}

void GmshMeshWriter::Element(const std::int64_t* nodes) {
  if (nodes_ != numNodes_ || elements_ >= numElements_) {
    throw std::logic_error("GmshMeshWriter: an element before every node, or more than declared");
  }
  if (elements_ == 0) {
    out_.Write("$EndNodes\n$Elements\n1 " + std::to_string(numElements_) + " 1 " + std::to_string(numElements_) + "\n" +
               std::to_string(elementDim_) + " 1 " + std::to_string(gmshElementType_) + " " +
               std::to_string(numElements_) + "\n");
  }
  line_ = std::to_string(++elements_);
  for (int v = 0; v < nodesPerElement_; ++v) {
    line_ += ' ';
    line_ += std::to_string(nodes[v] + 1);
  }
  line_ += '\n';
  out_.Write(line_);
}

void GmshMeshWriter::Finish() {
  if (nodes_ != numNodes_ || elements_ != numElements_) {
    throw std::logic_error("GmshMeshWriter: fewer nodes or elements than declared");
  }
  if (numElements_ == 0) out_.Write("$EndNodes\n$Elements\n0 0 0 0\n");
  out_.Write("$EndElements\n");
  out_.Commit();
}

void WriteGmshMesh(const std::string& path, const std::vector<double>& nodes, int gmshElementType, int nodesPerElement,
                   int elementDim, const std::vector<std::int64_t>& connectivity) {
  const std::int64_t numNodes = static_cast<std::int64_t>(nodes.size() / 3);
  const std::int64_t numElements = static_cast<std::int64_t>(connectivity.size() / nodesPerElement);
  GmshMeshWriter writer(path, numNodes, gmshElementType, nodesPerElement, elementDim, numElements);
  for (std::int64_t i = 0; i < numNodes; ++i) writer.Node(nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]);
  for (std::int64_t e = 0; e < numElements; ++e) writer.Element(connectivity.data() + e * nodesPerElement);
  writer.Finish();
}

PointCloudWriter::PointCloudWriter(const std::string& path, std::size_t count, int dim)
    : out_(PointPath(path)), ext_(LowerExtension(path)), count_(count), dim_(dim) {
  if (ext_ == ".npy") {
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(count) + ", " +
                         std::to_string(dim) + "), }";
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a
    // multiple of 64 and ended by a newline.
    const std::size_t total = 10 + header.size() + 1;
    header.append((64 - total % 64) % 64, ' ');
    header += '\n';
    const char magic[8] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
    out_.Write(magic, 8);
    char length[2];
    StoreLittleEndian(length, static_cast<std::uint16_t>(header.size()));
    out_.Write(length, 2);
    out_.Write(header);
  } else if (ext_ == ".ply") {
    std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) +
                         "\nproperty double x\nproperty double y\n";
    if (dim == 3) header += "property double z\n";
    out_.Write(header + "end_header\n");
  } else if (ext_ == ".csv") {
    out_.Write(dim == 3 ? "x,y,z\n" : "x,y\n");
  }
}

void PointCloudWriter::Append(const double* xyz, std::size_t n) {
  if (written_ + n > count_) throw std::logic_error("PointCloudWriter: more points than declared");
  written_ += n;
  if (ext_ == ".npy" || ext_ == ".ply") {
    for (std::size_t i = 0; i < n * dim_; ++i) {
      char bytes[8];
      StoreLittleEndian(bytes, xyz[i]);
      out_.Write(bytes, 8);
    }
    return;
  }
  const char separator = ext_ == ".csv" ? ',' : ' ';
  for (std::size_t i = 0; i < n; ++i) {
    line_.clear();
    for (int k = 0; k < dim_; ++k) {
      if (k) line_ += separator;
      AppendNumber(&line_, xyz[i * dim_ + k]);
    }
    line_ += '\n';
    out_.Write(line_);
  }
}

void PointCloudWriter::Finish() {
  if (written_ != count_) throw std::logic_error("PointCloudWriter: fewer points than declared");
  out_.Commit();
}

void WritePoints(const std::string& path, const double* xyz, std::size_t count, int dim) {
  PointCloudWriter writer(path, count, dim);
  writer.Append(xyz, count);
  writer.Finish();
}

}  // namespace invmap::io
