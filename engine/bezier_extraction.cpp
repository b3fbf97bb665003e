#include "engine/bezier_extraction.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace invmap::engine {

namespace {

using kernels::kMaxDegree;

/// Bezier extraction operators of one parametric direction: for every
/// non-empty span, the matrix that maps the span's p + 1 active B-spline
/// coefficients to its p + 1 Bezier coefficients.
struct DirectionExtraction {
  /// Polynomial degree p (0 for the dummy directions of curves and surfaces).
  int degree = 0;
  /// Per span: index of its first active control point (knot index - p).
  std::vector<int> firstControl;
  /// Per span: the knot interval (empty for dummy directions).
  std::vector<double> lo, hi;
  /// Per span: (p + 1) x (p + 1) row-major matrix, row = Bezier index,
  /// column = active control point (empty for dummy directions).
  std::vector<double> matrices;

  /// Number of non-empty spans (1 for dummy directions).
  int numSpans() const { return static_cast<int>(firstControl.size()); }
  /// The operator of span `span`, (p + 1)^2 values.
  const double* matrix(int span) const {
    return matrices.data() + static_cast<std::size_t>(span) * (degree + 1) * (degree + 1);
  }
};

/// A direction the patch does not have (v and w of curves, w of surfaces):
/// one control point and one span, so that curves and surfaces run through
/// the volume code. Its operator is the identity and is never stored.
DirectionExtraction DummyDirection() {
  DirectionExtraction dir;
  dir.firstControl = {0};
  return dir;
}

/// Coefficient vectors of de Boor points: entry [j][m] is the weight of the
/// span's local control point m in de Boor point j.
using DeBoorState = double[kMaxDegree + 1][kMaxDegree + 1];

/// Applies level r (1..p) of de Boor's recurrence with argument u to the
/// points j = r..p of span k, reading level r - 1 from `in` and writing
/// `out`, which may be `in` itself. After level r, point j only involves
/// local control points j - r..j, so only that support is computed and read;
/// going down in j keeps point j - 1 at level r - 1 while point j is updated
/// in place.
void DeBoorLevel(int p, int k, const std::vector<double>& t, int r, double u, const DeBoorState& in,
                 DeBoorState& out) {
  for (int j = p; j >= r; --j) {
    const int g = k - p + j;
    const double alpha = (u - t[g]) / (t[g + p + 1 - r] - t[g]);
    const int lo = j - r;
    out[j][j] = alpha * in[j][j];
    for (int m = j - 1; m > lo; --m) out[j][m] = (1.0 - alpha) * in[j - 1][m] + alpha * in[j][m];
    out[j][lo] = (1.0 - alpha) * in[j - 1][lo];
  }
}

/// Builds the operators of a direction with degree `p`, `count` control points
/// and the valid knot vector `t`. Bezier point i of span [a, b] is the blossom
/// f(a, .., a, b, .., b) with p - i arguments a, evaluated by de Boor's
/// recurrence on coefficient vectors; the levels with argument a are shared
/// by all i. Every denominator t[g + p + 1 - r] - t[g] covers [a, b], so it is
/// positive for any knot multiplicity and the combinations are convex: no
/// division by zero and no cancellation even at C^-1 knots or unclamped ends.
DirectionExtraction BuildDirection(int p, int count, const std::vector<double>& t) {
  DirectionExtraction dir;
  dir.degree = p;
  const int size = p + 1;
  const int maxSpans = count - p;
  dir.firstControl.reserve(maxSpans);
  dir.lo.reserve(maxSpans);
  dir.hi.reserve(maxSpans);
  dir.matrices.resize(static_cast<std::size_t>(maxSpans) * size * size);
  DeBoorState chain;
  DeBoorState work;
  for (int k = p; k < count; ++k) {
    const double a = t[k];
    const double b = t[k + 1];
    if (!(a < b)) continue;
    double* matrix = dir.matrices.data() + dir.firstControl.size() * size * size;
    dir.firstControl.push_back(k - p);
    dir.lo.push_back(a);
    dir.hi.push_back(b);
    for (int j = 0; j < size; ++j) chain[j][j] = 1.0;
    // Before Bezier point i, `chain` has had the levels 1..p - i with a; the
    // remaining i levels with b go to `work` so that `chain` can continue.
    for (int i = p; i >= 0; --i) {
      const int levelA = p - i;
      const DeBoorState* blossom = &chain;
      if (i > 0) {
        DeBoorLevel(p, k, t, levelA + 1, b, chain, work);
        for (int r = levelA + 2; r <= p; ++r) DeBoorLevel(p, k, t, r, b, work, work);
        blossom = &work;
      }
      for (int m = 0; m < size; ++m) matrix[i * size + m] = (*blossom)[p][m];
      if (i > 0) DeBoorLevel(p, k, t, levelA + 1, a, chain, chain);
    }
  }
  dir.matrices.resize(dir.firstControl.size() * size * size);
  return dir;
}

/// out[0..len) = sum_b matrixRow[b] * in[b * stride .. b * stride + len) for
/// b < terms: one row of an extraction operator applied to whole rows or
/// layers of points at once.
void CombineRows(const double* matrixRow, int terms, const double* in, std::size_t stride,
                 std::size_t len, double* out) {
  for (std::size_t x = 0; x < len; ++x) out[x] = matrixRow[0] * in[x];
  for (int b = 1; b < terms; ++b) {
    const double c = matrixRow[b];
    const double* src = in + b * stride;
    for (std::size_t x = 0; x < len; ++x) out[x] += c * src[x];
  }
}

/// Applies the u operator of one span to one row of the v/w-extracted net
/// (`row` holds the row's n_u points, D values each) and writes the p + 1
/// Bezier points of the row to `out`. D is a template parameter so that the
/// innermost loop over coordinates unrolls.
template <int D>
void ExtractRowU(const double* matrix, int size, const double* row, double* out) {
  for (int a = 0; a < size; ++a) {
    const double* m = matrix + a * size;
    double acc[D];
    for (int d = 0; d < D; ++d) acc[d] = m[0] * row[d];
    for (int b = 1; b < size; ++b) {
      for (int d = 0; d < D; ++d) acc[d] += m[b] * row[b * D + d];
    }
    for (int d = 0; d < D; ++d) out[a * D + d] = acc[d];
  }
}

/// Tensor-product extraction with D values per point (Cartesian, or
/// homogeneous (w x, w), when `rational`). `net` holds the patch's points
/// u fastest. Works direction by direction, w then v then u, so that each
/// operator is applied to whole layers and rows and the scratch stays at one
/// w-layer and one v-row of the net.
template <int D>
void ExtractTensor(const std::array<DirectionExtraction, 3>& dirs, const std::array<int, 3>& n,
                   const double* net, bool rational, ExtractedCells* cells) {
  const DirectionExtraction& du = dirs[0];
  const DirectionExtraction& dv = dirs[1];
  const DirectionExtraction& dw = dirs[2];
  const int sizeU = du.degree + 1, sizeV = dv.degree + 1, sizeW = dw.degree + 1;
  const std::size_t rowLen = static_cast<std::size_t>(n[0]) * D;
  const std::size_t layerLen = rowLen * n[1];
  // The operator of a dummy direction is the identity, so its layers or rows
  // are read from the input instead of copied: curves and surfaces skip a
  // full pass over the net.
  std::vector<double> layerScratch(dw.degree > 0 ? layerLen * sizeW : 0);
  std::vector<double> rowScratch(dv.degree > 0 ? rowLen * sizeV * sizeW : 0);
  std::vector<double> cellNet(static_cast<std::size_t>(cells->pointsPerCell) * D);
  const int dim = cells->ambientDim;
  double* outPoints = cells->points.data();
  double* outWeights = cells->weights.data();

  for (int sw = 0; sw < dw.numSpans(); ++sw) {
    // layers[c]: the net's v-u layers combined into Bezier layer c along w.
    const double* layers = net;
    if (dw.degree > 0) {
      const double* mw = dw.matrix(sw);
      const double* wBase = net + dw.firstControl[sw] * layerLen;
      for (int c = 0; c < sizeW; ++c) {
        CombineRows(mw + c * sizeW, sizeW, wBase, layerLen, layerLen, &layerScratch[c * layerLen]);
      }
      layers = layerScratch.data();
    }
    for (int sv = 0; sv < dv.numSpans(); ++sv) {
      // rows[c * sizeV + e]: layer c's rows combined into Bezier row e along v.
      const double* rows = layers;
      if (dv.degree > 0) {
        const double* mv = dv.matrix(sv);
        for (int c = 0; c < sizeW; ++c) {
          const double* vBase = layers + c * layerLen + dv.firstControl[sv] * rowLen;
          for (int e = 0; e < sizeV; ++e) {
            CombineRows(mv + e * sizeV, sizeV, vBase, rowLen, rowLen,
                        &rowScratch[(c * sizeV + e) * rowLen]);
          }
        }
        rows = rowScratch.data();
      }
      for (int su = 0; su < du.numSpans(); ++su) {
        const double* mu = du.matrix(su);
        const std::size_t uOffset = static_cast<std::size_t>(du.firstControl[su]) * D;
        // Polynomial cells are written in place; rational ones go through
        // cellNet to be divided by their weights.
        double* target = rational ? cellNet.data() : outPoints;
        for (int ce = 0; ce < sizeW * sizeV; ++ce) {
          ExtractRowU<D>(mu, sizeU, rows + ce * rowLen + uOffset, target + ce * sizeU * D);
        }
        if (rational) {
          for (int k = 0; k < cells->pointsPerCell; ++k) {
            const double w = cellNet[k * D + dim];
            for (int d = 0; d < dim; ++d) outPoints[k * dim + d] = cellNet[k * D + d] / w;
            outWeights[k] = w;
          }
          outWeights += cells->pointsPerCell;
        }
        outPoints += static_cast<std::size_t>(cells->pointsPerCell) * dim;
      }
    }
  }
}

}  // namespace

