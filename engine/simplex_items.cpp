#include "engine/simplex_items.h"

#include <algorithm>

#include "common/parallel.h"

namespace invmap::engine {

void SimplexItems::Build(const CellStore& store, const Bvh& bvh, int maxThreads) {
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
    if (cell < 0) continue;
    maxVertices = std::max(maxVertices, store.shape(cell).paramDim() + 1);
    ++simplexCount_;
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
  // Every item writes its own slots, and its cell's (a cell is one item).
  ForEachBlock(
      ExecutionPolicy::Par, static_cast<std::int64_t>(items.size()), 4096,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          const std::int64_t cell = store.affineSimplexCell(items[i]);
          cells_[i] = static_cast<std::int32_t>(cell);
          if (cell < 0) continue;
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
      },
      maxThreads);
}

std::size_t SimplexItems::MemoryBytes() const {
  return (cells_.capacity() + itemOfCell_.capacity() + corners_.capacity()) * sizeof(std::int32_t) +
         paramDims_.capacity() + vertices_.capacity() * sizeof(double);
}

}  // namespace invmap::engine
