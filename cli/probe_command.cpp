// invmap probe: the fields given at a geometry's nodes, at the closest
// point of every query point (docs/fields.md).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/path_checks.h"
#include "cli/run_summary.h"
#include "invmap/fields.h"
#include "io/field_geometry_file.h"
#include "io/file_io.h"
#include "io/input_error.h"
#include "io/point_reader.h"
#include "io/result_writer.h"

namespace invmap::cli {
namespace {

/// Points per chunk, as `invert` streams them: the rows of a chunk are
/// exactly `invert`'s for the same points.
constexpr std::size_t kProbeChunkPoints = 1 << 18;

/// The fields of `model` that --fields names, in that order; all of them
/// when it names none. An unknown name is a usage error (false, message
/// printed).
bool SelectFields(const FieldGeometry& model, const ProbeOptions& options, std::vector<const NodeField*>* selected) {
  if (options.fields.empty()) {
    for (const NodeField& field : model.fields) selected->push_back(&field);
    return true;
  }
  for (const std::string& name : options.fields) {
    const NodeField* found = nullptr;
    for (const NodeField& field : model.fields) {
      if (field.name == name) found = &field;
    }
    if (found == nullptr) {
      std::ostringstream known;
      for (const NodeField& field : model.fields) known << (known.tellp() > 0 ? ", " : "") << field.name;
      std::fprintf(stderr, "invmap probe: %s has no field '%s' (its fields: %s)\n", options.geometry.c_str(),
                   name.c_str(), known.str().c_str());
      return false;
    }
    selected->push_back(found);
  }
  return true;
}

}  // namespace

CLI::App* AddProbeCommand(CLI::App* app, ProbeOptions* options) {
  CLI::App* command = app->add_subcommand("probe", "node fields of the geometry at the closest point of every point");
  command->add_option("--geometry,-g", options->geometry, "geometry with node fields (.msh, .vtu, .exo, .e)")
      ->required();
  command->add_option("--points,-p", options->points, "query points (.xyz, .txt, .csv, .ply, .npy)")->required();
  command->add_option("--output,-o", options->output, "output file (.csv, .ply, .npy)")->required();
  command->add_option("--fields", options->fields, "comma-separated field names (default: every field)")
      ->delimiter(',');
  command->add_option("--max-distance", options->maxDistance, "points farther than this are not found")
      ->check(NonNegativeNumber());
  command->add_option("--threads", options->threads, "worker threads (default: all cores)")
      ->check(NonNegativeNumber());
  command->add_option("--time-step", options->timeStep, "Exodus: the time step of the nodal variables, from 1 "
                                                         "(default: the last)")
      ->check(PositiveInteger());
  command->add_flag("--quiet,-q", options->quiet, "no progress bar and no summary");
  return command;
}

int RunProbe(const ProbeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CheckInversionPaths(options.geometry, options.points, options.output, false);
  const std::string ext = io::LowerExtension(options.geometry);
  if (options.timeStep != 0 && ext != ".exo" && ext != ".e") {
    std::fprintf(stderr, "invmap probe: --time-step applies to Exodus files (.exo, .e); %s has one step per view\n",
                 options.geometry.c_str());
    return 2;
  }
  io::FieldReadOptions readOptions;
  readOptions.timeStep = options.timeStep;
  const FieldGeometry model = io::ReadGeometryWithFields(options.geometry, readOptions);
  if (model.fields.empty()) {
    throw io::InputError(options.geometry, 0,
                         "no node fields to probe (probe reads gmsh $NodeData, VTU point data and Exodus nodal "
                         "variables)");
  }
  std::vector<const NodeField*> fields;
  if (!SelectFields(model, options, &fields)) return 2;

  const Manifold manifold = BuildManifold(model.geometry, options.geometry);
  const auto built = std::chrono::steady_clock::now();
  const int dim = model.geometry.dimension;

  io::PointReadOptions pointOptions;
  pointOptions.forcedDim = dim;
  std::unique_ptr<io::PointReader> reader = io::OpenPointReader(options.points, pointOptions);
  io::ResultWriteOptions writeOptions;
  writeOptions.extraColumns = FieldColumnNames(fields);
  std::unique_ptr<io::ResultWriter> writer = io::OpenResultWriter(options.output, dim, writeOptions);
  InversionOptions inversion;
  inversion.maxDistance = options.maxDistance;
  inversion.threads = options.threads;

  Progress progress(options.quiet, reader->totalCountHint());
  RunSummary summary;
  io::PointChunk chunk;
  Results results;
  std::vector<double> values;
  std::string message;
  while (reader->ReadChunk(kProbeChunkPoints, &chunk)) {
    Error error = manifold.Invert(PointsView::Interleaved(chunk.xyz.data(), chunk.count, dim), inversion, &results,
                                  &message);
    if (error == Error::Ok) error = ProbeFields(model.geometry, fields, results, &values, &message, options.threads);
    if (error != Error::Ok) throw std::runtime_error(message);
    writer->WriteChunk(chunk.xyz.data(), chunk.count, results, chunk.firstIndex, values.data());
    summary.Add(results, chunk.count);
    progress.Update(summary.points());
  }
  writer->Finish();
  progress.Done();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.quiet) {
    std::printf("invmap probe: %s onto %s -> %s (%zu field columns)\n", options.points.c_str(),
                options.geometry.c_str(), options.output.c_str(), writeOptions.extraColumns.size());
    summary.Print(stdout, seconds, std::chrono::duration<double>(built - start).count());
  }
  return 0;
}

}  // namespace invmap::cli
