// The cells a model offers to model-to-model distance queries: its curves
// and surfaces as they are, and each volume by its boundary faces (where a
// volume's closest points to anything outside it lie), with their distance
// nets and a BVH over their boxes.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/pair_bounds.h"
#include "kernels/distance_net.h"
#include "kernels/pair_problem.h"

namespace invmap::engine {

/// One cell of a distance query: a cell of the store, or a boundary face of
/// one of its volume cells.
struct DistanceCell {
  kernels::CellView view;            ///< Control net in the model's frame.
  std::int64_t sourceCell = 0;       ///< The store's cell that answers are reported on.
  bool isFace = false;               ///< A face of the source (volume) cell.
  /// Faces: the source cell's reference coordinates of face coordinates s:
  /// origin + sum_j s_j axis[j].
  double faceOrigin[3] = {0, 0, 0};
  double faceAxis[2][3] = {};
  double boxLo[3] = {0, 0, 0};       ///< Control-point box (model frame).
  double boxHi[3] = {0, 0, 0};
  double size = 0.0;                 ///< Its diagonal.
  bool affine = false;               ///< Affine map (kernels::IsAffineCell).
};

class DistanceCells {
 public:
  /// The distance cells of `store`. Volume cells (parametric dimension
  /// equal to the ambient one) give their boundary faces: B-spline volumes
  /// the faces on their patch's parameter box; other volume cells every
  /// face no other volume cell has with the same control points.
  void Build(const CellStore& store);

  std::int64_t size() const { return static_cast<std::int64_t>(cells_.size()); }
  const DistanceCell& cell(std::int64_t i) const { return cells_[i]; }
  /// The distance nets of cell i; null for an affine cell (callers build
  /// them on the rare pair that needs them, kernels::PairSide::nets).
  const kernels::DistanceNets* nets(std::int64_t i) const { return nets_[i]; }
  const Bvh& bvh() const { return bvh_; }
  /// Oriented bounds of BVH node i's cells' control points (along their
  /// principal axes: thin where the cells are flat, as on a fine mesh).
  const OrientedBounds& nodeOriented(int i) const { return nodeOriented_[i]; }
  const CellStore& store() const { return *store_; }
  int dimension() const { return store_->dimension(); }
  /// True when the model has volume cells (then a model inside it is at
  /// distance 0 though its boundary faces are not).
  bool hasVolumes() const { return hasVolumes_; }
  /// The source cell's reference coordinates of reference coordinates `ref` on cell i.
  void ToSourceRef(std::int64_t i, const double* ref, double* sourceRef) const;
  /// The diagonal of the model's box: the scale of its tolerances.
  double modelSize() const { return modelSize_; }
  std::size_t MemoryBytes() const;

 private:
  void BuildOrientedBounds();

  const CellStore* store_ = nullptr;
  std::vector<DistanceCell> cells_;
  std::vector<const kernels::DistanceNets*> nets_;
  /// Faces' control points, weights and nets (store cells keep their own).
  std::vector<double> facePoints_;
  std::vector<double> faceWeights_;
  std::vector<std::unique_ptr<kernels::DistanceNets>> faceNets_;
  Bvh bvh_;
  std::vector<OrientedBounds> nodeOriented_;
  bool hasVolumes_ = false;
  double modelSize_ = 0.0;
};

/// Builds the distance nets of a cell around its control box's centre.
void BuildCellNets(const kernels::CellView& cell, const double* boxLo, const double* boxHi,
                   kernels::DistanceNets* nets);

}  // namespace invmap::engine
