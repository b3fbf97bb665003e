// OpenCascade's sample models (Debian's occt-misc): points around each,
// invmap never farther than BRepExtrema_DistShapeShape, its point on the
// face it names and that face's surface at its (u, v).
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

struct SampleModel {
  const char* path;  ///< Under the occt-misc data folder.
  int points;        ///< Fewer where OpenCascade's own query is slow (tens of points/s).
};

/// Every model of the step/, iges/ and occ/*.brep folders that has faces
/// (asahi.brep and edge.brep hold only curves: see cad_files_test), with as
/// many points as OpenCascade answers in a few seconds on two threads (a
/// point of terrain.brep, one B-spline face of 100,000 spans, takes it
/// seconds; of shell1.brep and Top.brep a tenth of one).
const SampleModel kModels[] = {
    {"step/screw.step", 2000},
    {"step/linkrods.step", 200},
    {"iges/bearing.iges", 150},
    {"iges/hammer.iges", 250},
    {"occ/Axis_of_bearing.brep", 1000},
    {"occ/Ball.brep", 500},
    {"occ/Bottom.brep", 250},
    {"occ/CrankArm.brep", 600},
    {"occ/MAT.brep", 40},
    {"occ/MODERN_Chair_1.brep", 1000},
    {"occ/MODERN_Cooker_1.brep", 1000},
    {"occ/MODERN_Cooker_1_opened.brep", 2000},
    {"occ/MODERN_Exhaust_1.brep", 2000},
    {"occ/MODERN_MVCooker_1.brep", 2000},
    {"occ/MODERN_MVCooker_1_opened.brep", 2000},
    {"occ/MODERN_Refrigerator_1.brep", 2000},
    {"occ/MODERN_Refrigerator_1_opened.brep", 1000},
    {"occ/MODERN_Sink_1.brep", 600},
    {"occ/MODERN_Sink_1_opened.brep", 2000},
    {"occ/MODERN_Table_1.brep", 2000},
    {"occ/Motor-c.brep", 400},
    {"occ/Pump_Nut.brep", 1000},
    {"occ/Pump_TopCover.brep", 500},
    {"occ/Room.brep", 2000},
    {"occ/Top.brep", 60},
    {"occ/bottle.brep", 2000},
    {"occ/face.brep", 2000},
    {"occ/face1.brep", 2000},
    {"occ/face2.brep", 2000},
    {"occ/fuse.brep", 2000},
    {"occ/hammer.brep", 250},
    {"occ/mal_ecrou.brep", 2000},
    {"occ/mal_tige.brep", 2000},
    {"occ/mal_vis.brep", 2000},
    {"occ/shell1.brep", 30},
    {"occ/solid.brep", 2000},
    {"occ/terrain.brep", 3},
    {"occ/wedge_ok.brep", 2000},
    {"occ/wing.brep", 1000},
};

/// How gtest names a model (ctest's test names include it).
void PrintTo(const SampleModel& model, std::ostream* out) { *out << model.path; }

class SampleModelTest : public ::testing::TestWithParam<SampleModel> {};

TEST_P(SampleModelTest, NeverFartherThanOpenCascadeAndOnTheFace) {
  const std::string path = std::string(INVMAP_OCC_SAMPLES) + "/" + GetParam().path;
  cad::LoadResult loaded = cad::Model::Load(path);
  ASSERT_EQ(loaded.error, "") << path;
  const TopoDS_Shape shape = ReadShape(path);
  // Half the points within 2 % of the size of the surface, half in a box a
  // fifth larger on each side than the model's.
  const std::vector<double> points = PointsAround(shape, GetParam().points, 0.02, 0.2, 11);
  const Comparison c = CheckAgainstOpenCascade(shape, *loaded.model, points, 1e-6);
  EXPECT_EQ(c.notFound, 0) << c.firstFailure;
  EXPECT_EQ(c.farther, 0) << c.firstFailure << " (worst excess " << c.worstExcess << " of the size)";
  EXPECT_EQ(c.offFace, 0) << c.firstFailure;
  EXPECT_EQ(c.badParameters, 0) << c.firstFailure;
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
