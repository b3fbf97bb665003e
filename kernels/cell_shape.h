// Cell types as tensor products of simplices (docs/formats.md section 1).
#pragma once

#include <array>
#include <cstdint>

#include "invmap/cell_type.h"

namespace invmap::kernels {

/// The public cell type (invmap/cell_type.h), named here as kernel code names it.
using invmap::CellType;

/// Largest number of simplex factors in a cell (hex = line x line x line).
constexpr int kMaxFactors = 3;
/// Largest parametric and ambient dimension.
constexpr int kMaxDim = 3;
/// Largest supported degree per factor.
constexpr int kMaxDegree = 8;
/// Weights of rational cells lie in [1 / kMaxWeight, kMaxWeight]: their
/// squares and products in the distance nets stay far from overflow and
/// underflow, and the tests hold ratios up to kMaxWeight^2 = 1e100.
constexpr double kMaxWeight = 1e50;
/// Control point coordinates lie in [-kMaxCoordinate, kMaxCoordinate], and a
/// geometry of any extent is at least kMinExtent across (its box diagonal):
/// squared distances and their tolerances (1e-11 of a cell's size, squared)
/// then stay normal doubles. Near 1e154 the squares overflow, near 1e-154
/// they underflow, and answers there went wrong (QA: a sphere scaled by
/// 1e155 or 1e-170).
constexpr double kMaxCoordinate = 1e100;
constexpr double kMinExtent = 1e-100;

/// One simplex factor of a cell: its dimension, its polynomial degree and the
/// offset of its free coordinates inside the cell's parameter vector.
struct SimplexFactor {
  int dim = 0;     ///< 1 (line), 2 (tri) or 3 (tet).
  int degree = 0;  ///< Polynomial degree, 0..kMaxDegree.
  int offset = 0;  ///< Index of the factor's first coordinate in the cell's parameters.
};

/// Number of multi-indices of total degree `degree` in `dim` free variables:
/// the number of Bernstein polynomials (control points) of a simplex factor.
constexpr int SimplexBasisSize(int dim, int degree) {
  int n = 1;
  for (int k = 1; k <= dim; ++k) n = n * (degree + k) / k;
  return n;
}

/// A cell type with its per-factor degrees: everything needed to size and
/// index its control net. Degrees are listed per simplex factor as in
/// docs/formats.md (line [p], tri [p], quad [p, q], tet [p], hex [p, q, r],
/// wedge [p_tri, q_line]).
class CellShape {
 public:
  CellShape() = default;
  /// Precondition: `degrees` holds one entry per factor of `type`, each in
  /// [0, kMaxDegree] (checked by IsValid, not here).
  CellShape(CellType type, std::array<int, kMaxFactors> degrees);

  CellType type() const { return type_; }
  int numFactors() const { return numFactors_; }
  const SimplexFactor& factor(int i) const { return factors_[i]; }
  /// Parametric dimension: 1 for curves, 2 for surfaces, 3 for volumes.
  int paramDim() const { return paramDim_; }
  /// Number of control points, the product of the factors' basis sizes.
  int numControlPoints() const { return numControlPoints_; }
  /// The same cell type with every factor's degree multiplied by `factor`
  /// (the shape of products of two maps on this cell).
  CellShape ScaledDegree(int factor) const;
  /// True when every degree is in [0, kMaxDegree].
  bool IsValid() const;
  /// True when every factor is an interval (lines, quads, hexes): the
  /// reference domain is the unit box, parameter i the i-th factor's.
  bool isBox() const {
    for (int f = 0; f < numFactors_; ++f) {
      if (factors_[f].dim != 1) return false;
    }
    return true;
  }

  /// True when reference coordinates `ref` lie off every face of the
  /// domain by more than `margin` (each simplex factor's barycentric
  /// coordinates, the implied last one included, above it).
  bool IsOffEveryFace(const double* ref, double margin) const {
    for (int f = 0; f < numFactors_; ++f) {
      const SimplexFactor& fac = factors_[f];
      double rest = 1.0;
      for (int i = 0; i < fac.dim; ++i) {
        if (!(ref[fac.offset + i] > margin)) return false;
        rest -= ref[fac.offset + i];
      }
      if (!(rest > margin)) return false;
    }
    return true;
  }

  /// Number of simplex factors of a cell type.
  static int NumFactorsOf(CellType type);
  /// Dimension of factor `i` of a cell type.
  static int FactorDimOf(CellType type, int i);
  /// Parametric dimension of a cell type: the sum of its factors'.
  static int ParamDimOf(CellType type);

 private:
  CellType type_ = CellType::Line;
  int numFactors_ = 0;
  int paramDim_ = 0;
  int numControlPoints_ = 0;
  std::array<SimplexFactor, kMaxFactors> factors_{};
};

}  // namespace invmap::kernels
