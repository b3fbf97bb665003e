#include "tests/cad/sign_points.h"

#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Compound.hxx>
#include <Geom_Curve.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Pnt.hxx>

#include <cmath>
#include <random>

#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {

std::vector<double> PointsNearEdgesAndVertices(const TopoDS_Shape& shape, int perFeature, unsigned seed) {
  const double size = ShapeSize(shape);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<gp_Pnt> anchors;
  TopTools_IndexedMapOfShape vertices, edges;
  TopExp::MapShapes(shape, TopAbs_VERTEX, vertices);
  TopExp::MapShapes(shape, TopAbs_EDGE, edges);
  for (int v = 1; v <= vertices.Extent(); ++v) {
    for (int k = 0; k < perFeature; ++k) anchors.push_back(BRep_Tool::Pnt(TopoDS::Vertex(vertices(v))));
  }
  for (int e = 1; e <= edges.Extent(); ++e) {
    double first, last;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(TopoDS::Edge(edges(e)), first, last);
    if (curve.IsNull()) continue;
    for (int k = 0; k < perFeature; ++k) anchors.push_back(curve->Value(first + (last - first) * unit(rng)));
  }
  std::vector<double> points;
  for (const gp_Pnt& a : anchors) {
    const gp_XYZ direction = gp_XYZ(gauss(rng), gauss(rng), gauss(rng)).Normalized();
    const gp_XYZ p = a.XYZ() + direction * (size * std::pow(10.0, -9.0 + 8.0 * unit(rng)));
    points.insert(points.end(), {p.X(), p.Y(), p.Z()});
  }
  const std::vector<double> around = PointsAround(shape, anchors.size(), 0.01, 0.1, seed);
  points.insert(points.end(), around.begin(), around.end());
  return points;
}

bool WithinModelPrecisionOfAnEdge(const TopoDS_Face& face, double distance, const double* closest) {
  const double tolerance = FaceTolerance(face);
  if (distance >= tolerance) return false;
  TopoDS_Compound edges;
  BRep_Builder builder;
  builder.MakeCompound(edges);
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) builder.Add(edges, it.Current());
  return OccDistance(edges, closest) <= tolerance;
}

}  // namespace invmap::cadtest
