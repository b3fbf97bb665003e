// Lower bounds of the distance between two boxes that live in different
// frames: the bounding boxes of two models' BVH nodes (or cells), each axis
// aligned in its own model's frame, the models under rigid motions.
#pragma once

#include <limits>

#include "engine/oriented_box.h"
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

/// A box along its own axes holding a set of points: the points x with
/// |axis[i] . (x - center)| <= half[i] (orthonormal axes, the principal
/// axes of the points, so it is as thin as the set is flat).
struct OrientedBounds {
  double center[3] = {0, 0, 0};
  double axis[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double half[3] = {0, 0, 0};
};

/// The oriented bounds of `count` points (3 coordinates each) along the
/// principal axes of `moments` (the points', or a superset's; none or
/// incomplete gives the coordinate axes), grown by a hair so that rounding never leaves a
/// point outside.
OrientedBounds FitOrientedBounds(const PointMoments& moments, const double* origin, const double* xyz, int count);

/// The 8 corners of a box (3 coordinates each).
void OrientedCorners(const OrientedBounds& box, double* corners);

/// A lower bound of the distance between oriented bounds `a` (in A's frame)
/// and `b` (in B's frame) under the motion of B's frame into A's: the
/// largest of the gap between their enclosing spheres and the gaps between
/// their projections on the 15 separating axes of two boxes (each box's 3
/// axes and their cross products). Stops once the bound reaches `target`
/// (a bound of at least it is returned then).
double OrientedPairLowerBound(const OrientedBounds& a, const OrientedBounds& b, const kernels::RigidMotion& bIntoA,
                              double target = std::numeric_limits<double>::infinity());
/// The same for two boxes in one frame (B's moved into A's beforehand:
/// a traversal meets each of B's nodes many times).
double OrientedPairLowerBound(const OrientedBounds& a, const OrientedBounds& b,
                              double target = std::numeric_limits<double>::infinity());

/// `box` under `motion` (its centre and axes moved).
OrientedBounds Moved(const OrientedBounds& box, const kernels::RigidMotion& motion);

/// The motion of B's frame into A's: motionA^-1 o motionB.
kernels::RigidMotion RelativeMotion(const kernels::RigidMotion& motionA, const kernels::RigidMotion& motionB);

}  // namespace invmap::engine
