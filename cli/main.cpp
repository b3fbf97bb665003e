// invmap: the command line (docs/cli.md).
//   exit codes: 0 success, 2 usage error, 3 unreadable or invalid input,
//   4 output not writable, 1 internal error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <limits>
#include <new>

#include "cli/commands.h"
#include "cad/register_readers.h"
#include "cli/path_checks.h"
#include "fem/register_readers.h"
#include "invmap/invmap.h"
#include "cli/option_checks.h"
#include "io/file_io.h"
#include "io/input_error.h"

namespace {

void AddInvertOptions(CLI::App* command, invmap::cli::InvertOptions* options, bool distanceRequired) {
  command->add_option("--geometry,-g", options->geometry,
                      "geometry file (.json, .obj, .ply, .stl, .off, .msh; CAD: .step, .stp, .iges, .igs, .brep)")
      ->required();
  command->add_option("--points,-p", options->points, "query points (.xyz, .txt, .csv, .ply, .npy)")->required();
  command->add_option("--output,-o", options->output, "output file; the format follows its extension")->required();
  auto* distance = command->add_option("--max-distance", options->maxDistance,
                                       "gap tolerance: points farther than this from every cell are not found");
  distance->check(invmap::cli::NonNegativeNumber());
  if (distanceRequired) distance->required();
  command->add_option("--threads", options->threads, "worker threads (default: all cores)")->check(invmap::cli::NonNegativeNumber());
  command->add_flag("--quiet,-q", options->quiet, "no progress bar and no summary");
  command->add_flag("--signed", options->signedDistance,
                    "CAD solids: signed distance, negative inside (invert: extra column; trim: near keeps the inside)");
  command->add_flag("--pointwise", options->pointwise,
                    "answers bit for bit independent of the other points (slower; see docs/limitations.md)");
}

}  // namespace

