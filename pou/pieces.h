// The pieces that cover a partition-of-unity surface for the closest-point
// search (docs/manifold.md, "Inversion").
//
// Chart v answers for the part of each of its triangles where v's
// barycentric coordinate is the largest (in the canonical frames of the
// transition maps: the kite between v, the midpoints of its two edges and
// the centroid). Those parts cover the surface: a point of the surface is
// theta_u(p) for some chart u and p, p has barycentric coordinates in one of
// u's triangles, and the corner v with the largest of them holds the same
// point of the surface, theta_u(p) = theta_v(phi_vu(p)), in its kite. In
// v's p-domain the kites lie within 2R/3 of the centre (R its radius).
//
// Each chart's pieces are the squares of a 7 x 7 grid over [-c, c]^2, c =
// 0.68 R, which holds that disk, those that meet the kites (the middle one,
// about the centre, lies where theta_v = psi_v). A piece carries the
// majorants of the shape functions over it (pou/piece_bounds.h) and boxes
// of R^3 that hold the image of its part of the kites, axis-aligned and
// oriented: the union, over a grid of cells (split further where the third
// derivative's bound is infinite or large), of the Taylor expansion at the
// cell's centre (its linear and quadratic terms' reach along each axis)
// with the remainder M rho^3 / 6 (M the cell's bound of the third
// derivative, rho its radius) and the evaluation's rounding allowance.
#pragma once

#include <cstdint>
#include <vector>

#include "pou/piece_bounds.h"
#include "pou/pou_surface.h"

namespace invmap::pou {

/// The disk of a chart its pieces must cover, as a share of R (the kites
/// reach 2R/3).
constexpr double kCoveredRadius = 0.68;

/// Squares per side of a chart's grid (odd: the middle one lies about the
/// centre, inside the disk where theta_v = psi_v).
constexpr int kPieceGrid = 7;

/// One piece, as the search keeps it (24 bytes: large meshes have millions).
struct Piece {
  std::int32_t chart = 0;
  std::uint8_t column = 0, row = 0;  ///< Its square of the chart's grid.
  std::uint16_t reachCount = 0;      ///< Its neighbours in PieceSet's pool.
  std::uint32_t firstReach = 0;
  float own[3] = {0, 0, 0};          ///< psi_v's majorant over the square (ShapeMajorants::own).
};

/// Two boxes of R^3 that hold theta_v of a piece's part of the kites: one
/// along the coordinate axes, one oriented (lo_j <= axis_j . x <= hi_j), its
/// orthonormal axes along the tangent plane and the normal at the square's
/// centre, as thin across the surface as the piece bulges. For the search
/// tree's build only.
struct PieceBounds {
  double boxLo[3] = {0, 0, 0}, boxHi[3] = {0, 0, 0};
  double axis[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double orientedLo[3] = {0, 0, 0}, orientedHi[3] = {0, 0, 0};
  /// The oriented box's corners (whose convex hull it is), 8 x 3 coordinates.
  void OrientedCorners(double out[24]) const;
};

/// Every chart's pieces, in chart order, and the neighbours' majorants they
/// point into.
class PieceSet {
 public:
  /// Builds the pieces of every chart; `bounds` receives each piece's boxes.
  void Build(const PouSurface& surface, std::vector<PieceBounds>* bounds);

  const std::vector<Piece>& pieces() const { return pieces_; }
  ShapeMajorants Shapes(const Piece& piece) const {
    return {{piece.own[0], piece.own[1], piece.own[2]}, reach_.data() + piece.firstReach, piece.reachCount};
  }
  std::size_t MemoryBytes() const {
    return pieces_.capacity() * sizeof(Piece) + reach_.capacity() * sizeof(ReachingShape);
  }

 private:
  std::vector<Piece> pieces_;
  std::vector<ReachingShape> reach_;
};

/// The square of chart coordinates a piece covers.
ChartBox PieceBox(const PouSurface& surface, const Piece& piece);

}  // namespace invmap::pou
