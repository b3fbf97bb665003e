// Lower bounds of the distance between two boxes that live in different
// frames: the bounding boxes of two models' BVH nodes (or cells), each axis
// aligned in its own model's frame, the models under rigid motions.
#pragma once

#include "kernels/pair_problem.h"

namespace invmap::engine {

/// Bounds between A's boxes (axis aligned in A's frame) and B's (axis
/// aligned in B's frame), given the motion of B's frame into A's.
class BoxPairBound {
 public:
  explicit BoxPairBound(const kernels::RigidMotion& bIntoA);

  /// A lower bound of the distance between box [loA, hiA] of A and box
  /// [loB, hiB] of B: the largest gap between their projections on A's
  /// axes, B's axes and the line through their centres (separating axes:
  /// any such gap is at most the distance). 0 when they may overlap.
  double LowerBound(const double* loA, const double* hiA, const double* loB, const double* hiB) const;

 private:
  double rotation_[3][3];
  double absRotation_[3][3];
  double translation_[3];
  bool identity_ = false;
};

/// The motion of B's frame into A's: motionA^-1 o motionB.
kernels::RigidMotion RelativeMotion(const kernels::RigidMotion& motionA, const kernels::RigidMotion& motionB);

}  // namespace invmap::engine
