// End-to-end tests of `invmap manifold`: a closed mesh written as OBJ, PLY,
// OFF and STL, with each base surface, gives a surface that `info` and
// `invert` take (inverted points checked against the independent evaluator
// of tests/support/pou_reference.h, which shares no code with pou/);
// `--tessellate` writes vertices that lie on the surface by that evaluator;
// bad meshes exit 3 naming the vertex, edge or triangle, leaving no output.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_fixture.h"
#include "tests/support/pou_meshes.h"
#include "tests/support/pou_reference.h"

namespace {

namespace fs = std::filesystem;
using invmap::testing::CliTest;
using invmap::testing::PouReference;
using invmap::testing::TriangleMesh;

std::string Number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::string Vertex(const TriangleMesh& m, std::int64_t v) {
  return Number(m.xyz[3 * v]) + " " + Number(m.xyz[3 * v + 1]) + " " + Number(m.xyz[3 * v + 2]);
}

/// The mesh as text in the format of `extension` (.obj, .ply, .off, .stl).
std::string MeshText(const TriangleMesh& m, const std::string& extension) {
  std::string text;
  if (extension == ".obj") {
    for (std::int64_t v = 0; v < m.numVertices(); ++v) text += "v " + Vertex(m, v) + "\n";
    for (std::int64_t t = 0; t < m.numTriangles(); ++t) {
      text += "f " + std::to_string(m.triangles[3 * t] + 1) + " " + std::to_string(m.triangles[3 * t + 1] + 1) + " " +
              std::to_string(m.triangles[3 * t + 2] + 1) + "\n";
    }
  } else if (extension == ".ply" || extension == ".off") {
    if (extension == ".ply") {
      text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.numVertices()) +
             "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
             std::to_string(m.numTriangles()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    } else {
      text = "OFF\n" + std::to_string(m.numVertices()) + " " + std::to_string(m.numTriangles()) + " 0\n";
    }
    for (std::int64_t v = 0; v < m.numVertices(); ++v) text += Vertex(m, v) + "\n";
    for (std::int64_t t = 0; t < m.numTriangles(); ++t) {
      text += "3 " + std::to_string(m.triangles[3 * t]) + " " + std::to_string(m.triangles[3 * t + 1]) + " " +
              std::to_string(m.triangles[3 * t + 2]) + "\n";
    }
  } else {
    // STL has no vertex list: the reader merges equal coordinates.
    text = "solid mesh\n";
    for (std::int64_t t = 0; t < m.numTriangles(); ++t) {
      text += "facet normal 0 0 0\nouter loop\n";
      for (int k = 0; k < 3; ++k) text += "vertex " + Vertex(m, m.triangles[3 * t + k]) + "\n";
      text += "endloop\nendfacet\n";
    }
    text += "endsolid mesh\n";
  }
  return text;
}

/// The pou_manifold patch of a surface file, for the independent evaluator.
struct SurfaceFile {
  std::vector<double> xyz, nets;
  std::vector<std::int64_t> triangles;
  std::vector<int> degrees;
};

SurfaceFile ReadSurface(const std::string& text) {
  const nlohmann::json json = nlohmann::json::parse(text);
  const nlohmann::json& patch = json.at("patches").at(0);
  EXPECT_EQ(patch.at("kind"), "pou_manifold");
  SurfaceFile s;
  for (const auto& v : patch.at("vertices"))
    for (double x : v) s.xyz.push_back(x);
  for (const auto& t : patch.at("cells"))
    for (std::int64_t i : t) s.triangles.push_back(i);
  for (int d : patch.at("degrees")) s.degrees.push_back(d);
  for (const auto& p : patch.at("chart_control_points"))
    for (double x : p) s.nets.push_back(x);
  return s;
}

/// The vertices of a binary little-endian PLY of doubles (what --tessellate
/// writes), and its triangle count.
std::vector<double> ReadPlyVertices(const std::string& text, std::int64_t* numTriangles) {
  const std::size_t end = text.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  EXPECT_NE(text.find("format binary_little_endian 1.0"), std::string::npos);
  std::istringstream header(text.substr(0, end));
  std::string line;
  std::int64_t numVertices = 0;
  while (std::getline(header, line)) {
    if (line.rfind("element vertex ", 0) == 0) numVertices = std::stoll(line.substr(15));
    if (line.rfind("element face ", 0) == 0) *numTriangles = std::stoll(line.substr(13));
  }
  const std::size_t body = end + std::strlen("end_header\n");
  EXPECT_EQ(text.size(), body + 24 * numVertices + 13 * *numTriangles);
  std::vector<double> xyz(3 * numVertices);
  if (text.size() >= body + 24 * numVertices) std::memcpy(xyz.data(), text.data() + body, 24 * numVertices);
  return xyz;
}

TEST_F(CliTest, ManifoldFromEveryMeshFormatAndBaseIsTakenByInfoAndInvert) {
  const TriangleMesh mesh = invmap::testing::Bipyramid(5);
  const double size = mesh.diagonal();
  // Points near the mesh and farther off, the same for every surface.
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> queries;
  std::string points;
  for (int i = 0; i < 6; ++i) {
    const std::int64_t v = static_cast<std::int64_t>(random() % mesh.numVertices());
    const double spread = i < 4 ? 0.05 : 0.5;
    for (int c = 0; c < 3; ++c) queries.push_back(mesh.xyz[3 * v + c] + spread * unit(random));
    points += Number(queries[3 * i]) + " " + Number(queries[3 * i + 1]) + " " + Number(queries[3 * i + 2]) + "\n";
  }
  WriteFile("points.xyz", points);
  for (const std::string extension : {".obj", ".ply", ".off", ".stl"}) {
    WriteFile("mesh" + extension, MeshText(mesh, extension));
    // With the OBJ, also the lowest degrees (the apexes have valence 5).
    const std::vector<int> degrees = extension == std::string(".obj") ? std::vector<int>{0, 1, 2} : std::vector<int>{0};
    for (const int degree : degrees)
    for (const std::string base : {"flat", "pn", "loop"}) {
      const std::string option = degree > 0 ? " --degree " + std::to_string(degree) : "";
      const std::string where = extension + " " + base + option;
      std::string out;
      ASSERT_EQ(Run("manifold -m " + Path("mesh" + extension) + " --base " + base + option + " -o " + Path("S.json"),
                    &out),
                0)
          << where << ": " << out;
      EXPECT_NE(out.find("7 charts, base " + base), std::string::npos) << where << ": " << out;
      const SurfaceFile surface = ReadSurface(ReadFile(Path("S.json")));
      if (degree > 0) {
        for (int d : surface.degrees) EXPECT_EQ(d, degree) << where;
      }
      ASSERT_EQ(surface.xyz.size(), mesh.xyz.size()) << where;
      ASSERT_EQ(surface.triangles.size(), mesh.triangles.size()) << where;
      ASSERT_EQ(Run("info -g " + Path("S.json"), &out), 0) << where << ": " << out;
      EXPECT_NE(out.find("pou chart"), std::string::npos) << where << ": " << out;
      ASSERT_EQ(Run("invert -g " + Path("S.json") + " -p " + Path("points.xyz") + " -o " + Path("r.csv") + " -q", &out),
                0)
          << where << ": " << out;
      // Each row: the distance agrees with the independent reference's
      // closest point (dense sampling and a polished solve), and the
      // reported chart and coordinates evaluate to the reported point.
      const PouReference reference(surface.xyz, surface.triangles, surface.degrees, surface.nets);
      std::istringstream rows(ReadFile(Path("r.csv")));
      std::string header, row;
      std::getline(rows, header);
      std::vector<std::string> names;
      {
        std::istringstream h(header);
        for (std::string name; std::getline(h, name, ',');) names.push_back(name);
      }
      const auto column = [&](const std::string& name) {
        const auto at = std::find(names.begin(), names.end(), name);
        EXPECT_NE(at, names.end()) << "no column " << name << " in " << header;
        return static_cast<std::size_t>(at - names.begin());
      };
      const std::size_t status = column("status"), cell = column("cell"), u = column("u"), v = column("v"),
                        distance = column("distance"), x = column("x");
      for (int i = 0; std::getline(rows, row); ++i) {
        std::vector<std::string> f;
        std::istringstream fields(row);
        for (std::string field; std::getline(fields, field, ',');) f.push_back(field);
        ASSERT_GT(f.size(), std::max({status, cell, u, v, distance, x + 2})) << where << ": " << row;
        EXPECT_EQ(f[status], "found") << where << ": " << row;
        std::int64_t chart;
        std::complex<double> at;
        const double expected = reference.Closest(&queries[3 * i], &chart, &at);
        // Never farther than the reference; at degrees 1 and 2 (charts that
        // bend less smoothly into each other) the reference's polish may stop
        // short of the minimum, which the surface's point evaluated by the
        // reference itself (below) confirms.
        EXPECT_LE(std::stod(f[distance]), expected + 1e-8 * size) << where << " point " << i;
        EXPECT_NEAR(std::stod(f[distance]), expected, (degree > 0 ? 1e-5 : 1e-8) * size) << where << " point " << i;
        double p[3];
        reference.Evaluate(std::stoll(f[cell]), {std::stod(f[u]), std::stod(f[v])}, p);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(std::stod(f[x + c]), p[c], 1e-9 * size) << where << " point " << i;
      }
    }
  }
}

TEST_F(CliTest, ManifoldTessellationVerticesLieOnTheSurface) {
  const TriangleMesh mesh = invmap::testing::Bipyramid(4);
  const double size = mesh.diagonal();
  WriteFile("mesh.off", MeshText(mesh, ".off"));
  for (const std::string base : {"flat", "pn", "loop"}) {
    std::string out;
    ASSERT_EQ(Run("manifold -m " + Path("mesh.off") + " --base " + base + " -o " + Path("S.json") + " --tessellate " +
                      Path("T.ply") + " --resolution 3 -q",
                  &out),
              0)
        << base << ": " << out;
    const SurfaceFile surface = ReadSurface(ReadFile(Path("S.json")));
    const PouReference reference(surface.xyz, surface.triangles, surface.degrees, surface.nets);
    std::int64_t numTriangles = 0;
    const std::vector<double> xyz = ReadPlyVertices(ReadFile(Path("T.ply")), &numTriangles);
    // Every mesh triangle into 3 x 3; vertices: 6 corners, 12 edges x 2, 8 x 1 inside.
    EXPECT_EQ(numTriangles, 8 * 9) << base;
    ASSERT_EQ(xyz.size(), 3u * (6 + 24 + 8)) << base;
    for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
      std::int64_t chart;
      std::complex<double> at;
      EXPECT_LT(reference.Closest(&xyz[3 * i], &chart, &at), 1e-9 * size) << base << " tessellation vertex " << i;
    }
  }
}

