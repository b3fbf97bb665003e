#include "cad/pseudo_normals.h"

#include "cad/vertex_fans.h"

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_DataMapOfShapeShape.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListIteratorOfListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>

namespace invmap::cad {
namespace {

/// p - x within this cosine of the face normal: the closest point is a
/// stationary point inside the face (the solver's stationarity is far
/// tighter; an answer on an edge is far off it).
constexpr double kAlongNormal = 1.0 - 1e-6;
/// A surface moving less than this share of the model's size across its
/// face's parameter range in one direction is singular there.
constexpr double kSingular = 1e-9;

/// Knot spans of positive length within the curve's domain, as own
/// parameter ranges (angular knots are angles already).
std::vector<std::pair<double, double>> Spans(const SplineCurve& curve) {
  std::vector<std::pair<double, double>> spans;
  const int n = static_cast<int>(curve.knots.size()) - curve.degree - 1;
  for (int i = curve.degree; i < n; ++i) {
    if (curve.knots[i + 1] > curve.knots[i]) spans.emplace_back(curve.knots[i], curve.knots[i + 1]);
  }
  return spans;
}

std::int64_t CountSpans(const std::vector<double>& knots, int degree, int count) {
  std::int64_t spans = 0;
  for (int i = degree; i < count; ++i) spans += knots[i + 1] > knots[i] ? 1 : 0;
  return spans;
}

}  // namespace

gp_Vec PseudoNormals::Normal(int face, double u, double v) const {
  const FaceData& f = faces_[face];
  gp_Pnt p;
  gp_Vec du, dv;
  f.surface->D1(u, v, p, du, dv);
  // A pole or an apex: the surface hardly moves across the face's whole
  // parameter range in one direction (measured against the model's size:
  // a file's rounding leaves a derivative of 1e-12 there, and a normal from
  // it that is one generator's, or its opposite), or its derivatives are
  // parallel. It has no normal; the vertex there decides.
  const double still = kSingular * size_;
  gp_Vec n = du.Crossed(dv);
  if (du.Magnitude() * (f.uvBox[1] - f.uvBox[0]) <= still || dv.Magnitude() * (f.uvBox[3] - f.uvBox[2]) <= still ||
      n.Magnitude() <= 1e-12 * du.Magnitude() * dv.Magnitude()) {
    return gp_Vec(0, 0, 0);
  }
  n.Normalize();
  return f.reversed ? -n : n;
}

void PseudoNormals::Build(const TopoDS_Shape& shape, const ConvertedModel& model) {
  size_ = model.size > 0.0 ? model.size : 1.0;
  TopTools_IndexedMapOfShape edgeMap, vertexMap;
  TopExp::MapShapes(shape, TopAbs_EDGE, edgeMap);
  TopExp::MapShapes(shape, TopAbs_VERTEX, vertexMap);
  edges_.resize(static_cast<std::size_t>(edgeMap.Extent()));
  for (int e = 1; e <= edgeMap.Extent(); ++e) {
    const TopoDS_Edge edge = TopoDS::Edge(edgeMap(e).Oriented(TopAbs_FORWARD));
    EdgeRecord& record = edges_[e - 1];
    if (!BRep_Tool::Degenerated(edge)) record.curve = BRep_Tool::Curve(edge, record.first, record.last);
    TopoDS_Vertex v0, v1;
    TopExp::Vertices(edge, v0, v1);
    record.vertex[0] = v0.IsNull() ? -1 : vertexMap.FindIndex(v0) - 1;
    record.vertex[1] = v1.IsNull() ? -1 : vertexMap.FindIndex(v1) - 1;
  }

  // The solid of each face, for the classifier (a closed shell outside any
  // solid is made one).
  TopTools_IndexedDataMapOfShapeListOfShape faceSolids, faceShells;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, faceSolids);
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SHELL, faceShells);
  TopTools_IndexedMapOfShape solids;
  TopTools_DataMapOfShapeShape shellSolids;

  faces_.resize(model.faces.size());
  for (std::size_t f = 0; f < model.faces.size(); ++f) {
    const FaceRecord& record = model.faces[f];
    FaceData& data = faces_[f];
    data.surface = record.surface;
    data.reversed = record.face.Orientation() == TopAbs_REVERSED;
    const TopoDS_Face forward = TopoDS::Face(record.face.Oriented(TopAbs_FORWARD));
    BRepTools::UVBounds(forward, data.uvBox[0], data.uvBox[1], data.uvBox[2], data.uvBox[3]);
    const Patch& patch = model.geometry.patches[f];
    data.surfaceCells = CountSpans(patch.knots[0], patch.degrees[0], patch.counts[0]) *
                        CountSpans(patch.knots[1], patch.degrees[1], patch.counts[1]);
    for (std::size_t j = 0; j < record.edges.size(); ++j) {
      const int e = edgeMap.FindIndex(record.edges[j]) - 1;
      for (const auto& [lo, hi] : Spans(patch.edges[j].curve)) data.edgeCells.push_back({e, lo, hi});
    }
    for (TopExp_Explorer it(forward, TopAbs_EDGE); it.More(); it.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(it.Current().Oriented(TopAbs_FORWARD));
      const int e = edgeMap.FindIndex(edge) - 1;
      if (std::find(data.edges.begin(), data.edges.end(), e) != data.edges.end()) continue;
      data.edges.push_back(e);
      double first = 0.0, last = 0.0;
      const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, forward, first, last);
      if (!pcurve.IsNull()) edges_[e].uses.push_back({static_cast<int>(f), pcurve});
    }
    TopoDS_Shape solid;
    if (const int at = faceSolids.FindIndex(record.face); at > 0 && !faceSolids(at).IsEmpty()) {
      solid = faceSolids(at).First();
    } else if (const int shellAt = faceShells.FindIndex(record.face); shellAt > 0 && !faceShells(shellAt).IsEmpty()) {
      // One solid per shell, made the first time one of its faces comes.
      const TopoDS_Shape& shell = faceShells(shellAt).First();
      if (!shellSolids.IsBound(shell)) {
        BRep_Builder builder;
        TopoDS_Solid made;
        builder.MakeSolid(made);
        builder.Add(made, shell);
        shellSolids.Bind(shell, made);
      }
      solid = shellSolids(shell);
    }
    if (!solid.IsNull()) data.solid = solids.Add(solid) - 1;
  }
  for (int s = 1; s <= solids.Extent(); ++s) solids_.push_back(solids(s));
  MarkSharedFaces(shape, model);
  classifiers_.resize(solids_.size());

  // Each vertex's pseudo-normal: every face's fan there (cad/vertex_fans.h).
  vertexNormals_.assign(static_cast<std::size_t>(vertexMap.Extent()), gp_Vec(0, 0, 0));
  for (std::size_t f = 0; f < model.faces.size(); ++f) {
    AddVertexFans(model.faces[f].face, faces_[f].surface, faces_[f].uvBox, vertexMap, &vertexNormals_);
  }
}

