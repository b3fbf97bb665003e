#include "pou/pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"
#include "pou/chart_maps.h"

namespace invmap::pou {
namespace {

constexpr int kGrid = 9;         // pieces per side of a chart's square (odd: one about the centre)
constexpr int kCells = 2;        // cells per side of a piece, for its image box
constexpr int kDeeperCells = 3;  // further halvings of a cell whose bound is poor
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

/// A box of R^3 that holds all of theta_v: the control points of its shape
/// function and its neighbours' (theta_v is a convex combination of their
/// values at points of their squares), widened for the rounding.
void ChartHull(const PouSurface& s, std::int64_t v, double lo[3], double hi[3]) {
  for (int c = 0; c < 3; ++c) {
    lo[c] = HUGE_VAL;
    hi[c] = -HUGE_VAL;
  }
  for (int i = -1; i < s.valence(v); ++i) {
    const ShapeNet net = s.net(i < 0 ? v : s.mesh().neighbor(v, i));
    for (int p = 0; p < (net.degree + 1) * (net.degree + 1); ++p)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], net.points[3 * p + c]);
        hi[c] = std::max(hi[c], net.points[3 * p + c]);
      }
  }
  for (int c = 0; c < 3; ++c) {
    const double pad = 1e-12 * std::max(std::fabs(lo[c]), std::fabs(hi[c]));
    lo[c] -= pad;
    hi[c] += pad;
  }
}

/// The extent along unit direction `a` of the Taylor enclosure of a cell
/// with centre jet `jet` and half-widths h: a . T +- reach, with the linear
/// and quadratic terms' reach along a, the remainder's M rho^3 / 6 and the
/// evaluation's rounding.
void Extent(const ThetaJet& jet, const double h[2], double third, const EvaluationSlack& slack, const double a[3],
            double* lo, double* hi) {
  const double rho = Length(h[0], h[1]);
  double centre = 0.0, d0 = 0.0, d1 = 0.0, quadratic = 0.0, weight = 0.0, magnitude = 0.0;
  for (int c = 0; c < 3; ++c) {
    const Jet<double>& t = jet.x[c];
    centre += a[c] * t.v;
    d0 += a[c] * t.du;
    d1 += a[c] * t.dv;
    quadratic += std::fabs(a[c]) * (std::fabs(t.duu) * h[0] * h[0] + 2.0 * std::fabs(t.duv) * h[0] * h[1] +
                                    std::fabs(t.dvv) * h[1] * h[1]);
    weight += std::fabs(a[c]);
    magnitude += std::fabs(a[c] * t.v);
  }
  const double reach = std::fabs(d0) * h[0] + std::fabs(d1) * h[1] + 0.5 * quadratic +
                       Length(Length(a[0], a[1]), a[2]) * third * rho * rho * rho / 6.0 +
                       weight * (slack.value + slack.first * (h[0] + h[1]) + slack.second * rho * rho);
  const double pad = reach * (1.0 + 1e-12) + 8.0 * kEpsilon * magnitude;
  *lo = std::min(*lo, centre - pad);
  *hi = std::max(*hi, centre + pad);
}

