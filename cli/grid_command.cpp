// invmap grid: an adaptive simplicial grid for the zero sets of implicit
// functions, written as grid.msh, grid.vtu, zero_sets.obj, zero_sets.ply and
// stats.json in the output directory (docs/grids.md, Outputs).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "cli/commands.h"
#include "implicit_io/csg_tree_file.h"
#include "implicit_io/function_list.h"
#include "implicit_io/grid_writers.h"
#include "implicit_io/initial_grid.h"
#include "implicit_io/zero_set_writers.h"
#include "invmap/implicit.h"
#include "io/input_error.h"

namespace invmap::cli {
namespace {

implicit::Mode ParseMode(const std::string& mode) {
  if (mode == "material") return implicit::Mode::MaterialInterface;
  if (mode == "csg") return implicit::Mode::Csg;
  return implicit::Mode::Arrangement;
}

/// The initial box grid; false (with a message) when the corners are not ordered.
bool MakeBox(const GridCommandOptions& options, implicit::SimplexMesh* mesh) {
  const int dimension = options.box.size() == 6 ? 3 : 2;
  implicit::Vec3 lo = {0, 0, 0}, hi = {0, 0, 0};
  for (int a = 0; a < dimension; ++a) {
    lo[a] = options.box[a];
    hi[a] = options.box[dimension + a];
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || !(lo[a] < hi[a])) {
      std::fprintf(stderr, "invmap grid: --box: the low corner must be below the high one on every axis\n");
      return false;
    }
  }
  *mesh = implicit::SimplexMesh::Box(lo, hi, dimension, options.resolution);
  return true;
}

/// Writes every output file, or none: a failure removes those already written.
void WriteOutputs(const GridCommandOptions& options, const implicit::Grid& grid, const implicit::ZeroSets& zeroSets,
                  const std::vector<std::string>& names) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(options.output, error);
  if (error || !fs::is_directory(options.output))
    throw io::InputError(options.output, 0, "cannot create the output directory", io::InputError::Kind::Output);
  const fs::path dir(options.output);
  // Files of an earlier run would mix with this one's if a write failed
  // halfway: none of the set survives a failure.
  const char* const kOutputs[] = {"grid.msh", "grid.vtu", "zero_sets.obj", "zero_sets.ply", "stats.json"};
  auto removeAll = [&] {
    for (const char* name : kOutputs) fs::remove(dir / name, error);
  };
  try {
    auto write = [&](const char* name, auto&& writer) {
      const fs::path path = dir / name;
      writer(path.string());
    };
    write("grid.msh", [&](const std::string& path) { io::WriteGridMsh(grid, names, path); });
    write("grid.vtu", [&](const std::string& path) { io::WriteGridVtu(grid, names, path); });
    write("zero_sets.obj", [&](const std::string& path) { io::WriteZeroSetsObj(zeroSets, path); });
    if (grid.mesh.dimension == 3)
      write("zero_sets.ply", [&](const std::string& path) { io::WriteZeroSetsPly(zeroSets, path); });
    write("stats.json", [&](const std::string& path) { io::WriteGridStats(grid.stats, path); });
  } catch (...) {
    removeAll();
    throw;
  }
  // A 2D run writes no PLY: drop an earlier run's.
  if (grid.mesh.dimension != 3) fs::remove(dir / "zero_sets.ply", error);
}

void PrintSummary(const implicit::Grid& grid, const implicit::ZeroSets& zeroSets, double epsilon) {
  const implicit::GridStats& s = grid.stats;
  std::printf("grid: %lld cells (%lld active), %lld vertices, epsilon %g, %.3f s refining%s\n",
              static_cast<long long>(s.cells), static_cast<long long>(s.activeCells),
              static_cast<long long>(s.vertices), epsilon, s.seconds,
              s.reachedMaxCells ? " (stopped at --max-cells: coarser than epsilon)" : "");
  std::printf("min radius ratio: %.4f (all cells), %.4f (active cells)\n", s.minRadiusRatio, s.minRadiusRatioActive);
  std::printf("zero sets: %zu triangles, %zu segments, %zu points\n", zeroSets.triangles.size() / 3,
              zeroSets.segments.size() / 2, zeroSets.points.size());
  if (s.activeCells == 0) std::printf("note: no zero set crosses the grid (no active cell)\n");
}

}  // namespace

int RunGrid(const GridCommandOptions& options) {
  if (!(options.epsilon > 0) || !std::isfinite(options.epsilon)) {
    std::fprintf(stderr, "invmap grid: --epsilon must be a positive number\n");
    return 2;
  }
  implicit::GridOptions gridOptions;
  gridOptions.mode = ParseMode(options.mode);
  gridOptions.epsilon = options.epsilon;
  gridOptions.maxCells = options.maxCells;
  gridOptions.threads = options.threads;

  implicit::SimplexMesh initial;
  if (!options.grid.empty()) {
    initial = io::ReadSimplexMeshMsh(options.grid);
  } else if (!MakeBox(options, &initial)) {
    return 2;
  }
  const std::vector<implicit::Function> functions = io::ReadFunctionList(options.functions, initial.dimension);
  if (gridOptions.mode == implicit::Mode::Csg)
    gridOptions.tree = io::ReadCsgTree(options.tree, static_cast<int>(functions.size()));

  const implicit::GridResult result = implicit::RefineGrid(initial, functions, gridOptions);
  if (!result.error.empty()) throw io::InputError(options.functions, 0, result.error);
  const implicit::ZeroSets zeroSets = implicit::ExtractZeroSets(result.grid, gridOptions);

  std::vector<std::string> names;
  for (const implicit::Function& function : functions) names.push_back(function.name);
  WriteOutputs(options, result.grid, zeroSets, names);
  if (!options.quiet) PrintSummary(result.grid, zeroSets, options.epsilon);
  return 0;
}

}  // namespace invmap::cli
