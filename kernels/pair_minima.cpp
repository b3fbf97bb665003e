#include "kernels/pair_minima.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "kernels/bernstein_net.h"
#include "kernels/cell_bounds.h"
#include "kernels/cell_minima.h"
#include "kernels/cell_solver.h"
#include "kernels/pair_certificate.h"
#include "kernels/pair_local_solve.h"
#include "kernels/pair_nets.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// How far off every face of the domain a converged solve must lie (in
/// barycentric coordinates) for the cells' refusal of it to be suspect:
/// beyond rounding of the boundary, where the distance may fall into it.
constexpr double kOffFace = 1e-9;

/// A subdomain pair in the workspace: depth, the vertices of every factor's
/// sub-simplex on both sides (the problem's reference coordinates), then
/// A's nets, B's nets, and each side's homogeneous control net on its
/// subdomain (w P in the model's frame, then w).
constexpr int kDepth = 0;
constexpr int kVertices = 1;
constexpr int kHeaderSize = kVertices + 2 * kMaxFactors * 4 * 3;
/// Faces of faces: a hex's edge is two reductions away from it.
constexpr int kMaxRecursion = 6;
/// A polished minimum is the same one when its points moved by at most
/// this share of the cells' sizes.
constexpr double kSamePointShare = 1e-6;
/// Newton steps of that polish: it starts next to the minimum.
constexpr int kPolishIterations = 10;

double* Vertex(double* slot, int side, int factor, int vertex) {
  return slot + kVertices + ((side * kMaxFactors + factor) * 4 + vertex) * 3;
}

void Barycentric(int dim, const double* s, double* lambda) {
  lambda[0] = 1.0;
  for (int i = 0; i < dim; ++i) {
    lambda[i + 1] = s[i];
    lambda[0] -= s[i];
  }
}

/// The vertices of a cell's reference domain (a product of simplices).
std::vector<std::array<double, 3>> ReferenceCorners(const CellShape& shape) {
  std::vector<std::array<double, 3>> corners{{0, 0, 0}};
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    std::vector<std::array<double, 3>> next;
    for (const std::array<double, 3>& corner : corners) {
      for (int v = 0; v <= fac.dim; ++v) {
        std::array<double, 3> out = corner;
        if (v > 0) out[fac.offset + v - 1] = 1.0;
        next.push_back(out);
      }
    }
    corners = std::move(next);
  }
  return corners;
}

/// A cell the search made (a subdomain or one of its faces), with its nets.
struct OwnedCell {
  std::vector<double> points, weights;
  CellView view;
  DistanceNets nets;
  double size = 1.0;
  bool affine = false;

  /// From a homogeneous net (coordinate k of control point c at
  /// homogeneous[k * count + c], the weight last).
  void Set(const CellShape& shape, int ad, bool rational, const std::vector<double>& homogeneous, int count) {
    points.resize(static_cast<size_t>(count) * ad);
    weights.resize(count);
    for (int c = 0; c < count; ++c) {
      const double w = homogeneous[static_cast<size_t>(ad) * count + c];
      weights[c] = w;
      for (int k = 0; k < ad; ++k) points[static_cast<size_t>(c) * ad + k] = homogeneous[static_cast<size_t>(k) * count + c] / w;
    }
    view.shape = shape;
    view.ambientDim = ad;
    view.points = points.data();
    view.weights = rational ? weights.data() : nullptr;
    double lo[3], hi[3], center[3], d2 = 0.0;
    ComputeControlBox(view, lo, hi);
    for (int k = 0; k < 3; ++k) {
      center[k] = 0.5 * (lo[k] + hi[k]);
      d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    size = std::sqrt(d2);
    if (!(size > 0.0)) size = 1e-300;
    affine = IsAffineCell(view, size);
    if (shape.paramDim() > 0) nets.Build(view, center);
  }
};

/// Reference coordinates of a sub-problem's cell in the original cell's:
/// origin + matrix t.
struct RefMap {
  double origin[3] = {0, 0, 0};
  double matrix[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

  void Apply(const double* t, double* out) const {
    for (int i = 0; i < 3; ++i) {
      out[i] = origin[i];
      for (int j = 0; j < 3; ++j) out[i] += matrix[i][j] * t[j];
    }
  }
  /// this o inner.
  RefMap Compose(const RefMap& inner) const {
    RefMap out;
    Apply(inner.origin, out.origin);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        out.matrix[i][j] = 0.0;
        for (int k = 0; k < 3; ++k) out.matrix[i][j] += matrix[i][k] * inner.matrix[k][j];
      }
    }
    return out;
  }
};

