// gmsh $NodeData as node fields, on meshes and views that gmsh itself
// writes (its C++ API, ascii and binary MSH 4.1; and the gmsh command's
// plugins): polynomial fields of the mesh's order reproduced exactly at
// inverted points, agreement with gmsh's own interpolation
// (gmsh::view::probe), the last time step of each view, malformed sections.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "tests/fem/fem_test_support.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ScratchDir;

/// gmsh's API keeps one global model: one set-up per process.
void InitializeGmsh() {
  static bool done = false;
  if (done) return;
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
  done = true;
}

double Scalar(double x, double y, double z, int degree) {
  double v = 0.5 + x - 2 * y + 0.25 * z;
  if (degree >= 2) v += x * y - z * z + 0.5 * x * z;
  if (degree >= 3) v += x * y * z - 0.5 * x * x * x + y * y * z;
  return v;
}

/// Meshes the unit cube (tetrahedra, or structured hexahedra) at `order`,
/// adds the views "T" (two steps: the polynomial of degree `order` is the
/// second) and "U" (a vector), writes `path` and returns the view tags.
std::vector<int> WriteCube(const std::string& path, int order, bool hexes, bool binary) {
  InitializeGmsh();
  gmsh::clear();
  gmsh::model::add("cube");
  gmsh::model::occ::addBox(0, 0, 0, 1, 1, 1);
  gmsh::model::occ::synchronize();
  gmsh::option::setNumber("Mesh.CharacteristicLengthMax", 0.45);
  gmsh::option::setNumber("Mesh.RecombineAll", hexes ? 1 : 0);
  if (hexes) gmsh::model::mesh::setTransfiniteAutomatic();
  gmsh::model::mesh::generate(3);
  gmsh::model::mesh::setOrder(order);
  std::vector<std::size_t> tags;
  std::vector<double> xyz, parametric;
  gmsh::model::mesh::getNodes(tags, xyz, parametric);
  std::vector<std::vector<double>> first, last, vector;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    first.push_back({-1.0});
    last.push_back({Scalar(x, y, z, order)});
    vector.push_back({x * x, y + z, Scalar(x, y, z, 1)});
  }
  const int t = gmsh::view::add("T");
  gmsh::view::addModelData(t, 0, "cube", "NodeData", tags, first, 0.0);
  gmsh::view::addModelData(t, 1, "cube", "NodeData", tags, last, 1.0);
  const int u = gmsh::view::add("U");
  gmsh::view::addModelData(u, 0, "cube", "NodeData", tags, vector, 0.0);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
  gmsh::option::setNumber("PostProcessing.SaveMesh", 1);
  gmsh::view::write(t, path);
  gmsh::option::setNumber("PostProcessing.SaveMesh", 0);
  gmsh::view::write(u, path, true);
  return {t, u};
}

struct GmshCase {
  int order;
  bool hexes;
  bool binary;
};

class GmshNodeDataTest : public ::testing::TestWithParam<GmshCase> {};

// Random points of the cube: the field is the polynomial (its degree is the
// mesh's order and the elements are affine), and what gmsh's own
// interpolation gives.
TEST_P(GmshNodeDataTest, ReproducesPolynomialAndGmshInterpolation) {
  const GmshCase c = GetParam();
  const ScratchDir dir;
  const std::string path = dir.Path("cube.msh");
  const std::vector<int> views = WriteCube(path, c.order, c.hexes, c.binary);
  const FieldGeometry model = io::ReadGmshWithFields(path);
  ASSERT_EQ(model.fields.size(), 2u);
  EXPECT_EQ(model.fields[0].name, "T");
  EXPECT_EQ(model.fields[1].components, 3);
  ASSERT_TRUE(CheckFields(model.geometry, model.fields).empty());
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  std::mt19937 rng(static_cast<unsigned>(c.order + 10 * c.hexes));
  std::uniform_real_distribution<double> u(0.01, 0.99);
  std::vector<double> xyz;
  for (int i = 0; i < 60; ++i) xyz.insert(xyz.end(), {u(rng), u(rng), u(rng)});
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(xyz.data(), 60, 3), {}, &results), Error::Ok);
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(model.geometry, {&model.fields[0], &model.fields[1]}, results, &values), Error::Ok);
  for (int i = 0; i < 60; ++i) {
    const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    EXPECT_NEAR(values[4 * i], Scalar(x, y, z, c.order), 1e-12) << "point " << i;
    EXPECT_NEAR(values[4 * i + 1], x * x, c.order >= 2 ? 1e-12 : 0.1) << "point " << i;
    EXPECT_NEAR(values[4 * i + 3], Scalar(x, y, z, 1), 1e-12) << "point " << i;
    std::vector<double> gmshValue;
    gmsh::view::probe(views[0], x, y, z, gmshValue, 1);
    ASSERT_EQ(gmshValue.size(), 1u);
    EXPECT_NEAR(values[4 * i], gmshValue[0], 1e-9) << "point " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, GmshNodeDataTest,
                         ::testing::Values(GmshCase{1, false, false}, GmshCase{2, false, true},
                                           GmshCase{3, false, false}, GmshCase{2, true, true},
                                           GmshCase{3, true, false}),
                         [](const ::testing::TestParamInfo<GmshCase>& p) {
                           return std::string(p.param.hexes ? "hex" : "tet") + "_order" + std::to_string(p.param.order) +
                                  (p.param.binary ? "_binary" : "_ascii");
                         });