/// A bad mesh: its file, and what the message must name.
struct BadMesh {
  std::string name;
  TriangleMesh mesh;
  std::string extension;
  std::vector<std::string> named;  ///< The message holds one of these.
};

std::vector<BadMesh> BadMeshes() {
  const TriangleMesh closed = invmap::testing::Bipyramid(5);  // vertices 0 to 6, triangles 0 to 9
  std::vector<BadMesh> bad;
  {
    TriangleMesh m = closed;  // triangle 9 is (1, 2, 6): its edges are left with one triangle
    m.triangles.resize(m.triangles.size() - 3);
    bad.push_back({"boundary", m, ".ply", {"edge (1, 2) is on the boundary", "edge (1, 6) is on the boundary",
                                            "edge (2, 6) is on the boundary"}});
  }
  {
    TriangleMesh m = closed;  // a fin on edge (0, 2): four triangles use it
    m.xyz.insert(m.xyz.end(), {0.5, 0.5, 2.0});
    m.triangles.insert(m.triangles.end(), {0, 2, 7, 2, 0, 7});
    bad.push_back({"non-manifold edge", m, ".obj", {"edge (0, 2) is non-manifold: 4 triangles use it"}});
  }
  {
    // Two bipyramids touching at vertex 0: the second is the first reflected
    // through that vertex (triangles reversed to keep it outward).
    TriangleMesh m = closed;
    const std::int64_t n = closed.numVertices();
    for (std::int64_t v = 1; v < n; ++v)
      for (int c = 0; c < 3; ++c) m.xyz.push_back(2.0 * closed.xyz[c] - closed.xyz[3 * v + c]);
    const auto copy = [n](std::int64_t v) { return v == 0 ? 0 : v + n - 1; };
    for (std::int64_t t = 0; t < closed.numTriangles(); ++t) {
      m.triangles.insert(m.triangles.end(), {copy(closed.triangles[3 * t]), copy(closed.triangles[3 * t + 2]),
                                             copy(closed.triangles[3 * t + 1])});
    }
    bad.push_back({"non-manifold vertex", m, ".obj", {"vertex 0 is non-manifold"}});
  }
  {
    TriangleMesh m = closed;
    m.xyz.insert(m.xyz.end(), {3.0, 3.0, 3.0});
    bad.push_back({"isolated vertex", m, ".off", {"vertex 7 belongs to no triangle (isolated)"}});
  }
  {
    TriangleMesh m = closed;  // triangle 0 (0, 2, 3) turned over
    std::swap(m.triangles[1], m.triangles[2]);
    bad.push_back({"inconsistent orientation", m, ".obj",
                   {"run along edge (0, 2) in the same direction (inconsistent orientation)",
                    "run along edge (0, 3) in the same direction (inconsistent orientation)",
                    "run along edge (2, 3) in the same direction (inconsistent orientation)"}});
  }
  {
    TriangleMesh m = closed;  // vertex 0 moved onto the middle of edge (2, 3)
    for (int c = 0; c < 3; ++c) m.xyz[c] = 0.5 * (m.xyz[6 + c] + m.xyz[9 + c]);
    bad.push_back({"zero-area triangle", m, ".obj", {"triangle 0 (vertices 0, 2, 3) has zero area (degenerate)"}});
  }
  {
    // In STL a triangle with two equal corners: the reader merges them.
    TriangleMesh m = closed;
    m.triangles[1] = m.triangles[0];
    bad.push_back({"repeated vertex", m, ".stl", {"triangle 0 (vertices 0, 0, ", "repeats a vertex (degenerate)"}});
  }
  return bad;
}

