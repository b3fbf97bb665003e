#include "engine/cell_store.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <tbb/concurrent_unordered_map.h>

#include "common/parallel.h"
#include "kernels/own_parameter.h"

namespace invmap::engine {

/// A mesh triangle's solver, over its own copy of the vertices (a solver
/// reads its control points in one array).
struct TriangleSolverEntry {
  double vertices[9];
  kernels::CellSolver solver;
};

struct CellStore::TriangleSolvers {
  tbb::concurrent_unordered_map<std::int64_t, std::unique_ptr<TriangleSolverEntry>> built;
};

namespace {

/// The solvers of every cell (bounds, distance nets), built in parallel:
/// the nets' arrays are final, and each solver points into them.
std::vector<kernels::CellSolver> BuildSolvers(const BezierNets& nets, int maxThreads) {
  const std::int64_t count = nets.size();
  std::vector<kernels::CellSolver> solvers(static_cast<std::size_t>(count));
  ForEachBlock(
      ExecutionPolicy::Par, count, 256,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c) solvers[c] = kernels::CellSolver(nets.View(c));
      },
      maxThreads);
  for (const auto& [cell, trim] : nets.trimmed.crossingCells) solvers[cell].SetTrim(trim.get());
  return solvers;
}

}  // namespace

CellStore CellStore::Build(const Geometry& geometry, int maxThreads) {
  if (MeshTriangles::Applies(geometry)) {
    MeshTriangles triangles;
    triangles.Build(geometry);
    return CellStore(std::move(triangles));
  }
  BezierNets nets = ToBezierNets(geometry);
  std::vector<kernels::CellSolver> solvers = BuildSolvers(nets, maxThreads);
  FaceAdjacency faceAdjacency;
  if (nets.hasVolumeCells) faceAdjacency.Build(solvers, maxThreads);
  std::vector<AffineRegion> regions = FindAffineRegions(nets, solvers);
  // Moving the nets keeps their arrays, where the solvers point.
  return CellStore(std::move(nets), std::move(solvers), std::move(faceAdjacency), std::move(regions));
}

CellStore::CellStore(BezierNets nets, std::vector<kernels::CellSolver> solvers, FaceAdjacency faceAdjacency,
                     std::vector<AffineRegion> regions)
    : nets_(std::move(nets)),
      size_(nets_.size()),
      solvers_(std::move(solvers)),
      regions_(std::move(regions)),
      faceAdjacency_(std::move(faceAdjacency)) {
  FindLargestSize();
  const auto& analyticCells = nets_.trimmed.analyticCells;
  if (!analyticCells.empty()) {
    analyticOf_.assign(static_cast<std::size_t>(size_), -1);
    for (std::size_t a = 0; a < analyticCells.size(); ++a) analyticOf_[analyticCells[a].first] = static_cast<std::int32_t>(a);
  }
  // Algorithm 6: the subdivisions the BVH is built over, every region once
  // (at its first cell) and every cell outside a region; without regions,
  // the cells themselves (no arrays).
  if (regions_.empty()) return;
  const std::int64_t count = size();
  regionOfCell_.assign(static_cast<std::size_t>(count), -1);
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    const AffineRegion& region = regions_[r];
    std::int64_t extent[3] = {1, 1, 1};
    for (int d = 0; d < region.paramDim; ++d) extent[d] = static_cast<std::int64_t>(region.breaks[d].size()) - 1;
    for (std::int64_t k = 0; k < extent[2]; ++k)
      for (std::int64_t j = 0; j < extent[1]; ++j)
        for (std::int64_t i = 0; i < extent[0]; ++i)
          regionOfCell_[region.firstCell + i * region.cellStride[0] + j * region.cellStride[1] +
                        k * region.cellStride[2]] = static_cast<std::int32_t>(r);
  }
  for (std::int64_t c = 0; c < count; ++c) {
    const std::int32_t r = regionOfCell_[c];
    if (r < 0) {
      subdivisions_.push_back(c);
    } else if (regions_[r].firstCell == c) {
      subdivisions_.push_back(-1 - static_cast<std::int64_t>(r));
    }
  }
}