/// Grows the piece's image boxes by the Taylor enclosure of a cell with
/// centre jet `jet` and half-widths h.
void AddCell(const ThetaJet& jet, const double h[2], double third, const EvaluationSlack& slack, Piece* piece) {
  for (int c = 0; c < 3; ++c) {
    const double a[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
    Extent(jet, h, third, slack, a, &piece->boxLo[c], &piece->boxHi[c]);
    Extent(jet, h, third, slack, piece->axis[c], &piece->orientedLo[c], &piece->orientedHi[c]);
  }
}

/// The piece's oriented axes: the tangent plane and the normal of theta_v at
/// the centre of its box (Gram-Schmidt); the coordinate axes where the
/// derivatives are degenerate.
void ChooseAxes(const PouSurface& s, Piece* piece) {
  const ThetaJet jet = s.Evaluate(piece->chart, 0.5 * (piece->box.lo[0] + piece->box.hi[0]),
                                  0.5 * (piece->box.lo[1] + piece->box.hi[1]));
  double t0[3], t1[3];
  for (int c = 0; c < 3; ++c) {
    t0[c] = jet.x[c].du;
    t1[c] = jet.x[c].dv;
  }
  const double n0 = Length(Length(t0[0], t0[1]), t0[2]);
  if (!(n0 > 0.0)) return;
  for (double& x : t0) x /= n0;
  const double along = t0[0] * t1[0] + t0[1] * t1[1] + t0[2] * t1[2];
  for (int c = 0; c < 3; ++c) t1[c] -= along * t0[c];
  const double n1 = Length(Length(t1[0], t1[1]), t1[2]);
  if (!(n1 > 0.0)) return;
  for (double& x : t1) x /= n1;
  const double n[3] = {t0[1] * t1[2] - t0[2] * t1[1], t0[2] * t1[0] - t0[0] * t1[2], t0[0] * t1[1] - t0[1] * t1[0]};
  for (int c = 0; c < 3; ++c) {
    piece->axis[0][c] = t0[c];
    piece->axis[1][c] = t1[c];
    piece->axis[2][c] = n[c];
  }
}

/// Adds the image of `cell` (within the covered disk) to the piece's box,
/// halving the cell while its third-derivative bound is infinite or its
/// Taylor remainder outweighs the linear part.
void AddImage(const PouSurface& s, const ChartBox& cell, int depth, const EvaluationSlack& slack, Piece* piece) {
  if (OutsideKites(s, piece->chart, cell)) return;
  const double u = 0.5 * (cell.lo[0] + cell.hi[0]), v = 0.5 * (cell.lo[1] + cell.hi[1]);
  const double h[2] = {0.5 * (cell.hi[0] - cell.lo[0]), 0.5 * (cell.hi[1] - cell.lo[1])};
  BlendParts parts;
  parts.edges = piece->shapes.edges;
  ReachingEdges(s, piece->chart, cell, piece->shapes, &parts.active);
  s.EvaluateParts(piece->chart, u, v, &parts);
  const ThetaJet jet = parts.Theta();
  BlendParts scratch;
  BoxSample sample;
  SampleBox(s, piece->chart, cell, parts, slack, &scratch, &sample);
  const double third = ThirdDerivativeBound(s, piece->chart, cell, piece->shapes, sample);
  double linear = 0.0;
  for (int c = 0; c < 3; ++c) linear += std::fabs(jet.x[c].du) * h[0] + std::fabs(jet.x[c].dv) * h[1];
  const double rho = Length(h[0], h[1]);
  if (depth < kDeeperCells && !(third * rho * rho * rho / 6.0 <= linear)) {
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const ChartBox half{{i == 0 ? cell.lo[0] : u, j == 0 ? cell.lo[1] : v},
                            {i == 0 ? u : cell.hi[0], j == 0 ? v : cell.hi[1]}};
        AddImage(s, half, depth + 1, slack, piece);
      }
    return;
  }
  if (!(third < HUGE_VAL)) {
    // Still unbounded: the box of the control points theta_v blends, and its
    // corners' extents along the oriented axes.
    double lo[3], hi[3];
    ChartHull(s, piece->chart, lo, hi);
    for (int c = 0; c < 3; ++c) {
      piece->boxLo[c] = std::min(piece->boxLo[c], lo[c]);
      piece->boxHi[c] = std::max(piece->boxHi[c], hi[c]);
    }
    for (int corner = 0; corner < 8; ++corner) {
      const double p[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]};
      for (int j = 0; j < 3; ++j) {
        const double* a = piece->axis[j];
        const double x = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        const double pad = 8.0 * kEpsilon * (std::fabs(a[0] * p[0]) + std::fabs(a[1] * p[1]) + std::fabs(a[2] * p[2]));
        piece->orientedLo[j] = std::min(piece->orientedLo[j], x - pad);
        piece->orientedHi[j] = std::max(piece->orientedHi[j], x + pad);
      }
    }
    return;
  }
  AddCell(jet, h, third, slack, piece);
}

}  // namespace

void Piece::OrientedCorners(double out[24]) const {
  // The axes are orthonormal up to rounding: a point's coordinates along
  // them rebuild it to within a few ulps of its size, which the pad covers.
  double size = 0.0;
  for (int j = 0; j < 3; ++j) size += std::max(std::fabs(orientedLo[j]), std::fabs(orientedHi[j]));
  const double pad = 1e-12 * size;
  for (int corner = 0; corner < 8; ++corner) {
    const double along[3] = {corner & 1 ? orientedHi[0] + pad : orientedLo[0] - pad,
                             corner & 2 ? orientedHi[1] + pad : orientedLo[1] - pad,
                             corner & 4 ? orientedHi[2] + pad : orientedLo[2] - pad};
    for (int c = 0; c < 3; ++c) {
      out[3 * corner + c] = along[0] * axis[0][c] + along[1] * axis[1][c] + along[2] * axis[2][c];
    }
  }
}

std::vector<Piece> MakePieces(const PouSurface& surface) {
  const std::int64_t charts = surface.numCharts();
  std::vector<Piece> pieces(charts * kGrid * kGrid);
  ForEachBlock(ExecutionPolicy::Par, charts, 16, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v) {
      const double side = 2.0 * kCoveredRadius * surface.radius(v) / kGrid;
      const double origin = -kCoveredRadius * surface.radius(v);
      const EvaluationSlack slack = SlackOf(surface, v);
      for (int j = 0; j < kGrid; ++j) {
        for (int i = 0; i < kGrid; ++i) {
          Piece& piece = pieces[(v * kGrid + j) * kGrid + i];
          piece.chart = v;
          piece.box = {{origin + i * side, origin + j * side}, {origin + (i + 1) * side, origin + (j + 1) * side}};
          for (int c = 0; c < 3; ++c) {
            piece.boxLo[c] = piece.orientedLo[c] = HUGE_VAL;
            piece.boxHi[c] = piece.orientedHi[c] = -HUGE_VAL;
          }
          if (OutsideKites(surface, v, piece.box)) continue;
          piece.shapes = BoundShapes(surface, v, piece.box);
          ChooseAxes(surface, &piece);
          const double cell = side / kCells;
          for (int b = 0; b < kCells; ++b)
            for (int a = 0; a < kCells; ++a) {
              const ChartBox box{{piece.box.lo[0] + a * cell, piece.box.lo[1] + b * cell},
                                 {piece.box.lo[0] + (a + 1) * cell, piece.box.lo[1] + (b + 1) * cell}};
              AddImage(surface, box, 0, slack, &piece);
            }
        }
      }
    }
  });
  // Squares of the grid outside the kites hold nothing to search.
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& p) { return !(p.boxLo[0] <= p.boxHi[0]); }),
               pieces.end());
  return pieces;
}

}  // namespace invmap::pou
