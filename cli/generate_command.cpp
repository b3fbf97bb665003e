// invmap generate: sample geometries and point clouds for demos, tests and benchmarks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "cli/commands.h"
#include "io/geometry_file.h"
#include "io/input_error.h"
#include "io/sample_writers.h"
#include "samples/sample_geometries.h"

namespace invmap::cli {
namespace {

/// Points around (near, far, box) or inside a geometry, from a fixed seed.
std::vector<double> SamplePoints(const GenerateOptions& options) {
  const Geometry geometry = io::ReadGeometryFile(options.geometry);
  BuildResult built = Manifold::Build(geometry);
  if (!built.error.empty()) throw io::InputError(options.geometry, 0, built.error);
  const Manifold& manifold = built.manifold;
  const ManifoldInfo info = manifold.Info();
  const int dim = info.dimension;
  double size2 = 0.0;
  for (int k = 0; k < dim; ++k) size2 += (info.boundsHi[k] - info.boundsLo[k]) * (info.boundsHi[k] - info.boundsLo[k]);
  const double size = std::sqrt(size2);

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), symmetric(-1.0, 1.0);
  // Cells are picked with equal probability, patches by their cell counts.
  std::vector<std::int64_t> firstCell{0};
  for (std::size_t p = 0; p < info.patches; ++p) firstCell.push_back(firstCell.back() + manifold.NumCells(static_cast<int>(p)));
  auto surfacePoint = [&](double* point) {
    const std::int64_t c = static_cast<std::int64_t>(unit(rng) * firstCell.back()) % firstCell.back();
    const int patch = static_cast<int>(std::upper_bound(firstCell.begin(), firstCell.end(), c) - firstCell.begin() - 1);
    const double sample[3] = {unit(rng), unit(rng), unit(rng)};
    double params[3];
    manifold.PointAt(patch, c - firstCell[patch], sample, params, point);
  };

  std::vector<double> points;
  points.reserve(static_cast<std::size_t>(options.count) * dim);
  for (std::int64_t i = 0; i < options.count; ++i) {
    double p[3] = {0, 0, 0};
    if (options.kind == "near" || options.kind == "inside") {
      if (info.cells == 0) throw std::invalid_argument("the geometry has no cells to sample");
      surfacePoint(p);
      if (options.kind == "near") {
        // A random direction, at most `spread` times the size away.
        double direction[3] = {0, 0, 0}, norm2 = 0.0;
        while (norm2 < 1e-6 || norm2 > 1.0) {
          norm2 = 0.0;
          for (int k = 0; k < dim; ++k) {
            direction[k] = symmetric(rng);
            norm2 += direction[k] * direction[k];
          }
        }
        const double offset = options.spread * size * unit(rng) / std::sqrt(norm2);
        for (int k = 0; k < dim; ++k) p[k] += offset * direction[k];
      }
    } else if (options.kind == "far" || options.kind == "box") {
      // box: the geometry's bounding box; far: a box three times as large.
      const double grow = options.kind == "far" ? 1.0 : 0.0;
      for (int k = 0; k < dim; ++k) {
        const double lo = info.boundsLo[k], hi = info.boundsHi[k], extent = std::max(hi - lo, 1e-3 * size);
        p[k] = lo - grow * extent + unit(rng) * (1.0 + 2.0 * grow) * extent;
      }
    } else {
      throw std::invalid_argument("--kind must be near, far, inside or box");
    }
    points.insert(points.end(), p, p + dim);
  }
  return points;
}

}  // namespace

int RunGenerate(const GenerateOptions& options) {
  const std::string& w = options.what;
  if (w == "surface") {
    io::WriteGeometryJson(samples::WavySurface(options.spans), options.output);
  } else if (w == "torus") {
    io::WriteGeometryJson(samples::NurbsTorus(2.0, 0.7), options.output);
  } else if (w == "curve") {
    io::WriteGeometryJson(samples::NurbsCurve2D(), options.output);
  } else if (w == "tets") {
    const samples::QuadraticTetMesh mesh = samples::CurvedTetMesh(options.resolution);
    io::WriteGmshMesh(options.output, mesh.nodes, /*gmsh tet10*/ 11, 10, 3, mesh.tets);
  } else if (w == "trimesh") {
    io::WritePlyMesh(samples::BumpySphere(options.triangles), options.output);
  } else if (w == "points") {
    const std::vector<double> points = SamplePoints(options);
    const Geometry geometry = io::ReadGeometryFile(options.geometry);
    io::WritePoints(options.output, points.data(), static_cast<std::size_t>(options.count), geometry.dimension);
  } else {
    std::fprintf(stderr, "invmap generate: unknown sample '%s' (surface, torus, curve, tets, trimesh, points)\n",
                 w.c_str());
    return 2;
  }
  return 0;
}

}  // namespace invmap::cli
