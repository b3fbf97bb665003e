// invmap distance queries: the minimum distance between two models under
// rigid poses (with their closest points, cells and parameters), moving
// models tracked pose after pose, every local minimum of a distance, and a
// tracked point (a haptic probe). Every answer is the certified global
// minimum, as invmap's point queries are. See docs/distance.md.
//
//   invmap::BuildResult a = invmap::Manifold::Build(geometryA), b = ...;
//   invmap::DistanceModel ma = invmap::DistanceModel::Build(a.manifold).model, mb = ...;
//   invmap::DistanceResult result;
//   invmap::Distance(ma, invmap::Pose(), mb, pose, {}, &result);
//   result.nearest.distance, result.nearest.a.point, result.nearest.b.cell, ...
//
// Nothing here throws: calls return an Error, with a message on request.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap {

/// A rigid motion x -> R x + t of a model, as 12 numbers in row order:
/// r00 r01 r02 tx  r10 r11 r12 ty  r20 r21 r22 tz. The default is the
/// identity. R must be a rotation (orthonormal, determinant +1) to 1e-6;
/// it is used as the nearest exact rotation (its polar factor). 2D models
/// take poses that keep the plane z = 0 (r02 = r12 = r20 = r21 = tz = 0,
/// r22 = 1).
struct Pose {
  double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

  /// The pose of 12 row-major numbers.
  static Pose FromRows(const double* twelve);
  /// A rotation by `angle` radians about the unit axis (x, y, z), then a translation.
  static Pose FromAxisAngle(const double* axis, double angle, const double* translation);
};

/// Empty when `pose` is a rigid motion for models of `dimension` (2 or 3),
/// else why not ("the pose's 3 x 3 part is not a rotation ...").
std::string CheckPose(const Pose& pose, int dimension);

/// One side of a distance answer: where on its model the point lies.
struct ModelPoint {
  std::int32_t patch = -1;  ///< -1 when not found.
  std::int64_t cell = -1;   ///< Cell within the patch (invert's numbering).
  /// Reported parameters (invert's: knot values for B-splines, reference
  /// coordinates otherwise); NaN where unused.
  double params[3] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::quiet_NaN()};
  /// The point in world coordinates (after the pose); z = 0 in 2D.
  double point[3] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::quiet_NaN()};
};

/// The minimum (or one local minimum) of the distance between two models.
struct DistanceAnswer {
  bool found = false;  ///< False when the models are farther apart than maxDistance.
  double distance = std::numeric_limits<double>::quiet_NaN();  ///< 0 when the models touch or intersect.
  ModelPoint a;        ///< The point of model A.
  ModelPoint b;        ///< The point of model B.
  /// True when every part of the search closed with its certificate (see
  /// docs/distance.md); false when some search ran out of its budget (the
  /// best point found is still reported).
  bool certified = true;
};

struct DistanceOptions {
  /// Models farther apart than this are "not found" (answer.found false).
  double maxDistance = std::numeric_limits<double>::infinity();
  /// Also list every local minimum of the distance (DistanceResult::minima).
  bool allMinima = false;
  /// Worker threads; 0 means all cores. Answers do not depend on it.
  int threads = 0;
};

struct DistanceResult {
  DistanceAnswer nearest;
  /// With allMinima: every local minimum of the distance not farther than
  /// maxDistance, nearest first, each distinct pair of points once.
  std::vector<DistanceAnswer> minima;
};

class DistanceModel;
struct DistanceModelBuild;

/// A manifold prepared for model-to-model distance: its curves and
/// surfaces, each volume's boundary faces, their distance bounds and a BVH.
/// It refers to the manifold, which must outlive it. Immutable, thread-safe
/// to query, cheap to copy (shared).
class DistanceModel {
 public:
  /// Never throws: an empty manifold gives an error message.
  static DistanceModelBuild Build(const Manifold& manifold);

  DistanceModel();
  ~DistanceModel();
  DistanceModel(const DistanceModel&);
  DistanceModel& operator=(const DistanceModel&);

  bool valid() const;
  const Manifold& manifold() const;
  /// Heap memory of the prepared cells and their BVH (the manifold's not included).
  std::size_t MemoryBytes() const;

  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
  friend struct DistanceAccess;
};

struct DistanceModelBuild {
  DistanceModel model;
  std::string error;  ///< Empty on success.
};

/// The minimum distance between models A and B under their poses: the
/// global minimum of |a - b| over all points a of A and b of B, with both
/// points. Models of different dimensions, or a pose that is not a rigid
/// motion, are Error::InvalidArgument.
Error Distance(const DistanceModel& a, const Pose& poseA, const DistanceModel& b, const Pose& poseB,
               const DistanceOptions& options, DistanceResult* result, std::string* message = nullptr);

/// Model B moving against model A, one pose at a time (time order): each
/// update starts from the previous answer and is verified globally, so a
/// small motion costs far less than a fresh query and a jump to another part
/// of a model is never missed. Answers are those of Distance.
class DistanceTracker {
 public:
  DistanceTracker(const DistanceModel& a, const DistanceModel& b, const Pose& poseA = Pose(),
                  const DistanceOptions& options = DistanceOptions());
  ~DistanceTracker();
  DistanceTracker(DistanceTracker&&) noexcept;
  DistanceTracker& operator=(DistanceTracker&&) noexcept;

  Error Update(const Pose& poseB, DistanceResult* result, std::string* message = nullptr);
  /// Moves A too (its pose for the following updates).
  Error SetPoseA(const Pose& poseA, std::string* message = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The answer for one point, as invert reports it (Results' fields).
struct PointAnswer {
  Status status = Status::Invalid;
  std::int32_t patch = -1;
  std::int64_t cell = -1;
  double params[3] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::quiet_NaN()};
  double closest[3] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                       std::numeric_limits<double>::quiet_NaN()};
  double distance = std::numeric_limits<double>::quiet_NaN();
};

/// One moving point (a haptic probe) against a manifold: Update(p) returns
/// the record Manifold::Invert gives for p, starting from the previous
/// answer's cell and verified globally (the whole BVH is searched under that
/// answer's bound, so it is never a stale local minimum). The manifold must
/// outlive the tracker. Not thread-safe: one tracker per thread.
class PointTracker {
 public:
  explicit PointTracker(const Manifold& manifold, double maxDistance = std::numeric_limits<double>::infinity());
  ~PointTracker();
  PointTracker(PointTracker&&) noexcept;
  PointTracker& operator=(PointTracker&&) noexcept;

  /// `point`: the manifold's dimension of coordinates. A point with a NaN
  /// or infinite coordinate gets Status::Invalid (not an error).
  Error Update(const double* point, PointAnswer* answer, std::string* message = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Every local minimum of each point's distance to the manifold within
/// options.maxDistance, nearest first, each once (a minimum on an edge that
/// cells share is one minimum, and counts only where the distance grows
/// into every cell that meets there). Point i's rows are
/// [offsets[i], offsets[i + 1]) of `minima` (Results' fields): status Found
/// for each minimum, or one row of status None (no minimum within
/// maxDistance) or Invalid (a NaN or infinite coordinate).
struct LocalMinimaResults {
  std::vector<std::int64_t> offsets;  ///< points + 1 entries.
  Results minima;
  /// Per point: 0 where some cell's enumeration ran out of its budget (a
  /// continuum of minima, such as a circle of them seen from a torus's axis).
  std::vector<std::uint8_t> certified;
};

Error LocalMinima(const Manifold& manifold, const PointsView& points, const InversionOptions& options,
                  LocalMinimaResults* results, std::string* message = nullptr);

}  // namespace invmap
