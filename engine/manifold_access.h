// The built parts of a Manifold, for the engine's systems beside the batch
// inversion (model-to-model distance, trackers, local minima). Defined in
// engine/api.cpp, where the manifold's insides are known.
#pragma once

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "invmap/invmap.h"

namespace invmap {

struct ManifoldAccess {
  /// The cells. Precondition: the manifold is built (valid()).
  static const engine::CellStore& Store(const Manifold& manifold);
  /// The BVH over the store's subdivisions.
  static const engine::Bvh& Tree(const Manifold& manifold);
};

}  // namespace invmap
