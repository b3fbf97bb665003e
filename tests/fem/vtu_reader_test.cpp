// The VTU reader against VTK itself: every linear, quadratic, cubic,
// Lagrange (orders 1 to 5) and Bezier cell type, written by VTK's XML
// writer in each of its encodings, read back by invmap and compared with
// VTK's own evaluation of the cell (vtkCell::EvaluateLocation) and of its
// point data (VTK's interpolation functions); parameter round trips; node
// fields of the element's degree reproduced exactly; malformed files.
#include "fem/vtu_reader.h"

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <filesystem>
#include <fstream>

#include "fem/vtk_cells.h"
#include "io/input_error.h"
#include "tests/fem/fem_test_support.h"
#include "tests/fem/vtk_test_cells.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ScratchDir;

/// One VTK cell type to test: its type, order (Lagrange and Bezier types;
/// 0 for fixed ones) and the total degree of polynomials its space holds.
struct VtkCase {
  int vtkType;
  int order;
  int completeDegree;
};

std::vector<VtkCase> AllCases() {
  std::vector<VtkCase> cases = {
      {VTK_LINE, 0, 1},
      {VTK_TRIANGLE, 0, 1},
      {VTK_QUAD, 0, 1},
      {VTK_PIXEL, 0, 1},
      {VTK_TETRA, 0, 1},
      {VTK_HEXAHEDRON, 0, 1},
      {VTK_VOXEL, 0, 1},
      {VTK_WEDGE, 0, 1},
      {VTK_QUADRATIC_EDGE, 0, 2},
      {VTK_QUADRATIC_TRIANGLE, 0, 2},
      {VTK_QUADRATIC_QUAD, 0, 2},
      {VTK_QUADRATIC_TETRA, 0, 2},
      {VTK_QUADRATIC_HEXAHEDRON, 0, 2},
      {VTK_QUADRATIC_WEDGE, 0, 2},
      {VTK_BIQUADRATIC_QUAD, 0, 2},
      {VTK_TRIQUADRATIC_HEXAHEDRON, 0, 2},
      {VTK_QUADRATIC_LINEAR_QUAD, 0, 1},
      {VTK_QUADRATIC_LINEAR_WEDGE, 0, 1},
      {VTK_BIQUADRATIC_QUADRATIC_WEDGE, 0, 2},
      {VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, 0, 2},
      {VTK_BIQUADRATIC_TRIANGLE, 0, 2},
      {VTK_CUBIC_LINE, 0, 3},
  };
  for (int order = 1; order <= 5; ++order) {
    for (int type : {VTK_LAGRANGE_CURVE, VTK_LAGRANGE_TRIANGLE, VTK_LAGRANGE_QUADRILATERAL, VTK_LAGRANGE_TETRAHEDRON,
                     VTK_LAGRANGE_HEXAHEDRON, VTK_LAGRANGE_WEDGE}) {
      cases.push_back({type, order, order});
    }
  }
  for (int order = 2; order <= 3; ++order) {
    for (int type : {VTK_BEZIER_CURVE, VTK_BEZIER_TRIANGLE, VTK_BEZIER_QUADRILATERAL, VTK_BEZIER_TETRAHEDRON,
                     VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE}) {
      cases.push_back({type, order, order});
    }
  }
  return cases;
}

std::string CaseName(const ::testing::TestParamInfo<VtkCase>& info) {
  std::string name = fem::VtkCellTypeName(info.param.vtkType).substr(4);
  if (info.param.order > 0) name += "_order" + std::to_string(info.param.order);
  return name;
}

/// A polynomial of total degree `degree` (every monomial present).
double Polynomial(const std::array<double, 3>& x, int degree) {
  double value = 0.25;
  int term = 0;
  for (int a = 0; a <= degree; ++a) {
    for (int b = 0; a + b <= degree; ++b) {
      for (int c = 0; a + b + c <= degree; ++c, ++term) {
        if (a + b + c == 0) continue;
        value += (0.3 + 0.1 * (term % 7)) * (term % 2 ? -1 : 1) * std::pow(x[0], a) * std::pow(x[1], b) *
                 std::pow(x[2], c);
      }
    }
  }
  return value;
}

bool IsAxisAligned(int vtkType) { return vtkType == VTK_PIXEL || vtkType == VTK_VOXEL; }

