// invmap._invmap._grid: adaptive grids for implicit complexes from Python
// (include/invmap/implicit.h). The package's grid() reads files and turns
// lists of dicts into JSON text; this half parses, refines without the GIL
// and returns numpy arrays.
#include "python/grid_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "implicit_io/csg_tree_file.h"
#include "implicit_io/function_list.h"
#include "implicit_io/initial_grid.h"
#include "invmap/implicit.h"
#include "io/input_error.h"
#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

template <typename T>
py::array_t<T> Array(const std::vector<T>& data, std::size_t rows, std::size_t columns) {
  py::array_t<T> out({rows, columns});
  if (!data.empty()) std::memcpy(out.mutable_data(), data.data(), data.size() * sizeof(T));
  return out;
}

py::array_t<int> Labels(const std::vector<std::array<int, 4>>& labels) {
  py::array_t<int> out({labels.size(), std::size_t{4}});
  for (std::size_t i = 0; i < labels.size(); ++i)
    for (int k = 0; k < 4; ++k) out.mutable_at(i, k) = labels[i][k];
  return out;
}

implicit::Mode ParseMode(const std::string& mode) {
  if (mode == "arrangement") return implicit::Mode::Arrangement;
  if (mode == "material") return implicit::Mode::MaterialInterface;
  if (mode == "csg") return implicit::Mode::Csg;
  throw InputError("grid: mode must be \"arrangement\", \"material\" or \"csg\", not \"" + mode + "\"");
}

py::dict Grid(const std::string& functionsText, const std::string& functionsName, const std::string& mode,
              const std::optional<std::string>& treeText, const std::string& treeName, double epsilon,
              const std::optional<std::vector<double>>& box, int resolution, const std::optional<std::string>& gridPath,
              std::int64_t maxCells, int threads) {
  implicit::GridResult result;
  implicit::ZeroSets zeroSets;
  std::vector<std::string> names;
  {
    py::gil_scoped_release noGil;
    implicit::GridOptions options;
    options.mode = ParseMode(mode);
    options.epsilon = epsilon;
    options.maxCells = maxCells;
    options.threads = threads;
    implicit::SimplexMesh initial;
    std::vector<implicit::Function> functions;
    try {
      if (options.mode == implicit::Mode::Csg && !treeText) throw InputError("grid: mode \"csg\" needs a tree");
      if (options.mode != implicit::Mode::Csg && treeText) throw InputError("grid: a tree is for mode \"csg\" only");
      if (maxCells < 1) throw InputError("grid: max_cells must be at least 1");
      if (gridPath) {
        initial = io::ReadSimplexMeshMsh(*gridPath);
      } else if (!box) {
        throw InputError("grid: give exactly one of box and initial_grid");
      } else {
        const std::vector<double>& b = *box;
        if (b.size() != 4 && b.size() != 6) throw InputError("grid: box needs 4 (2D) or 6 (3D) numbers");
        const int dimension = b.size() == 6 ? 3 : 2;
        implicit::Vec3 lo = {0, 0, 0}, hi = {0, 0, 0};
        for (int a = 0; a < dimension; ++a) {
          lo[a] = b[a];
          hi[a] = b[dimension + a];
          if (!(lo[a] < hi[a])) throw InputError("grid: box: the low corner must be below the high one on every axis");
        }
        if (resolution < 1) throw InputError("grid: resolution must be at least 1");
        initial = implicit::SimplexMesh::Box(lo, hi, dimension, resolution);
      }
      functions = io::ParseFunctionList(functionsText, functionsName, initial.dimension);
      if (options.mode == implicit::Mode::Csg)
        options.tree = io::ParseCsgTree(*treeText, treeName, static_cast<int>(functions.size()));
    } catch (const io::InputError& e) {
      throw InputError(e.what());
    }
    result = implicit::RefineGrid(initial, functions, options);
    if (!result.error.empty()) throw InputError("grid: " + result.error);
    zeroSets = implicit::ExtractZeroSets(result.grid, options);
    for (const implicit::Function& f : functions) names.push_back(f.name);
  }
  const implicit::Grid& grid = result.grid;
  const std::size_t corners = static_cast<std::size_t>(grid.mesh.dimension + 1);
  py::dict stats;
  stats["cells"] = grid.stats.cells;
  stats["active_cells"] = grid.stats.activeCells;
  stats["vertices"] = grid.stats.vertices;
  stats["min_radius_ratio"] = grid.stats.minRadiusRatio;
  stats["min_radius_ratio_active"] = grid.stats.minRadiusRatioActive;
  stats["seconds"] = grid.stats.seconds;
  stats["reached_max_cells"] = grid.stats.reachedMaxCells;
  py::dict zero;
  zero["vertices"] = Array(zeroSets.vertices, zeroSets.vertices.size() / 3, 3);
  zero["triangles"] = Array(zeroSets.triangles, zeroSets.triangles.size() / 3, 3);
  zero["triangle_labels"] = Labels(zeroSets.triangleLabels);
  zero["segments"] = Array(zeroSets.segments, zeroSets.segments.size() / 2, 2);
  zero["segment_labels"] = Labels(zeroSets.segmentLabels);
  zero["points"] = Array(zeroSets.points, zeroSets.points.size(), 1).attr("reshape")(-1);
  zero["point_labels"] = Labels(zeroSets.pointLabels);
  py::dict out;
  out["dimension"] = grid.mesh.dimension;
  out["vertices"] = Array(grid.mesh.vertices, grid.mesh.numVertices(), 3);
  out["cells"] = Array(grid.mesh.cells, grid.mesh.numCells(), corners);
  out["values"] = Array(grid.values, grid.mesh.numVertices(), static_cast<std::size_t>(grid.functionCount));
  out["active"] = Array(grid.active, grid.active.size(), 1).attr("reshape")(-1).attr("astype")("bool");
  out["function_names"] = names;
  out["stats"] = stats;
  out["zero_sets"] = zero;
  return out;
}

}  // namespace

void RegisterGrid(py::module_& m) {
  m.def("_grid", &Grid, py::arg("functions_text"), py::arg("functions_name"), py::arg("mode"), py::arg("tree_text"),
        py::arg("tree_name"), py::arg("epsilon"), py::arg("box"), py::arg("resolution"), py::arg("grid_path"),
        py::arg("max_cells"), py::arg("threads"), "Refines an implicit-complex grid (see invmap.grid).");
}

}  // namespace invmap::python
