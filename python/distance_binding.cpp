// invmap.distance, invmap.DistanceTracker: model-to-model distance from
// Python, as dicts with the fields of `invmap distance`'s JSON.
#include "python/distance_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>

#include "invmap/distance.h"
#include "python/errors.h"
#include "python/numpy_points.h"
#include "python/py_manifold.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

/// A pose from Python: None (the identity), 12 numbers in row order, or a
/// (3, 4) or (4, 4) matrix (the last row then 0 0 0 1).
Pose ToPose(const py::handle& value, const char* name, int dimension) {
  if (value.is_none()) return Pose();
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array) throw InputError(std::string(name) + ": expected 12 numbers or a (3, 4) or (4, 4) matrix");
  const double* data = array.data();
  Pose pose;
  const bool rows12 = array.ndim() == 1 && array.shape(0) == 12;
  const bool matrix3x4 = array.ndim() == 2 && array.shape(0) == 3 && array.shape(1) == 4;
  const bool matrix4x4 = array.ndim() == 2 && array.shape(0) == 4 && array.shape(1) == 4;
  if (!rows12 && !matrix3x4 && !matrix4x4) {
    std::ostringstream shape;
    shape << "(";
    for (py::ssize_t d = 0; d < array.ndim(); ++d) shape << (d ? ", " : "") << array.shape(d);
    shape << (array.ndim() == 1 ? ",)" : ")");
    throw InputError(std::string(name) + ": shape " + shape.str() + ", expected (12,), (3, 4) or (4, 4)");
  }
  std::copy(data, data + 12, pose.m);
  if (matrix4x4 && (data[12] != 0.0 || data[13] != 0.0 || data[14] != 0.0 || data[15] != 1.0)) {
    throw InputError(std::string(name) + ": the last row of a (4, 4) pose must be 0 0 0 1");
  }
  const std::string why = CheckPose(pose, dimension);
  if (!why.empty()) throw InputError(std::string(name) + ": " + why);
  return pose;
}

DistanceOptions MakeOptions(bool allMinima, std::optional<double> maxDistance, std::optional<std::int64_t> threads) {
  DistanceOptions options;
  options.allMinima = allMinima;
  if (maxDistance) options.maxDistance = CheckedMaxDistance(*maxDistance);
  if (threads) options.threads = CheckedThreads(*threads);
  return options;
}

void ThrowOnError(Error error, const std::string& message) {
  if (error == Error::Ok) return;
  if (error == Error::InvalidArgument) throw InputError(message);
  if (error == Error::OutOfMemory) throw std::bad_alloc();
  throw std::runtime_error(message);
}

py::object PointDict(const ModelPoint& point, int dimension) {
  py::list params, coordinates;
  for (const double p : point.params) {
    if (!std::isnan(p)) params.append(p);
  }
  for (int k = 0; k < dimension; ++k) coordinates.append(point.point[k]);
  py::dict out;
  out["patch"] = point.patch;
  out["cell"] = point.cell;
  out["params"] = params;
  out["point"] = coordinates;
  return out;
}

/// One answer: distance (None when not found), a, b (None when not found), certified.
py::dict AnswerDict(const DistanceAnswer& answer, int dimension) {
  py::dict out;
  out["distance"] = answer.found ? py::object(py::float_(answer.distance)) : py::object(py::none());
  out["a"] = answer.found ? PointDict(answer.a, dimension) : py::object(py::none());
  out["b"] = answer.found ? PointDict(answer.b, dimension) : py::object(py::none());
  out["certified"] = answer.certified;
  return out;
}

py::dict ResultDict(const DistanceResult& result, int dimension, bool allMinima, double seconds) {
  py::dict out = AnswerDict(result.nearest, dimension);
  if (allMinima) {
    py::list minima;
    for (const DistanceAnswer& m : result.minima) minima.append(AnswerDict(m, dimension));
    out["minima"] = minima;
  }
  out["seconds"] = seconds;
  return out;
}

void CheckDimensions(const PyManifold& a, const PyManifold& b) {
  if (a.dimension() != b.dimension()) {
    throw InputError("the models' dimensions differ (" + std::to_string(a.dimension()) + " and " +
                     std::to_string(b.dimension()) + ")");
  }
}

py::dict Distance(const PyManifold& a, const PyManifold& b, const py::handle& poseA, const py::handle& poseB,
                  bool allMinima, std::optional<double> maxDistance, std::optional<std::int64_t> threads) {
  CheckDimensions(a, b);
  const Pose pa = ToPose(poseA, "pose_a", a.dimension());
  const Pose pb = ToPose(poseB, "pose_b", b.dimension());
  const DistanceOptions options = MakeOptions(allMinima, maxDistance, threads);
  DistanceResult result;
  std::string message;
  Error error;
  const auto start = std::chrono::steady_clock::now();
  {
    py::gil_scoped_release noGil;
    error = invmap::Distance(a.distanceModel(), pa, b.distanceModel(), pb, options, &result, &message);
  }
  ThrowOnError(error, message);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return ResultDict(result, a.dimension(), allMinima, seconds);
}