TEST_F(CliTest, ManifoldRefusesBadMeshesNamingTheVertexOrEdgeAndWritesNothing) {
  for (const BadMesh& bad : BadMeshes()) {
    const std::string mesh = Path("bad" + bad.extension);
    WriteFile("bad" + bad.extension, MeshText(bad.mesh, bad.extension));
    std::string out;
    EXPECT_EQ(Run("manifold -m " + mesh + " -o " + Path("S.json") + " --tessellate " + Path("T.ply"), &out), 3)
        << bad.name << ": " << out;
    EXPECT_NE(out.find(mesh), std::string::npos) << bad.name << ": " << out;
    bool named = false;
    for (const std::string& text : bad.named) named = named || out.find(text) != std::string::npos;
    if (bad.name == "repeated vertex") {
      named = out.find(bad.named[0]) != std::string::npos && out.find(bad.named[1]) != std::string::npos;
    }
    EXPECT_TRUE(named) << bad.name << ": " << out;
    EXPECT_FALSE(fs::exists(Path("S.json"))) << bad.name;
    EXPECT_FALSE(fs::exists(Path("T.ply"))) << bad.name;
    std::error_code ignored;
    for (const auto& entry : fs::directory_iterator(dir_, ignored)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "bad" + bad.extension || name == "run.log") << bad.name << ": left " << name;
    }
    fs::remove(mesh);
  }
}

