// The certified closest point on a partition-of-unity surface
// (docs/manifold.md, "Inversion").
//
// The surface is covered by pieces (pou/pieces.h). For one query point x and
// a piece, a branch and bound over boxes of the piece (least lower bound
// first) proves that no point of the piece's part of the covered disk is
// closer than the best distance d so far less the tolerance, or finds a
// closer point. For a box with centre c and half-widths h, the jet of
// theta_v at c (value T, first derivatives J, second H) and M, the bound of
// the third derivative over the box (pou/piece_bounds.h), give
//  - a lower bound of |theta_v - x| over the box: the distance from x to the
//    parallelogram T + J [-h, h], less the rest of the Taylor expansion
//    (|H[d, d]| / 2 + M |h|^3 / 6) and the rounding allowances;
//  - an enclosure of the Hessian of f = |theta_v - x|^2,
//    2 (J^T J + sum_k (theta_k - x_k) H_k), from J + H [-h, h] +- M |h|^2 / 2,
//    H +- M |h| and the value's enclosure. When every matrix of it is
//    positive definite, f is convex on the box: a projected Newton solve on
//    the box ends at its least point, and f lies above its tangent plane
//    there; when that plane stays above the cut-off over the box, the box is
//    closed (the core's certificate of a convex subdomain);
//  - the same enclosure's gradient: where f falls toward one side of the box
//    all over it, the box's least point lies on that side, and where f is
//    convex along that side (or falls toward a corner) the side (corner)
//    closes the same way (the core's face certificate: a point whose nearest
//    point lies across a piece's edge).
// Other boxes are split (across the side whose image is longest) until they
// are pruned or closed. A box narrower than 1e-10 of the chart, or a query
// that examines more than 65,536 boxes, leaves the answer uncertified: the
// best point found is kept.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "pou/pieces.h"
#include "pou/pou_surface.h"

namespace invmap::pou {

/// The state of one query's search over one surface.
class PointSearch {
 public:
  /// Search for the point of `surface` nearest `x`; distances within
  /// `tolerance` of the best are not worth proving smaller. `cutoff`: the
  /// distance an answer may have at most (infinity for none). `band`: how
  /// far beyond `cutoff` an answer is still taken before the search has
  /// found one (the cell search's gap band, engine/point_search.h), so that
  /// a point at distance exactly `cutoff` is never lost to a solve that lands
  /// a rounding's width beyond it; 0 when `cutoff` is another answer's
  /// distance, which only a nearer point replaces.
  PointSearch(const PouSurface& surface, const double x[3], double tolerance, double cutoff, double band);

  /// A local solve in `chart` from (u, v), over the square of side 4R/3
  /// about its centre; a closer answer replaces the best.
  void Seed(std::int64_t chart, double u, double v);
  /// The branch and bound over one piece (the square `box` of `chart`, with
  /// its shape majorants).
  void SearchPiece(std::int64_t chart, const ChartBox& box, const ShapeMajorants& shapes);

  /// The squared distance below which a piece or box must be searched:
  /// the best's less the tolerance, or before any answer the cut-off and
  /// its band (equality admitted).
  double Cutoff2() const {
    if (!found_) {
      const double reach = distance_ + band_;
      return std::nextafter(reach * reach, HUGE_VAL);
    }
    const double d = distance_ - tolerance_;
    return d > 0.0 ? d * d : -1.0;
  }

  bool found() const { return found_; }
  /// The best distance (or the cut-off, when nothing was found).
  double distance() const { return distance_; }
  std::int64_t chart() const { return chart_; }
  /// The best point's coordinates in `chart()`.
  double u() const { return u_; }
  double v() const { return v_; }
  const double* point() const { return point_; }
  /// False when a box was too narrow to split or the budget ran out.
  bool certified() const { return certified_; }
  /// Boxes examined so far.
  int boxes() const { return boxes_; }

 private:
  struct Node {
    ChartBox box;
    double bound;  ///< Lower bound of f on the box, from its parent.
  };
  /// Projected Newton on f over `box` of `chart` from (u, v): the last
  /// iterate, its f, gradient and point.
  struct LocalAnswer {
    double u = 0.0, v = 0.0, f = 0.0;
    double grad[2] = {0, 0};
    double point[3] = {0, 0, 0};
  };
  LocalAnswer Solve(std::int64_t chart, const ChartBox& box, double u, double v) const;
  /// The local solve on `face` (the box, or one side or corner of it, that
  /// holds the box's least point of a convex f), offered as an answer; true
  /// when f's tangent plane there stays above the cut-off over the face.
  /// `jacobian`: a bound of theta_v's first derivative over the box, for the
  /// rounding allowance.
  bool CloseByTangent(std::int64_t chart, const ChartBox& box, const ChartBox& face, const double start[2],
                      double jacobian, const EvaluationSlack& slack);
  void Offer(std::int64_t chart, double u, double v, const double point[3], double f);

  const PouSurface& surface_;
  double x_[3];
  double tolerance_;
  double band_;
  bool found_ = false;
  double distance_;
  std::int64_t chart_ = -1;
  double u_ = 0.0, v_ = 0.0;
  double point_[3] = {0, 0, 0};
  bool certified_ = true;
  int boxes_ = 0;
  std::vector<Node> heap_;
  BlendParts parts_, scratch_;
  BoxSample sample_;
};

}  // namespace invmap::pou
