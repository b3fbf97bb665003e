#include "engine/distance_cells.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "kernels/cell_bounds.h"
#include "kernels/simplex_index.h"

namespace invmap::engine {
namespace {

/// A face of a volume cell before the shared ones are dropped.
struct FaceCandidate {
  std::int64_t cell = 0;
  kernels::CellShape shape;
  std::int64_t pointOffset = 0;  ///< First coordinate in the candidates' point array.
  std::int64_t weightOffset = -1;
  double origin[3] = {0, 0, 0};
  double axis[2][3] = {};
  std::uint64_t hash = 0;
};

/// Positions of a net's coefficient in each factor, first factor fastest.
struct NetStrides {
  int count[kernels::kMaxFactors] = {1, 1, 1};
  int stride[kernels::kMaxFactors] = {1, 1, 1};
  explicit NetStrides(const kernels::CellShape& shape) {
    int s = 1;
    for (int f = 0; f < shape.numFactors(); ++f) {
      count[f] = kernels::SimplexBasisSize(shape.factor(f).dim, shape.factor(f).degree);
      stride[f] = s;
      s *= count[f];
    }
  }
};

/// The shape of a face: the cell's factors with factor `cut` lowered by one
/// dimension (a line factor disappears).
kernels::CellShape FaceShape(const kernels::CellShape& shape, int cut) {
  int dims[kernels::kMaxFactors] = {0, 0, 0}, degrees[kernels::kMaxFactors] = {0, 0, 0}, count = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const int dim = shape.factor(f).dim - (f == cut ? 1 : 0);
    if (dim == 0) continue;
    dims[count] = dim;
    degrees[count++] = shape.factor(f).degree;
  }
  kernels::CellType type = kernels::CellType::Line;
  if (count == 1) {
    type = dims[0] == 1 ? kernels::CellType::Line : kernels::CellType::Tri;
  } else if (count == 2 && dims[0] == 1 && dims[1] == 1) {
    type = kernels::CellType::Quad;
  } else if (count == 2 && dims[0] == 2 && dims[1] == 1) {
    type = kernels::CellType::Wedge;
  }
  return kernels::CellShape(type, {degrees[0], count > 1 ? degrees[1] : 0, count > 2 ? degrees[2] : 0});
}

/// Appends face (`cut`, `vertex`) of a volume cell to `candidate`: its
/// control points (and weights) are the cell's with barycentric
/// coordinate `vertex` of factor `cut` zero; its coordinates map into the
/// cell's by origin + axes.
void ExtractFace(const kernels::CellView& cell, int cut, int vertex, FaceCandidate* candidate,
                 std::vector<double>* points, std::vector<double>* weights) {
  const kernels::CellShape& shape = cell.shape;
  const kernels::CellShape face = FaceShape(shape, cut);
  candidate->shape = face;
  const NetStrides cellStrides(shape), faceStrides(face);
  const kernels::SimplexFactor& cutFactor = shape.factor(cut);
  // The cut factor's remaining vertices, ascending.
  int remaining[3], numRemaining = 0;
  for (int v = 0; v <= cutFactor.dim; ++v) {
    if (v != vertex) remaining[numRemaining++] = v;
  }
  // The embedding: the other factors' coordinates pass through; the cut
  // factor's are the remaining simplex vertices' combination.
  std::fill(candidate->origin, candidate->origin + 3, 0.0);
  for (auto& axis : candidate->axis) std::fill(axis, axis + 3, 0.0);
  int faceFactor = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const kernels::SimplexFactor& factor = shape.factor(f);
    if (f != cut) {
      const int faceOffset = face.factor(faceFactor++).offset;
      for (int i = 0; i < factor.dim; ++i) candidate->axis[faceOffset + i][factor.offset + i] = 1.0;
      continue;
    }
    // Vertex v of the factor's simplex sits at e_v (v >= 1) or the origin.
    auto at = [&](int v, int i) { return v == i + 1 ? 1.0 : 0.0; };
    for (int i = 0; i < factor.dim; ++i) candidate->origin[factor.offset + i] = at(remaining[0], i);
    if (factor.dim > 1) {
      const int faceOffset = face.factor(faceFactor++).offset;
      for (int j = 1; j < numRemaining; ++j) {
        for (int i = 0; i < factor.dim; ++i) {
          candidate->axis[faceOffset + j - 1][factor.offset + i] = at(remaining[j], i) - at(remaining[0], i);
        }
      }
    }
  }
  // The face's control points, face net order.
  const int ad = cell.ambientDim;
  const int faceSize = face.numControlPoints();
  candidate->pointOffset = static_cast<std::int64_t>(points->size());
  candidate->weightOffset = cell.weights ? static_cast<std::int64_t>(weights->size()) : -1;
  const kernels::SimplexIndex& cutIndex = kernels::SimplexIndex::Get(cutFactor.dim, cutFactor.degree);
  const kernels::SimplexIndex* faceCutIndex =
      cutFactor.dim > 1 ? &kernels::SimplexIndex::Get(cutFactor.dim - 1, cutFactor.degree) : nullptr;
  for (int c = 0; c < faceSize; ++c) {
    int cellPosition = 0;
    int fi = 0;
    for (int f = 0; f < shape.numFactors(); ++f) {
      if (f != cut) {
        const int position = (c / faceStrides.stride[fi]) % faceStrides.count[fi];
        cellPosition += position * cellStrides.stride[f];
        ++fi;
        continue;
      }
      int position;
      if (cutFactor.dim == 1) {
        // lambda_1 = 0 is u = 0 (index 0); lambda_0 = 0 is u = 1 (the last).
        position = vertex == 1 ? 0 : cutFactor.degree;
      } else {
        const int facePosition = (c / faceStrides.stride[fi]) % faceStrides.count[fi];
        const std::array<int, 4>& b = faceCutIndex->multi(facePosition);
        std::array<int, 4> alpha{0, 0, 0, 0};
        for (int j = 0; j < numRemaining; ++j) alpha[remaining[j]] = b[j];
        position = cutIndex.Position(alpha);
        ++fi;
      }
      cellPosition += position * cellStrides.stride[f];
    }
    for (int k = 0; k < ad; ++k) points->push_back(cell.points[static_cast<size_t>(cellPosition) * ad + k]);
    if (cell.weights) weights->push_back(cell.weights[cellPosition]);
  }
  // A hash of the sorted control points (and weights): the same face of two
  // cells lists them in another order.
  std::vector<std::array<double, 4>> sorted(faceSize);
  for (int c = 0; c < faceSize; ++c) {
    for (int k = 0; k < 4; ++k) sorted[c][k] = 0.0;
    for (int k = 0; k < ad; ++k) sorted[c][k] = (*points)[candidate->pointOffset + c * ad + k];
    if (cell.weights) sorted[c][3] = (*weights)[candidate->weightOffset + c];
  }
  std::sort(sorted.begin(), sorted.end());
  std::uint64_t hash = 1469598103934665603ull;
  for (const auto& p : sorted) {
    for (const double v : p) {
      std::uint64_t bits;
      const double normalized = v == 0.0 ? 0.0 : v;  // -0 and +0 are one coordinate
      std::memcpy(&bits, &normalized, sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
  }
  candidate->hash = hash;
}

/// The sorted control points (and weights) of a candidate: equal for the
/// same face of two cells.
std::vector<std::array<double, 4>> FaceKey(const FaceCandidate& face, int ad, const std::vector<double>& points,
                                           const std::vector<double>& weights) {
  const int size = face.shape.numControlPoints();
  std::vector<std::array<double, 4>> key(size);
  for (int c = 0; c < size; ++c) {
    key[c] = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < ad; ++k) key[c][k] = points[face.pointOffset + c * ad + k] + 0.0;
    if (face.weightOffset >= 0) key[c][3] = weights[face.weightOffset + c];
  }
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

void BuildCellNets(const kernels::CellView& cell, const double* boxLo, const double* boxHi,
                   kernels::DistanceNets* nets) {
  double center[3];
  for (int k = 0; k < 3; ++k) center[k] = 0.5 * (boxLo[k] + boxHi[k]);
  nets->Build(cell, center);
}

void DistanceCells::Build(const CellStore& store) {
  store_ = &store;
  cells_.clear();
  nets_.clear();
  const int ad = store.dimension();
  // The largest span index per direction of every B-spline volume patch:
  // its cells' faces at span 0 or at that index lie on the patch's boundary.
  std::vector<std::array<int, 3>> lastSpan(store.numPatches(), {0, 0, 0});
  for (std::int64_t c = 0; c < store.size(); ++c) {
    const CellOrigin origin = store.origin(c);
    if (!origin.sharedParameters) continue;
    for (int d = 0; d < 3; ++d) lastSpan[origin.patch][d] = std::max(lastSpan[origin.patch][d], origin.span[d]);
  }

  std::vector<FaceCandidate> candidates;
  std::vector<double> candidatePoints, candidateWeights;
  double modelLo[3] = {0, 0, 0}, modelHi[3] = {0, 0, 0};
  bool any = false;
  for (std::int64_t c = 0; c < store.size(); ++c) {
    const kernels::CellSolver& solver = store.solver(c);
    for (int k = 0; k < 3; ++k) {
      modelLo[k] = any ? std::min(modelLo[k], solver.boxLo()[k]) : solver.boxLo()[k];
      modelHi[k] = any ? std::max(modelHi[k], solver.boxHi()[k]) : solver.boxHi()[k];
    }
    any = true;
    if (!solver.isFullRank()) {
      DistanceCell cell;
      cell.view = solver.cell();
      cell.sourceCell = c;
      std::copy(solver.boxLo(), solver.boxLo() + 3, cell.boxLo);
      std::copy(solver.boxHi(), solver.boxHi() + 3, cell.boxHi);
      cell.size = solver.size();
      cell.affine = solver.isAffine();
      cells_.push_back(cell);
      nets_.push_back(solver.isAffine() ? nullptr : &solver.nets());
      continue;
    }
    hasVolumes_ = true;
    const kernels::CellView& view = solver.cell();
    const CellOrigin origin = store.origin(c);
    for (int f = 0; f < view.shape.numFactors(); ++f) {
      const int dim = view.shape.factor(f).dim;
      for (int v = 0; v <= dim; ++v) {
        if (origin.sharedParameters && dim == 1) {
          // A B-spline volume's faces inside its patch are shared by the
          // neighbouring span: only the patch's outer faces are boundary.
          const int span = origin.span[view.shape.factor(f).offset];
          const bool outer = v == 1 ? span == 0 : span == lastSpan[origin.patch][view.shape.factor(f).offset];
          if (!outer) continue;
        }
        FaceCandidate candidate;
        candidate.cell = c;
        ExtractFace(view, f, v, &candidate, &candidatePoints, &candidateWeights);
        candidates.push_back(candidate);
      }
    }
  }
  double diagonal2 = 0.0;
  for (int k = 0; k < 3; ++k) diagonal2 += (modelHi[k] - modelLo[k]) * (modelHi[k] - modelLo[k]);
  modelSize_ = std::sqrt(diagonal2);

  // Faces two volume cells share (equal control points) are inside the
  // model: drop them in pairs.
  std::vector<std::size_t> order(candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return candidates[x].hash != candidates[y].hash ? candidates[x].hash < candidates[y].hash : x < y;
  });
  std::vector<char> keep(candidates.size(), 1);
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first + 1;
    while (last < order.size() && candidates[order[last]].hash == candidates[order[first]].hash) ++last;
    if (last - first > 1) {
      std::vector<std::vector<std::array<double, 4>>> keys;
      for (std::size_t i = first; i < last; ++i) {
        keys.push_back(FaceKey(candidates[order[i]], ad, candidatePoints, candidateWeights));
      }
      for (std::size_t i = first; i < last; ++i) {
        if (!keep[order[i]]) continue;
        for (std::size_t j = i + 1; j < last; ++j) {
          if (keep[order[j]] && candidates[order[i]].shape.numControlPoints() ==
                                    candidates[order[j]].shape.numControlPoints() &&
              keys[i - first] == keys[j - first]) {
            keep[order[i]] = keep[order[j]] = 0;
            break;
          }
        }
      }
    }
    first = last;
  }

