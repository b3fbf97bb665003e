// The certified closest point on a partition-of-unity surface.
//
// The surface is covered by pieces: each chart's square [-2R/3, 2R/3]^2,
// cut into a 4 x 4 grid of boxes, each with a box of R^3 that holds its image
// (the union of the value enclosures of a 4 x 4 grid of cells of it). The square holds every point where the
// chart's bump is the largest (the vertex's share of its triangles reaches
// 2R/3 at their centroids), so the pieces of all charts cover the surface;
// they overlap, which costs time but never correctness.
//
// For one query point x and a piece, a branch and bound over boxes of the
// piece (best first by lower bound) either proves that no point of the piece
// is closer than the best distance d so far minus the tolerance, or finds a
// closer point. A box's lower bound of f = |theta_v - x|^2 is the larger of
// the squared distance from x to the enclosure of theta_v and the mean-value
// form f(c) + min over the box of grad f(box) . (p - c) (pou/enclosure.h).
// A box on which the Hessian of f is positive definite for every matrix of
// its interval enclosure is convex: a projected Newton solve on the box finds
// its least point, and the box is closed once the tangent plane there
// (f convex lies above it) stays above the cut-off over the box. Other boxes
// are split in four until they are pruned, closed, or narrower than 1e-9 of
// the chart, in which case the answer is marked not certified; so is a
// query whose search encloses more than 20,000 boxes (it stops there and
// keeps the best point found).
#pragma once

#include <cstdint>
#include <vector>

#include "pou/enclosure.h"
#include "pou/pou_surface.h"

namespace invmap::pou {

/// One piece: a box of a chart's coordinates and a box of R^3 that holds
/// theta_v over it (an enclosure, rounded outward).
struct SurfacePiece {
  std::int64_t chart = 0;
  ChartBox box;
  double lo[3], hi[3];
};

/// The pieces of every chart, in chart order.
std::vector<SurfacePiece> MakePieces(const PouSurface& surface);

/// The state of one query's search.
struct PointSearch {
  const PouSurface* surface = nullptr;
  double x[3] = {0, 0, 0};
  /// Distances within this of the best are not worth proving smaller.
  double tolerance = 0.0;
  bool found = false;
  double distance = 0.0;  ///< Best so far (or the cut-off it must beat).
  std::int64_t chart = -1;
  double u = 0.0, v = 0.0;
  double point[3] = {0, 0, 0};
  bool certified = true;
  int boxes = 0;  ///< Boxes enclosed, for statistics.

  /// The squared distance below which a piece or box must be searched.
  double Cutoff2() const {
    const double d = distance - tolerance;
    return d > 0.0 ? d * d : -1.0;
  }
  /// A local solve in `chart` from (u0, v0), kept within the chart's piece
  /// square; the result updates the best when closer.
  void Seed(std::int64_t startChart, double u0, double v0);
  /// The branch and bound over one piece.
  void SearchPiece(const SurfacePiece& piece);

 private:
  void Offer(std::int64_t c, double pu, double pv, const double p[3], double f);
  /// Projected Newton for f on `box` of chart c from (pu, pv); returns the
  /// last iterate and its f, gradient and point.
  void SolveOnBox(std::int64_t c, const ChartBox& box, double* pu, double* pv, double* f, double grad[2],
                  double p[3]) const;
};

/// Half the side of a chart's piece square, as a share of its p-domain radius.
constexpr double kPieceHalfSide = 2.0 / 3.0;

}  // namespace invmap::pou
