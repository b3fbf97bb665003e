// Writers for what `invmap generate` produces: geometry files, meshes and
// point clouds. The meshes and point clouds are streamed (their elements
// handed over one at a time with their counts known up front), so memory
// stays bounded whatever their size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "io/file_io.h"

namespace invmap::io {

/// Writes `geometry` as the JSON geometry file of docs/formats.md, section 2
/// (bspline, bezier and mesh patches; every number the shortest decimal that
/// reads back as the same double), as text straight from the patches.
/// Throws InputError (kind Output) when the file cannot be written or a patch
/// kind has no JSON form (BezierCells: write it as gmsh instead).
void WriteGeometryJson(const Geometry& geometry, const std::string& path);

/// A binary little-endian PLY triangle mesh (double x, y, z vertices, int
/// vertex_indices lists), written vertex by vertex, then triangle by
/// triangle. Not thread-safe; the file appears under its name at Finish.
class PlyTriangleMeshWriter {
 public:
  /// Throws InputError (kind Output) for a name other than .ply, counts that
  /// int indices cannot hold, or an unwritable file.
  PlyTriangleMeshWriter(const std::string& path, std::int64_t numVertices, std::int64_t numTriangles);
  void Vertex(double x, double y, double z);
  /// After every vertex.
  void Triangle(std::int64_t a, std::int64_t b, std::int64_t c);
  /// Throws std::logic_error unless exactly the counts were written.
  void Finish();

 private:
  AtomicOutput out_;
  std::int64_t numVertices_, numTriangles_;
  std::int64_t vertices_ = 0, triangles_ = 0;
};

/// Writes a geometry whose patches are all triangle meshes as one PLY mesh
/// (PlyTriangleMeshWriter).
void WritePlyMesh(const Geometry& geometry, const std::string& path);

/// A gmsh 4.1 ascii mesh of one element type, all in one entity of the
/// elements' dimension without physical groups, written node by node, then
/// element by element (nodesPerElement 0-based node indices each, in gmsh's
/// node order). Not thread-safe; the file appears under its name at Finish.
class GmshMeshWriter {
 public:
  GmshMeshWriter(const std::string& path, std::int64_t numNodes, int gmshElementType, int nodesPerElement,
                 int elementDim, std::int64_t numElements);
  void Node(double x, double y, double z);
  /// After every node.
  void Element(const std::int64_t* nodes);
  /// Throws std::logic_error unless exactly the counts were written.
  void Finish();

 private:
  AtomicOutput out_;
  std::int64_t numNodes_, numElements_;
  int gmshElementType_, nodesPerElement_, elementDim_;
  std::int64_t nodes_ = 0, elements_ = 0;
  std::string line_;  ///< Reused for each line.
};

/// WriteGmshMesh from arrays: `nodes` (x, y, z each), `connectivity`.
void WriteGmshMesh(const std::string& path, const std::vector<double>& nodes, int gmshElementType,
                   int nodesPerElement, int elementDim, const std::vector<std::int64_t>& connectivity);

/// True when PointCloudWriter writes files named like `path` (.xyz, .txt,
/// .csv, .npy, .ply; case-insensitive).
bool IsPointCloudFileName(const std::string& path);

/// A point cloud of `count` points of `dim` coordinates, written as it is
/// generated, by extension: .xyz/.txt (space separated), .csv (header
/// x,y(,z)), .npy (float64, (N, dim)), .ply (binary little endian, double
/// x y (z)); %.17g in text formats. Not thread-safe; the file appears under
/// its name at Finish.
class PointCloudWriter {
 public:
  /// Throws InputError (kind Output) for another extension (before any file
  /// is made) or an unwritable file.
  PointCloudWriter(const std::string& path, std::size_t count, int dim);
  /// Appends n points (dim interleaved coordinates each).
  void Append(const double* xyz, std::size_t n);
  /// Throws std::logic_error unless exactly `count` points were appended.
  void Finish();

 private:
  AtomicOutput out_;
  std::string ext_;
  std::size_t count_;
  int dim_;
  std::size_t written_ = 0;
  std::string line_;  ///< Reused for each text line.
};

/// Writes `count` points in one go (PointCloudWriter).
void WritePoints(const std::string& path, const double* xyz, std::size_t count, int dim);

}  // namespace invmap::io
