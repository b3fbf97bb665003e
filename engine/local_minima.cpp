// Every local minimum of a point's distance to a manifold (LocalMinima in
// include/invmap/distance.h): each cell within the distance asked for
// enumerates its own minima (kernels/cell_minima.h); a minimum on a cell's
// edge counts only where every other cell that meets it there has it as a
// KKT point too (the distance grows into that cell as well), and minima
// that are one point of the model are reported once. On a trimmed face
// (CAD) a cell's minima outside the face's region are no answers; those on
// its boundary are its edges' (curve cells), where the distance must also
// grow into the face or fall only toward the part trimmed away
// (engine/trimmed_minima.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <vector>

#include "engine/api_errors.h"
#include "engine/bvh_build.h"
#include "common/check.h"
#include "engine/manifold_access.h"
#include "engine/trimmed_minima.h"
#include "common/parallel.h"
#include "invmap/distance.h"
#include "kernels/active_set.h"
#include "kernels/cell_minima.h"
#include "kernels/local_solver.h"
#include "kernels/tolerances.h"

namespace invmap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double BoxDistance2(const double* lo, const double* hi, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double gap = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
    d2 += gap * gap;
  }
  return d2;
}

/// The cells of `store` whose control box lies within `radius` of p (the
/// cells of an affine region one by one).
void CellsNear(const engine::CellStore& store, const engine::Bvh& bvh, const double* p, double radius,
               std::vector<std::int64_t>* cells, std::vector<int>* stack) {
  cells->clear();
  if (bvh.Nodes().empty()) return;
  const int dim = store.dimension();
  const double radius2 = radius * radius;
  stack->assign(1, 0);
  while (!stack->empty()) {
    const int index = stack->back();
    stack->pop_back();
    const engine::BvhBox box = bvh.NodeBounds(index);
    if (!(BoxDistance2(box.lo, box.hi, p, dim) <= radius2)) continue;
    const engine::BvhNode& node = bvh.Nodes()[index];
    if (node.count == 0) {
      stack->push_back(node.first);
      stack->push_back(node.first + 1);
      continue;
    }
    for (int i = node.first; i < node.first + node.count; ++i) {
      const std::int64_t s = bvh.Items()[i];
      if (!store.isRegion(s)) {
        const kernels::CellSolver& solver = store.solver(store.subdivisionCell(s));
        if (BoxDistance2(solver.boxLo(), solver.boxHi(), p, dim) <= radius2) cells->push_back(store.subdivisionCell(s));
        continue;
      }
      const engine::AffineRegion& region = store.subdivisionRegion(s);
      const int spans[3] = {static_cast<int>(region.breaks[0].size()) - 1,
                            region.paramDim > 1 ? static_cast<int>(region.breaks[1].size()) - 1 : 1,
                            region.paramDim > 2 ? static_cast<int>(region.breaks[2].size()) - 1 : 1};
      for (int k = 0; k < spans[2]; ++k) {
        for (int j = 0; j < spans[1]; ++j) {
          for (int i2 = 0; i2 < spans[0]; ++i2) {
            const std::int64_t c = region.firstCell + i2 * region.cellStride[0] + j * region.cellStride[1] +
                                   k * region.cellStride[2];
            const kernels::CellSolver& solver = store.solver(c);
            if (BoxDistance2(solver.boxLo(), solver.boxHi(), p, dim) <= radius2) cells->push_back(c);
          }
        }
      }
    }
  }
  std::sort(cells->begin(), cells->end());
}

struct Candidate {
  std::int64_t cell;
  kernels::CellMinimum minimum;
};

/// Scratch of one task.
struct MinimaScratch {
  kernels::MinimaWorkspace minima;
  kernels::SolveWorkspace solve;
  std::vector<std::int64_t> cells, neighbours;
  std::vector<int> stack;
  std::vector<Candidate> candidates, kept;
};

