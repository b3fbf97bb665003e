// A bound of the third derivative of theta_v over a box of a chart's
// coordinates: what the pieces' image boxes and the search's certificates
// rest on (pou/pieces.h, pou/piece_search.h).
//
// On the box, theta_v = psi_v + sum_z (beta_z / S) g_z, where for each
// neighbour z whose bump reaches the box, beta_z = xi(|w_z| / (sqrt(3)/2))
// is its bump, w_z = 1 - W_z the point's position relative to z in the
// edge's canonical frame, S = gamma_v + sum beta_z the sum of the bumps, and
// g_z = psi_z o phi_zv - psi_v the mismatch of the two shape functions. Each
// factor gets a majorant (pou/majorant.h):
//  - psi_v and psi_z: the ranges of their partial derivatives over a box of
//    their own chart that holds the piece's image (RangeOverBox), computed
//    once per piece (BoundShapes);
//  - W_z(p) = k p^a conj(p)^b (p turned to the edge, a = (1 + alpha)/2,
//    b = (1 - alpha)/2, alpha = n_v / 6, k = (sqrt(3)/2) / R_v): its j-th
//    derivative has norm at most k |p|^(1-j) times the sum over i + l = j of
//    C(j, i) |a (a-1) .. (a-i+1)| |b (b-1) .. (b-l+1)| (Wirtinger
//    derivatives); so do phi_zv = G(w_z), G(w) = k' w^a' conj(w)^b' with
//    alpha' = 6 / n_z, at |w| >= the box's least |w|, and the norms |p|, |w|
//    (alpha = 0);
//  - xi and its derivatives over the range of its argument (pou/bump_bounds.h);
//  - 1 / S, S and the weights beta_z / S, orders 0 to 2: their jets at the
//    box's centre plus the next order's bound times the box's radius (along
//    the segment from the centre); order 3 from the majorants, and S at
//    least gamma_v >= xi(|p|_max / R) and each beta_z's least value;
//  - g_z likewise, order 3 from the majorants of psi_z o phi_zv and psi_v
//    (of the difference: no cancellation is assumed). The mismatch needs
//    the whole box where phi_zv maps into psi_z's bounds (|w| <= (sqrt(3)/2)
//    kShapeBoundExtension) and away from the chart's centre; a box that
//    reaches a bump's support without that gets an infinite bound, and the
//    search splits it.
// Inside |p| < 0.1547 R no bump of a neighbour reaches and theta_v = psi_v.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pou/majorant.h"
#include "pou/pou_surface.h"

namespace invmap::pou {

/// A box of a chart's Cartesian coordinates (u, v).
struct ChartBox {
  double lo[2], hi[2];
};

/// True when no point of the box lies in the chart's kites, where the
/// chart's vertex has the largest barycentric coordinate in its triangle
/// (pou/pieces.h): some neighbour u has, over the whole box, the larger
/// coordinate, that is the point's canonical projection on the edge to u
/// beyond 1/2, in the two triangles along that edge.
bool OutsideKites(const PouSurface& surface, std::int64_t chart, const ChartBox& box);

/// A neighbour whose bump reaches a piece, and the majorant of its shape
/// function over the piece's image in its chart (orders 1 to 3, as floats
/// rounded up).
struct ReachingShape {
  std::int32_t edge = 0;
  float norm[3] = {0, 0, 0};
};

/// The majorants of the shape functions over a piece: psi_v over its box
/// (orders 1 to 3, floats rounded up), and the neighbours' whose bump
/// reaches it.
struct ShapeMajorants {
  float own[3] = {0, 0, 0};
  const ReachingShape* reach = nullptr;
  int count = 0;
};

/// psi_v's majorant over `box` into `own`; appends each neighbour whose bump
/// reaches the box, with psi_z's majorant over its image, to `reach`.
void BoundShapes(const PouSurface& surface, std::int64_t chart, const ChartBox& box, float own[3],
                 std::vector<ReachingShape>* reach);

/// Allowances for the rounding of a point evaluation of theta_v's parts in
/// chart `chart` (PouSurface::EvaluateParts): of values, first and second
/// derivatives. Every step of the evaluation rounds values no larger than the
/// coordinates of the control points involved (M, the largest of them) or
/// their differences scaled by the degree over the radius; the allowances
/// are 2^10, 2^14 / R and 2^18 / R^2 ulps of M.
struct EvaluationSlack {
  double value = 0.0, first = 0.0, second = 0.0;
};
EvaluationSlack SlackOf(const PouSurface& surface, std::int64_t chart);

/// What the bound takes from the blend at points of a box: the norms of the
/// value, first and second derivatives of the sum of the bumps S and, per
/// entry of ShapeMajorants::reach, of the weight beta_z / S, at the box's
/// centre; and of the mismatch g_z = psi_z o phi_zv - psi_v at the centre,
/// or, when z's bump vanishes there, at the point of the box's rim nearest
/// its support (so that the sample does not extrapolate psi_z), with the
/// distance from there to the farthest corner. Rounding allowances included.
struct BoxSample {
  double sum[3] = {0, 0, 0};
  std::vector<char> defined;
  std::vector<std::array<double, 3>> weight, mismatch;
  std::vector<double> reach;  ///< Per edge: how far the mismatch's sample is from the box's points.
};
/// From `parts`, evaluated at the box's centre for the edges of
/// ShapeMajorants::reach, and further evaluations where needed (`scratch`).
void SampleBox(const PouSurface& surface, std::int64_t chart, const ChartBox& box, const BlendParts& parts,
               const EvaluationSlack& slack, BlendParts* scratch, BoxSample* out);

/// Which entries of shapes.reach have a bump that may be positive on `box`
/// (the others need not be evaluated there); and their edges, for
/// PouSurface::EvaluateParts.
void ReachingEdges(const PouSurface& surface, std::int64_t chart, const ChartBox& box, const ShapeMajorants& shapes,
                   BlendParts* parts);

/// Bound of the norm of theta_v's third derivative over `box` (which lies in
/// the piece `shapes` were bound over), given its sample;
/// +infinity when the box reaches a bump's support too close to the chart's
/// centre or too far out for the majorants.
double ThirdDerivativeBound(const PouSurface& surface, std::int64_t chart, const ChartBox& box,
                            const ShapeMajorants& shapes, const BoxSample& sample);

}  // namespace invmap::pou