CellStore::CellStore(MeshTriangles triangles)
    : size_(triangles.size()),
      triangles_(std::move(triangles)),
      triangleShape_(kernels::CellType::Tri, {1, 1, 1}),
      triangleSolvers_(std::make_unique<TriangleSolvers>()) {
  nets_.dimension = 3;
  nets_.patchFirst = triangles_.patchFirst();
  nets_.numPatches = nets_.patchFirst.size() - 1;
  nets_.splineSpans.assign(nets_.numPatches, {0, 0, 0});
  FindLargestSize();
}

void CellStore::FindLargestSize() {
  // Regions' boxes are unions of their cells' boxes: the diagonal of all
  // boxes bounds every region's size, and every cell's (with its own size,
  // which is positive even for a cell that is a single point).
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  for (std::int64_t c = 0; c < size(); ++c) {
    double cellLo[3], cellHi[3];
    if (triangles_.empty()) {
      std::copy(solvers_[c].boxLo(), solvers_[c].boxLo() + 3, cellLo);
      std::copy(solvers_[c].boxHi(), solvers_[c].boxHi() + 3, cellHi);
    } else {
      triangles_.Box(c, cellLo, cellHi);
    }
    largestSize_ = std::max(largestSize_, kernels::CellSolver::SizeOfBox(cellLo, cellHi, dimension()));
    for (int k = 0; k < dimension(); ++k) {
      lo[k] = std::min(lo[k], cellLo[k]);
      hi[k] = std::max(hi[k], cellHi[k]);
    }
  }
  if (size() > 0) {
    const double depth = dimension() > 2 ? hi[2] - lo[2] : 0.0;
    largestSize_ = std::max(largestSize_, std::hypot(hi[0] - lo[0], hi[1] - lo[1], depth));
  }
}

CellStore::CellStore(CellStore&&) noexcept = default;
CellStore& CellStore::operator=(CellStore&&) noexcept = default;
CellStore::~CellStore() = default;

const kernels::CellSolver& CellStore::TriangleSolver(std::int64_t cell) const {
  auto& built = triangleSolvers_->built;
  if (const auto found = built.find(cell); found != built.end()) return found->second->solver;
  auto entry = std::make_unique<TriangleSolverEntry>();
  entry->solver = kernels::CellSolver(View(cell, entry->vertices));
  // Another thread may have built it meanwhile: the one in the map stays.
  return built.emplace(cell, std::move(entry)).first->second->solver;
}

const CellOrigin& CellStore::TriangleOrigin(std::int64_t cell) const {
  constexpr int kSlots = 8;
  thread_local CellOrigin slots[kSlots];
  thread_local int next = 0;
  CellOrigin& origin = slots[next];
  next = (next + 1) % kSlots;
  origin = CellOrigin();
  origin.patch = triangles_.PatchOf(cell);
  origin.type = kernels::CellType::Tri;
  origin.indexInPatch = cell - triangles_.patchFirst()[origin.patch];
  return origin;
}

kernels::CellView CellStore::View(std::int64_t cell, double* triangle) const {
  if (triangles_.empty()) return solvers_[cell].cell();
  for (int v = 0; v < 3; ++v) std::copy(triangles_.Vertex(cell, v), triangles_.Vertex(cell, v) + 3, triangle + 3 * v);
  kernels::CellView view;
  view.shape = triangleShape_;
  view.ambientDim = 3;
  view.points = triangle;
  return view;
}

double CellStore::cellSize(std::int64_t cell) const {
  if (triangles_.empty()) return solvers_[cell].size();
  double lo[3], hi[3];
  triangles_.Box(cell, lo, hi);
  return kernels::CellSolver::SizeOfBox(lo, hi, 3);
}

void CellStore::SubdivisionBox(std::int64_t s, double* lo, double* hi) const {
  if (!triangles_.empty()) {
    triangles_.Box(s, lo, hi);
    return;
  }
  const double* from[2] = {subdivisionBoxLo(s), subdivisionBoxHi(s)};
  for (int k = 0; k < 3; ++k) {
    lo[k] = from[0][k];
    hi[k] = from[1][k];
  }
}

