#include "cad/solid_parts.h"

#include <BRepBndLib.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Pnt.hxx>

#include <cmath>
#include <exception>
#include <limits>

#include "cad/model_conversion.h"
#include "cad/pseudo_normals.h"
#include "common/parallel.h"
#include "invmap/invmap.h"

namespace invmap::cad {

struct SolidParts::Part {
  ConvertedModel model;
  PseudoNormals normals;
  Manifold manifold;
};

SolidParts::SolidParts() = default;
SolidParts::~SolidParts() = default;

void SolidParts::Build(const std::vector<TopoDS_Shape>& solids, const ConvertedModel& whole) {
  whole_ = &whole;
  solids_ = solids;
  size_ = whole.size;
  boxes_.assign(solids.size(), Bnd_Box());
  for (std::size_t s = 0; s < solids.size(); ++s) {
    BRepBndLib::Add(solids[s], boxes_[s], false);
    boxes_[s].Enlarge(1e-7 * size_);
  }
  built_ = std::vector<std::once_flag>(solids.size());
  parts_.clear();
  parts_.resize(solids.size());
}

bool SolidParts::MayHold(int solid, const double* closest) const {
  return !boxes_[solid].IsOut(gp_Pnt(closest[0], closest[1], closest[2]));
}

namespace {

/// The model's faces of `solid` as a model of their own, from their
/// converted patches (nothing is converted again); false when an edge of
/// the solid is answered from a face of another solid (they share it), so
/// that the solid's own patches miss it.
bool SelectFaces(const ConvertedModel& whole, const TopoDS_Shape& solid, ConvertedModel* part) {
  part->size = whole.size;
  part->tolerance = whole.tolerance;
  for (int k = 0; k < 3; ++k) {
    part->boundsLo[k] = whole.boundsLo[k];
    part->boundsHi[k] = whole.boundsHi[k];
  }
  part->geometry.dimension = whole.geometry.dimension;
  TopExp::MapShapes(solid, TopAbs_FACE, part->faceMap);
  TopTools_MapOfShape held;
  for (int f = 1; f <= part->faceMap.Extent(); ++f) {
    const int at = whole.faceMap.FindIndex(part->faceMap(f)) - 1;
    if (at < 0) return false;
    FaceRecord record = whole.faces[at];
    record.face = TopoDS::Face(part->faceMap(f));  // its sense in this solid
    for (const TopoDS_Edge& edge : record.edges) held.Add(edge);
    part->faces.push_back(std::move(record));
    part->geometry.patches.push_back(whole.geometry.patches[at]);
  }
  for (TopExp_Explorer it(solid, TopAbs_EDGE); it.More(); it.Next()) {
    const TopoDS_Edge edge = TopoDS::Edge(it.Current().Oriented(TopAbs_FORWARD));
    if (BRep_Tool::Degenerated(edge) || held.Contains(edge)) continue;
    double first = 0.0, last = 0.0;
    if (!BRep_Tool::Curve(edge, first, last).IsNull() && last > first) return false;
  }
  return true;
}

}  // namespace

const SolidParts::Part* SolidParts::PartOf(int solid) const {
  std::call_once(built_[solid], [&] {
    try {
      auto part = std::make_unique<Part>();
      if (!SelectFaces(*whole_, solids_[solid], &part->model)) part->model = ConvertModel(solids_[solid]);
      part->normals.Build(solids_[solid], part->model);
      BuildResult built = Manifold::Build(part->model.geometry);
      if (!built.error.empty()) return;
      part->manifold = std::move(built.manifold);
      parts_[solid] = std::move(part);
    } catch (const Standard_Failure&) {
    } catch (const std::exception&) {
    }
  });
  return parts_[solid].get();
}

std::vector<double> SolidParts::Signs(int solid, const std::vector<double>& xyz, int threads) const {
  const std::size_t count = xyz.size() / 3;
  std::vector<double> signs(count, std::numeric_limits<double>::quiet_NaN());
  const Part* part = PartOf(solid);
  Results results;
  if (part != nullptr) {
    InversionOptions options;
    options.threads = threads;
    if (part->manifold.Invert(PointsView::Interleaved(xyz.data(), count, 3), options, &results) != Error::Ok) {
      part = nullptr;
    }
  }
  if (part == nullptr) {
    // The solid alone could not be converted: its classifier, point by point.
    BRepClass3d_SolidClassifier classifier(solids_[solid]);
    for (std::size_t i = 0; i < count; ++i) {
      classifier.Perform(gp_Pnt(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]), 1e-12 * size_);
      signs[i] = classifier.State() == TopAbs_IN ? -1.0 : 1.0;
    }
    return signs;
  }
  ForEachBlock(
      ExecutionPolicy::Par, static_cast<std::int64_t>(count), 256,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          if (results.status[i] != Status::Found) continue;
          signs[i] = results.distance[i] == 0.0
                         ? 1.0
                         : part->normals.Sign(&xyz[3 * i], results.patch[i], results.cell[i], &results.params[3 * i],
                                              &results.closest[3 * i]);
        }
      },
      threads);
  return signs;
}

}  // namespace invmap::cad