ExtractedCells ExtractBezierCells(const BSplinePatch& patch) {
  static constexpr kernels::CellType kTypeOfParamDim[] = {
      kernels::CellType::Line, kernels::CellType::Quad, kernels::CellType::Hex};
  ExtractedCells cells;
  cells.paramDim = static_cast<int>(patch.degrees.size());
  cells.type = kTypeOfParamDim[cells.paramDim - 1];
  cells.ambientDim = patch.ambientDim;

  std::array<DirectionExtraction, 3> dirs;
  std::array<int, 3> n{1, 1, 1};
  cells.numCells = 1;
  cells.pointsPerCell = 1;
  for (int dir = 0; dir < 3; ++dir) {
    if (dir < cells.paramDim) {
      cells.degrees[dir] = patch.degrees[dir];
      n[dir] = patch.counts[dir];
      dirs[dir] = BuildDirection(patch.degrees[dir], n[dir], patch.knots[dir]);
    } else {
      dirs[dir] = DummyDirection();
    }
    cells.spans[dir] = dirs[dir].numSpans();
    cells.numCells *= dirs[dir].numSpans();
    cells.pointsPerCell *= dirs[dir].degree + 1;
  }

  const std::size_t numCells = static_cast<std::size_t>(cells.numCells);
  cells.spanLo.resize(numCells * cells.paramDim);
  cells.spanHi.resize(numCells * cells.paramDim);
  std::size_t cell = 0;
  for (int sw = 0; sw < dirs[2].numSpans(); ++sw) {
    for (int sv = 0; sv < dirs[1].numSpans(); ++sv) {
      for (int su = 0; su < dirs[0].numSpans(); ++su, ++cell) {
        const int spans[3] = {su, sv, sw};
        for (int d = 0; d < cells.paramDim; ++d) {
          cells.spanLo[cell * cells.paramDim + d] = dirs[d].lo[spans[d]];
          cells.spanHi[cell * cells.paramDim + d] = dirs[d].hi[spans[d]];
        }
      }
    }
  }

  const bool rational = !patch.weights.empty();
  cells.points.resize(numCells * cells.pointsPerCell * cells.ambientDim);
  if (rational) cells.weights.resize(numCells * cells.pointsPerCell);

  if (!rational) {
    if (cells.ambientDim == 2) {
      ExtractTensor<2>(dirs, n, patch.controlPoints.data(), false, &cells);
    } else {
      ExtractTensor<3>(dirs, n, patch.controlPoints.data(), false, &cells);
    }
    return cells;
  }
  // Knot insertion is linear in homogeneous coordinates (w x, w), not in x.
  const int dimH = cells.ambientDim + 1;
  std::vector<double> homogeneous(patch.weights.size() * dimH);
  for (std::size_t k = 0; k < patch.weights.size(); ++k) {
    const double w = patch.weights[k];
    for (int d = 0; d < cells.ambientDim; ++d) {
      homogeneous[k * dimH + d] = w * patch.controlPoints[k * cells.ambientDim + d];
    }
    homogeneous[k * dimH + cells.ambientDim] = w;
  }
  if (dimH == 3) {
    ExtractTensor<3>(dirs, n, homogeneous.data(), true, &cells);
  } else {
    ExtractTensor<4>(dirs, n, homogeneous.data(), true, &cells);
  }
  return cells;
}

}  // namespace invmap::engine
