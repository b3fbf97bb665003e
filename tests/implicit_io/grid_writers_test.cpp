// Tests of the grid, zero-set and stats writers of `invmap grid`, their
// files read back by invmap's own readers (and gmsh when installed), and
// their all-or-nothing output.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "implicit_io/grid_writers.h"
#include "implicit_io/initial_grid.h"
#include "implicit_io/zero_set_writers.h"
#include "invmap/implicit.h"
#include "invmap/invmap.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/ply_mesh.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;

/// Two tetrahedra sharing the face (1, 2, 3), two functions, one active cell.
implicit::Grid SmallGrid3() {
  implicit::Grid grid;
  grid.mesh.dimension = 3;
  grid.mesh.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1.0 / 3};
  grid.mesh.cells = {0, 1, 2, 3, 1, 4, 2, 3};
  grid.functionCount = 2;
  for (std::size_t v = 0; v < 5; ++v) {
    const double* x = &grid.mesh.vertices[3 * v];
    grid.values.push_back(x[0] + x[1] + x[2] - 0.1);  // f0
    grid.values.push_back(static_cast<double>(v) / 3);  // f1
  }
  grid.active = {1, 0};
  return grid;
}

/// Two triangles of the unit square, one function.
implicit::Grid SmallGrid2() {
  implicit::Grid grid;
  grid.mesh.dimension = 2;
  grid.mesh.vertices = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  grid.mesh.cells = {0, 1, 2, 0, 2, 3};
  grid.functionCount = 1;
  grid.values = {0.1, 0.2, 0.3, 0.4};
  grid.active = {0, 1};
  return grid;
}

bool HaveGmsh() {
  static const bool have = std::system("gmsh -version > /dev/null 2>&1") == 0;
  return have;
}

