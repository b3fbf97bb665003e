// Storage of the branch and bound searches' subdomains: slots of a fixed
// number of doubles in a vector that grows, with a free list. Growing moves
// the slots, so they are named by index, never by pointer across an
// Allocate. The vectors belong to the caller's workspace and are reused
// from one search to the next (a warm search does not allocate).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace invmap::kernels {

class SlotPool {
 public:
  /// Starts empty over `storage` and `freeSlots` (both kept by the caller).
  SlotPool(std::vector<double>* storage, std::vector<int>* freeSlots, int slotSize)
      : storage_(storage), freeSlots_(freeSlots), slotSize_(slotSize) {
    freeSlots_->clear();
  }

  int Allocate() {
    if (!freeSlots_->empty()) {
      const int s = freeSlots_->back();
      freeSlots_->pop_back();
      return s;
    }
    const std::size_t need = static_cast<std::size_t>(used_ + 1) * slotSize_;
    if (storage_->size() < need) storage_->resize(std::max(need, 2 * storage_->size()));
    return used_++;
  }
  void Free(int s) { freeSlots_->push_back(s); }
  double* operator[](int s) { return storage_->data() + static_cast<std::size_t>(s) * slotSize_; }

 private:
  std::vector<double>* storage_;
  std::vector<int>* freeSlots_;
  int slotSize_;
  int used_ = 0;
};

}  // namespace invmap::kernels
