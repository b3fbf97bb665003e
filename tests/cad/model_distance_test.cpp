// Model-to-model distance between CAD models (trimmed faces), built with
// OpenCascade's modelling API, under poses: against OpenCascade's
// BRepExtrema_DistShapeShape between the two models' faces, closed forms
// where the trimming decides the answer (a sphere facing a plate's hole,
// where the plane's untrimmed minimum lies in the hole), and the reported
// points on the reported faces (the face classifier at the reported (u, v),
// the face's surface there at the reported point).
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Ax2.hxx>
#include <gp_Trsf.hxx>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "invmap/distance.h"
#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

/// A CAD model read back from its BREP file, its manifold and distance model.
struct CadDistanceModel {
  TopoDS_Shape shape;
  std::unique_ptr<cad::Model> cad;
  Manifold manifold;
  DistanceModel model;
};

std::unique_ptr<CadDistanceModel> Prepare(const TopoDS_Shape& shape, const std::string& name) {
  auto m = std::make_unique<CadDistanceModel>();
  m->shape = shape;
  m->cad = LoadShape(shape, name);
  BuildResult built = Manifold::Build(m->cad->geometry());
  EXPECT_EQ(built.error, "");
  m->manifold = std::move(built.manifold);
  DistanceModelBuild model = DistanceModel::Build(m->manifold);
  EXPECT_EQ(model.error, "");
  m->model = model.model;
  return m;
}

/// The pose as OpenCascade's transformation (the same 3 x 4 rows).
TopoDS_Shape Moved(const TopoDS_Shape& shape, const Pose& pose) {
  gp_Trsf trsf;
  const double* m = pose.m;
  trsf.SetValues(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
  return BRepBuilderAPI_Transform(shape, trsf, true).Shape();
}

void Apply(const Pose& pose, const double* x, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = pose.m[4 * k] * x[0] + pose.m[4 * k + 1] * x[1] + pose.m[4 * k + 2] * x[2] + pose.m[4 * k + 3];
}

/// "" when the reported point lies on the reported face of the (posed)
/// model: the face's surface at the reported (u, v), moved by the pose, is
/// the reported point, and the face classifier keeps (u, v).
std::string CheckOnFace(const CadDistanceModel& m, const Pose& pose, const ModelPoint& point, double size) {
  const std::vector<TopoDS_Face> faces = Faces(m.shape);
  if (point.patch < 0 || point.patch >= static_cast<int>(faces.size())) return "no face " + std::to_string(point.patch);
  const TopoDS_Face& face = faces[point.patch];
  const double tolerance = std::max(1e-7 * size, FaceTolerance(face));
  BRepClass_FaceClassifier classifier(face, gp_Pnt2d(point.params[0], point.params[1]), tolerance);
  if (classifier.State() == TopAbs_OUT) {
    return "(u, v) = (" + std::to_string(point.params[0]) + ", " + std::to_string(point.params[1]) +
           ") lies outside face " + std::to_string(point.patch);
  }
  const gp_Pnt at = BRep_Tool::Surface(face)->Value(point.params[0], point.params[1]);
  const double local[3] = {at.X(), at.Y(), at.Z()};
  double world[3];
  Apply(pose, local, world);
  const double gap = std::hypot(world[0] - point.point[0], world[1] - point.point[1], world[2] - point.point[2]);
  if (!(gap <= 10 * tolerance)) {
    return "the surface of face " + std::to_string(point.patch) + " at the reported (u, v) is " + std::to_string(gap) +
           " from the reported point";
  }
  return "";
}

/// OpenCascade's distance between the faces of the two posed shapes.
double OccModelDistance(const TopoDS_Shape& a, const Pose& poseA, const TopoDS_Shape& b, const Pose& poseB) {
  BRepExtrema_DistShapeShape extrema(Compound(Faces(Moved(a, poseA))), Compound(Faces(Moved(b, poseB))));
  EXPECT_TRUE(extrema.IsDone());
  return extrema.Value();
}

/// invmap's answer checked against OpenCascade's distance (never farther
/// beyond 1e-6 of the size, nor nearer beyond the models' tolerances) and
/// against the faces; returns invmap's distance.
double CheckPair(const CadDistanceModel& a, const Pose& poseA, const CadDistanceModel& b, const Pose& poseB,
                 const std::string& what) {
  SCOPED_TRACE(what);
  DistanceResult result;
  std::string message;
  EXPECT_EQ(Distance(a.model, poseA, b.model, poseB, DistanceOptions(), &result, &message), Error::Ok) << message;
  EXPECT_TRUE(result.nearest.found);
  EXPECT_TRUE(result.nearest.certified);
  const double size = std::max(ShapeSize(a.shape), ShapeSize(b.shape));
  const double occ = OccModelDistance(a.shape, poseA, b.shape, poseB);
  EXPECT_LE(result.nearest.distance, occ + 1e-6 * size) << "invmap farther than OpenCascade";
  EXPECT_GE(result.nearest.distance, occ - 1e-6 * size) << "invmap nearer than OpenCascade";
  EXPECT_NEAR(std::hypot(result.nearest.a.point[0] - result.nearest.b.point[0],
                         result.nearest.a.point[1] - result.nearest.b.point[1],
                         result.nearest.a.point[2] - result.nearest.b.point[2]),
              result.nearest.distance, 1e-9 * size);
  EXPECT_EQ(CheckOnFace(a, poseA, result.nearest.a, size), "") << "point on A";
  EXPECT_EQ(CheckOnFace(b, poseB, result.nearest.b, size), "") << "point on B";
  return result.nearest.distance;
}

TopoDS_Shape PlateWithHole() {
  // 40 x 30 x 2, a hole of radius 6 about (20, 15).
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(40, 30, 2)).Shape();
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 15, -1), gp_Dir(0, 0, 1)), 6.0, 4.0).Shape();
  return BRepAlgoAPI_Cut(box, drill).Shape();
}

