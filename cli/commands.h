// The subcommands of `invmap` (docs/cli.md). Each returns the
// process exit code; input and output errors are thrown as io::InputError
// and mapped to exit codes 3 and 4 by main.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace CLI {
class App;
}  // namespace CLI

namespace invmap::cli {

/// Options shared by invert and trim.
struct InvertOptions {
  std::string geometry;
  std::string points;
  std::string output;
  double maxDistance = std::numeric_limits<double>::infinity();
  int threads = 0;
  bool quiet = false;
  /// invert, .ply output: colour the points by distance (viridis).
  bool color = false;
  /// trim: keep the points within maxDistance ("near") or beyond it ("far").
  bool keepFar = false;
  /// CAD solids: the signed distance, negative inside (invert: an extra
  /// column and the deviation summary; trim: near is signed distance <=
  /// maxDistance, inside included).
  bool signedDistance = false;
  /// invert --signed: the band +-tolerance whose share the summary gives.
  double tolerance = std::numeric_limits<double>::infinity();
  /// Each point's answer a function of the point and the geometry only
  /// (InversionOptions::pointwise).
  bool pointwise = false;
  /// invert: every local minimum of each point's distance (RunInvertAllMinima).
  bool allMinima = false;
};

/// The geometry file at `path`, read and built. A malformed file, whether the
/// reader or Manifold::Build finds the problem, throws io::InputError naming
/// the file and the line it came from (for the formats that record lines;
/// exit code 3); a lack of memory throws std::bad_alloc, a bug
/// std::runtime_error (both exit code 1). `refuse`, when given, sees the
/// geometry before it is built and throws io::InputError for what the
/// command cannot take.
Manifold LoadManifold(const std::string& path, void (*refuse)(const Geometry&, const std::string& path) = nullptr);

/// `geometry`, read from `path`, built (errors as LoadManifold's).
Manifold BuildManifold(const Geometry& geometry, const std::string& path);

int RunInvert(const InvertOptions& options);
/// invert --all-minima: every local minimum of each point's distance, one
/// row each (docs/distance.md).
int RunInvertAllMinima(const InvertOptions& options);
int RunTrim(const InvertOptions& options);
int RunInfo(const std::string& geometry);

/// `invmap generate <what>`: a sample geometry or a point cloud.
struct GenerateOptions {
  std::string what;    ///< surface, torus, curve, tets, trimesh, bracket, points or scan.
  std::string output;
  int spans = 32;                      ///< surface: knot spans per direction.
  int resolution = 6;                  ///< tets: cubes per direction (6 tets each).
  std::int64_t triangles = 1000000;    ///< trimesh: at least this many triangles.
  std::string geometry;                ///< points, scan: the geometry to sample around.
  std::int64_t count = 100000;         ///< points: how many.
  std::string kind = "near";           ///< points: near, far, inside or box.
  double spread = 0.01;                ///< points, near: largest offset, relative to the geometry's size.
  std::uint64_t seed = 1;
  /// scan: measurement noise (standard deviation) and the part's growth at
  /// the top of its box, relative to the model's size (NaN: 1e-4 and 5e-4).
  double noise = std::numeric_limits<double>::quiet_NaN();
  double warp = std::numeric_limits<double>::quiet_NaN();
};

int RunGenerate(const GenerateOptions& options);

/// `invmap grid`: an adaptive simplicial grid for an implicit complex
/// (docs/grids.md).
struct GridCommandOptions {
  std::string functions;
  std::string mode = "arrangement";  ///< arrangement, material or csg.
  std::string tree;                  ///< csg: the tree file.
  double epsilon = 1e-4;
  std::string grid;                  ///< An initial .msh grid, or empty for the box.
  std::vector<double> box;           ///< 4 (2D) or 6 (3D) numbers: the low corner, then the high one.
  int resolution = 1;
  std::int64_t maxCells = std::numeric_limits<std::int64_t>::max();
  int threads = 0;
  std::string output;                ///< The output directory.
  bool quiet = false;
};

int RunGrid(const GridCommandOptions& options);

/// `invmap manifold`: a partition-of-unity surface over a closed triangle
/// mesh (docs/manifold.md).
struct ManifoldOptions {
  std::string mesh;
  std::string base = "loop";   ///< flat, pn or loop.
  int degree = 0;              ///< 0: automatic.
  std::string output;
  std::string tessellate;      ///< Optional .ply output.
  int resolution = 8;          ///< Tessellation: segments along each mesh edge.
  bool quiet = false;
};

int RunManifold(const ManifoldOptions& options);

/// `invmap probe`: node fields at the closest points (docs/fields.md).
struct ProbeOptions {
  std::string geometry;
  std::string points;
  std::string output;
  std::vector<std::string> fields;  ///< --fields; empty: every field.
  double maxDistance = std::numeric_limits<double>::infinity();
  int threads = 0;
  std::int64_t timeStep = 0;        ///< Exodus: 1-based time step; 0: the last.
  bool quiet = false;
};

int RunProbe(const ProbeOptions& options);
/// Adds the `probe` subcommand and its options to `app`.
CLI::App* AddProbeCommand(CLI::App* app, ProbeOptions* options);

/// `invmap distance` (docs/distance.md): AddDistanceCommand registers
/// the subcommand and its options on `app`; RunDistance runs it once parsed.
CLI::App* AddDistanceCommand(CLI::App* app);
int RunDistance();

}  // namespace invmap::cli
