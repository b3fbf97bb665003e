// invmap_bench_implicit: implicit-complex grids against the reference
// implementation's published figures (examples/data/implicit, the table of
// docs/benchmarks.md, implicit-complex grids): same functions, initial grid
// cube6.msh and epsilon. Prints a Markdown table (and writes a CSV) of cell
// counts, their difference from the reference and the refinement time with
// 1 and 2 threads (best of --repeat runs; the refinement only, timed as the
// reference times it).
//
//   invmap_bench_implicit [--data DIR] [--repeat N] [--csv FILE] [--smoke]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "implicit_io/csg_tree_file.h"
#include "implicit_io/function_list.h"
#include "implicit_io/initial_grid.h"
#include "invmap/implicit.h"

namespace {

using invmap::implicit::Mode;

struct Case {
  const char* functions;
  const char* tree;
  Mode mode;
  double epsilon;
  long long referenceCells;
  long long referenceActive;
  double referenceSeconds;  ///< 0: not published.
};

// The reference implementation's published figures (single thread, 2-core machine of this kind).
const Case kCases[] = {
    {"1-sphere.json", nullptr, Mode::Arrangement, 1e-2, 2942, 1537, 0.02},
    {"1-sphere.json", nullptr, Mode::Arrangement, 1e-3, 30218, 14636, 0.30},
    {"1-sphere.json", nullptr, Mode::Arrangement, 1e-4, 288555, 135671, 2.2},
    {"2-close-sphere.json", nullptr, Mode::Arrangement, 1e-3, 30995, 15512, 0.4},
    {"3-sphere.json", nullptr, Mode::Arrangement, 1e-3, 26084, 13572, 0.4},
    {"3-cyl3.json", nullptr, Mode::Arrangement, 1e-3, 20496, 10916, 0},
    {"2-cylSphere.json", nullptr, Mode::Arrangement, 1e-3, 57196, 29961, 0},
    {"10-wikiBall.json", nullptr, Mode::Arrangement, 5e-4, 270631, 155424, 3.3},
    {"10-wikiBall.json", "10-wikiBall-tree.json", Mode::Csg, 5e-4, 107140, 52398, 1.6},
    {"18-sphere.json", nullptr, Mode::Arrangement, 1e-4, 1510911, 888664, 21},
    {"18-sphere.json", nullptr, Mode::MaterialInterface, 1e-4, 905468, 405119, 9.7},
};

const char* ModeName(Mode mode) {
  switch (mode) {
    case Mode::Arrangement:
      return "arrangement";
    case Mode::MaterialInterface:
      return "material interface";
    case Mode::Csg:
      return "CSG";
  }
  return "";
}

double PercentDifference(long long ours, long long reference) {
  return 100.0 * static_cast<double>(ours - reference) / static_cast<double>(reference);
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = INVMAP_IMPLICIT_DATA_DIR;
  std::string csvPath;
  int repeat = 3;
  bool smoke = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--data") && i + 1 < argc) {
      data = argv[++i];
    } else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) {
      csvPath = argv[++i];
    } else if (!std::strcmp(argv[i], "--smoke")) {
      smoke = true;
    } else {
      std::fprintf(stderr, "usage: %s [--data DIR] [--repeat N] [--csv FILE] [--smoke]\n", argv[0]);
      return 2;
    }
  }
  std::FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
  if (!csvPath.empty() && !csv) {
    std::fprintf(stderr, "cannot write %s\n", csvPath.c_str());
    return 4;
  }
  if (csv)
    std::fprintf(csv,
                 "functions,mode,epsilon,cells,reference_cells,active_cells,reference_active_cells,"
                 "seconds_1_thread,seconds_2_threads,reference_seconds\n");
  std::printf("| functions | mode | epsilon | cells (ref.) | diff | active (ref.) | diff | 1 thread | 2 threads | "
              "reference | speed-up 1 thread |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  const invmap::implicit::SimplexMesh initial = invmap::io::ReadSimplexMeshMsh(data + "/cube6.msh");
  for (const Case& c : kCases) {
    if (smoke && c.referenceCells > 50000) continue;
    const std::vector<invmap::implicit::Function> functions = invmap::io::ReadFunctionList(data + "/" + c.functions, 3);
    invmap::implicit::GridOptions options;
    options.mode = c.mode;
    options.epsilon = c.epsilon;
    if (c.tree) options.tree = invmap::io::ReadCsgTree(data + "/" + c.tree, static_cast<int>(functions.size()));
    double best[2] = {1e300, 1e300};
    invmap::implicit::GridStats stats;
    for (int threads = 1; threads <= 2; ++threads) {
      options.threads = threads;
      for (int r = 0; r < (smoke ? 1 : repeat); ++r) {
        const invmap::implicit::GridResult result = invmap::implicit::RefineGrid(initial, functions, options);
        if (!result.error.empty()) {
          std::fprintf(stderr, "%s: %s\n", c.functions, result.error.c_str());
          return 1;
        }
        stats = result.grid.stats;
        best[threads - 1] = std::min(best[threads - 1], stats.seconds);
      }
    }
    char reference[32] = "-", speedup[32] = "-";
    if (c.referenceSeconds > 0) {
      std::snprintf(reference, sizeof reference, "%.2f s", c.referenceSeconds);
      std::snprintf(speedup, sizeof speedup, "%.1fx", c.referenceSeconds / best[0]);
    }
    std::printf("| %s%s%s | %s | %g | %lld (%lld) | %+.3f%% | %lld (%lld) | %+.3f%% | %.3f s | %.3f s | %s | %s |\n",
                c.functions, c.tree ? " + " : "", c.tree ? c.tree : "", ModeName(c.mode), c.epsilon,
                static_cast<long long>(stats.cells), c.referenceCells,
                PercentDifference(stats.cells, c.referenceCells), static_cast<long long>(stats.activeCells),
                c.referenceActive, PercentDifference(stats.activeCells, c.referenceActive), best[0], best[1],
                reference, speedup);
    std::fflush(stdout);
    if (csv)
      std::fprintf(csv, "%s,%s,%g,%lld,%lld,%lld,%lld,%.6f,%.6f,%g\n", c.functions, ModeName(c.mode), c.epsilon,
                   static_cast<long long>(stats.cells), c.referenceCells, static_cast<long long>(stats.activeCells),
                   c.referenceActive, best[0], best[1], c.referenceSeconds);
  }
  if (csv) std::fclose(csv);
  return 0;
}
