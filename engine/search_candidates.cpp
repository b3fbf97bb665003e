#include "engine/search_candidates.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "engine/bucket_candidates.h"

namespace invmap::engine {

void SearchCandidates(PointSearch& search) {
  const CellStore& store = search.store;
  const int dim = store.dimension();
  std::vector<std::pair<double, int>>& heap = search.scratch.order;
  const std::vector<CellCandidate>& candidates = search.scratch.candidates;
  const std::vector<int>& searched = search.scratch.searched;
  if (store.hasVolumeCells() && !search.inside) {
    // The cells whose box holds the point, likeliest first (by the point's
    // place in the straight tetrahedron of the cell's vertices).
    std::vector<std::pair<double, int>>& boxes = search.scratch.insideOrder;
    boxes.clear();
    for (std::size_t j = 0; j < searched.size(); ++j) {
      const int c = searched[j];
      if (SearchedBoxDistance2(search.scratch, j, search.p, dim) != 0.0 || search.WasTried(candidates[c].cell)) continue;
      const std::int64_t s = candidates[c].cell;
      const double score = store.isRegion(s) ? 0.0 : store.solver(store.subdivisionCell(s)).InsideScore(search.p);
      boxes.emplace_back(-score, c);
    }
    std::stable_sort(boxes.begin(), boxes.end(),
                     [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
    for (const auto& [negativeScore, c] : boxes) {
      if (search.inside) break;
      search.TryInside(candidates[c].cell);
    }
  }
  if (search.inside) return;
  // The predicted cell first when it is one of the candidates left (not a
  // lane's: those are solved already).
  std::int64_t seeded = -1;
  for (const int c : searched) {
    if (search.IsCell(candidates[c].cell, search.warmCell)) seeded = search.SolveWarmCell();
  }
  // Then the others that can still beat the best, in the order of this
  // point's own lower bound (popped lazily from a heap: the search usually
  // stops after the first few). The best only shrinks, so a candidate left
  // out here would never have been solved.
  heap.clear();
  for (std::size_t j = 0; j < searched.size(); ++j) {
    const double lowerBound2 = SearchedBoxDistance2(search.scratch, j, search.p, dim);
    if (lowerBound2 <= search.Prune2() && !search.IsCell(candidates[searched[j]].cell, seeded)) {
      heap.emplace_back(lowerBound2, searched[j]);
    }
  }
  const auto later = [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a > b; };
  std::make_heap(heap.begin(), heap.end(), later);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const auto [lowerBound2, c] = heap.back();
    heap.pop_back();
    if (lowerBound2 > search.Prune2()) break;
    search.Solve(candidates[c].cell);
  }
}

}  // namespace invmap::engine
