// invmap invert, trim and info: geometry in, points streamed through the engine.
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/run_summary.h"
#include "io/geometry_file.h"
#include "io/input_error.h"
#include "io/point_reader.h"
#include "io/result_writer.h"
#include "io/trim_writer.h"

namespace invmap::cli {
namespace {

/// Points per chunk: bounds memory for inputs of any size and sets how often
/// the progress bar moves.
constexpr std::size_t kChunkPoints = 1 << 20;

Manifold LoadManifold(const std::string& path) {
  const Geometry geometry = io::ReadGeometryFile(path);
  BuildResult built = Manifold::Build(geometry);
  if (!built.error.empty()) throw io::InputError(path, 0, built.error);
  return std::move(built.manifold);
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
void Stream(const InvertOptions& options, bool keepRaw, const char* verb, Sink&& sink) {
  const auto start = std::chrono::steady_clock::now();
  const Manifold manifold = LoadManifold(options.geometry);
  const int dim = manifold.Info().dimension;
  io::PointReadOptions readOptions;
  readOptions.forcedDim = dim;
  readOptions.keepRaw = keepRaw;
  std::unique_ptr<io::PointReader> reader = io::OpenPointReader(options.points, readOptions);
  InversionOptions inversion;
  inversion.maxDistance = options.maxDistance;
  inversion.threads = options.threads;

  sink.Open(*reader, dim);
  Progress progress(options.quiet, reader->totalCountHint());
  RunSummary summary;
  io::PointChunk chunk;
  Results results;
  while (reader->ReadChunk(kChunkPoints, &chunk)) {
    InvertChunk(manifold, chunk, dim, inversion, &results);
    sink.Write(chunk, results);
    summary.Add(results, chunk.count);
    progress.Update(summary.points());
  }
  sink.Finish();
  progress.Done();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.quiet) {
    std::printf("invmap %s: %s onto %s -> %s\n", verb, options.points.c_str(), options.geometry.c_str(),
                options.output.c_str());
    summary.Print(stdout, seconds);
  }
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
    writer = io::OpenResultWriter(options.output, dim, writeOptions);
  }
  void Write(const io::PointChunk& chunk, const Results& results) {
    writer->WriteChunk(chunk.xyz.data(), chunk.count, results, chunk.firstIndex);
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
  void Write(const io::PointChunk& chunk, const Results& results) {
    keep.assign(chunk.count, 0);
    for (std::size_t i = 0; i < chunk.count; ++i) {
      // Found means within maxDistance; None means beyond it. Invalid
      // points have no distance and are in neither set.
      const Status s = results.status[i];
      keep[i] = options.keepFar ? s == Status::None : s == Status::Found;
    }
    writer->WriteChunk(chunk, keep.data());
  }
  void Finish() { writer->Finish(); }
};

}  // namespace

int RunInvert(const InvertOptions& options) {
  if (options.allMinima) return RunInvertAllMinima(options);
  Stream(options, false, "invert", ResultSink{options, nullptr});
  return 0;
}

int RunTrim(const InvertOptions& options) {
  Stream(options, true, "trim", TrimSink{options, nullptr, {}});
  return 0;
}

int RunInfo(const std::string& geometry) {
  const Manifold manifold = LoadManifold(geometry);
  const ManifoldInfo info = manifold.Info();
  std::printf("geometry    %s\n", geometry.c_str());
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
