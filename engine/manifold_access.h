// The built parts of a Manifold, for the engine's systems beside the batch
// inversion (model-to-model distance, trackers, local minima). Defined in
// engine/api.cpp, where the manifold's insides are known.
#pragma once

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/search_index.h"
#include "invmap/invmap.h"

namespace invmap {

struct ManifoldAccess {
  /// Everything the searches read. Precondition: the manifold is built.
  static const engine::SearchIndex& Index(const Manifold& manifold);
  /// The cells. Precondition: the manifold is built (valid()).
  static const engine::CellStore& Store(const Manifold& manifold);
  /// The BVH over the store's subdivisions.
  static const engine::Bvh& Tree(const Manifold& manifold);
  /// True when the geometry has partition-of-unity surfaces (pou_manifold
  /// patches), which the store does not hold and only Manifold::Invert
  /// searches (engine/pou_patches.h).
  static bool HasPouSurfaces(const Manifold& manifold);
};

}  // namespace invmap
