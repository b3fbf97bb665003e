#include "bench/peers/scaling.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "bench/peers/harness.h"
#include "invmap/invmap.h"
#include "samples/sample_geometries.h"

namespace invmap::bench {
namespace {

/// Uniform double in [lo, hi) from the top 53 bits (the same on every standard library).
double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

/// Points in the slab around the wavy surface over [0, 1]^2 (cheap to make by
/// the ten million, unlike normal offsets).
std::vector<double> SurfaceSlabPoints(std::int64_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> xyz(3 * count);
  for (std::int64_t i = 0; i < count; ++i) {
    xyz[3 * i] = Uniform(rng, 0.0, 1.0);
    xyz[3 * i + 1] = Uniform(rng, 0.0, 1.0);
    xyz[3 * i + 2] = Uniform(rng, -0.15, 0.3);
  }
  return xyz;
}

/// Points in the shell 0.9 < r < 1.1 around the bumpy sphere.
std::vector<double> SphereShellPoints(std::int64_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> xyz;
  xyz.reserve(3 * count);
  while (static_cast<std::int64_t>(xyz.size()) < 3 * count) {
    const double x = Uniform(rng, -1, 1), y = Uniform(rng, -1, 1), z = Uniform(rng, -1, 1);
    const double r2 = x * x + y * y + z * z;
    if (r2 > 1.0 || r2 < 1e-6) continue;
    const double scale = Uniform(rng, 0.9, 1.1) / std::sqrt(r2);
    xyz.insert(xyz.end(), {x * scale, y * scale, z * scale});
  }
  return xyz;
}

/// Seconds of one Invert of the first `count` points.
double TimeInvert(const Manifold& manifold, const std::vector<double>& xyz, std::int64_t count, int threads,
                  Results* results) {
  InversionOptions options;
  options.threads = threads;
  const double t0 = Now();
  manifold.Invert(PointsView::Interleaved(xyz.data(), count, 3), options, results);
  return Now() - t0;
}

/// The geometry of a series at one size, its cell count and build time.
struct Built {
  Manifold manifold;
  std::int64_t cells = 0;
  double buildSeconds = 0.0;
};

/// Builds the manifold and times it; exits on a build error (the samples are valid).
Built Build(const Geometry& geometry) {
  Built built;
  const double t0 = Now();
  BuildResult result = Manifold::Build(geometry);
  built.buildSeconds = Now() - t0;
  if (!result.error.empty()) {
    std::fprintf(stderr, "invmap_bench_peers: scaling: %s\n", result.error.c_str());
    std::exit(2);
  }
  built.manifold = std::move(result.manifold);
  built.cells = static_cast<std::int64_t>(built.manifold.Info().cells);
  return built;
}

/// One thread per geometry size: the cost per point against the cells is the
/// question here (threads are the batch study's). Each size gets as many of
/// `xyz`'s points as fit in about `secondsPerSize` (at least 2000).
void CellsStudy(const std::string& name, const std::vector<Geometry>& geometries, const std::vector<double>& xyz,
                double secondsPerSize, std::vector<ScalingRow>* rows) {
  for (const Geometry& geometry : geometries) {
    Built built = Build(geometry);
    const std::int64_t available = static_cast<std::int64_t>(xyz.size() / 3);
    const std::int64_t probe = std::min<std::int64_t>(available, 2000);
    Results results;
    const double probeSeconds = TimeInvert(built.manifold, xyz, probe, 1, &results);  // also the warm-up
    const std::int64_t count = std::clamp<std::int64_t>(
        static_cast<std::int64_t>(probe / std::max(1e-9, probeSeconds) * secondsPerSize), probe, available);
    ScalingRow row;
    row.study = "cells";
    row.geometry = name;
    row.cells = built.cells;
    row.points = count;
    row.threads = 1;
    row.buildSeconds = built.buildSeconds;
    row.seconds = TimeInvert(built.manifold, xyz, count, 1, &results);
    std::fprintf(stderr, "  scaling cells %-8s %9lld cells  %8lld points: %lld points/s (build %.2f s)\n",
                 name.c_str(), static_cast<long long>(row.cells), static_cast<long long>(count),
                 static_cast<long long>(count / row.seconds), row.buildSeconds);
    rows->push_back(row);
  }
}

/// Batches of 10^3, 10^4, ... points until the next one would pass the cap.
void BatchStudy(const ScalingOptions& options, const std::string& name, const Geometry& geometry,
                const std::vector<double>& xyz, std::vector<ScalingRow>* rows) {
  Built built = Build(geometry);
  const std::int64_t maxCount = static_cast<std::int64_t>(xyz.size() / 3);
  Results results;
  TimeInvert(built.manifold, xyz, std::min<std::int64_t>(maxCount, 1000), 1, &results);  // warm-up
  for (int threads : {1, options.allThreads}) {
    for (std::int64_t count = 1000; count <= maxCount; count *= 10) {
      ScalingRow row;
      row.study = "batch";
      row.geometry = name;
      row.cells = built.cells;
      row.points = count;
      row.threads = threads == 0 ? options.allThreadsCount : threads;
      row.buildSeconds = built.buildSeconds;
      row.seconds = TimeInvert(built.manifold, xyz, count, threads, &results);
      std::fprintf(stderr, "  scaling batch %-8s %9lld points %d thread(s): %lld points/s\n", name.c_str(),
                   static_cast<long long>(count), row.threads, static_cast<long long>(count / row.seconds));
      rows->push_back(row);
      if (row.seconds * 10 > options.capSeconds) break;
    }
  }
}

}  // namespace

std::vector<ScalingRow> RunScaling(const ScalingOptions& options) {
  std::vector<ScalingRow> rows;
  const std::int64_t pointsPerSize = options.quick ? 2000 : 100000;
  const double secondsPerSize = options.quick ? 0.05 : 1.5;

  // Cells: about 10 to 10^6, a step of about 10 (the surface's 10^6 cells
  // take the longest build of the study).
  std::vector<Geometry> surfaces;
  const std::vector<int> spans = options.quick ? std::vector<int>{3, 10, 32} : std::vector<int>{3, 10, 32, 100, 316, 1000};
  for (int s : spans) surfaces.push_back(samples::WavySurface(s));
  CellsStudy("surface", surfaces, SurfaceSlabPoints(pointsPerSize, 101), secondsPerSize, &rows);
  surfaces.clear();

  std::vector<Geometry> spheres;
  const std::int64_t maxTriangles = options.quick ? 20000 : 1000000;
  for (std::int64_t t = 20; t <= 4 * maxTriangles; t *= 4) {
    spheres.push_back(samples::BumpySphere(t));
    if (spheres.back().patches[0].cells.size() / 3 >= static_cast<std::size_t>(maxTriangles)) break;
  }
  CellsStudy("trimesh", spheres, SphereShellPoints(pointsPerSize, 102), secondsPerSize, &rows);
  spheres.clear();

  // Batches: 10^3 to 10^7 points on mid-sized geometries.
  const std::int64_t maxBatch = options.quick ? 10000 : 10000000;
  BatchStudy(options, "surface", samples::WavySurface(32), SurfaceSlabPoints(maxBatch, 103), &rows);
  BatchStudy(options, "trimesh", samples::BumpySphere(options.quick ? 5000 : 300000), SphereShellPoints(maxBatch, 104),
             &rows);
  return rows;
}

bool WriteScalingCsv(const std::string& path, const std::vector<ScalingRow>& rows) {
  std::ofstream out(path);
  if (!out) return false;
  out.precision(9);
  out << "study,geometry,cells,points,threads,seconds,points_per_second,build_seconds\n";
  for (const ScalingRow& r : rows) {
    out << r.study << "," << r.geometry << "," << r.cells << "," << r.points << "," << r.threads << "," << r.seconds
        << "," << r.points / r.seconds << "," << r.buildSeconds << "\n";
  }
  return static_cast<bool>(out);
}

}  // namespace invmap::bench
