// CAD files through the command: good ones answer, bad ones (truncated
// STEP or IGES, files not of their format, STEP without shapes, IGES of curves only, BREP that is text
// garbage, models of curves only) exit 3 with a message naming the file
// and leave no output.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <TopoDS_Edge.hxx>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/cad/occ_reference.h"

namespace invmap::cadtest {
namespace {

struct CliRun {
  int exitCode = -1;
  std::string output;  ///< stdout and stderr together
};

CliRun RunCli(const std::string& arguments) {
  const std::string command = std::string(INVMAP_CLI_PATH) + " " + arguments + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) run.output += buffer;
  const int status = pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string WriteText(const std::string& name, const std::string& text) {
  const std::string path = ScratchDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string Sample(const char* path) { return std::string(INVMAP_OCC_SAMPLES) + "/" + path; }

/// A points file of a few points around the origin.
std::string PointsFile() { return WriteText("points.xyz", "0 0 0\n1 2 3\n-5 4 2\n"); }

/// Runs invert on a bad geometry: exit 3, a message naming the file and
/// `reason`, and no result file.
void ExpectRejected(const std::string& geometry, const std::string& reason) {
  const std::string output = ScratchDir() + "/rejected.csv";
  std::filesystem::remove(output);
  const CliRun run = RunCli("invert -g " + geometry + " -p " + PointsFile() + " -o " + output);
  EXPECT_EQ(run.exitCode, 3) << run.output;
  EXPECT_NE(run.output.find(geometry), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(reason), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(CadFiles, TruncatedStep) {
  std::ifstream in(Sample("step/screw.step"), std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  ExpectRejected(WriteText("truncated.step", text.substr(0, text.size() * 2 / 5)), "a truncated STEP file");
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

TEST(CadFiles, TruncatedStepWhoseFirstPartHoldsShapes) {
  // Cut after most of its faces: the reader gets a part of the model.
  const std::string text = ReadAll(Sample("step/screw.step"));
  ExpectRejected(WriteText("nearly_whole.step", text.substr(0, text.size() * 19 / 20)), "a truncated STEP file");
}

TEST(CadFiles, TruncatedAndGarbageIgesSayWhich) {
  const std::string text = ReadAll(Sample("iges/bearing.iges"));
  for (const double share : {0.05, 0.5, 0.95}) {
    const std::size_t cut = static_cast<std::size_t>(share * static_cast<double>(text.size()));
    ExpectRejected(WriteText("truncated.igs", text.substr(0, cut)), "a truncated IGES file");
  }
  std::string garbage(4000, '\0');
  for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<char>((i * 7919 + 13) % 251);
  ExpectRejected(WriteText("garbage.igs", garbage), "not an IGES file");
  ExpectRejected(WriteText("step_as.igs", ReadAll(Sample("step/screw.step"))), "not an IGES file");
  ExpectRejected(WriteText("iges_as.step", text), "not a STEP file");
}

TEST(CadFiles, StepWithoutShapes) {
  const std::string empty =
      "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('empty'),'2;1');\nFILE_NAME('empty.step','2024-01-01T00:00:00',"
      "(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
      "ENDSEC;\nEND-ISO-10303-21;\n";
  ExpectRejected(WriteText("empty.step", empty), "no shape");
}

TEST(CadFiles, IgesOfCurvesOnly) {
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 0);
  writer.AddShape(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(10, 0, 0)).Edge());
  writer.ComputeModel();
  const std::string path = ScratchDir() + "/curves.igs";
  ASSERT_TRUE(writer.Write(path.c_str()));
  ExpectRejected(path, "no faces");
}

TEST(CadFiles, BrepOfTextGarbage) {
  ExpectRejected(WriteText("garbage.brep", "this is not\na BREP file 12 34 {}\n"), "not an OpenCascade BREP file");
}

TEST(CadFiles, SampleModelsOfCurvesOnly) {
  ExpectRejected(Sample("occ/edge.brep"), "no faces");
  ExpectRejected(Sample("occ/asahi.brep"), "no faces");
}

TEST(CadFiles, MissingFile) { ExpectRejected(ScratchDir() + "/missing.step", "no such file"); }

TEST(CadFiles, StepAnswersAndInfoDescribesTheModel) {
  const std::string output = ScratchDir() + "/screw.csv";
  const CliRun run = RunCli("invert -g " + Sample("step/screw.step") + " -p " + PointsFile() + " -o " + output);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream in(output);
  std::string header, row;
  std::getline(in, header);
  EXPECT_EQ(header, "index,status,patch,cell,u,v,w,x,y,z,distance");
  int rows = 0;
  while (std::getline(in, row)) {
    EXPECT_NE(row.find(",found,"), std::string::npos) << row;
    ++rows;
  }
  EXPECT_EQ(rows, 3);
  const CliRun info = RunCli("info -g " + Sample("step/screw.step"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  for (const char* text : {"STEP", "faces       10", "cylinder", "torus", "cone", "edges", "vertices", "solids      1",
                           "approximated faces 0"}) {
    EXPECT_NE(info.output.find(text), std::string::npos) << text << " in\n" << info.output;
  }
}

TEST(CadFiles, EveryCommandReadingAGeometryReadsCad) {
  // generate points reads geometry through io's reader registry, where the
  // command registers the CAD readers; a bad CAD file is the same exit 3.
  const std::string points = ScratchDir() + "/around_screw.xyz";
  std::filesystem::remove(points);
  const CliRun run = RunCli("generate points -g " + Sample("step/screw.step") + " -n 50 --kind near -o " + points);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream in(points);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, 50);
  const std::string garbage = WriteText("garbage_for_generate.brep", "not a brep at all\n");
  const CliRun bad = RunCli("generate points -g " + garbage + " -n 5 -o " + ScratchDir() + "/none.xyz");
  EXPECT_EQ(bad.exitCode, 3) << bad.output;
  EXPECT_NE(bad.output.find(garbage), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(ScratchDir() + "/none.xyz"));
}

}  // namespace
}  // namespace invmap::cadtest

namespace invmap::cadtest {
namespace {

/// Reads a CSV result file's rows, split at commas.
std::vector<std::vector<std::string>> CsvRows(const std::string& path, std::string* header) {
  std::ifstream in(path);
  std::getline(in, *header);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.push_back("");
    rows.push_back(fields);
  }
  return rows;
}

TEST(CadSigned, SignedColumnAndDeviationSummary) {
  // The screw's points: its centre (inside) and points far outside.
  const std::string points = WriteText("screw_points.xyz", "-18 -1 -14\n0 0 0\n-40 0 0\n-18 -1 -13.9\n");
  const std::string output = ScratchDir() + "/screw_signed.csv";
  const CliRun run = RunCli("invert --signed --tolerance 0.1 -g " + Sample("step/screw.step") + " -p " + points +
                            " -o " + output);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  for (const char* text : {"deviation", "mean", "sigma", "outside", "inside", "within +-0.1"}) {
    EXPECT_NE(run.output.find(text), std::string::npos) << text << " in\n" << run.output;
  }
  std::string header;
  const auto rows = CsvRows(output, &header);
  EXPECT_EQ(header, "index,status,patch,cell,u,v,w,x,y,z,distance,signed_distance");
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 12u);
    EXPECT_EQ(std::abs(std::stod(row[11])), std::stod(row[10]));
  }
  // Every sign is the side OpenCascade's classifier gives.
  const TopoDS_Shape screw = ReadShape(Sample("step/screw.step"));
  BRepClass3d_SolidClassifier classifier(screw);
  const double xyz[4][3] = {{-18, -1, -14}, {0, 0, 0}, {-40, 0, 0}, {-18, -1, -13.9}};
  for (int i = 0; i < 4; ++i) {
    classifier.Perform(gp_Pnt(xyz[i][0], xyz[i][1], xyz[i][2]), 1e-9);
    EXPECT_EQ(std::stod(rows[i][11]) < 0.0, classifier.State() == TopAbs_IN) << "point " << i;
  }
  EXPECT_LT(std::stod(rows[0][11]), 0.0);
}

TEST(CadSigned, ColoursCentredOnZero) {
  const std::string points = WriteText("screw_points2.xyz", "-18 -1 -14\n0 0 0\n");
  const std::string output = ScratchDir() + "/screw_signed.ply";
  const CliRun run = RunCli("invert --signed --color -q -g " + Sample("step/screw.step") + " -p " + points + " -o " +
                            output);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream in(output, std::ios::binary);
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("property double signed_distance"), std::string::npos) << header;
  EXPECT_NE(header.find("cool-warm colormap of signed_distance from -"), std::string::npos) << header;
}

TEST(CadSigned, OpenShellsAndOtherGeometriesAreUsageErrors) {
  const std::string output = ScratchDir() + "/open_signed.csv";
  std::filesystem::remove(output);
  CliRun run = RunCli("invert --signed -g " + Sample("occ/face1.brep") + " -p " + PointsFile() + " -o " + output);
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("face 0"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(output));
  const std::string json = WriteText(
      "curve.json",
      R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [{"kind": "bezier", "cell": "line",
          "degrees": [1], "control_points": [[0, 0, 0], [1, 0, 0]]}]})");
  run = RunCli("invert --signed -g " + json + " -p " + PointsFile() + " -o " + output);
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("--signed needs a CAD model"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(CadSigned, TrimKeepsTheInsideAsNear) {
  // Inside the screw's body (deep), just outside and far outside.
  const std::string points = WriteText("trim_points.xyz", "-18 -1 -14\n-40 0 0\n");
  const std::string near = ScratchDir() + "/near.xyz", far = ScratchDir() + "/far.xyz";
  ASSERT_EQ(RunCli("trim --signed --max-distance 0.5 -q -g " + Sample("step/screw.step") + " -p " + points + " -o " +
                   near).exitCode,
            0);
  ASSERT_EQ(RunCli("trim --signed --max-distance 0.5 --keep far -q -g " + Sample("step/screw.step") + " -p " + points +
                   " -o " + far).exitCode,
            0);
  std::ifstream n(near), f(far);
  std::string nearText((std::istreambuf_iterator<char>(n)), {}), farText((std::istreambuf_iterator<char>(f)), {});
  EXPECT_EQ(nearText, "-18 -1 -14\n");
  EXPECT_EQ(farText, "-40 0 0\n");
}

}  // namespace
}  // namespace invmap::cadtest

namespace invmap::cadtest {
namespace {

std::string BundledBracket() { return std::string(INVMAP_SOURCE_DIR) + "/examples/data/bracket.step"; }

TEST(ScanToCad, BundledBracketIsTheGeneratorsPart) {
  const std::string generated = ScratchDir() + "/bracket.step";
  const CliRun run = RunCli("generate bracket -o " + generated);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(run.output, "");  // OpenCascade's writer reports nothing on stdout
  cad::LoadResult bundled = cad::Model::Load(BundledBracket()), fresh = cad::Model::Load(generated);
  ASSERT_EQ(bundled.error, "");
  ASSERT_EQ(fresh.error, "");
  const cad::ModelInfo info = bundled.model->Info();
  EXPECT_EQ(info.solids, 1u);
  EXPECT_EQ(info.faces, 24u);
  EXPECT_TRUE(info.openParts.empty());
  EXPECT_TRUE(info.approximatedFaces.empty());
  const std::vector<double> points = PointsAround(ReadShape(BundledBracket()), 500, 0.05, 0.2, 9);
  const Results a = InvertOnModel(*bundled.model, points), b = InvertOnModel(*fresh.model, points);
  EXPECT_EQ(a.distance, b.distance);
  EXPECT_EQ(a.patch, b.patch);
}

TEST(ScanToCad, ScanPointsLieOnTheModelWithoutNoiseAndWarp) {
  // A scan with no noise and no growth puts its points on the exact faces
  // (but for the 0.2 % outliers): invmap finds them at distance zero.
  const std::string scan = ScratchDir() + "/exact_scan.xyz";
  const CliRun run = RunCli("generate scan -g " + BundledBracket() + " -n 20000 --noise 0 --warp 0 --seed 3 -o " + scan);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::ifstream in(scan);
  std::vector<double> points;
  for (double x; in >> x;) points.push_back(x);
  ASSERT_EQ(points.size(), 3u * 20000);
  cad::LoadResult bracket = cad::Model::Load(BundledBracket());
  const Results results = InvertOnModel(*bracket.model, points);
  int onSurface = 0;
  for (double d : results.distance) onSurface += d <= 1e-9 * 108.0 ? 1 : 0;
  EXPECT_GE(onSurface, 20000 * 99 / 100);
}

TEST(ScanToCad, DemoPrintsTheDeviationSummary) {
  const std::string scan = ScratchDir() + "/demo_scan.ply", map = ScratchDir() + "/deviation.ply";
  ASSERT_EQ(RunCli("generate scan -g " + BundledBracket() + " -n 20000 -o " + scan).exitCode, 0);
  const CliRun run =
      RunCli("invert --signed --color --tolerance 0.05 -g " + BundledBracket() + " -p " + scan + " -o " + map);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  for (const char* text : {"points      20000 (found 20000", "deviation", "within +-0.05"}) {
    EXPECT_NE(run.output.find(text), std::string::npos) << text << " in\n" << run.output;
  }
  EXPECT_TRUE(std::filesystem::exists(map));
}

}  // namespace
}  // namespace invmap::cadtest
