// End-to-end tests of `invmap distance`: the JSON answer against analytic
// distances, pose lists, --max-distance, and the exit codes (bad pose
// lines named by line, usage errors, unwritable output, no partial output).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class DistanceCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("invmap_distance_cli_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A: the sample torus (R = 2, r = 0.7 around z). B: a segment on the z
    // axis from z = 3 to z = 4, as a straight cubic Bezier curve.
    ASSERT_EQ(Run("generate torus -o " + Path("torus.json")), 0);
    WriteFile("stick.json", R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
      {"kind": "bezier", "cell": "line", "degrees": [3],
       "control_points": [[0, 0, 3], [0, 0, 3.3333333333333333], [0, 0, 3.6666666666666667], [0, 0, 4]]}]})");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  int Run(const std::string& args, std::string* out = nullptr, std::string* err = nullptr) const {
    const std::string outLog = Path("out.log"), errLog = Path("err.log");
    const std::string command =
        std::string(INVMAP_CLI_PATH) + " " + args + " > " + outLog + " 2> " + errLog + " < /dev/null";
    const int status = std::system(command.c_str());
    if (out) *out = ReadFile(outLog);
    if (err) *err = ReadFile(errLog);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  static std::string ReadFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  void WriteFile(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
  }

  std::string Models() const { return "distance --a " + Path("torus.json") + " --b " + Path("stick.json"); }

  fs::path dir_;
};

/// Distance from p to the torus of radii 2 and 0.7 around z.
double TorusDistance(double x, double y, double z) {
  return std::abs(std::sqrt(std::pow(std::sqrt(x * x + y * y) - 2.0, 2) + z * z) - 0.7);
}

/// The answer for the stick moved by (tx, 0, 0): its low end (tx, 0, 3) is nearest.
void ExpectStickAnswer(const json& answer, double tx) {
  ASSERT_TRUE(answer["distance"].is_number()) << answer.dump();
  EXPECT_NEAR(answer["distance"].get<double>(), TorusDistance(tx, 0, 3), 1e-9);
  const json& b = answer["b"];
  EXPECT_EQ(b["patch"], 0);
  EXPECT_EQ(b["cell"], 0);
  ASSERT_EQ(b["params"].size(), 1u);
  EXPECT_NEAR(b["params"][0].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(b["point"][0].get<double>(), tx, 1e-12);
  EXPECT_NEAR(b["point"][2].get<double>(), 3.0, 1e-12);
  const json& a = answer["a"];
  ASSERT_EQ(a["params"].size(), 2u);
  ASSERT_EQ(a["point"].size(), 3u);
  EXPECT_NEAR(TorusDistance(a["point"][0], a["point"][1], a["point"][2]), 0.0, 1e-9);
  const double dx = a["point"][0].get<double>() - tx, dz = a["point"][2].get<double>() - 3.0;
  const double dy = a["point"][1].get<double>();
  EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), answer["distance"].get<double>(), 1e-9);
  EXPECT_EQ(answer["certified"], true);
}

TEST_F(DistanceCliTest, OnePoseToStdout) {
  std::string out;
  ASSERT_EQ(Run(Models() + " --pose-b 1,0,0,2,0,1,0,0,0,0,1,0", &out), 0) << out;
  const json answer = json::parse(out);
  ExpectStickAnswer(answer, 2.0);
  EXPECT_TRUE(answer["seconds"].is_number());
  // The identity by default.
  ASSERT_EQ(Run(Models(), &out), 0);
  ExpectStickAnswer(json::parse(out), 0.0);
}

TEST_F(DistanceCliTest, OutputFileAndSummary) {
  std::string out;
  ASSERT_EQ(Run(Models() + " --pose-b '1, 0, 0, 1.5, 0, 1, 0, 0, 0, 0, 1, 0' -o " + Path("d.json"), &out), 0);
  EXPECT_NE(out.find("invmap distance"), std::string::npos);  // the summary, not the JSON
  ExpectStickAnswer(json::parse(ReadFile(Path("d.json"))), 1.5);
}

TEST_F(DistanceCliTest, PoseListInTimeOrder) {
  WriteFile("poses.txt", "# the stick sliding along x\n1,0,0,0,0,1,0,0,0,0,1,0\n\n1,0,0,0.5,0,1,0,0,0,0,1,0\n"
                         "  1, 0, 0, 2.5, 0, 1, 0, 0, 0, 0, 1, 0\r\n1,0,0,-1,0,1,0,0,0,0,1,0\n");
  std::string out;
  ASSERT_EQ(Run(Models() + " --poses-b " + Path("poses.txt") + " -q -o " + Path("p.json"), &out), 0) << out;
  EXPECT_EQ(out, "");
  const json result = json::parse(ReadFile(Path("p.json")));
  ASSERT_EQ(result["poses"].size(), 4u);
  const double tx[] = {0.0, 0.5, 2.5, -1.0};
  for (int i = 0; i < 4; ++i) ExpectStickAnswer(result["poses"][i], tx[i]);
  EXPECT_TRUE(result["seconds"].is_number());
}

