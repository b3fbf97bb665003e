// Rational VTK Bezier cells (a RationalWeights point data attribute) read
// by the VTU reader: every Bezier type at several orders against VTK's own
// rational evaluation (vtkCell::EvaluateLocation and its interpolation
// functions on the grid VTK's reader reads from the same file), parameter
// round trips, and exact conics whose answers are analytic: a quarter
// circle and a quarter annulus solid of anisotropic orders.
#include <gtest/gtest.h>
#include <vtkBezierHexahedron.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>

#include "fem/vtk_cells.h"
#include "fem/vtu_reader.h"
#include "tests/fem/fem_test_support.h"
#include "tests/fem/vtk_test_cells.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ScratchDir;

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kPi = 3.14159265358979323846;

struct BezierCase {
  int vtkType;
  int order;
};

std::vector<BezierCase> BezierCases() {
  std::vector<BezierCase> cases;
  for (int type : {VTK_BEZIER_CURVE, VTK_BEZIER_TRIANGLE, VTK_BEZIER_QUADRILATERAL}) {
    for (int order = 1; order <= 4; ++order) cases.push_back({type, order});
  }
  for (int type : {VTK_BEZIER_TETRAHEDRON, VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE}) {
    for (int order = 1; order <= 3; ++order) cases.push_back({type, order});
  }
  return cases;
}

std::string CaseName(const ::testing::TestParamInfo<BezierCase>& info) {
  return fem::VtkCellTypeName(info.param.vtkType).substr(4) + "_order" + std::to_string(info.param.order);
}

CellType InvmapType(int vtkType) {
  CellType type = CellType::Line;
  EXPECT_TRUE(fem::VtkCellTypeToInvmap(vtkType, &type));
  return type;
}

/// A weights array named "W" and made the point data's rational weights.
vtkSmartPointer<vtkDoubleArray> AddRationalWeights(vtkUnstructuredGrid* grid, const std::vector<double>& weights) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName("W");
  for (double w : weights) array->InsertNextValue(w);
  grid->GetPointData()->SetRationalWeights(array);
  return array;
}

/// A one-cell grid of a Bezier type: nodes placed by Place (curved),
/// weights from 0.4 to 2.5 varying from node to node, point data "f".
vtkSmartPointer<vtkUnstructuredGrid> MakeRationalGrid(const BezierCase& c) {
  const vtkSmartPointer<vtkCell> reference = MakeReferenceCell(c.vtkType, c.order);
  const int n = static_cast<int>(reference->GetNumberOfPoints());
  const double* pcoords = reference->GetParametricCoords();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> f;
  f->SetName("f");
  vtkNew<vtkIdList> ids;
  std::vector<double> weights;
  for (int i = 0; i < n; ++i) {
    const std::array<double, 3> x = Place(pcoords + 3 * i, true);
    points->InsertNextPoint(x.data());
    f->InsertNextValue(std::sin(3.0 * x[0]) + x[1] * x[2] + 0.1 * i);
    weights.push_back(0.4 + 2.1 * std::fmod(0.37 + 0.618034 * i, 1.0));
    ids->InsertNextId(i);
  }
  grid->SetPoints(points);
  grid->InsertNextCell(c.vtkType, ids);
  grid->GetPointData()->AddArray(f);
  AddRationalWeights(grid, weights);
  return grid;
}

