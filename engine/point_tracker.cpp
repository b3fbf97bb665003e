// PointTracker (include/invmap/distance.h): one moving point's closest
// point, started from the previous answer's cell and verified over the
// whole BVH under that answer's bound.
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <vector>

#include "engine/affine_regions.h"
#include "engine/api_errors.h"
#include "engine/manifold_access.h"
#include "engine/nearest_cells.h"
#include "invmap/distance.h"
#include "kernels/active_set.h"
#include "kernels/cell_solver.h"

namespace invmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double BoxDistance2(const double* lo, const double* hi, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double gap = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
    d2 += gap * gap;
  }
  return d2;
}

}  // namespace

struct PointTracker::Impl {
  const Manifold* manifold = nullptr;
  double maxDistance = kInf;
  kernels::SolveWorkspace workspace;
  struct Entry {
    double lowerBound2;
    int node;
  };
  std::vector<Entry> heap;
  bool hasPrevious = false;
  std::int64_t previousCell = -1;
  double previousRef[3] = {0, 0, 0};

  /// The running best of one update.
  struct Best {
    double distance2 = kInf;
    std::int64_t cell = -1;
    double ref[3] = {0, 0, 0};
    double closest[3] = {0, 0, 0};
  };

  void Search(const double* p, PointAnswer* answer);
};

void PointTracker::Impl::Search(const double* p, PointAnswer* answer) {
  const engine::CellStore& store = ManifoldAccess::Store(*manifold);
  const engine::Bvh& bvh = ManifoldAccess::Tree(*manifold);
  const int dim = store.dimension();
  Best best;
  // Found means within maxDistance: the bound admits a point at exactly it.
  best.distance2 = maxDistance < kInf ? maxDistance * maxDistance * (1.0 + 1e-15) : kInf;
  auto consider = [&](std::int64_t cell, const kernels::CellSolveResult& r) {
    if (r.status == kernels::PointStatus::Farther || r.status == kernels::PointStatus::InvalidInput) return;
    const double d2 = r.distance * r.distance;
    if (!(d2 < best.distance2)) return;
    best.distance2 = d2;
    best.cell = cell;
    std::copy(r.ref, r.ref + 3, best.ref);
    std::copy(r.closest, r.closest + 3, best.closest);
  };
  // The previous answer's cell first, from its parameters: a small move
  // lands near them, and its distance bounds everything else.
  if (hasPrevious && previousCell >= 0 && previousCell < store.size()) {
    consider(previousCell, store.solver(previousCell).Solve(p, previousRef, &workspace, best.distance2));
  }
  // Then every other subdivision the bound cannot exclude, nearest box first.
  auto order = [](const Entry& a, const Entry& b) { return a.lowerBound2 > b.lowerBound2; };
  heap.clear();
  if (!bvh.Nodes().empty()) heap.push_back({0.0, 0});
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), order);
    const Entry entry = heap.back();
    heap.pop_back();
    if (!(entry.lowerBound2 < best.distance2)) break;
    const engine::BvhNode& node = bvh.Nodes()[entry.node];
    if (node.count == 0) {
      for (int child = node.first; child <= node.first + 1; ++child) {
        const engine::BvhBox box = bvh.NodeBounds(child);
        const double lb2 = BoxDistance2(box.lo, box.hi, p, dim);
        if (lb2 < best.distance2) {
          heap.push_back({lb2, child});
          std::push_heap(heap.begin(), heap.end(), order);
        }
      }
      continue;
    }
    for (int i = node.first; i < node.first + node.count; ++i) {
      const std::int64_t s = bvh.Items()[i];
      const engine::BvhBox box = engine::ItemBoxOf(bvh, store, i);
      if (!(BoxDistance2(box.lo, box.hi, p, dim) < best.distance2)) continue;
      if (store.isRegion(s)) {
        const engine::RegionSolution r = engine::SolveAffineRegion(store.subdivisionRegion(s), p);
        if (r.distance * r.distance < best.distance2) {
          best.distance2 = r.distance * r.distance;
          best.cell = r.cell;
          std::copy(r.ref, r.ref + 3, best.ref);
          std::copy(r.closest, r.closest + 3, best.closest);
        }
        continue;
      }
      const std::int64_t cell = store.subdivisionCell(s);
      if (cell == previousCell && hasPrevious) continue;  // solved first
      consider(cell, store.solver(cell).Solve(p, nullptr, &workspace, best.distance2));
    }
  }
  *answer = PointAnswer();
  if (best.cell < 0) {
    answer->status = Status::None;
    return;
  }
  hasPrevious = true;
  previousCell = best.cell;
  std::copy(best.ref, best.ref + 3, previousRef);
  const engine::CellOrigin origin = store.origin(best.cell);
  const kernels::CellShape& shape = store.shape(best.cell);
  double ref[3] = {best.ref[0], best.ref[1], best.ref[2]};
  kernels::SnapToDomain(shape.type(), ref);
  answer->status = Status::Found;
  answer->patch = origin.patch;
  answer->cell = origin.indexInPatch;
  // As Manifold::Invert reports them (a trimmed CAD face's own parameters,
  // angles, an edge's pcurve).
  store.ReportedParameters(best.cell, ref, answer->params);
  for (int k = 0; k < 3; ++k) answer->closest[k] = k < dim ? best.closest[k] : 0.0;
  answer->distance = std::sqrt(best.distance2);
}

PointTracker::PointTracker(const Manifold& manifold, double maxDistance) : impl_(std::make_unique<Impl>()) {
  impl_->manifold = &manifold;
  impl_->maxDistance = maxDistance;
}

PointTracker::~PointTracker() = default;
PointTracker::PointTracker(PointTracker&&) noexcept = default;
PointTracker& PointTracker::operator=(PointTracker&&) noexcept = default;

Error PointTracker::Update(const double* point, PointAnswer* answer, std::string* message) {
  return engine::Guarded(message, [&] {
    if (!impl_) throw std::invalid_argument("the tracker was moved from");
    if (!impl_->manifold->valid()) throw std::invalid_argument("the manifold is empty (not built)");
    if (!answer || !point) throw std::invalid_argument("point or answer: null");
    if (ManifoldAccess::HasPouSurfaces(*impl_->manifold)) {
      throw std::invalid_argument("partition-of-unity surfaces (pou_manifold patches) cannot be tracked yet");
    }
    if (std::isnan(impl_->maxDistance) || impl_->maxDistance < 0.0) {
      throw std::invalid_argument("maxDistance must be >= 0");
    }
    const int dim = ManifoldAccess::Store(*impl_->manifold).dimension();
    double p[3] = {0, 0, 0};
    for (int k = 0; k < dim; ++k) {
      p[k] = point[k];
      if (!std::isfinite(p[k])) {
        *answer = PointAnswer();
        answer->status = Status::Invalid;
        return Error::Ok;
      }
    }
    impl_->Search(p, answer);
    return Error::Ok;
  });
}

}  // namespace invmap
