#include "fem/lagrange_cells.h"

#include <algorithm>

#include "kernels/cell_shape.h"

namespace invmap::fem {
namespace {

/// A rational element's control values: `nodal` holds numNodes() rows of
/// `components` values, `control` receives numControlPoints() rows and
/// `controlWeights` (if not null) their weights. A control point that
/// copies a node takes its values and weight unchanged, bit for bit, as
/// LagrangeToBernstein::Apply does; a zero coefficient leaves its node out
/// (a node without a field value spoils only what it contributes to).
void ApplyRational(const io::LagrangeToBernstein& c, const double* nodal, int components, const double* nodeWeights,
                   double* control, double* controlWeights) {
  const std::size_t n = static_cast<std::size_t>(components);
  for (int i = 0; i < c.numControlPoints(); ++i) {
    double* out = control + i * n;
    if (const int j = c.copiedNode(i); j >= 0) {
      std::copy_n(nodal + j * n, n, out);
      if (controlWeights != nullptr) controlWeights[i] = nodeWeights[j];
      continue;
    }
    std::fill_n(out, n, 0.0);
    double weight = 0.0;
    for (int j = 0; j < c.numNodes(); ++j) {
      const double cw = c.coefficient(i, j) * nodeWeights[j];
      if (cw == 0.0) continue;
      weight += cw;
      for (std::size_t k = 0; k < n; ++k) out[k] += cw * nodal[j * n + k];
    }
    for (std::size_t k = 0; k < n; ++k) out[k] /= weight;
    if (controlWeights != nullptr) controlWeights[i] = weight;
  }
}

}  // namespace

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
  elements_.push_back({type, degree, &converter, elementNodes_.size(), -1});
  elementNodes_.insert(elementNodes_.end(), elementNodes, elementNodes + converter.numNodes());
}

void LagrangePatchBuilder::AddRationalElement(CellType type, int degree, const io::LagrangeToBernstein& converter,
                                              const std::int64_t* elementNodes, const double* nodeWeights) {
  elements_.push_back({type, degree, &converter, elementNodes_.size(), static_cast<std::ptrdiff_t>(nodeWeights_.size())});
  elementNodes_.insert(elementNodes_.end(), elementNodes, elementNodes + converter.numNodes());
  nodeWeights_.insert(nodeWeights_.end(), nodeWeights, nodeWeights + converter.numNodes());
}

Patch LagrangePatchBuilder::MakePatch(int dim) const {
  Patch patch;
  patch.kind = Patch::Kind::BezierCells;
  std::size_t numPoints = 0;
  for (const Element& e : elements_) numPoints += static_cast<std::size_t>(e.converter->numControlPoints());
  patch.points.resize(numPoints * static_cast<std::size_t>(dim));
  if (!nodeWeights_.empty()) patch.weights.assign(numPoints, 1.0);
  patch.cellTypes.reserve(elements_.size());
  patch.cellDegrees.reserve(3 * elements_.size());
  patch.cellOffsets.reserve(elements_.size() + 1);
  patch.cellOffsets.push_back(0);
  std::vector<double> nodal, control;
  std::int64_t point = 0;
  for (const Element& e : elements_) {
    const int n = e.converter->numNodes();
    nodal.resize(3 * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      const std::size_t node = static_cast<std::size_t>(elementNodes_[e.firstNode + j]);
      for (int k = 0; k < 3; ++k) nodal[3 * j + k] = nodes_[3 * node + k];
    }
    if (e.firstWeight < 0) {
      e.converter->Apply(nodal.data(), dim, patch.points.data() + point * dim);
    } else {
      control.resize(3 * static_cast<std::size_t>(e.converter->numControlPoints()));
      ApplyRational(*e.converter, nodal.data(), 3, nodeWeights_.data() + e.firstWeight, control.data(),
                    patch.weights.data() + point);
      for (int i = 0; i < e.converter->numControlPoints(); ++i) {
        std::copy_n(control.data() + 3 * i, dim, patch.points.data() + (point + i) * dim);
      }
    }
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
    if (e.firstWeight < 0) {
      c.ApplyToValues(element.data(), components, out.data() + first);
    } else {
      ApplyRational(c, element.data(), components, nodeWeights_.data() + e.firstWeight, out.data() + first, nullptr);
    }
  }
  return out;
}

}  // namespace invmap::fem
