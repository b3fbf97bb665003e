#include "fem/vtu_reader.h"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "fem/file_checks.h"
#include "fem/lagrange_cells.h"
#include "fem/vtk_cells.h"
#include "fem/vtk_messages.h"
#include "io/lagrange_to_bernstein.h"
#include "io/input_error.h"
#include "kernels/cell_shape.h"

namespace invmap::fem {
namespace {

/// Node coordinates, 3 per point, checked finite.
std::vector<double> ReadNodes(vtkUnstructuredGrid* grid, const std::string& path) {
  const vtkIdType n = grid->GetNumberOfPoints();
  std::vector<double> nodes(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    grid->GetPoint(i, nodes.data() + 3 * i);
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(nodes[3 * i + k])) {
        throw io::InputError(path, 0, "point " + std::to_string(i) + " has a coordinate that is not finite");
      }
    }
  }
  return nodes;
}

/// The numeric point data arrays as node fields over the builder's patch,
/// but for the rational weights (part of the geometry, not a field).
std::vector<NodeField> ReadPointFields(vtkUnstructuredGrid* grid, const LagrangePatchBuilder& builder) {
  std::vector<NodeField> fields;
  std::set<std::string> names;
  vtkPointData* data = grid->GetPointData();
  const vtkIdType n = grid->GetNumberOfPoints();
  for (int a = 0; a < data->GetNumberOfArrays(); ++a) {
    vtkDataArray* array = data->GetArray(a);  // null for non-numeric arrays
    if (array == nullptr || array == data->GetRationalWeights()) continue;
    if (array->GetName() == nullptr || array->GetNumberOfTuples() != n) continue;
    const std::string name = array->GetName();
    if (name.empty() || !names.insert(name).second) continue;
    const int components = array->GetNumberOfComponents();
    if (components < 1) continue;
    std::vector<double> nodal(static_cast<std::size_t>(n) * components);
    for (vtkIdType i = 0; i < n; ++i) array->GetTuple(i, nodal.data() + i * components);
    NodeField& field = fields.emplace_back();
    field.name = name;
    field.components = components;
    field.patchValues.push_back(builder.ConvertField(nodal, components));
  }
  return fields;
}

/// VTK's rational weights of the Bezier cells (the point data array that
/// the RationalWeights attribute names), or null; checked to hold one value
/// per point.
vtkDataArray* RationalWeights(vtkUnstructuredGrid* grid, const std::string& path) {
  vtkDataArray* weights = grid->GetPointData()->GetRationalWeights();
  if (weights == nullptr) return nullptr;
  const std::string name = weights->GetName() == nullptr ? "" : weights->GetName();
  if (weights->GetNumberOfComponents() != 1 || weights->GetNumberOfTuples() != grid->GetNumberOfPoints()) {
    throw io::InputError(path, 0, "rational weights '" + name + "': " +
                                      std::to_string(weights->GetNumberOfComponents()) + " components and " +
                                      std::to_string(weights->GetNumberOfTuples()) + " tuples, expected 1 and " +
                                      std::to_string(grid->GetNumberOfPoints()) + " (one per point)");
  }
  return weights;
}

bool IsBezierType(int vtkType) { return vtkType >= VTK_BEZIER_CURVE && vtkType <= VTK_BEZIER_WEDGE; }

bool IsHigherOrderType(int vtkType) {
  return IsBezierType(vtkType) || (vtkType >= VTK_LAGRANGE_CURVE && vtkType <= VTK_LAGRANGE_WEDGE);
}

/// How many of a cell's HigherOrderDegrees VTK reads: the curve's first,
/// the quadrilateral's first two, the hexahedron's and wedge's three; 0 for
/// other types, whose order VTK takes from their node count.
int OrdersVtkReads(int vtkType, CellType type) {
  if (!IsHigherOrderType(vtkType)) return 0;
  switch (type) {
    case CellType::Line:
      return 1;
    case CellType::Quad:
      return 2;
    case CellType::Hex:
    case CellType::Wedge:
      return 3;
    default:
      return 0;
  }
}

