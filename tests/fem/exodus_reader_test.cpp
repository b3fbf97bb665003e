// The Exodus reader against files the Exodus library writes, checked
// against VTK's Exodus reader (vtkExodusIIReader, which knows Exodus's node
// numbering independently) and VTK's evaluation of the cells it makes; the
// serendipity elements against VTK's serendipity cells; nodal variables at
// chosen time steps; polynomial fields of the element's degree reproduced
// exactly; element blocks as patches; malformed files.
#include "fem/exodus_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <vtkCell.h>
#include <vtkDataArray.h>
#include <vtkExodusIIReader.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>

#include "fem/exodus_elements.h"
#include "io/input_error.h"
#include "tests/fem/exodus_writer.h"
#include "tests/fem/fem_test_support.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ScratchDir;

struct ExodusCase {
  const char* type;
  int nodes;
  int completeDegree;
};

const ExodusCase kCases[] = {
    {"BAR2", 2, 1},   {"BAR3", 3, 2},   {"TRI3", 3, 1},    {"TRI6", 6, 2},  {"QUAD4", 4, 1},
    {"QUAD8", 8, 2},  {"QUAD9", 9, 2},  {"TETRA4", 4, 1},  {"TETRA10", 10, 2}, {"HEX8", 8, 1},
    {"HEX20", 20, 2}, {"HEX27", 27, 2}, {"WEDGE6", 6, 1},  {"WEDGE15", 15, 2},
};

fem::ExodusElementType TypeOf(const ExodusCase& c) {
  fem::ExodusElementType type;
  EXPECT_TRUE(fem::FindExodusElementType(c.type, c.nodes, &type)) << c.type;
  return type;
}

bool IsPlanar(CellType cell) { return cell == CellType::Tri || cell == CellType::Quad; }

/// Where a reference point goes: a curved (or affine) map, in the plane for
/// triangles and quads (a 2D file).
std::array<double, 3> Place(const std::array<double, 3>& r, CellType cell, bool curved) {
  const double b = curved ? 1.0 : 0.0;
  std::array<double, 3> x{0.3 + 1.1 * r[0] + 0.2 * r[1] - 0.1 * r[2] + b * (0.15 * r[1] * r[1] - 0.1 * r[0] * r[2]),
                          -0.2 + 0.15 * r[0] + 0.9 * r[1] + 0.25 * r[2] + b * 0.12 * r[0] * r[0],
                          0.5 - 0.1 * r[0] + 0.2 * r[1] + 1.2 * r[2] + b * (0.2 * r[0] * r[1] + 0.1 * r[0] * r[0])};
  if (IsPlanar(cell)) x[2] = 0.0;
  return x;
}

double Field(const std::array<double, 3>& x, int degree, int step) {
  double value = 1.0 + 0.5 * x[0] - 0.75 * x[1] + 0.25 * x[2];
  if (degree >= 2) value += x[0] * x[1] - 0.5 * x[1] * x[1] + 0.3 * x[0] * x[2] + 0.2 * x[2] * x[2];
  return step == 1 ? value : 2.0 * value + 1.0;
}

/// One element of the case, nodes in Exodus order at Place(reference
/// node), and nodal variables "T" (2 steps) and "P"; stored as floats
/// (ioWordSize 4) or doubles.
std::string WriteOneElement(const ScratchDir& dir, const ExodusCase& c, bool curved, int ioWordSize = 8) {
  const fem::ExodusElementType type = TypeOf(c);
  std::vector<double> xyz;
  std::vector<double> t1, t2, p;
  ExodusBlockToWrite block{10, c.type, c.nodes, {}, "only"};
  for (const auto& r : fem::ExodusReferenceNodes(type)) {
    const std::array<double, 3> x = Place(r, type.cell, curved);
    xyz.insert(xyz.end(), x.begin(), x.end());
    t1.push_back(Field(x, c.completeDegree, 1));
    t2.push_back(Field(x, c.completeDegree, 2));
    p.push_back(x[0] - x[1]);
    block.connectivity.push_back(static_cast<int>(t1.size()));
  }
  const std::string path = dir.Path(std::string(c.type) + ".exo");
  EXPECT_TRUE(WriteExodus(path, IsPlanar(type.cell) ? 2 : 3, xyz, {block}, {{"T", {t1, t2}}, {"P", {p, p}}},
                          ioWordSize));
  return path;
}

/// VTK's reading of a one-block file: the block's grid.
struct VtkExodus {
  vtkNew<vtkExodusIIReader> reader;
  vtkUnstructuredGrid* grid = nullptr;
};

void ReadWithVtk(const std::string& path, int step, VtkExodus* out) {
  out->reader->SetFileName(path.c_str());
  out->reader->UpdateInformation();
  out->reader->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
  out->reader->SetTimeStep(step - 1);
  out->reader->Update();
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(out->reader->GetOutput()->GetBlock(0));
  ASSERT_NE(blocks, nullptr);
  out->grid = vtkUnstructuredGrid::SafeDownCast(blocks->GetBlock(0));
  ASSERT_NE(out->grid, nullptr);
  ASSERT_EQ(out->grid->GetNumberOfCells(), 1);
}

