#include "kernels/trim_region.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

/// Deepest halving of a piece: far below any resolution a double can hold
/// on a piece that starts at most the whole region.
constexpr int kMaxHalvings = 80;

/// The box of a homogeneous net's Cartesian control points, widened by the
/// rounding its halvings may have carried in: each level's de Casteljau
/// averages round once per step, and the net of depth k is that many levels
/// of rounding away from the exact half of the original piece.
void NetBox(const double* h, int degree, int depth, double box[4]) {
  box[0] = box[2] = std::numeric_limits<double>::infinity();
  box[1] = box[3] = -std::numeric_limits<double>::infinity();
  double magnitude = 0.0;
  for (int i = 0; i <= degree; ++i) {
    const double u = h[3 * i] / h[3 * i + 2], v = h[3 * i + 1] / h[3 * i + 2];
    box[0] = std::min(box[0], u);
    box[1] = std::max(box[1], u);
    box[2] = std::min(box[2], v);
    box[3] = std::max(box[3], v);
    magnitude = std::max({magnitude, std::abs(u), std::abs(v)});
  }
  const double margin = 8.0 * std::numeric_limits<double>::epsilon() * (depth + 1) * (degree + 2) * magnitude;
  box[0] -= margin;
  box[1] += margin;
  box[2] -= margin;
  box[3] += margin;
}

bool BoxHolds(const double box[4], const double* uv) {
  return uv[0] >= box[0] && uv[0] <= box[1] && uv[1] >= box[2] && uv[1] <= box[3];
}

bool BoxesMeet(const double box[4], const double* lo, const double* hi) {
  return box[0] <= hi[0] && box[1] >= lo[0] && box[2] <= hi[1] && box[3] >= lo[1];
}

/// Halves a homogeneous net at t = 1/2 (de Casteljau): `left` gets [0, 1/2],
/// `right` [1/2, 1], sharing the midpoint bit for bit.
void Halve(const double* h, int degree, double* left, double* right) {
  double work[3 * (TrimPieces::kMaxDegree + 1)];
  std::copy(h, h + 3 * (degree + 1), work);
  for (int k = 0; k < 3; ++k) {
    left[k] = work[k];
    right[3 * degree + k] = work[3 * degree + k];
  }
  for (int level = 1; level <= degree; ++level) {
    for (int i = 0; i <= degree - level; ++i) {
      for (int k = 0; k < 3; ++k) work[3 * i + k] = 0.5 * (work[3 * i + k] + work[3 * (i + 1) + k]);
    }
    for (int k = 0; k < 3; ++k) {
      left[3 * level + k] = work[k];
      right[3 * (degree - level) + k] = work[3 * (degree - level) + k];
    }
  }
}

/// The crossings of the ray from `uv` in +u with a polygon whose box does
/// not hold `uv`, mod 2: its segments that straddle the ray's line (half
/// open: v > uv[1] on one side) all lie beyond `uv` when the box does, and
/// a path straddles the line an odd number of times exactly when its ends
/// lie on either side.
bool OutsideParity(const double box[4], double firstV, double lastV, const double* uv) {
  return box[0] > uv[0] && ((firstV > uv[1]) != (lastV > uv[1]));
}

/// Orientation of c against the line through a and b: positive left of
/// a -> b; 0 when rounding could give either sign (c within rounding of
/// the line), so callers treat 0 as "on it".
double Orientation(const double* a, const double* b, const double* c) {
  const double left = (b[0] - a[0]) * (c[1] - a[1]);
  const double right = (b[1] - a[1]) * (c[0] - a[0]);
  const double bound = 8.0 * std::numeric_limits<double>::epsilon() * (std::abs(left) + std::abs(right));
  const double o = left - right;
  return std::abs(o) > bound ? o : 0.0;
}

