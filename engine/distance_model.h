// The insides of the public distance API (include/invmap/distance.h) that
// its implementation files share: a prepared model, poses turned into rigid
// motions, and engine answers turned into the public records.
#pragma once

#include <string>

#include "engine/distance_cells.h"
#include "engine/model_distance.h"
#include "invmap/distance.h"

namespace invmap {

struct DistanceModel::Impl {
  const Manifold* manifold = nullptr;
  engine::DistanceCells cells;
};

struct DistanceAccess {
  static const DistanceModel::Impl* Get(const DistanceModel& model) { return model.impl_.get(); }
};

namespace engine {

/// The rigid motion of a pose, for models of dimension `dimension`: false,
/// with the reason in `error`, when the pose is not finite, its matrix is not
/// a rotation to 1e-6 (orthonormal, determinant +1), or (2D) it leaves the
/// plane. The rotation used is the polar factor of the given matrix.
bool ToMotion(const Pose& pose, int dimension, kernels::RigidMotion* motion, std::string* error);

/// The public answer of an engine answer.
DistanceAnswer ToAnswer(const CellPairAnswer& answer, const DistanceModel::Impl& a, const DistanceModel::Impl& b);

/// The placed model of a prepared one.
PlacedModel Place(const DistanceModel::Impl& model, const kernels::RigidMotion& motion);

}  // namespace engine
}  // namespace invmap