class ExodusElementTest : public ::testing::TestWithParam<ExodusCase> {};

// The element's map and its nodal variable at a chosen time step agree
// with VTK's reading of the same file at random parameters. The file
// stores floats: VTK's Exodus reader keeps single precision, so both read
// the same numbers.
TEST_P(ExodusElementTest, MatchesVtkExodusReader) {
  const ExodusCase c = GetParam();
  const ScratchDir dir;
  const std::string path = WriteOneElement(dir, c, true, 4);
  io::FieldReadOptions options;
  options.timeStep = 1;
  const FieldGeometry model = fem::ReadExodus(path, options);
  ASSERT_EQ(model.geometry.patches.size(), 1u);
  ASSERT_EQ(model.fields.size(), 2u);
  EXPECT_EQ(model.fields[0].name, "T");
  VtkExodus vtk;
  ReadWithVtk(path, 1, &vtk);
  vtkCell* cell = vtk.grid->GetCell(0);
  vtkDataArray* t = vtk.grid->GetPointData()->GetArray("T");
  ASSERT_NE(t, nullptr);
  const CellType type = TypeOf(c).cell;
  std::mt19937 rng(static_cast<unsigned>(c.nodes * 13 + c.completeDegree));
  std::vector<double> weights(static_cast<std::size_t>(cell->GetNumberOfPoints()));
  for (int trial = 0; trial < 30; ++trial) {
    const std::array<double, 3> r = RandomReferencePoint(type, rng);
    double pcoords[3] = {r[0], r[1], r[2]}, x[3];
    int subId = 0;
    cell->EvaluateLocation(subId, pcoords, x, weights.data());
    double tv = 0.0;
    for (std::size_t i = 0; i < weights.size(); ++i) tv += weights[i] * t->GetComponent(static_cast<vtkIdType>(i), 0);
    const std::vector<double> mine = EvaluateAt(model.geometry, nullptr, 0, 0, r);
    for (int k = 0; k < model.geometry.dimension; ++k) EXPECT_NEAR(mine[k], x[k], 1e-12) << c.type << " trial " << trial;
    EXPECT_NEAR(EvaluateAt(model.geometry, &model.fields[0], 0, 0, r)[0], tv, 1e-11) << c.type << " trial " << trial;
  }
}

// On an affine element a field of the element's complete degree is
// reproduced exactly at inverted points, at the default (last) time step.
TEST_P(ExodusElementTest, PolynomialFieldReproducedByProbe) {
  const ExodusCase c = GetParam();
  const ScratchDir dir;
  const FieldGeometry model = fem::ReadExodus(WriteOneElement(dir, c, false), {});
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const CellType type = TypeOf(c).cell;
  const int dim = model.geometry.dimension;
  std::mt19937 rng(static_cast<unsigned>(c.nodes));
  std::vector<double> points;
  std::vector<std::array<double, 3>> xs;
  for (int trial = 0; trial < 30; ++trial) {
    const std::array<double, 3> x = Place(RandomReferencePoint(type, rng, 0.01), type, false);
    xs.push_back(x);
    points.insert(points.end(), x.begin(), x.begin() + dim);
  }
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(points.data(), xs.size(), dim), {}, &results), Error::Ok);
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(model.geometry, {&model.fields[0]}, results, &values), Error::Ok);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    ASSERT_EQ(results.status[i], Status::Found);
    EXPECT_LT(results.distance[i], 1e-12);
    EXPECT_NEAR(values[i], Field(xs[i], c.completeDegree, 2), 1e-11) << c.type << " point " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(ExodusTypes, ExodusElementTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<ExodusCase>& p) { return std::string(p.param.type); });

