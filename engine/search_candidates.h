// Algorithm 4 over the candidate list algorithm 3 gave a bucket of points.
#pragma once

#include "engine/point_search.h"

namespace invmap::engine {

/// Algorithm 4 over the bucket's candidate list: in a volume the cells whose
/// box holds the point, then the predicted cell, then the rest.
void SearchCandidates(PointSearch& search);

}  // namespace invmap::engine
