// The map at a local solve's iterate, and the buffer of its line search's
// trial points.
#pragma once

#include <utility>

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// The map at the iterate (to `order`, when `valid`) and a buffer for the
/// line search's trial points: an accepted trial's evaluation serves the next
/// iteration, so a step costs one evaluation of the map, not two.
struct JetCache {
  JetCache() = default;
  JetCache(const JetCache&) = delete;
  JetCache& operator=(const JetCache&) = delete;

  /// Makes *atRef the map at `ref` to at least `need`.
  void EnsureAt(const CellView& cell, const double* ref, JetOrder need) {
    if (valid && order >= need) return;
    EvaluateMap(cell, ref, need, atRef);
    for (int i = 0; i < 3; ++i) at[i] = ref[i];
    valid = true;
    order = need;
  }
  /// The trial point `ref`, evaluated to `trialOrder`, became the iterate.
  void AcceptTrial(JetOrder trialOrder, const double* ref) {
    std::swap(atRef, trial);
    for (int i = 0; i < 3; ++i) at[i] = ref[i];
    valid = true;
    order = trialOrder;
  }

  MapJet jets[2];
  MapJet* atRef = &jets[0];
  MapJet* trial = &jets[1];
  /// Where *atRef was evaluated (it stays there when `valid` turns false).
  /// Copied by loops: std::copy of its 3 values compiled to a memmove call.
  double at[3] = {0, 0, 0};
  bool valid = false;
  JetOrder order = JetOrder::Value;
};

}  // namespace invmap::kernels
