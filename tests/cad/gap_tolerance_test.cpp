// The gap tolerance at D = 0 on trimmed CAD faces: the closest points invmap
// reports, re-inverted with D = 0, are all found (the trial lost 94 of 3,000
// on the bracket and 87 on OpenCascade's bottle, on face and cell edges a
// rounding outside their boxes); the unlimited answer is the reference.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>
#include <gtest/gtest.h>

#include <string>

#include "tests/cad/occ_reference.h"
#include "tests/support/gap_contract.h"

namespace invmap::cadtest {
namespace {

void CheckZeroGap(const cad::Model& model, const TopoDS_Shape& shape) {
  BuildResult built = Manifold::Build(model.geometry());
  ASSERT_EQ(built.error, "");
  const std::vector<double> points = PointsAround(shape, 3000, 0.05, 0.2, 11);
  testing::ExpectClosestPointsFoundAtZeroGap(built.manifold, points, ShapeSize(shape));
}

TEST(CadGapTolerance, ClosestPointsOfTheBracketAreFoundAtZero) {
  const std::string path = std::string(INVMAP_SOURCE_DIR) + "/examples/data/bracket.step";
  cad::LoadResult loaded = cad::Model::Load(path);
  ASSERT_TRUE(loaded.model) << loaded.error;
  CheckZeroGap(*loaded.model, ReadShape(path));
}

TEST(CadGapTolerance, ClosestPointsOfADrilledBoxAreFoundAtZero) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(40, 30, 10)).Shape();
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 15, -1), gp_Dir(0, 0, 1)), 6.0, 12.0).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Cut(box, drill).Shape();
  CheckZeroGap(*LoadShape(part, "gap_drilled_box"), part);
}

TEST(CadGapTolerance, ClosestPointsOfTheBottleAreFoundAtZero) {
  const std::string path = std::string(INVMAP_OCC_SAMPLES) + "/occ/bottle.brep";
  cad::LoadResult loaded = cad::Model::Load(path);
  ASSERT_TRUE(loaded.model) << loaded.error;
  CheckZeroGap(*loaded.model, ReadShape(path));
}

}  // namespace
}  // namespace invmap::cadtest