// Blocks are patches in file order, elements cells in block order; the
// element type name is matched on its base (any case) and node count.
TEST(ExodusReader, BlocksArePatchesAndNamesAreForgiving) {
  const ScratchDir dir;
  // Two unit cubes side by side (HEX8), and a tet on top: 3 blocks.
  std::vector<double> xyz;
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 3; ++i) xyz.insert(xyz.end(), {double(i), double(j), double(k)});
    }
  }
  xyz.insert(xyz.end(), {0.5, 0.5, 2.0});
  auto node = [](int i, int j, int k) { return 1 + i + 3 * j + 6 * k; };
  std::vector<int> hexes;
  for (int i = 0; i < 2; ++i) {
    hexes.insert(hexes.end(), {node(i, 0, 0), node(i + 1, 0, 0), node(i + 1, 1, 0), node(i, 1, 0), node(i, 0, 1),
                               node(i + 1, 0, 1), node(i + 1, 1, 1), node(i, 1, 1)});
  }
  const std::vector<int> tet = {node(0, 0, 1), node(1, 0, 1), node(0, 1, 1), 13};
  const std::string path = dir.Path("blocks.e");
  ASSERT_TRUE(WriteExodus(path, 3, xyz,
                          {{7, "hex", 8, {hexes.begin(), hexes.begin() + 8}, "left"},
                           {3, "Hexahedron", 8, {hexes.begin() + 8, hexes.end()}, "right"},
                           {9, "tetra", 4, tet, "top"}},
                          {}));
  const FieldGeometry model = fem::ReadExodus(path, {});
  ASSERT_EQ(model.geometry.patches.size(), 3u);
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const double p[9] = {0.25, 0.5, 0.5, 1.75, 0.25, 0.75, 0.1, 0.1, 1.2};
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(p, 3, 3), {}, &results), Error::Ok);
  EXPECT_EQ(results.patch[0], 0);
  EXPECT_EQ(results.patch[1], 1);
  EXPECT_EQ(results.patch[2], 2);
  EXPECT_NEAR(results.params[3], 0.75, 1e-12);
  EXPECT_NEAR(results.params[4], 0.25, 1e-12);
  EXPECT_NEAR(results.params[5], 0.75, 1e-12);
}

void ExpectExodusError(const std::string& path, const io::FieldReadOptions& options, const std::string& text) {
  ExpectInputError([&] { fem::ReadExodus(path, options); }, {text, path});
}

TEST(ExodusReader, BadFilesAreInputErrorsNamingBlockAndElement) {
  const ScratchDir dir;
  ExpectExodusError(dir.Path("missing.exo"), {}, "no such file");
  ExpectExodusError(dir.Write("text.exo", "not netCDF at all\n"), {}, "not an Exodus II file");
  // /dev/zero and a sparse file of gigabytes: refused at once (the whole
  // file was read to check its header, and /dev/zero never ended).
  std::filesystem::create_symlink("/dev/zero", dir.Path("zero.exo"));
  ExpectExodusError(dir.Path("zero.exo"), {}, "not a regular file");
  const std::string sparse = dir.Write("sparse.exo", "");
  std::filesystem::resize_file(sparse, std::uintmax_t{2} << 30);
  ExpectExodusError(sparse, {}, "not an Exodus II file: neither a netCDF (CDF) nor an HDF5 signature");
  // A classic netCDF header claiming a 3 GB attribute in a 40-byte file
  // (found by fuzz_fem: the netCDF library allocated it before failing).
  const std::string header("CDF\x01" "\0\0\0\0" "\0\0\0\0\0\0\0\0" "\0\0\0\x0c\0\0\0\x01"
                           "\0\0\0\x01" "a\0\0\0" "\0\0\0\x02" "\xc0\0\0\0" "abcd", 40);
  ExpectExodusError(dir.Write("huge_attribute.exo", header), {}, "netCDF global attribute 0 does not fit in the file");
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0.5, -1};
  ASSERT_TRUE(WriteExodus(dir.Path("pyramid.exo"), 3, xyz, {{4, "PYRAMID", 5, {1, 2, 3, 4, 5}, ""}}, {}));
  ExpectExodusError(dir.Path("pyramid.exo"), {}, "element block 4 (PYRAMID)");
  ASSERT_TRUE(WriteExodus(dir.Path("range.exo"), 3, xyz, {{2, "TET4", 4, {1, 2, 3, 4, 5, 2, 3, 9}, ""}}, {}));
  ExpectExodusError(dir.Path("range.exo"), {}, "element block 2 (TET4), element 1 of the block: node 9 out of range");
  ASSERT_TRUE(WriteExodus(dir.Path("steps.exo"), 3, xyz, {{1, "TET4", 4, {1, 2, 3, 4}, ""}},
                          {{"T", {{1, 2, 3, 4, 5}, {2, 3, 4, 5, 6}}}}));
  io::FieldReadOptions options;
  options.timeStep = 3;
  ExpectExodusError(dir.Path("steps.exo"), options, "time step 3 requested, the file has 2 time steps");
  options.timeStep = 1;
  const FieldGeometry first = fem::ReadExodus(dir.Path("steps.exo"), options);
  const FieldGeometry last = fem::ReadExodus(dir.Path("steps.exo"), {});
  EXPECT_EQ(first.fields[0].patchValues[0][0], 1.0);
  EXPECT_EQ(last.fields[0].patchValues[0][0], 2.0);
  // A file cut short, by a byte or in its node variables: the netCDF
  // library would read the missing values as zeros and succeed.
  const std::string whole = io::scratch::ReadAll(dir.Path("steps.exo"));
  for (const std::size_t cut : {std::size_t{1}, std::size_t{8}, whole.size() / 8}) {
    SCOPED_TRACE(cut);
    ExpectExodusError(dir.Write("cut.exo", whole.substr(0, whole.size() - cut)), {}, "the file is cut short");
  }
}

}  // namespace
}  // namespace invmap::testing