/// True when the model point `x` of a cell's minimum is a KKT point of the
/// distance to p in every other cell that holds it (within `onTolerance`).
bool MinimumOfEveryCellThere(const engine::CellStore& store, const engine::Bvh& bvh, const double* p,
                             const Candidate& candidate, double onTolerance, double edgeTolerance,
                             MinimaScratch* scratch) {
  // An edge of a trimmed face: the distance must grow into its face too.
  if (!engine::MinimumOnCell(store, candidate.cell, candidate.minimum.ref, p)) return false;
  CellsNear(store, bvh, candidate.minimum.closest, edgeTolerance, &scratch->neighbours, &scratch->stack);
  for (const std::int64_t n : scratch->neighbours) {
    if (n == candidate.cell) continue;
    double ref[3];
    if (!engine::HoldsPoint(store, n, candidate.minimum.closest, onTolerance, edgeTolerance, &scratch->solve, ref)) {
      continue;  // the point is not on this cell
    }
    if (!engine::MinimumOnCell(store, n, ref, p)) return false;
  }
  return true;
}

void WriteRow(const engine::CellStore& store, const Candidate* candidate, Status status, std::size_t row,
              Results* out) {
  out->status[row] = status;
  out->iterations[row] = 0;
  if (!candidate) {
    out->patch[row] = -1;
    out->cell[row] = -1;
    for (int k = 0; k < 3; ++k) out->params[3 * row + k] = out->closest[3 * row + k] = kNaN;
    out->distance[row] = kNaN;
    return;
  }
  const engine::CellOrigin origin = store.origin(candidate->cell);
  const kernels::CellShape& shape = store.shape(candidate->cell);
  double ref[3] = {candidate->minimum.ref[0], candidate->minimum.ref[1], candidate->minimum.ref[2]};
  kernels::SnapToDomain(shape.type(), ref);
  out->patch[row] = origin.patch;
  out->cell[row] = origin.indexInPatch;
  // As invert reports them (a trimmed face's own (u, v), an edge's pcurve's).
  store.ReportedParameters(candidate->cell, ref, &out->params[3 * row]);
  for (int k = 0; k < 3; ++k) out->closest[3 * row + k] = k < store.dimension() ? candidate->minimum.closest[k] : 0.0;
  out->distance[row] = candidate->minimum.distance;
}

}  // namespace

