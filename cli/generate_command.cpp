// invmap generate: sample geometries and point clouds for demos, tests and
// benchmarks. Meshes and point clouds are streamed to their file as they are
// made, so memory stays bounded over the whole range of sizes --help states.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

#include "cad/sample_part.h"
#include "cli/commands.h"
#include "cli/path_checks.h"
#include "io/file_io.h"
#include "io/input_error.h"
#include "io/sample_writers.h"
#include "samples/sample_geometries.h"

namespace invmap::cli {
namespace {

/// Points around (near, far, box) or inside a geometry, from a fixed seed,
/// one at a time.
class PointSampler {
 public:
  PointSampler(const Manifold& manifold, const GenerateOptions& options)
      : manifold_(manifold), info_(manifold.Info()), kind_(options.kind), spread_(options.spread), rng_(options.seed) {
    double size2 = 0.0;
    for (int k = 0; k < info_.dimension; ++k) {
      size2 += (info_.boundsHi[k] - info_.boundsLo[k]) * (info_.boundsHi[k] - info_.boundsLo[k]);
    }
    size_ = std::sqrt(size2);
    // Cells are picked with equal probability, patches by their cell counts.
    firstCell_.push_back(0);
    for (std::size_t p = 0; p < info_.patches; ++p) {
      firstCell_.push_back(firstCell_.back() + manifold.NumCells(static_cast<int>(p)));
    }
  }

  int dimension() const { return info_.dimension; }

  /// The next point (dimension() coordinates).
  void Next(double* p) {
    const int dim = info_.dimension;
    if (kind_ == "near" || kind_ == "inside") {
      SurfacePoint(p);
      if (kind_ == "near") {
        // A random direction, at most `spread` times the size away.
        double direction[3] = {0, 0, 0}, norm2 = 0.0;
        while (norm2 < 1e-6 || norm2 > 1.0) {
          norm2 = 0.0;
          for (int k = 0; k < dim; ++k) {
            direction[k] = symmetric_(rng_);
            norm2 += direction[k] * direction[k];
          }
        }
        const double offset = spread_ * size_ * unit_(rng_) / std::sqrt(norm2);
        for (int k = 0; k < dim; ++k) p[k] += offset * direction[k];
      }
    } else {
      // box: the geometry's bounding box; far: a box three times as large.
      const double grow = kind_ == "far" ? 1.0 : 0.0;
      for (int k = 0; k < dim; ++k) {
        const double lo = info_.boundsLo[k], hi = info_.boundsHi[k], extent = std::max(hi - lo, 1e-3 * size_);
        p[k] = lo - grow * extent + unit_(rng_) * (1.0 + 2.0 * grow) * extent;
      }
    }
  }

 private:
  /// A point of a random cell at random reference coordinates.
  void SurfacePoint(double* point) {
    const std::int64_t c = static_cast<std::int64_t>(unit_(rng_) * firstCell_.back()) % firstCell_.back();
    const int patch = static_cast<int>(std::upper_bound(firstCell_.begin(), firstCell_.end(), c) - firstCell_.begin() - 1);
    const double sample[3] = {unit_(rng_), unit_(rng_), unit_(rng_)};
    double params[3];
    manifold_.PointAt(patch, c - firstCell_[patch], sample, params, point);
  }