/// A straight piece from a to b against the ray from `uv` in +u: adds its
/// crossing to *parity; false when `uv` lies on the segment (to rounding).
bool SegmentParity(const double* a, const double* b, const double* uv, bool* parity) {
  if ((a[1] > uv[1]) == (b[1] > uv[1])) {
    // No straddle; the point may still lie on a level segment.
    if (a[1] == uv[1] && b[1] == uv[1] && uv[0] >= std::min(a[0], b[0]) && uv[0] <= std::max(a[0], b[0])) return false;
    return true;
  }
  const double o = Orientation(a, b, uv);
  if (o == 0.0) return false;
  // The crossing lies beyond uv (larger u) when uv is left of a rising
  // segment or right of a falling one.
  *parity ^= (o > 0.0) == (b[1] > a[1]);
  return true;
}

/// True when the segment a -> b may meet the box [lo, hi]: the part of the
/// segment's line inside the segment's own box is the segment, so it meets
/// [lo, hi] exactly when its line meets the two boxes' common part.
bool SegmentMeets(const double* a, const double* b, const double* lo, const double* hi) {
  const double clo[2] = {std::max(lo[0], std::min(a[0], b[0])), std::max(lo[1], std::min(a[1], b[1]))};
  const double chi[2] = {std::min(hi[0], std::max(a[0], b[0])), std::min(hi[1], std::max(a[1], b[1]))};
  if (clo[0] > chi[0] || clo[1] > chi[1]) return false;
  bool positive = false, negative = false;
  for (int corner = 0; corner < 4; ++corner) {
    const double c[2] = {corner & 1 ? chi[0] : clo[0], corner & 2 ? chi[1] : clo[1]};
    const double o = Orientation(a, b, c);
    positive = positive || o >= 0.0;
    negative = negative || o <= 0.0;
  }
  return positive && negative;
}



bool PieceParity(const TrimPieces::Net& net, const double* uv, const double* resolution, bool* parity) {
  const int n = net.degree;
  if (n == 1) {
    const double a[2] = {net.h[0] / net.h[2], net.h[1] / net.h[2]}, b[2] = {net.h[3] / net.h[5], net.h[4] / net.h[5]};
    return SegmentParity(a, b, uv, parity);
  }
  double box[4];
  NetBox(net.h, n, net.depth, box);
  if (!BoxHolds(box, uv)) {
    *parity ^= OutsideParity(box, net.h[1] / net.h[2], net.h[3 * n + 1] / net.h[3 * n + 2], uv);
    return true;
  }
  if ((box[1] - box[0] <= resolution[0] && box[3] - box[2] <= resolution[1]) || net.depth >= kMaxHalvings) return false;
  TrimPieces::Net left, right;
  left.degree = right.degree = n;
  left.depth = right.depth = net.depth + 1;
  Halve(net.h, n, left.h, right.h);
  return PieceParity(left, uv, resolution, parity) && PieceParity(right, uv, resolution, parity);
}

bool PieceMeets(const TrimPieces::Net& net, const double* lo, const double* hi, const double* resolution) {
  const int n = net.degree;
  if (n == 1) {
    const double a[2] = {net.h[0] / net.h[2], net.h[1] / net.h[2]}, b[2] = {net.h[3] / net.h[5], net.h[4] / net.h[5]};
    return SegmentMeets(a, b, lo, hi);
  }
  double box[4];
  NetBox(net.h, n, net.depth, box);
  if (!BoxesMeet(box, lo, hi)) return false;
  // No larger than the box (or the resolution) in both directions: halving
  // further could not tell whether the piece itself enters it.
  bool small = true;
  for (int d = 0; d < 2; ++d) {
    small = small && box[2 * d + 1] - box[2 * d] <= 2.0 * std::max(hi[d] - lo[d], resolution[d]);
  }
  if (small || net.depth >= kMaxHalvings) return true;
  TrimPieces::Net left, right;
  left.degree = right.degree = n;
  left.depth = right.depth = net.depth + 1;
  Halve(net.h, n, left.h, right.h);
  return PieceMeets(left, lo, hi, resolution) || PieceMeets(right, lo, hi, resolution);
}

}  // namespace