Pose Translation(double x, double y, double z) {
  const double axis[3] = {0, 0, 1}, t[3] = {x, y, z};
  return Pose::FromAxisAngle(axis, 0.0, t);
}

TEST(CadModelDistance, SphereFacingAPlatesHoleIsNearestToTheRim) {
  // The top face's plane comes nearest to the sphere inside the hole, which
  // the face trims away: the answer is the rim (a circle of radius 6 at
  // z = 2), sqrt((6 - e)^2 + h^2) - 3 from a sphere of radius 3 at height h
  // above it and e off its axis; lowered into the hole, the hole's wall at
  // 6 - e - 3. (Off the axis: on it every point of the rim is nearest, a
  // circle of minima.)
  const auto plate = Prepare(PlateWithHole(), "plate_with_hole");
  const auto ball = Prepare(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 3.0).Shape(), "ball");
  for (const double h : {2.0, 3.5, 6.0}) {
    const double d = CheckPair(*plate, Pose(), *ball, Translation(20.5, 15, 2 + h), "height " + std::to_string(h));
    EXPECT_NEAR(d, std::sqrt(5.5 * 5.5 + h * h) - 3.0, 1e-8) << "height " << h;
  }
  const double inHole = CheckPair(*plate, Pose(), *ball, Translation(20.5, 15, 1), "in the hole");
  EXPECT_NEAR(inHole, 2.5, 1e-8);
  // Off the axis, tilted: against OpenCascade only.
  const double axis[3] = {1, 2, 0.5}, t[3] = {22, 13, 4};
  CheckPair(*plate, Pose(), *ball, Pose::FromAxisAngle(axis, 0.7, t), "tilted");
}