  // The kept faces' nets, copied compactly (views point into them, so they
  // are laid out before any view is taken).
  facePoints_.clear();
  faceWeights_.clear();
  std::vector<std::int64_t> pointAt(candidates.size(), -1), weightAt(candidates.size(), -1);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!keep[i]) continue;
    const FaceCandidate& face = candidates[i];
    const int count = face.shape.numControlPoints();
    pointAt[i] = static_cast<std::int64_t>(facePoints_.size());
    facePoints_.insert(facePoints_.end(), candidatePoints.begin() + face.pointOffset,
                       candidatePoints.begin() + face.pointOffset + static_cast<std::int64_t>(count) * ad);
    if (face.weightOffset >= 0) {
      weightAt[i] = static_cast<std::int64_t>(faceWeights_.size());
      faceWeights_.insert(faceWeights_.end(), candidateWeights.begin() + face.weightOffset,
                          candidateWeights.begin() + face.weightOffset + count);
    }
  }
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!keep[i]) continue;
    const FaceCandidate& face = candidates[i];
    DistanceCell cell;
    cell.view.shape = face.shape;
    cell.view.ambientDim = ad;
    cell.view.points = facePoints_.data() + pointAt[i];
    cell.view.weights = weightAt[i] >= 0 ? faceWeights_.data() + weightAt[i] : nullptr;
    cell.sourceCell = face.cell;
    cell.isFace = true;
    std::copy(face.origin, face.origin + 3, cell.faceOrigin);
    for (int j = 0; j < 2; ++j) std::copy(face.axis[j], face.axis[j] + 3, cell.faceAxis[j]);
    kernels::ComputeControlBox(cell.view, cell.boxLo, cell.boxHi);
    double d2 = 0.0;
    for (int k = 0; k < ad; ++k) d2 += (cell.boxHi[k] - cell.boxLo[k]) * (cell.boxHi[k] - cell.boxLo[k]);
    cell.size = std::sqrt(d2);
    if (!(cell.size > 0.0)) cell.size = std::max(modelSize_, 1.0) * 1e-300;
    cell.affine = kernels::IsAffineCell(cell.view, cell.size);
    cells_.push_back(cell);
    if (cell.affine) {
      nets_.push_back(nullptr);
    } else {
      faceNets_.push_back(std::make_unique<kernels::DistanceNets>());
      BuildCellNets(cell.view, cell.boxLo, cell.boxHi, faceNets_.back().get());
      nets_.push_back(faceNets_.back().get());
    }
  }

  std::vector<BvhBox> boxes(cells_.size());
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      boxes[i].lo[k] = cells_[i].boxLo[k];
      boxes[i].hi[k] = cells_[i].boxHi[k];
    }
  }
  // Leaves of at most 2 cells: the dual traversal prunes pairs of nodes by
  // their oriented bounds, far tighter than a leaf's pairs of cell boxes,
  // and a tracker's kept frontier is the finer for it (measured on
  // triangle meshes: tracked poses 1.3x faster than with leaves of 4,
  // fresh queries the same).
  BvhBuildOptions options;
  options.maxLeafSize = 2;
  bvh_ = BuildBvh(boxes.data(), static_cast<int>(boxes.size()), options);
  BuildOrientedBounds();
}

