// invmap distance: the minimum distance between two models under rigid
// poses, for one pose of B or a list of them (docs/cli.md, docs/distance.md).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/path_checks.h"
#include "cli/run_summary.h"
#include "invmap/distance.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"

namespace invmap::cli {
namespace {

struct DistanceCommandOptions {
  std::string a, b;
  std::string poseA, poseB, posesB;
  std::string output;
  double maxDistance = std::numeric_limits<double>::infinity();
  bool allMinima = false;
  int threads = 0;
  bool quiet = false;
};

DistanceCommandOptions& Options() {
  static DistanceCommandOptions options;
  return options;
}

/// The 12 numbers of a pose: separated by commas (and optional white
/// space). False when there are not exactly 12 finite numbers.
bool ParsePose(std::string_view text, Pose* pose, std::string* why) {
  std::vector<double> values;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view token = text.substr(start, end - start);
    while (!token.empty() && (token.front() == ' ' || token.front() == '\t')) token.remove_prefix(1);
    while (!token.empty() && (token.back() == ' ' || token.back() == '\t' || token.back() == '\r')) {
      token.remove_suffix(1);
    }
    double value = 0.0;
    if (token.empty()) {
      *why = "an empty number at position " + std::to_string(values.size() + 1) +
             " (expected 12 comma-separated numbers)";
      return false;
    }
    if (!io::ParseDouble(token, &value) || !std::isfinite(value)) {
      *why = "'" + std::string(token) + "' is not a finite number";
      return false;
    }
    values.push_back(value);
    start = end + 1;
  }
  if (values.size() != 12) {
    *why = "expected 12 comma-separated numbers r00,r01,r02,tx,r10,...,tz, found " + std::to_string(values.size());
    return false;
  }
  *pose = Pose::FromRows(values.data());
  return true;
}

/// The poses of --poses-b: one line each; blank lines and lines starting
/// with '#' are skipped. A bad line is an input error naming it.
std::vector<Pose> ReadPoses(const std::string& path, std::vector<std::int64_t>* lines) {
  io::InputBuffer in(path);
  std::vector<Pose> poses;
  std::string_view line;
  while (in.ReadLine(&line)) {
    std::string_view trimmed = line;
    while (!trimmed.empty() && (trimmed.front() == ' ' || trimmed.front() == '\t')) trimmed.remove_prefix(1);
    while (!trimmed.empty() && (trimmed.back() == ' ' || trimmed.back() == '\t' || trimmed.back() == '\r')) {
      trimmed.remove_suffix(1);
    }
    if (trimmed.empty() || trimmed.front() == '#') continue;
    Pose pose;
    std::string why;
    if (!ParsePose(trimmed, &pose, &why)) throw io::InputError(path, in.lineNumber(), why);
    poses.push_back(pose);
    lines->push_back(in.lineNumber());
  }
  if (poses.empty()) throw io::InputError(path, 0, "no poses (one line of 12 comma-separated numbers per pose)");
  return poses;
}

/// A geometry file read and built (cli::LoadManifold), on the heap.
std::unique_ptr<Manifold> LoadModel(const std::string& path) { return std::make_unique<Manifold>(LoadManifold(path)); }

/// A number as JSON: %.17g (round-trips a double); null when not finite.
std::string Number(double value) {
  if (!std::isfinite(value)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string PointJson(const ModelPoint& point, int dimension) {
  std::string out = "{\"patch\": " + std::to_string(point.patch) + ", \"cell\": " + std::to_string(point.cell) +
                    ", \"params\": [";
  bool first = true;
  for (const double p : point.params) {
    if (std::isnan(p)) continue;
    out += (first ? "" : ", ") + Number(p);
    first = false;
  }
  out += "], \"point\": [";
  for (int k = 0; k < dimension; ++k) out += (k ? ", " : "") + Number(point.point[k]);
  return out + "]}";
}

/// One answer's fields (without braces): distance, a, b, certified.
std::string AnswerFields(const DistanceAnswer& answer, int dimension) {
  if (!answer.found) {
    return "\"distance\": null, \"a\": null, \"b\": null, \"certified\": " +
           std::string(answer.certified ? "true" : "false");
  }
  return "\"distance\": " + Number(answer.distance) + ", \"a\": " + PointJson(answer.a, dimension) +
         ", \"b\": " + PointJson(answer.b, dimension) + ", \"certified\": " + (answer.certified ? "true" : "false");
}

/// A result's fields: the nearest answer and, with all minima, the list.
std::string ResultFields(const DistanceResult& result, int dimension, bool allMinima, const char* indent) {
  std::string out = AnswerFields(result.nearest, dimension);
  if (allMinima) {
    out += ", \"minima\": [";
    for (std::size_t i = 0; i < result.minima.size(); ++i) {
      out += (i ? ",\n" : "\n") + std::string(indent) + "  {" + AnswerFields(result.minima[i], dimension) + "}";
    }
    out += result.minima.empty() ? "]" : "\n" + std::string(indent) + "]";
  }
  return out;
}

/// Writes `text` to --output (atomically) or stdout.
void Emit(const std::string& text, const std::string& output) {
  if (output.empty()) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
    return;
  }
  io::AtomicOutput file(output);
  file.Write(text);
  file.Commit();
}

/// Throws the usage error of a pose option that does not parse or is not rigid.
Pose PoseOption(const std::string& text, const char* option, int dimension) {
  Pose pose;
  if (text.empty()) return pose;
  std::string why;
  if (!ParsePose(text, &pose, &why)) throw UsageError(std::string(option) + ": " + why);
  why = CheckPose(pose, dimension);
  if (!why.empty()) throw UsageError(std::string(option) + ": " + why);
  return pose;
}

int Run(const DistanceCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.output.empty()) {
    RefuseOutputOverInput(options.output, options.a, "--a");
    RefuseOutputOverInput(options.output, options.b, "--b");
    if (!options.posesB.empty()) RefuseOutputOverInput(options.output, options.posesB, "--poses-b");
    RequireOutputExtension(options.output, ".json", "distance", "--output");
    CheckWritable(options.output);
  }
  std::vector<Pose> poses;
  std::vector<std::int64_t> poseLines;
  if (!options.posesB.empty()) poses = ReadPoses(options.posesB, &poseLines);
  const std::unique_ptr<Manifold> manifoldA = LoadModel(options.a);
  const std::unique_ptr<Manifold> manifoldB = LoadModel(options.b);
  const int dimension = manifoldA->Info().dimension;
  if (manifoldB->Info().dimension != dimension) {
    throw io::InputError(options.b, 0,
                         "the models' dimensions differ (" + options.a + " is " + std::to_string(dimension) +
                             "D, " + options.b + " " + std::to_string(manifoldB->Info().dimension) + "D)");
  }
  const Pose poseA = PoseOption(options.poseA, "--pose-a", dimension);
  const Pose poseB = PoseOption(options.poseB, "--pose-b", dimension);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string why = CheckPose(poses[i], dimension);
    if (!why.empty()) throw io::InputError(options.posesB, poseLines[i], why);
  }
  DistanceModelBuild builtA = DistanceModel::Build(*manifoldA);
  if (!builtA.error.empty()) throw io::InputError(options.a, 0, builtA.error);
  DistanceModelBuild builtB = DistanceModel::Build(*manifoldB);
  if (!builtB.error.empty()) throw io::InputError(options.b, 0, builtB.error);

