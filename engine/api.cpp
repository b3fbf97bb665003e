// The public API's boundary: the only place that catches exceptions.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "common/check.h"
#include "common/parallel.h"
#include "engine/api_errors.h"
#include "engine/geometry_validation.h"
#include "engine/invert_batch.h"
#include "engine/manifold_access.h"
#include "engine/search_index.h"
#include "invmap/invmap.h"

namespace invmap {

struct Manifold::Impl {
  engine::SearchIndex index;
};

namespace {

/// The query coordinates as double structure of arrays (one copy, so the
/// solve path reads contiguous doubles whatever the caller's layout), copied
/// in parallel into `soa` (view.count * view.dim values, not initialized
/// before: a serial fill would cap the speed-up of fast workloads).
template <typename T>
void CopyCoordinates(const PointsView& view, int threads, double* soa) {
  const std::int64_t n = static_cast<std::int64_t>(view.count);
  ForEachBlock(
      ExecutionPolicy::Par, n, 1 << 16,
      [&](std::int64_t begin, std::int64_t end) {
        for (int k = 0; k < view.dim; ++k) {
          const T* src = static_cast<const T*>(view.coord[k]);
          double* dst = soa + k * n;
          for (std::int64_t i = begin; i < end; ++i) dst[i] = static_cast<double>(src[i * view.stride]);
        }
      },
      threads);
}

}  // namespace

namespace {

template <typename T>
PointsView MakeInterleaved(const T* xyz, std::size_t count, int dim) {
  PointsView v;
  v.count = count;
  v.dim = dim;
  v.scalar = std::is_same_v<T, float> ? Scalar::Float32 : Scalar::Float64;
  for (int k = 0; k < dim; ++k) v.coord[k] = xyz + k;
  v.stride = static_cast<std::size_t>(dim);
  return v;
}

template <typename T>
PointsView MakeSeparate(const T* x, const T* y, const T* z, std::size_t count, int dim) {
  PointsView v;
  v.count = count;
  v.dim = dim;
  v.scalar = std::is_same_v<T, float> ? Scalar::Float32 : Scalar::Float64;
  v.coord[0] = x;
  v.coord[1] = y;
  v.coord[2] = dim == 3 ? z : nullptr;
  v.stride = 1;
  return v;
}

}  // namespace

PointsView PointsView::Interleaved(const double* xyz, std::size_t count, int dim) {
  return MakeInterleaved(xyz, count, dim);
}
PointsView PointsView::Interleaved(const float* xyz, std::size_t count, int dim) {
  return MakeInterleaved(xyz, count, dim);
}
PointsView PointsView::Separate(const double* x, const double* y, const double* z, std::size_t count, int dim) {
  return MakeSeparate(x, y, z, count, dim);
}
PointsView PointsView::Separate(const float* x, const float* y, const float* z, std::size_t count, int dim) {
  return MakeSeparate(x, y, z, count, dim);
}

Manifold::Manifold() = default;
Manifold::~Manifold() = default;
Manifold::Manifold(Manifold&&) noexcept = default;
Manifold& Manifold::operator=(Manifold&&) noexcept = default;

bool Manifold::valid() const { return impl_ != nullptr; }

namespace {

/// Manifold::Build's body: validates `geometry`, then makes the manifold's
/// index with build(geometry); every exception becomes the result's code.
template <typename BuildIndex>
BuildResult ValidateAndBuild(const Geometry& geometry, const BuildIndex& build) {
  BuildResult result;
  try {
    // The one validation of every geometry, whatever produced it.
    result.problem = engine::ValidateGeometry(geometry);
    if (result.problem) {
      result.error = Describe(result.problem);
      result.code = Error::InvalidArgument;
      return result;
    }
    build(&result.manifold);
  } catch (const std::bad_alloc&) {
    result.problem.message = "out of memory while building the manifold";
    result.code = Error::OutOfMemory;
  } catch (const std::exception& e) {
    result.problem.message = std::string("building the manifold failed: ") + e.what();
    result.code = Error::Internal;
  }
  result.error = Describe(result.problem);
  return result;
}

}  // namespace

BuildResult Manifold::Build(const Geometry& geometry) {
  return ValidateAndBuild(geometry, [&](Manifold* manifold) {
    manifold->impl_ = std::make_unique<Impl>(Impl{engine::SearchIndex::Build(geometry)});
  });
}

BuildResult Manifold::Build(Geometry&& geometry) {
  return ValidateAndBuild(geometry, [&](Manifold* manifold) {
    manifold->impl_ = std::make_unique<Impl>(Impl{engine::SearchIndex::Build(std::move(geometry))});
  });
}

ManifoldInfo Manifold::Info() const {
  ManifoldInfo info;
  if (!impl_) return info;
  const engine::CellStore& store = impl_->index.cells();
  info.dimension = store.dimension();
  info.patches = store.numPatches();
  info.cells = static_cast<std::size_t>(store.size());
  std::map<std::string, std::size_t> byShape;
  for (std::int64_t c = 0; c < store.size(); ++c) {
    const kernels::CellShape& shape = store.shape(c);
    std::string key = CellTypeName(shape.type());
    key += ' ';
    for (int f = 0; f < shape.numFactors(); ++f) {
      if (f) key += 'x';
      key += std::to_string(shape.factor(f).degree);
    }
    double triangle[9];
    if (store.View(c, triangle).weights) key += " rational";
    ++byShape[key];
  }
  info.cellsByShape.assign(byShape.begin(), byShape.end());
  const engine::BvhBox& bounds = impl_->index.bvh().RootBounds();
  for (int k = 0; k < 3; ++k) {
    info.boundsLo[k] = info.cells ? bounds.lo[k] : 0.0;
    info.boundsHi[k] = info.cells ? bounds.hi[k] : 0.0;
  }
  info.memoryBytes = impl_->index.MemoryBytes() + sizeof(Impl);
  impl_->index.pou().AddInfo(&info);
  return info;
}

std::int64_t Manifold::NumCells(int patch) const {
  if (!impl_ || patch < 0 || static_cast<std::size_t>(patch) >= impl_->index.cells().numPatches()) return 0;
  if (const std::int64_t charts = impl_->index.pou().NumCells(patch); charts >= 0) return charts;
  return impl_->index.cells().patchFirstCell(patch + 1) - impl_->index.cells().patchFirstCell(patch);
}

bool Manifold::PointAt(int patch, std::int64_t cell, const double sample[3], double params[3], double point[3]) const {
  if (cell < 0 || cell >= NumCells(patch)) return false;
  if (impl_->index.pou().NumCells(patch) >= 0) return impl_->index.pou().PointAt(patch, cell, sample, params, point);
  const engine::CellStore& store = impl_->index.cells();
  const std::int64_t c = store.patchFirstCell(patch) + cell;
  double triangle[9];
  const kernels::CellView view = store.View(c, triangle);
  const kernels::CellShape& shape = view.shape;
  double ref[3] = {0, 0, 0};
  for (int f = 0; f < shape.numFactors(); ++f) {
    const kernels::SimplexFactor& fac = shape.factor(f);
    double s[3];
    for (int i = 0; i < fac.dim; ++i) s[i] = std::clamp(sample[fac.offset + i], 0.0, 1.0);
    // Sorting the unit cube's coordinates maps it uniformly onto the simplex
    // (the order statistics' gaps are the barycentric coordinates).
    for (int i = 1; i < fac.dim; ++i) {
      for (int j = i; j > 0 && s[j] < s[j - 1]; --j) std::swap(s[j], s[j - 1]);
    }
    double previous = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      ref[fac.offset + i] = s[i] - previous;
      previous = s[i];
    }
  }
  kernels::MapJet jet;
  kernels::EvaluateMap(view, ref, kernels::JetOrder::Value, &jet);
  store.ReportedParameters(c, ref, params);
  for (int k = 0; k < 3; ++k) point[k] = k < view.ambientDim ? jet.x[k] : 0.0;
  return true;
}

