#include "engine/search_index.h"

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace invmap::engine {
namespace {

/// The box of every subdivision (affine regions and the cells outside them),
/// in subdivision order: what the BVH is built over.
std::vector<BvhBox> SubdivisionBoxes(const CellStore& cells) {
  std::vector<BvhBox> boxes(static_cast<std::size_t>(cells.numSubdivisions()));
  for (std::int64_t s = 0; s < cells.numSubdivisions(); ++s) {
    for (int k = 0; k < 3; ++k) {
      boxes[s].lo[k] = cells.subdivisionBoxLo(s)[k];
      boxes[s].hi[k] = cells.subdivisionBoxHi(s)[k];
    }
  }
  return boxes;
}

}  // namespace

SearchIndex SearchIndex::Build(const Geometry& geometry, int maxThreads) {
  CellStore cells = CellStore::Build(geometry, maxThreads);
  const std::vector<BvhBox> boxes = SubdivisionBoxes(cells);
  BvhBuildOptions options;
  options.maxThreads = maxThreads;
  Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()), options);
  WideBvh wideBvh(bvh, cells.dimension(),
                  [&cells](int s, std::vector<double>* xyz) { cells.SubdivisionHullPoints(s, xyz); });
  SimplexItems simplices;
  simplices.Build(cells, bvh);
  PouPatches pou;
  // The validation checked every pou_manifold patch (its topology included):
  // a failure here is a bug.
  if (const std::string error = pou.Build(geometry, maxThreads); !error.empty()) {
    throw std::logic_error("pou_manifold passed validation but does not build: " + error);
  }
  return SearchIndex(std::move(cells), std::move(bvh), std::move(wideBvh), std::move(simplices), std::move(pou));
}

SearchIndex::SearchIndex(CellStore cells, Bvh bvh, WideBvh wideBvh, SimplexItems simplices, PouPatches pou)
    : cells_(std::move(cells)),
      bvh_(std::move(bvh)),
      wideBvh_(std::move(wideBvh)),
      simplices_(std::move(simplices)),
      pou_(std::move(pou)) {}

std::size_t SearchIndex::MemoryBytes() const {
  return cells_.MemoryBytes() + bvh_.MemoryBytes() + wideBvh_.MemoryBytes() + simplices_.MemoryBytes() +
         pou_.MemoryBytes();
}

}  // namespace invmap::engine
