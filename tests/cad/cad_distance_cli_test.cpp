// `invmap distance` and `invmap invert --all-minima` on CAD files written
// by OpenCascade's writers (a STEP plate with a hole, a BREP ball above
// it): the distance is the closed form where the plate's hole decides it
// (the plane's untrimmed minimum lies in the hole), and the minima are the
// rim's point toward the ball, once.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <STEPControl_Writer.hxx>
#include <gp_Ax2.hxx>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

/// Runs the command line; its exit code and its output (stdout and stderr).
std::pair<int, std::string> RunInvmap(const std::string& arguments) {
  const std::string command = std::string(INVMAP_CLI_PATH) + " " + arguments + " 2>&1";
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The number after the first `"key": ` at or after `from` in a JSON text.
double NumberAfter(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\": ", from);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + key.size() + 4, nullptr);
}

/// A 40 x 30 x 2 plate with a hole of radius 6 about (20, 15), as STEP.
std::string WritePlateStep() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(40, 30, 2)).Shape();
  const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 15, -1), gp_Dir(0, 0, 1)), 6.0, 4.0).Shape();
  const std::string path = ScratchDir() + "/plate.step";
  STEPControl_Writer writer;
  EXPECT_EQ(writer.Transfer(BRepAlgoAPI_Cut(box, drill).Shape(), STEPControl_AsIs), IFSelect_RetDone);
  EXPECT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  return path;
}

TEST(CadDistanceCli, PlateAndBallFromStepAndBrep) {
  const std::string plate = WritePlateStep();
  // A ball of radius 3 at (20.5, 15, 5): 3 above the plate, over its hole.
  const std::string ball = ScratchDir() + "/ball.brep";
  ASSERT_TRUE(BRepTools::Write(BRepPrimAPI_MakeSphere(gp_Pnt(20.5, 15, 5), 3.0).Shape(), ball.c_str()));
  const std::string output = ScratchDir() + "/plate_ball.json";
  std::filesystem::remove(output);
  const auto [code, text] = RunInvmap("distance --a " + plate + " --b " + ball + " -q -o " + output);
  ASSERT_EQ(code, 0) << text;
  const std::string json = ReadText(output);
  // The rim's point (26, 15, 2) toward the ball's centre, less its radius.
  EXPECT_NEAR(NumberAfter(json, "distance"), std::sqrt(5.5 * 5.5 + 3.0 * 3.0) - 3.0, 1e-8) << json;

  // Posed: the ball moved down into the hole, off its axis by 0.5: the wall.
  const std::string posed = ScratchDir() + "/plate_ball_posed.json";
  const auto [posedCode, posedText] =
      RunInvmap("distance --a " + plate + " --b " + ball + " --pose-b 1,0,0,0,0,1,0,0,0,0,1,-4 -q -o " + posed);
  ASSERT_EQ(posedCode, 0) << posedText;
  EXPECT_NEAR(NumberAfter(ReadText(posed), "distance"), 2.5, 1e-8) << ReadText(posed);
}

TEST(CadDistanceCli, AllMinimaOfPointsOnAStepPlate) {
  const std::string plate = WritePlateStep();
  const std::string points = ScratchDir() + "/over_the_hole.xyz";
  // Over the hole, 0.5 off its axis: the rim's point (26, 15, 2), once.
  std::ofstream(points) << "20.5 15 5\n";
  const std::string output = ScratchDir() + "/minima.csv";
  std::filesystem::remove(output);
  const auto [code, text] =
      RunInvmap("invert --all-minima --max-distance 7 -g " + plate + " -p " + points + " -q -o " + output);
  ASSERT_EQ(code, 0) << text;
  std::ifstream in(output);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 2u) << ReadText(output);  // the header and one minimum
  const std::string expected = std::to_string(std::sqrt(5.5 * 5.5 + 9.0)).substr(0, 8);
  EXPECT_NE(rows[1].find(expected), std::string::npos) << rows[1];
}

}  // namespace
}  // namespace invmap::cadtest