TEST(ImplicitGridWriters, MshRoundTrip) {
  ScratchDir dir;
  for (const implicit::Grid& grid : {SmallGrid3(), SmallGrid2()}) {
    const int dim = grid.mesh.dimension;
    SCOPED_TRACE(dim);
    const std::string path = dir.Path("grid" + std::to_string(dim) + ".msh");
    const std::vector<std::string> names = dim == 3 ? std::vector<std::string>{"sphere", "pla\"ne"}
                                                    : std::vector<std::string>{};
    WriteGridMsh(grid, names, path);

    const Geometry geometry = ReadGmsh(path);
    EXPECT_EQ(geometry.dimension, dim);
    ASSERT_EQ(geometry.patches.size(), 1u);
    const Patch& patch = geometry.patches[0];
    const std::size_t per = static_cast<std::size_t>(dim + 1);
    ASSERT_EQ(patch.cellTypes.size(), grid.mesh.numCells());
    for (std::size_t c = 0; c < grid.mesh.numCells(); ++c) {
      EXPECT_EQ(patch.cellTypes[c], dim == 3 ? CellType::Tet : CellType::Tri);
      for (std::size_t j = 0; j < per; ++j) {
        for (int a = 0; a < dim; ++a) {
          EXPECT_EQ(patch.points[(static_cast<std::size_t>(patch.cellOffsets[c]) + j) * dim + a],
                    grid.mesh.vertices[3 * grid.mesh.cells[c * per + j] + a]);
        }
      }
    }
    // And back to a simplex mesh: the same vertices and cells (all positive).
    const implicit::SimplexMesh mesh = ReadSimplexMeshMsh(path);
    EXPECT_EQ(mesh.vertices, grid.mesh.vertices);
    EXPECT_EQ(mesh.cells, grid.mesh.cells);

    const std::string text = ReadAll(path);
    EXPECT_EQ(text.rfind("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 0), 0u);
    if (dim == 3) {
      EXPECT_NE(text.find("\"f0 sphere\""), std::string::npos);
      EXPECT_NE(text.find("\"f1 pla'ne\""), std::string::npos);
      EXPECT_NE(text.find("\n2 0.3333333333333333\n"), std::string::npos) << "shortest round-trip text";
    } else {
      EXPECT_NE(text.find("\"f0\""), std::string::npos);
    }
    EXPECT_NE(text.find("$ElementData\n1\n\"active\"\n1\n0\n3\n0\n1\n" + std::to_string(grid.mesh.numCells()) +
                        "\n1 " + std::to_string(grid.active[0]) + "\n"),
              std::string::npos);

    if (!HaveGmsh()) continue;
    const std::string out = dir.Path("gmsh" + std::to_string(dim) + ".msh");
    const std::string command = "gmsh '" + path + "' -0 -o '" + out + "' > '" + dir.Path("gmsh.log") + "' 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << ReadAll(dir.Path("gmsh.log"));
    const Geometry again = ReadGmsh(out);
    ASSERT_EQ(again.patches.size(), 1u);
    EXPECT_EQ(again.patches[0].cellTypes.size(), grid.mesh.numCells());
  }
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed: checked with invmap's reader only";
}

TEST(ImplicitGridWriters, MshViewsReadByGmsh) {
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed (Debian package gmsh)";
  ScratchDir dir;
  const std::string path = dir.Path("grid.msh");
  WriteGridMsh(SmallGrid3(), {"a", "b"}, path);
  // gmsh parses the views too: re-save them and find the values.
  const std::string geo = dir.Write("views.geo", "Merge \"" + path +
                                                     "\";\nSave View[0] \"" + dir.Path("view0.pos") + "\";\n");
  const std::string command = "gmsh '" + geo + "' -0 -o '" + dir.Path("out.msh") + "' > '" + dir.Path("gmsh.log") +
                              "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadAll(dir.Path("gmsh.log"));
  const std::string view = ReadAll(dir.Path("view0.pos"));
  EXPECT_NE(view.find("f0 a"), std::string::npos) << view;
}

/// The parts of a raw-appended VTU file.
struct VtuParts {
  std::string xml;                   ///< Everything outside the raw data (the data replaced by nothing).
  std::string raw;                   ///< The bytes after '_' up to the closing tag.
  std::vector<std::uint64_t> offsets;  ///< Declared offset="..." attributes, in file order.
};

VtuParts SplitVtu(const std::string& text) {
  VtuParts parts;
  const std::size_t open = text.find("<AppendedData encoding=\"raw\">");
  const std::size_t underscore = text.find('_', open);
  const std::string closing = "\n  </AppendedData>\n</VTKFile>\n";
  EXPECT_NE(open, std::string::npos);
  EXPECT_GE(text.size(), closing.size());
  EXPECT_EQ(text.compare(text.size() - closing.size(), closing.size(), closing), 0);
  parts.xml = text.substr(0, underscore) + text.substr(text.size() - closing.size());
  parts.raw = text.substr(underscore + 1, text.size() - closing.size() - underscore - 1);
  for (std::size_t at = text.find("offset=\""); at < open; at = text.find("offset=\"", at + 1)) {
    parts.offsets.push_back(std::stoull(text.substr(at + 8)));
  }
  return parts;
}

TEST(ImplicitGridWriters, VtuBlocksAndValues) {
  ScratchDir dir;
  const implicit::Grid grid = SmallGrid3();
  const std::string path = dir.Path("grid.vtu");
  WriteGridVtu(grid, {"s<1>", "p&q"}, path);
  const VtuParts parts = SplitVtu(ReadAll(path));
  EXPECT_NE(parts.xml.find("Name=\"f0 s&lt;1&gt;\""), std::string::npos);
  EXPECT_NE(parts.xml.find("Name=\"f1 p&amp;q\""), std::string::npos);
  EXPECT_NE(parts.xml.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(parts.xml.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);

  // Walk the blocks: each declared offset starts a block, and the blocks
  // fill the appended section exactly.
  std::vector<std::uint64_t> sizes;
  std::uint64_t at = 0;
  while (at < parts.raw.size()) {
    ASSERT_LE(at + 8, parts.raw.size());
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, parts.raw.data() + at, 8);
    ASSERT_EQ(sizes.size() < parts.offsets.size() ? parts.offsets[sizes.size()] : ~0ull, at);
    sizes.push_back(bytes);
    at += 8 + bytes;
  }
  EXPECT_EQ(at, parts.raw.size());
  // f0, f1, active, points, connectivity, offsets, types.
  const std::vector<std::uint64_t> expected = {5 * 8, 5 * 8, 2, 5 * 24, 8 * 8, 2 * 8, 2};
  EXPECT_EQ(sizes, expected);

  const auto blockData = [&](std::size_t b) { return parts.raw.data() + parts.offsets[b] + 8; };
  for (std::size_t v = 0; v < 5; ++v) {
    double f1 = 0, y = 0;
    std::memcpy(&f1, blockData(1) + 8 * v, 8);
    std::memcpy(&y, blockData(3) + 24 * v + 8, 8);
    EXPECT_EQ(f1, grid.values[2 * v + 1]);
    EXPECT_EQ(y, grid.mesh.vertices[3 * v + 1]);
  }
  EXPECT_EQ(blockData(2)[0], 1);
  EXPECT_EQ(blockData(2)[1], 0);
  std::int64_t connectivity[8], offsets[2];
  std::memcpy(connectivity, blockData(4), sizeof connectivity);
  std::memcpy(offsets, blockData(5), sizeof offsets);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(connectivity[i], grid.mesh.cells[i]);
  EXPECT_EQ(offsets[0], 4);
  EXPECT_EQ(offsets[1], 8);
  EXPECT_EQ(blockData(6)[0], 10);

  // The XML around the data is well formed.
  const std::string xmlPath = dir.Write("skeleton.xml", parts.xml);
  if (std::system("xmllint --version > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("xmllint --noout '" + xmlPath + "'").c_str()), 0) << parts.xml;
  }

  // 2D: triangles, no names.
  WriteGridVtu(SmallGrid2(), {}, dir.Path("grid2.vtu"));
  const VtuParts two = SplitVtu(ReadAll(dir.Path("grid2.vtu")));
  EXPECT_NE(two.xml.find("Name=\"f0\""), std::string::npos);
  ASSERT_EQ(two.offsets.size(), 6u);
  EXPECT_EQ(two.raw[two.offsets[5] + 8], 5);
  EXPECT_EQ(two.raw.size(), two.offsets[5] + 8 + 2);
}

TEST(ImplicitGridWriters, InconsistentGridIsAProgrammingError) {
  ScratchDir dir;
  implicit::Grid grid = SmallGrid3();
  EXPECT_THROW(WriteGridMsh(grid, {"only one"}, dir.Path("a.msh")), std::invalid_argument);
  grid.values.pop_back();
  EXPECT_THROW(WriteGridVtu(grid, {}, dir.Path("a.vtu")), std::invalid_argument);
  EXPECT_EQ(dir.EntryCount(), 0u);
}

// ---------------------------------------------------------------------------
// Zero sets and stats.

implicit::ZeroSets SmallZeroSets() {
  implicit::ZeroSets z;
  z.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2};
  z.triangles = {0, 1, 2, 0, 2, 3, 1, 2, 3};
  z.triangleLabels = {{2, -1, -1, -1}, {0, -1, -1, -1}, {2, -1, -1, -1}};
  z.segments = {1, 2};
  z.segmentLabels = {{0, 2, -1, -1}};
  z.points = {2};
  z.pointLabels = {{0, 1, 2, -1}};
  return z;  // Vertices 4 and 5 are used by no triangle.
}

/// Number of lines starting with `prefix`.
std::size_t CountLines(const std::string& text, const std::string& prefix) {
  std::size_t count = 0;
  for (std::size_t at = 0; at < text.size();) {
    if (text.compare(at, prefix.size(), prefix) == 0) ++count;
    const std::size_t end = text.find('\n', at);
    at = end == std::string::npos ? text.size() : end + 1;
  }
  return count;
}

TEST(ImplicitZeroSets, ObjGroupsByLabel) {
  ScratchDir dir;
  const std::string path = dir.Path("zero_sets.obj");
  WriteZeroSetsObj(SmallZeroSets(), path);
  const std::string text = ReadAll(path);
  EXPECT_EQ(CountLines(text, "v "), 6u);
  EXPECT_EQ(CountLines(text, "f "), 3u);
  EXPECT_EQ(CountLines(text, "l "), 1u);
  EXPECT_EQ(CountLines(text, "p "), 1u);
  EXPECT_EQ(CountLines(text, "g "), 4u);
  // Groups in label order, primitives 1-based.
  const std::size_t g0 = text.find("g f0\nf 1 3 4\n");
  const std::size_t g012 = text.find("g f0_f1_f2\np 3\n");
  const std::size_t g02 = text.find("g f0_f2\nl 2 3\n");
  const std::size_t g2 = text.find("g f2\nf 1 2 3\nf 2 3 4\n");
  EXPECT_NE(g0, std::string::npos) << text;
  EXPECT_LT(g0, g012);
  EXPECT_LT(g012, g02);
  EXPECT_LT(g02, g2);
  EXPECT_NE(g2, std::string::npos) << text;
  EXPECT_NE(text.find("v 2 2 2\n"), std::string::npos);

  implicit::ZeroSets bad = SmallZeroSets();
  bad.segmentLabels.clear();
  EXPECT_THROW(WriteZeroSetsObj(bad, dir.Path("bad.obj")), std::invalid_argument);
  bad = SmallZeroSets();
  bad.points = {6};
  EXPECT_THROW(WriteZeroSetsObj(bad, dir.Path("bad.obj")), std::invalid_argument);
}

TEST(ImplicitZeroSets, PlyReadsBackAsAMesh) {
  ScratchDir dir;
  const std::string path = dir.Path("surfaces.ply");
  const implicit::ZeroSets z = SmallZeroSets();
  WriteZeroSetsPly(z, path);
  const Geometry geometry = ReadPlyMesh(path);
  EXPECT_EQ(geometry.dimension, 3);
  ASSERT_EQ(geometry.patches.size(), 1u);
  const Patch& patch = geometry.patches[0];
  EXPECT_EQ(patch.kind, Patch::Kind::Mesh);
  EXPECT_EQ(patch.cell, CellType::Tri);
  ASSERT_EQ(patch.cells.size(), z.triangles.size());
  EXPECT_EQ(patch.points.size(), 4u * 3);  // Only the used vertices.
  for (std::size_t i = 0; i < z.triangles.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(patch.points[3 * static_cast<std::size_t>(patch.cells[i]) + a], z.vertices[3 * z.triangles[i] + a]);
    }
  }
}

TEST(ImplicitGridStats, ExactKeys) {
  ScratchDir dir;
  implicit::GridStats stats;
  stats.cells = 30218;
  stats.activeCells = 14636;
  stats.vertices = 5555;
  stats.minRadiusRatio = 0.1;
  stats.minRadiusRatioActive = 0.25;
  stats.seconds = 0.3;
  const std::string path = dir.Path("stats.json");
  WriteGridStats(stats, path);
  const nlohmann::ordered_json json = nlohmann::ordered_json::parse(ReadAll(path));
  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());
  const std::vector<std::string> expected = {"cells",
                                             "active_cells",
                                             "vertices",
                                             "min_radius_ratio",
                                             "min_radius_ratio_active",
                                             "seconds"};
  EXPECT_EQ(keys, expected);
  EXPECT_TRUE(json["cells"].is_number_integer());
  EXPECT_EQ(json["cells"].get<std::int64_t>(), 30218);
  EXPECT_EQ(json["active_cells"].get<std::int64_t>(), 14636);
  EXPECT_EQ(json["vertices"].get<std::int64_t>(), 5555);
  EXPECT_EQ(json["min_radius_ratio"].get<double>(), 0.1);
  EXPECT_EQ(json["min_radius_ratio_active"].get<double>(), 0.25);
  EXPECT_EQ(json["seconds"].get<double>(), 0.3);
}

