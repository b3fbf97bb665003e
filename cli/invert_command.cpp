// invmap invert, trim and info: geometry in, points streamed through the engine.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cad/model.h"
#include "cli/commands.h"
#include "cli/deviation_summary.h"
#include "cli/path_checks.h"
#include "cli/run_summary.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"
#include "io/point_reader.h"
#include "io/result_writer.h"
#include "io/trim_writer.h"

namespace invmap::cli {
namespace {

/// Points per chunk: bounds memory for inputs of any size and sets how often
/// the progress bar moves. A chunk holds about 140 bytes a point (the
/// coordinates as read and the engine's copy, the results, the sort keys):
/// 37 MB at 2^18, where 2^20's 145 MB was most of the peak on meshes of a
/// million triangles, at the same CPU time (docs/benchmarks.md).
constexpr std::size_t kChunkPoints = 1 << 18;

/// A geometry ready for queries, and the CAD model it came from (null for
/// other formats).
struct LoadedGeometry {
  std::unique_ptr<cad::Model> cad;
  Manifold manifold;
};

LoadedGeometry LoadGeometry(const std::string& path) {
  LoadedGeometry loaded;
  if (!cad::IsCadFile(path)) {
    loaded.manifold = LoadManifold(path);
    return loaded;
  }
  cad::LoadResult model = cad::Model::Load(path);
  if (!model.error.empty()) throw io::InputError(path, 0, model.error);
  loaded.cad = std::move(model.model);
  loaded.manifold = BuildManifold(loaded.cad->geometry(), path);
  return loaded;
}

/// Why --signed cannot be used with this geometry (empty when it can).
std::string SignedUsageError(const InvertOptions& options, const LoadedGeometry& loaded) {
  if (!options.signedDistance) return {};
  if (!loaded.cad) {
    return "--signed needs a CAD model (.step, .stp, .iges, .igs, .brep): " + options.geometry + " has no inside";
  }
  const std::string unsupported = loaded.cad->SignedUnsupported();
  return unsupported.empty() ? std::string() : options.geometry + ": " + unsupported;
}

/// Invert one chunk; a batch-level error is an internal failure here (the
/// inputs were validated), reported as such.
void InvertChunk(const Manifold& manifold, const io::PointChunk& chunk, int dim, const InversionOptions& options,
                 Results* results) {
  std::string message;
  const Error error =
      manifold.Invert(PointsView::Interleaved(chunk.xyz.data(), chunk.count, dim), options, results, &message);
  if (error != Error::Ok) throw std::runtime_error(message);
}

/// Streams every point of `options.points` through the manifold; `sink`
/// receives each chunk with its results.
template <typename Sink>
int Stream(const InvertOptions& options, bool keepRaw, const char* verb, Sink&& sink) {
  const auto start = std::chrono::steady_clock::now();
  CheckInversionPaths(options.geometry, options.points, options.output, keepRaw);
  const LoadedGeometry loaded = LoadGeometry(options.geometry);
  if (const std::string error = SignedUsageError(options, loaded); !error.empty()) {
    std::fprintf(stderr, "invmap %s: %s\n", verb, error.c_str());
    return 2;
  }
  const Manifold& manifold = loaded.manifold;
  const auto built = std::chrono::steady_clock::now();
  const int dim = manifold.Info().dimension;
  io::PointReadOptions readOptions;
  readOptions.forcedDim = dim;
  readOptions.keepRaw = keepRaw;
  std::unique_ptr<io::PointReader> reader = io::OpenPointReader(options.points, readOptions);
  InversionOptions inversion;
  inversion.maxDistance = options.maxDistance;
  inversion.threads = options.threads;
  inversion.pointwise = options.pointwise;
  // Signed trimming keeps the inside however deep: every point needs its side.
  if (options.signedDistance && keepRaw) inversion.maxDistance = std::numeric_limits<double>::infinity();

  sink.Open(*reader, dim);
  Progress progress(options.quiet, reader->totalCountHint());
  RunSummary summary;
  DeviationSummary deviation(options.tolerance);
  io::PointChunk chunk;
  Results results;
  std::vector<double> signedDistances;
  while (reader->ReadChunk(kChunkPoints, &chunk)) {
    InvertChunk(manifold, chunk, dim, inversion, &results);
    if (options.signedDistance) {
      signedDistances.resize(chunk.count);
      loaded.cad->SignDistances(chunk.xyz.data(), chunk.count, results, signedDistances.data(), options.threads);
      deviation.Add(signedDistances.data(), chunk.count);
    }
    sink.Write(chunk, results, options.signedDistance ? signedDistances.data() : nullptr);
    summary.Add(results, chunk.count);
    progress.Update(summary.points());
  }
  sink.Finish();
  progress.Done();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.quiet) {
    std::printf("invmap %s: %s onto %s -> %s\n", verb, options.points.c_str(), options.geometry.c_str(),
                options.output.c_str());
    summary.Print(stdout, seconds, std::chrono::duration<double>(built - start).count());
    if (options.signedDistance) deviation.Print(stdout);
  }
  return 0;
}

/// Result rows of every point (invert).
struct ResultSink {
  const InvertOptions& options;
  std::unique_ptr<io::ResultWriter> writer;
  int dim = 3;

