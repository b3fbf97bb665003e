#include "pou/pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"
#include "pou/chart_maps.h"

namespace invmap::pou {
namespace {

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
void AddCell(const ThetaJet& jet, const double h[2], double third, const EvaluationSlack& slack,
             PieceBounds* bounds) {
  for (int c = 0; c < 3; ++c) {
    const double a[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
    Extent(jet, h, third, slack, a, &bounds->boxLo[c], &bounds->boxHi[c]);
    Extent(jet, h, third, slack, bounds->axis[c], &bounds->orientedLo[c], &bounds->orientedHi[c]);
  }
}

/// The piece's oriented axes: the tangent plane and the normal of theta_v at
/// the centre of its box (Gram-Schmidt); the coordinate axes where the
/// derivatives are degenerate.
void ChooseAxes(const PouSurface& s, std::int64_t chart, const ChartBox& box, PieceBounds* bounds) {
  const ThetaJet jet = s.Evaluate(chart, 0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1]));
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
    bounds->axis[0][c] = t0[c];
    bounds->axis[1][c] = t1[c];
    bounds->axis[2][c] = n[c];
  }
}

/// Adds the image of `cell` (within the covered disk) to the piece's box,
/// halving the cell while its third-derivative bound is infinite or its
/// Taylor remainder outweighs the linear part.
void AddImage(const PouSurface& s, std::int64_t chart, const ShapeMajorants& shapes, const ChartBox& cell, int depth,
              const EvaluationSlack& slack, PieceBounds* bounds) {
  if (OutsideKites(s, chart, cell)) return;
  const double u = 0.5 * (cell.lo[0] + cell.hi[0]), v = 0.5 * (cell.lo[1] + cell.hi[1]);
  const double h[2] = {0.5 * (cell.hi[0] - cell.lo[0]), 0.5 * (cell.hi[1] - cell.lo[1])};
  BlendParts parts;
  ReachingEdges(s, chart, cell, shapes, &parts);
  s.EvaluateParts(chart, u, v, &parts);
  const ThetaJet jet = parts.Theta();
  BlendParts scratch;
  BoxSample sample;
  SampleBox(s, chart, cell, parts, slack, &scratch, &sample);
  const double third = ThirdDerivativeBound(s, chart, cell, shapes, sample);
  double linear = 0.0;
  for (int c = 0; c < 3; ++c) linear += std::fabs(jet.x[c].du) * h[0] + std::fabs(jet.x[c].dv) * h[1];
  const double rho = Length(h[0], h[1]);
  if (depth < kDeeperCells && !(third * rho * rho * rho / 6.0 <= linear)) {
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const ChartBox half{{i == 0 ? cell.lo[0] : u, j == 0 ? cell.lo[1] : v},
                            {i == 0 ? u : cell.hi[0], j == 0 ? v : cell.hi[1]}};
        AddImage(s, chart, shapes, half, depth + 1, slack, bounds);
      }
    return;
  }
  if (!(third < HUGE_VAL)) {
    // Still unbounded: the box of the control points theta_v blends, and its
    // corners' extents along the oriented axes.
    double lo[3], hi[3];
    ChartHull(s, chart, lo, hi);
    for (int c = 0; c < 3; ++c) {
      bounds->boxLo[c] = std::min(bounds->boxLo[c], lo[c]);
      bounds->boxHi[c] = std::max(bounds->boxHi[c], hi[c]);
    }
    for (int corner = 0; corner < 8; ++corner) {
      const double p[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]};
      for (int j = 0; j < 3; ++j) {
        const double* a = bounds->axis[j];
        const double x = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        const double pad = 8.0 * kEpsilon * (std::fabs(a[0] * p[0]) + std::fabs(a[1] * p[1]) + std::fabs(a[2] * p[2]));
        bounds->orientedLo[j] = std::min(bounds->orientedLo[j], x - pad);
        bounds->orientedHi[j] = std::max(bounds->orientedHi[j], x + pad);
      }
    }
    return;
  }
  AddCell(jet, h, third, slack, bounds);
}

}  // namespace

void PieceBounds::OrientedCorners(double out[24]) const {
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

ChartBox PieceBox(const PouSurface& surface, const Piece& piece) {
  const double side = 2.0 * kCoveredRadius * surface.radius(piece.chart) / kPieceGrid;
  const double origin = -kCoveredRadius * surface.radius(piece.chart);
  return {{origin + piece.column * side, origin + piece.row * side},
          {origin + (piece.column + 1) * side, origin + (piece.row + 1) * side}};
}

void PieceSet::Build(const PouSurface& surface, std::vector<PieceBounds>* bounds) {
  const std::int64_t charts = surface.numCharts();
  // Per chart, then gathered in chart order (the pool's offsets shifted).
  struct ChartPieces {
    std::vector<Piece> pieces;
    std::vector<PieceBounds> bounds;
    std::vector<ReachingShape> reach;
  };
  std::vector<ChartPieces> perChart(charts);
  ForEachBlock(ExecutionPolicy::Par, charts, 16, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v) {
      ChartPieces& out = perChart[v];
      const EvaluationSlack slack = SlackOf(surface, v);
      for (int row = 0; row < kPieceGrid; ++row) {
        for (int column = 0; column < kPieceGrid; ++column) {
          Piece piece;
          piece.chart = static_cast<std::int32_t>(v);
          piece.column = static_cast<std::uint8_t>(column);
          piece.row = static_cast<std::uint8_t>(row);
          const ChartBox box = PieceBox(surface, piece);
          if (OutsideKites(surface, v, box)) continue;
          piece.firstReach = static_cast<std::uint32_t>(out.reach.size());
          BoundShapes(surface, v, box, piece.own, &out.reach);
          piece.reachCount = static_cast<std::uint16_t>(out.reach.size() - piece.firstReach);
          const ShapeMajorants shapes{{piece.own[0], piece.own[1], piece.own[2]},
                                      out.reach.data() + piece.firstReach, piece.reachCount};
          PieceBounds b;
          for (int c = 0; c < 3; ++c) {
            b.boxLo[c] = b.orientedLo[c] = HUGE_VAL;
            b.boxHi[c] = b.orientedHi[c] = -HUGE_VAL;
          }
          ChooseAxes(surface, v, box, &b);
          const double cell = (box.hi[0] - box.lo[0]) / kCells;
          for (int j = 0; j < kCells; ++j)
            for (int i = 0; i < kCells; ++i) {
              const ChartBox part{{box.lo[0] + i * cell, box.lo[1] + j * cell},
                                  {box.lo[0] + (i + 1) * cell, box.lo[1] + (j + 1) * cell}};
              AddImage(surface, v, shapes, part, 0, slack, &b);
            }
          // Squares of the grid whose cells all lie outside the kites hold
          // nothing to search.
          if (!(b.boxLo[0] <= b.boxHi[0])) {
            out.reach.resize(piece.firstReach);
            continue;
          }
          out.pieces.push_back(piece);
          out.bounds.push_back(b);
        }
      }
    }
  });
  pieces_.clear();
  reach_.clear();
  bounds->clear();
  for (ChartPieces& chart : perChart) {
    for (Piece piece : chart.pieces) {
      piece.firstReach += static_cast<std::uint32_t>(reach_.size());
      pieces_.push_back(piece);
    }
    reach_.insert(reach_.end(), chart.reach.begin(), chart.reach.end());
    bounds->insert(bounds->end(), chart.bounds.begin(), chart.bounds.end());
    chart = ChartPieces();
  }
}

}  // namespace invmap::pou
