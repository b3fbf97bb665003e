#include "implicit/grid_refiner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/parallel.h"
#include "implicit/radius_ratio.h"
#include "implicit/refinement_criteria.h"

namespace invmap::implicit {
namespace {

// Block sizes of the parallel loops: large enough that a block's scratch
// allocation and task overhead are negligible.
constexpr std::int64_t kVertexGrain = 512;
constexpr std::int64_t kCellGrain = 256;

}  // namespace

template <int N>
GridRefiner<N>::GridRefiner(const SimplexMesh& initial, const std::vector<Function>& functions,
                            const GridOptions& options)
    : functions_(functions),
      options_(options),
      functionCount_(static_cast<int>(functions.size())),
      grid_(initial) {
  // Cell and vertex indices are 32-bit; a bisection adds at most a few
  // hundred cells, so this cap keeps them in range.
  options_.maxCells = std::min<std::int64_t>(options_.maxCells, std::int64_t{4000000000});
}

template <int N>
std::string GridRefiner<N>::EvaluateVertices(std::size_t begin, std::size_t end) {
  const std::size_t k = static_cast<std::size_t>(functionCount_);
  values_.resize(end * k);
  gradients_.resize(end * k * 3);
  gradientNorms_.resize(end * k);
  std::vector<std::uint8_t> blockFailed(end - begin, 0);
  ForEachBlock(ExecutionPolicy::Par, static_cast<std::int64_t>(end - begin), kVertexGrain,
                       [&](std::int64_t blockBegin, std::int64_t blockEnd) {
                         const std::size_t first = begin + static_cast<std::size_t>(blockBegin);
                         const std::size_t count = static_cast<std::size_t>(blockEnd - blockBegin);
                         std::vector<double> values(count), gradients(3 * count);
                         for (std::size_t f = 0; f < k; ++f) {
                           functions_[f].evaluate(grid_.point(static_cast<std::uint32_t>(first)), count, values.data(),
                                                  gradients.data());
                           for (std::size_t i = 0; i < count; ++i) {
                             const std::size_t slot = (first + i) * k + f;
                             values_[slot] = values[i];
                             double norm2 = 0;
                             for (int a = 0; a < 3; ++a) {
                               const double g = a < N ? gradients[3 * i + a] : 0.0;
                               gradients_[3 * slot + a] = g;
                               norm2 += g * g;
                             }
                             gradientNorms_[slot] = std::sqrt(norm2);
                             if (!std::isfinite(values[i]) || !std::isfinite(norm2))
                               blockFailed[first + i - begin] = 1;
                           }
                         }
                       });
  for (std::size_t v = begin; v < end; ++v) {
    if (!blockFailed[v - begin]) continue;
    for (std::size_t f = 0; f < k; ++f) {
      const std::size_t slot = v * k + f;
      if (std::isfinite(values_[slot]) && std::isfinite(gradientNorms_[slot])) continue;
      const double* p = grid_.point(static_cast<std::uint32_t>(v));
      std::ostringstream message;
      message.precision(17);
      message << "function " << f + 1 << " (" << functions_[f].name << ") is not finite at (" << p[0] << ", "
              << p[1] << ", " << p[2] << "): value " << values_[slot] << ", gradient (" << gradients_[3 * slot]
              << ", " << gradients_[3 * slot + 1] << ", " << gradients_[3 * slot + 2] << ")";
      return message.str();
    }
  }
  return {};
}

template <int N>
void GridRefiner<N>::TestAndQueue(const std::vector<std::uint32_t>& cells) {
  active_.resize(grid_.numCells(), 0);
  std::vector<std::uint8_t> refinable(cells.size(), 0);
  const std::size_t k = static_cast<std::size_t>(functionCount_);
  ForEachBlock(ExecutionPolicy::Par, static_cast<std::int64_t>(cells.size()), kCellGrain,
                       [&](std::int64_t begin, std::int64_t end) {
                         CriteriaEvaluator<N> evaluator(options_.mode, options_.epsilon, functionCount_,
                                                        &options_.tree);
                         for (std::int64_t i = begin; i < end; ++i) {
                           const auto& cell = grid_.cell(cells[i]);
                           const double* points[N + 1];
                           VertexSamples samples[N + 1];
                           for (int v = 0; v <= N; ++v) {
                             points[v] = grid_.point(cell[v]);
                             const std::size_t slot = static_cast<std::size_t>(cell[v]) * k;
                             samples[v] = {values_.data() + slot, gradients_.data() + 3 * slot,
                                           gradientNorms_.data() + slot};
                           }
                           const CellVerdict verdict = evaluator.Evaluate(points, samples);
                           active_[cells[i]] = verdict.active;
                           refinable[i] = verdict.refinable;
                         }
                       });
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (!refinable[i]) continue;
    QueueEntry entry;
    entry.cell = cells[i];
    entry.version = grid_.version(cells[i]);
    entry.edge = static_cast<std::uint8_t>(grid_.LongestEdge(cells[i], &entry.length2));
    entry.sequence = sequence_++;
    queue_.push_back(entry);
    std::push_heap(queue_.begin(), queue_.end(), QueueOrder());
  }
}

