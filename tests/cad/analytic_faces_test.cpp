// Faces on planes, cylinders, cones, spheres and tori, answered in closed
// form (Patch::analytic, kernels/analytic_surface.h): built with
// OpenCascade (solids with holes, partial angle ranges, lone faces in
// tilted and left-handed frames, a cone face across its apex, spindle
// torus faces), every surface cell checked to take the closed form (but
// those at a cone's apex or on a spindle torus's axis), and the answers compared with two independent
// references: the NURBS cells' certified search on the same geometry with
// the descriptions removed (equal distances within 1e-9 of the size), and
// OpenCascade's extrema on the faces (never farther beyond 1e-9 of the
// size; the reported (u, v) on the face, the face's surface there at the
// reported point). Points near the faces and their edges, far away, on
// the axes, at the poles, the apex, the centres and behind the surfaces.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>
#include <gp_Ax3.hxx>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "engine/manifold_access.h"
#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

/// A frame whose axis is tilted off every coordinate axis.
gp_Ax2 Tilted(const gp_Pnt& origin) { return gp_Ax2(origin, gp_Dir(0.3, -0.5, 0.8), gp_Dir(0.9, 0.5, -0.025)); }

/// Surface cells of each patch, and how many of them take the closed form.
struct AnalyticCount {
  std::vector<int> cells, analytic;
};

AnalyticCount CountAnalyticCells(const Manifold& manifold) {
  const engine::CellStore& store = ManifoldAccess::Store(manifold);
  AnalyticCount count;
  count.cells.assign(store.numPatches(), 0);
  count.analytic.assign(store.numPatches(), 0);
  for (std::size_t p = 0; p < store.numPatches(); ++p) {
    for (std::int64_t c = store.patchFirstCell(p); c < store.patchFirstCell(p + 1); ++c) {
      if (store.origin(c).edge >= 0) continue;
      ++count.cells[p];
      if (store.analytic(c)) ++count.analytic[p];
    }
  }
  return count;
}

/// Points around `shape`: near its faces (from 1e-7 to 3 % of its size
/// off), near its edges, in its box grown by a third, and `special` ones.
std::vector<double> QueryPoints(const TopoDS_Shape& shape, const std::vector<double>& special, unsigned seed) {
  std::vector<double> points = PointsAround(shape, 900, {1e-7, 1e-3, 0.03}, 0.3, seed, 3);
  const std::vector<double> edges = PointsNearEdges(shape, 300, {1e-6, 0.02}, seed + 100);
  points.insert(points.end(), edges.begin(), edges.end());
  points.insert(points.end(), special.begin(), special.end());
  return points;
}

/// Appends origin + t axis for each t.
void AddOnAxis(const gp_Ax2& frame, const std::vector<double>& ts, std::vector<double>* points) {
  for (const double t : ts) {
    const gp_Pnt p = frame.Location().Translated(t * gp_Vec(frame.Direction()));
    points->insert(points->end(), {p.X(), p.Y(), p.Z()});
  }
}

/// Which surface cells of a face take the closed form.
enum class Expect { All, Some };

/// What a face of `patch` should take: all its cells, but those of a cone
/// whose v range reaches its apex and those of a spindle torus whose v
/// range reaches its axis (some: the cells there keep the NURBS search).
Expect Expected(const Patch& patch) {
  const AnalyticSurface& a = patch.analytic;
  if (a.kind == AnalyticSurface::Kind::Torus && a.minorRadius > a.radius) {
    // Where the parallels' radius R + r cos v vanishes: v = +-acos(-R / r) (mod 2 pi).
    const double meets = std::acos(-a.radius / a.minorRadius);
    const std::vector<double>& v = patch.knots[1];
    for (int turn = -2; turn <= 2; ++turn) {
      for (const double at : {meets, -meets}) {
        const double w = at + 2.0 * M_PI * turn;
        if (w >= v.front() - 1e-6 && w <= v.back() + 1e-6) return Expect::Some;
      }
    }
    return Expect::All;
  }
  if (a.kind == AnalyticSurface::Kind::Cone) {
    const double apex = -a.radius / std::sin(a.semiAngle);
    const std::vector<double>& v = patch.knots[1];
    if (apex >= v.front() - 1e-6 && apex <= v.back() + 1e-6) return Expect::Some;
  }
  return Expect::All;
}

