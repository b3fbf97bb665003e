// Algorithm 4 with the candidates generated lazily from the BVH: for points
// whose bucket's candidate list would be long (far from the geometry, or on
// a large mesh).
#pragma once

#include "engine/bvh_build.h"
#include "engine/point_search.h"
#include "engine/simplex_items.h"
#include "engine/wide_bvh.h"

namespace invmap::engine {

/// Algorithm 4 with the candidates generated lazily: a traversal of the BVH
/// cut at the best distance so far.
void SearchBvh(const Bvh& bvh, const WideBvh& wide, const SimplexItems& simplices, PointSearch& search);

}  // namespace invmap::engine
