#include "cad/vertex_fans.h"

#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec2d.hxx>

#include <algorithm>
#include <cmath>

namespace invmap::cad {
namespace {

/// How far inside the face the fan is sampled: this share of an edge's
/// parameter range along it, of the face's parameter box across a
/// degenerate edge. Far above rounding (a file's apex is off by 1e-12 of
/// the size), far below the faces' features.
constexpr double kInside = 1e-5;
/// Samples of the fan across a corner's sector, and along each degenerate
/// edge (a whole turn of a cone: each step well below a half turn).
constexpr int kSectorSamples = 16;
constexpr int kDegenerateSamples = 64;

/// An edge of a wire as the wire runs it, with its pcurve on the face.
struct WireStep {
  TopoDS_Edge edge;
  bool degenerate = false;
  Handle(Geom2d_Curve) pcurve;
  double first = 0.0, last = 0.0;
  bool reversed = false;

  /// The pcurve at `fraction` of the way along the wire's sense.
  gp_Pnt2d At(double fraction) const {
    return pcurve->Value(reversed ? last + fraction * (first - last) : first + fraction * (last - first));
  }
};

/// Accumulates the integral of the outward normal over the arc the fan's
/// directions sweep, from samples in order across the fan.
class Fan {
 public:
  Fan(const Handle(Geom_Surface) & surface, bool reversed, const gp_Pnt& origin)
      : surface_(surface), reversed_(reversed), origin_(origin) {}

  void Add(const gp_Pnt2d& uv) {
    gp_Pnt p;
    gp_Vec du, dv;
    surface_->D1(uv.X(), uv.Y(), p, du, dv);
    gp_Vec direction(origin_, p), normal = du.Crossed(dv);
    if (direction.Magnitude() <= 0.0 || normal.Magnitude() <= 0.0) return;
    direction.Normalize();
    normal.Normalize();
    if (reversed_) normal.Reverse();
    if (started_) {
      const double angle = std::atan2(direction_.Crossed(direction).Magnitude(), direction_.Dot(direction));
      sum_ += 0.5 * angle * (normal_ + normal);
    }
    direction_ = direction;
    normal_ = normal;
    started_ = true;
  }
  const gp_Vec& Sum() const { return sum_; }
  const gp_Pnt& Origin() const { return origin_; }