TEST_F(DistanceCliTest, MaxDistanceGivesNull) {
  std::string out;
  ASSERT_EQ(Run(Models() + " --max-distance 2.5", &out), 0);
  const json answer = json::parse(out);
  EXPECT_TRUE(answer["distance"].is_null());
  EXPECT_TRUE(answer["a"].is_null());
  ASSERT_EQ(Run(Models() + " --max-distance 3", &out), 0);
  ExpectStickAnswer(json::parse(out), 0.0);
}

TEST_F(DistanceCliTest, BadPoseLinesAreNamedByLine) {
  WriteFile("short.txt", "1,0,0,0,0,1,0,0,0,0,1,0\n1,0,0,0,0,1,0,0,0,0,1\n");
  std::string err;
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("short.txt") + " -o " + Path("x.json"), nullptr, &err), 3);
  EXPECT_NE(err.find("short.txt:2:"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(Path("x.json")));
  // A matrix that is not a rotation (a scaling) on line 3.
  WriteFile("scaled.txt", "1,0,0,0,0,1,0,0,0,0,1,0\n\n2,0,0,0,0,2,0,0,0,0,2,0\n");
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("scaled.txt") + " -o " + Path("x.json"), nullptr, &err), 3);
  EXPECT_NE(err.find("scaled.txt:3:"), std::string::npos) << err;
  EXPECT_NE(err.find("rotation"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(Path("x.json")));
  // A comma too many, and a NUL byte, are named as such (the message whole).
  WriteFile("comma.txt", "1,0,0,0,0,1,0,0,0,0,1,0,\n");
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("comma.txt"), nullptr, &err), 3);
  EXPECT_NE(err.find("comma.txt:1: an empty number at position 13"), std::string::npos) << err;
  WriteFile("nul.txt", std::string("1,0,0,0,0,1,0,0,0,0,1,0.6") + '\0' + "1\n");
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("nul.txt"), nullptr, &err), 3);
  EXPECT_NE(err.find("nul.txt:1: '0.6\\x001' is not a finite number"), std::string::npos) << err;
  // No pose at all.
  WriteFile("empty.txt", "# nothing\n");
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("empty.txt"), nullptr, &err), 3);
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("missing.txt"), nullptr, &err), 3);
}