template <int N>
std::string GridRefiner<N>::Run() {
  std::string error;
  RunWithThreads(options_.threads, [&] {
    // The initial vertices are evaluated before the clock starts, as in the
    // reference implementation's timing.
    error = EvaluateVertices(0, grid_.numVertices());
    if (!error.empty()) return;
    const auto start = std::chrono::steady_clock::now();

    std::vector<std::uint32_t> cells(grid_.numCells());
    for (std::size_t c = 0; c < cells.size(); ++c) cells[c] = static_cast<std::uint32_t>(c);
    TestAndQueue(cells);

    std::vector<QueueEntry> batch;
    while (!queue_.empty() && !stats_.reachedMaxCells) {
      const double length2 = queue_.front().length2;
      batch.clear();
      while (!queue_.empty() && queue_.front().length2 == length2) {
        std::pop_heap(queue_.begin(), queue_.end(), QueueOrder());
        batch.push_back(queue_.back());
        queue_.pop_back();
      }
      const std::size_t firstNewVertex = grid_.numVertices();
      cells.clear();
      for (const QueueEntry& entry : batch) {
        if (grid_.version(entry.cell) != entry.version) continue;  // split since it was queued
        const auto& cell = grid_.cell(entry.cell);
        grid_.Bisect(cell[BisectionGrid<N>::kEdgeVertex[entry.edge][0]],
                     cell[BisectionGrid<N>::kEdgeVertex[entry.edge][1]], &cells);
        if (static_cast<std::int64_t>(grid_.numCells()) > options_.maxCells) {
          stats_.reachedMaxCells = true;
          break;
        }
      }
      error = EvaluateVertices(firstNewVertex, grid_.numVertices());
      if (!error.empty()) return;
      // A cell index can appear twice when a child was bisected again in the
      // same batch; test each once, in its final state.
      std::sort(cells.begin(), cells.end());
      cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
      TestAndQueue(cells);
    }
    stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ComputeStats();
  });
  return error;
}

template <int N>
void GridRefiner<N>::ComputeStats() {
  const std::int64_t count = static_cast<std::int64_t>(grid_.numCells());
  constexpr std::int64_t kGrain = 4096;
  const std::int64_t blocks = (count + kGrain - 1) / kGrain;
  struct Partial {
    std::int64_t active = 0;
    double all = 1, activeOnly = 1;
  };
  std::vector<Partial> partial(static_cast<std::size_t>(blocks));
  ForEachBlock(ExecutionPolicy::Par, blocks, 1, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t b = begin; b < end; ++b) {
      Partial& p = partial[b];
      for (std::int64_t c = b * kGrain; c < std::min(count, (b + 1) * kGrain); ++c) {
        const auto& cell = grid_.cell(static_cast<std::uint32_t>(c));
        const double ratio = N == 3 ? TetRadiusRatio(grid_.point(cell[0]), grid_.point(cell[1]),
                                                     grid_.point(cell[2]), grid_.point(cell[N]))
                                    : TriangleRadiusRatio(grid_.point(cell[0]), grid_.point(cell[1]),
                                                          grid_.point(cell[2]));
        p.all = std::min(p.all, ratio);
        if (active_[c]) {
          ++p.active;
          p.activeOnly = std::min(p.activeOnly, ratio);
        }
      }
    }
  });
  stats_.cells = count;
  stats_.vertices = static_cast<std::int64_t>(grid_.numVertices());
  stats_.activeCells = 0;
  for (const Partial& p : partial) {
    stats_.activeCells += p.active;
    stats_.minRadiusRatio = std::min(stats_.minRadiusRatio, p.all);
    stats_.minRadiusRatioActive = std::min(stats_.minRadiusRatioActive, p.activeOnly);
  }
}

template <int N>
Grid GridRefiner<N>::TakeGrid() {
  Grid grid;
  grid.mesh = grid_.ToMesh();
  grid.functionCount = functionCount_;
  grid.values = std::move(values_);
  grid.active = std::move(active_);
  grid.stats = stats_;
  return grid;
}

template class GridRefiner<2>;
template class GridRefiner<3>;

}  // namespace invmap::implicit
