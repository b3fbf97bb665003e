// RefineGrid: the public entry point of implicit grids. Validates the
// arguments once, then runs GridRefiner; the only try/catch of implicit/.
#include <cmath>
#include <exception>
#include <new>
#include <sstream>

#include "implicit/csg_tree.h"
#include "implicit/grid_refiner.h"
#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

std::string ValidateMesh(const SimplexMesh& mesh) {
  if (mesh.dimension != 2 && mesh.dimension != 3)
    return "initial grid: dimension must be 2 or 3, not " + std::to_string(mesh.dimension);
  if (mesh.vertices.size() % 3 != 0) return "initial grid: vertices must hold 3 coordinates per vertex";
  const std::size_t perCell = static_cast<std::size_t>(mesh.dimension + 1);
  if (mesh.cells.empty() || mesh.cells.size() % perCell != 0)
    return "initial grid: cells must hold " + std::to_string(perCell) + " vertex indices per cell, and at least one cell";
  const std::size_t vertices = mesh.numVertices();
  if (vertices >= 0xffffffffu) return "initial grid: too many vertices";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!std::isfinite(mesh.vertices[i]))
      return "initial grid: vertex " + std::to_string(i / 3) + " has a coordinate that is not finite";
    if (mesh.dimension == 2 && i % 3 == 2 && mesh.vertices[i] != 0)
      return "initial grid: vertex " + std::to_string(i / 3) + " of a 2D grid has z != 0";
  }
  for (std::size_t i = 0; i < mesh.cells.size(); ++i) {
    if (mesh.cells[i] >= vertices)
      return "initial grid: cell " + std::to_string(i / perCell) + " names vertex " + std::to_string(mesh.cells[i]) +
             " but there are " + std::to_string(vertices) + " vertices";
    // Bisection needs each cell's vertices distinct.
    for (std::size_t j = i - i % perCell; j < i; ++j) {
      if (mesh.cells[j] == mesh.cells[i])
        return "initial grid: cell " + std::to_string(i / perCell) + " names vertex " + std::to_string(mesh.cells[i]) +
               " twice";
    }
  }
  return {};
}

std::string ValidateArguments(const SimplexMesh& initial, const std::vector<Function>& functions,
                              const GridOptions& options) {
  std::string error = ValidateMesh(initial);
  if (!error.empty()) return error;
  if (functions.empty()) return "no functions";
  for (std::size_t f = 0; f < functions.size(); ++f)
    if (!functions[f].evaluate) return "function " + std::to_string(f + 1) + " has no evaluate callback";
  if (!(options.epsilon > 0) || !std::isfinite(options.epsilon)) {
    std::ostringstream message;
    message << "epsilon must be positive and finite, not " << options.epsilon;
    return message.str();
  }
  if (options.maxCells < 1) return "maxCells must be at least 1";
  if (options.threads < 0) return "threads must be 0 (all cores) or positive";
  if (options.mode == Mode::Csg) {
    if (options.tree.empty()) return "CSG mode needs a tree";
    error = ValidateCsgTree(options.tree, static_cast<int>(functions.size()));
    if (!error.empty()) return "CSG tree: " + error;
  }
  return {};
}

template <int N>
GridResult Refine(const SimplexMesh& initial, const std::vector<Function>& functions, const GridOptions& options) {
  GridRefiner<N> refiner(initial, functions, options);
  GridResult result;
  result.error = refiner.Run();
  if (result.error.empty()) result.grid = refiner.TakeGrid();
  return result;
}

}  // namespace

GridResult RefineGrid(const SimplexMesh& initial, const std::vector<Function>& functions, const GridOptions& options) {
  GridResult result;
  result.error = ValidateArguments(initial, functions, options);
  if (!result.error.empty()) return result;
  try {
    return initial.dimension == 3 ? Refine<3>(initial, functions, options) : Refine<2>(initial, functions, options);
  } catch (const std::bad_alloc&) {
    result.error = "out of memory";
  } catch (const std::exception& e) {
    // A user callback may throw; report it rather than let it cross the API.
    result.error = std::string("refinement failed: ") + e.what();
  } catch (...) {
    result.error = "refinement failed: a function callback threw an exception that is not a std::exception";
  }
  return result;
}

}  // namespace invmap::implicit
