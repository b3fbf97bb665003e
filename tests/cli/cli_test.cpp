// End-to-end tests of the invmap command: formats, exit codes, no partial
// output, thread-count invariance and trim, against analytic answers.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_fixture.h"

namespace {

namespace fs = std::filesystem;
using invmap::testing::CliTest;

/// The rows of a result CSV, split into fields (header excluded).
std::vector<std::vector<std::string>> CsvRows(const std::string& text, std::string* header) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, *header);
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::string field;
    std::istringstream fieldsIn(line);
    while (std::getline(fieldsIn, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.push_back("");
    rows.push_back(fields);
  }
  return rows;
}

/// Distance from p to the torus of radii R = 2, r = 0.7 around z (`generate torus`).
double TorusDistance(double x, double y, double z) {
  return std::abs(std::sqrt(std::pow(std::sqrt(x * x + y * y) - 2.0, 2) + z * z) - 0.7);
}

TEST_F(CliTest, InvertMatchesTheTorusExactlyInEveryOutputFormat) {
  ASSERT_EQ(Run("generate torus -o " + Path("torus.json")), 0);
  // Independent points: a fixed grid around the torus.
  std::ostringstream points;
  points.precision(17);
  std::vector<std::array<double, 3>> queries;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) {
      const std::array<double, 3> q{-3.3 + 0.6 * i, -3.2 + 0.55 * j, 0.37 * std::sin(1.0 * i + j)};
      queries.push_back(q);
      points << q[0] << ' ' << q[1] << ' ' << q[2] << '\n';
    }
  }
  WriteFile("points.xyz", points.str());
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("out.csv") + " -q"), 0);
  std::string header;
  const auto rows = CsvRows(ReadFile(Path("out.csv")), &header);
  EXPECT_EQ(header, "index,status,patch,cell,u,v,w,x,y,z,distance");
  ASSERT_EQ(rows.size(), queries.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 11u);
    EXPECT_EQ(rows[i][0], std::to_string(i));
    EXPECT_EQ(rows[i][1], "found");
    EXPECT_EQ(rows[i][6], "");  // w unused on a surface
    const double distance = std::stod(rows[i][10]);
    EXPECT_NEAR(distance, TorusDistance(queries[i][0], queries[i][1], queries[i][2]), 1e-9) << "row " << i;
    // The closest point is at that distance from the query.
    const double dx = std::stod(rows[i][7]) - queries[i][0], dy = std::stod(rows[i][8]) - queries[i][1],
                 dz = std::stod(rows[i][9]) - queries[i][2];
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), distance, 1e-12);
  }
  // The binary formats carry the same values.
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("out.npy") + " -q"), 0);
  const std::string npy = ReadFile(Path("out.npy"));
  ASSERT_GT(npy.size(), 128u);
  const std::size_t headerLength = static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8);
  ASSERT_EQ(npy.size(), 10 + headerLength + queries.size() * 11 * 8);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    double row[11];
    std::memcpy(row, npy.data() + 10 + headerLength + i * 88, 88);
    EXPECT_EQ(row[0], static_cast<double>(i));
    EXPECT_EQ(row[1], 0.0);  // found
    EXPECT_EQ(row[10], std::stod(rows[i][10]));
  }
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("out.ply") + " -q"), 0);
  EXPECT_EQ(ReadFile(Path("out.ply")).rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
}

TEST_F(CliTest, PointFormatsGiveTheSameResults) {
  ASSERT_EQ(Run("generate surface --spans 8 -o " + Path("s.json")), 0);
  std::string reference;
  for (const char* ext : {"xyz", "csv", "npy", "ply"}) {
    const std::string pts = Path(std::string("p.") + ext);
    ASSERT_EQ(Run("generate points -g " + Path("s.json") + " -n 500 --seed 3 -o " + pts), 0) << ext;
    ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + pts + " -o " + Path("r.csv") + " -q"), 0) << ext;
    const std::string result = ReadFile(Path("r.csv"));
    if (reference.empty()) {
      reference = result;
    } else {
      EXPECT_EQ(result, reference) << ext;
    }
  }
}

TEST_F(CliTest, ResultsDoNotDependOnTheThreadCount) {
  ASSERT_EQ(Run("generate surface --spans 16 -o " + Path("s.json")), 0);
  ASSERT_EQ(Run("generate points -g " + Path("s.json") + " -n 20000 --kind far -o " + Path("p.npy")), 0);
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.npy") + " -o " + Path("one.csv") + " --threads 1 -q"), 0);
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.npy") + " -o " + Path("two.csv") + " --threads 2 -q"), 0);
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.npy") + " -o " + Path("all.csv") + " -q"), 0);
  const std::string one = ReadFile(Path("one.csv"));
  EXPECT_EQ(one, ReadFile(Path("two.csv")));
  EXPECT_EQ(one, ReadFile(Path("all.csv")));
  // More threads than cores: the same results and nothing on stderr (no
  // raw library warning), even without --quiet's silence.
  for (const char* threads : {"3", "7", "64"}) {
    std::string log;
    ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.npy") + " -o " + Path("many.csv") + " --threads " +
                  threads + " -q", &log),
              0);
    EXPECT_EQ(log, "") << "--threads " << threads;
    EXPECT_EQ(ReadFile(Path("many.csv")), one) << "--threads " << threads;
  }
}

