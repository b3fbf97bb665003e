// What a cad::Model holds (OpenCascade types: private to cad/).
#pragma once

#include <TopoDS_Shape.hxx>

#include <string>
#include <vector>

#include "cad/model_conversion.h"
#include "cad/pseudo_normals.h"
#include "cad/solid_parts.h"
#include "cad/model.h"

namespace invmap::cad {

struct Model::Impl {
  TopoDS_Shape shape;
  std::string format;
  ConvertedModel model;
  /// Open shells and free faces, as ModelInfo::openParts words them.
  std::vector<std::string> openParts;
  /// The faces around each edge and vertex, for the signs (cad/pseudo_normals.h).
  PseudoNormals normals;
  /// Each solid on its own, for models of several (cad/solid_parts.h).
  SolidParts solidParts;

  /// Fills openParts, normals and solidParts from shape and model.
  void BuildTopology();
};

}  // namespace invmap::cad