/// The closed form answers the surface cells it should (Expected), the
/// NURBS search none of them; both agree with each other and with
/// OpenCascade.
void CheckAnalyticFaces(const TopoDS_Shape& shape, const std::string& name, const std::vector<double>& special,
                        unsigned seed) {
  const std::unique_ptr<cad::Model> model = LoadShape(shape, name);
  ASSERT_TRUE(model);
  const Geometry& geometry = model->geometry();
  Geometry nurbs = geometry;
  for (Patch& patch : nurbs.patches) patch.analytic.kind = AnalyticSurface::Kind::None;

  const std::vector<double> points = QueryPoints(shape, special, seed);
  Manifold withAnalytic, withoutAnalytic;
  const Results fast = InvertOnGeometry(geometry, points, &withAnalytic);
  const Results reference = InvertOnGeometry(nurbs, points, &withoutAnalytic);

  const AnalyticCount on = CountAnalyticCells(withAnalytic), off = CountAnalyticCells(withoutAnalytic);
  ASSERT_EQ(on.cells.size(), geometry.patches.size());
  for (std::size_t p = 0; p < on.cells.size(); ++p) {
    ASSERT_NE(geometry.patches[p].analytic.kind, AnalyticSurface::Kind::None) << name << " face " << p;
    EXPECT_GT(on.cells[p], 0) << "face " << p;
    switch (Expected(geometry.patches[p])) {
      case Expect::All:
        EXPECT_EQ(on.analytic[p], on.cells[p]) << name << " face " << p;
        break;
      case Expect::Some:
        EXPECT_GT(on.analytic[p], 0) << name << " face " << p;
        EXPECT_LT(on.analytic[p], on.cells[p]) << name << " face " << p;
        break;
    }
    EXPECT_EQ(off.analytic[p], 0) << name << " face " << p;
  }

  const double size = ShapeSize(shape);
  int differ = 0;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    ASSERT_EQ(fast.status[i], Status::Found);
    ASSERT_EQ(reference.status[i], Status::Found);
    if (std::abs(fast.distance[i] - reference.distance[i]) > 1e-9 * size && differ++ < 5) {
      ADD_FAILURE() << name << " point " << i << " (" << points[3 * i] << ", " << points[3 * i + 1] << ", "
                    << points[3 * i + 2] << "): closed form " << fast.distance[i] << " (face " << fast.patch[i]
                    << ", cell " << fast.cell[i] << "), NURBS search " << reference.distance[i] << " (face "
                    << reference.patch[i] << ", cell " << reference.cell[i] << ")";
    }
  }
  EXPECT_EQ(differ, 0);
  const Comparison c = CheckAgainstOpenCascade(shape, *model, points, 1e-9);
  EXPECT_EQ(c.notFound, 0) << c.firstFailure;
  EXPECT_EQ(c.farther, 0) << c.firstFailure;
  EXPECT_EQ(c.offFace, 0) << c.firstFailure;
  EXPECT_EQ(c.badParameters, 0) << c.firstFailure;
}

TEST(AnalyticFaces, PlanesWithHolesAndACylinder) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(40, 30, 10)).Shape();
  const gp_Ax2 axis(gp_Pnt(20, 15, -1), gp_Dir(0, 0, 1));
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(axis, 6.0, 12.0).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Cut(box, drill).Shape();
  std::vector<double> special = {20, 15, 5, 20, 15, -3, 20, 15, 14, 0, 0, 0, 40, 30, 10, 20, 21, 5, 20, 9, 5};
  AddOnAxis(axis, {0.0, 1.0, 6.0, 11.0, 13.0}, &special);
  CheckAnalyticFaces(part, "analytic_box_hole", special, 11);
}