TEST(CadModelDistance, FilletedBoxAndTorusUnderPoses) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(30, 20, 10)).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer it(box, TopAbs_EDGE); it.More(); it.Next()) fillet.Add(2.5, TopoDS::Edge(it.Current()));
  const auto filleted = Prepare(fillet.Shape(), "filleted_box_distance");
  const auto torus = Prepare(BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 6.0, 1.5).Shape(), "torus");
  const double poses[][7] = {
      // axis, angle, translation
      {1, 0.2, 0, 0.15, 15, 10, 13}, // above the top face, tilted a little
      {1, 1, 0, 0.9, 33, 23, 12},    // past a corner, tilted
      {0, 1, 0, 1.4, 38, 10, 5},     // nearly upright beside an end
      {0.3, -1, 2, 2.1, -4, -5, 9},  // toward the fillets of another corner
      {0, 0, 1, 0.3, 15, 10, 5},     // around the box: intersecting
  };
  for (const auto& p : poses) {
    const Pose pose = Pose::FromAxisAngle(p, p[3], p + 4);
    CheckPair(*filleted, Pose(), *torus, pose, "pose at " + std::to_string(p[4]) + " " + std::to_string(p[5]));
  }
}

TEST(CadModelDistance, CutSphereAndPlateWithHoleBothPosed) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 5.0).Shape();
  const TopoDS_Shape above = BRepPrimAPI_MakeBox(gp_Pnt(-10, -10, 2), gp_Pnt(10, 10, 10)).Shape();
  const auto cutSphere = Prepare(BRepAlgoAPI_Cut(sphere, above).Shape(), "cut_sphere_distance");
  const auto plate = Prepare(PlateWithHole(), "plate_with_hole_b");
  const double axisA[3] = {0, 0, 1}, tA[3] = {1, -2, 0.5};
  const Pose poseA = Pose::FromAxisAngle(axisA, 0.2, tA);
  // The cut sphere's flat face down over the hole, then its cap into it,
  // then tilted across the hole's rim.
  const double flip[3] = {1, 0, 0};
  const double t1[3] = {21, 13, 5}, t2[3] = {21, 13, 9}, t3[3] = {17, 12, 8};
  CheckPair(*plate, poseA, *cutSphere, Translation(21, 13, 5), "flat face down");
  CheckPair(*plate, poseA, *cutSphere, Pose::FromAxisAngle(flip, M_PI, t1), "cap down into the hole");
  CheckPair(*plate, poseA, *cutSphere, Pose::FromAxisAngle(flip, M_PI, t2), "cap down above the hole");
  const double tilt[3] = {1, 1, 0};
  CheckPair(*plate, poseA, *cutSphere, Pose::FromAxisAngle(tilt, 2.5, t3), "tilted over the rim");
}

TEST(CadModelDistance, RandomPosesOfACutSphereAroundAFilletedPlateWithHole) {
  // Random rotations, B's centre on a sphere about A's centre at a random
  // radius from inside A's box to a little outside it: gaps, contacts,
  // intersections, faces, edges and vertices facing each other.
  const TopoDS_Shape plate = PlateWithHole();
  BRepFilletAPI_MakeFillet fillet(plate);
  for (TopExp_Explorer it(plate, TopAbs_EDGE); it.More(); it.Next()) {
    // The box's four vertical corner edges.
    double first, last;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(TopoDS::Edge(it.Current()), first, last);
    if (curve.IsNull()) continue;
    const gp_Pnt p0 = curve->Value(first), p1 = curve->Value(last);
    const bool corner = (p0.X() < 1e-9 || p0.X() > 40 - 1e-9) && (p0.Y() < 1e-9 || p0.Y() > 30 - 1e-9);
    if (corner && std::abs(p0.X() - p1.X()) < 1e-9 && std::abs(p0.Y() - p1.Y()) < 1e-9) {
      fillet.Add(3.0, TopoDS::Edge(it.Current()));
    }
  }
  const auto a = Prepare(fillet.Shape(), "filleted_plate");
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 5.0).Shape();
  const TopoDS_Shape above = BRepPrimAPI_MakeBox(gp_Pnt(-10, -10, 2.5), gp_Pnt(10, 10, 10)).Shape();
  const auto b = Prepare(BRepAlgoAPI_Cut(sphere, above).Shape(), "cut_sphere_random");
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), across(-5.0, 45.0), gap(-0.5, 2.0);
  int apart = 0;
  for (int n = 0; n < 16; ++n) {
    const double axis[3] = {unit(random), unit(random), unit(random)};
    // Over or under the plate (the hole, the fillets), or beside one of its ends.
    double t[3];
    if (n % 2 == 0) {
      t[0] = across(random);
      t[1] = 0.75 * across(random);
      t[2] = (n % 4 == 0 ? 7.0 : -5.0) + gap(random);
    } else {
      t[0] = n % 4 == 1 ? -5.0 - gap(random) : 45.0 + gap(random);
      t[1] = 0.75 * across(random);
      t[2] = 3.0 * unit(random);
    }
    const double d = CheckPair(*a, Pose(), *b, Pose::FromAxisAngle(axis, 3.0 * unit(random), t), "random pose " + std::to_string(n));
    apart += d > 0.0 ? 1 : 0;
  }
  EXPECT_GE(apart, 10);  // mostly apart: the trimmed faces decide
}

