// invmap::cad::Model: reading, conversion and the model's description.
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <limits>
#include <map>
#include <new>
#include <vector>

#include "cad/model_conversion.h"
#include "cad/model_impl.h"
#include "cad/shape_reader.h"
#include "common/parallel.h"
#include "cad/model.h"

namespace invmap::cad {

Model::Model() : impl_(std::make_unique<Impl>()) {}
Model::~Model() = default;

LoadResult Model::Load(const std::string& path) {
  LoadResult result;
  try {
    std::unique_ptr<Model> model(new Model());
    Impl& impl = *model->impl_;
    impl.shape = ReadCadShape(path, &impl.format);
    impl.model = ConvertModel(impl.shape);
    impl.BuildTopology();
    result.model = std::move(model);
  } catch (const ReadError& e) {
    result.error = e.reason;
    result.fileError = e.fileError;
  } catch (const Standard_Failure& e) {
    result.error = std::string("OpenCascade failed on the model: ") + e.GetMessageString();
  } catch (const std::bad_alloc&) {
    result.error = "out of memory while reading the model";
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  return result;
}

const Geometry& Model::geometry() const { return impl_->model.geometry; }

ModelInfo Model::Info() const {
  const Impl& impl = *impl_;
  ModelInfo info;
  info.format = impl.format;
  TopTools_IndexedMapOfShape edges, vertices, shells, solids;
  TopExp::MapShapes(impl.shape, TopAbs_EDGE, edges);
  TopExp::MapShapes(impl.shape, TopAbs_VERTEX, vertices);
  TopExp::MapShapes(impl.shape, TopAbs_SHELL, shells);
  TopExp::MapShapes(impl.shape, TopAbs_SOLID, solids);
  info.faces = impl.model.faces.size();
  info.edges = static_cast<std::size_t>(edges.Extent());
  info.vertices = static_cast<std::size_t>(vertices.Extent());
  info.shells = static_cast<std::size_t>(shells.Extent());
  info.solids = static_cast<std::size_t>(solids.Extent());
  std::map<std::string, std::size_t> bySurface;
  for (std::size_t f = 0; f < impl.model.faces.size(); ++f) {
    ++bySurface[impl.model.faces[f].type];
    if (!impl.model.faces[f].approximated) continue;
    info.approximatedFaces.push_back(static_cast<int>(f));
    info.approximationDeviation = std::max(info.approximationDeviation, impl.model.faces[f].deviation);
  }
  info.facesBySurface.assign(bySurface.begin(), bySurface.end());
  info.openParts = impl.openParts;
  info.approximationTolerance = impl.model.tolerance;
  for (int k = 0; k < 3; ++k) {
    info.boundsLo[k] = impl.model.boundsLo[k];
    info.boundsHi[k] = impl.model.boundsHi[k];
  }
  return info;
}

std::string Model::SignedUnsupported() const {
  if (impl_->openParts.empty()) return {};
  return impl_->openParts.front() + " is not a closed shell, so the model has no inside (--signed needs closed solids)";
}

void Model::SignDistances(const double* xyz, std::size_t count, const Results& results, double* signedDistances,
                          int threads) const {
  const PseudoNormals& normals = impl_->normals;
  ForEachBlock(
      ExecutionPolicy::Par, static_cast<std::int64_t>(count), 256,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          const double d = results.distance[i];
          if (results.status[i] != Status::Found) {
            signedDistances[i] = std::numeric_limits<double>::quiet_NaN();
          } else if (d == 0.0) {
            signedDistances[i] = 0.0;
          } else {
            signedDistances[i] = d * normals.Sign(xyz + 3 * i, results.patch[i], results.cell[i], &results.params[3 * i],
                                                  &results.closest[3 * i]);
          }
        }
      },
      threads);
  if (impl_->solidParts.Count() > 1) SignInOtherSolids(xyz, count, results, signedDistances, threads);
}

void Model::SignInOtherSolids(const double* xyz, std::size_t count, const Results& results, double* signedDistances,
                              int threads) const {
  // The sign above is the side of the solid whose face is nearest. Inside
  // that solid is inside the model; outside it, the point may still be
  // inside another solid that touches it there or holds it, and only one
  // whose box holds the closest point can (cad/solid_parts.h). A face that
  // bounds two solids at once (a compsolid) tells neither side: every solid
  // around it is asked.
  const PseudoNormals& normals = impl_->normals;
  const SolidParts& parts = impl_->solidParts;
  std::vector<std::vector<std::size_t>> asked(parts.Count());
  for (std::size_t i = 0; i < count; ++i) {
    const double d = results.distance[i];
    if (results.status[i] != Status::Found || d == 0.0) continue;
    const int patch = results.patch[i];
    const bool shared = normals.SharedBetweenSolids(patch);
    if (shared) {
      signedDistances[i] = d;
    } else if (signedDistances[i] < 0.0) {
      continue;
    }
    const int own = normals.SolidOf(patch);
    for (std::size_t s = 0; s < parts.Count(); ++s) {
      if ((shared || static_cast<int>(s) != own) && parts.MayHold(static_cast<int>(s), &results.closest[3 * i])) {
        asked[s].push_back(i);
      }
    }
  }
  for (std::size_t s = 0; s < parts.Count(); ++s) {
    if (asked[s].empty()) continue;
    std::vector<double> points;
    points.reserve(3 * asked[s].size());
    for (const std::size_t i : asked[s]) points.insert(points.end(), xyz + 3 * i, xyz + 3 * i + 3);
    const std::vector<double> signs = parts.Signs(static_cast<int>(s), points, threads);
    for (std::size_t k = 0; k < asked[s].size(); ++k) {
      if (signs[k] < 0.0) signedDistances[asked[s][k]] = -results.distance[asked[s][k]];
    }
  }
}

bool IsCadFile(const std::string& path) { return HasCadExtension(path); }

void Model::Impl::BuildTopology() {
  // Shells that are open, and faces in no shell: the model has no inside there.
  TopTools_IndexedMapOfShape shells;
  TopExp::MapShapes(shape, TopAbs_SHELL, shells);
  for (int s = 1; s <= shells.Extent(); ++s) {
    if (BRep_Tool::IsClosed(shells(s))) continue;
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shells(s), TopAbs_FACE, faces);
    std::string part = "shell " + std::to_string(s - 1);
    if (faces.Extent() > 0) {
      part += " (faces " + std::to_string(model.faceMap.FindIndex(faces(1)) - 1);
      part += faces.Extent() > 1 ? " and " + std::to_string(faces.Extent() - 1) + " more)" : ")";
    }
    openParts.push_back(part);
  }
  normals.Build(shape, model);
  solidParts.Build(normals.Solids(), model);
  TopTools_IndexedDataMapOfShapeListOfShape faceShells;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SHELL, faceShells);
  for (int f = 1; f <= model.faceMap.Extent(); ++f) {
    const int at = faceShells.FindIndex(model.faceMap(f));
    if (at == 0 || faceShells(at).IsEmpty()) openParts.push_back("face " + std::to_string(f - 1) + " (in no shell)");
  }
}

}  // namespace invmap::cad
