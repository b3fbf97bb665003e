#include "cad/model_conversion.h"

#include <BRepBndLib.hxx>
#include <BRepLib.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Geom2d_Curve.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Wire.hxx>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "cad/curve_conversion.h"
#include "cad/surface_conversion.h"

namespace invmap::cad {
namespace {

/// A wire's pcurve in the order and sense the wire runs.
struct LoopCurve {
  SplineCurve curve;
  double start[2], end[2];
};

double Distance2(const double* a, const double* b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

/// Orders a wire's pcurves into closed loops by their ends: each next curve
/// is the one starting nearest the current end, and a loop closes when its
/// own start is nearer than any curve left (the trimming closes the small
/// gaps by straight segments, so the order must not jump across the face).
std::vector<std::vector<SplineCurve>> ChainLoops(std::vector<LoopCurve> curves) {
  std::vector<std::vector<SplineCurve>> loops;
  std::vector<bool> used(curves.size(), false);
  std::size_t left = curves.size();
  while (left > 0) {
    std::size_t current = 0;
    while (used[current]) ++current;
    used[current] = true;
    --left;
    const double* loopStart = curves[current].start;
    std::vector<SplineCurve> loop{curves[current].curve};
    const double* end = curves[current].end;
    while (left > 0) {
      std::size_t next = curves.size();
      double best = Distance2(end, loopStart);
      for (std::size_t c = 0; c < curves.size(); ++c) {
        if (used[c]) continue;
        const double d = Distance2(end, curves[c].start);
        if (d < best) {
          best = d;
          next = c;
        }
      }
      if (next == curves.size()) break;
      used[next] = true;
      --left;
      loop.push_back(curves[next].curve);
      end = curves[next].end;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

void Ends(const SplineCurve& curve, double* start, double* end) {
  const std::size_t n = curve.points.size() / 2;
  start[0] = curve.points[0];
  start[1] = curve.points[1];
  end[0] = curve.points[2 * (n - 1)];
  end[1] = curve.points[2 * (n - 1) + 1];
}

/// The face's trimming loops, in the parameters of its surface.
std::vector<std::vector<SplineCurve>> FaceLoops(const TopoDS_Face& forward, double tolerance2d, FaceRecord* record) {
  std::vector<std::vector<SplineCurve>> loops;
  for (TopExp_Explorer wires(forward, TopAbs_WIRE); wires.More(); wires.Next()) {
    std::vector<LoopCurve> curves;
    for (TopExp_Explorer edges(wires.Current(), TopAbs_EDGE); edges.More(); edges.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(edges.Current());
      double first = 0.0, last = 0.0;
      const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, forward, first, last);
      if (pcurve.IsNull() || !(last > first)) continue;
      ConvertedCurve converted = ConvertCurve2d(pcurve, first, last, tolerance2d);
      record->approximated = record->approximated || converted.approximated;
      LoopCurve loopCurve;
      loopCurve.curve = edge.Orientation() == TopAbs_REVERSED ? Reversed(converted.curve) : converted.curve;
      Ends(loopCurve.curve, loopCurve.start, loopCurve.end);
      curves.push_back(std::move(loopCurve));
    }
    for (std::vector<SplineCurve>& loop : ChainLoops(std::move(curves))) loops.push_back(std::move(loop));
  }
  return loops;
}

/// The face's parameter box from its pcurves, a hair wider so that loops
/// along its sides stay inside.
void ParameterBox(const TopoDS_Face& forward, double* u0, double* u1, double* v0, double* v1) {
  BRepTools::UVBounds(forward, *u0, *u1, *v0, *v1);
  const double du = 1e-9 * (*u1 - *u0) + 1e-12, dv = 1e-9 * (*v1 - *v0) + 1e-12;
  *u0 -= du;
  *u1 += du;
  *v0 -= dv;
  *v1 += dv;
}

}  // namespace

ConvertedModel ConvertModel(const TopoDS_Shape& input) {
  ConvertedModel model;
  TopoDS_Shape shape = input;
  // Edges known only by their pcurves get a 3D curve: the edges are answers.
  BRepLib::BuildCurves3d(shape);
  Bnd_Box box;
  BRepBndLib::AddOptimal(shape, box, false, false);
  box.Get(model.boundsLo[0], model.boundsLo[1], model.boundsLo[2], model.boundsHi[0], model.boundsHi[1],
          model.boundsHi[2]);
  model.size = std::sqrt(box.SquareExtent());
  model.tolerance = 1e-7 * model.size;
  model.geometry.dimension = 3;
  TopExp::MapShapes(shape, TopAbs_FACE, model.faceMap);
  TopTools_MapOfShape ownedEdges;
  for (int i = 1; i <= model.faceMap.Extent(); ++i) {
    const TopoDS_Face face = TopoDS::Face(model.faceMap(i));
    const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
    FaceRecord record;
    record.face = face;
    Patch patch;
    try {
      record.surface = BRep_Tool::Surface(face);
      if (record.surface.IsNull()) throw std::runtime_error("it has no surface");
      double u0, u1, v0, v1;
      ParameterBox(forward, &u0, &u1, &v0, &v1);
      const ConvertedSurface surface = ConvertSurface(record.surface, u0, u1, v0, v1, model.tolerance);
      record.type = surface.type;
      record.approximated = surface.approximated;
      record.deviation = surface.deviation;
      SurfaceSpline spline = surface.surface;
      BalanceSpans(&spline);
      SetSurface(spline, &patch);
      patch.analytic = surface.analytic;
      const double tolerance2d = 1e-10 * std::max(u1 - u0, v1 - v0);
      patch.trimLoops = FaceLoops(forward, tolerance2d, &record);
      for (TopExp_Explorer edges(forward, TopAbs_EDGE); edges.More(); edges.Next()) {
        const TopoDS_Edge edge = TopoDS::Edge(edges.Current().Oriented(TopAbs_FORWARD));
        if (BRep_Tool::Degenerated(edge) || ownedEdges.Contains(edge)) continue;
        double first = 0.0, last = 0.0;
        const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
        if (curve.IsNull() || !(last > first)) continue;
        ownedEdges.Add(edge);
        PatchEdge patchEdge;
        const ConvertedCurve converted = ConvertCurve(curve, first, last, model.tolerance);
        patchEdge.curve = converted.curve;
        record.approximated = record.approximated || converted.approximated;
        record.deviation = std::max(record.deviation, converted.deviation);
        double pFirst = 0.0, pLast = 0.0;
        const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, forward, pFirst, pLast);
        if (!pcurve.IsNull() && pLast > pFirst) {
          patchEdge.pcurve = ConvertCurve2d(pcurve, pFirst, pLast, tolerance2d).curve;
        }
        patch.edges.push_back(std::move(patchEdge));
        record.edges.push_back(edge);
      }
    } catch (const Standard_Failure& e) {
      throw std::runtime_error("face " + std::to_string(i - 1) + ": " + e.GetMessageString());
    } catch (const std::exception& e) {
      throw std::runtime_error("face " + std::to_string(i - 1) + ": " + e.what());
    }
    model.geometry.patches.push_back(std::move(patch));
    model.faces.push_back(std::move(record));
  }
  return model;
}

}  // namespace invmap::cad