TEST_F(CliTest, PointwiseAnswersDoNotDependOnTheOtherPoints) {
  // The same points inverted all together and in two halves: with
  // --pointwise every row is the same, bit for bit (row indices aside).
  ASSERT_EQ(Run("generate surface --spans 16 -o " + Path("s.json")), 0);
  ASSERT_EQ(Run("generate points -g " + Path("s.json") + " -n 4000 --kind near --spread 0.05 -o " + Path("p.xyz")), 0);
  const std::string all = ReadFile(Path("p.xyz"));
  std::size_t half = 0;
  for (int line = 0; line < 1700; ++line) half = all.find('\n', half) + 1;
  WriteFile("a.xyz", all.substr(0, half));
  WriteFile("b.xyz", all.substr(half));
  for (const char* name : {"p", "a", "b"}) {
    ASSERT_EQ(Run("invert --pointwise -g " + Path("s.json") + " -p " + Path(std::string(name) + ".xyz") + " -o " +
                  Path(std::string(name) + ".csv") + " -q"),
              0);
  }
  std::string header;
  const auto whole = CsvRows(ReadFile(Path("p.csv")), &header);
  auto parts = CsvRows(ReadFile(Path("a.csv")), &header);
  const auto second = CsvRows(ReadFile(Path("b.csv")), &header);
  parts.insert(parts.end(), second.begin(), second.end());
  ASSERT_EQ(parts.size(), whole.size());
  int differ = 0;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    differ += !std::equal(whole[i].begin() + 1, whole[i].end(), parts[i].begin() + 1, parts[i].end());
  }
  EXPECT_EQ(differ, 0);
  // And the answers are those of the default search, to its tolerance.
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("default.csv") + " -q"), 0);
  const auto usual = CsvRows(ReadFile(Path("default.csv")), &header);
  ASSERT_EQ(usual.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(usual[i][1], whole[i][1]);
    EXPECT_NEAR(std::stod(usual[i][10]), std::stod(whole[i][10]), 1e-12) << "row " << i;
  }
}

TEST_F(CliTest, TrimKeepsPassedThroughAttributesInInputOrder) {
  // A unit-square quad in z = 0: the distance of a point is |z| when x, y are inside.
  WriteFile("square.json",
            R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
                 {"kind": "mesh", "cell": "quad", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "cells": [[0,1,2,3]]}]})");
  WriteFile("scan.csv",
            "x,y,z,intensity,label\n"
            "0.5,0.5,0.01,17,a\n"
            "0.2,0.3,0.5,18,b\n"
            "0.9,0.1,-0.02,19,c\n"
            "nan,0.1,0.0,20,d\n"
            "0.4,0.4,-0.3,21,e\n");
  ASSERT_EQ(Run("trim -g " + Path("square.json") + " -p " + Path("scan.csv") + " -o " + Path("near.csv") +
                " --max-distance 0.05 -q"),
            0);
  EXPECT_EQ(ReadFile(Path("near.csv")), "x,y,z,intensity,label\n0.5,0.5,0.01,17,a\n0.9,0.1,-0.02,19,c\n");
  ASSERT_EQ(Run("trim -g " + Path("square.json") + " -p " + Path("scan.csv") + " -o " + Path("far.csv") +
                " --max-distance 0.05 --keep far -q"),
            0);
  EXPECT_EQ(ReadFile(Path("far.csv")), "x,y,z,intensity,label\n0.2,0.3,0.5,18,b\n0.4,0.4,-0.3,21,e\n");
}

TEST_F(CliTest, GapToleranceAndInvalidPoints) {
  WriteFile("square.json",
            R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
                 {"kind": "mesh", "cell": "tri", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "cells": [[0,1,2]]}]})");
  WriteFile("p.xyz", "0.2 0.2 0.1\n0.2 0.2 5\ninf 0 0\n");
  ASSERT_EQ(Run("invert -g " + Path("square.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv") +
                " --max-distance 1 -q"),
            0);
  std::string header;
  const auto rows = CsvRows(ReadFile(Path("r.csv")), &header);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][1], "found");
  EXPECT_EQ(rows[0][2], "0");
  EXPECT_EQ(rows[0][3], "0");
  EXPECT_NEAR(std::stod(rows[0][4]), 0.2, 1e-15);  // u = the reference coordinate of vertex 1
  EXPECT_NEAR(std::stod(rows[0][5]), 0.2, 1e-15);
  EXPECT_NEAR(std::stod(rows[0][10]), 0.1, 1e-15);
  EXPECT_EQ(rows[1][1], "none");
  EXPECT_EQ(rows[1][2], "-1");
  EXPECT_EQ(rows[2][1], "invalid");
}

