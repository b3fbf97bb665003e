// A shape's faces as TrimmedSurface patches: each face's surface converted
// exactly (cad/surface_conversion.h), its wires' pcurves as the trimming
// loops, and each edge of the model as the curve cells of the first face
// (in face-map order) it bounds.
#pragma once

#include <Geom_Surface.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::cad {

struct FaceRecord {
  TopoDS_Face face;                ///< As the face map holds it (with its orientation).
  Handle(Geom_Surface) surface;    ///< BRep_Tool::Surface(face): the surface (u, v) refer to.
  std::string type;                ///< ConvertedSurface::type.
  bool approximated = false;       ///< The surface or a curve of it is approximated.
  double deviation = 0.0;          ///< Then the largest deviation measured.
  /// The edges answered from this face's patch, in its `edges` order.
  std::vector<TopoDS_Edge> edges;
};

struct ConvertedModel {
  Geometry geometry;
  std::vector<FaceRecord> faces;
  TopTools_IndexedMapOfShape faceMap;  ///< TopExp::MapShapes(shape, TopAbs_FACE).
  double size = 0.0;                   ///< The diagonal of the model's box.
  double tolerance = 0.0;              ///< Approximations are within this (1e-7 of the size).
  double boundsLo[3] = {0, 0, 0}, boundsHi[3] = {0, 0, 0};
};

/// Converts every face of `shape`. Throws std::runtime_error naming the
/// face when one cannot be converted.
ConvertedModel ConvertModel(const TopoDS_Shape& shape);

}  // namespace invmap::cad
