#include "engine/simplex_items.h"

#include <algorithm>

namespace invmap::engine {

void SimplexItems::Build(const CellStore& store, const Bvh& bvh) {
  cells_.clear();
  itemOfCell_.clear();
  paramDims_.clear();
  vertices_.clear();
  corners_.clear();
  meshVertices_ = nullptr;
  simplexCount_ = 0;
  dimension_ = store.dimension();
  const std::vector<int>& items = bvh.Items();
  int maxVertices = 0;
  for (const int item : items) {
    const std::int64_t cell = store.affineSimplexCell(item);
    if (cell >= 0) maxVertices = std::max(maxVertices, store.shape(cell).paramDim() + 1);
  }
  if (maxVertices == 0) return;
  const MeshTriangles& triangles = store.meshTriangles();
  cells_.resize(items.size());
  itemOfCell_.assign(static_cast<std::size_t>(store.size()), -1);
  paramDims_.assign(items.size(), 0);
  if (!triangles.empty()) {
    meshVertices_ = triangles.vertices();
    corners_.resize(3 * items.size());
  } else {
    stride_ = maxVertices * dimension_;
    vertices_.assign(items.size() * static_cast<std::size_t>(stride_), 0.0);
  }
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::int64_t cell = store.affineSimplexCell(items[i]);
    cells_[i] = static_cast<std::int32_t>(cell);
    if (cell < 0) continue;
    ++simplexCount_;
    itemOfCell_[cell] = static_cast<std::int32_t>(i);
    paramDims_[i] = static_cast<std::int8_t>(store.shape(cell).paramDim());
    if (meshVertices_) {
      for (int v = 0; v < 3; ++v) corners_[3 * i + v] = triangles.Corner(cell, v);
      continue;
    }
    double* out = vertices_.data() + i * stride_;
    for (int v = 0; v <= paramDims_[i]; ++v) {
      const double* vertex = store.SimplexVertex(cell, v);
      std::copy(vertex, vertex + dimension_, out + v * dimension_);
    }
  }
}

std::size_t SimplexItems::MemoryBytes() const {
  return (cells_.capacity() + itemOfCell_.capacity() + corners_.capacity()) * sizeof(std::int32_t) +
         paramDims_.capacity() + vertices_.capacity() * sizeof(double);
}

}  // namespace invmap::engine