TEST_F(CliTest, ExitCodesAndNoPartialOutput) {
  ASSERT_EQ(Run("generate surface --spans 4 -o " + Path("s.json")), 0);
  WriteFile("p.xyz", "0.1 0.2 0.3\n0.4 0.5 0.6\n");
  std::string log;
  // Usage errors: 2.
  EXPECT_EQ(Run("invert -g " + Path("s.json"), &log), 2);
  EXPECT_EQ(Run("frobnicate", &log), 2);
  EXPECT_NE(log.find("unknown command 'frobnicate' (commands: invert, trim, info, generate, grid, manifold, probe, distance)"),
            std::string::npos)
      << log;
  EXPECT_EQ(Run("trim -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("t.xyz"), &log), 2)
      << "trim needs --max-distance";
  // A negative or non-numeric option value: named in a short message.
  for (const std::string value : {"-1", "abc", "nan"}) {
    EXPECT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv") +
                      " --max-distance " + value,
                  &log),
              2);
    EXPECT_NE(log.find("'" + value + "' is not a number >= 0"), std::string::npos) << log;
    EXPECT_LT(log.size(), 200u) << log;
  }
  // Missing and malformed input: 3, with the file (and line) named, no output.
  EXPECT_EQ(Run("invert -g " + Path("missing.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv"), &log), 3);
  EXPECT_NE(log.find("missing.json"), std::string::npos) << log;
  WriteFile("bad.json", "{\"format\": \"invmap-geometry\", \"version\": 1,\n \"dimension\": 3,\n \"patches\": [ {\"kind\": \"blob\"} ]}\n");
  EXPECT_EQ(Run("invert -g " + Path("bad.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv"), &log), 3);
  EXPECT_NE(log.find("bad.json:3"), std::string::npos) << log;
  // A problem the build finds (Manifold::Build validates every geometry):
  // named at the file and line of the value at fault, no output.
  WriteFile("knots.json",
            "{\"format\": \"invmap-geometry\", \"version\": 1, \"dimension\": 3, \"patches\": [\n"
            " {\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [3],\n"
            "  \"knots\": [[0, 0, 0.6,\n 0.5, 1]],\n"
            "  \"control_points\": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}]}\n");
  EXPECT_EQ(Run("invert -g " + Path("knots.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv"), &log), 3);
  EXPECT_NE(log.find("knots.json:4: patches[0].knots[0]: decreasing at index 3 (0.6 > 0.5)"), std::string::npos)
      << log;
  WriteFile("badpoints.xyz", "0.1 0.2 0.3\n0.4 zero 0.6\n");
  EXPECT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("badpoints.xyz") + " -o " + Path("r.csv"), &log), 3);
  EXPECT_NE(log.find("badpoints.xyz:2"), std::string::npos) << log;
  EXPECT_EQ(Run("invert -g " + Path("s.json") + " -p " + dir_.string() + " -o " + Path("r.csv"), &log), 3);
  EXPECT_FALSE(fs::exists(Path("r.csv")));
  // Unwritable output: 4, nothing left behind.
  EXPECT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("no/such/dir/r.csv"), &log), 4);
  // A directory listing shows only the files this test wrote (no temporaries).
  for (const auto& entry : fs::directory_iterator(dir_)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "s.json" || name == "p.xyz" || name == "bad.json" || name == "knots.json" ||
                name == "badpoints.xyz" || name == "run.log")
        << "left behind: " << name;
  }
}