void TrimPieces::Add(const Net& net) {
  degree_.push_back(net.degree);
  depth_.push_back(net.depth);
  offset_.push_back(static_cast<int>(h_.size() / 3));
  h_.insert(h_.end(), net.h, net.h + 3 * (net.degree + 1));
  double box[4];
  NetBox(net.h, net.degree, net.depth, box);
  box_.insert(box_.end(), box, box + 4);
}

void TrimPieces::Load(int piece, Net* net) const {
  net->degree = degree_[piece];
  net->depth = depth_[piece];
  const double* h = &h_[3 * offset_[piece]];
  std::copy(h, h + 3 * (net->degree + 1), net->h);
}

std::size_t TrimPieces::MemoryBytes() const {
  return (degree_.capacity() + depth_.capacity() + offset_.capacity()) * sizeof(int) +
         (h_.capacity() + box_.capacity()) * sizeof(double);
}

void TrimPieces::AddRefined(const TrimPieces& from, const double* lo, const double* hi, double share) {
  const double limit[2] = {share * (hi[0] - lo[0]), share * (hi[1] - lo[1])};
  // Depth-first over the halves that still meet the box.
  std::vector<Net> stack;
  for (int p = 0; p < from.size(); ++p) {
    if (!BoxesMeet(from.box(p), lo, hi)) continue;
    stack.emplace_back();
    from.Load(p, &stack.back());
    while (!stack.empty()) {
      Net net = stack.back();
      stack.pop_back();
      double box[4];
      NetBox(net.h, net.degree, net.depth, box);
      if (!BoxesMeet(box, lo, hi)) continue;
      const bool small = box[1] - box[0] <= limit[0] && box[3] - box[2] <= limit[1];
      if (net.degree == 1 || small || net.depth >= kMaxHalvings) {
        Add(net);
        continue;
      }
      Net left, right;
      left.degree = right.degree = net.degree;
      left.depth = right.depth = net.depth + 1;
      Halve(net.h, net.degree, left.h, right.h);
      stack.push_back(right);
      stack.push_back(left);
    }
  }
}

bool TrimPieces::Meets(const double* lo, const double* hi, const double* resolution) const {
  Net net;
  for (int p = 0; p < size(); ++p) {
    if (!BoxesMeet(box(p), lo, hi)) continue;
    Load(p, &net);
    if (PieceMeets(net, lo, hi, resolution)) return true;
  }
  return false;
}

bool TrimPieces::Parity(const double* uv, const int* which, int count, const double* resolution, bool* parity) const {
  Net net;
  for (int i = 0; i < count; ++i) {
    const int p = which[i];
    const double* b = box(p);
    if (!BoxHolds(b, uv)) {
      const int first = offset_[p], last = first + degree_[p];
      *parity ^= OutsideParity(b, h_[3 * first + 1] / h_[3 * first + 2], h_[3 * last + 1] / h_[3 * last + 2], uv);
      continue;
    }
    Load(p, &net);
    if (!PieceParity(net, uv, resolution, parity)) return false;
  }
  return true;
}

void TrimRegion::AddPiece(int degree, const double* uv, const double* weights) {
  TrimPieces::Net net;
  net.degree = degree;
  for (int i = 0; i <= degree; ++i) {
    const double w = weights ? weights[i] : 1.0;
    net.h[3 * i] = w * uv[2 * i];
    net.h[3 * i + 1] = w * uv[2 * i + 1];
    net.h[3 * i + 2] = w;
  }
  loops_.Add(net);
}