/// invmap.DistanceTracker: keeps both manifolds alive (Python references).
class PyDistanceTracker {
 public:
  PyDistanceTracker(py::object a, py::object b, const py::handle& poseA, std::optional<double> maxDistance,
                    bool allMinima, std::optional<std::int64_t> threads)
      : a_(std::move(a)), b_(std::move(b)), allMinima_(allMinima) {
    const PyManifold& ma = a_.cast<const PyManifold&>();
    const PyManifold& mb = b_.cast<const PyManifold&>();
    CheckDimensions(ma, mb);
    dimension_ = ma.dimension();
    const Pose pose = ToPose(poseA, "pose_a", dimension_);
    const DistanceOptions options = MakeOptions(allMinima, maxDistance, threads);
    py::gil_scoped_release noGil;
    tracker_ = std::make_unique<DistanceTracker>(ma.distanceModel(), mb.distanceModel(), pose, options);
  }

  py::dict Update(const py::handle& poseB) {
    const Pose pose = ToPose(poseB, "pose_b", dimension_);
    DistanceResult result;
    std::string message;
    Error error;
    const auto start = std::chrono::steady_clock::now();
    {
      py::gil_scoped_release noGil;
      const std::lock_guard<std::mutex> lock(mutex_);
      error = tracker_->Update(pose, &result, &message);
    }
    ThrowOnError(error, message);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return ResultDict(result, dimension_, allMinima_, seconds);
  }

  void SetPoseA(const py::handle& poseA) {
    const Pose pose = ToPose(poseA, "pose_a", dimension_);
    std::string message;
    Error error;
    {
      py::gil_scoped_release noGil;
      const std::lock_guard<std::mutex> lock(mutex_);
      error = tracker_->SetPoseA(pose, &message);
    }
    ThrowOnError(error, message);
  }

 private:
  py::object a_, b_;
  bool allMinima_;
  int dimension_ = 3;
  std::unique_ptr<DistanceTracker> tracker_;
  /// Updates from several Python threads take turns: a tracker carries the
  /// previous pose's answer from one update to the next.
  std::mutex mutex_;
};

/// invmap.PointTracker: keeps the manifold alive (a Python reference).
class PyPointTracker {
 public:
  PyPointTracker(py::object manifold, std::optional<double> maxDistance)
      : manifold_(std::move(manifold)), dimension_(manifold_.cast<const PyManifold&>().dimension()) {
    const DistanceOptions checked = MakeOptions(false, maxDistance, std::nullopt);
    tracker_ = std::make_unique<PointTracker>(manifold_.cast<const PyManifold&>().manifold(), checked.maxDistance);
  }

  py::dict Update(const py::handle& point) {
    const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(point);
    if (!array || array.ndim() != 1 || array.shape(0) != dimension_) {
      throw InputError("point: expected " + std::to_string(dimension_) + " coordinates");
    }
    double p[3] = {0, 0, 0};
    std::copy(array.data(), array.data() + dimension_, p);
    PointAnswer answer;
    std::string message;
    Error error;
    {
      py::gil_scoped_release noGil;
      const std::lock_guard<std::mutex> lock(mutex_);
      error = tracker_->Update(p, &answer, &message);
    }
    ThrowOnError(error, message);
    py::dict out;
    out["status"] = static_cast<int>(answer.status);
    out["patch"] = answer.patch;
    out["cell"] = answer.cell;
    out["params"] = py::make_tuple(answer.params[0], answer.params[1], answer.params[2]);
    py::list closest;
    for (int k = 0; k < dimension_; ++k) closest.append(answer.closest[k]);
    out["closest"] = py::tuple(closest);
    out["distance"] = answer.distance;
    return out;
  }

 private:
  py::object manifold_;
  int dimension_;
  std::unique_ptr<PointTracker> tracker_;
  std::mutex mutex_;  ///< As DistanceTracker's: updates take turns.
};

/// A numpy array that owns `values` (moved, not copied).
template <typename T>
py::array Adopt(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto owned = std::make_unique<std::vector<T>>(std::move(values));
  py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  const void* data = owned.release()->data();
  return py::array(py::dtype::of<T>(), std::move(shape), data, owner);
}

