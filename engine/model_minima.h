// Every local minimum of the distance between two models (--all-minima):
// each pair of cells within the distance asked for enumerates its own
// (kernels/pair_minima.h); a minimum on an edge of cells counts only where
// every pair of cells holding its two points has it as a KKT point too (and
// where a volume's face holds it, only where the other point lies outside
// that volume), and minima that are one pair of model points are reported once.
#pragma once

#include <vector>

#include "engine/model_distance.h"

namespace invmap::engine {

/// The minima, nearest first; `certified` false when some pair's
/// enumeration ran out of its budget.
std::vector<CellPairAnswer> AllPairMinima(const PlacedModel& a, const PlacedModel& b, double maxDistance,
                                          bool* certified, ModelDistanceWorkspace* ws);

}  // namespace invmap::engine
