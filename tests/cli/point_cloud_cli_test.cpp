// `invmap invert` and `invmap trim` on LAS and PCD point clouds: the same
// results as on the same points written as .xyz, trimmed files as the
// independent writers write the kept points, bad files answered with exit
// code 3 naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_fixture.h"
#include "tests/support/las_writer.h"
#include "tests/support/pcd_writer.h"

namespace {

namespace fs = std::filesystem;
using invmap::testing::LasFile;
using invmap::testing::PcdTestCloud;

/// CliTest with the torus of `invmap generate torus` in its directory.
class PointCloudCliTest : public invmap::testing::CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    ASSERT_EQ(Run("generate torus -o " + Path("torus.json")), 0);
  }

  /// `invert` of `points` onto the torus, to CSV; the result's text.
  std::string Invert(const std::string& points) {
    const std::string out = Path("result.csv");
    EXPECT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path(points) + " -o " + out + " -q"), 0) << points;
    return ReadFile(out);
  }
};

/// Points around the torus (R = 2, r = 0.7) as LAS record values with
/// scale 0.001 and the given offsets, some on, some off it.
LasFile TorusLas(int minor, int format, std::size_t count, std::mt19937_64* rng) {
  LasFile file;
  file.versionMinor = minor;
  file.pointFormat = format;
  file.extraBytes = 3;
  file.scale[0] = file.scale[1] = file.scale[2] = 0.001;
  file.offset[0] = 0.5;
  file.offset[1] = -0.25;
  file.offset[2] = 0.125;
  file.points = invmap::testing::RandomLasPoints(count, format, file.extraBytes, 3500, rng);
  return file;
}

/// The points of a LAS file as .xyz text (17 digits), with the point's
/// index as a fourth column.
std::string LasAsXyz(const LasFile& file) {
  std::string text;
  char line[160];
  for (std::size_t i = 0; i < file.points.size(); ++i) {
    const auto& p = file.points[i];
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %zu\n", p.x * file.scale[0] + file.offset[0],
                  p.y * file.scale[1] + file.offset[1], p.z * file.scale[2] + file.offset[2], i);
    text += line;
  }
  return text;
}

/// Indices (the fourth column) of the lines of a trimmed .xyz file.
std::vector<std::size_t> KeptIndices(const std::string& xyz) {
  std::vector<std::size_t> indices;
  std::istringstream in(xyz);
  double x, y, z;
  std::size_t index;
  while (in >> x >> y >> z >> index) indices.push_back(index);
  return indices;
}

TEST_F(PointCloudCliTest, InvertAndTrimOnLasMatchTheSamePointsAsXyz) {
  std::mt19937_64 rng(17);
  for (const auto& [minor, format] : {std::pair{0, 1}, {2, 3}, {3, 5}, {4, 6}, {4, 10}}) {
    SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
    const LasFile file = TorusLas(minor, format, 3000, &rng);
    WriteFile("scan.las", invmap::testing::WriteLas(file));
    WriteFile("scan.xyz", LasAsXyz(file));
    const std::string fromXyz = Invert("scan.xyz");
    ASSERT_NE(fromXyz.find("\n2999,"), std::string::npos);
    EXPECT_TRUE(Invert("scan.las") == fromXyz);

    const std::string trim = "trim -g " + Path("torus.json") + " --max-distance 0.2 -q -p ";
    ASSERT_EQ(Run(trim + Path("scan.xyz") + " -o " + Path("near.xyz")), 0);
    ASSERT_EQ(Run(trim + Path("scan.las") + " -o " + Path("near.las")), 0);
    LasFile kept = file;
    kept.points.clear();
    for (std::size_t i : KeptIndices(ReadFile(Path("near.xyz")))) kept.points.push_back(file.points[i]);
    ASSERT_GT(kept.points.size(), 100u);
    ASSERT_LT(kept.points.size(), file.points.size());
    EXPECT_TRUE(ReadFile(Path("near.las")) == invmap::testing::WriteLas(kept));
  }
}