void TrimRegion::Finish() {
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  for (int p = 0; p < loops_.size(); ++p) {
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], loops_.box(p)[2 * d]);
      hi[d] = std::max(hi[d], loops_.box(p)[2 * d + 1]);
    }
  }
  if (loops_.size() == 0) return;
  for (int d = 0; d < 2; ++d) {
    const double magnitude = std::max(std::abs(lo[d]), std::abs(hi[d]));
    resolution_[d] = kTrimResolution * ((hi[d] - lo[d]) + magnitude);
  }
  // Pieces are halved once here until their boxes are small beside the
  // region: the tests then mostly settle on the boxes alone instead of
  // halving the same pieces again for every subdomain of every query.
  const double extent[2] = {hi[0] - lo[0], hi[1] - lo[1]};
  TrimPieces::Net net;
  for (int p = 0; p < loops_.size(); ++p) {
    loops_.Load(p, &net);
    AddSplit(net, extent);
  }
  // Rays in +u meet only the pieces whose v range holds theirs.
  const int buckets = std::clamp(pieces_.size(), 1, 1024);
  bucketLo_ = lo[1];
  bucketScale_ = hi[1] > lo[1] ? buckets / (hi[1] - lo[1]) : 0.0;
  std::vector<std::vector<int>> members(static_cast<std::size_t>(buckets));
  auto bucketOf = [&](double v) {
    return std::clamp(static_cast<int>(std::floor((v - bucketLo_) * bucketScale_)), 0, buckets - 1);
  };
  for (int p = 0; p < pieces_.size(); ++p) {
    for (int b = bucketOf(pieces_.box(p)[2]); b <= bucketOf(pieces_.box(p)[3]); ++b) members[b].push_back(p);
  }
  bucketFirst_.assign(1, 0);
  for (const std::vector<int>& m : members) {
    bucketPieces_.insert(bucketPieces_.end(), m.begin(), m.end());
    bucketFirst_.push_back(static_cast<int>(bucketPieces_.size()));
  }
  loops_ = TrimPieces();
}

void TrimRegion::AddSplit(const TrimPieces::Net& net, const double* extent) {
  double box[4];
  NetBox(net.h, net.degree, net.depth, box);
  const bool small = box[1] - box[0] <= kPieceShare * extent[0] && box[3] - box[2] <= kPieceShare * extent[1];
  if (net.degree == 1 || small || net.depth >= kPresplitDepth) {
    pieces_.Add(net);
    return;
  }
  TrimPieces::Net left, right;
  left.degree = right.degree = net.degree;
  left.depth = right.depth = net.depth + 1;
  Halve(net.h, net.degree, left.h, right.h);
  AddSplit(left, extent);
  AddSplit(right, extent);
}

std::size_t TrimRegion::MemoryBytes() const {
  return loops_.MemoryBytes() + pieces_.MemoryBytes() +
         (bucketFirst_.capacity() + bucketPieces_.capacity()) * sizeof(int);
}

TrimPieces TrimRegion::PiecesFor(const double* lo, const double* hi) const {
  // A hair wider: the subdomains' own boxes are widened by their rounding.
  double wideLo[2], wideHi[2];
  for (int d = 0; d < 2; ++d) {
    const double margin = kTrimBoxMargin * (hi[d] - lo[d]) + resolution_[d];
    wideLo[d] = lo[d] - margin;
    wideHi[d] = hi[d] + margin;
  }
  TrimPieces near;
  near.AddRefined(pieces_, wideLo, wideHi, 1.0 / 16.0);
  return near;
}

TrimRegion::Side TrimRegion::ClassifyBox(const double* lo, const double* hi, const TrimPieces& near) const {
  if (near.Meets(lo, hi, resolution_)) return Side::Crossing;
  // No piece enters the box: it lies wholly on the side of its center.
  const double center[2] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])};
  return ClassifyPoint(center);
}

TrimRegion::Side TrimRegion::ClassifyPoint(const double* uv) const {
  if (bucketFirst_.size() < 2) return Side::Inside;  // no loops: the whole surface
  const int buckets = static_cast<int>(bucketFirst_.size()) - 1;
  const double at = (uv[1] - bucketLo_) * bucketScale_;
  // Beyond every piece's v range no ray crosses the boundary.
  if (!(at >= -1.0 && at <= buckets + 1.0)) return Side::Outside;
  const int b = std::clamp(static_cast<int>(std::floor(at)), 0, buckets - 1);
  bool parity = false;
  if (!pieces_.Parity(uv, bucketPieces_.data() + bucketFirst_[b], bucketFirst_[b + 1] - bucketFirst_[b], resolution_,
                      &parity)) {
    return Side::Crossing;
  }
  return parity ? Side::Inside : Side::Outside;
}

}  // namespace invmap::kernels