Error LocalMinima(const Manifold& manifold, const PointsView& points, const InversionOptions& options,
                  LocalMinimaResults* results, std::string* message) {
  return engine::Guarded(message, [&] {
    INVMAP_VERIFY(manifold.valid(), "the manifold is empty (not built)");
    INVMAP_VERIFY(results, "results: null");
    INVMAP_VERIFY(!ManifoldAccess::HasPouSurfaces(manifold),
                  "partition-of-unity surfaces (pou_manifold patches) have no search for every local minimum yet");
    const engine::CellStore& store = ManifoldAccess::Store(manifold);
    const engine::Bvh& bvh = ManifoldAccess::Tree(manifold);
    const int dim = store.dimension();
    INVMAP_VERIFY(points.dim == dim, "points: dimension " << points.dim << ", the geometry's is " << dim);
    for (int k = 0; k < dim; ++k) {
      INVMAP_VERIFY(points.count == 0 || points.coord[k], "points: coordinate array " << k << " is null");
    }
    INVMAP_VERIFY(!std::isnan(options.maxDistance) && options.maxDistance >= 0.0,
                  "options: maxDistance " << options.maxDistance << ", expected >= 0");
    INVMAP_VERIFY(options.threads >= 0, "options: threads " << options.threads << ", expected >= 0 (0 = all cores)");
    const engine::BvhBox& bounds = bvh.RootBounds();
    double size2 = 0.0;
    for (int k = 0; k < dim && store.size() > 0; ++k) size2 += (bounds.hi[k] - bounds.lo[k]) * (bounds.hi[k] - bounds.lo[k]);
    const double size = std::sqrt(size2);
    // A point is on a cell within this; two minima closer than this are one.
    const double onTolerance = 1e-9 * std::max(size, 1e-300);
    const double mergeTolerance = 1e-7 * std::max(size, 1e-300);
    // A CAD model's edges lie within its tolerance of the faces they bound.
    const double edgeTolerance = store.hasTrimmedSurfaces() ? mergeTolerance : onTolerance;

    const std::int64_t n = static_cast<std::int64_t>(points.count);
    std::vector<std::vector<Candidate>> perPoint(n);
    std::vector<std::uint8_t> invalid(n, 0), certified(n, 1);
    ForEachBlock(
        ExecutionPolicy::Par, n, 4,
        [&](std::int64_t begin, std::int64_t end) {
          MinimaScratch scratch;
          for (std::int64_t i = begin; i < end; ++i) {
            double p[3] = {0, 0, 0};
            bool finite = true;
            for (int k = 0; k < dim; ++k) {
              p[k] = points.scalar == Scalar::Float64
                         ? static_cast<const double*>(points.coord[k])[i * points.stride]
                         : static_cast<const float*>(points.coord[k])[i * points.stride];
              finite = finite && std::isfinite(p[k]);
            }
            if (!finite) {
              invalid[i] = 1;
              continue;
            }
            CellsNear(store, bvh, p, options.maxDistance, &scratch.cells, &scratch.stack);
            scratch.candidates.clear();
            for (const std::int64_t c : scratch.cells) {
              const kernels::CellMinimaResult found =
                  kernels::CellLocalMinima(store.solver(c), p, options.maxDistance, &scratch.minima);
              if (!found.certified) certified[i] = 0;
              const kernels::TrimmedCell* trim = store.solver(c).trim();
              for (kernels::CellMinimum m : found.minima) {
                // A minimum of the cell's box outside its face's region is none of the face's.
                if (trim && !trim->Admits(m.ref)) continue;
                // Inside a volume the point is its own closest point: at
                // distance exactly 0, as invert reports it, not the rounding
                // of the solve that found it there.
                if (store.shape(c).paramDim() == dim && m.distance <= kernels::kDistanceTolerance * store.solver(c).size()) {
                  m.distance = 0.0;
                }
                scratch.candidates.push_back({c, m});
              }
            }
            std::sort(scratch.candidates.begin(), scratch.candidates.end(), [](const Candidate& a, const Candidate& b) {
              return a.minimum.distance != b.minimum.distance ? a.minimum.distance < b.minimum.distance : a.cell < b.cell;
            });
            scratch.kept.clear();
            for (const Candidate& candidate : scratch.candidates) {
              bool known = false;
              for (const Candidate& k : scratch.kept) {
                double gap2 = 0.0;
                for (int d = 0; d < dim; ++d) {
                  gap2 += (k.minimum.closest[d] - candidate.minimum.closest[d]) *
                          (k.minimum.closest[d] - candidate.minimum.closest[d]);
                }
                known = known || std::sqrt(gap2) <= mergeTolerance;
              }
              if (known || !MinimumOfEveryCellThere(store, bvh, p, candidate, onTolerance, edgeTolerance, &scratch)) continue;
              scratch.kept.push_back(candidate);
            }
            perPoint[i] = scratch.kept;
          }
        },
        options.threads);

    results->offsets.assign(n + 1, 0);
    for (std::int64_t i = 0; i < n; ++i) {
      results->offsets[i + 1] = results->offsets[i] + std::max<std::int64_t>(1, static_cast<std::int64_t>(perPoint[i].size()));
    }
    const std::size_t rows = static_cast<std::size_t>(results->offsets[n]);
    Results& out = results->minima;
    out.status.resize(rows);
    out.patch.resize(rows);
    out.cell.resize(rows);
    out.params.resize(3 * rows);
    out.closest.resize(3 * rows);
    out.distance.resize(rows);
    out.iterations.resize(rows);
    for (std::int64_t i = 0; i < n; ++i) {
      const std::size_t first = static_cast<std::size_t>(results->offsets[i]);
      if (invalid[i] || perPoint[i].empty()) {
        WriteRow(store, nullptr, invalid[i] ? Status::Invalid : Status::None, first, &out);
        continue;
      }
      for (std::size_t m = 0; m < perPoint[i].size(); ++m) WriteRow(store, &perPoint[i][m], Status::Found, first + m, &out);
    }
    results->certified = certified;
    return Error::Ok;
  });
}

}  // namespace invmap
