// The public distance API's boundary (include/invmap/distance.h): argument
// checks, poses, and the only place its calls catch exceptions.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <stdexcept>

#include "engine/api_errors.h"
#include "engine/distance_model.h"
#include "engine/manifold_access.h"
#include "engine/model_minima.h"
#include "kernels/active_set.h"
#include "kernels/cell_shape.h"

namespace invmap {
namespace {

/// The model's dimension (Manifold::Info gathers far more, too slowly for
/// every query).
int DimensionOf(const DistanceModel& model) { return DistanceAccess::Get(model)->cells.dimension(); }

/// The checks every query makes of its models and options.
void CheckModels(const DistanceModel& a, const DistanceModel& b, const DistanceOptions& options) {
  if (!a.valid() || !b.valid()) throw std::invalid_argument("a distance model is empty (not built)");
  const int da = DimensionOf(a), db = DimensionOf(b);
  if (da != db) {
    throw std::invalid_argument("the models' dimensions differ (" + std::to_string(da) + " and " +
                                std::to_string(db) + ")");
  }
  if (std::isnan(options.maxDistance) || options.maxDistance < 0.0) {
    std::ostringstream why;  // -1, not to_string's -1.000000
    why << "options: maxDistance " << options.maxDistance << ", expected >= 0";
    throw std::invalid_argument(why.str());
  }
  if (options.threads < 0) throw std::invalid_argument("options: threads must be >= 0 (0 = all cores)");
}

/// result->minima: every local minimum of the distance (engine/model_minima.h).
void AddAllMinima(const DistanceModel::Impl& a, const kernels::RigidMotion& ma, const DistanceModel::Impl& b,
                  const kernels::RigidMotion& mb, double maxDistance, engine::ModelDistanceWorkspace* ws,
                  DistanceResult* result) {
  bool certified = true;
  const std::vector<engine::CellPairAnswer> minima =
      engine::AllPairMinima(engine::Place(a, ma), engine::Place(b, mb), maxDistance, &certified, ws);
  // Models that meet where the enumeration of faces never looks (a part of
  // one inside a volume of the other, which the inside test found): the
  // points at distance 0 there form a continuum, which no list of isolated
  // minima holds. Its common point stands for it, and the list is not
  // certified complete.
  const bool overlapUnlisted = result->nearest.found && result->nearest.distance == 0.0 &&
                               (minima.empty() || minima.front().distance > 0.0);
  if (overlapUnlisted) {
    certified = false;
    result->minima.push_back(result->nearest);
  }
  for (const engine::CellPairAnswer& m : minima) {
    DistanceAnswer answer = engine::ToAnswer(m, a, b);
    answer.certified = certified;
    result->minima.push_back(answer);
  }
  if (overlapUnlisted) result->minima.front().certified = false;
}

kernels::RigidMotion MotionOrThrow(const Pose& pose, int dimension, const char* which) {
  kernels::RigidMotion motion;
  std::string error;
  if (!engine::ToMotion(pose, dimension, &motion, &error)) throw std::invalid_argument(std::string(which) + ": " + error);
  return motion;
}

}  // namespace

Pose Pose::FromRows(const double* twelve) {
  Pose pose;
  std::copy(twelve, twelve + 12, pose.m);
  return pose;
}

Pose Pose::FromAxisAngle(const double* axis, double angle, const double* translation) {
  const Eigen::Vector3d unit = Eigen::Vector3d(axis[0], axis[1], axis[2]).normalized();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, unit).toRotationMatrix();
  Pose pose;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) pose.m[4 * k + l] = r(k, l);
    pose.m[4 * k + 3] = translation[k];
  }
  return pose;
}

std::string CheckPose(const Pose& pose, int dimension) {
  kernels::RigidMotion motion;
  std::string error;
  return engine::ToMotion(pose, dimension, &motion, &error) ? std::string() : error;
}