/// The distance must grow into the original cell of `side` along its
/// parameter `param` (a face a reduction was forced onto by the distance
/// bending down across it).
struct Strict {
  int side;
  int param;
};

struct Problem {
  PairSide side[2];
  RefMap map[2];
  std::vector<Strict> strict;
  std::shared_ptr<OwnedCell> owned[2];
  int recursion = 0;
};

class Enumerator {
 public:
  Enumerator(const PairSide& a, const PairSide& b, double maxDistance, PairMinimaResult* out)
      : original_{a, b}, layout_(a.cell.shape, b.cell.shape), maxDistance_(maxDistance), out_(out) {
    size_ = a.size + b.size;
  }

  void Run(const Problem& problem);

 private:
  /// Records the point pair (original reference coordinates) when it is a
  /// KKT point of the original pair within reach, with every strict slope.
  /// What Record made of a point.
  enum class Recorded { Minimum, Elsewhere, NotKkt };
  /// Minimum when recorded; Elsewhere when the point lies outside a
  /// trimmed face's region or beyond the distance asked for; NotKkt when it
  /// is no minimum of the cells (not stationary, or falling into a cell).
  Recorded Record(const double* refA, const double* refB, const std::vector<Strict>& strict);
  /// The sub-problem's answer back to the original cells.
  Recorded RecordLocal(const Problem& problem, double* slot, const double* local);
  void SolveIn(const Problem& problem, double* slot);
  /// The minima of the subdomain pair on its face where `side`'s line
  /// factor `factor` is at local vertex `vertex` (a face of the problem's cell).
  void ReduceToFace(const Problem& problem, double* slot, int side, int factor, int vertex, bool strict);
  std::vector<double> Homogeneous(const Problem& problem, double* slot, int side) const;
  /// True when every control point of a face of side `side` (homogeneous,
  /// as Homogeneous gives them) is one point to the distance tolerance.
  bool CollapsedFace(const std::vector<double>& homogeneous, int count, int ad, int side) const;
  /// The local-to-problem map of side `side` of the subdomain.
  RefMap SubdomainMap(const Problem& problem, double* slot, int side) const;
  /// True when a trimmed side's part of the subdomain lies wholly outside
  /// its face's region (it holds no minimum of the face).
  bool OutsideRegion(const Problem& problem, double* slot) const;

  PairSide original_[2];
  PairLayout layout_;
  double maxDistance_;
  double size_ = 1.0;
  PairMinimaResult* out_;
  // Per Run (nested runs keep their own copies on the stack of calls).
  int slotSize_ = 0;
  int netLength_[2] = {0, 0};
  int controlCount_[2] = {0, 0};
};

std::vector<double> Enumerator::Homogeneous(const Problem& problem, double* slot, int side) const {
  const int ad = problem.side[0].cell.ambientDim;
  const double* start = slot + kHeaderSize + netLength_[0] + netLength_[1] +
                        (side == 1 ? static_cast<size_t>(ad + 1) * controlCount_[0] : 0);
  return std::vector<double>(start, start + static_cast<size_t>(ad + 1) * controlCount_[side]);
}

bool Enumerator::CollapsedFace(const std::vector<double>& homogeneous, int count, int ad, int side) const {
  const double tolerance = kDistanceTolerance * original_[side].size;
  for (int c = 1; c < count; ++c) {
    double gap2 = 0.0;
    for (int k = 0; k < ad; ++k) {
      const double first = homogeneous[static_cast<size_t>(k) * count] / homogeneous[static_cast<size_t>(ad) * count];
      const double here =
          homogeneous[static_cast<size_t>(k) * count + c] / homogeneous[static_cast<size_t>(ad) * count + c];
      gap2 += (here - first) * (here - first);
    }
    if (!(std::sqrt(gap2) <= tolerance)) return false;
  }
  return true;
}

RefMap Enumerator::SubdomainMap(const Problem& problem, double* slot, int side) const {
  RefMap local;
  for (auto& row : local.matrix) std::fill(row, row + 3, 0.0);
  const CellShape& shape = problem.side[side].cell.shape;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      local.origin[fac.offset + i] = Vertex(slot, side, f, 0)[i];
      for (int k = 1; k <= fac.dim; ++k) {
        local.matrix[fac.offset + i][fac.offset + k - 1] = Vertex(slot, side, f, k)[i] - Vertex(slot, side, f, 0)[i];
      }
    }
  }
  return problem.map[side].Compose(local);
}