/// The grid VTK's own reader reads from `path`.
vtkSmartPointer<vtkUnstructuredGrid> ReadWithVtk(const std::string& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

class RationalVtuCellTest : public ::testing::TestWithParam<BezierCase> {};

// The map and the field agree with VTK's rational evaluation of the file
// (as VTK's reader reads it) at random parametric coordinates; the weights
// matter (VTK's rational functions differ from its polynomial ones there).
TEST_P(RationalVtuCellTest, MatchesVtkRationalEvaluation) {
  const BezierCase c = GetParam();
  const ScratchDir dir;
  const std::string path = dir.Path("rational.vtu");
  ASSERT_TRUE(Write(MakeRationalGrid(c), path, static_cast<Encoding>((c.vtkType + c.order) % 5)));
  const FieldGeometry model = fem::ReadVtu(path);
  ASSERT_EQ(model.fields.size(), 1u) << "the weights are not a field";
  EXPECT_EQ(model.fields[0].name, "f");
  ASSERT_TRUE(CheckFields(model.geometry, model.fields).empty());
  const Patch& patch = model.geometry.patches[0];
  ASSERT_EQ(patch.weights.size() * static_cast<std::size_t>(model.geometry.dimension), patch.points.size());

  const vtkSmartPointer<vtkUnstructuredGrid> vtk = ReadWithVtk(path);
  ASSERT_NE(vtk->GetPointData()->GetRationalWeights(), nullptr) << "VTK's reader lost the weights";
  vtkCell* cell = vtk->GetCell(0);
  const vtkSmartPointer<vtkCell> polynomial = MakeReferenceCell(c.vtkType, c.order);
  const std::size_t n = static_cast<std::size_t>(cell->GetNumberOfPoints());
  std::vector<double> rationalBasis(n), polynomialBasis(n);
  vtkDataArray* f = vtk->GetPointData()->GetArray("f");
  const CellType type = InvmapType(c.vtkType);
  std::mt19937 rng(static_cast<unsigned>(c.vtkType * 17 + c.order));
  double largestWeightEffect = 0.0;
  for (int trial = 0; trial < 40; ++trial) {
    const std::array<double, 3> r = RandomReferencePoint(type, rng);
    double pcoords[3] = {r[0], r[1], r[2]};
    double x[3];
    int subId = 0;
    cell->EvaluateLocation(subId, pcoords, x, rationalBasis.data());
    polynomial->InterpolateFunctions(pcoords, polynomialBasis.data());
    double fv = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      fv += rationalBasis[i] * f->GetComponent(static_cast<vtkIdType>(i), 0);
      largestWeightEffect = std::max(largestWeightEffect, std::abs(rationalBasis[i] - polynomialBasis[i]));
    }
    const std::vector<double> mine = EvaluateAt(model.geometry, nullptr, 0, 0, r);
    ASSERT_EQ(mine.size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mine[k], x[k], 1e-12) << "coordinate " << k << " at trial " << trial;
    EXPECT_NEAR(EvaluateAt(model.geometry, &model.fields[0], 0, 0, r)[0], fv, 1e-12 * std::max(1.0, std::abs(fv)))
        << "trial " << trial;
  }
  EXPECT_GT(largestWeightEffect, 1e-3) << "the weights should change VTK's basis";
}

// Points VTK's rational cell maps to are found on it; inside a volume the
// parameters are VTK's parametric coordinates.
TEST_P(RationalVtuCellTest, ParametersRoundTrip) {
  const BezierCase c = GetParam();
  const ScratchDir dir;
  const std::string path = dir.Path("rational.vtu");
  ASSERT_TRUE(Write(MakeRationalGrid(c), path, Encoding::Appended));
  BuildResult built = Manifold::Build(fem::ReadVtu(path).geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const vtkSmartPointer<vtkUnstructuredGrid> vtk = ReadWithVtk(path);
  ExpectVtkPointsRoundTrip(built.manifold, vtk->GetCell(0), InvmapType(c.vtkType),
                           static_cast<unsigned>(c.vtkType + 5 * c.order), 40);
}

INSTANTIATE_TEST_SUITE_P(EveryBezierType, RationalVtuCellTest, ::testing::ValuesIn(BezierCases()), CaseName);

/// The quarter circle of radius 1 as a rational quadratic Bezier curve
/// (control points (1, 0), (1, 1), (0, 1); weights 1, sqrt(2)/2, 1), at t.
std::array<double, 2> QuarterCircle(double t) {
  const double w = kSqrt2 / 2.0;
  const double b0 = (1 - t) * (1 - t), b1 = 2 * t * (1 - t) * w, b2 = t * t;
  const double d = b0 + b1 + b2;
  return {(b0 + b1) / d, (b1 + b2) / d};
}

// A quarter circle of radius 2 written as a rational VTK Bezier curve: the
// distance of every point is its distance to the circle, the closest point
// lies on the ray through it, and the parameter is the circle's own.
TEST(VtuRational, QuarterCircleIsExact) {
  const ScratchDir dir;
  constexpr double kRadius = 2.0, kZ = 0.3;
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  // VTK's node order: the end points, then the interior control point.
  for (const auto& p : {std::array<double, 3>{kRadius, 0, kZ}, {0, kRadius, kZ}, {kRadius, kRadius, kZ}}) {
    points->InsertNextPoint(p.data());
  }
  grid->SetPoints(points);
  const vtkIdType ids[3] = {0, 1, 2};
  grid->InsertNextCell(VTK_BEZIER_CURVE, 3, ids);
  AddRationalWeights(grid, {1.0, 1.0, kSqrt2 / 2.0});
  const std::string path = dir.Path("arc.vtu");
  ASSERT_TRUE(Write(grid, path, Encoding::Ascii));
  BuildResult built = Manifold::Build(fem::ReadVtu(path).geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;

  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0.05, kPi / 2 - 0.05), radius(0.3, 4.0), dz(-0.5, 0.5);
  std::vector<double> xyz, expectedDistance, expectedAngle;
  for (int i = 0; i < 200; ++i) {
    const double theta = angle(rng), rho = radius(rng), h = dz(rng);
    xyz.insert(xyz.end(), {rho * std::cos(theta), rho * std::sin(theta), kZ + h});
    expectedDistance.push_back(std::hypot(rho - kRadius, h));
    expectedAngle.push_back(theta);
  }
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(xyz.data(), 200, 3), {}, &results), Error::Ok);
  for (int i = 0; i < 200; ++i) {
    ASSERT_EQ(results.status[i], Status::Found);
    EXPECT_NEAR(results.distance[i], expectedDistance[i], 1e-12) << "point " << i;
    EXPECT_NEAR(std::atan2(results.closest[3 * i + 1], results.closest[3 * i]), expectedAngle[i], 1e-12);
    const std::array<double, 2> onArc = QuarterCircle(results.params[3 * i]);
    EXPECT_NEAR(std::atan2(onArc[1], onArc[0]), expectedAngle[i], 1e-10) << "point " << i;
  }
}

