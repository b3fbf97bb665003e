// invmap invert --all-minima: every local minimum of each point's distance
// (docs/distance.md), one row per minimum in invert's columns, nearest
// first, the point's index repeated; a point with none gets one `none` row.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/path_checks.h"
#include "cli/run_summary.h"
#include "invmap/distance.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"
#include "io/npy.h"
#include "io/point_reader.h"

namespace invmap::cli {
namespace {

constexpr std::size_t kChunkPoints = 1 << 16;

/// A number as invert's CSV writes it: %.17g, empty when NaN.
void AppendNumber(std::string* line, double value) {
  if (std::isnan(value)) return;
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  *line += text;
}

const char* StatusName(Status status) {
  return status == Status::Found ? "found" : status == Status::None ? "none" : "invalid";
}

/// Rows as CSV (invert's header and columns) or npy ((rows, 11) float64).
class MinimaWriter {
 public:
  MinimaWriter(const std::string& path, int dim, bool npy) : out_(path), dim_(dim), npy_(npy) {
    if (npy_) {
      out_.Write(io::FixedNpyHeader("<f8", 0, 11));
    } else {
      out_.Write("index,status,patch,cell,u,v,w,x,y,z,distance\n");
    }
  }

  void Row(std::int64_t index, const Results& results, std::size_t r) {
    const bool found = results.status[r] == Status::Found;
    if (npy_) {
      double values[11] = {static_cast<double>(index), static_cast<double>(results.status[r]),
                           static_cast<double>(results.patch[r]), static_cast<double>(results.cell[r])};
      for (int k = 0; k < 3; ++k) {
        values[4 + k] = results.params[3 * r + k];
        values[7 + k] = k < dim_ ? results.closest[3 * r + k] : std::nan("");
      }
      values[10] = results.distance[r];
      char bytes[sizeof values];
      for (int i = 0; i < 11; ++i) io::StoreLittleEndian(bytes + 8 * i, values[i]);
      out_.Write(bytes, sizeof bytes);
      ++rows_;
      return;
    }
    std::string line = std::to_string(index) + "," + StatusName(results.status[r]) + ",";
    line += std::to_string(found ? results.patch[r] : -1) + "," + std::to_string(found ? results.cell[r] : -1);
    for (int k = 0; k < 3; ++k) {
      line += ",";
      if (found) AppendNumber(&line, results.params[3 * r + k]);
    }
    for (int k = 0; k < 3; ++k) {
      line += ",";
      if (found && k < dim_) AppendNumber(&line, results.closest[3 * r + k]);
    }
    line += ",";
    if (found) AppendNumber(&line, results.distance[r]);
    line += "\n";
    out_.Write(line);
    ++rows_;
  }

  void Finish() {
    if (npy_) {
      const std::string header = io::FixedNpyHeader("<f8", rows_, 11);
      out_.WriteAt(0, header.data(), header.size());
    }
    out_.Commit();
  }

 private:
  io::AtomicOutput out_;
  int dim_;
  bool npy_;
  std::int64_t rows_ = 0;
};

/// --all-minima has no search over partition-of-unity surfaces: refused
/// (exit 3) rather than answered as if the surface were absent.
void RefusePouSurfaces(const Geometry& geometry, const std::string& path) {
  for (const Patch& patch : geometry.patches) {
    if (patch.kind == Patch::Kind::PouManifold) {
      throw io::InputError(path, 0,
                           "--all-minima: partition-of-unity surfaces (pou_manifold patches) have no search for "
                           "every local minimum yet");
    }
  }
}

}  // namespace

int RunInvertAllMinima(const InvertOptions& options) {
  RefuseOutputOverInput(options.output, options.points, "--points");
  RefuseOutputOverInput(options.output, options.geometry, "--geometry");
  const std::string extension = io::LowerExtension(options.output);
  if (extension != ".csv" && extension != ".npy") {
    std::fprintf(stderr, "invmap invert: --all-minima writes .csv or .npy (several rows per point), not '%s'\n",
                 extension.c_str());
    return 2;
  }
  io::PointFormatOf(options.points);  // an unknown point format before the geometry is read
  const auto start = std::chrono::steady_clock::now();
  const Manifold manifold = LoadManifold(options.geometry, RefusePouSurfaces);
  const int dim = manifold.Info().dimension;
  io::PointReadOptions readOptions;
  readOptions.forcedDim = dim;
  std::unique_ptr<io::PointReader> reader = io::OpenPointReader(options.points, readOptions);
  MinimaWriter writer(options.output, dim, extension == ".npy");
  InversionOptions inversion;
  inversion.maxDistance = options.maxDistance;
  inversion.threads = options.threads;
  Progress progress(options.quiet, reader->totalCountHint());
  io::PointChunk chunk;
  LocalMinimaResults results;
  std::int64_t points = 0, minima = 0, uncertified = 0;
  while (reader->ReadChunk(kChunkPoints, &chunk)) {
    std::string message;
    if (LocalMinima(manifold, PointsView::Interleaved(chunk.xyz.data(), chunk.count, dim), inversion, &results,
                    &message) != Error::Ok) {
      throw std::runtime_error(message);
    }
    for (std::size_t i = 0; i < chunk.count; ++i) {
      for (std::int64_t r = results.offsets[i]; r < results.offsets[i + 1]; ++r) {
        writer.Row(chunk.firstIndex + static_cast<std::int64_t>(i), results.minima, static_cast<std::size_t>(r));
        if (results.minima.status[r] == Status::Found) ++minima;
      }
      if (!results.certified[i]) ++uncertified;
    }
    points += static_cast<std::int64_t>(chunk.count);
    progress.Update(points);
  }
  writer.Finish();
  progress.Done();
  if (!options.quiet) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("invmap invert --all-minima: %s onto %s -> %s\n", options.points.c_str(), options.geometry.c_str(),
                options.output.c_str());
    std::printf("  points %lld, local minima %lld, not certified %lld, %.3f s\n", static_cast<long long>(points),
                static_cast<long long>(minima), static_cast<long long>(uncertified), seconds);
  }
  return 0;
}

}  // namespace invmap::cli
