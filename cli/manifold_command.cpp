// `invmap manifold`: the partition-of-unity surface of a closed triangle
// mesh, written as a geometry file with one pou_manifold patch
// (docs/manifold.md), and optionally a tessellation of it.
#include <chrono>
#include <cstdio>

#include "cli/commands.h"
#include "cli/path_checks.h"
#include "invmap/pou.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"
#include "io/sample_writers.h"

namespace invmap::cli {

int RunManifold(const ManifoldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string extension = io::LowerExtension(options.mesh);
  if (extension != ".obj" && extension != ".ply" && extension != ".off" && extension != ".stl") {
    throw io::InputError(options.mesh, 0, "expected a triangle mesh (.obj, .ply, .off or .stl)");
  }
  RefuseOutputOverInput(options.output, options.mesh, "--mesh");
  RequireOutputExtension(options.output, ".json", "manifold", "--output");
  if (!options.tessellate.empty()) {
    RefuseOutputOverInput(options.tessellate, options.mesh, "--mesh", "--tessellate");
    RequireOutputExtension(options.tessellate, ".ply", "manifold", "--tessellate");
  }
  CheckWritable(options.output);
  if (!options.tessellate.empty()) CheckWritable(options.tessellate);
  const Geometry mesh = io::ReadGeometryFile(options.mesh);
  if (mesh.patches.size() != 1 || mesh.patches[0].cell != CellType::Tri) {
    throw io::InputError(options.mesh, 0, "the mesh has faces other than triangles (quads); a triangle mesh is needed");
  }
  const Patch& triangles = mesh.patches[0];
  PouOptions pou;
  pou.base = options.base == "flat" ? PouBase::Flat : options.base == "pn" ? PouBase::PnTriangles : PouBase::Loop;
  pou.degree = options.degree;
  Geometry surface;
  surface.dimension = 3;
  surface.patches.emplace_back();
  const std::int64_t numVertices = static_cast<std::int64_t>(triangles.points.size() / 3);
  const std::int64_t numTriangles = static_cast<std::int64_t>(triangles.cells.size() / 3);
  if (std::string e = BuildPouManifold(triangles.points.data(), numVertices, triangles.cells.data(), numTriangles, pou,
                                       &surface.patches[0]);
      !e.empty()) {
    throw io::InputError(options.mesh, 0, e + " (vertices and triangles are numbered from 0 in file order)");
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::WriteGeometryJson(surface, options.output);
  if (!options.tessellate.empty()) {
    PouCharts charts;
    if (std::string e = PouCharts::Create(surface.patches[0], &charts); !e.empty()) {
      throw std::logic_error("the surface just built does not read back: " + e);
    }
    Geometry tessellation;
    tessellation.dimension = 3;
    Patch& out = tessellation.patches.emplace_back();
    out.kind = Patch::Kind::Mesh;
    out.cell = CellType::Tri;
    charts.Tessellate(options.resolution, &out.points, &out.cells);
    io::WritePlyMesh(tessellation, options.tessellate);
  }
  if (!options.quiet) {
    std::printf("mesh        %s: %lld vertices, %lld triangles\n", options.mesh.c_str(),
                static_cast<long long>(numVertices), static_cast<long long>(numTriangles));
    std::printf("surface     %s: %lld charts, base %s, built in %.3f s\n", options.output.c_str(),
                static_cast<long long>(numVertices), options.base.c_str(), seconds);
    if (!options.tessellate.empty()) {
      std::printf("tessellation %s: %d segments per mesh edge\n", options.tessellate.c_str(), options.resolution);
    }
  }
  return 0;
}

}  // namespace invmap::cli