// A quarter of an annulus swept along z, as one rational Bezier hexahedron
// of orders (2, 1, 1) given by HigherOrderDegrees: inside points are found
// at distance 0 with their radius and height as the second and third
// parameters and their angle from the first; points beyond the outer wall
// are at their radial distance from it.
TEST(VtuRational, QuarterAnnulusSolidIsExact) {
  const ScratchDir dir;
  constexpr double kInner = 1.0, kOuter = 2.5, kHeight = 0.7;
  vtkNew<vtkBezierHexahedron> reference;
  reference->GetPointIds()->SetNumberOfIds(12);
  reference->GetPoints()->SetNumberOfPoints(12);
  reference->Initialize();
  reference->SetOrder(2, 1, 1);
  const double* pcoords = reference->GetParametricCoords();
  const std::array<double, 2> arc[3] = {{1, 0}, {1, 1}, {0, 1}};
  const double arcWeight[3] = {1.0, kSqrt2 / 2.0, 1.0};
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<double> weights;
  std::vector<vtkIdType> ids;
  for (int i = 0; i < 12; ++i) {
    // Node i sits at the Bernstein lattice point of its control point.
    const int a = static_cast<int>(std::lround(2 * pcoords[3 * i]));
    const double rho = pcoords[3 * i + 1] == 0.0 ? kInner : kOuter;
    points->InsertNextPoint(rho * arc[a][0], rho * arc[a][1], kHeight * pcoords[3 * i + 2]);
    weights.push_back(arcWeight[a]);
    ids.push_back(i);
  }
  grid->SetPoints(points);
  grid->InsertNextCell(VTK_BEZIER_HEXAHEDRON, 12, ids.data());
  AddRationalWeights(grid, weights);
  vtkNew<vtkIntArray> degrees;
  degrees->SetName("HigherOrderDegrees");
  degrees->SetNumberOfComponents(3);
  const int orders[3] = {2, 1, 1};
  degrees->InsertNextTypedTuple(orders);
  grid->GetCellData()->SetHigherOrderDegrees(degrees);
  const std::string path = dir.Path("annulus.vtu");
  ASSERT_TRUE(Write(grid, path, Encoding::BinaryZlib));
  const FieldGeometry model = fem::ReadVtu(path);
  BuildResult built = Manifold::Build(model.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.02, kPi / 2 - 0.02), unit(0.02, 0.98),
      beyond(0.01, 1.0);
  std::vector<double> xyz;
  struct Expected {
    double theta, rho, z;
  };
  std::vector<Expected> expected;
  for (int i = 0; i < 150; ++i) {
    const double theta = angle(rng), z = kHeight * unit(rng);
    const double rho = i % 3 == 2 ? kOuter + beyond(rng) : kInner + (kOuter - kInner) * unit(rng);
    xyz.insert(xyz.end(), {rho * std::cos(theta), rho * std::sin(theta), z});
    expected.push_back({theta, rho, z});
  }
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(xyz.data(), expected.size(), 3), {}, &results), Error::Ok);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Expected& e = expected[i];
    ASSERT_EQ(results.status[i], Status::Found);
    const bool outside = e.rho > kOuter;
    EXPECT_NEAR(results.distance[i], outside ? e.rho - kOuter : 0.0, 1e-11) << "point " << i;
    const std::array<double, 2> onArc = QuarterCircle(results.params[3 * i]);
    EXPECT_NEAR(std::atan2(onArc[1], onArc[0]), e.theta, 1e-9) << "point " << i;
    EXPECT_NEAR(results.params[3 * i + 1], outside ? 1.0 : (e.rho - kInner) / (kOuter - kInner), 1e-9);
    EXPECT_NEAR(results.params[3 * i + 2], e.z / kHeight, 1e-9) << "point " << i;
  }
}