/// The nodes VTK's higher-order curve, quadrilateral, hexahedron or wedge of
/// HigherOrderDegrees `orders` (each in [1, kMaxDegree]) has: VTK evaluates
/// that many shape functions whatever the cell holds.
long long NodesOfOrders(CellType type, const int orders[3]) {
  const long long p = orders[0], q = orders[1], r = orders[2];
  switch (type) {
    case CellType::Line:
      return p + 1;
    case CellType::Quad:
      return (p + 1) * (q + 1);
    case CellType::Hex:
      return (p + 1) * (q + 1) * (r + 1);
    default:  // a wedge: a triangle of order p (= q) times a line of order r
      return p == q ? (p + 1) * (p + 2) / 2 * (r + 1) : 0;
  }
}

/// The HigherOrderDegrees of cell `c` as the orders VTK reads (-1 for those
/// it does not), refused before VTK evaluates the cell when they are not
/// whole numbers in [1, 8] or give another node count than the cell's
/// `count`: VTK writes the shape functions of the degrees' nodes into room
/// for the cell's (heap overflows fuzz_fem found) and throws
/// std::length_error on negative ones.
void ReadCellOrders(vtkDataArray* degrees, vtkIdType c, int vtkType, CellType type, vtkIdType count,
                    const std::string& path, const std::string& where, int orders[3]) {
  const int used = OrdersVtkReads(vtkType, type);
  if (degrees == nullptr || degrees->GetNumberOfComponents() != 3 || c >= degrees->GetNumberOfTuples() ||
      used == 0) {
    return;
  }
  std::ostringstream text;
  for (int k = 0; k < 3; ++k) text << (k == 0 ? "" : " ") << degrees->GetComponent(c, k);
  for (int k = 0; k < used; ++k) {
    const double order = degrees->GetComponent(c, k);
    if (!(order >= 1.0 && order <= kernels::kMaxDegree) || order != std::floor(order)) {
      throw io::InputError(path, 0, where + ": HigherOrderDegrees " + text.str() +
                                        ": orders must be whole numbers from 1 to " +
                                        std::to_string(kernels::kMaxDegree));
    }
    orders[k] = static_cast<int>(order);
  }
  const int full[3] = {orders[0], used > 1 ? orders[1] : 1, used > 2 ? orders[2] : 1};
  const long long expected = NodesOfOrders(type, full);
  if (expected != count) {
    throw io::InputError(path, 0, where + ": HigherOrderDegrees " + text.str() + " give " +
                                      std::to_string(expected) + " points, the cell has " + std::to_string(count));
  }
}

/// What the XML headers say beyond the sizes CheckDeclaredSizes checks.
struct VtuHeaders {
  /// The VTKFile element's version attribute ("" when there is none).
  std::string version;
  /// Whether an array is named HigherOrderDegrees (VTK takes the orders of
  /// higher-order hexahedra from it while reading a file before 2.2).
  bool namesDegrees = false;
};

/// Whether VTK renumbers the higher-order hexahedra of a file of `version`
/// from VTK 8's node order (files before format 2.2, or without a version
/// VTK can parse).
bool BeforeFormat22(const std::string& version) {
  int major = -1, minor = -1;
  if (std::sscanf(version.c_str(), "%d.%d", &major, &minor) != 2) return true;
  return major < 2 || (major == 2 && minor < 2);
}

