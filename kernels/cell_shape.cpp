#include "kernels/cell_shape.h"

#include <algorithm>

namespace invmap::kernels {

int CellShape::NumFactorsOf(CellType type) {
  switch (type) {
    case CellType::Line:
    case CellType::Tri:
    case CellType::Tet:
      return 1;
    case CellType::Quad:
    case CellType::Wedge:
      return 2;
    case CellType::Hex:
      return 3;
  }
  return 0;
}

int CellShape::ParamDimOf(CellType type) {
  int dim = 0;
  for (int i = 0; i < NumFactorsOf(type); ++i) dim += FactorDimOf(type, i);
  return dim;
}

int CellShape::FactorDimOf(CellType type, int i) {
  switch (type) {
    case CellType::Line:
    case CellType::Quad:
    case CellType::Hex:
      return 1;
    case CellType::Tri:
      return 2;
    case CellType::Tet:
      return 3;
    case CellType::Wedge:
      return i == 0 ? 2 : 1;
  }
  return 0;
}

CellShape::CellShape(CellType type, std::array<int, kMaxFactors> degrees)
    : type_(type), numFactors_(NumFactorsOf(type)) {
  numControlPoints_ = 1;
  for (int i = 0; i < numFactors_; ++i) {
    SimplexFactor& f = factors_[i];
    f.dim = FactorDimOf(type, i);
    f.degree = degrees[i];
    f.offset = paramDim_;
    paramDim_ += f.dim;
    numControlPoints_ *= SimplexBasisSize(f.dim, std::max(f.degree, 0));
  }
}

CellShape CellShape::ScaledDegree(int factor) const {
  std::array<int, kMaxFactors> degrees{};
  for (int i = 0; i < numFactors_; ++i) degrees[i] = factors_[i].degree * factor;
  return CellShape(type_, degrees);
}

bool CellShape::IsValid() const {
  if (numFactors_ == 0) return false;
  for (int i = 0; i < numFactors_; ++i) {
    if (factors_[i].degree < 0 || factors_[i].degree > kMaxDegree) return false;
  }
  return true;
}

}  // namespace invmap::kernels
