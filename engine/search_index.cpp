#include "engine/search_index.h"

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/parallel.h"

namespace invmap::engine {
namespace {

/// The box of every subdivision (affine regions and the cells outside them),
/// in subdivision order: what the BVH is built over.
std::vector<BvhBox> SubdivisionBoxes(const CellStore& cells, int maxThreads) {
  std::vector<BvhBox> boxes(static_cast<std::size_t>(cells.numSubdivisions()));
  ForEachBlock(
      ExecutionPolicy::Par, cells.numSubdivisions(), 4096,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t s = begin; s < end; ++s) cells.SubdivisionBox(s, boxes[s].lo, boxes[s].hi);
      },
      maxThreads);
  return boxes;
}

}  // namespace

SearchIndex SearchIndex::Build(const Geometry& geometry, int maxThreads) {
  return BuildOver(CellStore::Build(geometry, maxThreads), geometry, maxThreads);
}

SearchIndex SearchIndex::Build(Geometry&& geometry, int maxThreads) {
  if (!MeshTriangles::Applies(geometry)) return Build(static_cast<const Geometry&>(geometry), maxThreads);
  MeshTriangles triangles;
  triangles.Take(std::move(geometry));
  // Meshes alone: no partition-of-unity surfaces to build.
  return BuildOver(CellStore(std::move(triangles)), Geometry{}, maxThreads);
}

SearchIndex SearchIndex::BuildOver(CellStore cells, const Geometry& geometry, int maxThreads) {
  Bvh bvh;
  {
    // The boxes go once the tree has its own copy (48 bytes a triangle).
    const std::vector<BvhBox> boxes = SubdivisionBoxes(cells, maxThreads);
    BvhBuildOptions options;
    options.maxThreads = maxThreads;
    // Mesh triangles: the store gives a triangle's box from its vertices.
    options.keepItemBoxes = cells.meshTriangles().empty();
    bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()), options);
  }
  SimplexItems simplices;
  simplices.Build(cells, bvh, maxThreads);
  // A mesh's triangles give their vertices by index: no copy of them.
  WideBvh wideBvh =
      simplices.meshVertices()
          ? WideBvh(bvh, IndexedHulls{simplices.meshVertices(), simplices.corners(), 3})
          : WideBvh(
                bvh, cells.dimension(),
                [&cells](int s, std::vector<double>* xyz) { cells.SubdivisionHullPoints(s, xyz); },
                !simplices.coversEveryItem());
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
