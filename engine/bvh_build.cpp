// The only file in invmap that includes Embree.
//
// Embree's SAH builder works on float boxes and calls back into this file to
// make its nodes; those temporary nodes live in Embree's thread-local
// allocator and only record the tree's shape. The flat invmap tree is then
// laid out from that shape, and its bounds are recomputed in double from the
// caller's boxes and only then rounded outward to float offsets, so Embree's
// float boxes never reach a bound.
#include "engine/bvh_build.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/parallel.h"

namespace invmap::engine {
namespace {

/// Depth limit handed to Embree. Embree switches to median splits 8 levels
/// before it and fails beyond it; 64 leaves room for very uneven SAH trees
/// while bounding the depth of the builder's recursion.
constexpr unsigned kMaxDepth = 64;

/// Tag of a temporary inner node, distinct from every leaf's item count (>= 1).
constexpr std::uint32_t kInnerTag = 0;

/// Temporary inner node made by Embree's createNode callback. Starts with the
/// same 32-bit tag as a leaf, so a node's kind is read from its first word.
struct BuildInner {
  std::uint32_t tag;      ///< Always kInnerTag.
  void* children[2];      ///< Temporary nodes of the two children.
};

// A temporary leaf is an array of 32-bit words: word 0 holds the item count
// n >= 1 and words 1 .. n the input box indices.

/// First word of a temporary node: kInnerTag or a leaf's item count.
std::uint32_t NodeTag(const void* node) { return *static_cast<const std::uint32_t*>(node); }

/// Embree createNode callback: allocates an inner node from the thread-local
/// allocator. Returns null if that allocation fails; Embree then reports the
/// error, which BuildBvh turns into an exception.
void* CreateNode(RTCThreadLocalAllocator alloc, unsigned int /*childCount*/, void* /*userPtr*/) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(BuildInner), alignof(BuildInner));
  if (memory == nullptr) return nullptr;
  return new (memory) BuildInner{kInnerTag, {nullptr, nullptr}};
}

/// Embree setNodeChildren callback: records the children of an inner node.
/// maxBranchingFactor = 2, so childCount is always 2.
void SetNodeChildren(void* node, void** children, unsigned int childCount, void* /*userPtr*/) {
  if (node == nullptr) return;
  auto* inner = static_cast<BuildInner*>(node);
  for (unsigned int i = 0; i < childCount && i < 2; ++i) inner->children[i] = children[i];
}

/// Embree setNodeBounds callback: ignores Embree's bounds, which are float;
/// BuildBvh recomputes every node's bounds in double.
void SetNodeBounds(void* /*node*/, const RTCBounds** /*bounds*/, unsigned int /*childCount*/,
                   void* /*userPtr*/) {}

/// Embree createLeaf callback: stores the input indices of the leaf's boxes
/// and counts the leaf in *userPtr (a std::atomic<std::int64_t>), so that the
/// flat node array can be allocated at its exact size, 2 * leaves - 1.
void* CreateLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t primCount,
                 void* userPtr) {
  static_cast<std::atomic<std::int64_t>*>(userPtr)->fetch_add(1, std::memory_order_relaxed);
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(std::uint32_t) * (primCount + 1),
                                     alignof(std::uint32_t));
  if (memory == nullptr) return nullptr;
  auto* words = static_cast<std::uint32_t*>(memory);
  words[0] = static_cast<std::uint32_t>(primCount);
  for (size_t i = 0; i < primCount; ++i) words[i + 1] = prims[i].primID;
  return words;
}

/// Name of an Embree error code for messages.
const char* ErrorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "unknown Embree error code";
}

/// Receives Embree's error messages for one device. Embree reports an error
/// on the thread that made the failing API call, which is BuildBvh's thread.
struct ErrorLog {
  std::string message;  ///< First message Embree reported; empty if none.
};

/// Embree device error callback: keeps the first message.
void OnEmbreeError(void* userPtr, RTCError code, const char* str) {
  auto* log = static_cast<ErrorLog*>(userPtr);
  if (!log->message.empty()) return;
  log->message = ErrorName(code);
  if (str != nullptr) log->message += std::string(": ") + str;
}