/// Bezier cells' nodes are control points: their point data are control
/// values, not samples of a field.
bool IsBezier(int vtkType) { return vtkType >= VTK_BEZIER_CURVE && vtkType <= VTK_BEZIER_WEDGE; }

/// A one-cell grid of the case: nodes placed by Place, point data "f" (the
/// polynomial of the case's complete degree) and "v" (three components).
vtkSmartPointer<vtkUnstructuredGrid> MakeGrid(const VtkCase& c, bool curved) {
  vtkSmartPointer<vtkCell> reference = MakeReferenceCell(c.vtkType, c.order);
  const int n = static_cast<int>(reference->GetNumberOfPoints());
  const double* pcoords = reference->GetParametricCoords();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> f, v;
  f->SetName("f");
  v->SetName("v");
  v->SetNumberOfComponents(3);
  vtkNew<vtkIdList> ids;
  for (int i = 0; i < n; ++i) {
    const std::array<double, 3> x = Place(pcoords + 3 * i, curved, IsAxisAligned(c.vtkType));
    points->InsertNextPoint(x.data());
    f->InsertNextValue(Polynomial(x, c.completeDegree));
    const double vector[3] = {x[0] * x[1], std::sin(x[2]) + i, x[0] - 2 * x[2]};
    v->InsertNextTuple(vector);
    ids->InsertNextId(i);
  }
  grid->SetPoints(points);
  grid->InsertNextCell(c.vtkType, ids);
  grid->GetPointData()->AddArray(f);
  grid->GetPointData()->AddArray(v);
  return grid;
}

CellType InvmapType(int vtkType) {
  CellType type = CellType::Line;
  EXPECT_TRUE(fem::VtkCellTypeToInvmap(vtkType, &type));
  return type;
}

class VtuCellTest : public ::testing::TestWithParam<VtkCase> {};

/// A grid written by VTK's writer and read back by invmap, built.
struct ReadBack {
  FieldGeometry model;
  BuildResult built;
};

ReadBack WriteReadAndBuild(vtkUnstructuredGrid* grid, const std::string& path, Encoding encoding) {
  EXPECT_TRUE(Write(grid, path, encoding));
  ReadBack out;
  out.model = fem::ReadVtu(path);
  out.built = Manifold::Build(out.model.geometry);
  EXPECT_TRUE(out.built.error.empty()) << out.built.error;
  return out;
}

// The map and both fields agree with VTK's evaluation at random parametric
// coordinates, for a curved cell written in one of the encodings (cycled
// over the cases).
TEST_P(VtuCellTest, MatchesVtkEvaluation) {
  const VtkCase c = GetParam();
  const ScratchDir dir;
  const vtkSmartPointer<vtkUnstructuredGrid> grid = MakeGrid(c, true);
  const Encoding encoding = static_cast<Encoding>((c.vtkType + c.order) % 5);
  const std::string path = dir.Path("cell.vtu");
  ASSERT_TRUE(Write(grid, path, encoding));
  const FieldGeometry model = fem::ReadVtu(path);
  ASSERT_EQ(model.geometry.patches.size(), 1u);
  ASSERT_EQ(model.geometry.patches[0].cellTypes.size(), 1u);
  ASSERT_EQ(model.fields.size(), 2u);
  EXPECT_EQ(model.fields[0].name, "f");
  EXPECT_EQ(model.fields[1].components, 3);
  ASSERT_TRUE(CheckFields(model.geometry, model.fields).empty());

  vtkCell* cell = grid->GetCell(0);
  const CellType type = InvmapType(c.vtkType);
  std::mt19937 rng(static_cast<unsigned>(c.vtkType * 31 + c.order));
  std::vector<double> weights(static_cast<std::size_t>(cell->GetNumberOfPoints()));
  vtkDataArray* f = grid->GetPointData()->GetArray("f");
  vtkDataArray* v = grid->GetPointData()->GetArray("v");
  for (int trial = 0; trial < 40; ++trial) {
    const std::array<double, 3> r = RandomReferencePoint(type, rng);
    double pcoords[3] = {r[0], r[1], r[2]};
    double x[3];
    int subId = 0;
    cell->EvaluateLocation(subId, pcoords, x, weights.data());
    double fv = 0.0, vv[3] = {0, 0, 0};
    for (std::size_t i = 0; i < weights.size(); ++i) {
      fv += weights[i] * f->GetComponent(static_cast<vtkIdType>(i), 0);
      for (int k = 0; k < 3; ++k) vv[k] += weights[i] * v->GetComponent(static_cast<vtkIdType>(i), k);
    }
    const std::vector<double> mine = EvaluateAt(model.geometry, nullptr, 0, 0, r);
    ASSERT_EQ(mine.size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mine[k], x[k], 1e-12) << "coordinate " << k << " at trial " << trial;
    // Relative to the values: the second component reaches a few hundred.
    EXPECT_NEAR(EvaluateAt(model.geometry, &model.fields[0], 0, 0, r)[0], fv, 1e-12 * std::max(1.0, std::abs(fv)))
        << "trial " << trial;
    const std::vector<double> vector = EvaluateAt(model.geometry, &model.fields[1], 0, 0, r);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(vector[k], vv[k], 1e-12 * std::max(1.0, std::abs(vv[k]))) << "component " << k;
    }
  }
}