bool HaveGmshCommand() { return std::system("gmsh -version > /dev/null 2>&1") == 0; }

// A view made by the gmsh command's plugins on a linear mesh: a linear
// field is reproduced exactly.
TEST(GmshNodeData, PluginViewOfTheGmshCommand) {
  ASSERT_TRUE(HaveGmshCommand()) << "the gmsh command is not installed (Debian package gmsh)";
  const ScratchDir dir;
  dir.Write("cube.geo",
            "SetFactory(\"OpenCASCADE\");\nBox(1) = {0,0,0, 1,1,1};\nMesh.CharacteristicLengthMax = 0.3;\n"
            "Mesh 3;\nPlugin(NewView).NumComp = 1;\nPlugin(NewView).Run;\n"
            "Plugin(ModifyComponents).Expression0 = \"2*x - y + 3*z + 1\";\nPlugin(ModifyComponents).View = 0;\n"
            "Plugin(ModifyComponents).Run;\nView[0].Name = \"phi\";\nMesh.MshFileVersion = 4.1;\n"
            "PostProcessing.SaveMesh = 1;\nSave View[0] \"" + dir.Path("phi.msh") + "\";\n");
  ASSERT_EQ(std::system(("gmsh " + dir.Path("cube.geo") + " -0 -v 0 > /dev/null 2>&1").c_str()), 0);
  const FieldGeometry model = io::ReadGmshWithFields(dir.Path("phi.msh"));
  ASSERT_EQ(model.fields.size(), 1u);
  EXPECT_EQ(model.fields[0].name, "phi");
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const double p[6] = {0.2, 0.3, 0.4, 0.9, 0.05, 0.6};
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(p, 2, 3), {}, &results), Error::Ok);
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(model.geometry, {&model.fields[0]}, results, &values), Error::Ok);
  EXPECT_NEAR(values[0], 2 * 0.2 - 0.3 + 3 * 0.4 + 1, 1e-12);
  EXPECT_NEAR(values[1], 2 * 0.9 - 0.05 + 3 * 0.6 + 1, 1e-12);
}

/// A one-tet mesh with `nodeData` appended.
std::string OneTetWith(const std::string& nodeData) {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
         "$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n" +
         nodeData;
}

void ExpectGmshError(const std::string& text, const std::string& expected) {
  std::istringstream in(text);
  try {
    io::ReadGmshWithFields(in, "t.msh");
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(GmshNodeData, MalformedSectionsNameTheLine) {
  // Line 31 is the second data line.
  ExpectGmshError(OneTetWith("$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n2\n1 1.0\n9 2.0\n$EndNodeData\n"),
                  "t.msh:31: view 'T' has data for node 9, which $Nodes does not define");
  ExpectGmshError(OneTetWith("$NodeData\n1\n\"T\"\n1\n0\n2\n0\n1\n$EndNodeData\n"), "3 integer tags");
  ExpectGmshError(OneTetWith("$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n4\n1 1\n2 2\n3 3\n$EndNodeData\n"),
                  "expected a node tag");
  // Nodes without a value leave the field NaN where they count only.
  std::istringstream partial(OneTetWith("$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n2\n1 1.0\n2 3.0\n$EndNodeData\n"));
  const FieldGeometry model = io::ReadGmshWithFields(partial, "t.msh");
  ASSERT_EQ(model.fields.size(), 1u);
  EXPECT_EQ(model.fields[0].patchValues[0][0], 1.0);
  EXPECT_EQ(model.fields[0].patchValues[0][1], 3.0);
  EXPECT_TRUE(std::isnan(model.fields[0].patchValues[0][2]));
}

}  // namespace
}  // namespace invmap::testing
