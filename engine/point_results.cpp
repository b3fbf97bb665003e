#include "engine/point_results.h"

#include <cmath>
#include <limits>
#include <vector>

#include "kernels/active_set.h"
#include "kernels/tolerances.h"

namespace invmap::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Rows [begin, end) of `from` (`width` values each) written to rows
/// to[begin..end) of *into.
template <typename T>
void ScatterRows(const std::vector<T>& from, const std::int64_t* to, std::int64_t begin, std::int64_t end, int width,
                 std::vector<T>* into) {
  for (std::int64_t s = begin; s < end; ++s) {
    for (int k = 0; k < width; ++k) (*into)[width * to[s] + k] = from[width * s + k];
  }
}

}  // namespace

void ResizeResults(std::int64_t count, Results* results) {
  const std::size_t n = static_cast<std::size_t>(count);
  results->status.resize(n);
  results->patch.resize(n);
  results->cell.resize(n);
  results->params.resize(3 * n);
  results->closest.resize(3 * n);
  results->distance.resize(n);
  results->iterations.resize(n);
}

void WriteNotFound(Status status, std::int64_t i, Results* results) {
  results->status[i] = status;
  results->patch[i] = -1;
  results->cell[i] = -1;
  for (int k = 0; k < 3; ++k) {
    results->params[3 * i + k] = kNaN;
    results->closest[3 * i + k] = kNaN;
  }
  results->distance[i] = kNaN;
  results->iterations[i] = 0;
}

void ScatterResults(const Results& source, const std::int64_t* to, std::int64_t begin, std::int64_t end,
                    Results* target) {
  ScatterRows(source.status, to, begin, end, 1, &target->status);
  ScatterRows(source.patch, to, begin, end, 1, &target->patch);
  ScatterRows(source.cell, to, begin, end, 1, &target->cell);
  ScatterRows(source.params, to, begin, end, 3, &target->params);
  ScatterRows(source.closest, to, begin, end, 3, &target->closest);
  ScatterRows(source.distance, to, begin, end, 1, &target->distance);
  ScatterRows(source.iterations, to, begin, end, 1, &target->iterations);
}

}  // namespace invmap::engine
