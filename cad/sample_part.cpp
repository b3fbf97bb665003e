#include "cad/sample_part.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <cmath>
#include <random>

#include "cad/model_impl.h"
#include "cad/shape_reader.h"

namespace invmap::cad {
namespace {

/// The edges of `shape` whose two vertices satisfy `test`.
template <typename Test>
std::vector<TopoDS_Edge> EdgesWhere(const TopoDS_Shape& shape, Test test) {
  std::vector<TopoDS_Edge> edges;
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_EDGE, map);
  for (int i = 1; i <= map.Extent(); ++i) {
    const TopoDS_Edge& edge = TopoDS::Edge(map(i));
    TopoDS_Vertex a, b;
    TopExp::Vertices(edge, a, b);
    if (!a.IsNull() && !b.IsNull() && test(BRep_Tool::Pnt(a)) && test(BRep_Tool::Pnt(b))) edges.push_back(edge);
  }
  return edges;
}

TopoDS_Shape Drill(const TopoDS_Shape& part, const gp_Pnt& from, const gp_Dir& along, double diameter, double depth) {
  return BRepAlgoAPI_Cut(part, BRepPrimAPI_MakeCylinder(gp_Ax2(from, along), diameter / 2, depth).Shape()).Shape();
}

TopoDS_Shape Bracket() {
  const TopoDS_Shape base = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(80, 50, 8)).Shape();
  const TopoDS_Shape upright = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(8, 50, 60)).Shape();
  TopoDS_Shape part = BRepAlgoAPI_Fuse(base, upright).Shape();
  {
    // The inner corner between base and upright, and the base's two outer
    // vertical corners.
    BRepFilletAPI_MakeFillet fillet(part);
    for (const TopoDS_Edge& e : EdgesWhere(part, [](const gp_Pnt& p) { return std::abs(p.X() - 8) < 1e-7 && std::abs(p.Z() - 8) < 1e-7; }))
      fillet.Add(6.0, e);
    for (const double y : {0.0, 50.0}) {
      for (const TopoDS_Edge& e : EdgesWhere(part, [y](const gp_Pnt& p) {
             return std::abs(p.X() - 80) < 1e-7 && std::abs(p.Y() - y) < 1e-7;
           }))
        fillet.Add(5.0, e);
    }
    part = fillet.Shape();
  }
  // The turned boss: the profile (r, z) revolved about x = 58, y = 25.
  const double cx = 58, cy = 25;
  BRepBuilderAPI_MakePolygon profile;
  for (const auto& [r, z] : std::vector<std::pair<double, double>>{{0, 4}, {10, 4}, {10, 16}, {7, 19}, {0, 19}}) {
    profile.Add(gp_Pnt(cx + r, cy, z));
  }
  profile.Close();
  const TopoDS_Face section = BRepBuilderAPI_MakeFace(profile.Wire()).Face();
  const TopoDS_Shape boss = BRepPrimAPI_MakeRevol(section, gp_Ax1(gp_Pnt(cx, cy, 0), gp_Dir(0, 0, 1)), 2 * M_PI).Shape();
  part = BRepAlgoAPI_Fuse(part, boss).Shape();
  part = Drill(part, gp_Pnt(cx, cy, -1), gp_Dir(0, 0, 1), 6.0, 30.0);
  part = Drill(part, gp_Pnt(26, 13, -1), gp_Dir(0, 0, 1), 10.0, 12.0);
  part = Drill(part, gp_Pnt(26, 37, -1), gp_Dir(0, 0, 1), 10.0, 12.0);
  part = Drill(part, gp_Pnt(-1, 25, 40), gp_Dir(1, 0, 0), 12.0, 12.0);
  return part;
}

}  // namespace

std::string WriteSampleBracket(const std::string& path) {
  SilenceOpenCascade();
  try {
    const TopoDS_Shape part = Bracket();
    STEPControl_Writer writer;
    Interface_Static::SetCVal("write.step.unit", "MM");
    if (writer.Transfer(part, STEPControl_AsIs) != IFSelect_RetDone) return "OpenCascade could not transfer the part";
    if (writer.Write(path.c_str()) != IFSelect_RetDone) return "cannot write " + path;
  } catch (const Standard_Failure& e) {
    return std::string("OpenCascade failed to build the part: ") + e.GetMessageString();
  }
  return {};
}

