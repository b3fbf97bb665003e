#include "engine/pou_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "common/parallel.h"
#include "engine/spatial_sort.h"
#include "kernels/tolerances.h"
#include "pou/chart_maps.h"
#include "pou/piece_search.h"

namespace invmap::engine {
namespace {

double BoxDistance2(const double* lo, const double* hi, const double* x) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = x[k] < lo[k] ? lo[k] - x[k] : x[k] > hi[k] ? x[k] - hi[k] : 0.0;
    d2 += gap * gap;
  }
  return d2 * (1.0 - 1e-15);
}

}  // namespace

std::string PouPatches::Build(const Geometry& geometry, int maxThreads) {
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    const Patch& patch = geometry.patches[p];
    if (patch.kind != Patch::Kind::PouManifold) continue;
    const std::string where = "patch " + std::to_string(p) + ": ";
    if (geometry.dimension != 3) return where + "a pou_manifold needs dimension 3";
    if (patch.points.size() % 3 != 0) return where + "vertices: coordinate count not a multiple of 3";
    if (patch.cells.size() % 3 != 0) return where + "cells: index count not a multiple of 3 (triangles)";
    for (double x : patch.points) {
      if (!std::isfinite(x)) return where + "vertices: a coordinate is not finite";
    }
    auto s = std::make_unique<Surface>();
    s->patch = p;
    if (std::string e = s->surface.Restore(patch.points, patch.cells, patch.degrees, patch.chartControlPoints);
        !e.empty()) {
      return where + e;
    }
    std::vector<pou::PieceBounds> bounds;
    RunWithThreads(maxThreads, [&] { s->pieces.Build(s->surface, &bounds); });
    std::vector<BvhBox> boxes(bounds.size());
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        boxes[i].lo[k] = bounds[i].boxLo[k];
        boxes[i].hi[k] = bounds[i].boxHi[k];
      }
    }
    BvhBuildOptions options;
    options.maxThreads = maxThreads;
    options.maxLeafSize = 8;
    s->bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()), options);
    s->wide = WideBvh(s->bvh, 3, [&bounds](int box, std::vector<double>* xyz) {
      double corners[24];
      bounds[box].OrientedCorners(corners);
      xyz->insert(xyz->end(), corners, corners + 24);
    });
    const BvhBox& root = s->bvh.RootBounds();
    // Distances the search does not try to improve on, and the gap band
    // before any answer: the core's tolerance of a cell's size, for the
    // surface's bounding box (docs/manifold.md).
    s->tolerance = kernels::kDistanceTolerance * std::hypot(root.hi[0] - root.lo[0], root.hi[1] - root.lo[1],
                                                   root.hi[2] - root.lo[2]);
    surfaces_.push_back(std::move(s));
  }
  return {};
}

const PouPatches::Surface* PouPatches::Find(std::size_t patch) const {
  for (const auto& s : surfaces_) {
    if (s->patch == patch) return s.get();
  }
  return nullptr;
}

std::int64_t PouPatches::NumCells(std::size_t patch) const {
  const Surface* s = Find(patch);
  return s ? s->surface.numCharts() : -1;
}

bool PouPatches::PointAt(std::size_t patch, std::int64_t cell, const double sample[3], double params[3],
                         double point[3]) const {
  const Surface* s = Find(patch);
  if (!s || cell < 0 || cell >= s->surface.numCharts()) return false;
  const double radius = s->surface.radius(cell) / std::sqrt(3.0);
  const double r = radius * std::sqrt(std::clamp(sample[0], 0.0, 1.0));
  const double a = 2.0 * pou::kPi * std::clamp(sample[1], 0.0, 1.0);
  params[0] = r * std::cos(a);
  params[1] = r * std::sin(a);
  params[2] = std::numeric_limits<double>::quiet_NaN();
  s->surface.EvaluatePoint(cell, params[0], params[1], point);
  return true;
}

void PouPatches::AddInfo(ManifoldInfo* info) const {
  std::map<std::string, std::size_t> byShape(info->cellsByShape.begin(), info->cellsByShape.end());
  for (const auto& s : surfaces_) {
    const bool first = info->cells == 0;
    info->cells += static_cast<std::size_t>(s->surface.numCharts());
    for (std::int64_t v = 0; v < s->surface.numCharts(); ++v) {
      const std::string d = std::to_string(s->surface.degree(v));
      ++byShape["pou chart " + d + "x" + d];
    }
    const BvhBox& root = s->bvh.RootBounds();
    for (int k = 0; k < 3; ++k) {
      info->boundsLo[k] = first ? root.lo[k] : std::min(info->boundsLo[k], root.lo[k]);
      info->boundsHi[k] = first ? root.hi[k] : std::max(info->boundsHi[k], root.hi[k]);
    }
  }
  info->cellsByShape.assign(byShape.begin(), byShape.end());
}

std::size_t PouPatches::MemoryBytes() const {
  std::size_t bytes = 0;
  for (const auto& s : surfaces_) {
    bytes += sizeof(Surface) + s->pieces.MemoryBytes() + s->bvh.MemoryBytes() + s->wide.MemoryBytes() +
             s->surface.nets().capacity() * sizeof(double) + s->surface.mesh().positions().capacity() * sizeof(double) +
             s->surface.mesh().triangles().capacity() * sizeof(std::int64_t) * 3;
  }
  return bytes;
}