TEST(AnalyticFaces, PartialCylinderInATiltedFrame) {
  const gp_Ax2 frame = Tilted(gp_Pnt(1, 2, 3));
  const TopoDS_Shape part = BRepPrimAPI_MakeCylinder(frame, 4.0, 10.0, 2.5).Shape();
  std::vector<double> special;
  AddOnAxis(frame, {-3.0, 0.0, 2.0, 5.0, 10.0, 14.0}, &special);
  CheckAnalyticFaces(part, "analytic_cylinder", special, 12);
}

TEST(AnalyticFaces, PointedAndTruncatedCones) {
  // A pointed cone (its apex a vertex of the face: the cells at the apex
  // keep the NURBS search, the others take the closed form) and a
  // truncated cone over part of a turn.
  const gp_Ax2 frame = Tilted(gp_Pnt(-2, 1, 0));
  const TopoDS_Shape pointed = BRepPrimAPI_MakeCone(frame, 5.0, 0.0, 8.0).Shape();
  const gp_Ax2 other(gp_Pnt(20, 0, 0), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0));
  const TopoDS_Shape truncated = BRepPrimAPI_MakeCone(other, 6.0, 2.0, 5.0, 4.0).Shape();
  const TopoDS_Compound both = CompoundOf({pointed, truncated});
  std::vector<double> special;
  AddOnAxis(frame, {-2.0, 0.0, 3.0, 8.0, 8.5, 12.0}, &special);  // through the base, to the apex and past it
  AddOnAxis(other, {-1.0, 2.5, 5.0, 9.0}, &special);
  CheckAnalyticFaces(both, "analytic_cones", special, 13);
}

TEST(AnalyticFaces, SpheresPartialAndDrilled) {
  const gp_Ax2 frame = Tilted(gp_Pnt(0, 0, 0));
  // Longitudes over 4.5 radians, latitudes from -1 to 1.2 (no pole).
  const TopoDS_Shape zone = BRepPrimAPI_MakeSphere(frame, 5.0, -1.0, 1.2, 4.5).Shape();
  // A whole sphere with its poles, drilled off-axis: trimmed cells.
  const gp_Pnt centre(20, 0, 0);
  const TopoDS_Shape ball = BRepPrimAPI_MakeSphere(centre, 6.0).Shape();
  const TopoDS_Shape drill =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(22, -10, 1), gp_Dir(0, 1, 0.2)), 2.0, 20.0).Shape();
  const TopoDS_Shape drilled = BRepAlgoAPI_Cut(ball, drill).Shape();
  const TopoDS_Compound both = CompoundOf({zone, drilled});
  std::vector<double> special = {0, 0, 0, 20, 0, 0, 20, 0, 6, 20, 0, -6, 20, 0, 6.5, 20, 0, -9, 20, 0, 3, 22, 0, 1};
  AddOnAxis(frame, {-7.0, -5.0, -2.0, 0.5, 5.0, 9.0}, &special);
  CheckAnalyticFaces(both, "analytic_spheres", special, 14);
}

TEST(AnalyticFaces, TorusPartialAndCutByABox) {
  const gp_Ax2 frame = Tilted(gp_Pnt(0, 0, 0));
  const TopoDS_Shape ring = BRepPrimAPI_MakeTorus(frame, 6.0, 2.0, 4.0).Shape();
  const gp_Ax2 flat(gp_Pnt(30, 0, 0), gp_Dir(0, 0, 1));
  const TopoDS_Shape whole = BRepPrimAPI_MakeTorus(flat, 7.0, 2.5).Shape();
  const TopoDS_Shape cutter = BRepPrimAPI_MakeBox(gp_Pnt(31, -3, -5), gp_Pnt(45, 4, 1)).Shape();
  const TopoDS_Shape cut = BRepAlgoAPI_Cut(whole, cutter).Shape();
  const TopoDS_Compound both = CompoundOf({ring, cut});
  // Centres, axes, the tubes' centre circles, inside the tubes.
  std::vector<double> special = {30, 0, 0, 30, 0, 5, 37, 0, 0, 23, 0, 0, 30, 7, 0, 30, -7, 0.1, 38, 0, 0.5, 30, 0, -4};
  AddOnAxis(frame, {-4.0, 0.0, 3.0}, &special);
  const gp_Pnt onCircle = frame.Location().Translated(6.0 * gp_Vec(frame.XDirection()));
  special.insert(special.end(), {onCircle.X(), onCircle.Y(), onCircle.Z()});
  CheckAnalyticFaces(both, "analytic_tori", special, 15);
}

