// The manifold the Python module hands out (invmap.Manifold): a built
// manifold with the serialized geometry it was built from, which is what
// pickling sends (workers rebuild from it, not from a file), its node
// fields if any, the CAD model it was read from if any, and its distance
// model, prepared on first use.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "invmap/distance.h"
#include "invmap/fields.h"
#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "io/geometry_source.h"
#include "python/cad_binding.h"
#include "python/errors.h"
#include "python/fields_binding.h"
#include "python/geometry_state.h"

namespace invmap::python {

class PyManifold {
 public:
  /// Builds `geometry`; a malformed one throws InputError
  /// "<nameForMessages>: <reason>", worded as the command line words it, or,
  /// for a geometry read from a file with its `source`, naming the file and
  /// line. Pure C++: callers may release the GIL around it.
  PyManifold(const Geometry& geometry, const std::string& nameForMessages, const io::GeometrySource* source = nullptr)
      : PyManifold(geometry, nameForMessages, source, SerializeGeometry(geometry), nullptr) {}
  /// The same from a geometry no longer needed: the build takes a mesh's
  /// arrays instead of copying them (Manifold::Build(Geometry&&)).
  PyManifold(Geometry&& geometry, const std::string& nameForMessages, const io::GeometrySource* source = nullptr)
      : PyManifold(geometry, nameForMessages, source, SerializeGeometry(geometry), &geometry) {}

  /// A CAD model's manifold: it pickles as the model's file (CadSource).
  PyManifold(const CadSource& source, const std::string& nameForMessages)
      : PyManifold(source.model->geometry(), nameForMessages, nullptr, source.state, nullptr) {
    cad_ = source.model;
  }

  /// The same with the node fields of the geometry's file (kept for probe,
  /// with the geometry; without fields the geometry is handed over).
  PyManifold(FieldGeometry&& model, const std::string& nameForMessages, const io::GeometrySource* source = nullptr)
      : PyManifold(model.geometry, nameForMessages, source, SerializeGeometry(model.geometry),
                   model.fields.empty() ? &model.geometry : nullptr) {
    if (model.fields.empty()) return;
    state_ = SerializeModel(state_, model.fields);
    fields_ = std::make_shared<const FieldGeometry>(std::move(model));
  }

  const Manifold& manifold() const { return manifold_; }
  /// The CAD model the manifold was read from, or null.
  const cad::Model* cad() const { return cad_.get(); }
  /// The geometry and its node fields; null without fields.
  const FieldGeometry* fields() const { return fields_.get(); }
  /// SerializeGeometry of the geometry, with the fields (SerializeModel): the pickled state.
  const std::string& state() const { return state_; }
  int dimension() const { return dimension_; }
  std::size_t patches() const { return patches_; }
  std::int64_t cells() const { return cells_; }

  /// The charts of patch `patch` when it is a pou_manifold
  /// (include/invmap/pou.h), else null.
  const PouCharts* charts(std::size_t patch) const {
    for (const auto& [p, c] : *charts_) {
      if (p == patch) return &c;
    }
    return nullptr;
  }

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
  /// `handOver`: null, or `geometry` itself when the build may take its
  /// arrays (its patches' kinds stay, which the charts below read).
  PyManifold(const Geometry& geometry, const std::string& nameForMessages, const io::GeometrySource* source,
             std::string state, Geometry* handOver)
      : state_(std::move(state)), dimension_(geometry.dimension), patches_(geometry.patches.size()) {
    BuildResult built = handOver ? Manifold::Build(std::move(*handOver)) : Manifold::Build(geometry);
    if (built.code == Error::OutOfMemory) throw std::bad_alloc();  // MemoryError
    if (built.code == Error::Internal) throw std::runtime_error(nameForMessages + ": " + built.error);
    if (built.problem && source) throw InputError(source->ToInputError(built.problem).what());
    if (!built.error.empty()) throw InputError(nameForMessages + ": " + built.error);
    manifold_ = std::move(built.manifold);
    for (std::size_t p = 0; p < patches_; ++p) cells_ += manifold_.NumCells(static_cast<int>(p));
    auto charts = std::make_shared<std::vector<std::pair<std::size_t, PouCharts>>>();
    for (std::size_t p = 0; p < patches_; ++p) {
      if (geometry.patches[p].kind != Patch::Kind::PouManifold) continue;
      PouCharts c;
      const std::string error = PouCharts::Create(geometry.patches[p], &c);
      if (!error.empty()) throw InputError(nameForMessages + ": patch " + std::to_string(p) + ": " + error);
      charts->emplace_back(p, std::move(c));
    }
    charts_ = std::move(charts);
  }

  struct DistanceCache {
    std::mutex mutex;
    DistanceModel model;
  };
  std::shared_ptr<const cad::Model> cad_;
  Manifold manifold_;
  std::string state_;
  std::shared_ptr<const FieldGeometry> fields_;
  std::shared_ptr<const std::vector<std::pair<std::size_t, PouCharts>>> charts_;
  int dimension_;
  std::size_t patches_;
  std::int64_t cells_ = 0;
  std::shared_ptr<DistanceCache> distance_ = std::make_shared<DistanceCache>();
};

}  // namespace invmap::python