TEST_F(PointCloudCliTest, InvertAndTrimOnPcdMatchTheSamePointsAsXyz) {
  std::mt19937_64 rng(18);
  PcdTestCloud cloud = invmap::testing::RandomPcdCloud(2000, 'F', 4, true, &rng);
  cloud.points[5][0] = std::nan("");  // x of point 5
  // Fields x, intensity, y, _ (3 values), normal (3 values), z, ...: x, y
  // and z are values 0, 2 and 9.
  ASSERT_EQ(cloud.fields[5].name, "z");
  std::string xyz;
  char line[160];
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const auto& v = cloud.points[i];
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %zu\n", v[0], v[2], v[9], i);
    xyz += line;
  }
  WriteFile("scan.xyz", xyz);
  const std::string fromXyz = Invert("scan.xyz");
  ASSERT_NE(fromXyz.find("\n5,invalid,"), std::string::npos);
  ASSERT_EQ(Run("trim -g " + Path("torus.json") + " --max-distance 0.2 -q -p " + Path("scan.xyz") + " -o " +
                Path("near.xyz")),
            0);
  const std::vector<std::size_t> indices = KeptIndices(ReadFile(Path("near.xyz")));
  ASSERT_GT(indices.size(), 10u);
  PcdTestCloud kept = cloud;
  kept.points.clear();
  for (std::size_t i : indices) kept.points.push_back(cloud.points[i]);
  for (const char* encoding : {"ascii", "binary", "binary_compressed"}) {
    SCOPED_TRACE(encoding);
    WriteFile("scan.pcd", invmap::testing::WritePcd(cloud, encoding));
    EXPECT_TRUE(Invert("scan.pcd") == fromXyz);
    ASSERT_EQ(Run("trim -g " + Path("torus.json") + " --max-distance 0.2 -q -p " + Path("scan.pcd") + " -o " +
                  Path("near.pcd")),
              0);
    const std::string trimmed = ReadFile(Path("near.pcd"));
    EXPECT_NE(trimmed.find("\nWIDTH " + std::to_string(indices.size()) + "\n"), std::string::npos);
    EXPECT_NE(trimmed.find("\nPOINTS " + std::to_string(indices.size()) + "\n"), std::string::npos);
    if (std::string(encoding) != "binary_compressed") {
      const std::string expected = invmap::testing::WritePcd(kept, encoding);
      const std::string data = "DATA " + std::string(encoding) + "\n";
      EXPECT_TRUE(trimmed.substr(trimmed.find(data)) == expected.substr(expected.find(data)));
    }
    // The trimmed cloud inverts like the kept points.
    const std::string again = Invert("near.pcd");
    EXPECT_EQ(std::count(again.begin(), again.end(), '\n'), static_cast<long>(indices.size()) + 1);
    EXPECT_EQ(again.find("invalid"), std::string::npos);
  }
}

TEST_F(PointCloudCliTest, BadCloudsExitWith3NamingTheFileAndLeaveNoOutput) {
  std::mt19937_64 rng(19);
  std::string las = invmap::testing::WriteLas(TorusLas(2, 1, 10, &rng));
  las[107] = 11;  // 11 point records claimed, 10 present
  WriteFile("lying.las", las);
  std::string out;
  EXPECT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("lying.las") + " -o " + Path("r.csv"), &out), 3);
  EXPECT_NE(out.find(Path("lying.las") + ": the header's 11 point records"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(Path("r.csv")));

  WriteFile("scan.laz", las);
  EXPECT_EQ(Run("trim -g " + Path("torus.json") + " -p " + Path("scan.laz") + " -o " + Path("t.las") +
                " --max-distance 1", &out),
            3);
  EXPECT_NE(out.find(Path("scan.laz") + ": compressed LAZ is not supported"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(Path("t.las")));

  WriteFile("bad.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA ascii\n1 2 3\n4 5 six\n");
  EXPECT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("bad.pcd") + " -o " + Path("r.csv"), &out), 3);
  EXPECT_NE(out.find(Path("bad.pcd") + ":7: field 'z': 'six' is not a number"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(Path("r.csv")));

  // A .las result is not offered: results carry closest points, cells and
  // parameters that LAS's integer coordinates cannot hold.
  WriteFile("scan.las", invmap::testing::WriteLas(TorusLas(2, 1, 10, &rng)));
  EXPECT_NE(Run("invert -g " + Path("torus.json") + " -p " + Path("scan.las") + " -o " + Path("r.las"), &out), 0);
  EXPECT_NE(out.find("unknown result file extension '.las'"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(Path("r.las")));
}

}  // namespace
