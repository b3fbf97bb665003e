// The items below a child of the wide tree, for the tests that check its
// bounds against every item they stand for.
#pragma once

#include <vector>

#include "engine/wide_bvh.h"

namespace invmap::engine {

/// Appends the items (Bvh::Items() order) below child c of wide node `node`.
inline void ItemsBelow(const WideBvh& wide, int node, int c, std::vector<int>* items) {
  const WideNode& w = wide.Nodes()[node];
  if (w.count[c] > 0) {
    for (int i = w.first[c]; i < w.first[c] + w.count[c]; ++i) items->push_back(i);
    return;
  }
  if (w.count[c] < 0) return;
  for (int g = 0; g < 4; ++g) ItemsBelow(wide, w.first[c], g, items);
}

}  // namespace invmap::engine