TEST_F(DistanceCliTest, TranslationsBeyondTheSupportedRangeAreRefused) {
  // Up to 1e100 the answer is right (the stick 1e100 above the torus, whose
  // distance is 1e100 to 1e-16); beyond, squared distances of the pair
  // search overflowed (1e155 gave a null distance, "certified").
  std::string out, err;
  ASSERT_EQ(Run(Models() + " --pose-b 1,0,0,0,0,1,0,0,0,0,1,1e100", &out), 0) << out;
  const json answer = json::parse(out);
  ASSERT_TRUE(answer["distance"].is_number()) << out;
  EXPECT_NEAR(answer["distance"].get<double>() / 1e100, 1.0, 1e-12);
  // (Not certified there: the torus's cells are far smaller than a rounding
  // of the posed stick's coordinates, so no bound tells them apart.)
  for (const char* tz : {"1.1e100", "1e155", "-1e200"}) {
    EXPECT_EQ(Run(Models() + " --pose-b 1,0,0,0,0,1,0,0,0,0,1," + tz, nullptr, &err), 2) << tz;
    EXPECT_NE(err.find("--pose-b: the pose's translation"), std::string::npos) << err;
    EXPECT_NE(err.find("outside [-1e100, 1e100]"), std::string::npos) << err;
  }
  WriteFile("far.txt", "1,0,0,0,0,1,0,0,0,0,1,0\n1,0,0,1e155,0,1,0,0,0,0,1,0\n");
  EXPECT_EQ(Run(Models() + " --poses-b " + Path("far.txt") + " -o " + Path("x.json"), nullptr, &err), 3);
  EXPECT_NE(err.find("far.txt:2:"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(Path("x.json")));
}

TEST_F(DistanceCliTest, UsageErrors) {
  std::string err;
  EXPECT_EQ(Run(Models() + " --pose-b 1,0,0", nullptr, &err), 2);
  EXPECT_NE(err.find("--pose-b"), std::string::npos) << err;
  EXPECT_EQ(Run(Models() + " --pose-a 0,1,0,0,1,0,0,0,0,0,1,0", nullptr, &err), 2);  // a reflection
  EXPECT_NE(err.find("--pose-a"), std::string::npos) << err;
  WriteFile("poses.txt", "1,0,0,0,0,1,0,0,0,0,1,0\n");
  EXPECT_EQ(Run(Models() + " --pose-b 1,0,0,0,0,1,0,0,0,0,1,0 --poses-b " + Path("poses.txt")), 2);
  EXPECT_EQ(Run("distance --a " + Path("torus.json")), 2);
  EXPECT_EQ(Run(Models() + " --max-distance -1"), 2);
}

TEST_F(DistanceCliTest, InputAndOutputErrors) {
  std::string err;
  EXPECT_EQ(Run("distance --a " + Path("nothing.json") + " --b " + Path("stick.json"), nullptr, &err), 3);
  EXPECT_NE(err.find("nothing.json"), std::string::npos);
  WriteFile("broken.json", "{\"format\": \"invmap-geometry\", \"version\": 1, \"patches\": [");
  EXPECT_EQ(Run("distance --a " + Path("torus.json") + " --b " + Path("broken.json"), nullptr, &err), 3);
  EXPECT_EQ(Run(Models() + " -o " + Path("no/such/dir/d.json"), nullptr, &err), 4);
}

TEST_F(DistanceCliTest, AnOutputOverAnInputOrOfAnotherFormatIsRefusedBeforeAnyWork) {
  WriteFile("poses.txt", "1,0,0,0,0,1,0,0,0,0,1,0\n");
  const std::string torus = ReadFile(Path("torus.json"));
  const std::string poses = ReadFile(Path("poses.txt"));
  std::string err;
  for (const std::string& input : {Path("torus.json"), Path("stick.json"), Path("poses.txt")}) {
    SCOPED_TRACE(input);
    EXPECT_EQ(Run(Models() + " --poses-b " + Path("poses.txt") + " -o " + input, nullptr, &err), 2) << err;
    EXPECT_NE(err.find("writing it would destroy the input"), std::string::npos) << err;
  }
  EXPECT_EQ(ReadFile(Path("torus.json")), torus);
  EXPECT_EQ(ReadFile(Path("poses.txt")), poses);
  for (const std::string name : {"d.csv", "d.ply", "d"}) {
    EXPECT_EQ(Run(Models() + " -o " + Path(name), nullptr, &err), 2) << name;
    EXPECT_NE(err.find("distance writes .json files"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(Path(name))) << name;
  }
}

}  // namespace

namespace {

TEST_F(DistanceCliTest, DistanceAllMinima) {
  // The stick beside the tube (x = 2.5): its low end is the nearest; the
  // list holds every local minimum, nearest first, the nearest the answer.
  std::string out;
  ASSERT_EQ(Run(Models() + " --pose-b 1,0,0,2.5,0,1,0,0,0,0,1,-2 --all-minima", &out), 0) << out;
  const json answer = json::parse(out);
  ASSERT_TRUE(answer["minima"].is_array());
  ASSERT_GE(answer["minima"].size(), 1u);
  EXPECT_EQ(answer["minima"][0]["distance"], answer["distance"]);
  for (std::size_t i = 1; i < answer["minima"].size(); ++i) {
    EXPECT_LE(answer["minima"][i - 1]["distance"].get<double>(), answer["minima"][i]["distance"].get<double>());
  }
  EXPECT_EQ(answer["minima"][0]["certified"], true);
}

TEST_F(DistanceCliTest, InvertAllMinima) {
  // Above and below the torus's tube core at (2, 0, 0): the tube's top or
  // bottom is the one minimum (2.3 away); a NaN point is invalid; nothing
  // lies within 1 of (2, 0, 3).
  WriteFile("points.xyz", "2 0 3\nnan 0 0\n2 0 -3\n");
  std::string out;
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("m.csv") +
                    " --all-minima -q",
                &out),
            0)
      << out;
  std::istringstream rows(ReadFile(Path("m.csv")));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "index,status,patch,cell,u,v,w,x,y,z,distance");
  std::vector<std::string> lines;
  while (std::getline(rows, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("0,found,", 0), 0u);
  EXPECT_NEAR(std::stod(lines[0].substr(lines[0].rfind(',') + 1)), 2.3, 1e-9);
  EXPECT_EQ(lines[1], "1,invalid,-1,-1,,,,,,,");
  EXPECT_EQ(lines[2].rfind("2,found,", 0), 0u);
  EXPECT_NEAR(std::stod(lines[2].substr(lines[2].rfind(',') + 1)), 2.3, 1e-9);
  // Within 1: none.
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("n.csv") +
                " --all-minima --max-distance 1 -q"),
            0);
  EXPECT_NE(ReadFile(Path("n.csv")).find("\n0,none,-1,-1,,,,,,,\n"), std::string::npos);
  // npy: (rows, 11); PLY cannot hold several rows per point.
  ASSERT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("m.npy") +
                " --all-minima -q"),
            0);
  EXPECT_EQ(fs::file_size(Path("m.npy")), 128u + 3u * 11u * 8u);
  EXPECT_EQ(Run("invert -g " + Path("torus.json") + " -p " + Path("points.xyz") + " -o " + Path("m.ply") +
                " --all-minima"),
            2);
  EXPECT_FALSE(fs::exists(Path("m.ply")));
}

}  // namespace