/// Throws std::runtime_error naming the failed step and Embree's message
/// (std::bad_alloc when Embree ran out of memory: a resource, not a bug).
[[noreturn]] void ThrowEmbreeError(const char* step, RTCError code, const ErrorLog& log) {
  if (code == RTC_ERROR_OUT_OF_MEMORY) throw std::bad_alloc();
  std::ostringstream msg;
  msg << "invmap BVH build: Embree " << step << " failed ("
      << (log.message.empty() ? std::string(ErrorName(code)) : log.message) << ")";
  throw std::runtime_error(msg.str());
}

/// Throws std::invalid_argument unless every box is finite with lo <= hi.
/// Runs once per build, never per query.
void VerifyBoxes(const BvhBox* boxes, int count) {
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double lo = boxes[i].lo[k];
      const double hi = boxes[i].hi[k];
      if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) {
        std::ostringstream msg;
        msg << "invmap BVH build: box " << i << " has axis " << k << " = [" << lo << ", " << hi
            << "]; need finite lo <= hi";
        throw std::invalid_argument(msg.str());
      }
    }
  }
}

/// The float nearest to x, with values beyond the float range clamped to
/// +-FLT_MAX (converting them directly would be undefined behaviour); the
/// start of LowerOffset and UpperOffset.
float NearestFloat(double x) {
  return static_cast<float>(std::clamp(x, -static_cast<double>(FLT_MAX), static_cast<double>(FLT_MAX)));
}

/// Extends `box` by `other`.
void Extend(BvhBox* box, const BvhBox& other) {
  for (int k = 0; k < 3; ++k) {
    box->lo[k] = std::min(box->lo[k], other.lo[k]);
    box->hi[k] = std::max(box->hi[k], other.hi[k]);
  }
}

/// The empty box: lo = +inf, hi = -inf, the identity of Extend.
BvhBox EmptyBox() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

/// Float offset f of a lower bound from `origin` such that
/// Bvh::Absolute(origin, f) <= value: the rebuilt bound never exceeds the true
/// one. Usually the nearest float already works or one step down does; the
/// step doubles because near a large origin one float step may not move the
/// double sum.
float LowerOffset(double value, double origin) {
  float offset = NearestFloat(value - origin);
  for (float step = 0.0f; Bvh::Absolute(origin, offset) > value;) {
    step = step == 0.0f ? std::max(std::abs(offset) * FLT_EPSILON, FLT_MIN) : 2.0f * step;
    offset = std::nextafter(offset - step, -std::numeric_limits<float>::infinity());
  }
  return offset;
}

/// Float offset f of an upper bound from `origin` such that
/// Bvh::Absolute(origin, f) >= value; the mirror of LowerOffset.
float UpperOffset(double value, double origin) {
  float offset = NearestFloat(value - origin);
  for (float step = 0.0f; Bvh::Absolute(origin, offset) < value;) {
    step = step == 0.0f ? std::max(std::abs(offset) * FLT_EPSILON, FLT_MIN) : 2.0f * step;
    offset = std::nextafter(offset + step, std::numeric_limits<float>::infinity());
  }
  return offset;
}

/// Owning handles that release Embree objects on every exit path.
using DeviceHandle = std::unique_ptr<RTCDeviceTy, decltype(&rtcReleaseDevice)>;
using BvhHandle = std::unique_ptr<RTCBVHTy, decltype(&rtcReleaseBVH)>;

}  // namespace

std::size_t Bvh::MemoryBytes() const {
  return nodes_.capacity() * sizeof(BvhNode) + items_.capacity() * sizeof(int) +
         itemBoxes_.capacity() * sizeof(BvhBox);
}