  void Open(const io::PointReader&, int pointDim) {
    dim = pointDim;
    io::ResultWriteOptions writeOptions;
    writeOptions.colorByDistance = options.color;
    if (options.signedDistance) {
      // The last column, and what the colours show.
      writeOptions.extraColumns = {"signed_distance"};
      writeOptions.signedColorColumn = 0;
    }
    writer = io::OpenResultWriter(options.output, dim, writeOptions);
  }
  void Write(const io::PointChunk& chunk, const Results& results, const double* signedDistances) {
    writer->WriteChunk(chunk.xyz.data(), chunk.count, results, chunk.firstIndex, signedDistances);
  }
  void Finish() { writer->Finish(); }
};

/// The input records of the points to keep (trim).
struct TrimSink {
  const InvertOptions& options;
  std::unique_ptr<io::TrimWriter> writer;
  std::vector<unsigned char> keep;

  void Open(const io::PointReader& reader, int) {
    writer = std::make_unique<io::TrimWriter>(options.output, reader.layout());
  }
  void Write(const io::PointChunk& chunk, const Results& results, const double* signedDistances) {
    keep.assign(chunk.count, 0);
    for (std::size_t i = 0; i < chunk.count; ++i) {
      // Found means within maxDistance; None means beyond it. Invalid
      // points have no distance and are in neither set. Signed: near is at
      // most maxDistance outside the solid (or inside it), far beyond that.
      const Status s = results.status[i];
      if (signedDistances) {
        const double d = signedDistances[i];
        keep[i] = !std::isnan(d) && (options.keepFar ? d > options.maxDistance : d <= options.maxDistance);
      } else {
        keep[i] = options.keepFar ? s == Status::None : s == Status::Found;
      }
    }
    writer->WriteChunk(chunk, keep.data());
  }
  void Finish() { writer->Finish(); }
};

/// The CAD model's part of `invmap info`.
void PrintCadInfo(const cad::ModelInfo& info) {
  std::printf("format      %s (units as the reader returns them: millimetres for STEP and IGES)\n", info.format.c_str());
  std::printf("solids      %zu\nshells      %zu", info.solids, info.shells);
  if (!info.openParts.empty()) {
    std::printf(" (not closed: %s", info.openParts.front().c_str());
    if (info.openParts.size() > 1) std::printf(" and %zu more", info.openParts.size() - 1);
    std::printf(")");
  }
  std::printf("\nfaces       %zu\n", info.faces);
  for (const auto& [type, count] : info.facesBySurface) std::printf("  %-20s %zu\n", type.c_str(), count);
  std::printf("edges       %zu\nvertices    %zu\n", info.edges, info.vertices);
  std::printf("model box   [%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]\n", info.boundsLo[0], info.boundsHi[0],
              info.boundsLo[1], info.boundsHi[1], info.boundsLo[2], info.boundsHi[2]);
  std::printf("approximated faces %zu", info.approximatedFaces.size());
  if (!info.approximatedFaces.empty()) {
    std::printf(" (aimed within %.3g, measured within %.3g):", info.approximationTolerance,
                info.approximationDeviation);
    for (int f : info.approximatedFaces) std::printf(" %d", f);
  }
  std::printf("\n");
}

}  // namespace

namespace {

/// The manifold `built` holds, or its failure thrown as LoadManifold
/// promises; an invalid geometry's error names the line `source` recorded
/// for it when there is one.
Manifold TakeManifold(BuildResult built, const std::string& path, const io::GeometrySource* source) {
  switch (built.code) {
    case Error::Ok:
      return std::move(built.manifold);
    case Error::InvalidArgument:
      if (source != nullptr) source->Check(built.problem);
      throw io::InputError(path, 0, built.error);
    case Error::OutOfMemory:
      throw std::bad_alloc();
    case Error::Internal:
      break;
  }
  throw std::runtime_error(built.error);
}

}  // namespace

Manifold LoadManifold(const std::string& path, void (*refuse)(const Geometry&, const std::string& path)) {
  io::GeometrySource source;
  Geometry geometry = io::ReadGeometryFile(path, &source);
  if (refuse) refuse(geometry, path);
  // The geometry is not needed after the build: a mesh's arrays are taken
  // rather than copied.
  return TakeManifold(Manifold::Build(std::move(geometry)), path, &source);
}

Manifold BuildManifold(const Geometry& geometry, const std::string& path) {
  return TakeManifold(Manifold::Build(geometry), path, nullptr);
}

int RunInvert(const InvertOptions& options) {
  if (options.allMinima) return RunInvertAllMinima(options);
  if (options.color && io::LowerExtension(options.output) != ".ply") {
    throw UsageError("--color colours .ply output; " + options.output + " is not a .ply file");
  }
  return Stream(options, false, "invert", ResultSink{options, nullptr});
}

int RunTrim(const InvertOptions& options) { return Stream(options, true, "trim", TrimSink{options, nullptr, {}}); }

int RunInfo(const std::string& geometry) {
  const LoadedGeometry loaded = LoadGeometry(geometry);
  const Manifold& manifold = loaded.manifold;
  const ManifoldInfo info = manifold.Info();
  std::printf("geometry    %s\n", geometry.c_str());
  if (loaded.cad) PrintCadInfo(loaded.cad->Info());
  std::printf("dimension   %d\n", info.dimension);
  std::printf("patches     %zu\n", info.patches);
  std::printf("cells       %zu\n", info.cells);
  for (const auto& [shape, count] : info.cellsByShape) std::printf("  %-20s %zu\n", shape.c_str(), count);
  std::printf("bounds      [%.6g, %.6g] x [%.6g, %.6g]", info.boundsLo[0], info.boundsHi[0], info.boundsLo[1],
              info.boundsHi[1]);
  if (info.dimension == 3) std::printf(" x [%.6g, %.6g]", info.boundsLo[2], info.boundsHi[2]);
  std::printf("\nmemory      %.2f MB (cells, distance bounds and BVH)\n", info.memoryBytes / 1048576.0);
  return 0;
}

}  // namespace invmap::cli