TEST(ImplicitWriters, UnwritableOutputLeavesNoFile) {
  ScratchDir dir;
  const std::string missing = dir.Path("no_such_dir");
  const auto expectOutputError = [&](const std::function<void(const std::string&)>& write, const std::string& name) {
    SCOPED_TRACE(name);
    const std::string path = missing + "/" + name;
    ExpectInputError([&] { write(path); }, path, 0, "", InputError::Kind::Output);
    EXPECT_FALSE(std::filesystem::exists(path));
  };
  expectOutputError([](const std::string& p) { WriteGridMsh(SmallGrid3(), {}, p); }, "grid.msh");
  expectOutputError([](const std::string& p) { WriteGridVtu(SmallGrid3(), {}, p); }, "grid.vtu");
  expectOutputError([](const std::string& p) { WriteZeroSetsObj(SmallZeroSets(), p); }, "zero_sets.obj");
  expectOutputError([](const std::string& p) { WriteZeroSetsPly(SmallZeroSets(), p); }, "zero_sets.ply");
  expectOutputError([](const std::string& p) { WriteGridStats(implicit::GridStats(), p); }, "stats.json");
  // A directory in the way of the target: an error, and the directory stays.
  std::filesystem::create_directory(dir.Path("stats.json"));
  ExpectInputError([&] { WriteGridStats(implicit::GridStats(), dir.Path("stats.json")); }, dir.Path("stats.json"), 0,
                   "is a directory", InputError::Kind::Output);
  EXPECT_TRUE(std::filesystem::is_directory(dir.Path("stats.json")));
  EXPECT_EQ(dir.EntryCount(), 1u);
}

}  // namespace
}  // namespace invmap::io