bool Enumerator::OutsideRegion(const Problem& problem, double* slot) const {
  for (int side = 0; side < 2; ++side) {
    const TrimmedCell* trim = original_[side].trim;
    if (!trim) continue;
    // The subdomain's box in the original cell's reference coordinates:
    // the map is affine, so its corners' images bound it.
    const RefMap map = SubdomainMap(problem, slot, side);
    const int pd = problem.side[side].cell.shape.paramDim();
    double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    for (int corner = 0; corner < (1 << pd); ++corner) {
      double t[3] = {0, 0, 0}, ref[3];
      for (int i = 0; i < pd; ++i) t[i] = (corner >> i) & 1;
      map.Apply(t, ref);
      for (int d = 0; d < 2; ++d) {
        lo[d] = std::min(lo[d], ref[d]);
        hi[d] = std::max(hi[d], ref[d]);
      }
    }
    if (trim->ClassifySubdomain(lo, hi) == TrimRegion::Side::Outside) return true;
  }
  return false;
}

Enumerator::Recorded Enumerator::Record(const double* refA, const double* refB, const std::vector<Strict>& strict) {
  double w[kMaxPairParams];
  const int pa = layout_.paramDim(0), pb = layout_.paramDim(1);
  std::copy(refA, refA + pa, w);
  std::copy(refB, refB + pb, w + pa);
  layout_.Project(w);
  // A trimmed face's minima are those its region admits (its boundary's
  // are its edges', curve cells of their own).
  for (int side = 0; side < 2; ++side) {
    const TrimmedCell* trim = original_[side].trim;
    if (trim && !trim->Admits(w + layout_.offset(side))) return Recorded::Elsewhere;
  }
  PairJet jet;
  EvaluatePair(original_[0], original_[1], layout_, w, JetOrder::Second, &jet);
  const int ad = original_[0].cell.ambientDim;
  double d = std::sqrt(PairSquaredDistance(jet, ad));
  if (!(d <= maxDistance_)) return Recorded::Elsewhere;
  PairKkt kkt = CheckPairKkt(layout_, jet, w, ad, size_);
  if (!kkt.kkt) {
    // A solve on a subdomain's own nets (a cell of its own) stops within
    // its tolerance of that cell, which the original pair's test may find
    // short of stationary (a rational cell's heavy weights): polished on
    // the original pair, it counts when it stays at the same points.
    PairLocalOptions options;
    options.size = size_;
    options.maxIterations = kPolishIterations;
    // Its final Newton step, whose decrease the distance's rounding hides,
    // is taken however long in the parameters: the test of the points
    // moved below bounds it. On a cell small beside the distance and the
    // other cell (a sphere of radius 0.01 half a unit from a polyline of
    // size 4) that step is longer than kFinalStep, which left the solve
    // short of the cells' KKT test at the minimum itself: it was dropped.
    options.finalStep = kInf;
    const PairLocalResult polished = PairLocalSolve(original_[0], original_[1], layout_, w, options);
    double moved2 = 0.0;
    for (int k = 0; k < ad; ++k) {
      moved2 += (polished.x[k] - jet.x[k]) * (polished.x[k] - jet.x[k]) + (polished.y[k] - jet.y[k]) * (polished.y[k] - jet.y[k]);
    }
    if (!polished.kkt.kkt || !(std::sqrt(moved2) <= kSamePointShare * size_)) return Recorded::NotKkt;
    std::copy(polished.w, polished.w + layout_.n(), w);
    EvaluatePair(original_[0], original_[1], layout_, w, JetOrder::Second, &jet);
    d = std::sqrt(PairSquaredDistance(jet, ad));
    if (!(d <= maxDistance_)) return Recorded::Elsewhere;
    kkt = polished.kkt;
  }
  for (const Strict& s : strict) {
    // The slope into the cell, as the KKT test judges slopes: positive
    // beyond rounding.
    const int p = layout_.offset(s.side) + s.param;
    const double inward = w[p] < 0.5 ? 1.0 : -1.0;
    double length2 = 0.0;
    for (int k = 0; k < ad; ++k) length2 += jet.d1[k][p] * jet.d1[k][p];
    const double tolerance = (1e-7 * d + 1e-12 * size_) * std::max(std::sqrt(length2), kThinDirection * size_);
    if (!(inward * kkt.gradient[p] > tolerance)) return Recorded::NotKkt;
  }
  PairMinimum minimum;
  std::copy(w, w + pa, minimum.refA);
  std::copy(w + pa, w + pa + pb, minimum.refB);
  std::copy(jet.x, jet.x + 3, minimum.pointA);
  std::copy(jet.y, jet.y + 3, minimum.pointB);
  minimum.distance = d;
  out_->minima.push_back(minimum);
  return Recorded::Minimum;
}

