// The closest points between TWO cells: the joint parameters w = (u, v) of a
// pair, their domain (the product of the two cells' reference domains), and
// the joint map z(w) = x(u) - y(v), whose squared length the pair kernels
// minimize. Each cell keeps its control net in its own model's frame and is
// placed in a common frame by a rigid motion, so a moving model is never
// rebuilt.
#pragma once

#include "kernels/bernstein.h"
#include "kernels/cell_map.h"
#include "kernels/distance_net.h"
#include "kernels/trimmed_cell.h"

namespace invmap::kernels {

/// Most joint parameters of a pair (two volumes' worth).
constexpr int kMaxPairParams = 2 * kMaxDim;
/// Most constraints of a pair's domain: one per barycentric coordinate of
/// every simplex factor of both cells (a hex has 6, a tet 4).
constexpr int kMaxPairConstraints = 4 * kMaxDim;

/// A rigid motion x -> rotation x + translation (3D; a 2D cell has z = 0
/// and a motion that keeps the plane).
struct RigidMotion {
  double rotation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double translation[3] = {0, 0, 0};

  /// out = rotation x + translation (3 coordinates; `x` may alias `out`).
  void Apply(const double* x, double* out) const;
  /// out = rotation v (3 coordinates; `v` may alias `out`).
  void Rotate(const double* v, double* out) const;
  /// True when the rotation is the identity and the translation zero.
  bool IsIdentity() const;
};

/// One cell of a pair as the pair kernels see it.
struct PairSide {
  CellView cell;        ///< The control net, in its model's frame.
  RigidMotion motion;   ///< Its model's frame into the common frame.
  double size = 1.0;    ///< Diagonal of the control-point box (CellSolver::size).
  /// The cell's distance nets (kernels/distance_net.h), built around its
  /// control box's centre in its model's frame. Needed by the certified
  /// search unless both cells are affine.
  const DistanceNets* nets = nullptr;
  bool affine = false;  ///< The map is affine (CellSolver::isAffine).
  /// A cell of a trimmed face that the face's loops cross (CellSolver::trim),
  /// or null: the pair kernels then answer only points its region admits
  /// (the face's edges, curve cells of their own, answer its boundary).
  const TrimmedCell* trim = nullptr;
};

/// The joint parameters of a pair: w = (u_0 .. u_{pdA-1}, v_0 .. v_{pdB-1}),
/// and the linear constraints of their domain, one per barycentric
/// coordinate of each simplex factor: either w[first] >= 0, or
/// 1 - (w[first] + .. + w[first + count - 1]) >= 0.
class PairLayout {
 public:
  struct Constraint {
    int first = 0;
    int count = 1;
    bool sum = false;  ///< The factor's implicit coordinate 1 - sum.
  };

  PairLayout() = default;
  PairLayout(const CellShape& a, const CellShape& b);

  int n() const { return n_; }
  /// Parameters of side 0 (A) or 1 (B); side s's start at offset(s).
  int paramDim(int side) const { return paramDim_[side]; }
  int offset(int side) const { return side == 0 ? 0 : paramDim_[0]; }
  const CellShape& shape(int side) const { return shape_[side]; }
  int numConstraints() const { return numConstraints_; }
  const Constraint& constraint(int c) const { return constraints_[c]; }
  /// The constraint's value at w (>= 0 inside the domain).
  double Slack(int c, const double* w) const;
  /// The gradient of Slack (n values).
  void Normal(int c, double* normal) const;
  /// Moves w into the domain: negative coordinates to 0, a factor whose
  /// coordinates sum past 1 scaled back onto its face.
  void Project(double* w) const;
  /// The centroid of the domain.
  void Center(double* w) const;

 private:
  CellShape shape_[2];
  int paramDim_[2] = {0, 0};
  int n_ = 0;
  int numConstraints_ = 0;
  Constraint constraints_[kMaxPairConstraints];
};

/// An edge of a pair's subdomain: vertices vi and vj of simplex factor
/// `factor` of side `side`.
struct PairEdge {
  int side = 0, factor = 0, vi = 0, vj = 1;
};

/// The longest edge of a pair's subdomain, each parameter's length scaled
/// by paramScale (the cells' lengths per joint parameter); vertex(side,
/// factor, v) gives a vertex's reference coordinates. Ties keep the first.
template <typename VertexOf>
PairEdge LongestPairEdge(const PairLayout& layout, const double* paramScale, VertexOf&& vertex) {
  PairEdge edge;
  double longest = -1.0;
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      for (int p = 0; p <= fac.dim; ++p) {
        for (int q = p + 1; q <= fac.dim; ++q) {
          double length2 = 0.0;
          for (int i = 0; i < fac.dim; ++i) {
            const double e =
                (vertex(side, f, p)[i] - vertex(side, f, q)[i]) * paramScale[layout.offset(side) + fac.offset + i];
            length2 += e * e;
          }
          if (length2 > longest) {
            longest = length2;
            edge = PairEdge{side, f, p, q};
          }
        }
      }
    }
  }
  return edge;
}

/// The joint map z(w) = x(u) - y(v) in the common frame, with its
/// derivatives along the joint parameters (the second ones are block
/// diagonal: x depends on u alone, y on v alone).
struct PairJet {
  double x[3] = {0, 0, 0};  ///< Side A's point.
  double y[3] = {0, 0, 0};  ///< Side B's point.
  double z[3] = {0, 0, 0};  ///< x - y.
  double d1[3][kMaxPairParams] = {};                  ///< dz_k / dw_i.
  double d2[3][kMaxPairParams][kMaxPairParams] = {};  ///< d2 z_k / dw_i dw_j (order Second).
};

/// Evaluates the pair's joint map at w up to `order`. The ambient
/// dimension is the cells' (both the same).
void EvaluatePair(const PairSide& a, const PairSide& b, const PairLayout& layout, const double* w, JetOrder order,
                  PairJet* jet);

/// |z|^2 of a jet (ambient coordinates of the cells).
double PairSquaredDistance(const PairJet& jet, int ambientDim);

/// The weight function W(ref) of a cell: 1 for a polynomial cell.
double CellWeightAt(const CellView& cell, const double* ref);

}  // namespace invmap::kernels