TEST_F(CliTest, AnUnknownOutputExtensionIsAUsageErrorFoundBeforeAnyInputIsRead) {
  // The geometry is unreadable: the extension must be refused before it is read.
  WriteFile("bad.json", "{ not json");
  WriteFile("p.xyz", "0.1 0.2 0.3\n");
  std::string log;
  EXPECT_EQ(Run("invert -g " + Path("bad.json") + " -p " + Path("p.xyz") + " -o " + Path("r.xyzq"), &log), 2) << log;
  EXPECT_NE(log.find("unknown result file extension '.xyzq' (expected .csv, .ply or .npy)"), std::string::npos) << log;
  // trim writes the points' own format.
  EXPECT_EQ(Run("trim -g " + Path("bad.json") + " -p " + Path("p.xyz") + " -o " + Path("t.ply") + " --max-distance 1",
                &log),
            2)
      << log;
  EXPECT_NE(log.find("trim writes the points' own format"), std::string::npos) << log;
  // An unknown point format is found before the geometry is read too (exit 3: an input problem).
  EXPECT_EQ(Run("invert -g " + Path("bad.json") + " -p " + Path("p.dat") + " -o " + Path("r.csv"), &log), 3) << log;
  EXPECT_NE(log.find("p.dat: unknown point file extension"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(Path("r.xyzq")));
  EXPECT_FALSE(fs::exists(Path("t.ply")));
}

TEST_F(CliTest, AnOutputOverAnInputIsRefusedByAnyPathBeforeAnythingIsRead) {
  ASSERT_EQ(Run("generate surface --spans 4 -o " + Path("s.json")), 0);
  const std::string points = "0.1 0.2 0.3\n0.4 0.5 0.6\n";
  WriteFile("p.xyz", points);
  const std::string geometry = ReadFile(Path("s.json"));
  fs::create_symlink(Path("p.xyz"), Path("link.xyz"));
  fs::create_hard_link(Path("p.xyz"), Path("hard.xyz"));
  fs::create_directories(Path("sub"));
  const std::string g = " -g " + Path("s.json");
  const std::string p = " -p " + Path("p.xyz");
  std::string log;
  for (const std::string& output :
       {Path("p.xyz"), Path("sub/../p.xyz"), Path("link.xyz"), Path("hard.xyz"), Path("s.json")}) {
    SCOPED_TRACE(output);
    EXPECT_EQ(Run("invert" + g + p + " -o " + output + " -q", &log), 2) << log;
    EXPECT_NE(log.find("writing it would destroy the input"), std::string::npos) << log;
    EXPECT_EQ(Run("trim" + g + p + " -o " + output + " --max-distance 1 -q", &log), 2) << log;
  }
  EXPECT_EQ(Run("generate points" + g + " -o " + Path("s.json"), &log), 2) << log;
  // A PLY mesh geometry as the output of its own points' inversion.
  ASSERT_EQ(Run("generate trimesh --triangles 20 -o " + Path("m.ply")), 0);
  const std::string mesh = ReadFile(Path("m.ply"));
  EXPECT_EQ(Run("invert -g " + Path("m.ply") + p + " -o " + Path("m.ply"), &log), 2) << log;
  EXPECT_EQ(ReadFile(Path("p.xyz")), points);
  EXPECT_EQ(ReadFile(Path("s.json")), geometry);
  EXPECT_EQ(ReadFile(Path("m.ply")), mesh);
  EXPECT_TRUE(fs::is_symlink(Path("link.xyz")));
}

TEST_F(CliTest, OptionsThatWouldBeIgnoredAreUsageErrors) {
  ASSERT_EQ(Run("generate surface --spans 2 -o " + Path("s.json")), 0);
  WriteFile("p.xyz", "0.1 0.2 0.3\n");
  const std::string run = "invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -q";
  std::string log;
  // --color colours .ply output only.
  EXPECT_EQ(Run(run + " --color -o " + Path("r.csv"), &log), 2) << log;
  EXPECT_NE(log.find("--color"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(Path("r.csv")));
  // --tolerance is a figure of the signed deviation summary.
  EXPECT_EQ(Run(run + " --tolerance 0.1 -o " + Path("r.csv"), &log), 2) << log;
  EXPECT_NE(log.find("--tolerance"), std::string::npos) << log;
  // The all-minima rows carry no sign and no colour.
  EXPECT_EQ(Run(run + " --all-minima --signed -o " + Path("r.csv"), &log), 2) << log;
  EXPECT_EQ(Run(run + " --all-minima --color -o " + Path("r.csv"), &log), 2) << log;
  EXPECT_FALSE(fs::exists(Path("r.csv")));
  // A point file holds at least one point: generate writes none only as a usage error.
  EXPECT_EQ(Run("generate points -g " + Path("s.json") + " -n 0 -o " + Path("none.xyz"), &log), 2) << log;
  EXPECT_FALSE(fs::exists(Path("none.xyz")));
  // Parse errors read like every other message of the command.
  EXPECT_EQ(Run(run + " -o " + Path("r.csv") + " --threads 99999999999999999999", &log), 2) << log;
  EXPECT_EQ(log.rfind("invmap: ", 0), 0u) << log;
  // A bad number is named as given with its range in words (CLI11's own
  // checks printed the largest double in full).
  for (const std::string value : {"-1", "abc"}) {
    EXPECT_EQ(Run(run + " -o " + Path("r.csv") + " --max-distance " + value, &log), 2) << log;
    EXPECT_NE(log.find("--max-distance: '" + value + "' is not a number >= 0"), std::string::npos) << log;
    EXPECT_LT(log.size(), 200u) << log;
  }
}

TEST_F(CliTest, GenerateWritesOnlyFilesNamedForTheirFormat) {
  // A sample's output must carry its format's extension: a gmsh mesh named
  // .json would be read back as a geometry file and fail there.
  std::string log;
  const struct {
    const char* command;
    const char* wrong;
    const char* right;
  } cases[] = {{"generate tets --resolution 1", "t.json", "t.msh"},
               {"generate trimesh --triangles 20", "m.json", "m.ply"},
               {"generate surface --spans 2", "s.msh", "s.json"},
               {"generate torus", "t.ply", "torus.json"},
               {"generate curve", "c.obj", "c.json"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command);
    EXPECT_EQ(Run(std::string(c.command) + " -o " + Path(c.wrong), &log), 2) << log;
    EXPECT_NE(log.find("--output " + Path(c.wrong) + ": generate"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(Path(c.wrong)));
    ASSERT_EQ(Run(std::string(c.command) + " -o " + Path(c.right), &log), 0) << log;
    EXPECT_EQ(Run("info -g " + Path(c.right), &log), 0) << log;
  }
}

TEST_F(CliTest, AnOutputThroughASymbolicLinkIsWrittenToItsTarget) {
  ASSERT_EQ(Run("generate surface --spans 4 -o " + Path("s.json")), 0);
  WriteFile("p.xyz", "0.1 0.2 0.3\n0.4 0.5 0.6\n");
  fs::create_directories(Path("results"));
  WriteFile("results/old.csv", "old results\n");
  fs::create_symlink("results/old.csv", Path("latest.csv"));  // relative to the link's directory
  fs::create_symlink(Path("results/new.csv"), Path("dangling.csv"));
  fs::create_symlink(Path("latest.csv"), Path("chain.csv"));
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("latest.csv") + " -q"), 0);
  EXPECT_TRUE(fs::is_symlink(Path("latest.csv")));
  EXPECT_EQ(ReadFile(Path("results/old.csv")).rfind("index,status,", 0), 0u);
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("dangling.csv") + " -q"), 0);
  EXPECT_TRUE(fs::is_symlink(Path("dangling.csv")));
  EXPECT_EQ(ReadFile(Path("results/new.csv")).rfind("index,status,", 0), 0u);
  // A link to a link reaches the same file; the results are the same.
  fs::remove(Path("results/old.csv"));
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("chain.csv") + " -q"), 0);
  EXPECT_TRUE(fs::is_symlink(Path("chain.csv")));
  EXPECT_EQ(ReadFile(Path("results/old.csv")), ReadFile(Path("results/new.csv")));
  // A loop of links is an unwritable output.
  fs::create_symlink(Path("loop2.csv"), Path("loop1.csv"));
  fs::create_symlink(Path("loop1.csv"), Path("loop2.csv"));
  std::string log;
  EXPECT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -o " + Path("loop1.csv") + " -q", &log), 4)
      << log;
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_NE(entry.path().filename().string()[0], '.') << "left behind: " << entry.path();
  }
}