void DistanceCells::BuildOrientedBounds() {
  const std::vector<BvhNode>& nodes = bvh_.Nodes();
  nodeOriented_.assign(nodes.size(), OrientedBounds());
  if (nodes.empty()) return;
  const double* origin = bvh_.Origin();
  // Every control point in leaf order, and where each item's start.
  std::vector<double> points;
  std::vector<std::size_t> itemStart(bvh_.Items().size() + 1, 0);
  for (std::size_t item = 0; item < bvh_.Items().size(); ++item) {
    itemStart[item] = points.size() / 3;
    const kernels::CellView& view = cells_[bvh_.Items()[item]].view;
    const int ad = view.ambientDim;
    for (int p = 0; p < view.shape.numControlPoints(); ++p) {
      double x[3] = {0, 0, 0};
      for (int k = 0; k < ad; ++k) x[k] = view.points[static_cast<std::size_t>(p) * ad + k];
      points.insert(points.end(), x, x + 3);
    }
  }
  itemStart.back() = points.size() / 3;
  // Children come after their parent: the items below a node are a range
  // in leaf order, and its moments its children's merged. Each node's box
  // is fitted to its own points (not its children's boxes, which would
  // grow a little at every level).
  std::vector<PointMoments> moments(nodes.size());
  std::vector<int> firstItem(nodes.size()), endItem(nodes.size());
  for (int i = static_cast<int>(nodes.size()) - 1; i >= 0; --i) {
    const BvhNode& node = nodes[i];
    if (node.count > 0) {
      firstItem[i] = node.first;
      endItem[i] = node.first + node.count;
      moments[i] = PointMoments::Of(points.data() + 3 * itemStart[firstItem[i]],
                                    itemStart[endItem[i]] - itemStart[firstItem[i]]);
    } else {
      firstItem[i] = std::min(firstItem[node.first], firstItem[node.first + 1]);
      endItem[i] = std::max(endItem[node.first], endItem[node.first + 1]);
      moments[i] = PointMoments::Merge(moments[node.first], moments[node.first + 1]);
    }
    const std::size_t begin = itemStart[firstItem[i]], end = itemStart[endItem[i]];
    nodeOriented_[i] = FitOrientedBounds(moments[i], origin, points.data() + 3 * begin, static_cast<int>(end - begin));
  }
}

void DistanceCells::ToSourceRef(std::int64_t i, const double* ref, double* sourceRef) const {
  const DistanceCell& cell = cells_[i];
  const int sourceDim = store_->shape(cell.sourceCell).paramDim();
  if (!cell.isFace) {
    std::copy(ref, ref + sourceDim, sourceRef);
    return;
  }
  const int faceDim = cell.view.shape.paramDim();
  for (int i2 = 0; i2 < sourceDim; ++i2) {
    double v = cell.faceOrigin[i2];
    for (int j = 0; j < faceDim; ++j) v += ref[j] * cell.faceAxis[j][i2];
    sourceRef[i2] = v;
  }
}

std::size_t DistanceCells::MemoryBytes() const {
  std::size_t bytes = cells_.capacity() * sizeof(DistanceCell) + nets_.capacity() * sizeof(void*) +
                      (facePoints_.capacity() + faceWeights_.capacity()) * sizeof(double) + bvh_.MemoryBytes() +
                      nodeOriented_.capacity() * sizeof(OrientedBounds);
  for (const auto& nets : faceNets_) bytes += nets->MemoryBytes() + sizeof(kernels::DistanceNets);
  return bytes;
}

}  // namespace invmap::engine