TEST_F(CliTest, ManifoldRefusesOutputsOverItsMeshOrOfAnotherFormatAndUnwritablePathsBeforeBuilding) {
  const TriangleMesh mesh = invmap::testing::Bipyramid(4);
  WriteFile("mesh.ply", MeshText(mesh, ".ply"));
  const std::string original = ReadFile(Path("mesh.ply"));
  const std::string m = "manifold -m " + Path("mesh.ply");
  std::string out;
  EXPECT_EQ(Run(m + " -o " + Path("mesh.ply"), &out), 2) << out;
  EXPECT_NE(out.find("writing it would destroy the input"), std::string::npos) << out;
  EXPECT_EQ(Run(m + " -o " + Path("S.json") + " --tessellate " + Path("mesh.ply"), &out), 2) << out;
  EXPECT_EQ(ReadFile(Path("mesh.ply")), original);
  EXPECT_EQ(Run(m + " -o " + Path("S.ply"), &out), 2) << out;
  EXPECT_NE(out.find("manifold writes .json files"), std::string::npos) << out;
  EXPECT_EQ(Run(m + " -o " + Path("S.json") + " --tessellate " + Path("T.obj"), &out), 2) << out;
  EXPECT_NE(out.find("manifold writes .ply files"), std::string::npos) << out;
  // A tessellation that cannot be written is found before the surface is
  // built or written: exit 4 and nothing left behind.
  EXPECT_EQ(Run(m + " -o " + Path("S.json") + " --tessellate " + Path("no/such/dir/T.ply"), &out), 4) << out;
  EXPECT_NE(out.find("no/such/dir/T.ply"), std::string::npos) << out;
  std::error_code ignored;
  for (const auto& entry : fs::directory_iterator(dir_, ignored)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "mesh.ply" || name == "run.log") << "left " << name;
  }
}

}  // namespace