 private:
  const Handle(Geom_Surface) & surface_;
  bool reversed_;
  gp_Pnt origin_;
  gp_Vec sum_{0, 0, 0}, direction_, normal_;
  bool started_ = false;
};

gp_Vec2d Unit(const gp_Vec2d& v) { return v.Magnitude() > 0.0 ? v.Normalized() : v; }

}  // namespace

void AddVertexFans(const TopoDS_Face& face, const Handle(Geom_Surface) & surface, const double uvBox[4],
                   const TopTools_IndexedMapOfShape& vertexMap, std::vector<gp_Vec>* normals) {
  // The forward face: its region lies left of its wires in (u, v).
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  const double uRange = uvBox[1] - uvBox[0], vRange = uvBox[3] - uvBox[2];
  const double gap = 1e-7 * std::max(uRange, vRange);
  for (TopExp_Explorer wires(forward, TopAbs_WIRE); wires.More(); wires.Next()) {
    std::vector<WireStep> steps;
    bool complete = true;
    for (BRepTools_WireExplorer it(TopoDS::Wire(wires.Current()), forward); it.More(); it.Next()) {
      WireStep step;
      step.edge = it.Current();
      step.degenerate = BRep_Tool::Degenerated(step.edge);
      step.reversed = it.Orientation() == TopAbs_REVERSED;
      step.pcurve = BRep_Tool::CurveOnSurface(step.edge, forward, step.first, step.last);
      complete = complete && !step.pcurve.IsNull();
      steps.push_back(step);
    }
    if (!complete) continue;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const WireStep& in = steps[k];
      if (in.degenerate) continue;
      // The corner after `in`: the degenerate edges up to the next edge.
      std::vector<const WireStep*> collapsed;
      std::size_t next = (k + 1) % steps.size();
      while (steps[next].degenerate && next != k) {
        collapsed.push_back(&steps[next]);
        next = (next + 1) % steps.size();
      }
      const WireStep& out = steps[next];
      const TopoDS_Vertex vertex = TopExp::LastVertex(in.edge, Standard_True);
      if (vertex.IsNull() || out.degenerate) continue;
      const int v = vertexMap.FindIndex(vertex) - 1;
      if (v < 0) continue;
      const gp_Pnt2d arrival = in.At(1.0), departure = out.At(0.0);
      Fan fan(surface, reversed, surface->Value(arrival.X(), arrival.Y()));
      const gp_Pnt2d inside0 = in.At(1.0 - kInside), inside1 = out.At(kInside);
      // Without a degenerate edge, the way back and the way out meet at one
      // point of the surface's parameters, or at two (a periodic surface's
      // pcurves a period apart, or a singular line crossed without an edge).
      const gp_Pnt2d middle((arrival.XY() + departure.XY()) * 0.5);
      const bool jump = arrival.Distance(departure) > gap;
      const bool singular =
          !collapsed.empty() ||
          (jump && surface->Value(middle.X(), middle.Y()).Distance(fan.Origin()) <=
                       1e-7 * surface->Value(inside0.X(), inside0.Y()).Distance(fan.Origin()) / kInside);
      if (!singular) {
        // An ordinary corner: the sector from the way out counterclockwise
        // to the way back, on a small circle around the vertex.
        const gp_Vec2d wayOut(departure, inside1), wayBack(arrival, inside0);
        const double radius = std::min(wayOut.Magnitude(), wayBack.Magnitude());
        const double start = std::atan2(wayOut.Y(), wayOut.X());
        double sweep = std::atan2(wayBack.Y(), wayBack.X()) - start;
        if (sweep <= 0.0) sweep += 2.0 * M_PI;
        fan.Add(inside1);
        for (int s = 1; s < kSectorSamples; ++s) {
          const double angle = start + sweep * s / kSectorSamples;
          fan.Add(gp_Pnt2d(arrival.X() + radius * std::cos(angle), arrival.Y() + radius * std::sin(angle)));
        }
        fan.Add(inside0);
      } else {
        // The vertex is a line in (u, v): the surface is singular there. The
        // fan runs from the way back along the line, just inside the face,
        // to the way out (a gap without degenerate edge is crossed straight).
        // A degenerate edge's own sense is not to be trusted (files run them
        // either way), so each is run from the end nearer where the last
        // one ended, and the face's side is the side the edges leave to.
        gp_Pnt2d at = arrival;
        auto alongLine = [&](auto point) {
          const gp_Pnt2d from = point(0.0), to = point(1.0);
          gp_Vec2d side = Unit(gp_Vec2d(-(to.Y() - from.Y()), to.X() - from.X()));
          if (side.Dot(gp_Vec2d(arrival, inside0)) + side.Dot(gp_Vec2d(departure, inside1)) < 0.0) side.Reverse();
          const double depth = kInside * (std::abs(side.X()) * uRange + std::abs(side.Y()) * vRange);
          for (int s = 0; s <= kDegenerateSamples; ++s) {
            fan.Add(point(static_cast<double>(s) / kDegenerateSamples).Translated(depth * side));
          }
          at = to;
        };
        fan.Add(inside0);
        if (collapsed.empty()) {
          alongLine([&](double t) { return gp_Pnt2d(arrival.XY() + t * (departure.XY() - arrival.XY())); });
        }
        for (const WireStep* line : collapsed) {
          const bool backwards = line->At(1.0).Distance(at) < line->At(0.0).Distance(at);
          alongLine([&](double t) { return line->At(backwards ? 1.0 - t : t); });
        }
        fan.Add(inside1);
      }
      (*normals)[v] += fan.Sum();
    }
  }
}

}  // namespace invmap::cad