TEST_F(CliTest, AnOutputReplacedKeepsItsPermissionsAndOnlyRegularWritableFilesAreReplaced) {
  ASSERT_EQ(Run("generate surface --spans 4 -o " + Path("s.json")), 0);
  WriteFile("p.xyz", "0.1 0.2 0.3\n");
  const std::string invert = "invert -g " + Path("s.json") + " -p " + Path("p.xyz") + " -q -o ";
  // A private output stays private.
  WriteFile("private.csv", "secret\n");
  fs::permissions(Path("private.csv"), fs::perms::owner_read | fs::perms::owner_write);
  ASSERT_EQ(Run(invert + Path("private.csv")), 0);
  EXPECT_EQ(fs::status(Path("private.csv")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(ReadFile(Path("private.csv")).rfind("index,status,", 0), 0u);
  // A pipe is not replaced by a plain file (its reader would wait forever).
  ASSERT_EQ(::mkfifo(Path("pipe.csv").c_str(), 0644), 0);
  std::string log;
  EXPECT_EQ(Run(invert + Path("pipe.csv"), &log), 4) << log;
  EXPECT_NE(log.find("not a regular file"), std::string::npos) << log;
  EXPECT_TRUE(fs::is_fifo(Path("pipe.csv")));
  // A read-only output is not replaced (root may write it, as with cp).
  WriteFile("readonly.csv", "old\n");
  fs::permissions(Path("readonly.csv"), fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  if (::geteuid() != 0) {
    EXPECT_EQ(Run(invert + Path("readonly.csv"), &log), 4) << log;
    EXPECT_EQ(ReadFile(Path("readonly.csv")), "old\n");
  } else {
    ASSERT_EQ(Run(invert + Path("readonly.csv")), 0);
    EXPECT_EQ(fs::status(Path("readonly.csv")).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  }
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_NE(entry.path().filename().string()[0], '.') << "left behind: " << entry.path();
  }
}

/// Names in `dir` that start with a dot: the hidden temporary outputs.
std::vector<std::string> HiddenFiles(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name[0] == '.') names.push_back(name);
  }
  return names;
}

TEST_F(CliTest, ASignalDuringAnInversionRemovesItsTemporaryOutput) {
  ASSERT_EQ(Run("generate surface --spans 16 -o " + Path("s.json")), 0);
  // Five chunks of 2^18 points take seconds: the signal comes while they are solved.
  ASSERT_EQ(Run("generate points -g " + Path("s.json") + " -n 1100000 -o " + Path("p.npy")), 0);
  for (const int signo : {SIGINT, SIGTERM, SIGHUP}) {
    SCOPED_TRACE(signo);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::freopen("/dev/null", "w", stdout);
      std::freopen("/dev/null", "w", stderr);
      execl(INVMAP_CLI_PATH, INVMAP_CLI_PATH, "invert", "-g", Path("s.json").c_str(), "-p", Path("p.npy").c_str(), "-o",
            Path("r.csv").c_str(), "--threads", "1", static_cast<char*>(nullptr));
      _exit(127);
    }
    // Until the temporary output exists (polling; no time limit matters here).
    for (int i = 0; i < 60000 && HiddenFiles(dir_).empty(); ++i) usleep(1000);
    ASSERT_EQ(HiddenFiles(dir_).size(), 1u);
    kill(pid, signo);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    // Ended by the signal itself, as the shell expects (it reports 128 + signo).
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), signo);
    EXPECT_TRUE(HiddenFiles(dir_).empty()) << HiddenFiles(dir_)[0];
    EXPECT_FALSE(fs::exists(Path("r.csv")));
  }
}

TEST_F(CliTest, TrimWritesAPlainPlyVertexCount) {
  ASSERT_EQ(Run("generate surface --spans 4 -o " + Path("s.json")), 0);
  ASSERT_EQ(Run("generate points -g " + Path("s.json") + " -n 10 --kind far -o " + Path("p.ply")), 0);
  for (const char* keep : {"near", "far"}) {
    SCOPED_TRACE(keep);
    ASSERT_EQ(Run("trim -g " + Path("s.json") + " -p " + Path("p.ply") + " -o " + Path("t.ply") +
                  " --max-distance 1e300 -q --keep " + keep),
              0);
    const std::string text = ReadFile(Path("t.ply"));
    const std::string count = std::string(keep) == "near" ? "10" : "0";
    EXPECT_NE(text.find("\nelement vertex " + count + "\n"), std::string::npos) << text.substr(0, 200);
    // Trimming the trimmed file keeps one padding comment, not two.
    ASSERT_EQ(Run("trim -g " + Path("s.json") + " -p " + Path("t.ply") + " -o " + Path("t2.ply") +
                  " --max-distance 1e300 -q --keep " + keep),
              0);
    const std::string again = ReadFile(Path("t2.ply"));
    EXPECT_EQ(again, text);
  }
  ASSERT_EQ(Run("invert -g " + Path("s.json") + " -p " + Path("p.ply") + " -o " + Path("r.ply") + " -q"), 0);
  EXPECT_NE(ReadFile(Path("r.ply")).find("\nelement vertex 10\n"), std::string::npos);
}

