#include "engine/simplex_items.h"

#include <algorithm>

namespace invmap::engine {

void SimplexItems::Build(const CellStore& store, const Bvh& bvh) {
  cells_.clear();
  itemOfCell_.clear();
  paramDims_.clear();
  vertices_.clear();
  simplexCount_ = 0;
  const std::vector<int>& items = bvh.Items();
  int maxVertices = 0;
  for (const int item : items) {
    const std::int64_t cell = store.affineSimplexCell(item);
    if (cell >= 0) maxVertices = std::max(maxVertices, store.shape(cell).paramDim() + 1);
  }
  if (maxVertices == 0) return;
  const int dim = store.dimension();
  stride_ = maxVertices * dim;
  cells_.resize(items.size());
  itemOfCell_.assign(static_cast<std::size_t>(store.size()), -1);
  paramDims_.assign(items.size(), 0);
  vertices_.assign(items.size() * static_cast<std::size_t>(stride_), 0.0);
  for (std::size_t i = 0; i < items.size(); ++i) {
    cells_[i] = store.affineSimplexCell(items[i]);
    if (cells_[i] < 0) continue;
    ++simplexCount_;
    itemOfCell_[cells_[i]] = static_cast<std::int32_t>(i);
    paramDims_[i] = static_cast<std::int8_t>(store.shape(cells_[i]).paramDim());
    double* out = vertices_.data() + i * stride_;
    for (int v = 0; v <= paramDims_[i]; ++v) {
      const double* vertex = store.SimplexVertex(cells_[i], v);
      std::copy(vertex, vertex + dim, out + v * dim);
    }
  }
}

std::size_t SimplexItems::MemoryBytes() const {
  return cells_.capacity() * sizeof(std::int64_t) + itemOfCell_.capacity() * sizeof(std::int32_t) +
         paramDims_.capacity() + vertices_.capacity() * sizeof(double);
}

}  // namespace invmap::engine
