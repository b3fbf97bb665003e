#include "bench/peers/probe_meshes.h"

#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace invmap::bench {
namespace {

/// Builds the grid's points, sharing each edge midpoint between cells.
class PointTable {
 public:
  PointTable(vtkPoints* points, vtkDoubleArray* field, int degree) : points_(points), field_(field), degree_(degree) {}

  vtkIdType Add(const std::array<double, 3>& x) {
    field_->InsertNextValue(ExactField(x, degree_));
    return points_->InsertNextPoint(x.data());
  }

  /// The midpoint of edge (a, b), created once.
  vtkIdType Midpoint(vtkIdType a, vtkIdType b) {
    const auto key = std::minmax(a, b);
    const auto it = midpoints_.find(key);
    if (it != midpoints_.end()) return it->second;
    double pa[3], pb[3];
    points_->GetPoint(a, pa);
    points_->GetPoint(b, pb);
    const vtkIdType id = Add({0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])});
    midpoints_.emplace(key, id);
    return id;
  }

 private:
  vtkPoints* points_;
  vtkDoubleArray* field_;
  int degree_;
  std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> midpoints_;
};

}  // namespace

std::array<double, 3> BoxPoint(const std::array<double, 3>& u) {
  return {u[0] + 0.2 * u[1] + 0.1 * u[2], 0.1 * u[0] + 0.9 * u[1] - 0.05 * u[2], -0.1 * u[0] + 0.15 * u[1] + 1.1 * u[2]};
}

double ExactField(const std::array<double, 3>& x, int degree) {
  double v = 0.3 + x[0] - 2.0 * x[1] + 0.5 * x[2];
  if (degree >= 2) v += x[0] * x[1] - 0.75 * x[2] * x[2] + 0.5 * x[0] * x[2];
  return v;
}

std::string ProbeMeshName(const ProbeMeshKind& kind) {
  return std::string(kind.order == 1 ? "linear " : "quadratic ") + (kind.hexes ? "hexes" : "tets");
}

vtkSmartPointer<vtkUnstructuredGrid> MakeProbeMesh(const ProbeMeshKind& kind, int cells) {
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto field = vtkSmartPointer<vtkDoubleArray>::New();
  field->SetName("f");
  PointTable table(points, field, kind.order);
  const int n = cells;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<vtkIdType> vertex(static_cast<std::size_t>((n + 1) * (n + 1) * (n + 1)));
  for (int k = 0; k <= n; ++k) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        std::array<double, 3> u{double(i) / n, double(j) / n, double(k) / n};
        // Interior tetrahedron vertices move; hexahedra stay parallelepipeds.
        if (!kind.hexes && i > 0 && i < n && j > 0 && j < n && k > 0 && k < n) {
          for (double& c : u) c += jitter(rng) / n;
        }
        vertex[i + (n + 1) * (j + (n + 1) * k)] = table.Add(BoxPoint(u));
      }
    }
  }
  const auto v = [&](int i, int j, int k) { return vertex[i + (n + 1) * (j + (n + 1) * k)]; };
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const vtkIdType c[8] = {v(i, j, k),         v(i + 1, j, k),     v(i + 1, j + 1, k),     v(i, j + 1, k),
                                v(i, j, k + 1),     v(i + 1, j, k + 1), v(i + 1, j + 1, k + 1), v(i, j + 1, k + 1)};
        if (kind.hexes) {
          if (kind.order == 1) {
            grid->InsertNextCell(VTK_HEXAHEDRON, 8, c);
            continue;
          }
          // VTK_QUADRATIC_HEXAHEDRON: bottom edges, top edges, vertical edges.
          static const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                           {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
          vtkIdType ids[20];
          for (int a = 0; a < 8; ++a) ids[a] = c[a];
          for (int e = 0; e < 12; ++e) ids[8 + e] = table.Midpoint(c[edges[e][0]], c[edges[e][1]]);
          grid->InsertNextCell(VTK_QUADRATIC_HEXAHEDRON, 20, ids);
          continue;
        }
        // Six tetrahedra around the diagonal 0-6, positively oriented.
        static const int tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                       {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        for (const auto& t : tets) {
          vtkIdType ids[10] = {c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
          if (kind.order == 1) {
            grid->InsertNextCell(VTK_TETRA, 4, ids);
            continue;
          }
          // VTK_QUADRATIC_TETRA: edges (0,1) (1,2) (2,0) (0,3) (1,3) (2,3).
          static const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
          for (int e = 0; e < 6; ++e) ids[4 + e] = table.Midpoint(ids[edges[e][0]], ids[edges[e][1]]);
          grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
        }
      }
    }
  }
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(field);
  return grid;
}

}  // namespace invmap::bench
