#include "engine/pair_bound_cache.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::engine {
namespace {

/// Past this many slots (24 MB) the table is emptied rather than grown: a long
/// trajectory over a large model would otherwise keep every pair it met.
constexpr std::size_t kMaxSlots = std::size_t{1} << 20;
constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Cell indices past this are not kept (their key would not be unique).
constexpr std::int64_t kMaxCell = std::int64_t{1} << 31;

bool Keyable(std::int64_t a, std::int64_t b) { return a >= 0 && b >= 0 && a < kMaxCell && b < kMaxCell; }

std::uint64_t KeyOf(std::int64_t a, std::int64_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
}

std::size_t HashOf(std::uint64_t key, std::size_t mask) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
}

}  // namespace

void PairBoundCache::MoveTo(const kernels::RigidMotion& bIntoA) {
  const double radiusB = std::max(radius_, 0.0);
  if (hasMotion_) {
    double rotation2 = 0.0, translation2 = 0.0, magnitude = radiusB;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const double d = bIntoA.rotation[i][j] - last_.rotation[i][j];
        rotation2 += d * d;
      }
      const double d = bIntoA.translation[i] - last_.translation[i];
      translation2 += d * d;
      magnitude += std::abs(bIntoA.translation[i]) + std::abs(last_.translation[i]);
    }
    // The rounding of the differences, the norms and the points themselves:
    // a few ulps of the coordinates' magnitude on top.
    const double step = std::sqrt(rotation2) * radiusB + std::sqrt(translation2);
    drift_ += step * (1.0 + 16.0 * kEps) + 64.0 * kEps * magnitude;
  }
  last_ = bIntoA;
  hasMotion_ = true;
  // Partitions of pairs no search of the last two motions used are dropped:
  // the models moved on, and what a pair keeps is some kilobytes.
  ++moves_;
  for (auto it = partitions_.begin(); it != partitions_.end();) {
    it = it->second.usedAt + 2 < moves_ ? partitions_.erase(it) : std::next(it);
  }
}

bool PairBoundCache::HasPartition(std::int64_t a, std::int64_t b) const {
  if (!Keyable(a, b)) return false;
  const auto it = partitions_.find(KeyOf(a, b));
  return it != partitions_.end() && it->second.partition.valid;
}

kernels::PairPartition* PairBoundCache::Partition(std::int64_t a, std::int64_t b) {
  if (!Keyable(a, b)) return nullptr;
  KeptPartition& kept = partitions_[KeyOf(a, b)];
  kept.usedAt = moves_;
  return &kept.partition;
}

std::size_t PairBoundCache::Find(std::uint64_t key) const {
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = HashOf(key, mask);
  while (slots_[i].key != key && slots_[i].key != kEmpty) i = (i + 1) & mask;
  return i;
}

bool PairBoundCache::Holds(double bound, double driftAt, double distance) const {
  const double left = bound - (drift_ - driftAt);
  // The subtraction's rounding, relative to the bound.
  return left - 4.0 * kEps * (bound + drift_) >= distance;
}

bool PairBoundCache::Excludes(std::int64_t a, std::int64_t b, double distance) const {
  if (slots_.empty() || !Keyable(a, b)) return false;
  const Slot& slot = slots_[Find(KeyOf(a, b))];
  return slot.key != kEmpty && Holds(slot.bound, slot.driftAt, distance);
}

void PairBoundCache::SetFrontier(std::vector<FrontierEntry>* next, bool fromRoots) {
  frontier_.swap(*next);
  next->clear();
  if (fromRoots) {
    rootFrontierSize_ = frontier_.size();
  } else if (frontier_.size() > 4 * rootFrontierSize_ + 256) {
    frontier_.clear();
  }
}

void PairBoundCache::Record(std::int64_t a, std::int64_t b, double lowerBound) {
  if (!(lowerBound > 0.0) || !Keyable(a, b)) return;  // proves nothing, or cannot be kept
  if (2 * (used_ + 1) > slots_.size()) Grow();
  const std::uint64_t key = KeyOf(a, b);
  Slot& slot = slots_[Find(key)];
  if (slot.key == key && slot.driftAt == drift_) {
    // Two proofs at the same motion: the stronger holds.
    slot.bound = std::max(slot.bound, lowerBound);
    return;
  }
  if (slot.key == kEmpty) ++used_;
  slot = {key, lowerBound, drift_};
}

void PairBoundCache::Clear() {
  std::fill(slots_.begin(), slots_.end(), Slot{kEmpty, 0.0, 0.0});
  used_ = 0;
  frontier_.clear();
  partitions_.clear();
}

void PairBoundCache::Grow() {
  if (slots_.size() >= kMaxSlots) {
    std::fill(slots_.begin(), slots_.end(), Slot{kEmpty, 0.0, 0.0});
    used_ = 0;
    return;
  }
  std::vector<Slot> old = std::move(slots_);
  slots_.assign(std::max<std::size_t>(1024, 2 * old.size()), Slot{kEmpty, 0.0, 0.0});
  used_ = 0;
  for (const Slot& slot : old) {
    if (slot.key == kEmpty) continue;
    slots_[Find(slot.key)] = slot;
    ++used_;
  }
}

}  // namespace invmap::engine