  const Manifold& manifold_;
  const ManifoldInfo info_;
  const std::string kind_;
  const double spread_;
  double size_ = 0.0;
  std::vector<std::int64_t> firstCell_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0}, symmetric_{-1.0, 1.0};
};

/// `generate points`: streamed a block at a time.
void GeneratePoints(const GenerateOptions& options) {
  RefuseOutputOverInput(options.output, options.geometry, "--geometry");
  if (!io::IsPointCloudFileName(options.output)) {
    throw UsageError("--output " + options.output + ": unknown point file extension '" +
                     io::LowerExtension(options.output) + "' (use .xyz, .txt, .csv, .npy or .ply)");
  }
  const Manifold manifold = LoadManifold(options.geometry);
  PointSampler sampler(manifold, options);
  const int dim = sampler.dimension();
  io::PointCloudWriter writer(options.output, static_cast<std::size_t>(options.count), dim);
  constexpr std::int64_t kBlock = 1 << 16;
  std::vector<double> block;
  for (std::int64_t first = 0; first < options.count; first += kBlock) {
    const std::int64_t n = std::min(kBlock, options.count - first);
    block.resize(static_cast<std::size_t>(n * dim));
    for (std::int64_t i = 0; i < n; ++i) sampler.Next(&block[static_cast<std::size_t>(i * dim)]);
    writer.Append(block.data(), static_cast<std::size_t>(n));
  }
  writer.Finish();
}

/// A simulated scan of a CAD model (cad::SimulateScan), written as points.
void WriteScan(const GenerateOptions& options) {
  RefuseOutputOverInput(options.output, options.geometry, "--geometry");
  if (!io::IsPointCloudFileName(options.output)) {
    throw UsageError("--output " + options.output + ": unknown point file extension '" +
                     io::LowerExtension(options.output) + "' (use .xyz, .txt, .csv, .npy or .ply)");
  }
  cad::LoadResult loaded = cad::Model::Load(options.geometry);
  if (!loaded.error.empty()) throw io::InputError(options.geometry, 0, loaded.error);
  const cad::ModelInfo info = loaded.model->Info();
  double size2 = 0.0;
  for (int k = 0; k < 3; ++k) size2 += (info.boundsHi[k] - info.boundsLo[k]) * (info.boundsHi[k] - info.boundsLo[k]);
  const double size = std::sqrt(size2);
  cad::ScanOptions scan;
  scan.count = options.count;
  scan.seed = options.seed;
  scan.noise = std::isnan(options.noise) ? 1e-4 * size : options.noise * size;
  scan.warp = std::isnan(options.warp) ? 5e-4 * size : options.warp * size;
  scan.outlierReach = 1e-2 * size;
  const std::vector<double> points = cad::SimulateScan(*loaded.model, scan);
  io::WritePoints(options.output, points.data(), points.size() / 3, 3);
}


}  // namespace

int RunGenerate(const GenerateOptions& options) {
  const std::string& w = options.what;
  const std::string command = "generate " + w;
  const auto require = [&](const char* extension) {
    RequireOutputExtension(options.output, extension, command.c_str(), "--output");
  };
  if (w == "surface" || w == "torus" || w == "curve") require(".json");
  if (w == "tets") require(".msh");
  if (w == "trimesh") require(".ply");
  if (w == "bracket") require(".step");
  if (w == "surface") {
    io::WriteGeometryJson(samples::WavySurface(options.spans), options.output);
  } else if (w == "torus") {
    io::WriteGeometryJson(samples::NurbsTorus(2.0, 0.7), options.output);
  } else if (w == "curve") {
    io::WriteGeometryJson(samples::NurbsCurve2D(), options.output);
  } else if (w == "tets") {
    const samples::CurvedTetGrid grid(options.resolution);
    io::GmshMeshWriter writer(options.output, grid.NumNodes(), /*gmsh tet10*/ 11, 10, 3, grid.NumTets());
    grid.ForEachNode([&](double x, double y, double z) { writer.Node(x, y, z); });
    grid.ForEachTet([&](const std::int64_t* nodes) { writer.Element(nodes); });
    writer.Finish();
  } else if (w == "trimesh") {
    const samples::BumpySphereMesh mesh(options.triangles);
    io::PlyTriangleMeshWriter writer(options.output, mesh.NumVertices(), mesh.NumTriangles());
    mesh.ForEachVertex([&](double x, double y, double z) { writer.Vertex(x, y, z); });
    mesh.ForEachTriangle([&](std::int64_t a, std::int64_t b, std::int64_t c) { writer.Triangle(a, b, c); });
    writer.Finish();
  } else if (w == "bracket") {
    if (const std::string error = cad::WriteSampleBracket(options.output); !error.empty()) {
      throw io::InputError(options.output, 0, error, io::InputError::Kind::Output);
    }
  } else if (w == "scan") {
    WriteScan(options);
  } else if (w == "points") {
    GeneratePoints(options);
  } else {
    std::fprintf(stderr,
                 "invmap generate: unknown sample '%s' (surface, torus, curve, tets, trimesh, bracket, points, scan)\n",
                 w.c_str());
    return 2;
  }
  return 0;
}

}  // namespace invmap::cli