// Inverting points of a volume cell gives back VTK's parametric
// coordinates; points of a surface or curve cell are found on it.
TEST_P(VtuCellTest, ParametersRoundTrip) {
  const VtkCase c = GetParam();
  const ScratchDir dir;
  const vtkSmartPointer<vtkUnstructuredGrid> grid = MakeGrid(c, true);
  const ReadBack read = WriteReadAndBuild(grid, dir.Path("cell.vtu"), Encoding::Appended);
  ExpectVtkPointsRoundTrip(read.built.manifold, grid->GetCell(0), InvmapType(c.vtkType),
                           static_cast<unsigned>(c.vtkType + 7 * c.order), 50);
}

class VtuFieldTest : public ::testing::TestWithParam<VtkCase> {};

// A polynomial field of the element's complete degree on an affine cell is
// reproduced exactly by probe (the interpolant of such a field is the
// field itself).
TEST_P(VtuFieldTest, PolynomialFieldReproducedByProbe) {
  const VtkCase c = GetParam();
  const ScratchDir dir;
  const vtkSmartPointer<vtkUnstructuredGrid> grid = MakeGrid(c, false);
  const ReadBack read = WriteReadAndBuild(grid, dir.Path("cell.vtu"), Encoding::BinaryZlib);
  const FieldGeometry& model = read.model;
  const Manifold& manifold = read.built.manifold;
  const CellType type = InvmapType(c.vtkType);
  std::mt19937 rng(static_cast<unsigned>(3 * c.vtkType + c.order));
  std::vector<double> xyz;
  for (int trial = 0; trial < 40; ++trial) {
    const std::array<double, 3> r = RandomReferencePoint(type, rng, 0.01);
    const std::array<double, 3> x = Place(r.data(), false, IsAxisAligned(c.vtkType));
    xyz.insert(xyz.end(), x.begin(), x.end());
  }
  Results results;
  ASSERT_EQ(manifold.Invert(PointsView::Interleaved(xyz.data(), 40, 3), {}, &results), Error::Ok);
  std::vector<double> values;
  ASSERT_EQ(ProbeFields(model.geometry, {&model.fields[0]}, results, &values), Error::Ok);
  for (int i = 0; i < 40; ++i) {
    const std::array<double, 3> x{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
    EXPECT_NEAR(values[i], Polynomial(x, c.completeDegree), 1e-10) << "point " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(AllVtkCells, VtuCellTest, ::testing::ValuesIn(AllCases()), CaseName);

/// The cases whose nodes interpolate (all but VTK's Bezier cells).
std::vector<VtkCase> InterpolatoryCases() {
  std::vector<VtkCase> cases;
  for (const VtkCase& c : AllCases()) {
    if (!IsBezier(c.vtkType)) cases.push_back(c);
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(InterpolatoryVtkCells, VtuFieldTest, ::testing::ValuesIn(InterpolatoryCases()), CaseName);

// Every encoding of VTK's writer gives the same geometry and fields, bit for bit.
TEST(VtuReader, EveryEncodingReadsTheSame) {
  const ScratchDir dir;
  const vtkSmartPointer<vtkUnstructuredGrid> grid = MakeGrid({VTK_LAGRANGE_HEXAHEDRON, 3, 3}, true);
  std::vector<FieldGeometry> models;
  for (int e = 0; e < 5; ++e) {
    const std::string path = dir.Path("grid" + std::to_string(e) + ".vtu");
    ASSERT_TRUE(Write(grid, path, static_cast<Encoding>(e)));
    models.push_back(fem::ReadVtu(path));
  }
  for (std::size_t e = 1; e < models.size(); ++e) {
    EXPECT_EQ(models[e].geometry.patches[0].points, models[0].geometry.patches[0].points) << "encoding " << e;
    EXPECT_EQ(models[e].fields[1].patchValues, models[0].fields[1].patchValues) << "encoding " << e;
  }
}

// A flat grid of triangles and quads is a 2D geometry; cells keep their VTK ids.
TEST(VtuReader, FlatGridIsTwoDimensionalAndKeepsCellIds) {
  const ScratchDir dir;
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  for (const auto& p : {std::array<double, 3>{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}}) {
    points->InsertNextPoint(p.data());
  }
  grid->SetPoints(points);
  const vtkIdType quad[4] = {0, 1, 2, 3}, tri[3] = {1, 4, 2};
  grid->InsertNextCell(VTK_QUAD, 4, quad);
  grid->InsertNextCell(VTK_TRIANGLE, 3, tri);
  const std::string path = dir.Path("flat.vtu");
  ASSERT_TRUE(Write(grid, path, Encoding::Ascii));
  const FieldGeometry model = fem::ReadVtu(path);
  EXPECT_EQ(model.geometry.dimension, 2);
  ASSERT_EQ(model.geometry.patches[0].cellTypes.size(), 2u);
  EXPECT_EQ(model.geometry.patches[0].cellTypes[0], CellType::Quad);
  EXPECT_EQ(model.geometry.patches[0].cellTypes[1], CellType::Tri);
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const double p[2] = {1.6, 0.2};
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(p, 1, 2), {}, &results), Error::Ok);
  EXPECT_EQ(results.cell[0], 1);
  EXPECT_EQ(results.distance[0], 0.0);
}

/// Expects ReadVtu(path) to fail naming the file and saying `text`.
void ExpectReadError(const std::string& path, const std::string& text) {
  ExpectInputError([&] { fem::ReadVtu(path); }, {text, path});
}

TEST(VtuReader, BadFilesAreInputErrorsNamingFileAndCell) {
  const ScratchDir dir;
  ExpectReadError(dir.Path("missing.vtu"), "no such file");
  ExpectReadError(dir.Write("text.vtu", "this is not XML\n"), "not a readable VTK unstructured grid");
  // /dev/zero kept VTK's reader busy for good; a sparse file of gigabytes
  // was scanned whole: both are refused at once.
  std::filesystem::create_symlink("/dev/zero", dir.Path("zero.vtu"));
  ExpectReadError(dir.Path("zero.vtu"), "not a regular file");
  const std::string sparse = dir.Write("sparse.vtu", "");
  std::filesystem::resize_file(sparse, std::uintmax_t{2} << 30);
  ExpectReadError(sparse, "it does not start with '<'");
  ExpectReadError(dir.Write("truncated.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n"),
                  "not a readable VTK unstructured grid");
  // A pyramid: VTK reads it, invmap names the cell.
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  for (const auto& p : {std::array<double, 3>{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}, {2, 0, 0}}) {
    points->InsertNextPoint(p.data());
  }
  grid->SetPoints(points);
  const vtkIdType tet[4] = {0, 1, 2, 4}, pyramid[5] = {0, 1, 2, 3, 4};
  grid->InsertNextCell(VTK_TETRA, 4, tet);
  grid->InsertNextCell(VTK_PYRAMID, 5, pyramid);
  ASSERT_TRUE(Write(grid, dir.Path("pyramid.vtu"), Encoding::Ascii));
  ExpectReadError(dir.Path("pyramid.vtu"), "cell 1 (VTK_PYRAMID)");
  vtkNew<vtkUnstructuredGrid> empty;
  empty->SetPoints(points);
  ASSERT_TRUE(Write(empty, dir.Path("empty.vtu"), Encoding::Ascii));
  ExpectReadError(dir.Path("empty.vtu"), "no cells");
  // A Bezier quadrilateral of 2 points whose HigherOrderDegrees promise 6:
  // VTK wrote the 6 shape functions past room for 2 (found by fuzz_fem).
  const std::string degrees =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n<UnstructuredGrid><Piece NumberOfPoints=\"6\" NumberOfCells=\"1\">\n"
      "<CellData HigherOrderDegrees=\"D\"><DataArray type=\"Int32\" Name=\"D\" NumberOfComponents=\"3\" "
      "format=\"ascii\">2 1 1</DataArray></CellData>\n<Points><DataArray type=\"Float64\" "
      "NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 1 1 0.2 0 1 0 0.5 -0.4 0 0.5 1.3 0.5</DataArray>"
      "</Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5"
      "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">2</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">77</DataArray></Cells>\n"
      "</Piece></UnstructuredGrid></VTKFile>\n";
  ExpectReadError(dir.Write("degrees.vtu", degrees),
                  "cell 0 (VTK_BEZIER_QUADRILATERAL): HigherOrderDegrees 2 1 1 give 6 points, the cell has 2");
}

/// A one-cell VTU in VTK's ascii layout: `points` points, one cell of VTK
/// type `vtkType` over all of them, and HigherOrderDegrees `degrees` (an
/// array named `degreesName`) when not empty; format version `version`.
std::string OneCellVtu(int points, int vtkType, const std::string& degrees, const std::string& version = "1.0",
                       const std::string& degreesName = "D") {
  std::string coordinates, ids;
  for (int i = 0; i < points; ++i) {
    coordinates += std::to_string(i % 7) + " " + std::to_string(i % 5) + " " + std::to_string(i % 3) + " ";
    ids += std::to_string(i) + " ";
  }
  const std::string cellData =
      degrees.empty() ? ""
                      : "<CellData HigherOrderDegrees=\"" + degreesName + "\"><DataArray type=\"Float64\" Name=\"" +
                            degreesName + "\" NumberOfComponents=\"3\" format=\"ascii\">" + degrees +
                            "</DataArray></CellData>\n";
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"" + version +
         "\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid><Piece NumberOfPoints=\"" + std::to_string(points) +
         "\" NumberOfCells=\"1\">\n" + cellData +
         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" + coordinates +
         "</DataArray></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">" + ids +
         "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">" + std::to_string(points) +
         "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">" + std::to_string(vtkType) +
         "</DataArray></Cells>\n</Piece></UnstructuredGrid></VTKFile>\n";
}

// HigherOrderDegrees past degree 8, below 1 or fractional are refused before
// VTK evaluates the cell: VTK wrote the 1681 shape functions of orders 40 x
// 40 into room for a 3-point quadrilateral (heap corruption under fuzz_fem)
// and threw std::length_error on negative orders. Cells with more points
// than degree 8 allows never reach VTK either (VTK took minutes on a
// 3000-point Lagrange triangle).
TEST(VtuReader, DegreesAndPointCountsPastDegreeEightAreRefusedNamingTheCell) {
  const ScratchDir dir;
  ExpectReadError(dir.Write("orders40.vtu", OneCellVtu(3, VTK_LAGRANGE_QUADRILATERAL, "40 40 1")),
                  "cell 0 (VTK_LAGRANGE_QUADRILATERAL): HigherOrderDegrees 40 40 1: orders must be whole numbers "
                  "from 1 to 8");
  ExpectReadError(dir.Write("bezier40.vtu", OneCellVtu(3, VTK_BEZIER_QUADRILATERAL, "40 40 1")),
                  "cell 0 (VTK_BEZIER_QUADRILATERAL): HigherOrderDegrees 40 40 1: orders must be");
  ExpectReadError(dir.Write("negative.vtu", OneCellVtu(9, VTK_LAGRANGE_QUADRILATERAL, "-5 2 1")),
                  "HigherOrderDegrees -5 2 1: orders must be whole numbers from 1 to 8");
  ExpectReadError(dir.Write("huge.vtu", OneCellVtu(9, VTK_LAGRANGE_QUADRILATERAL, "1e300 2 1")),
                  "HigherOrderDegrees 1e+300 2 1: orders must be");
  // Hexahedra from files of format 2.2 (VTK drops the degrees of older
  // ones unless the array is named HigherOrderDegrees; see below).
  ExpectReadError(dir.Write("half.vtu", OneCellVtu(8, VTK_LAGRANGE_HEXAHEDRON, "1 1 1.5", "2.2")),
                  "cell 0 (VTK_LAGRANGE_HEXAHEDRON): HigherOrderDegrees 1 1 1.5: orders must be");
  ExpectReadError(dir.Write("zero.vtu", OneCellVtu(3, VTK_LAGRANGE_QUADRILATERAL, "2 0 0")),
                  "HigherOrderDegrees 2 0 0: orders must be");
  ExpectReadError(dir.Write("hex9.vtu", OneCellVtu(27, VTK_LAGRANGE_HEXAHEDRON, "9 9 9", "2.2")),
                  "HigherOrderDegrees 9 9 9: orders must be");
  // A curve's second and third degrees are not read (VTK reads its first).
  const std::string curve = dir.Write("curve.vtu", OneCellVtu(3, VTK_LAGRANGE_CURVE, "2 0 0"));
  EXPECT_NO_THROW(fem::ReadVtu(curve));
  ExpectReadError(dir.Write("curve10.vtu", OneCellVtu(10, VTK_LAGRANGE_CURVE, "")),
                  "cell 0 (VTK_LAGRANGE_CURVE): 10 points, more than a cell of degree 8 has (9)");
  ExpectReadError(dir.Write("triangle.vtu", OneCellVtu(3000, VTK_LAGRANGE_TRIANGLE, "")),
                  "cell 0 (VTK_LAGRANGE_TRIANGLE): 3000 points, more than a cell of degree 8 has (45)");
}

// VTK renumbers the higher-order hexahedra of files before format 2.2 by
// an array named HigherOrderDegrees while reading, unchecked: these
// degrees made it read gigabytes past a 27-point cell's ids (a crash).
// Such hexahedra are refused before VTK reads the degrees; from a file of
// format 2.2 the same cell reads.
TEST(VtuReader, OldFormatHexahedraWithDegreesAreRefusedBeforeVtkRenumbersThem) {
  const ScratchDir dir;
  const std::string crash = "-335544320 -335544320 1073741825";
  const std::string refusal =
      "cell 0 (VTK_LAGRANGE_HEXAHEDRON): a higher-order hexahedron with HigherOrderDegrees in a file of format "
      "version '0.1' (before 2.2)";
  ExpectReadError(dir.Write("crash.vtu", OneCellVtu(27, VTK_LAGRANGE_HEXAHEDRON, crash, "0.1", "HigherOrderDegrees")),
                  refusal);
  ExpectReadError(dir.Write("old.vtu", OneCellVtu(27, VTK_LAGRANGE_HEXAHEDRON, "2 2 2", "0.1", "HigherOrderDegrees")),
                  refusal);
  const std::string current =
      dir.Write("current.vtu", OneCellVtu(27, VTK_LAGRANGE_HEXAHEDRON, "2 2 2", "2.2", "HigherOrderDegrees"));
  EXPECT_NO_THROW(fem::ReadVtu(current));
  ExpectReadError(dir.Write("current_crash.vtu",
                            OneCellVtu(27, VTK_LAGRANGE_HEXAHEDRON, crash, "2.2", "HigherOrderDegrees")),
                  "HigherOrderDegrees -3.35544e+08 -3.35544e+08 1.07374e+09: orders must be");
  // Without hexahedra the old format is read with its degrees.
  const std::string quad =
      dir.Write("quad.vtu", OneCellVtu(6, VTK_LAGRANGE_QUADRILATERAL, "2 1 1", "0.1", "HigherOrderDegrees"));
  EXPECT_NO_THROW(fem::ReadVtu(quad));
}

// A point id past the points, written by hand in VTK's ascii layout.
TEST(VtuReader, PointIdOutOfRangeNamesTheCell) {
  const ScratchDir dir;
  const std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid><Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">\n"
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0</DataArray>"
      "</Points>\n"
      "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 7</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">3</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5</DataArray></Cells>\n"
      "</Piece></UnstructuredGrid></VTKFile>\n";
  ExpectReadError(dir.Write("bad_id.vtu", text), "cell 0 (VTK_TRIANGLE): point id 7 out of range");
  // A piece claiming far more points than the file could hold is refused
  // before VTK sizes its arrays by it.
  std::string huge = text;
  huge.replace(huge.find("NumberOfPoints=\"3\""), 18, "NumberOfPoints=\"90000000000\"");
  ExpectReadError(dir.Write("huge.vtu", huge), "NumberOfPoints 90000000000 does not fit a file of this size");
}

}  // namespace
}  // namespace invmap::testing