/// Checks the sizes the file's XML declares (points, cells, components of
/// each piece and array) against the file's size before VTK allocates them:
/// VTK sizes its arrays by what the header says. Scans up to the appended
/// data (all headers come before it), or the whole file.
VtuHeaders CheckDeclaredSizes(const std::string& path) {
  VtuHeaders headers;
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  const double bytes = static_cast<double>(std::filesystem::file_size(path, error));
  // Compressed data can hold far more values than bytes; a thousandfold is
  // generous for real meshes and still bounds a corrupt header's claim.
  const double limit = 1000.0 * bytes + 1e6;
  static const char* kCounts[] = {"NumberOfPoints=\"", "NumberOfCells=\"", "NumberOfComponents=\""};
  std::string window;
  char chunk[1 << 16];
  // An XML document starts with '<' (after white space or a byte order
  // mark): anything else, such as a sparse file's zeros, is refused before
  // gigabytes of it are scanned.
  if (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    const std::string_view start(chunk, static_cast<std::size_t>(in.gcount()));
    const std::size_t first = start.find_first_not_of(" \t\r\n\xef\xbb\xbf");
    if (first == std::string_view::npos || start[first] != '<') {
      throw io::InputError(path, 0,
                           "not a readable VTK unstructured grid: it does not start with '<' (not an XML file)");
    }
    if (const std::size_t file = start.find("<VTKFile"); file != std::string_view::npos) {
      const std::size_t at = start.find("version=\"", file);
      const std::size_t end = at == std::string_view::npos ? at : start.find('"', at + 9);
      if (end != std::string_view::npos && end - file < 4096) headers.version = start.substr(at + 9, end - at - 9);
    }
    in.clear();
    in.seekg(0);
  }
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    // Keep the tail of the previous chunk: a match may straddle the boundary.
    window = window.substr(window.size() > 64 ? window.size() - 64 : 0) + std::string(chunk, in.gcount());
    for (const char* key : kCounts) {
      for (std::size_t at = window.find(key); at != std::string::npos; at = window.find(key, at + 1)) {
        const std::size_t start = at + std::strlen(key);
        const std::size_t end = window.find('"', start);
        if (end == std::string::npos) break;
        const double count = std::strtod(window.substr(start, end - start).c_str(), nullptr);
        if (!(count <= limit)) {
          throw io::InputError(path, 0, std::string(key).substr(0, std::strlen(key) - 2) + " " +
                                            window.substr(start, end - start) + " does not fit a file of this size");
        }
      }
    }
    headers.namesDegrees = headers.namesDegrees || window.find("\"HigherOrderDegrees\"") != std::string::npos;
    if (window.find("<AppendedData") != std::string::npos) return headers;
  }
  return headers;
}

/// VTK renumbers the higher-order hexahedra of a file before format 2.2
/// from VTK 8's node order while reading, by the HigherOrderDegrees array
/// unchecked: degrees that do not fit a hexahedron's nodes made VTK read
/// far past its arrays (a crash fuzz_fem found). Such a file is read first
/// without that array; a higher-order hexahedron among its cells is refused
/// before VTK reads the degrees.
void RefuseHexahedraRenumberedByDegrees(const std::string& path, const VtuHeaders& headers,
                                        const ScopedVtkMessages& messages) {
  if (!headers.namesDegrees || !BeforeFormat22(headers.version)) return;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  reader->SetCellArrayStatus("HigherOrderDegrees", 0);
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!messages.FirstError().empty() || reader->GetErrorCode() != 0 || grid == nullptr) {
    const std::string why = messages.FirstError().empty() ? "VTK's XML reader failed" : messages.FirstError();
    throw io::InputError(path, 0, "not a readable VTK unstructured grid: " + why);
  }
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int vtkType = grid->GetCellType(c);
    if (vtkType == VTK_HIGHER_ORDER_HEXAHEDRON || vtkType == VTK_LAGRANGE_HEXAHEDRON ||
        vtkType == VTK_BEZIER_HEXAHEDRON) {
      throw io::InputError(path, 0, "cell " + std::to_string(c) + " (" + VtkCellTypeName(vtkType) +
                                        "): a higher-order hexahedron with HigherOrderDegrees in a file of format " +
                                        "version '" + headers.version + "' (before 2.2), whose nodes VTK renumbers "
                                        "by those degrees before they can be checked; invmap reads such cells "
                                        "from files of version 2.2 or later (VTK 9.1 writes them)");
    }
  }
}

}  // namespace