Enumerator::Recorded Enumerator::RecordLocal(const Problem& problem, double* slot, const double* local) {
  double refs[2][3];
  const int offset = problem.side[0].cell.shape.paramDim();
  for (int side = 0; side < 2; ++side) {
    double t[3] = {0, 0, 0};
    for (int i = 0; i < problem.side[side].cell.shape.paramDim(); ++i) t[i] = local[(side == 0 ? 0 : offset) + i];
    SubdomainMap(problem, slot, side).Apply(t, refs[side]);
  }
  return Record(refs[0], refs[1], problem.strict);
}

void Enumerator::SolveIn(const Problem& problem, double* slot) {
  OwnedCell sub[2];
  PairSide sides[2];
  for (int side = 0; side < 2; ++side) {
    const PairSide& s = problem.side[side];
    sub[side].Set(s.cell.shape, s.cell.ambientDim, s.cell.weights != nullptr, Homogeneous(problem, slot, side),
                  controlCount_[side]);
    sides[side] = s;
    sides[side].cell = sub[side].view;
  }
  const PairLayout layout(sides[0].cell.shape, sides[1].cell.shape);
  double start[kMaxPairParams];
  layout.Center(start);
  PairLocalOptions options;
  options.size = size_;
  // The subdomain's parameters stretch the original cells' (a hundredth of
  // a cell becomes a unit): its final Newton step is the cells' own.
  double widest = 0.0;
  for (int side = 0; side < 2; ++side) {
    const RefMap map = SubdomainMap(problem, slot, side);
    for (const auto& row : map.matrix) {
      for (const double entry : row) widest = std::max(widest, std::abs(entry));
    }
  }
  if (widest > 0.0) options.finalStep = kFinalStep / widest;
  const PairLocalResult local = PairLocalSolve(sides[0], sides[1], layout, start, options);
  // The subdomain holds at most one minimum, and the solve's end tells
  // where: a solve that stopped before converging (its iteration cap), at
  // no minimum of the cells, leaves the subdomain open. (One that
  // converged but misses the subdomain's KKT test by rounding, as on a
  // rational cell's heavy weights, ended at the subdomain's least point:
  // Record's polish judges it.)
  // A converged solve off every face of subdomains of the cells
  // themselves (not of a face a reduction searches, whose least point the
  // distance may fall from into the cell) that the cells' test refuses is
  // a minimum the search could not settle, not a subdomain without one.
  if (RecordLocal(problem, slot, local.w) == Recorded::NotKkt &&
      (!local.converged || (problem.recursion == 0 && sides[0].cell.shape.IsOffEveryFace(local.w, kOffFace) &&
                            sides[1].cell.shape.IsOffEveryFace(local.w + layout.paramDim(0), kOffFace)))) {
    out_->certified = false;
  }
}

