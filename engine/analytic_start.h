// The start of a point's search after an answer on a cell of a face's
// elementary surface (kernels/analytic_surface.h). Such an answer has no
// local model for PredictStart's Newton step (engine/warm_start.h); the
// surface's closed form gives better: the point's foot on the whole
// surface, and so the span of the face it lies in.
#pragma once

#include <cstdint>

#include "engine/cell_store.h"
#include "engine/warm_start.h"

namespace invmap::engine {

/// When `warm` answered on a cell of an elementary surface: the cell of
/// the face's span holding the foot of `p` on the surface (`warm`'s cell,
/// or its neighbour across the sides the foot lies beyond, when the face
/// has a cell there), and the foot's reference coordinates in it (beyond
/// [0, 1] when the foot is beyond that cell too), and true. False
/// otherwise, with nothing written.
bool PredictOnElementarySurface(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell,
                                double* ref);

}  // namespace invmap::engine