TEST(CadModelDistance, SampleModelsAgainstTurnedCopies) {
  // OpenCascade's sample models (occt-misc) against copies of themselves
  // turned about a random axis through their centre and moved by 0.6 to
  // 0.9 of their size: real files' faces, loops and tolerances.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), reach(0.6, 0.9);
  for (const char* name : {"step/screw.step", "occ/Pump_Nut.brep", "occ/CrankArm.brep"}) {
    const std::string path = std::string(INVMAP_OCC_SAMPLES) + "/" + name;
    const auto model = Prepare(ReadShape(path), std::string("sample_") + std::to_string(random()));
    const auto info = model->cad->Info();
    double center[3], size = 0.0;
    for (int k = 0; k < 3; ++k) {
      center[k] = 0.5 * (info.boundsLo[k] + info.boundsHi[k]);
      size = std::hypot(size, info.boundsHi[k] - info.boundsLo[k]);
    }
    for (int n = 0; n < 3; ++n) {
      const double axis[3] = {unit(random), unit(random), unit(random)};
      double direction[3] = {unit(random), unit(random), unit(random)};
      const double length = std::hypot(direction[0], direction[1], direction[2]), r = reach(random) * size;
      Pose pose = Pose::FromAxisAngle(axis, 3.0 * unit(random), center);
      // x -> R (x - c) + c + r d.
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) pose.m[4 * k + 3] -= pose.m[4 * k + l] * center[l];
        pose.m[4 * k + 3] += r * direction[k] / length;
      }
      CheckPair(*model, Pose(), *model, pose, std::string(name) + " pose " + std::to_string(n));
    }
  }
}

TEST(CadModelDistance, TrackerFollowsABallAcrossTheHole) {
  // Each tracked pose against a fresh query and OpenCascade.
  const auto plate = Prepare(PlateWithHole(), "plate_with_hole_track");
  const auto ball = Prepare(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 3.0).Shape(), "ball_track");
  DistanceTracker tracker(plate->model, ball->model);
  const double size = ShapeSize(plate->shape);
  for (int step = 0; step <= 12; ++step) {
    const double x = 8.0 + 2.0 * step;  // across the hole (x from 14 to 26)
    const Pose pose = Translation(x, 16, 5.5);  // off the hole's axis (on it: a circle of minima)
    DistanceResult tracked;
    std::string message;
    ASSERT_EQ(tracker.Update(pose, &tracked, &message), Error::Ok) << message;
    DistanceResult fresh;
    ASSERT_EQ(Distance(plate->model, Pose(), ball->model, pose, DistanceOptions(), &fresh, &message), Error::Ok);
    ASSERT_TRUE(tracked.nearest.found);
    EXPECT_TRUE(tracked.nearest.certified) << "step " << step;
    const double occ = OccModelDistance(plate->shape, Pose(), ball->shape, pose);
    EXPECT_NEAR(tracked.nearest.distance, fresh.nearest.distance, 1e-9 * size) << "step " << step;
    EXPECT_NEAR(tracked.nearest.distance, occ, 1e-6 * size) << "step " << step;
    EXPECT_EQ(CheckOnFace(*plate, Pose(), tracked.nearest.a, size), "") << "step " << step;
  }
}

}  // namespace
}  // namespace invmap::cadtest