int main(int argc, char** argv) {
  // An interrupted run leaves no temporary output behind.
  invmap::io::RemoveTemporaryFilesOnSignals();
  invmap::fem::RegisterFemReaders();
  invmap::cad::RegisterCadReaders();
  CLI::App app{"invmap: closest points, cells and parameters of point clouds on parametric geometry"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("invmap ") + invmap::Version());

  invmap::cli::InvertOptions invert;
  CLI::App* invertCommand = app.add_subcommand("invert", "closest point, cell, parameters and distance of every point");
  AddInvertOptions(invertCommand, &invert, false);
  auto* color = invertCommand->add_flag(
      "--color", invert.color,
      ".ply output: colour the points by distance (viridis; --signed: cool-warm, blue inside to red outside, centred on 0)");
  invertCommand->add_option("--tolerance", invert.tolerance, "--signed: report the share of points within +-T")
      ->check(invmap::cli::NonNegativeNumber())
      ->needs("--signed");
  invertCommand->add_flag("--all-minima", invert.allMinima, "every local minimum of each point's distance (.csv, .npy)")
      ->excludes("--signed")
      ->excludes(color);

  invmap::cli::InvertOptions trim;
  std::string keep = "near";
  CLI::App* trimCommand = app.add_subcommand("trim", "keep the input points within (or beyond) a distance");
  AddInvertOptions(trimCommand, &trim, true);
  trimCommand->add_option("--keep", keep, "near (distance <= D, default) or far (distance > D)")
      ->check(CLI::IsMember({"near", "far"}));

  std::string infoGeometry;
  CLI::App* infoCommand = app.add_subcommand("info", "patches, cells, bounds and memory of a geometry");
  infoCommand->add_option("--geometry,-g", infoGeometry, "geometry file")->required();

  invmap::cli::GenerateOptions generate;
  CLI::App* generateCommand = app.add_subcommand("generate", "write a sample geometry or a point cloud");
  generateCommand->add_option("what", generate.what,
                              "surface | torus | curve | tets | trimesh | bracket (STEP) | points | scan")
      ->required();
  generateCommand->add_option("--output,-o", generate.output, "output file")->required();
  generateCommand->add_option("--spans", generate.spans, "surface: knot spans per direction")->check(CLI::Range(1, 4096));
  generateCommand->add_option("--resolution", generate.resolution, "tets: cubes per direction")->check(CLI::Range(1, 200));
  generateCommand->add_option("--triangles", generate.triangles, "trimesh: at least this many triangles")
      ->check(CLI::Range(int64_t{20}, int64_t{200000000}));
  generateCommand->add_option("--geometry,-g", generate.geometry, "points, scan: geometry to sample (scan: a CAD model)");
  generateCommand->add_option("--count,-n", generate.count, "points: number of points")
      ->check(CLI::Range(int64_t{1}, int64_t{2000000000}));
  generateCommand->add_option("--kind", generate.kind, "points: near, far, inside or box")
      ->check(CLI::IsMember({"near", "far", "inside", "box"}));
  generateCommand->add_option("--spread", generate.spread, "points, near: largest offset relative to the size")
      ->check(invmap::cli::NonNegativeNumber());
  generateCommand->add_option("--seed", generate.seed, "random seed");
  generateCommand->add_option("--noise", generate.noise, "scan: measurement noise, relative to the size (default 1e-4)")
      ->check(invmap::cli::NonNegativeNumber());
  generateCommand->add_option("--warp", generate.warp,
                              "scan: the part's growth at its top, relative to the size (default 5e-4)");

  invmap::cli::GridCommandOptions grid;
  CLI::App* gridCommand =
      app.add_subcommand("grid", "refine a simplicial grid for the zero sets of implicit functions");
  gridCommand->add_option("--functions,-f", grid.functions, "function list (.json)")->required();
  gridCommand->add_option("--mode", grid.mode, "arrangement (default), material or csg")
      ->check(CLI::IsMember({"arrangement", "material", "csg"}));
  gridCommand->add_option("--tree", grid.tree, "csg: the CSG tree (.json)");
  gridCommand->add_option("--epsilon", grid.epsilon, "distance threshold in model units (default 1e-4)");
  auto* gridFile = gridCommand->add_option("--grid", grid.grid, "initial grid (.msh: linear tetrahedra or triangles)");
  auto* box = gridCommand->add_option("--box", grid.box, "initial box x0,y0[,z0],x1,y1[,z1]")->delimiter(',');
  gridFile->excludes(box);
  auto* resolution = gridCommand->add_option("--resolution", grid.resolution, "box: squares or cubes per side (default 1)")
      ->check(CLI::Range(1, 1000));
  gridFile->excludes(resolution);
  gridCommand->add_option("--max-cells", grid.maxCells, "stop refining at this many cells")
      ->check(CLI::Range(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()));
  gridCommand->add_option("--threads", grid.threads, "worker threads (default: all cores)")->check(invmap::cli::NonNegativeNumber());
  gridCommand->add_option("--output,-o", grid.output, "output directory")->required();
  gridCommand->add_flag("--quiet,-q", grid.quiet, "no summary");

  invmap::cli::ManifoldOptions manifold;
  std::string manifoldDegree = "auto";
  CLI::App* manifoldCommand =
      app.add_subcommand("manifold", "a smooth partition-of-unity surface over a closed triangle mesh");
  manifoldCommand->add_option("--mesh,-m", manifold.mesh, "closed triangle mesh (.obj, .ply, .off, .stl)")->required();
  manifoldCommand->add_option("--base", manifold.base, "surface the charts are fitted to: flat, pn or loop (default)")
      ->check(CLI::IsMember({"flat", "pn", "loop"}));
  manifoldCommand->add_option("--degree", manifoldDegree, "bidegree of the shape functions: auto (default) or 1 to 8");
  manifoldCommand->add_option("--output,-o", manifold.output, "the surface (.json)")->required();
  auto* tessellate = manifoldCommand->add_option("--tessellate", manifold.tessellate, "also write a triangle mesh of the surface (.ply)");
  manifoldCommand->add_option("--resolution", manifold.resolution, "tessellation: segments along each mesh edge (default 8)")
      ->check(CLI::Range(1, 1000))
      ->needs(tessellate);
  manifoldCommand->add_flag("--quiet,-q", manifold.quiet, "no summary");

  invmap::cli::ProbeOptions probe;
  CLI::App* probeCommand = invmap::cli::AddProbeCommand(&app, &probe);
  CLI::App* distanceCommand = invmap::cli::AddDistanceCommand(&app);

  // CLI11 says only "A subcommand is required" for a misspelt one.
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* command : app.get_subcommands({})) {
      known = known || command->check_name(argv[1]);
      names += (names.empty() ? "" : ", ") + command->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "invmap: unknown command '%s' (commands: %s)\nRun with --help for more information.\n",
                   argv[1], names.c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; a parse error is a usage
    // error, worded like every other message of the command.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "invmap: %s\nRun with --help for more information.\n", e.what());
    return 2;
  }

  try {
    if (*invertCommand) return invmap::cli::RunInvert(invert);
    if (*trimCommand) {
      trim.keepFar = keep == "far";
      return invmap::cli::RunTrim(trim);
    }
    if (*infoCommand) return invmap::cli::RunInfo(infoGeometry);
    if (*probeCommand) return invmap::cli::RunProbe(probe);
    if (*distanceCommand) return invmap::cli::RunDistance();
    if (*generateCommand) {
      if ((generate.what == "points" || generate.what == "scan") && generate.geometry.empty()) {
        std::fprintf(stderr, "invmap generate %s: --geometry is required\n", generate.what.c_str());
        return 2;
      }
      return invmap::cli::RunGenerate(generate);
    }
    if (*manifoldCommand) {
      if (manifoldDegree != "auto") {
        int degree = 0;
        if (!CLI::detail::lexical_cast(manifoldDegree, degree) || degree < 1 || degree > 8) {
          std::fprintf(stderr, "invmap manifold: --degree %s: expected auto or 1 to 8\n", manifoldDegree.c_str());
          return 2;
        }
        manifold.degree = degree;
      }
      return invmap::cli::RunManifold(manifold);
    }
    if (*gridCommand) {
      if (grid.grid.empty() && grid.box.empty()) {
        std::fprintf(stderr, "invmap grid: give --grid G.msh or --box x0,y0[,z0],x1,y1[,z1]\n");
        return 2;
      }
      if (!grid.box.empty() && grid.box.size() != 4 && grid.box.size() != 6) {
        std::fprintf(stderr, "invmap grid: --box needs 4 (2D) or 6 (3D) numbers, got %zu\n", grid.box.size());
        return 2;
      }
      if ((grid.mode == "csg") != !grid.tree.empty()) {
        std::fprintf(stderr, "invmap grid: --tree is required with --mode csg and only then\n");
        return 2;
      }
      return invmap::cli::RunGrid(grid);
    }
  } catch (const invmap::cli::UsageError& e) {
    std::fprintf(stderr, "invmap: %s\n", e.what());
    return 2;
  } catch (const invmap::io::InputError& e) {
    std::fprintf(stderr, "invmap: %s\n", e.what());
    return e.kind() == invmap::io::InputError::Kind::Output ? 4 : 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "invmap: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "invmap: %s\n", e.what());
    return 1;
  }
  return 0;
}
