// When an iterate of the local solve is stationary on its face: the slope
// tests of the solve and of the KKT check, each direction of the parameters
// judged by how far the map moves along it. Inline: every iteration of the
// local solve runs them (see kernels/step_selection.h).
#pragma once

#include <algorithm>
#include <cmath>

#include "kernels/active_set.h"
#include "kernels/cell_map.h"
#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// |v| of 3 coordinates; where the sum of squares overflows or underflows
/// (cells near the ends of the double range), summed in units of the
/// largest coordinate instead.
inline double Norm(const double* v) {
  const double length2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (length2 > 1e-300 && length2 < 1e300) return std::sqrt(length2);
  const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(largest > 0.0) || !std::isfinite(largest)) return largest;
  const double a = v[0] / largest, b = v[1] / largest, c = v[2] / largest;
  return largest * std::sqrt(a * a + b * b + c * c);
}

/// The scale of the stationarity, release and KKT tests: a slope r . J v
/// along a direction v of the parameters is judged against perLength times
/// how far the map moves along v, |J v| (never less than kThinDirection
/// times the cell's size). Each direction by its own scale: a direction the
/// map stretches little (the thickness of a thin cell, the width of a narrow
/// ribbon) or much (next to a heavy weight) would otherwise be judged by the
/// cell's size, and a slope along a thickness of 1e-6 of it passed for
/// stationary with the point 1e-8 of the size away (QA's thin hexes).
struct DirectionScale {
  const MapJet& jet;
  int ambientDim, paramDim;
  double perLength;    ///< Tolerance per unit of mapped length.
  double floorLength;  ///< kThinDirection times the cell's size.

  /// |J v|: how far the map moves per unit of the parameter step v.
  double MappedLength(const double* v) const {
    double moved[3] = {0, 0, 0};
    for (int k = 0; k < ambientDim; ++k) {
      for (int i = 0; i < paramDim; ++i) moved[k] += jet.d1[k][i] * v[i];
    }
    return Norm(moved);
  }
  /// |J e_i|: how far the map moves per unit of parameter i.
  double ColumnLength(int i) const {
    const double column[3] = {jet.d1[0][i], jet.d1[1][i], ambientDim > 2 ? jet.d1[2][i] : 0.0};
    return Norm(column);
  }
  /// The tolerance of a slope along a direction the map moves `mappedLength`
  /// per unit. (A product, not squares: those overflow long before either
  /// factor; +infinity where even it does.)
  double Tolerance(double mappedLength) const { return perLength * std::max(mappedLength, floorLength); }
};

/// True when the gradient `grad` vanishes on the free face of `face` up to
/// the tolerances of `scale`: along directions of the face whose images
/// under J are orthogonal (the longest first, the others with its part
/// removed), each judged by its own mapped length. The face basis's own
/// columns mix parameters: next to a heavy weight one column of J can be
/// 1e12 times another, and a column holding a share of it would lend the
/// test that scale along directions the map hardly stretches (in a thin
/// cell, the thickness would take the length's scale).
inline bool IsStationaryOnFace(const FaceBasis& face, const double* grad, const DirectionScale& scale) {
  const int m = face.columns;
  double along[3][3] = {};  // along[c]: direction c of the face, reduced coordinates
  double image[3][3] = {};  // J T along[c], in units of `unit`
  double largest = 0.0;
  for (int c = 0; c < m; ++c) {
    along[c][c] = 1.0;
    for (int k = 0; k < scale.ambientDim; ++k) {
      for (int i = 0; i < scale.paramDim; ++i) image[c][k] += scale.jet.d1[k][i] * face.t[i][c];
      largest = std::max(largest, std::abs(image[c][k]));
    }
  }
  // Near the ends of the double range, the images in units of a power of
  // two near the largest (exact), so that their squares neither overflow
  // nor underflow.
  double unit = 1.0;
  if ((largest > 1e150 || largest < 1e-150) && largest > 0.0 && std::isfinite(largest)) {
    unit = std::ldexp(1.0, std::ilogb(largest));
    for (int c = 0; c < m; ++c) {
      for (double& x : image[c]) x /= unit;
    }
  }
  const auto length2 = [&](const double* v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; };
  bool placed[3] = {false, false, false};
  for (int step = 0; step < m; ++step) {
    int longest = -1;
    for (int c = 0; c < m; ++c) {
      if (!placed[c] && (longest < 0 || length2(image[c]) > length2(image[longest]))) longest = c;
    }
    placed[longest] = true;
    const double norm2 = length2(image[longest]);
    if (!(norm2 > 0.0)) break;  // the rest does not move the map at all
    for (int c = 0; c < m; ++c) {
      if (placed[c]) continue;
      double share = 0.0;
      for (int k = 0; k < 3; ++k) share += image[longest][k] * image[c][k];
      share /= norm2;
      for (int k = 0; k < 3; ++k) {
        image[c][k] -= share * image[longest][k];
        along[c][k] -= share * along[longest][k];
      }
    }
  }
  for (int c = 0; c < m; ++c) {
    const double norm = std::sqrt(length2(along[c]));
    double slope = 0.0;
    for (int i = 0; i < scale.paramDim; ++i) {
      double direction = 0.0;
      for (int j = 0; j < m; ++j) direction += face.t[i][j] * along[c][j];
      slope += direction * grad[i];
    }
    if (std::abs(slope) / norm > scale.Tolerance(unit * std::sqrt(length2(image[c])) / norm)) return false;
  }
  return true;
}

/// Cells of line factors (lines, quads, hexes): the parameters whose factor
/// has no enforced constraint. Other cells: -1.
inline int FreeLineParameters(const CellShape& shape, const ActiveSet& active, int* coords) {
  int m = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).dim != 1) return -1;
    if (active.enforced[f] == 0) coords[m++] = shape.factor(f).offset;
  }
  return m;
}

/// True when every parameter of `coords` (count of them) has a slope within
/// its own tolerance: a cell of line factors, whose face directions are its
/// free parameters, judged as IsKktPoint judges it.
inline bool FreeParametersStationary(const int* coords, int count, const double* grad, const DirectionScale& scale) {
  for (int a = 0; a < count; ++a) {
    if (!(std::abs(grad[coords[a]]) <= scale.Tolerance(scale.ColumnLength(coords[a])))) return false;
  }
  return true;
}

}  // namespace invmap::kernels
