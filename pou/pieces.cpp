#include "pou/pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"

namespace invmap::pou {
namespace {

constexpr int kGrid = 8;         // pieces per side of a chart's square
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

/// Grows the piece's image box by the Taylor enclosure of a cell with centre
/// jet `jet` and half-widths h.
void AddCell(const ThetaJet& jet, const double h[2], double third, const EvaluationSlack& slack, Piece* piece) {
  const double rho = std::hypot(h[0], h[1]);
  for (int c = 0; c < 3; ++c) {
    const Jet<double>& t = jet.x[c];
    const double reach = std::fabs(t.du) * h[0] + std::fabs(t.dv) * h[1] +
                         0.5 * (std::fabs(t.duu) * h[0] * h[0] + 2.0 * std::fabs(t.duv) * h[0] * h[1] +
                                std::fabs(t.dvv) * h[1] * h[1]) +
                         third * rho * rho * rho / 6.0 + slack.value + slack.first * (h[0] + h[1]) +
                         slack.second * rho * rho;
    const double pad = reach * (1.0 + 1e-12) + 4.0 * kEpsilon * std::fabs(t.v);
    piece->boxLo[c] = std::min(piece->boxLo[c], t.v - pad);
    piece->boxHi[c] = std::max(piece->boxHi[c], t.v + pad);
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
  s.EvaluateParts(piece->chart, u, v, &parts);
  const ThetaJet jet = parts.Theta();
  BlendParts scratch;
  BoxSample sample;
  SampleBox(s, piece->chart, cell, parts, slack, &scratch, &sample);
  const double third = ThirdDerivativeBound(s, piece->chart, cell, piece->shapes, sample);
  double linear = 0.0;
  for (int c = 0; c < 3; ++c) linear += std::fabs(jet.x[c].du) * h[0] + std::fabs(jet.x[c].dv) * h[1];
  const double rho = std::hypot(h[0], h[1]);
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
    // Still unbounded: the box of the control points theta_v blends.
    double lo[3], hi[3];
    ChartHull(s, piece->chart, lo, hi);
    for (int c = 0; c < 3; ++c) {
      piece->boxLo[c] = std::min(piece->boxLo[c], lo[c]);
      piece->boxHi[c] = std::max(piece->boxHi[c], hi[c]);
    }
    return;
  }
  AddCell(jet, h, third, slack, piece);
}

}  // namespace

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
          piece.shapes = BoundShapes(surface, v, piece.box);
          for (int c = 0; c < 3; ++c) {
            piece.boxLo[c] = HUGE_VAL;
            piece.boxHi[c] = -HUGE_VAL;
          }
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