void PseudoNormals::MarkSharedFaces(const TopoDS_Shape& shape, const ConvertedModel& model) {
  if (solids_.size() < 2) return;
  // A sub-shape listed under two different shells bounds two solids (the
  // shells of one solid, its outer one and its voids', share nothing; a
  // closed shell outside any solid is a solid of its own here).
  auto sharedKind = [&](TopAbs_ShapeEnum kind) {
    TopTools_IndexedDataMapOfShapeListOfShape ancestors;
    TopExp::MapShapesAndAncestors(shape, kind, TopAbs_SHELL, ancestors);
    TopTools_IndexedMapOfShape shared;
    for (int k = 1; k <= ancestors.Extent(); ++k) {
      const TopTools_ListOfShape& shells = ancestors(k);
      for (TopTools_ListIteratorOfListOfShape it(shells); it.More(); it.Next()) {
        if (!it.Value().IsSame(shells.First())) {
          shared.Add(ancestors.FindKey(k));
          break;
        }
      }
    }
    return shared;
  };
  const TopTools_IndexedMapOfShape faces = sharedKind(TopAbs_FACE), edges = sharedKind(TopAbs_EDGE),
                                   vertices = sharedKind(TopAbs_VERTEX);
  for (std::size_t f = 0; f < model.faces.size(); ++f) {
    const TopoDS_Face& face = model.faces[f].face;
    bool shared = faces.Contains(face);
    for (TopExp_Explorer it(face, TopAbs_EDGE); it.More() && !shared; it.Next()) shared = edges.Contains(it.Current());
    for (TopExp_Explorer it(face, TopAbs_VERTEX); it.More() && !shared; it.Next()) {
      shared = vertices.Contains(it.Current());
    }
    faces_[f].shared = shared;
  }
}