namespace engine {

bool ToMotion(const Pose& pose, int dimension, kernels::RigidMotion* motion, std::string* error) {
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) r(k, l) = pose.m[4 * k + l];
    t[k] = pose.m[4 * k + 3];
  }
  if (!r.allFinite() || !t.allFinite()) {
    *error = "the pose has a NaN or infinite number";
    return false;
  }
  // The posed model's coordinates stay within a few times the supported
  // range, where the pair search's squared distances are normal doubles (a
  // translation of 1e155 overflowed them: a null distance "certified").
  if (t.cwiseAbs().maxCoeff() > kernels::kMaxCoordinate) {
    std::ostringstream text;
    text << "the pose's translation (" << t[0] << ", " << t[1] << ", " << t[2]
         << ") lies outside [-1e100, 1e100] (the range invmap supports)";
    *error = text.str();
    return false;
  }
  const double deviation = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(deviation <= 1e-6) || !(r.determinant() > 0.0)) {
    std::ostringstream text;
    text << "the pose's 3 x 3 part is not a rotation (R^T R differs from I by " << deviation << ", determinant "
         << r.determinant() << ")";
    *error = text.str();
    return false;
  }
  if (dimension == 2 && (r(0, 2) != 0.0 || r(1, 2) != 0.0 || r(2, 0) != 0.0 || r(2, 1) != 0.0 || r(2, 2) != 1.0 ||
                         t[2] != 0.0)) {
    *error = "a pose of a 2D model must keep the plane z = 0 (r02 = r12 = r20 = r21 = tz = 0, r22 = 1)";
    return false;
  }
  // The nearest rotation (the polar factor): the distance nets assume an
  // exact one (a rotation keeps |N|^2).
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d exact = deviation == 0.0 ? r : Eigen::Matrix3d(svd.matrixU() * svd.matrixV().transpose());
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) motion->rotation[k][l] = exact(k, l);
    motion->translation[k] = t[k];
  }
  return true;
}

PlacedModel Place(const DistanceModel::Impl& model, const kernels::RigidMotion& motion) {
  PlacedModel placed;
  placed.cells = &model.cells;
  placed.motion = motion;
  placed.manifold = model.manifold;
  return placed;
}

namespace {

ModelPoint ToModelPoint(const CellPairAnswer& answer, int side, const DistanceModel::Impl& model) {
  ModelPoint point;
  const CellStore& store = model.cells.store();
  const std::int64_t cell = answer.sourceCell[side];
  const CellOrigin origin = store.origin(cell);
  const kernels::CellShape& shape = store.shape(cell);
  double ref[3] = {answer.sourceRef[side][0], answer.sourceRef[side][1], answer.sourceRef[side][2]};
  kernels::SnapToDomain(shape.type(), ref);
  point.patch = origin.patch;
  point.cell = origin.indexInPatch;
  // As point queries report them: knot values, angles where a direction is
  // angular, and on a trimmed face's edge the pcurve's (u, v).
  double params[3];
  store.ReportedParameters(cell, ref, params);
  for (int i = 0; i < 3; ++i) point.params[i] = params[i];
  const int dim = store.dimension();
  for (int k = 0; k < 3; ++k) point.point[k] = k < dim ? answer.point[side][k] : 0.0;
  return point;
}

}  // namespace

DistanceAnswer ToAnswer(const CellPairAnswer& answer, const DistanceModel::Impl& a, const DistanceModel::Impl& b) {
  DistanceAnswer out;
  out.certified = answer.certified;
  if (!answer.found) return out;
  out.found = true;
  out.distance = answer.distance;
  out.a = ToModelPoint(answer, 0, a);
  out.b = ToModelPoint(answer, 1, b);
  return out;
}

}  // namespace engine

DistanceModel::DistanceModel() = default;
DistanceModel::~DistanceModel() = default;
DistanceModel::DistanceModel(const DistanceModel&) = default;
DistanceModel& DistanceModel::operator=(const DistanceModel&) = default;

bool DistanceModel::valid() const { return impl_ != nullptr; }
const Manifold& DistanceModel::manifold() const { return *impl_->manifold; }
std::size_t DistanceModel::MemoryBytes() const { return impl_ ? impl_->cells.MemoryBytes() + sizeof(Impl) : 0; }

DistanceModelBuild DistanceModel::Build(const Manifold& manifold) {
  DistanceModelBuild result;
  try {
    if (!manifold.valid()) {
      result.error = "the manifold is empty (not built)";
      return result;
    }
    if (ManifoldAccess::HasPouSurfaces(manifold)) {
      result.error = "partition-of-unity surfaces (pou_manifold patches) have no distance model yet";
      return result;
    }
    auto impl = std::make_shared<Impl>();
    impl->manifold = &manifold;
    impl->cells.Build(ManifoldAccess::Store(manifold));
    result.model.impl_ = std::move(impl);
  } catch (const std::bad_alloc&) {
    result.error = "out of memory while preparing the distance model";
  } catch (const std::exception& e) {
    result.error = std::string("preparing the distance model failed: ") + e.what();
  }
  return result;
}