void Enumerator::ReduceToFace(const Problem& problem, double* slot, int side, int factor, int vertex, bool strict) {
  if (problem.recursion >= kMaxRecursion) {
    out_->certified = false;
    return;
  }
  const PairSide& s = problem.side[side];
  const CellShape& shape = s.cell.shape;
  const int ad = s.cell.ambientDim;
  const std::vector<double> homogeneous = Homogeneous(problem, slot, side);
  // The control points whose index along the factor is its first or last.
  int count[kMaxFactors] = {1, 1, 1}, stride[kMaxFactors] = {1, 1, 1}, total = 1;
  for (int f = 0; f < shape.numFactors(); ++f) {
    count[f] = SimplexBasisSize(shape.factor(f).dim, shape.factor(f).degree);
    stride[f] = total;
    total *= count[f];
  }
  const int keepIndex = vertex == 0 ? 0 : count[factor] - 1;
  std::vector<int> kept;
  for (int c = 0; c < total; ++c) {
    if ((c / stride[factor]) % count[factor] == keepIndex) kept.push_back(c);
  }
  const int faceCount = static_cast<int>(kept.size());
  std::vector<double> faceHomogeneous(static_cast<size_t>(ad + 1) * faceCount);
  for (int k = 0; k <= ad; ++k) {
    for (int i = 0; i < faceCount; ++i) faceHomogeneous[static_cast<size_t>(k) * faceCount + i] = homogeneous[static_cast<size_t>(k) * total + kept[i]];
  }
  // The face's local coordinates into the subdomain's: the factor's
  // parameter fixed at the vertex, the others in order.
  RefMap faceIn;
  for (auto& row : faceIn.matrix) std::fill(row, row + 3, 0.0);
  int faceFactors = 0;
  std::array<int, kMaxFactors> degrees{};
  int facePd = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    if (f == factor) {
      faceIn.origin[fac.offset] = vertex;
      continue;
    }
    degrees[faceFactors++] = fac.degree;
    for (int i = 0; i < fac.dim; ++i) faceIn.matrix[fac.offset + i][facePd + i] = 1.0;
    facePd += fac.dim;
  }
  const RefMap faceMap = SubdomainMap(problem, slot, side).Compose(faceIn);
  // The original parameter the face holds fixed: the largest entry of the
  // map's column for the factor's parameter.
  std::vector<Strict> strictness = problem.strict;
  if (strict) {
    const RefMap subdomain = SubdomainMap(problem, slot, side);
    int best = 0;
    for (int i = 1; i < original_[side].cell.shape.paramDim(); ++i) {
      if (std::abs(subdomain.matrix[i][shape.factor(factor).offset]) >
          std::abs(subdomain.matrix[best][shape.factor(factor).offset])) {
        best = i;
      }
    }
    strictness.push_back({side, best});
  }
  const int other = 1 - side;
  auto faceShape = [&] {
    return CellShape(faceFactors == 1 ? (facePd == 1 ? CellType::Line : CellType::Tri) : CellType::Quad, degrees);
  };
  if (faceFactors == 0 || CollapsedFace(faceHomogeneous, faceCount, ad, side)) {
    // A curve's end, or a face that is one point (a sphere's pole): a
    // point against the other side's subdomain, whose minima are a
    // point's (kernels/cell_minima.h). A collapsed face searched as a
    // cell of its own has no direction of its parameters the distance
    // changes along: it was split down to the budget, every piece a
    // "minimum" (the pole of an 8-cell sphere made thousands a pair).
    OwnedCell otherCell;
    otherCell.Set(problem.side[other].cell.shape, ad, problem.side[other].cell.weights != nullptr,
                  Homogeneous(problem, slot, other), controlCount_[other]);
    double end[3] = {0, 0, 0}, world[3];
    for (int k = 0; k < ad; ++k) end[k] = faceHomogeneous[static_cast<size_t>(k) * faceCount] / faceHomogeneous[static_cast<size_t>(ad) * faceCount];
    s.motion.Apply(end, world);
    // Into the other side's model frame: R^T (x - t).
    const RigidMotion& motion = problem.side[other].motion;
    double local[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) local[k] += motion.rotation[l][k] * (world[l] - motion.translation[l]);
    }
    const CellSolver solver(otherCell.view);
    MinimaWorkspace workspace;
    const CellMinimaResult found = CellLocalMinima(solver, local, maxDistance_, &workspace);
    if (!found.certified) out_->certified = false;
    const RefMap otherMap = SubdomainMap(problem, slot, other);
    // The original pair's KKT test at a collapsed face depends on where on
    // it the parameters lie (the slopes into the cell at a pole follow the
    // meridian): the point counts where some place of the face passes, its
    // centre or a corner (the whole face passes at a minimum of the models).
    std::vector<std::array<double, 3>> places;
    if (faceFactors == 0) {
      places.push_back({0, 0, 0});
    } else {
      std::array<double, 3> center{0, 0, 0};
      ReferenceCenter(faceShape(), center.data());
      places.push_back(center);
      for (const std::array<double, 3>& corner : ReferenceCorners(faceShape())) places.push_back(corner);
    }
    for (const CellMinimum& m : found.minima) {
      double otherRef[3];
      otherMap.Apply(m.ref, otherRef);
      for (const std::array<double, 3>& place : places) {
        double faceRef[3];
        faceMap.Apply(place.data(), faceRef);
        const Recorded recorded = side == 0 ? Record(faceRef, otherRef, strictness) : Record(otherRef, faceRef, strictness);
        if (recorded != Recorded::NotKkt) break;
      }
    }
    return;
  }
  Problem child;
  child.recursion = problem.recursion + 1;
  child.strict = strictness;
  child.owned[side] = std::make_shared<OwnedCell>();
  child.owned[side]->Set(faceShape(), ad, s.cell.weights != nullptr, faceHomogeneous, faceCount);
  child.owned[other] = std::make_shared<OwnedCell>();
  child.owned[other]->Set(problem.side[other].cell.shape, ad, problem.side[other].cell.weights != nullptr,
                          Homogeneous(problem, slot, other), controlCount_[other]);
  for (int t = 0; t < 2; ++t) {
    child.side[t] = problem.side[t];
    child.side[t].cell = child.owned[t]->view;
    child.side[t].nets = &child.owned[t]->nets;
    child.side[t].size = child.owned[t]->size;
    child.side[t].affine = child.owned[t]->affine;
  }
  child.map[side] = faceMap;
  child.map[other] = SubdomainMap(problem, slot, other);
  // Run has its own layout; this run's sizes are restored after it.
  const int saveSlot = slotSize_, saveNets[2] = {netLength_[0], netLength_[1]},
            saveCount[2] = {controlCount_[0], controlCount_[1]};
  Run(child);
  slotSize_ = saveSlot;
  netLength_[0] = saveNets[0];
  netLength_[1] = saveNets[1];
  controlCount_[0] = saveCount[0];
  controlCount_[1] = saveCount[1];
}

