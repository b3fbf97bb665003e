#include "fem/lagrange_cells.h"

#include <algorithm>

#include "kernels/cell_shape.h"

namespace invmap::fem {

int ParamDimOf(CellType type) { return kernels::CellShape::ParamDimOf(static_cast<kernels::CellType>(type)); }

int GeometryDimension(const std::vector<double>& nodes, bool anyVolume) {
  if (anyVolume) return 3;
  for (std::size_t i = 2; i < nodes.size(); i += 3) {
    if (nodes[i] != 0.0) return 3;
  }
  return 2;
}

void LagrangePatchBuilder::AddElement(CellType type, int degree, const io::LagrangeToBernstein& converter,
                                      const std::int64_t* elementNodes) {
  elements_.push_back({type, degree, &converter, elementNodes_.size()});
  elementNodes_.insert(elementNodes_.end(), elementNodes, elementNodes + converter.numNodes());
}

Patch LagrangePatchBuilder::MakePatch(int dim) const {
  Patch patch;
  patch.kind = Patch::Kind::BezierCells;
  std::size_t numPoints = 0;
  for (const Element& e : elements_) numPoints += static_cast<std::size_t>(e.converter->numControlPoints());
  patch.points.resize(numPoints * static_cast<std::size_t>(dim));
  patch.cellTypes.reserve(elements_.size());
  patch.cellDegrees.reserve(3 * elements_.size());
  patch.cellOffsets.reserve(elements_.size() + 1);
  patch.cellOffsets.push_back(0);
  std::vector<double> nodal;
  std::int64_t point = 0;
  for (const Element& e : elements_) {
    const int n = e.converter->numNodes();
    nodal.resize(3 * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      const std::size_t node = static_cast<std::size_t>(elementNodes_[e.firstNode + j]);
      for (int k = 0; k < 3; ++k) nodal[3 * j + k] = nodes_[3 * node + k];
    }
    e.converter->Apply(nodal.data(), dim, patch.points.data() + point * dim);
    point += e.converter->numControlPoints();
    patch.cellTypes.push_back(e.type);
    const std::array<int, 3> degrees = io::UniformDegrees(e.type, e.degree);
    patch.cellDegrees.insert(patch.cellDegrees.end(), degrees.begin(), degrees.end());
    patch.cellOffsets.push_back(point);
  }
  return patch;
}

std::vector<double> LagrangePatchBuilder::ConvertField(const std::vector<double>& nodal, int components) const {
  const std::size_t n = static_cast<std::size_t>(components);
  std::vector<double> out;
  std::vector<double> element;
  for (const Element& e : elements_) {
    const io::LagrangeToBernstein& c = *e.converter;
    element.resize(c.numNodes() * n);
    for (int j = 0; j < c.numNodes(); ++j) {
      std::copy_n(nodal.data() + elementNodes_[e.firstNode + j] * n, n, element.data() + j * n);
    }
    const std::size_t first = out.size();
    out.resize(first + c.numControlPoints() * n);
    c.ApplyToValues(element.data(), components, out.data() + first);
  }
  return out;
}

}  // namespace invmap::fem