std::vector<double> SimulateScan(const Model& model, const ScanOptions& options) {
  const Model::Impl& impl = *model.impl_;
  const ConvertedModel& converted = impl.model;
  // A fine mesh of every face (of a copy: the mesh is stored on the faces,
  // and the model's own shape stays as read): its triangles pick places by
  // area, and its nodes' parameters put them on the exact surface.
  TopoDS_Shape shape = BRepBuilderAPI_Copy(impl.shape).Shape();
  BRepTools::Clean(shape);
  BRepMesh_IncrementalMesh mesher(shape, 2e-3 * converted.size, false, 0.3);
  TopTools_IndexedMapOfShape meshedFaces;
  TopExp::MapShapes(shape, TopAbs_FACE, meshedFaces);
  struct Triangle {
    int face;
    gp_Pnt2d uv[3];
  };
  std::vector<Triangle> triangles;
  std::vector<double> cumulative;
  for (std::size_t f = 0; f < converted.faces.size(); ++f) {
    TopLoc_Location location;
    const Handle(Poly_Triangulation) mesh =
        BRep_Tool::Triangulation(TopoDS::Face(meshedFaces(static_cast<int>(f) + 1)), location);
    if (mesh.IsNull() || !mesh->HasUVNodes()) continue;
    for (int t = 1; t <= mesh->NbTriangles(); ++t) {
      int n[3];
      mesh->Triangle(t).Get(n[0], n[1], n[2]);
      Triangle triangle{static_cast<int>(f), {mesh->UVNode(n[0]), mesh->UVNode(n[1]), mesh->UVNode(n[2])}};
      const gp_Pnt a = mesh->Node(n[0]), b = mesh->Node(n[1]), c = mesh->Node(n[2]);
      const double area = 0.5 * gp_Vec(a, b).Crossed(gp_Vec(a, c)).Magnitude();
      triangles.push_back(triangle);
      cumulative.push_back((cumulative.empty() ? 0.0 : cumulative.back()) + area);
    }
  }
  std::vector<double> points;
  if (triangles.empty()) return points;
  double zLo = converted.boundsLo[2], zHi = converted.boundsHi[2];
  if (!(zHi > zLo)) zHi = zLo + 1.0;
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), symmetric(-1.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  points.reserve(static_cast<std::size_t>(options.count) * 3);
  for (std::int64_t i = 0; i < options.count; ++i) {
    const std::size_t t =
        std::lower_bound(cumulative.begin(), cumulative.end(), unit(rng) * cumulative.back()) - cumulative.begin();
    const Triangle& triangle = triangles[std::min(t, triangles.size() - 1)];
    double s = unit(rng), r = unit(rng);
    if (s + r > 1.0) {
      s = 1.0 - s;
      r = 1.0 - r;
    }
    const gp_XY uv = triangle.uv[0].XY() + s * (triangle.uv[1].XY() - triangle.uv[0].XY()) +
                     r * (triangle.uv[2].XY() - triangle.uv[0].XY());
    const FaceRecord& face = converted.faces[triangle.face];
    gp_Pnt p;
    gp_Vec du, dv;
    face.surface->D1(uv.X(), uv.Y(), p, du, dv);
    gp_Vec normal = du.Crossed(dv);
    if (normal.Magnitude() > 0.0) normal.Normalize();
    if (face.face.Orientation() == TopAbs_REVERSED) normal.Reverse();
    double offset = options.warp * (p.Z() - zLo) / (zHi - zLo) + options.noise * gauss(rng);
    if (unit(rng) < options.outliers) offset = options.outlierReach * symmetric(rng);
    const gp_Pnt q = p.Translated(offset * normal);
    points.insert(points.end(), {q.X(), q.Y(), q.Z()});
  }
  return points;
}

Patch Tessellate(const Model& model, double deflection) {
  const Model::Impl& impl = *model.impl_;
  // A copy: the mesh is stored on the shape's faces, and the model's own
  // shape stays as read.
  TopoDS_Shape shape = BRepBuilderAPI_Copy(impl.shape).Shape();
  BRepTools::Clean(shape);
  BRepMesh_IncrementalMesh mesher(shape, deflection, false, 0.5);
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Tri;
  for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next()) {
    const TopoDS_Face& face = TopoDS::Face(it.Current());
    TopLoc_Location location;
    const Handle(Poly_Triangulation) mesh = BRep_Tool::Triangulation(face, location);
    if (mesh.IsNull()) continue;
    const std::int64_t first = static_cast<std::int64_t>(patch.points.size() / 3);
    for (int i = 1; i <= mesh->NbNodes(); ++i) {
      const gp_Pnt p = mesh->Node(i).Transformed(location.Transformation());
      patch.points.insert(patch.points.end(), {p.X(), p.Y(), p.Z()});
    }
    for (int t = 1; t <= mesh->NbTriangles(); ++t) {
      int n[3];
      mesh->Triangle(t).Get(n[0], n[1], n[2]);
      for (int k = 0; k < 3; ++k) patch.cells.push_back(first + n[k] - 1);
    }
  }
  return patch;
}

}  // namespace invmap::cad