Bvh BuildBvh(const BvhBox* boxes, int count, const BvhBuildOptions& options) {
  if (count < 0 || (count > 0 && boxes == nullptr)) {
    throw std::invalid_argument("invmap BVH build: need count >= 0 and non-null boxes, got count " +
                                std::to_string(count));
  }
  // A binary tree over n leaves has 2n - 1 nodes, which must fit the
  // int32 child indices.
  if (count > std::numeric_limits<std::int32_t>::max() / 2) {
    throw std::invalid_argument("invmap BVH build: " + std::to_string(count) +
                                " boxes exceed the limit of 2^30 - 1");
  }
  if (options.maxLeafSize < 1 || options.maxLeafSize > RTC_BUILD_MAX_PRIMITIVES_PER_LEAF) {
    throw std::invalid_argument("invmap BVH build: maxLeafSize " +
                                std::to_string(options.maxLeafSize) + " is outside [1, " +
                                std::to_string(RTC_BUILD_MAX_PRIMITIVES_PER_LEAF) + "]");
  }
  VerifyBoxes(boxes, count);

  Bvh bvh;
  if (count == 0) return bvh;

  for (int i = 0; i < count; ++i) Extend(&bvh.rootBounds_, boxes[i]);
  // The nodes' float offsets are taken from the centre, where float
  // resolution relative to the geometry's size is finest.
  for (int k = 0; k < 3; ++k) {
    bvh.origin_[k] = 0.5 * bvh.rootBounds_.lo[k] + 0.5 * bvh.rootBounds_.hi[k];
  }

  // Embree sees the boxes moved to the centre and scaled uniformly into
  // [-1, 1]^3: it asserts on float overflow, and a uniform scale changes no
  // SAH decision. It only chooses the tree's shape, so rounding is harmless.
  double halfExtent = 0.0;
  for (int k = 0; k < 3; ++k) {
    halfExtent = std::max(halfExtent, 0.5 * bvh.rootBounds_.hi[k] - 0.5 * bvh.rootBounds_.lo[k]);
  }
  const double invScale = std::isfinite(1.0 / halfExtent) ? 1.0 / halfExtent : 1.0;
  const auto builderCoord = [&](double c, int k) {
    return static_cast<float>(std::clamp((c - bvh.origin_[k]) * invScale, -1.0, 1.0));
  };
  std::vector<RTCBuildPrimitive> prims(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    RTCBuildPrimitive& p = prims[i];
    p.lower_x = builderCoord(boxes[i].lo[0], 0);
    p.lower_y = builderCoord(boxes[i].lo[1], 1);
    p.lower_z = builderCoord(boxes[i].lo[2], 2);
    p.upper_x = builderCoord(boxes[i].hi[0], 0);
    p.upper_y = builderCoord(boxes[i].hi[1], 1);
    p.upper_z = builderCoord(boxes[i].hi[2], 2);
    p.geomID = 0;
    p.primID = static_cast<unsigned>(i);
  }

  // No "threads=" in the device config: Embree would turn it into a
  // process-wide tbb::global_control. The build runs in a task arena instead.
  ErrorLog log;
  DeviceHandle device(rtcNewDevice("verbose=0"), &rtcReleaseDevice);
  if (!device) ThrowEmbreeError("rtcNewDevice", rtcGetDeviceError(nullptr), log);
  rtcSetDeviceErrorFunction(device.get(), &OnEmbreeError, &log);
  BvhHandle embreeBvh(rtcNewBVH(device.get()), &rtcReleaseBVH);
  if (!embreeBvh) ThrowEmbreeError("rtcNewBVH", rtcGetDeviceError(device.get()), log);

  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.byteSize = sizeof(args);
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.buildFlags = RTC_BUILD_FLAG_NONE;
  args.maxBranchingFactor = 2;
  args.maxDepth = kMaxDepth;
  args.sahBlockSize = 1;
  args.minLeafSize = 1;
  args.maxLeafSize = static_cast<unsigned>(options.maxLeafSize);
  // An item test in NearestCells is cheaper than a node visit, which pops,
  // bounds and pushes. With equal costs the SAH makes leaves of ~1.2 boxes;
  // at 0.5 (measured with cachegrind, 1M random boxes, point queries) it
  // makes half as many nodes, and queries run ~15% fewer instructions and
  // ~10% fewer L1 misses. Lower ratios gave no further gain.
  args.traversalCost = 1.0f;
  args.intersectionCost = 0.5f;
  args.bvh = embreeBvh.get();
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  // Capacity equal to the count and no splitPrimitive: Embree's high quality
  // mode then uses the binned SAH builder without spatial splits, so each box
  // lands in exactly one leaf.
  args.primitiveArrayCapacity = prims.size();
  args.createNode = &CreateNode;
  args.setNodeChildren = &SetNodeChildren;
  args.setNodeBounds = &SetNodeBounds;
  args.createLeaf = &CreateLeaf;
  args.splitPrimitive = nullptr;
  args.buildProgress = nullptr;
  std::atomic<std::int64_t> leafCount{0};
  args.userPtr = &leafCount;

  void* buildRoot = nullptr;
  RunWithThreads(options.maxThreads, [&] { buildRoot = rtcBuildBVH(&args); });
  const RTCError buildError = rtcGetDeviceError(device.get());
  if (buildError != RTC_ERROR_NONE || buildRoot == nullptr) {
    ThrowEmbreeError("rtcBuildBVH", buildError, log);
  }

  // Lay the tree out depth first with siblings adjacent: a node is written
  // when popped, and an inner node reserves both child slots at once, so a
  // child's index is always larger than its parent's.
  const std::int64_t numNodes = 2 * leafCount.load() - 1;
  bvh.nodes_.reserve(static_cast<std::size_t>(numNodes));
  bvh.items_.reserve(static_cast<std::size_t>(count));
  if (options.keepItemBoxes) bvh.itemBoxes_.reserve(static_cast<std::size_t>(count));
  bvh.nodes_.push_back(BvhNode{});
  std::vector<std::pair<const void*, std::int32_t>> pending = {{buildRoot, 0}};
  while (!pending.empty()) {
    const auto [buildNode, index] = pending.back();
    pending.pop_back();
    const std::uint32_t tag = NodeTag(buildNode);
    if (tag == kInnerTag) {
      const auto* inner = static_cast<const BuildInner*>(buildNode);
      const auto first = static_cast<std::int32_t>(bvh.nodes_.size());
      bvh.nodes_[index].first = first;
      bvh.nodes_[index].count = 0;
      bvh.nodes_.push_back(BvhNode{});
      bvh.nodes_.push_back(BvhNode{});
      // Pushed second, popped first: the first child's subtree follows the pair.
      pending.emplace_back(inner->children[1], first + 1);
      pending.emplace_back(inner->children[0], first);
    } else {
      const auto* ids = static_cast<const std::uint32_t*>(buildNode) + 1;
      bvh.nodes_[index].first = static_cast<std::int32_t>(bvh.items_.size());
      bvh.nodes_[index].count = static_cast<std::int32_t>(tag);
      for (std::uint32_t i = 0; i < tag; ++i) {
        bvh.items_.push_back(static_cast<int>(ids[i]));
        if (options.keepItemBoxes) bvh.itemBoxes_.push_back(boxes[ids[i]]);
      }
    }
  }
  if (static_cast<int>(bvh.items_.size()) != count ||
      static_cast<std::int64_t>(bvh.nodes_.size()) != numNodes) {
    throw std::runtime_error("invmap BVH build: Embree's tree holds " +
                             std::to_string(bvh.items_.size()) + " boxes in " +
                             std::to_string(bvh.nodes_.size()) + " nodes instead of " +
                             std::to_string(count) + " in " + std::to_string(numNodes));
  }

  // Children have larger indices than their parent, so one backward sweep
  // bounds every child before its parent. A leaf rounds the exact union of
  // its boxes outward; an inner node takes the min / max of its children's
  // rounded offsets, which contains them exactly and stays conservative.
  for (std::size_t n = bvh.nodes_.size(); n-- > 0;) {
    BvhNode& node = bvh.nodes_[n];
    if (node.count > 0) {
      BvhBox bounds = EmptyBox();
      for (std::int32_t i = 0; i < node.count; ++i) Extend(&bounds, boxes[bvh.items_[node.first + i]]);
      for (int k = 0; k < 3; ++k) {
        node.lo[k] = LowerOffset(bounds.lo[k], bvh.origin_[k]);
        node.hi[k] = UpperOffset(bounds.hi[k], bvh.origin_[k]);
      }
    } else {
      const BvhNode& left = bvh.nodes_[node.first];
      const BvhNode& right = bvh.nodes_[node.first + 1];
      for (int k = 0; k < 3; ++k) {
        node.lo[k] = std::min(left.lo[k], right.lo[k]);
        node.hi[k] = std::max(left.hi[k], right.hi[k]);
      }
    }
  }
  return bvh;
}

}  // namespace invmap::engine