FieldGeometry ReadVtu(const std::string& path) {
  RequireReadableFile(path);
  const VtuHeaders headers = CheckDeclaredSizes(path);
  ScopedVtkMessages messages;
  RefuseHexahedraRenumberedByDegrees(path, headers, messages);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!messages.FirstError().empty() || reader->GetErrorCode() != 0 || grid == nullptr) {
    const std::string why = messages.FirstError().empty() ? "VTK's XML reader failed" : messages.FirstError();
    throw io::InputError(path, 0, "not a readable VTK unstructured grid: " + why);
  }
  const vtkIdType numCells = grid->GetNumberOfCells();
  if (numCells == 0) throw io::InputError(path, 0, "no cells");

  const std::vector<double> nodes = ReadNodes(grid, path);
  const vtkIdType numNodes = grid->GetNumberOfPoints();
  // With rational weights VTK's Bezier cells evaluate rationally; their
  // change of basis is learned from the same grid without the weights (the
  // Bernstein polynomials in VTK's node order), and the weights applied in
  // homogeneous coordinates (lagrange_cells.h).
  vtkDataArray* rationalWeights = RationalWeights(grid, path);
  vtkNew<vtkUnstructuredGrid> polynomialGrid;
  if (rationalWeights != nullptr) {
    polynomialGrid->ShallowCopy(grid);
    polynomialGrid->GetPointData()->SetRationalWeights(nullptr);
  }
  vtkUnstructuredGrid* shapeGrid = rationalWeights != nullptr ? polynomialGrid.Get() : grid;
  std::vector<double> cellWeights;
  vtkDataArray* degrees = grid->GetCellData()->GetHigherOrderDegrees();
  VtkCellConversions conversions;
  bool anyVolume = false;
  std::vector<std::int64_t> elementNodes;
  LagrangePatchBuilder builder(nodes);
  for (vtkIdType c = 0; c < numCells; ++c) {
    const int vtkType = grid->GetCellType(c);
    const std::string where = "cell " + std::to_string(c) + " (" + VtkCellTypeName(vtkType) + ")";
    CellType type;
    if (!VtkCellTypeToInvmap(vtkType, &type)) {
      throw io::InputError(path, 0, where + ": invmap does not read this cell type (it reads lines, triangles, "
                                            "quadrilaterals, tetrahedra, hexahedra and wedges: linear, quadratic, "
                                            "Lagrange and Bezier)");
    }
    vtkIdType count = 0;
    const vtkIdType* points = nullptr;
    grid->GetCellPoints(c, count, points);
    for (vtkIdType j = 0; j < count; ++j) {
      if (points[j] < 0 || points[j] >= numNodes) {
        throw io::InputError(path, 0, where + ": point id " + std::to_string(points[j]) + " out of range [0, " +
                                          std::to_string(numNodes) + ")");
      }
    }
    // More nodes than a cell of degree 8 has are refused before VTK
    // evaluates them (VTK's Lagrange triangle of 3000 nodes took minutes).
    const int most = io::BernsteinCount(type, kernels::kMaxDegree);
    if (count > most) {
      throw io::InputError(path, 0, where + ": " + std::to_string(count) + " points, more than a cell of degree " +
                                        std::to_string(kernels::kMaxDegree) + " has (" + std::to_string(most) +
                                        ")");
    }
    int orders[3] = {-1, -1, -1};
    ReadCellOrders(degrees, c, vtkType, type, count, path, where, orders);
    const VtkCellConversion* conversion = conversions.Find(shapeGrid, c, orders);
    if (conversion == nullptr || conversion->converter.numNodes() != count) {
      throw io::InputError(path, 0, where + ": " + std::to_string(count) +
                                        " points, whose VTK shape functions are not a polynomial of degree 8 or "
                                        "less (a malformed cell)");
    }
    elementNodes.assign(points, points + count);
    if (rationalWeights != nullptr && IsBezierType(vtkType)) {
      cellWeights.resize(static_cast<std::size_t>(count));
      for (vtkIdType j = 0; j < count; ++j) {
        cellWeights[j] = rationalWeights->GetComponent(points[j], 0);
        const double w = cellWeights[j];
        if (!(w > 0.0) || !std::isfinite(w) || w > kernels::kMaxWeight || w < 1.0 / kernels::kMaxWeight) {
          std::ostringstream text;
          text << where << ": point " << points[j] << " has rational weight " << w
               << " (weights must be positive, in [1e-50, 1e50])";
          throw io::InputError(path, 0, text.str());
        }
      }
      builder.AddRationalElement(conversion->type, conversion->degree, conversion->converter, elementNodes.data(),
                                 cellWeights.data());
    } else {
      builder.AddElement(conversion->type, conversion->degree, conversion->converter, elementNodes.data());
    }
    anyVolume = anyVolume || ParamDimOf(conversion->type) == 3;
  }

  FieldGeometry out;
  out.geometry.dimension = GeometryDimension(nodes, anyVolume);
  out.geometry.patches.push_back(builder.MakePatch(out.geometry.dimension));
  out.fields = ReadPointFields(grid, builder);
  return out;
}

}  // namespace invmap::fem