  DistanceOptions distanceOptions;
  distanceOptions.maxDistance = options.maxDistance;
  distanceOptions.allMinima = options.allMinima;
  distanceOptions.threads = options.threads;
  std::string text;
  std::string message;
  if (poses.empty()) {
    DistanceResult result;
    if (Distance(builtA.model, poseA, builtB.model, poseB, distanceOptions, &result, &message) != Error::Ok) {
      throw std::runtime_error(message);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    text = "{" + ResultFields(result, dimension, options.allMinima, "") + ", \"seconds\": " + Number(seconds) + "}\n";
  } else {
    // B moves: each pose starts from the previous answer (DistanceTracker).
    DistanceTracker tracker(builtA.model, builtB.model, poseA, distanceOptions);
    Progress progress(options.quiet, static_cast<std::int64_t>(poses.size()));
    text = "{\"poses\": [";
    for (std::size_t i = 0; i < poses.size(); ++i) {
      DistanceResult result;
      if (tracker.Update(poses[i], &result, &message) != Error::Ok) throw std::runtime_error(message);
      text += (i ? ",\n  {" : "\n  {") + ResultFields(result, dimension, options.allMinima, "  ") + "}";
      progress.Update(static_cast<std::int64_t>(i + 1));
    }
    progress.Done();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    text += "\n], \"seconds\": " + Number(seconds) + "}\n";
  }
  Emit(text, options.output);
  if (!options.quiet && !options.output.empty()) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("invmap distance: %s to %s, %zu pose%s -> %s (%.3f s)\n", options.a.c_str(), options.b.c_str(),
                poses.empty() ? std::size_t{1} : poses.size(), poses.size() == 1 || poses.empty() ? "" : "s",
                options.output.c_str(), seconds);
  }
  return 0;
}

}  // namespace

CLI::App* AddDistanceCommand(CLI::App* app) {
  DistanceCommandOptions& options = Options();
  CLI::App* command = app->add_subcommand("distance", "minimum distance between two models under rigid poses");
  command->add_option("--a", options.a, "model A: any geometry file invert reads")->required();
  command->add_option("--b", options.b, "model B")->required();
  command->add_option("--pose-a", options.poseA, "pose of A: 12 comma-separated numbers r00,r01,r02,tx,...,tz");
  auto* poseB = command->add_option("--pose-b", options.poseB, "pose of B (default identity)");
  auto* posesB = command->add_option("--poses-b", options.posesB, "file of poses of B, one per line, in time order");
  poseB->excludes(posesB);
  command->add_option("--max-distance", options.maxDistance, "models farther apart than this: distance null")
      ->check(NonNegativeNumber());
  command->add_flag("--all-minima", options.allMinima, "also list every local minimum of the distance");
  command->add_option("--output,-o", options.output, "output JSON file (default: stdout)");
  command->add_option("--threads", options.threads, "worker threads (default: all cores)")->check(NonNegativeNumber());
  command->add_flag("--quiet,-q", options.quiet, "no progress bar and no summary");
  return command;
}

int RunDistance() {
  try {
    return Run(Options());
  } catch (const UsageError& e) {
    std::fprintf(stderr, "invmap distance: %s\n", e.what());
    return 2;
  }
}

}  // namespace invmap::cli