Error Manifold::Invert(const PointsView& points, const InversionOptions& options, Results* results,
                       std::string* message) const {
  return engine::Guarded(message, [&] {
    // Batch-level checks of the arguments, once per call (never per point).
    INVMAP_VERIFY(impl_, "the manifold is empty (not built)");
    INVMAP_VERIFY(results, "results: null");
    const int dim = impl_->index.dimension();
    INVMAP_VERIFY(points.dim == dim, "points: dimension " << points.dim << ", the geometry's is " << dim);
    for (int k = 0; k < dim; ++k) {
      INVMAP_VERIFY(points.count == 0 || points.coord[k], "points: coordinate array " << k << " is null");
    }
    INVMAP_VERIFY(!std::isnan(options.maxDistance) && options.maxDistance >= 0.0,
                  "options: maxDistance " << options.maxDistance << ", expected >= 0");
    INVMAP_VERIFY(options.threads >= 0, "options: threads " << options.threads << ", expected >= 0 (0 = all cores)");
    const std::unique_ptr<double[]> soa(new double[points.count * dim]);
    if (points.scalar == Scalar::Float64) {
      CopyCoordinates<double>(points, options.threads, soa.get());
    } else {
      CopyCoordinates<float>(points, options.threads, soa.get());
    }
    engine::QueryPoints query;
    query.count = static_cast<std::int64_t>(points.count);
    for (int k = 0; k < dim; ++k) query.coord[k] = soa.get() + k * points.count;
    engine::InvertBatch(impl_->index, query, options, results);
    return Error::Ok;
  });
}

const engine::SearchIndex& ManifoldAccess::Index(const Manifold& m) { return m.impl_->index; }
const engine::CellStore& ManifoldAccess::Store(const Manifold& m) { return m.impl_->index.cells(); }
const engine::Bvh& ManifoldAccess::Tree(const Manifold& m) { return m.impl_->index.bvh(); }
bool ManifoldAccess::HasPouSurfaces(const Manifold& m) { return !m.impl_->index.pou().empty(); }

const char* Version() { return INVMAP_VERSION; }  // project(VERSION) of CMakeLists.txt

}  // namespace invmap