Error Distance(const DistanceModel& a, const Pose& poseA, const DistanceModel& b, const Pose& poseB,
               const DistanceOptions& options, DistanceResult* result, std::string* message) {
  return engine::Guarded(message, [&] {
    if (!result) throw std::invalid_argument("result: null");
    CheckModels(a, b, options);
    const int dim = DimensionOf(a);
    const DistanceModel::Impl& ia = *DistanceAccess::Get(a);
    const DistanceModel::Impl& ib = *DistanceAccess::Get(b);
    const kernels::RigidMotion ma = MotionOrThrow(poseA, dim, "pose of A");
    const kernels::RigidMotion mb = MotionOrThrow(poseB, dim, "pose of B");
    engine::ModelDistanceOptions engineOptions;
    engineOptions.maxDistance = options.maxDistance;
    engineOptions.threads = options.threads;
    engine::ModelDistanceWorkspace ws;
    const engine::CellPairAnswer answer =
        engine::NearestPair(engine::Place(ia, ma), engine::Place(ib, mb), engineOptions, &ws);
    *result = DistanceResult();
    result->nearest = engine::ToAnswer(answer, ia, ib);
    if (options.allMinima) AddAllMinima(ia, ma, ib, mb, options.maxDistance, &ws, result);
    return Error::Ok;
  });
}

struct DistanceTracker::Impl {
  DistanceModel a, b;
  kernels::RigidMotion motionA;
  DistanceOptions options;
  engine::ModelDistanceWorkspace ws;
  engine::CellPairAnswer previous;
  bool hasPrevious = false;
  engine::PairBoundCache boundCache;
  std::string setupError;
};

DistanceTracker::DistanceTracker(const DistanceModel& a, const DistanceModel& b, const Pose& poseA,
                                 const DistanceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->a = a;
  impl_->b = b;
  impl_->options = options;
  try {
    CheckModels(a, b, options);
    impl_->motionA = MotionOrThrow(poseA, DimensionOf(a), "pose of A");
  } catch (const std::exception& e) {
    impl_->setupError = e.what();
  }
}

DistanceTracker::~DistanceTracker() = default;
DistanceTracker::DistanceTracker(DistanceTracker&&) noexcept = default;
DistanceTracker& DistanceTracker::operator=(DistanceTracker&&) noexcept = default;

Error DistanceTracker::SetPoseA(const Pose& poseA, std::string* message) {
  return engine::Guarded(message, [&] {
    if (!impl_) throw std::invalid_argument("the tracker was moved from");
    if (!impl_->setupError.empty() && impl_->setupError.rfind("pose of A", 0) != 0) {
      throw std::invalid_argument(impl_->setupError);
    }
    impl_->motionA = MotionOrThrow(poseA, DimensionOf(impl_->a), "pose of A");
    impl_->setupError.clear();
    return Error::Ok;
  });
}

Error DistanceTracker::Update(const Pose& poseB, DistanceResult* result, std::string* message) {
  return engine::Guarded(message, [&] {
    if (!impl_) throw std::invalid_argument("the tracker was moved from");
    if (!impl_->setupError.empty()) throw std::invalid_argument(impl_->setupError);
    if (!result) throw std::invalid_argument("result: null");
    const DistanceModel::Impl& ia = *DistanceAccess::Get(impl_->a);
    const DistanceModel::Impl& ib = *DistanceAccess::Get(impl_->b);
    const kernels::RigidMotion mb = MotionOrThrow(poseB, DimensionOf(impl_->b), "pose of B");
    engine::ModelDistanceOptions engineOptions;
    engineOptions.maxDistance = impl_->options.maxDistance;
    engineOptions.threads = impl_->options.threads;
    engineOptions.warm = impl_->hasPrevious ? &impl_->previous : nullptr;
    engineOptions.boundCache = &impl_->boundCache;
    const engine::CellPairAnswer answer = engine::NearestPair(engine::Place(ia, impl_->motionA), engine::Place(ib, mb),
                                                              engineOptions, &impl_->ws);
    if (answer.found) {
      impl_->previous = answer;
      impl_->hasPrevious = true;
    }
    *result = DistanceResult();
    result->nearest = engine::ToAnswer(answer, ia, ib);
    if (impl_->options.allMinima) {
      AddAllMinima(ia, impl_->motionA, ib, mb, impl_->options.maxDistance, &impl_->ws, result);
    }
    return Error::Ok;
  });
}

}  // namespace invmap