TEST_F(CliTest, EndlessAndHugeSparseGeometryFilesFailFast) {
  std::string log;
  for (const char* ext : {"json", "stl", "obj", "off"}) {
    SCOPED_TRACE(ext);
    const std::string zero = Path(std::string("z.") + ext);
    fs::create_symlink("/dev/zero", zero);
    EXPECT_EQ(Run("info -g " + zero, &log), 3) << log;
    EXPECT_NE(log.find(zero + ":"), std::string::npos) << log;
    EXPECT_LT(log.size(), 300u) << log;
  }
  // Sparse files: gigabytes that cost no disk.
  const std::pair<const char*, std::uintmax_t> sparse[] = {
      {"big.stl", std::uintmax_t{6} << 30}, {"big.json", std::uintmax_t{2} << 30}, {"big.obj", std::uintmax_t{2} << 30}};
  for (const auto& [name, size] : sparse) {
    SCOPED_TRACE(name);
    WriteFile(name, "");
    fs::resize_file(Path(name), size);
    EXPECT_EQ(Run("info -g " + Path(name), &log), 3) << log;
  }
  EXPECT_NE(log.find("line longer than 64 MiB"), std::string::npos) << log;
}

TEST_F(CliTest, AHugeDegenerateObjFaceCostsWhatItsDistinctTrianglesCost) {
  // One face of 3 million indices of three vertices: one triangle.
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (int i = 0; i < 1000000; ++i) text += " 1 2 3";
  WriteFile("fan.obj", text + "\n");
  std::string log;
  ASSERT_EQ(Run("info -g " + Path("fan.obj"), &log), 0) << log;
  EXPECT_NE(log.find("cells       1\n"), std::string::npos) << log;
}

TEST_F(CliTest, AnObjCoordinateOutsideTheRangeNamesItsLine) {
  WriteFile("far.obj", "v 0 0 0\nv 1 0 0\nv 0 1e300 0\nf 1 2 3\n");
  std::string log;
  EXPECT_EQ(Run("info -g " + Path("far.obj"), &log), 3) << log;
  EXPECT_NE(log.find("far.obj:3: v: coordinate 1: \"1e300\" is outside [-1e100, 1e100]"), std::string::npos) << log;
}

TEST_F(CliTest, AnEmptyOrTooSmallGeometryIsAnInputError) {
  WriteFile("p.xyz", "0 0 0\n");
  WriteFile("empty.json", R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": []})");
  // A triangle 1e-280 across, with a point 5e-281 from it.
  WriteFile("tiny.json", R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
               {"kind": "mesh", "cell": "tri", "vertices": [[0,0,0],[1e-280,0,0],[0,1e-280,0]], "cells": [[0,1,2]]}]})");
  WriteFile("q.xyz", "0 0 5e-281\n");
  std::string log;
  EXPECT_EQ(Run("invert -g " + Path("empty.json") + " -p " + Path("p.xyz") + " -o " + Path("r.csv"), &log), 3) << log;
  EXPECT_NE(log.find("empty.json: the geometry has no cells"), std::string::npos) << log;
  EXPECT_EQ(Run("invert -g " + Path("tiny.json") + " -p " + Path("q.xyz") + " -o " + Path("r.csv"), &log), 3) << log;
  EXPECT_NE(log.find("tiny.json: the geometry is 1.41421e-280 across (its box diagonal), below 1e-100"),
            std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(Path("r.csv")));
}

TEST_F(CliTest, MeshFilesWhoseHeaderCountsLieAreInputErrors) {
  // Fewer faces declared than the file holds (the rest would be dropped
  // unseen), or more than it holds: exit 3 naming the file and line, no output.
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face FACES\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n";
  const auto withFaces = [&](const char* faces) {
    std::string text = ply;
    text.replace(text.find("FACES"), 5, faces);
    return text;
  };
  WriteFile("few.ply", withFaces("1"));
  WriteFile("many.ply", withFaces("3"));
  WriteFile("few.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n");
  WriteFile("p.xyz", "0.2 0.2 1\n");
  const std::pair<const char*, const char*> cases[] = {
      {"few.ply", "few.ply:14: data after the last record"},
      {"many.ply", "many.ply:15: the file ends in 'face' record 2 of 3"},
      {"few.off", "few.off:7: data after the last of the 1 faces the header declares"}};
  for (const auto& [file, message] : cases) {
    std::string log;
    EXPECT_EQ(Run("invert -g " + Path(file) + " -p " + Path("p.xyz") + " -o " + Path("r.csv"), &log), 3) << log;
    EXPECT_NE(log.find(message), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(Path("r.csv")));
  }
  // The same two faces declared: read, built (the mesh handed over) and
  // answered; the point is 1 above the face.
  WriteFile("two.ply", withFaces("2"));
  ASSERT_EQ(Run("invert -q -g " + Path("two.ply") + " -p " + Path("p.xyz") + " -o " + Path("r.csv")), 0);
  std::string header;
  const auto rows = CsvRows(ReadFile(Path("r.csv")), &header);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][1], "found");
  EXPECT_EQ(std::stod(rows[0][10]), 1.0);
}

