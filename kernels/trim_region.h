// The region of a trimmed surface's parameter plane: the points enclosed by
// closed loops of 2D (rational) Bezier pieces, by the even-odd rule, so the
// loops' orientations do not matter.
//
// Every test here is exact comparisons on control points, no root finding:
// a piece lies in the box of its control points (positive weights), and so
// does its control polygon. A point outside that box therefore sees the same
// winding of the piece as of the polygon (the straight-line homotopy between
// the two stays in the box), and a ray from the point in +u crosses the
// polygon an odd number of times exactly when the polygon's two ends lie on
// either side of the ray's line and the box lies beyond the point in u.
// Pieces whose box holds the point are halved (de Casteljau) until their
// halves' boxes do not, down to a resolution below which the point is taken
// to lie on the boundary. Straight pieces are decided by one orientation.
#pragma once

#include <cstdint>
#include <vector>

namespace invmap::kernels {

/// 2D (rational) Bezier pieces with their boxes: the tests the trimming
/// rests on.
class TrimPieces {
 public:
  /// Largest degree of a piece (CAD pcurves reach 25: OpenCascade's limit).
  static constexpr int kMaxDegree = 25;
  /// A piece's homogeneous control net, (w u, w v, w) per control point,
  /// and the halvings that made it (its boxes widen by their rounding).
  struct Net {
    int degree = 0;
    int depth = 0;
    double h[3 * (kMaxDegree + 1)];
  };

  void Add(const Net& net);
  int size() const { return static_cast<int>(degree_.size()); }
  const double* box(int piece) const { return &box_[4 * piece]; }
  void Load(int piece, Net* net) const;
  std::size_t MemoryBytes() const;

  /// Adds the pieces of `from` that may meet the box [lo, hi], halved while
  /// larger than `share` times the box in either direction (halves that do
  /// not meet it are left out).
  void AddRefined(const TrimPieces& from, const double* lo, const double* hi, double share);

  /// True when some piece may meet the closed box [lo, hi] (halved down to
  /// the box's size or `resolution` to tell).
  bool Meets(const double* lo, const double* hi, const double* resolution) const;

  /// Toggles *parity for each crossing of the ray from `uv` in +u with the
  /// pieces listed in `which` (count of them); false when `uv` lies within
  /// `resolution` of one of them.
  bool Parity(const double* uv, const int* which, int count, const double* resolution, bool* parity) const;

 private:
  std::vector<int> degree_, depth_, offset_;
  std::vector<double> h_;    // homogeneous control points, 3 per point
  std::vector<double> box_;  // 4 per piece: u lo, u hi, v lo, v hi
};

class TrimRegion {
 public:
  /// Where a point or a box lies. Crossing: some boundary piece may meet the
  /// box (a point: lies within the resolution of the boundary).
  enum class Side : std::uint8_t { Outside, Inside, Crossing };

  static constexpr int kMaxPieceDegree = TrimPieces::kMaxDegree;

  /// Appends one piece: a Bezier curve of `degree` (1..kMaxPieceDegree) with
  /// degree + 1 control points `uv` (u, v pairs) and positive `weights` (or
  /// null). The pieces of each loop must follow each other end to end, and
  /// every loop must be closed: piece k + 1 starts where piece k ends, the
  /// last ends where the loop's first starts (bit for bit).
  void AddPiece(int degree, const double* uv, const double* weights);

  /// Call once every piece is in: fixes the resolution (a tiny share of the
  /// pieces' extent in each parameter), halves the pieces until small beside
  /// the region, and indexes them by v for the rays.
  void Finish();

  int numPieces() const { return pieces_.size(); }
  std::size_t MemoryBytes() const;

  /// The region's pieces that may meet the box [lo, hi], halved to a
  /// sixteenth of its size: what ClassifyBox needs for boxes inside it
  /// (a cell's), so their tests start small.
  TrimPieces PiecesFor(const double* lo, const double* hi) const;

  /// Side of the closed box [lo, hi] (lo == hi in a direction is allowed:
  /// a segment or a point); `near` holds every piece that may meet it
  /// (PiecesFor a box holding it).
  Side ClassifyBox(const double* lo, const double* hi, const TrimPieces& near) const;

  /// Side of one point: Inside, Outside, or Crossing within the resolution
  /// of the boundary.
  Side ClassifyPoint(const double* uv) const;

 private:
  /// Finish's halving: down to this share of the region's extent in each
  /// parameter, at most kPresplitDepth times.
  static constexpr double kPieceShare = 1.0 / 32.0;
  static constexpr int kPresplitDepth = 10;
  /// Adds `net` to pieces_, halved further while large beside `extent`.
  void AddSplit(const TrimPieces::Net& net, const double* extent);

  TrimPieces loops_;   // as added, closed loops
  TrimPieces pieces_;  // halved by Finish
  double resolution_[2] = {0, 0};
  // The pieces whose v range meets each of the buckets of equal height
  // between bucketLo_ and bucketLo_ + buckets / bucketScale_: a ray meets
  // only those of its bucket.
  double bucketLo_ = 0.0, bucketScale_ = 0.0;
  std::vector<int> bucketFirst_, bucketPieces_;
};

}  // namespace invmap::kernels