double PseudoNormals::ClassifierSign(int face, const gp_Pnt& p) const {
  const int solid = faces_[face].solid;
  if (solid < 0) return 1.0;
  std::lock_guard<std::mutex> lock(classifierMutex_);
  std::unique_ptr<BRepClass3d_SolidClassifier>& classifier = classifiers_[solid];
  if (!classifier) classifier = std::make_unique<BRepClass3d_SolidClassifier>(solids_[solid]);
  classifier->Perform(p, 1e-12 * size_);
  return classifier->State() == TopAbs_IN ? -1.0 : 1.0;
}

double PseudoNormals::EdgeSign(const gp_Vec& offset, int edge, double s) const {
  const EdgeRecord& record = edges_[edge];
  const double reach = 1e-9 * (record.last - record.first);
  gp_Vec normal(0, 0, 0);
  if (s - record.first <= reach && record.vertex[0] >= 0) {
    normal = vertexNormals_[record.vertex[0]];
  } else if (record.last - s <= reach && record.vertex[1] >= 0) {
    normal = vertexNormals_[record.vertex[1]];
  } else {
    for (const EdgeUse& use : record.uses) {
      const gp_Pnt2d uv = use.pcurve->Value(s);
      normal += Normal(use.face, uv.X(), uv.Y());
    }
  }
  const double dot = offset.Dot(normal);
  if (!(std::abs(dot) > 1e-9 * offset.Magnitude() * normal.Magnitude())) return std::nan("");
  return dot > 0.0 ? 1.0 : -1.0;
}

double PseudoNormals::Sign(const double* p, int patch, std::int64_t cell, const double* uv, const double* closest) const {
  const gp_Pnt point(p[0], p[1], p[2]);
  const gp_Pnt x(closest[0], closest[1], closest[2]);
  const gp_Vec offset(x, point);
  const double d = offset.Magnitude();
  if (d == 0.0) return 1.0;
  const FaceData& face = faces_[patch];
  ShapeAnalysis_Curve projector;
  double sign = std::nan("");
  try {
    if (cell >= face.surfaceCells) {
      // An answer on an edge: its own parameter there, from the cell's span.
      const std::size_t at = static_cast<std::size_t>(cell - face.surfaceCells);
      if (at < face.edgeCells.size()) {
        const EdgeCell& span = face.edgeCells[at];
        const EdgeRecord& edge = edges_[span.edge];
        gp_Pnt projected;
        double s = 0.0;
        projector.Project(edge.curve, x, 1e-12 * size_, projected, s, span.lo, span.hi, Standard_True);
        sign = EdgeSign(offset, span.edge, s);
      }
    } else {
      const gp_Vec n = Normal(patch, uv[0], uv[1]);
      const double along = n.Magnitude() > 0.0 ? offset.Dot(n) / d : 0.0;
      if (std::abs(along) >= kAlongNormal) return along > 0.0 ? 1.0 : -1.0;
      // On the face's boundary: the edge (or vertex) nearest the answer.
      int nearest = -1;
      double nearestDistance = 1e-6 * size_, nearestS = 0.0;
      for (const int e : face.edges) {
        const EdgeRecord& edge = edges_[e];
        if (edge.curve.IsNull()) continue;
        gp_Pnt projected;
        double s = 0.0;
        const double distance = projector.Project(edge.curve, x, 1e-12 * size_, projected, s, edge.first, edge.last,
                                                  Standard_True);
        if (distance <= nearestDistance) {
          nearest = e;
          nearestDistance = distance;
          nearestS = s;
        }
      }
      if (nearest >= 0) sign = EdgeSign(offset, nearest, nearestS);
    }
  } catch (const Standard_Failure&) {
    sign = std::nan("");
  }
  return std::isnan(sign) ? ClassifierSign(patch, point) : sign;
}

}  // namespace invmap::cad
