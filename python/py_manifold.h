// The manifold the Python module hands out (invmap.Manifold): a built
// manifold with the serialized geometry it was built from, which is what
// pickling sends (workers rebuild from it, not from a file), its node
// fields if any, and its distance model, prepared on first use.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "invmap/distance.h"
#include "invmap/fields.h"
#include "invmap/invmap.h"
#include "python/errors.h"
#include "python/fields_binding.h"
#include "python/geometry_state.h"

namespace invmap::python {

class PyManifold {
 public:
  /// Builds `geometry`; a malformed one throws InputError
  /// "<nameForMessages>: <reason>", worded as the command line words it.
  /// Pure C++: callers may release the GIL around it.
  PyManifold(const Geometry& geometry, const std::string& nameForMessages)
      : state_(SerializeGeometry(geometry)), dimension_(geometry.dimension), patches_(geometry.patches.size()) {
    BuildResult built = Manifold::Build(geometry);
    if (!built.error.empty()) throw InputError(nameForMessages + ": " + built.error);
    manifold_ = std::move(built.manifold);
    for (std::size_t p = 0; p < patches_; ++p) cells_ += manifold_.NumCells(static_cast<int>(p));
  }

  /// The same with the node fields of the geometry's file (kept for probe).
  PyManifold(FieldGeometry&& model, const std::string& nameForMessages) : PyManifold(model.geometry, nameForMessages) {
    if (model.fields.empty()) return;
    state_ = SerializeModel(state_, model.fields);
    fields_ = std::make_shared<const FieldGeometry>(std::move(model));
  }

  const Manifold& manifold() const { return manifold_; }
  /// The geometry and its node fields; null without fields.
  const FieldGeometry* fields() const { return fields_.get(); }
  /// SerializeGeometry of the geometry, with the fields (SerializeModel): the pickled state.
  const std::string& state() const { return state_; }
  int dimension() const { return dimension_; }
  std::size_t patches() const { return patches_; }
  std::int64_t cells() const { return cells_; }

  /// The distance model (include/invmap/distance.h), prepared on the first
  /// call and kept. It refers to this object's manifold: the module never
  /// moves a manifold once Python holds it. Thread-safe; pure C++.
  const DistanceModel& distanceModel() const {
    std::lock_guard<std::mutex> lock(distance_->mutex);
    if (!distance_->model.valid()) {
      DistanceModelBuild built = DistanceModel::Build(manifold_);
      if (!built.error.empty()) throw InputError(built.error);
      distance_->model = built.model;
    }
    return distance_->model;
  }

 private:
  struct DistanceCache {
    std::mutex mutex;
    DistanceModel model;
  };
  Manifold manifold_;
  std::string state_;
  std::shared_ptr<const FieldGeometry> fields_;
  int dimension_;
  std::size_t patches_;
  std::int64_t cells_ = 0;
  std::shared_ptr<DistanceCache> distance_ = std::make_shared<DistanceCache>();
};

}  // namespace invmap::python
