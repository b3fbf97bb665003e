// OpenCascade's sample models (Debian's occt-misc): thousands of points
// around each, invmap never farther than OpenCascade's distance (the
// extrema of BRepExtrema_DistShapeShape set up once per face and edge,
// which gives DistShapeShape's own distance on a share of the points), its
// point on the face it names and that face's surface at its (u, v).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

#include "tests/cad/occ_nearest.h"
#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

struct SampleModel {
  const char* path;          ///< Under the occt-misc data folder.
  int distShapeShapePoints;  ///< How many of its points DistShapeShape itself answers (few where it is slow).
};

/// Every model of the step/, iges/ and occ/*.brep folders that has faces
/// (asahi.brep and edge.brep hold only curves: see cad_files_test).
/// DistShapeShape itself, tens to thousands of times slower than OccNearest
/// (seconds a point on terrain.brep, one B-spline face of 100,000 spans; a
/// tenth of a second on shell1.brep and Top.brep), answers a few seconds'
/// worth of the points.
constexpr int kPoints = 4000;
const SampleModel kModels[] = {
    {"step/screw.step", 200},
    {"step/linkrods.step", 20},
    {"iges/bearing.iges", 15},
    {"iges/hammer.iges", 25},
    {"occ/Axis_of_bearing.brep", 100},
    {"occ/Ball.brep", 50},
    {"occ/Bottom.brep", 25},
    {"occ/CrankArm.brep", 60},
    {"occ/MAT.brep", 4},
    {"occ/MODERN_Chair_1.brep", 100},
    {"occ/MODERN_Cooker_1.brep", 100},
    {"occ/MODERN_Cooker_1_opened.brep", 200},
    {"occ/MODERN_Exhaust_1.brep", 200},
    {"occ/MODERN_MVCooker_1.brep", 200},
    {"occ/MODERN_MVCooker_1_opened.brep", 200},
    {"occ/MODERN_Refrigerator_1.brep", 200},
    {"occ/MODERN_Refrigerator_1_opened.brep", 100},
    {"occ/MODERN_Sink_1.brep", 60},
    {"occ/MODERN_Sink_1_opened.brep", 200},
    {"occ/MODERN_Table_1.brep", 200},
    {"occ/Motor-c.brep", 40},
    {"occ/Pump_Nut.brep", 100},
    {"occ/Pump_TopCover.brep", 50},
    {"occ/Room.brep", 200},
    {"occ/Top.brep", 6},
    {"occ/bottle.brep", 200},
    {"occ/face.brep", 200},
    {"occ/face1.brep", 200},
    {"occ/face2.brep", 200},
    {"occ/fuse.brep", 200},
    {"occ/hammer.brep", 25},
    {"occ/mal_ecrou.brep", 200},
    {"occ/mal_tige.brep", 200},
    {"occ/mal_vis.brep", 200},
    {"occ/shell1.brep", 3},
    {"occ/solid.brep", 200},
    {"occ/terrain.brep", 3},
    {"occ/wedge_ok.brep", 200},
    {"occ/wing.brep", 100},
};

/// `count` points around a model: three eighths within 2 % of its size
/// from its surface, an eighth within 0.1 % (where a scan's points lie), a
/// quarter within 1 % or 0.01 % of its edges (where the trimming decides),
/// a quarter in a box a fifth larger on each side than the model's.
std::vector<double> PointsAroundModel(const TopoDS_Shape& shape, int count) {
  std::vector<double> points = PointsAround(shape, count - count / 4, {0.02, 0.02, 0.02, 0.001}, 0.2, 11, 3);
  const std::vector<double> nearEdges = PointsNearEdges(shape, count / 4, {0.01, 1e-4}, 12);
  points.insert(points.end(), nearEdges.begin(), nearEdges.end());
  return points;
}

/// How gtest names a model (ctest's test names include it).
void PrintTo(const SampleModel& model, std::ostream* out) { *out << model.path; }

class SampleModelTest : public ::testing::TestWithParam<SampleModel> {};

TEST_P(SampleModelTest, NeverFartherThanOpenCascadeAndOnTheFace) {
  const std::string path = std::string(INVMAP_OCC_SAMPLES) + "/" + GetParam().path;
  cad::LoadResult loaded = cad::Model::Load(path);
  ASSERT_EQ(loaded.error, "") << path;
  const TopoDS_Shape shape = ReadShape(path);
  const std::vector<double> points = PointsAroundModel(shape, kPoints);
  const Comparison c = CheckAgainstOpenCascade(shape, *loaded.model, points, 1e-6);
  EXPECT_EQ(c.notFound, 0) << c.firstFailure;
  EXPECT_EQ(c.farther, 0) << c.firstFailure << " (worst excess " << c.worstExcess << " of the size)";
  EXPECT_EQ(c.offFace, 0) << c.firstFailure;
  EXPECT_EQ(c.badParameters, 0) << c.firstFailure;
}

// The reference above is DistShapeShape's own extrema set up once: on a
// share of the same points (near and far ones alike) it gives
// DistShapeShape's distance.
TEST_P(SampleModelTest, SetUpOnceReferenceIsDistShapeShape) {
  const std::string path = std::string(INVMAP_OCC_SAMPLES) + "/" + GetParam().path;
  const TopoDS_Shape shape = ReadShape(path);
  const std::vector<TopoDS_Face> faces = Faces(shape);
  const TopoDS_Compound boundary = Compound(faces);
  const double size = ShapeSize(shape);
  const std::vector<double> points = PointsAroundModel(shape, kPoints);
  const std::size_t n = points.size() / 3;
  const std::size_t checked = GetParam().distShapeShapePoints;
  OccNearest nearest(faces);
  double worst = 0.0;
  for (std::size_t j = 0; j < checked; ++j) {
    const std::size_t i = j * n / checked;  // spread over near, close and far points
    const double once = nearest.Distance(&points[3 * i]);
    const double each = OccDistance(boundary, &points[3 * i]);
    worst = std::max(worst, std::abs(once - each) / size);
    EXPECT_NEAR(once, each, 1e-9 * size) << "point " << i;
  }
  RecordProperty("worst_difference_of_size", std::to_string(worst));
}

std::string ModelName(const ::testing::TestParamInfo<SampleModel>& info) {
  std::string name = info.param.path;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(OcctMisc, SampleModelTest, ::testing::ValuesIn(kModels), ModelName);

}  // namespace
}  // namespace invmap::cadtest