void Enumerator::Run(const Problem& problem) {
  const PairSide& a = problem.side[0];
  const PairSide& b = problem.side[1];
  const PairNets nets(a, b);
  const int ad = a.cell.ambientDim;
  const PairLayout layout(a.cell.shape, b.cell.shape);
  const int n = layout.n();
  netLength_[0] = nets.sideLength(0);
  netLength_[1] = nets.sideLength(1);
  controlCount_[0] = a.cell.shape.numControlPoints();
  controlCount_[1] = b.cell.shape.numControlPoints();
  slotSize_ = kHeaderSize + netLength_[0] + netLength_[1] + (ad + 1) * (controlCount_[0] + controlCount_[1]);
  const int slotSize = slotSize_;
  std::vector<double> slots;
  std::vector<int> freeSlots, stack;
  int used = 0;
  auto allocate = [&] {
    if (!freeSlots.empty()) {
      const int s = freeSlots.back();
      freeSlots.pop_back();
      return s;
    }
    slots.resize(static_cast<size_t>(used + 1) * slotSize);
    return used++;
  };
  auto slotAt = [&](int s) { return slots.data() + static_cast<size_t>(s) * slotSize; };
  const int root = allocate();
  {
    double* slot = slotAt(root);
    std::fill(slot, slot + kHeaderSize, 0.0);
    for (int side = 0; side < 2; ++side) {
      const CellShape& shape = layout.shape(side);
      for (int f = 0; f < shape.numFactors(); ++f) {
        for (int v = 1; v <= shape.factor(f).dim; ++v) Vertex(slot, side, f, v)[v - 1] = 1.0;
      }
    }
    double* sideA = slot + kHeaderSize;
    nets.BuildRoot(sideA, sideA + netLength_[0]);
    double* homogeneous = sideA + netLength_[0] + netLength_[1];
    for (int side = 0; side < 2; ++side) {
      const CellView& cell = problem.side[side].cell;
      const int count = controlCount_[side];
      for (int c = 0; c < count; ++c) {
        const double w = cell.weights ? cell.weights[c] : 1.0;
        for (int k = 0; k < ad; ++k) homogeneous[static_cast<size_t>(k) * count + c] = w * cell.points[static_cast<size_t>(c) * ad + k];
        homogeneous[static_cast<size_t>(ad) * count + c] = w;
      }
      homogeneous += static_cast<size_t>(ad + 1) * count;
    }
  }
  stack.push_back(root);
  const double slack = nets.RoundingSlack();
  const double limit2 = maxDistance_ < kInf ? maxDistance_ * maxDistance_ : kInf;
  std::vector<double> scratch;
  int examined = 0;
  double paramScale[kMaxPairParams];
  for (int side = 0; side < 2; ++side) {
    double center[3];
    ReferenceCenter(layout.shape(side), center);
    MapJet jet;
    EvaluateMap(problem.side[side].cell, center, JetOrder::First, &jet);
    for (int i = 0; i < layout.paramDim(side); ++i) {
      double length2 = 0.0;
      for (int k = 0; k < ad; ++k) length2 += jet.d1[k][i] * jet.d1[k][i];
      paramScale[layout.offset(side) + i] = std::sqrt(length2) + 1e-3 * problem.side[side].size;
    }
  }
  // A parameter's factor and its place in it.
  int sideOf[kMaxPairParams], factorOf[kMaxPairParams], dirOf[kMaxPairParams];
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      for (int d = 0; d < shape.factor(f).dim; ++d) {
        const int p = layout.offset(side) + shape.factor(f).offset + d;
        sideOf[p] = side;
        factorOf[p] = f;
        dirOf[p] = d;
      }
    }
  }
  auto isLine = [&](int p) { return layout.shape(sideOf[p]).factor(factorOf[p]).dim == 1; };
  // Whether the subdomain reaches the problem cell's face where line factor
  // f of `side` is at `value` (0 or 1), and at which of its local vertices.
  auto reaches = [&](double* slot, int side, int f, double value, int* vertex) {
    for (int v = 0; v < 2; ++v) {
      if (Vertex(slot, side, f, v)[0] == value) {
        *vertex = v;
        return true;
      }
    }
    return false;
  };
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    double* slot = slotAt(s);
    const double* sideA = slot + kHeaderSize;
    const double* sideB = sideA + netLength_[0];
    const double low = nets.LowerBound(sideA, sideB, &scratch) - slack;
    if (low > limit2 || OutsideRegion(problem, slot)) {
      freeSlots.push_back(s);
      continue;
    }
    const double high = nets.UpperBound(sideA, sideB) + slack;
    const double c1 = std::max(low, 0.0), c2 = high;
    // First order: a parameter along which the distance is monotone.
    double g1lo[kMaxPairParams], g1hi[kMaxPairParams], g2lo[kMaxPairParams], g2hi[kMaxPairParams];
    nets.GradientRanges(sideA, sideB, c1, g1lo, g1hi, &scratch);
    nets.GradientRanges(sideA, sideB, c2, g2lo, g2hi, &scratch);
    bool settled = false;
    for (int p = 0; p < n && !settled; ++p) {
      const double lo = std::min(g1lo[p], g2lo[p]), hi = std::max(g1hi[p], g2hi[p]);
      const double margin = 1e-12 * std::max(std::abs(lo), std::abs(hi));
      if (!(lo > margin) && !(hi < -margin)) continue;
      const int side = sideOf[p], f = factorOf[p], dir = dirOf[p];
      const int dim = layout.shape(side).factor(f).dim;
      // Falling toward local vertex 0 (increasing) or dir + 1 (decreasing).
      const int from = lo > 0.0 ? dir + 1 : 0, to = lo > 0.0 ? 0 : dir + 1;
      double lambdaFrom[4], lambdaTo[4];
      Barycentric(dim, Vertex(slot, side, f, from), lambdaFrom);
      Barycentric(dim, Vertex(slot, side, f, to), lambdaTo);
      bool open = true;
      for (int bary = 0; bary <= dim && open; ++bary) {
        if (!(lambdaTo[bary] - lambdaFrom[bary] < 0.0)) continue;
        double least = kInf;
        for (int v = 0; v <= dim; ++v) {
          double lambda[4];
          Barycentric(dim, Vertex(slot, side, f, v), lambda);
          least = std::min(least, lambda[bary]);
        }
        open = least > 0.0;
      }
      if (open) {
        settled = true;
      } else if (dim == 1) {
        // Every minimum of S lies on the face it falls toward.
        ReduceToFace(problem, slot, side, f, to, false);
        slot = slotAt(s);
        settled = true;
      }
    }
    if (settled) {
      freeSlots.push_back(s);
      continue;
    }
    double h1lo[kMaxPairParams * kMaxPairParams], h1hi[kMaxPairParams * kMaxPairParams];
    double h2lo[kMaxPairParams * kMaxPairParams], h2hi[kMaxPairParams * kMaxPairParams];
    nets.HessianRanges(sideA, sideB, c1, false, h1lo, h1hi, &scratch);
    nets.HessianRanges(sideA, sideB, c2, false, h2lo, h2hi, &scratch);
    if (IntervalPositiveDefinite(n, h1lo, h1hi) && IntervalPositiveDefinite(n, h2lo, h2hi)) {
      // At most one minimum (as in kernels/cell_minima.cpp): solve for it.
      SolveIn(problem, slot);
      freeSlots.push_back(s);
      continue;
    }
    // Second order: a concave line parameter, or a saddle in two of them,
    // everywhere: the minima lie on faces across them, where the distance
    // must also grow into the cell at first order.
    auto hlo = [&](int r, int c) { return std::min(h1lo[r * n + c], h2lo[r * n + c]); };
    auto hhi = [&](int r, int c) { return std::max(h1hi[r * n + c], h2hi[r * n + c]); };
    int bent[2] = {-1, -1};
    for (int p = 0; p < n && bent[0] < 0; ++p) {
      if (isLine(p) && hhi(p, p) < 0.0) bent[0] = p;
    }
    for (int p = 0; p < n && bent[0] < 0; ++p) {
      for (int q = p + 1; q < n && bent[0] < 0; ++q) {
        if (!isLine(p) || !isLine(q)) continue;
        const double products[4] = {hlo(p, p) * hlo(q, q), hlo(p, p) * hhi(q, q), hhi(p, p) * hlo(q, q),
                                    hhi(p, p) * hhi(q, q)};
        const double mixedLeast = hlo(p, q) > 0.0 ? hlo(p, q) : (hhi(p, q) < 0.0 ? -hhi(p, q) : 0.0);
        if (*std::max_element(products, products + 4) < mixedLeast * mixedLeast) {
          bent[0] = p;
          bent[1] = q;
        }
      }
    }
    if (bent[0] >= 0) {
      for (const int p : bent) {
        if (p < 0) continue;
        for (const double value : {0.0, 1.0}) {
          int vertex = 0;
          if (reaches(slot, sideOf[p], factorOf[p], value, &vertex)) {
            ReduceToFace(problem, slot, sideOf[p], factorOf[p], vertex, true);
            slot = slotAt(s);
          }
        }
      }
      freeSlots.push_back(s);
      continue;
    }
    if (++examined > kMaxPairSubdomains || slot[kDepth] >= kMaxDepth) {
      out_->certified = false;
      SolveIn(problem, slot);
      freeSlots.push_back(s);
      continue;
    }
    // Split the longest edge (by the cells' lengths per parameter).
    const PairEdge edge =
        LongestPairEdge(layout, paramScale, [slot](int side, int f, int v) { return Vertex(slot, side, f, v); });
    const int splitSide = edge.side, splitFactor = edge.factor, vi = edge.vi, vj = edge.vj;
    for (int child = 0; child < 2; ++child) {
      const int keep = child == 0 ? vi : vj;
      const int move = child == 0 ? vj : vi;
      const int c = allocate();
      double* parent = slotAt(s);
      double* target = slotAt(c);
      std::copy(parent, parent + kHeaderSize, target);
      target[kDepth] = parent[kDepth] + 1;
      double* moved = Vertex(target, splitSide, splitFactor, move);
      const double* kept = Vertex(target, splitSide, splitFactor, keep);
      for (int i = 0; i < 3; ++i) moved[i] = 0.5 * (moved[i] + kept[i]);
      const double* parentNets[2] = {parent + kHeaderSize, parent + kHeaderSize + netLength_[0]};
      double* childNets[2] = {target + kHeaderSize, target + kHeaderSize + netLength_[0]};
      for (int side = 0; side < 2; ++side) {
        if (side == splitSide) {
          nets.Split(side, splitFactor, keep, move, parentNets[side], childNets[side]);
        } else {
          std::copy(parentNets[side], parentNets[side] + netLength_[side], childNets[side]);
        }
      }
      const double* parentControl = parent + kHeaderSize + netLength_[0] + netLength_[1];
      double* childControl = target + kHeaderSize + netLength_[0] + netLength_[1];
      for (int side = 0; side < 2; ++side) {
        const int count = controlCount_[side];
        for (int k = 0; k <= ad; ++k) {
          const double* from = parentControl + static_cast<size_t>(k) * count;
          double* to = childControl + static_cast<size_t>(k) * count;
          if (side == splitSide) {
            SplitNet(layout.shape(side), splitFactor, keep, move, from, to);
          } else {
            std::copy(from, from + count, to);
          }
        }
        parentControl += static_cast<size_t>(ad + 1) * count;
        childControl += static_cast<size_t>(ad + 1) * count;
      }
      stack.push_back(c);
    }
    freeSlots.push_back(s);
  }
}

}  // namespace

PairMinimaResult PairLocalMinima(const PairSide& a, const PairSide& b, double maxDistance) {
  PairMinimaResult result;
  Enumerator enumerator(a, b, maxDistance, &result);
  Problem problem;
  problem.side[0] = a;
  problem.side[1] = b;
  enumerator.Run(problem);
  return result;
}

}  // namespace invmap::kernels