void PouPatches::Invert(const QueryPoints& points, const InversionOptions& options, Results* results) const {
  const std::int64_t n = points.count;
  if (surfaces_.empty() || n == 0) return;
  // Morton order, so that each point's search starts from its neighbour's
  // answer; not when pointwise (InversionOptions::pointwise), where each
  // search starts from the nearest pieces alone and its answer depends on
  // the point and the geometry only.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool any = false;
  for (std::int64_t i = 0; i < n; ++i) {
    const double p[3] = {points.coord[0][i], points.coord[1][i], points.coord[2][i]};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = any ? std::min(lo[k], p[k]) : p[k];
      hi[k] = any ? std::max(hi[k], p[k]) : p[k];
    }
    any = true;
  }
  if (!any) return;
  std::vector<std::int64_t> order;
  SpatialSort(ExecutionPolicy::Par, points.coord[0], points.coord[1], points.coord[2], n, lo, hi, &order, nullptr,
              options.threads);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  ForEachBlock(
      ExecutionPolicy::Par, n, 256,
      [&](std::int64_t begin, std::int64_t end) {
        // The previous point's answer per surface: where the next search starts.
        std::vector<pou::ChartPoint> previous(surfaces_.size(), pou::ChartPoint{-1, 0, 0});
        // A wide tree entry: a node (count 0) or a leaf's items, and the
        // lower bound of the squared distance it was pushed with.
        struct Entry {
          double bound2;
          int first, count;
        };
        std::vector<Entry> pending;
        for (std::int64_t s = begin; s < end; ++s) {
          const std::int64_t i = order[s];
          if (results->status[i] == Status::Invalid) continue;
          for (std::size_t k = 0; k < surfaces_.size(); ++k) {
            const Surface& surface = *surfaces_[k];
            // A cell's answer (or an earlier surface's) is beaten only by a
            // nearer point; before any answer, the gap tolerance admits the
            // same band as the cells' search (PointSearch::GapBand, with the
            // surface's size): a point at distance maxDistance is found.
            const bool hadAnswer = results->status[i] == Status::Found;
            const double cutoff = hadAnswer ? results->distance[i] : options.maxDistance;
            const double band = hadAnswer ? 0.0 : surface.tolerance;
            const double x[3] = {points.coord[0][i], points.coord[1][i], points.coord[2][i]};
            pou::PointSearch search(surface.surface, x, surface.tolerance, cutoff, band);
            if (previous[k].chart >= 0 && !options.pointwise) {
              search.Seed(previous[k].chart, previous[k].u, previous[k].v);
            }
            // Depth first over the wide tree, nearest child first; an entry
            // is skipped when its bound (recorded when it was pushed) no
            // longer beats the cut-off.
            const WideBvh& wide = surface.wide;
            const Bvh& bvh = surface.bvh;
            const WidePoint point = wide.Prepare(x);
            pending.clear();
            if (!wide.Nodes().empty()) pending.push_back({0.0, 0, 0});
            while (!pending.empty()) {
              const Entry entry = pending.back();
              pending.pop_back();
              if (entry.bound2 >= search.Cutoff2()) continue;
              if (entry.count > 0) {
                for (int item = entry.first; item < entry.first + entry.count; ++item) {
                  if (BoxDistance2(bvh.ItemBoxes()[item].lo, bvh.ItemBoxes()[item].hi, x) >= search.Cutoff2()) continue;
                  if (WideBvh::OrientedDistance2(wide.ItemOrientedBox(item), point) >= search.Cutoff2()) continue;
                  const pou::Piece& piece = surface.pieces.pieces()[bvh.Items()[item]];
                  search.SearchPiece(piece.chart, pou::PieceBox(surface.surface, piece), surface.pieces.Shapes(piece));
                }
                continue;
              }
              const WideNode& node = wide.Nodes()[entry.first];
              double box2[4], bound2[4];
              WideBvh::ChildDistances2(node, point, box2, bound2);
              // The children within the cut-off, pushed farthest first.
              Entry near[4];
              int count = 0;
              for (int c = 0; c < 4; ++c) {
                if (node.count[c] < 0 || !(bound2[c] < search.Cutoff2())) continue;
                int at = count++;
                for (; at > 0 && near[at - 1].bound2 < bound2[c]; --at) near[at] = near[at - 1];
                near[at] = {bound2[c], node.first[c], node.count[c]};
              }
              for (int c = 0; c < count; ++c) pending.push_back(near[c]);
            }
            if (!search.found()) continue;
            previous[k] = {search.chart(), search.u(), search.v()};
            if (hadAnswer && !(search.distance() < results->distance[i])) continue;
            const pou::ChartPoint owner = surface.surface.Owner(search.chart(), search.u(), search.v());
            results->status[i] = Status::Found;
            results->patch[i] = static_cast<std::int32_t>(surface.patch);
            results->cell[i] = owner.chart;
            results->params[3 * i] = owner.u;
            results->params[3 * i + 1] = owner.v;
            results->params[3 * i + 2] = kNaN;
            for (int c = 0; c < 3; ++c) results->closest[3 * i + c] = search.point()[c];
            results->distance[i] = search.distance();
            results->iterations[i] = search.boxes();
          }
        }
      },
      options.threads);
}

}  // namespace invmap::engine