TEST_F(CliTest, GapToleranceZeroFindsEveryPointInsideAndTrimKeepsThemNear) {
  // QA: 14 of 100,000 inside points of curved tets came back none at
  // --max-distance 0, and trim --keep far output them.
  ASSERT_EQ(Run("generate tets --resolution 2 -o " + Path("solid.msh")), 0);
  ASSERT_EQ(Run("generate points -g " + Path("solid.msh") + " --kind inside -n 20000 -o " + Path("in.xyz")), 0);
  for (const char* gap : {"0", "1e-15"}) {
    SCOPED_TRACE(gap);
    const std::string common = " -g " + Path("solid.msh") + " -p " + Path("in.xyz") + " --max-distance " + gap + " -q";
    ASSERT_EQ(Run("invert" + common + " -o " + Path("r.csv")), 0);
    std::string header;
    const auto rows = CsvRows(ReadFile(Path("r.csv")), &header);
    ASSERT_EQ(rows.size(), 20000u);
    int notAtZero = 0;
    for (const auto& row : rows) notAtZero += !(row[1] == "found" && row[10] == "0");
    EXPECT_EQ(notAtZero, 0);
    ASSERT_EQ(Run("trim" + common + " --keep far -o " + Path("far.xyz")), 0);
    EXPECT_EQ(ReadFile(Path("far.xyz")), "");
    ASSERT_EQ(Run("trim" + common + " --keep near -o " + Path("near.xyz")), 0);
    EXPECT_EQ(ReadFile(Path("near.xyz")), ReadFile(Path("in.xyz")));
  }
}

TEST_F(CliTest, GenerateTrimeshWritesAClosedOutwardMesh) {
  // Streamed vertex by vertex and triangle by triangle (vertices of shared
  // edges shared by index): every edge has exactly two triangles, running
  // it in opposite directions, and the normals point outward.
  ASSERT_EQ(Run("generate trimesh --triangles 1000 -o " + Path("m.ply")), 0);
  const std::string bytes = ReadFile(Path("m.ply"));
  const std::size_t body = bytes.find("end_header\n") + 11;
  ASSERT_NE(bytes.find("element vertex 642\n"), std::string::npos);
  ASSERT_NE(bytes.find("element face 1280\n"), std::string::npos);
  std::vector<std::array<double, 3>> vertices(642);
  std::memcpy(vertices.data(), bytes.data() + body, 642 * 24);
  std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
  int inward = 0;
  for (int t = 0; t < 1280; ++t) {
    std::int32_t v[3];
    ASSERT_EQ(bytes[body + 642 * 24 + 13 * t], 3);
    std::memcpy(v, bytes.data() + body + 642 * 24 + 13 * t + 1, 12);
    for (int e = 0; e < 3; ++e) ++edges[{v[e], v[(e + 1) % 3]}];
    const auto& a = vertices[v[0]];
    const auto& b = vertices[v[1]];
    const auto& c = vertices[v[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double normal[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    inward += normal[0] * (a[0] + b[0] + c[0]) + normal[1] * (a[1] + b[1] + c[1]) + normal[2] * (a[2] + b[2] + c[2]) <= 0;
  }
  EXPECT_EQ(inward, 0);
  EXPECT_EQ(edges.size(), 3u * 1280u);
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
}

TEST_F(CliTest, InfoDescribesTheGeometry) {
  ASSERT_EQ(Run("generate surface --spans 8 -o " + Path("s.json")), 0);
  std::string log;
  ASSERT_EQ(Run("info -g " + Path("s.json"), &log), 0);
  // 8 x 8 spans plus the crease's extra span boundary: the surface has 8 x 8 cells.
  EXPECT_NE(log.find("cells       64"), std::string::npos) << log;
  EXPECT_NE(log.find("quad 3x3"), std::string::npos) << log;
  EXPECT_NE(log.find("dimension   3"), std::string::npos) << log;
}

TEST_F(CliTest, QuadraticTetMeshPointsInsideAreFoundAtDistanceZero) {
  ASSERT_EQ(Run("generate tets --resolution 3 -o " + Path("solid.msh")), 0);
  ASSERT_EQ(Run("generate points -g " + Path("solid.msh") + " --kind inside -n 2000 -o " + Path("in.npy")), 0);
  ASSERT_EQ(Run("invert -g " + Path("solid.msh") + " -p " + Path("in.npy") + " -o " + Path("r.csv") + " -q"), 0);
  std::string header;
  const auto rows = CsvRows(ReadFile(Path("r.csv")), &header);
  ASSERT_EQ(rows.size(), 2000u);
  for (const auto& row : rows) {
    EXPECT_EQ(row[1], "found");
    EXPECT_LT(std::stod(row[10]), 1e-9);
    EXPECT_NE(row[6], "");  // a volume reports w
  }
}

}  // namespace

// --- invmap grid ------------------------------------------------------------

const char kSphereFunction[] = R"([{"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.3}])";