// In a grid with rational weights only the Bezier cells are rational, as
// in VTK: a Lagrange cell beside a rational Bezier cell keeps its
// polynomial map, and both agree with VTK's evaluation.
TEST(VtuRational, OnlyBezierCellsAreRational) {
  const ScratchDir dir;
  const vtkSmartPointer<vtkCell> bezier = MakeReferenceCell(VTK_BEZIER_QUADRILATERAL, 2);
  const vtkSmartPointer<vtkCell> lagrange = MakeReferenceCell(VTK_LAGRANGE_QUADRILATERAL, 2);
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<double> weights;
  std::vector<vtkIdType> ids;
  for (int cell = 0; cell < 2; ++cell) {
    const double* pcoords = (cell == 0 ? bezier : lagrange)->GetParametricCoords();
    ids.clear();
    for (int i = 0; i < 9; ++i) {
      std::array<double, 3> x = Place(pcoords + 3 * i, true);
      x[0] += 2.0 * cell;
      ids.push_back(points->InsertNextPoint(x.data()));
      weights.push_back(i % 2 == 0 ? 1.0 : 0.5 + 0.25 * i);
    }
    grid->SetPoints(points);
    grid->InsertNextCell(cell == 0 ? VTK_BEZIER_QUADRILATERAL : VTK_LAGRANGE_QUADRILATERAL, 9, ids.data());
  }
  AddRationalWeights(grid, weights);
  const std::string path = dir.Path("mixed.vtu");
  ASSERT_TRUE(Write(grid, path, Encoding::Binary));
  const FieldGeometry model = fem::ReadVtu(path);
  const vtkSmartPointer<vtkUnstructuredGrid> vtk = ReadWithVtk(path);
  std::vector<double> basis(9);
  std::mt19937 rng(3);
  for (int cell = 0; cell < 2; ++cell) {
    for (int trial = 0; trial < 20; ++trial) {
      const std::array<double, 3> r = RandomReferencePoint(CellType::Quad, rng);
      double pcoords[3] = {r[0], r[1], r[2]};
      double x[3];
      int subId = 0;
      vtk->GetCell(cell)->EvaluateLocation(subId, pcoords, x, basis.data());
      const std::vector<double> mine = EvaluateAt(model.geometry, nullptr, 0, cell, r);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(mine[k], x[k], 1e-12) << "cell " << cell << " coordinate " << k;
    }
  }
}

// A weight that is not positive, or outside the range invmap supports, is an
// input error naming the cell and point.
TEST(VtuRational, BadWeightNamesTheCellAndPoint) {
  const ScratchDir dir;
  for (double bad : {0.0, -1.5, 1e-60, 1e60}) {
    const vtkSmartPointer<vtkUnstructuredGrid> grid = MakeRationalGrid({VTK_BEZIER_TRIANGLE, 2});
    grid->GetPointData()->GetRationalWeights()->SetComponent(4, 0, bad);
    const std::string path = dir.Path("bad_weight.vtu");
    ASSERT_TRUE(Write(grid, path, Encoding::Ascii));
    ExpectInputError([&] { fem::ReadVtu(path); },
                     {path, "cell 0 (VTK_BEZIER_TRIANGLE): point 4 has rational weight", "positive, in [1e-50, 1e50]"});
  }
}

}  // namespace
}  // namespace invmap::testing
