// The side of a closed solid a point is on, from its closest point: the
// outward normal of the face there, or, where that point is on an edge or
// a vertex (the point then lies in the normal cone of several faces), the
// faces' normals summed (an edge) or weighted by the faces' angles at the
// vertex (the angle-weighted pseudo-normal of Baerentzen and Aanaes, which
// is positive over the whole normal cone of an outside point). The signs
// come from the geometry at the closest point, so they hold however close
// the point is; where that geometry does not decide (a closest point
// inside a face but not along its normal, at a crease; a degenerate
// corner), OpenCascade's solid classifier does.
#pragma once

#include <BRepClass3d_SolidClassifier.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "cad/model_conversion.h"

namespace invmap::cad {

class PseudoNormals {
 public:
  void Build(const TopoDS_Shape& shape, const ConvertedModel& model);

  /// +1 outside, -1 inside, for point `p` whose answer on the model's
  /// geometry is `closest` on face `patch`, cell `cell`, parameters `uv`.
  double Sign(const double* p, int patch, std::int64_t cell, const double* uv, const double* closest) const;

  /// The model's solids (a closed shell outside any solid made one), and
  /// the one face `face` bounds (-1 for none).
  const std::vector<TopoDS_Shape>& Solids() const { return solids_; }
  int SolidOf(int face) const { return faces_[face].solid; }
  /// True when face `face`, or an edge or vertex of it, bounds more than one
  /// solid (a compsolid's shared face): Sign then tells the side of one of
  /// them, which says nothing about the others.
  bool SharedBetweenSolids(int face) const { return faces_[face].shared; }

 private:
  struct EdgeUse {
    int face;
    Handle(Geom2d_Curve) pcurve;
  };
  struct EdgeRecord {
    Handle(Geom_Curve) curve;
    double first = 0.0, last = 1.0;
    std::vector<EdgeUse> uses;
    int vertex[2] = {-1, -1};  // at first and at last
  };
  /// An edge cell of a face's patch: its edge and own parameter range.
  struct EdgeCell {
    int edge;
    double lo, hi;
  };
  struct FaceData {
    Handle(Geom_Surface) surface;
    bool reversed = false;
    double uvBox[4] = {0, 0, 0, 0};
    std::int64_t surfaceCells = 0;  ///< Cells below this are surface cells.
    std::vector<EdgeCell> edgeCells;
    std::vector<int> edges;  ///< Every edge of the face.
    int solid = -1;          ///< Its solid for the classifier.
    bool shared = false;     ///< SharedBetweenSolids.
  };

  /// The outward unit normal of face f at (u, v); zero at a singular point
  /// (a pole, an apex), whose sign the vertex there gives.
  gp_Vec Normal(int face, double u, double v) const;
  /// The sign from edge e at own parameter s (a vertex's at its ends).
  double EdgeSign(const gp_Vec& offset, int edge, double s) const;
  /// Sets FaceData::shared.
  void MarkSharedFaces(const TopoDS_Shape& shape, const ConvertedModel& model);
  /// The sign by the classifier (slow; the last resort).
  double ClassifierSign(int face, const gp_Pnt& p) const;

  std::vector<FaceData> faces_;
  std::vector<EdgeRecord> edges_;
  std::vector<gp_Vec> vertexNormals_;
  std::vector<TopoDS_Shape> solids_;
  double size_ = 1.0;
  mutable std::mutex classifierMutex_;
  mutable std::vector<std::unique_ptr<BRepClass3d_SolidClassifier>> classifiers_;
};

}  // namespace invmap::cad
