// Solids built with OpenCascade's modelling API, written as BREP files and
// read back: a box with a cylindrical hole, a sphere cut by a plane and a
// profile revolved by three quarters of a turn against closed forms; a
// filleted box and the union of two crossing cylinders against
// OpenCascade's BRepExtrema_DistShapeShape, the crossing cylinders also
// against dense samples of their trimmed faces (BRepClass_FaceClassifier).
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Ax2.hxx>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

double Hypot(double a, double b) { return std::sqrt(a * a + b * b); }

/// Distance from q (in-plane coordinates) to the rectangle [lo, hi] minus
/// the open disk of radius r about c (r = 0: no hole), at height h above it.
double RectangleRegionDistance(double q0, double q1, double h, const double* lo, const double* hi, const double* c,
                               double r) {
  const double d0 = std::max({lo[0] - q0, 0.0, q0 - hi[0]}), d1 = std::max({lo[1] - q1, 0.0, q1 - hi[1]});
  double inPlane = Hypot(d0, d1);
  if (inPlane == 0.0 && r > 0.0) inPlane = std::max(0.0, r - Hypot(q0 - c[0], q1 - c[1]));
  return Hypot(inPlane, h);
}

/// Distance from (rho, z) to the outline of the rectangle [r0, r1] x [z0, z1].
double RectangleOutlineDistance(double rho, double z, double r0, double r1, double z0, double z1) {
  const double outside = Hypot(std::max({r0 - rho, 0.0, rho - r1}), std::max({z0 - z, 0.0, z - z1}));
  if (outside > 0.0) return outside;
  return std::min({rho - r0, r1 - rho, z - z0, z1 - z});
}

/// Checks invmap's distances against a closed form to 1e-8 of the size,
/// and that every reported point lies on the reported face (the face
/// classifier at the reported (u, v), on the surface at those parameters).
void CheckClosedForm(const TopoDS_Shape& shape, const cad::Model& model, const std::vector<double>& points,
                     const std::function<double(const double*)>& exact) {
  const std::vector<TopoDS_Face> faces = Faces(shape);
  const double size = ShapeSize(shape);
  const Results results = InvertOnModel(model, points);
  int wrong = 0, outside = 0;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    ASSERT_EQ(results.status[i], Status::Found);
    const double expected = exact(&points[3 * i]);
    if (std::abs(results.distance[i] - expected) > 1e-8 * size && wrong++ < 5) {
      ADD_FAILURE() << "point " << points[3 * i] << " " << points[3 * i + 1] << " " << points[3 * i + 2]
                    << ": invmap " << results.distance[i] << " (face " << results.patch[i] << ", cell "
                    << results.cell[i] << "), exact " << expected;
    }
    const TopoDS_Face& face = faces[results.patch[i]];
    BRepClass_FaceClassifier classifier(face, gp_Pnt2d(results.params[3 * i], results.params[3 * i + 1]),
                                        1e-7 * size);
    const gp_Pnt at = BRep_Tool::Surface(face)->Value(results.params[3 * i], results.params[3 * i + 1]);
    const double gap = at.Distance(gp_Pnt(results.closest[3 * i], results.closest[3 * i + 1], results.closest[3 * i + 2]));
    if ((classifier.State() == TopAbs_OUT || gap > 1e-9 * size) && outside++ < 5) {
      ADD_FAILURE() << "point " << i << ": reported (u, v) = (" << results.params[3 * i] << ", "
                    << results.params[3 * i + 1] << ") on face " << results.patch[i] << " is "
                    << (classifier.State() == TopAbs_OUT ? "outside the face" : "off the reported point by ") << gap;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(outside, 0);
}

TEST(BuiltSolids, BoxWithCylindricalHole) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(40, 30, 10)).Shape();
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 15, -1), gp_Dir(0, 0, 1)), 6.0, 12.0).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Cut(box, drill).Shape();
  const std::unique_ptr<cad::Model> model = LoadShape(part, "box_with_hole");
  const std::vector<double> points = PointsAround(part, 3000, 0.03, 0.3, 1);
  CheckClosedForm(part, *model, points, [](const double* p) {
    const double hole[2] = {20, 15};
    const double xy[2][2] = {{0, 0}, {40, 30}}, yz[2][2] = {{0, 0}, {30, 10}}, xz[2][2] = {{0, 0}, {40, 10}};
    double d = std::min(RectangleRegionDistance(p[0], p[1], p[2], xy[0], xy[1], hole, 6.0),
                        RectangleRegionDistance(p[0], p[1], p[2] - 10, xy[0], xy[1], hole, 6.0));
    d = std::min({d, RectangleRegionDistance(p[1], p[2], p[0], yz[0], yz[1], hole, 0.0),
                  RectangleRegionDistance(p[1], p[2], p[0] - 40, yz[0], yz[1], hole, 0.0),
                  RectangleRegionDistance(p[0], p[2], p[1], xz[0], xz[1], hole, 0.0),
                  RectangleRegionDistance(p[0], p[2], p[1] - 30, xz[0], xz[1], hole, 0.0)});
    // The hole's wall: radius 6 about (20, 15), z in [0, 10].
    const double rho = Hypot(p[0] - 20, p[1] - 15);
    return std::min(d, Hypot(rho - 6.0, std::max({-p[2], 0.0, p[2] - 10})));
  });
}