/// Manifold.local_minima: every local minimum of each point's distance.
py::dict LocalMinimaPy(const PyManifold& self, const py::handle& points, std::optional<double> maxDistance,
                       std::optional<std::int64_t> threads) {
  const NumpyPoints view = ReadNumpyPoints(points, self.dimension());
  const DistanceOptions checked = MakeOptions(false, maxDistance, threads);
  InversionOptions options;
  options.maxDistance = checked.maxDistance;
  options.threads = checked.threads;
  LocalMinimaResults results;
  std::string message;
  Error error;
  {
    py::gil_scoped_release noGil;
    error = LocalMinima(self.manifold(), view.view, options, &results, &message);
  }
  ThrowOnError(error, message);
  Results& rows = results.minima;
  const auto n = static_cast<py::ssize_t>(rows.status.size());
  const int dim = self.dimension();
  if (dim == 2) {
    for (py::ssize_t i = 0; i < n; ++i) {
      rows.closest[2 * i] = rows.closest[3 * i];
      rows.closest[2 * i + 1] = rows.closest[3 * i + 1];
    }
    rows.closest.resize(2 * n);
  }
  std::vector<std::uint8_t> status(rows.status.size());
  for (std::size_t i = 0; i < status.size(); ++i) status[i] = static_cast<std::uint8_t>(rows.status[i]);
  py::array_t<bool> certified(static_cast<py::ssize_t>(results.certified.size()));
  for (std::size_t i = 0; i < results.certified.size(); ++i) certified.mutable_data()[i] = results.certified[i] != 0;
  py::dict out;
  const auto offsetCount = static_cast<py::ssize_t>(results.offsets.size());
  out["offsets"] = Adopt(std::move(results.offsets), {offsetCount});
  out["status"] = Adopt(std::move(status), {n});
  out["patch"] = Adopt(std::move(rows.patch), {n});
  out["cell"] = Adopt(std::move(rows.cell), {n});
  out["params"] = Adopt(std::move(rows.params), {n, 3});
  out["closest"] = Adopt(std::move(rows.closest), {n, dim});
  out["distance"] = Adopt(std::move(rows.distance), {n});
  out["certified"] = certified;
  return out;
}

}  // namespace

void RegisterDistance(py::module_& m) {
  py::object manifold = m.attr("Manifold");
  manifold.attr("local_minima") = py::cpp_function(
      &LocalMinimaPy, py::is_method(manifold), py::arg("points"), py::arg("max_distance") = py::none(),
      py::arg("threads") = py::none(), R"doc(
Every local minimum of each point's distance within max_distance (as
`invmap invert --all-minima`), nearest first, each once.

Returns a dict of numpy arrays: offsets (N + 1,) int64 (point i's rows are
offsets[i]:offsets[i + 1]); per row status, patch, cell, params, closest,
distance as Manifold.invert gives them (a point with no minimum has one row
of status 1, an invalid point one of status 2); certified (N,) bool, False
where some cell's enumeration ran out of its budget (a continuum of minima).
)doc");
  m.def("distance", &Distance, py::arg("a"), py::arg("b"), py::arg("pose_a") = py::none(),
        py::arg("pose_b") = py::none(), py::arg("all_minima") = false, py::arg("max_distance") = py::none(),
        py::arg("threads") = py::none(), R"doc(
Minimum distance between manifolds a and b, each under a rigid pose.

pose_a, pose_b: None (identity), 12 numbers r00 r01 r02 tx r10 .. tz, or a
  (3, 4) or (4, 4) matrix; the 3 x 3 part must be a rotation.
all_minima: also list every local minimum of the distance ("minima").
max_distance: models farther apart than this give distance None.

Returns the fields of `invmap distance`'s JSON: {"distance": d or None,
"a": {"patch", "cell", "params", "point"} or None, "b": {...},
"certified": bool, "seconds": float} (and "minima": [...]); points are in
world coordinates (after the pose). Models that touch or intersect are at
distance 0 with a common point. The GIL is released while it runs.
)doc");
  py::class_<PyDistanceTracker>(m, "DistanceTracker", R"doc(
Manifold b moving against manifold a, one pose at a time (time order):
each update starts from the previous answer and is verified globally.
)doc")
      .def(py::init<py::object, py::object, const py::handle&, std::optional<double>, bool, std::optional<int>>(),
           py::arg("a"), py::arg("b"), py::arg("pose_a") = py::none(), py::arg("max_distance") = py::none(),
           py::arg("all_minima") = false, py::arg("threads") = py::none())
      .def("update", &PyDistanceTracker::Update, py::arg("pose_b"),
           "The answer for b's next pose: the dict invmap.distance returns.")
      .def("set_pose_a", &PyDistanceTracker::SetPoseA, py::arg("pose_a"), "Moves a (for the following updates).");
  py::class_<PyPointTracker>(m, "PointTracker", R"doc(
One moving point (a haptic probe) against a manifold: each update starts
from the previous answer and is verified over the whole manifold, so it is
never a stale local minimum.
)doc")
      .def(py::init<py::object, std::optional<double>>(), py::arg("manifold"), py::arg("max_distance") = py::none())
      .def("update", &PyPointTracker::Update, py::arg("point"), R"doc(
The record Manifold.invert gives for this one point, as a dict of scalars:
status (0 found, 1 none, 2 invalid), patch, cell, params (3 floats, NaN
where unused), closest (dimension floats), distance.
)doc");
}

}  // namespace invmap::python