void CellStore::SubdivisionHullPoints(std::int64_t s, std::vector<double>* xyz) const {
  if (!triangles_.empty()) {
    for (int v = 0; v < 3; ++v) xyz->insert(xyz->end(), triangles_.Vertex(s, v), triangles_.Vertex(s, v) + 3);
    return;
  }
  if (isRegion(s)) {
    const AffineRegion& region = subdivisionRegion(s);
    if (region.paramDim == nets_.dimension) return;
    for (int corner = 0; corner < (1 << region.paramDim); ++corner) {
      double x[3] = {0, 0, 0};
      for (int k = 0; k < nets_.dimension; ++k) {
        x[k] = region.b[k];
        for (int d = 0; d < region.paramDim; ++d) {
          x[k] += region.A[k][d] * ((corner >> d) & 1 ? region.hi[d] : region.lo[d]);
        }
      }
      xyz->insert(xyz->end(), x, x + 3);
    }
    return;
  }
  const std::int64_t cell = subdivisionCell(s);
  const kernels::CellShape& shape = nets_.shapes[cell];
  if (shape.paramDim() == nets_.dimension) return;
  const double* points = nets_.points.data() + nets_.pointOffset[cell];
  for (int i = 0; i < shape.numControlPoints(); ++i) {
    for (int k = 0; k < 3; ++k) xyz->push_back(k < nets_.dimension ? points[i * nets_.dimension + k] : 0.0);
  }
}

std::int64_t CellStore::SplineNeighbor(std::int64_t cell, const int* step) const {
  if (!triangles_.empty()) return -1;
  const CellOrigin& origin = nets_.origins[cell];
  if (!origin.sharedParameters) return -1;
  const std::array<int, 3>& spans = nets_.splineSpans[origin.patch];
  // Cells follow their patch's span grid, first direction fastest.
  std::int64_t index = 0, stride = 1;
  for (int d = 0; d < 3; ++d) {
    const std::int64_t span = origin.span[d] + step[d];
    if (span < 0 || span >= spans[d]) return -1;
    index += span * stride;
    stride *= spans[d];
  }
  // Trimmed surfaces leave out the spans outside their region.
  if (origin.patch < static_cast<std::int32_t>(nets_.trimmed.spanCells.size())) {
    const std::vector<std::int64_t>& spanCells = nets_.trimmed.spanCells[origin.patch];
    if (!spanCells.empty()) return spanCells[index];
  }
  return nets_.patchFirst[origin.patch] + index;
}

void CellStore::ReportedParameters(std::int64_t cell, const double* ref, double* params) const {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const CellOrigin from = origin(cell);
  if (from.edge >= 0) {
    const double own = kernels::OwnParameter(from.paramLo[0], from.paramScale[0], from.angular & 1, ref[0]);
    nets_.trimmed.edges[from.edge].At(own, params);
    params[2] = kNaN;
    return;
  }
  const int pd = kernels::CellShape::ParamDimOf(from.type);
  for (int k = 0; k < 3; ++k) {
    params[k] =
        k < pd ? kernels::OwnParameter(from.paramLo[k], from.paramScale[k], (from.angular >> k) & 1, ref[k])
               : kNaN;
  }
}

std::size_t CellStore::MemoryBytes() const {
  std::size_t bytes = nets_.MemoryBytes() + solvers_.capacity() * sizeof(kernels::CellSolver) +
                      regions_.capacity() * sizeof(AffineRegion) + regionOfCell_.capacity() * sizeof(std::int32_t) +
                      subdivisions_.capacity() * sizeof(std::int64_t) + faceAdjacency_.MemoryBytes() +
                      analyticOf_.capacity() * sizeof(std::int32_t);
  for (const AffineRegion& r : regions_)
    for (const std::vector<double>& breaks : r.breaks) bytes += breaks.capacity() * sizeof(double);
  for (const kernels::CellSolver& s : solvers_) bytes += s.NetMemoryBytes();
  bytes += triangles_.MemoryBytes();
  if (triangleSolvers_) bytes += triangleSolvers_->built.size() * (sizeof(TriangleSolverEntry) + 64);
  return bytes;
}

}  // namespace invmap::engine