TEST(BuiltSolids, SphereCutByAPlane) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(1, 2, 3), 10.0).Shape();
  const TopoDS_Shape above = BRepPrimAPI_MakeBox(gp_Pnt(-20, -20, 7), gp_Pnt(20, 20, 20)).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Cut(sphere, above).Shape();
  const std::unique_ptr<cad::Model> model = LoadShape(part, "cut_sphere");
  const std::vector<double> points = PointsAround(part, 3000, 0.03, 0.3, 2);
  CheckClosedForm(part, *model, points, [](const double* p) {
    const double q[3] = {p[0] - 1, p[1] - 2, p[2] - 3};
    const double r = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    const double h = 4.0, rim = std::sqrt(100.0 - h * h), rho = Hypot(q[0], q[1]);
    // The cap: the sphere below z = h, or its rim where the radial foot is cut away.
    const double toRim = Hypot(rho - rim, q[2] - h);
    const double cap = r > 0.0 && 10.0 * q[2] / r <= h ? std::abs(r - 10.0) : toRim;
    const double disk = Hypot(std::max(0.0, rho - rim), q[2] - h);
    return std::min(cap, disk);
  });
}

TEST(BuiltSolids, ProfileRevolvedThreeQuarters) {
  // The rectangle r in [5, 8], z in [0, 6] of the XZ plane, turned 270
  // degrees about Z: cylinders, annuli, and two rectangular end faces.
  BRepBuilderAPI_MakePolygon outline(gp_Pnt(5, 0, 0), gp_Pnt(8, 0, 0), gp_Pnt(8, 0, 6), gp_Pnt(5, 0, 6), true);
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(outline.Wire()).Face();
  const TopoDS_Shape part = BRepPrimAPI_MakeRevol(profile, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 1.5 * M_PI).Shape();
  const std::unique_ptr<cad::Model> model = LoadShape(part, "revolved");
  const std::vector<double> points = PointsAround(part, 3000, 0.03, 0.3, 3);
  CheckClosedForm(part, *model, points, [](const double* p) {
    const double rho = Hypot(p[0], p[1]);
    double phi = std::atan2(p[1], p[0]);
    if (phi < 0.0) phi += 2.0 * M_PI;
    double d = std::numeric_limits<double>::infinity();
    if (phi <= 1.5 * M_PI) d = RectangleOutlineDistance(rho, p[2], 5, 8, 0, 6);
    // The end faces: the profile at 0 and at 270 degrees (the plane x = 0, y < 0).
    const double lo[2] = {5, 0}, hi[2] = {8, 6}, none[2] = {0, 0};
    d = std::min(d, RectangleRegionDistance(p[0], p[2], p[1], lo, hi, none, 0.0));
    d = std::min(d, RectangleRegionDistance(-p[1], p[2], p[0], lo, hi, none, 0.0));
    return d;
  });
}

TEST(BuiltSolids, FilletedBoxAgainstOpenCascade) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(30, 20, 10)).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer it(box, TopAbs_EDGE); it.More(); it.Next()) fillet.Add(2.5, TopoDS::Edge(it.Current()));
  const TopoDS_Shape part = fillet.Shape();
  const std::unique_ptr<cad::Model> model = LoadShape(part, "filleted_box");
  const std::vector<double> points = PointsAround(part, 2000, 0.03, 0.3, 4);
  const Comparison c = CheckAgainstOpenCascade(part, *model, points, 1e-7);
  EXPECT_EQ(c.notFound + c.farther + c.offFace + c.badParameters, 0) << c.firstFailure;
}

TEST(BuiltSolids, CrossingCylindersAgainstOpenCascadeAndDenseSamples) {
  const TopoDS_Shape a = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-15, 0, 0), gp_Dir(1, 0, 0)), 5.0, 30.0).Shape();
  const TopoDS_Shape b = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, -12, 1), gp_Dir(0, 1, 0)), 4.0, 24.0).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Fuse(a, b).Shape();
  const std::unique_ptr<cad::Model> model = LoadShape(part, "crossing_cylinders");
  std::vector<double> points = PointsAround(part, 1500, 0.03, 0.3, 5);
  const Comparison c = CheckAgainstOpenCascade(part, *model, points, 1e-7);
  EXPECT_EQ(c.notFound + c.farther + c.offFace + c.badParameters, 0) << c.firstFailure;

  // Dense samples bound the distance from above (they are points of the
  // faces) and from below within their spacing.
  const FaceSamples dense = SampleFaces(Faces(part), 100);
  const std::vector<gp_Pnt>& samples = dense.points;
  const double spacing = dense.spacing;
  points.resize(3 * 150);
  const Results results = InvertOnModel(*model, points);
  const double size = ShapeSize(part);
  int above = 0, below = 0;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    const gp_Pnt p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
    double sampled = std::numeric_limits<double>::infinity();
    for (const gp_Pnt& s : samples) sampled = std::min(sampled, p.Distance(s));
    above += results.distance[i] > sampled + 1e-9 * size ? 1 : 0;
    below += results.distance[i] < sampled - spacing ? 1 : 0;
  }
  EXPECT_EQ(above, 0) << "points where a sample of the faces is nearer than invmap's answer";
  EXPECT_EQ(below, 0) << "points where invmap's answer is nearer than the samples allow (spacing " << spacing << ")";
}

}  // namespace
}  // namespace invmap::cadtest