TEST(AnalyticFaces, LoneFacesInOddFramesAcrossAnApexAndOnASpindleTorus) {
  // Lone faces from surfaces: a cylinder in a left-handed frame, a cone
  // face spanning both sides of its apex, a plane in a tilted frame, three
  // faces of a spindle torus (minor radius above the major): one reaching
  // its axis (the cells there keep the NURBS search), one outside, one on
  // the inner part (as OpenCascade's sample screw's rounded head), and a
  // sphere in a left-handed frame with its poles.
  gp_Ax3 leftHanded(gp_Pnt(0, 0, 0), gp_Dir(0, 0.6, 0.8), gp_Dir(1, 0, 0));
  leftHanded.YReverse();
  ASSERT_FALSE(leftHanded.Direct());
  Handle(Geom_Surface) cylinder = new Geom_CylindricalSurface(leftHanded, 3.0);
  const gp_Ax3 coneFrame(gp_Pnt(12, 0, 0), gp_Dir(1, 0, 0.2), gp_Dir(0, 1, 0));
  Handle(Geom_Surface) cone = new Geom_ConicalSurface(coneFrame, 0.5, 1.0);  // apex at v = -1 / sin 0.5
  Handle(Geom_Surface) plane = new Geom_Plane(gp_Ax3(Tilted(gp_Pnt(0, 12, 0))));
  Handle(Geom_Surface) spindle = new Geom_ToroidalSurface(gp_Ax3(gp_Pnt(-14, 0, 0), gp_Dir(0, 0, 1)), 2.0, 3.0);
  gp_Ax3 sphereFrame(gp_Pnt(0, -12, 0), gp_Dir(0, 0, 1), gp_Dir(0, 1, 0));
  sphereFrame.YReverse();
  Handle(Geom_Surface) sphere = new Geom_SphericalSurface(sphereFrame, 2.5);
  const TopoDS_Compound all = CompoundOf({
      BRepBuilderAPI_MakeFace(cylinder, 0.3, 4.0, -2.0, 5.0, 1e-7).Face(),
      BRepBuilderAPI_MakeFace(cone, 0.0, 5.0, -4.0, 2.0, 1e-7).Face(),
      BRepBuilderAPI_MakeFace(plane, -3.0, 4.0, -2.0, 5.0, 1e-7).Face(),
      BRepBuilderAPI_MakeFace(spindle, 0.0, 3.0, -1.0, 2.8, 1e-7).Face(),
      BRepBuilderAPI_MakeFace(spindle, 3.5, 5.0, -1.5, 1.5, 1e-7).Face(),
      BRepBuilderAPI_MakeFace(spindle, 5.2, 6.2, 2.5, 3.9, 1e-7).Face(),  // the inner part: parallels' radius < 0
      BRepBuilderAPI_MakeFace(sphere, 1.0, 5.5, -0.5 * M_PI, 0.5 * M_PI, 1e-7).Face(),
  });
  std::vector<double> special = {0, 0, 0, 0, 1.2, 1.6, 0, -12, 0, 0, -12, 2.5, 0, -12, -3, -14, 0, 0, -14, 0, 3};
  const double apexV = -1.0 / std::sin(0.5);
  const gp_Pnt apex = cone->Value(0.0, apexV);
  special.insert(special.end(), {apex.X(), apex.Y(), apex.Z()});
  for (const double t : {-2.0, 1.0, 3.0}) {
    const gp_Pnt onAxis = coneFrame.Location().Translated((apexV * std::cos(0.5) + t) * gp_Vec(coneFrame.Direction()));
    special.insert(special.end(), {onAxis.X(), onAxis.Y(), onAxis.Z()});
  }
  CheckAnalyticFaces(all, "analytic_lone_faces", special, 16);
}

}  // namespace
}  // namespace invmap::cadtest
