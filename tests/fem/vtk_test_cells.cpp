#include "tests/fem/vtk_test_cells.h"

#include <vtkCellType.h>
#include <vtkGenericCell.h>
#include <vtkHigherOrderHexahedron.h>
#include <vtkHigherOrderQuadrilateral.h>
#include <vtkHigherOrderWedge.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <random>
#include <vector>

#include "tests/fem/fem_test_support.h"

namespace invmap::testing {

int HigherOrderPoints(int vtkType, int order) {
  const int p = order;
  switch (vtkType) {
    case VTK_LAGRANGE_CURVE:
    case VTK_BEZIER_CURVE:
      return p + 1;
    case VTK_LAGRANGE_TRIANGLE:
    case VTK_BEZIER_TRIANGLE:
      return (p + 1) * (p + 2) / 2;
    case VTK_LAGRANGE_QUADRILATERAL:
    case VTK_BEZIER_QUADRILATERAL:
      return (p + 1) * (p + 1);
    case VTK_LAGRANGE_TETRAHEDRON:
    case VTK_BEZIER_TETRAHEDRON:
      return (p + 1) * (p + 2) * (p + 3) / 6;
    case VTK_LAGRANGE_HEXAHEDRON:
    case VTK_BEZIER_HEXAHEDRON:
      return (p + 1) * (p + 1) * (p + 1);
    default:
      return (p + 1) * (p + 1) * (p + 2) / 2;
  }
}

vtkSmartPointer<vtkCell> MakeReferenceCell(int vtkType, int order) {
  vtkSmartPointer<vtkCell> cell;
  cell.TakeReference(vtkGenericCell::InstantiateCell(vtkType));
  if (order > 0) {
    const int n = HigherOrderPoints(vtkType, order);
    cell->GetPointIds()->SetNumberOfIds(n);
    cell->GetPoints()->SetNumberOfPoints(n);
    cell->Initialize();
    if (auto* quad = vtkHigherOrderQuadrilateral::SafeDownCast(cell)) quad->SetUniformOrderFromNumPoints(n);
    if (auto* hex = vtkHigherOrderHexahedron::SafeDownCast(cell)) hex->SetUniformOrderFromNumPoints(n);
    if (auto* wedge = vtkHigherOrderWedge::SafeDownCast(cell)) wedge->SetUniformOrderFromNumPoints(n);
  }
  return cell;
}

std::array<double, 3> Place(const double* r, bool curved, bool aligned) {
  if (aligned) return {0.3 + 1.1 * r[0], -0.2 + 0.9 * r[1], 0.5 + 1.2 * r[2]};
  const double x = 0.3 + 1.1 * r[0] + 0.2 * r[1] - 0.1 * r[2];
  const double y = -0.2 + 0.15 * r[0] + 0.9 * r[1] + 0.25 * r[2];
  const double z = 0.5 - 0.1 * r[0] + 0.2 * r[1] + 1.2 * r[2];
  if (!curved) return {x, y, z};
  return {x + 0.15 * r[1] * r[1] - 0.1 * r[0] * r[2], y + 0.12 * r[0] * r[0] + 0.08 * r[2] * r[2],
          z + 0.2 * r[0] * r[1] + 0.1 * r[0] * r[0]};
}

bool Write(vtkUnstructuredGrid* grid, const std::string& path, Encoding encoding) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->SetCompressorTypeToNone();
  switch (encoding) {
    case Encoding::Ascii:
      writer->SetDataModeToAscii();
      break;
    case Encoding::Binary:
      writer->SetDataModeToBinary();
      break;
    case Encoding::BinaryZlib:
      writer->SetDataModeToBinary();
      writer->SetCompressorTypeToZLib();
      break;
    case Encoding::Appended:
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOn();
      break;
    case Encoding::AppendedRawZlib:
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      writer->SetCompressorTypeToZLib();
      break;
  }
  return writer->Write() == 1;
}

void ExpectVtkPointsRoundTrip(const Manifold& manifold, vtkCell* cell, CellType type, unsigned seed, int count) {
  std::vector<double> basis(static_cast<std::size_t>(cell->GetNumberOfPoints()));
  std::mt19937 rng(seed);
  std::vector<double> xyz;
  std::vector<std::array<double, 3>> expected;
  for (int trial = 0; trial < count; ++trial) {
    const std::array<double, 3> r = RandomReferencePoint(type, rng, 0.02);
    double pcoords[3] = {r[0], r[1], r[2]};
    double x[3];
    int subId = 0;
    cell->EvaluateLocation(subId, pcoords, x, basis.data());
    xyz.insert(xyz.end(), x, x + 3);
    expected.push_back(r);
  }
  Results results;
  ASSERT_EQ(manifold.Invert(PointsView::Interleaved(xyz.data(), expected.size(), 3), {}, &results), Error::Ok);
  const bool volume = type == CellType::Tet || type == CellType::Hex || type == CellType::Wedge;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(results.status[i], Status::Found);
    EXPECT_LT(results.distance[i], 1e-10) << "point " << i;
    if (!volume) continue;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(results.params[3 * i + k], expected[i][k], 1e-9) << "point " << i;
  }
}

}  // namespace invmap::testing
