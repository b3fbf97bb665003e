// End-to-end tests of the invmap command: formats, exit codes, no partial
// output, thread-count invariance and trim, against analytic answers.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
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
    EXPECT_TRUE(name == "s.json" || name == "p.xyz" || name == "bad.json" || name == "badpoints.xyz" ||
                name == "run.log")
        << "left behind: " << name;
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
