// Oriented boxes: a second bounding volume for the nearest-cell search, next
// to the axis-aligned boxes. An oriented box is lo_j <= a_j . x <= hi_j for
// three orthogonal axes a_j, the principal axes of a set of cells' control
// points. A cell lies in the convex hull of its control points (positive
// weights), so it lies in the box.
//
// Why: an axis-aligned box bounds the distance to a patch of size h only to
// within O(h) wherever the patch is tilted against the axes, while a box
// along the patch's own axes is as thin as the patch bulges, O(h^2). With
// axis-aligned boxes alone the cells whose bound a near point cannot
// exclude grow like 1/h: on a refined surface, 3 times the cells a point
// must reject (by their Bernstein distance nets) for every 10 times the
// cells (measured, the wavy surface from 10^3 to 10^5 cells).
#pragma once

#include <cstddef>

#include <Eigen/Core>

namespace invmap::engine {

/// lo[j] <= axis[j] . (x - origin) <= hi[j], j = 0, 1, 2, for every point x
/// of the hull, in floats like the wide tree's boxes and rounded outward.
/// The axes are orthogonal and scaled so that the matrix of their float
/// values has norm below 1: the distance to the box in their frame never
/// exceeds the distance in space. An axis of a box that bounds nothing
/// along it has lo -inf, hi +inf; the unbounded box has three.
struct OrientedBox {
  float axis[3][3];  ///< axis[j][k]: component k of axis j.
  float lo[3];
  float hi[3];
};

/// The oriented box that holds everything; used where no hull is known.
OrientedBox UnboundedOrientedBox();

/// Count, mean and centred scatter of a set of points: enough to choose an
/// oriented box's axes, and merged exactly across sets (Chan et al.'s
/// pairwise update), so a tree's nodes get theirs from their children's
/// without rereading the points.
struct PointMoments {
  double count = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();  ///< Sum of (x - mean)(x - mean)^T.
  /// False when some set merged in had no hull to give: no box then.
  bool complete = true;

  /// The moments of `count` points (3 coordinates each); no points is no
  /// hull (not complete).
  static PointMoments Of(const double* xyz, std::size_t count);
  /// The moments of the union of two sets.
  static PointMoments Merge(const PointMoments& a, const PointMoments& b);
};

/// Fits an oriented box along the principal axes of `moments` to the points
/// those moments describe, given (again) to AddToInterval; Result() is the
/// box.
class OrientedBoxFitter {
 public:
  /// `dimension` 2 keeps the axes in the plane (the third coordinate is
  /// ignored and the third axis bounds nothing); offsets are taken from
  /// `origin`.
  OrientedBoxFitter(int dimension, const double origin[3], const PointMoments& moments);

  /// `count` points, 3 coordinates each (any order, in any number of calls).
  void AddToInterval(const double* xyz, std::size_t count);
  /// The box; unbounded when the moments were empty or incomplete, or a
  /// point was not finite.
  OrientedBox Result() const;

 private:
  int dimension_;
  Eigen::Vector3d origin_;
  bool valid_ = true;
  float axis_[3][3] = {};
  double lo_[3], hi_[3];
  double magnitude_ = 0.0;  ///< Largest sum of |offset| over the points.
};

}  // namespace invmap::engine