TEST_F(CliTest, GridWritesEveryOutputAndItsSurfaceFeedsInvert) {
  WriteFile("sphere.json", kSphereFunction);
  std::string out;
  ASSERT_EQ(Run("grid -f " + Path("sphere.json") + " --box 0,0,0,1,1,1 --resolution 2 --epsilon 1e-3 -o " +
                    Path("grid"),
                &out),
            0)
      << out;
  for (const char* name : {"grid.msh", "grid.vtu", "zero_sets.obj", "zero_sets.ply", "stats.json"})
    EXPECT_TRUE(fs::exists(Path("grid/") + name)) << name;
  EXPECT_EQ(ReadFile(Path("grid/grid.msh")).rfind("$MeshFormat\n4.1 0 8\n", 0), 0u);
  EXPECT_NE(ReadFile(Path("grid/grid.vtu")).find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  const std::string stats = ReadFile(Path("grid/stats.json"));
  for (const char* key : {"\"cells\"", "\"active_cells\"", "\"vertices\"", "\"min_radius_ratio\"",
                          "\"min_radius_ratio_active\"", "\"seconds\""})
    EXPECT_NE(stats.find(key), std::string::npos) << key;

  // Points of the true sphere are within epsilon of the extracted surface.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  std::ostringstream points;
  points.precision(17);
  for (int i = 0; i < 500; ++i) {
    double d[3] = {normal(rng), normal(rng), normal(rng)};
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    points << 0.5 + 0.3 * d[0] / n << " " << 0.5 + 0.3 * d[1] / n << " " << 0.5 + 0.3 * d[2] / n << "\n";
  }
  WriteFile("sphere_points.xyz", points.str());
  ASSERT_EQ(Run("invert -q -g " + Path("grid/zero_sets.ply") + " -p " + Path("sphere_points.xyz") + " -o " +
                    Path("distances.csv"),
                &out),
            0)
      << out;
  std::string header;
  const auto rows = CsvRows(ReadFile(Path("distances.csv")), &header);
  ASSERT_EQ(rows.size(), 500u);
  std::istringstream names(header);
  std::string name;
  int distanceColumn = -1;
  for (int c = 0; std::getline(names, name, ','); ++c)
    if (name == "distance") distanceColumn = c;
  ASSERT_GE(distanceColumn, 0) << header;
  for (const auto& row : rows) EXPECT_LE(std::stod(row[distanceColumn]), 1e-3);
}

TEST_F(CliTest, GridIn2DWritesCurves) {
  WriteFile("quintic.json", R"([{"type": "quintic", "center": [0, 0]}])");
  std::string out;
  ASSERT_EQ(Run("grid -f " + Path("quintic.json") + " --box -1.5,-1.5,1.5,1.5 --epsilon 1e-3 -o " + Path("g"), &out),
            0)
      << out;
  const std::string obj = ReadFile(Path("g/zero_sets.obj"));
  EXPECT_NE(obj.find("\nl "), std::string::npos);
  EXPECT_FALSE(fs::exists(Path("g/zero_sets.ply")));
  EXPECT_NE(ReadFile(Path("g/grid.msh")).find("$NodeData"), std::string::npos);
}

TEST_F(CliTest, GridErrorsHaveExitCodesAndLeaveNoOutput) {
  WriteFile("sphere.json", kSphereFunction);
  const std::string box = " --box 0,0,0,1,1,1 -o " + Path("out");
  std::string out;
  EXPECT_EQ(Run("grid -f " + Path("missing.json") + box, &out), 3);
  EXPECT_NE(out.find("missing.json"), std::string::npos) << out;
  WriteFile("bad.json", "[\n  {\"type\": \"sphere\",\n   \"center\": [0, 0, 0], \"radius\": -1}\n]\n");
  EXPECT_EQ(Run("grid -f " + Path("bad.json") + box, &out), 3);
  EXPECT_NE(out.find("bad.json:3"), std::string::npos) << out;
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " --mode csg" + box, &out), 2) << out;
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " --epsilon -1e-3" + box, &out), 2) << out;
  EXPECT_NE(out.find("--epsilon must be a positive number"), std::string::npos) << out;
  // A 2D function list on a 3D grid.
  WriteFile("disk.json", "[{\"type\": \"sphere\", \"center\": [0.5, 0.5], \"radius\": 0.3}]");
  EXPECT_EQ(Run("grid -f " + Path("disk.json") + box, &out), 3) << out;
  EXPECT_NE(out.find("disk.json:1: functions[0].center: 2 numbers, expected 3 numbers (the grid is 3D)"),
            std::string::npos)
      << out;
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " --box 0,0,0,1,1 -o " + Path("out"), &out), 2) << out;
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " --box 1,0,0,0,1,1 -o " + Path("out"), &out), 2) << out;
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " -o " + Path("out"), &out), 2) << out;
  EXPECT_FALSE(fs::exists(Path("out/grid.msh")));
  WriteFile("occupied", "a file where the output directory should be");
  EXPECT_EQ(Run("grid -f " + Path("sphere.json") + " --box 0,0,0,1,1,1 -o " + Path("occupied"), &out), 4) << out;
  EXPECT_EQ(ReadFile(Path("occupied")), "a file where the output directory should be");
}
