#include "kernels/pair_search.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "kernels/cell_bounds.h"
#include "kernels/pair_certificate.h"
#include "kernels/pair_taylor_bounds.h"
#include "kernels/pair_local_solve.h"
#include "kernels/pair_motion_bound.h"
#include "kernels/pair_nets.h"
#include "kernels/simplex_index.h"
#include "kernels/simplex_pair.h"
#include "kernels/simplex_subdomain.h"
#include "kernels/slot_pool.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A subdomain pair lives in one slot of the workspace: a header (lower
/// bound, depth, a KKT point found in it, the vertices of every factor's
/// sub-simplex on both sides in the cells' reference coordinates), then
/// A's nets and B's (kernels/pair_nets.h).
constexpr int kLowerBound = 0;
constexpr int kDepth = 1;
constexpr int kHasSeed = 2;    ///< 1 when the slot holds a KKT point of its own.
constexpr int kSeedValue = 3;  ///< Its squared distance.
/// The depth from which a certificate is tried again after one failed on
/// an ancestor (kernels/pair_certificate.h: one closes once the subdomain
/// is small enough; trying at every depth costs more than the splits).
constexpr int kRetryDepth = 4;
constexpr int kSeedPoint = 5;  ///< Its joint parameters.
/// Per side, where its part of the subdomain lies in its trimmed face's
/// region (TrimRegion::Side; Inside for a side without trimming).
constexpr int kTrimSide = kSeedPoint + kMaxPairParams;
constexpr int kVertices = kTrimSide + 2;
constexpr int kHeaderSize = kVertices + 2 * kMaxFactors * 4 * 3;

double* Vertex(double* slot, int side, int factor, int vertex) {
  return slot + kVertices + ((side * kMaxFactors + factor) * 4 + vertex) * 3;
}

/// The vertex control points of an affine segment or triangle.
void SimplexVertices(const PairSide& side, double vertices[3][3]) {
  const SimplexFactor& factor = side.cell.shape.factor(0);
  const SimplexIndex& index = SimplexIndex::Get(factor.dim, factor.degree);
  const int ad = side.cell.ambientDim;
  for (int v = 0; v <= factor.dim; ++v) {
    std::array<int, 4> corner{0, 0, 0, 0};
    corner[v] = factor.degree;
    const double* p = side.cell.points + static_cast<size_t>(index.Position(corner)) * ad;
    const double local[3] = {p[0], p[1], ad > 2 ? p[2] : 0.0};
    side.motion.Apply(local, vertices[v]);
  }
}

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxPairParams, kMaxPairParams>;

/// The eigenvectors of `h` (n x n, symmetric) scaled to a unit diagonal,
/// scaled back: columns of `basis` (column c at basis[c n]). Along them a
/// direction in which the function barely bends is kept apart from the
/// steep ones. False when h has no positive diagonal.
bool ScaledEigenBasis(const Matrix& h, double* basis) {
  const int n = static_cast<int>(h.rows());
  double largest = 0.0;
  for (int r = 0; r < n; ++r) largest = std::max(largest, h(r, r));
  if (!(largest > 0.0) || !h.allFinite()) return false;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPairParams, 1> scale(n);
  // By the diagonal's magnitude: a direction in which f bends down (a
  // minimum on a face, held by its multiplier) scaled by the floor instead
  // grew by 1e6 against the others and its bound swamped the certificate.
  for (int r = 0; r < n; ++r) scale[r] = 1.0 / std::sqrt(std::max(std::abs(h(r, r)), 1e-12 * largest));
  const Matrix scaled = scale.asDiagonal() * h * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Matrix> eigen(scaled);
  const Matrix directions = scale.asDiagonal() * eigen.eigenvectors();
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) basis[c * n + r] = directions(r, c);
  }
  return true;
}

/// A kept subdomain (PairPartition::leaves): its bound, the drift then,
/// where its two parts were (kernels/pair_motion_bound.h), then its slot's
/// header and its own-frame nets.
constexpr int kLeafPlace = 2;
constexpr int kLeafHeader = kLeafPlace + kSubdomainPlaceSize;

/// A tracker's partition of a pair is dropped past this many times the
/// subdomains a search from the whole pair ended with (PairPartition).
constexpr std::size_t kPartitionGrowth = 2;

/// A split by bend is overruled when its edge is shorter than the longest
/// by more than this factor (squared: 1024^2).
constexpr double kBendSplitRatio2 = 1024.0 * 1024.0;

/// The pair search over one pair of cells.
class PairSearch {
 public:
  PairSearch(const PairSide& a, const PairSide& b, PairWorkspace* ws, const PairReuse* reuse = nullptr)
      : a_(a), b_(b), layout_(a.cell.shape, b.cell.shape), ws_(ws), reuse_(reuse) {
    ambientDim_ = a.cell.ambientDim;
    n_ = layout_.n();
    tau_ = kDistanceTolerance * std::max(a.size, b.size);
    options_.size = a.size + b.size;
    retryStep_ = std::max(1, n_ / 2);
    trimmed_ = a.trim || b.trim;
    // A trimmed pair's subdomains are closed by tests of its region too: not kept.
    if (trimmed_) reuse_ = nullptr;
    if (reuse_ && reuse_->next) {
      reuse_->next->valid = false;
      reuse_->next->leaves.clear();
      for (int side = 0; side < 2; ++side) {
        const PairSide& s = side == 0 ? a : b;
        if (!s.nets) continue;
        const double* c = s.nets->center();
        const double local[3] = {c[0], c[1], ambientDim_ > 2 ? c[2] : 0.0};
        s.motion.Apply(local, netCenter_[side]);
      }
    }
    for (int side = 0; side < 2; ++side) {
      const PairSide& s = side == 0 ? a : b;
      double center[3];
      ReferenceCenter(s.cell.shape, center);
      MapJet jet;
      EvaluateMap(s.cell, center, JetOrder::First, &jet);
      for (int i = 0; i < s.cell.shape.paramDim(); ++i) {
        double length2 = 0.0;
        for (int k = 0; k < ambientDim_; ++k) length2 += jet.d1[k][i] * jet.d1[k][i];
        // Parameters the map barely depends on still get split now and then.
        paramScale_[layout_.offset(side) + i] = std::sqrt(length2) + 1e-3 * s.size;
      }
    }
  }

  PairSolveResult Solve(const double* startA, const double* startB, double bound2);
  PairSolveResult Probe(double bound2);
  double RootLowerBound();

 private:
  bool HaveNets() const { return a_.nets && b_.nets; }
  void SetRoot(double* slot);
  bool Contains(double* slot, const double* w) const;
  void Center(double* slot, double* w) const;
  /// True when the subdomain is closed around a KKT point in it.
  bool CertifiedAround(double* slot, double pruneLevel);
  bool CertifyWith(double* slot, const double* w, double value, const PairKkt& kkt, double pruneLevel);
  void ChooseSplit(double* slot, int* side, int* factor, int* vi, int* vj) const;
  /// True when the subdomain holds a KKT point (the best, or its own).
  bool HoldsKktPoint(double* slot) const {
    return slot[kHasSeed] != 0.0 || (best_.kkt.kkt && Contains(slot, best_.w));
  }
  void ChooseSplitByVariation(double* slot, int* side, int* factor, int* vi, int* vj) const;
  /// Splits along the edge where the joint net bends most next to its
  /// least coefficient (PairNets::MostBentEdgeAt), as the cell search
  /// splits where its net bends most (kernels/bernstein_net.h); by length
  /// where the net is linear there.
  void ChooseSplitByBend(double* slot, const PairNets& nets, int* side, int* factor, int* vi, int* vj) const;
  /// The longest edge instead of the chosen one when that is shorter by
  /// more than kBendSplitRatio2 (squared): a split that narrows one
  /// direction for ever leaves the certificate the others' whole length.
  void KeepSplitsLong(double* slot, int* side, int* factor, int* vi, int* vj) const;
  PairLocalResult Local(const double* start) {
    PairLocalResult local = PairLocalSolve(a_, b_, layout_, start, options_);
    iterations_ += local.iterations;
    return local;
  }
  PairSolveResult Finish(const PairLocalResult& best, bool certified, double bound2) const;
  const TrimmedCell* Trim(int side) const { return side == 0 ? a_.trim : b_.trim; }
  /// True unless the reference coordinates of some trimmed side lie
  /// outside its face's region.
  bool Admitted(const double* w) const;
  /// The subdomain's reference box on `side` (line factors: quads, lines).
  void SideBox(double* slot, int side, double* lo, double* hi) const;
  /// A trimmed pair's closest points are an admitted KKT point of the pair
  /// over the cells' boxes, or lie on a trimmed face's boundary, which its
  /// edges' pairs answer: false when the subdomain can hold no such KKT
  /// point with a squared distance up to `level2` (kernels/kkt_exclusion.h's
  /// argument on the joint gradient's nets) or only on a face of a cell's
  /// box that lies outside the region.
  bool MayHoldAdmittedKkt(double* slot, const PairNets& nets, double level2);
  /// Forgets a local answer outside the region (its distance becomes +inf).
  void Reject(PairLocalResult* local) const {
    local->squaredDistance = kInf;
    local->kkt.kkt = false;
    local->onBoundary = false;
  }

  const PairSide& a_;
  const PairSide& b_;
  PairLayout layout_;
  PairWorkspace* ws_;
  int ambientDim_ = 3;
  int n_ = 0;
  double tau_ = 0.0;
  double slack_ = 0.0;
  PairLocalOptions options_;
  double paramScale_[kMaxPairParams] = {};
  int iterations_ = 0;
  PairLocalResult best_;
  double open_ = kInf;  ///< Least bound of the parts a search left open.
  /// Depths between certificate attempts (kRetryDepth): about one split of
  /// every parameter, which halves the Hessian's bounds' spread.
  int retryStep_ = 1;
  int examined_ = 0;
  bool trimmed_ = false;
  /// Trimmed pairs: the root nets' bound, which holds for every point of
  /// the pair (the KKT exclusion above holds for the KKT points only).
  double rootBound2_ = 0.0;

  // A tracker's partitions (PairPartition): with reuse_->next, every slot
  // also holds its own-frame nets after the placed ones (at ownOffset_),
  // and every subdomain the search closes is written there.
  const PairReuse* reuse_ = nullptr;
  int ownOffset_ = 0;
  /// False once some part of the pair was left without a proved bound.
  bool complete_ = true;
  /// The deepest subdomain kept.
  double keptDepth_ = 0.0;
  /// Each side's nets' centre in the common frame (their NW_k / WW are about it).
  double netCenter_[2][3] = {};
  bool Keeping() const { return reuse_ && reuse_->next; }
  /// The distance bound of a subdomain whose nets' least quotient is lb.
  double Bound(double lb) const { return std::sqrt(std::max(0.0, lb - slack_)); }
  /// Writes a closed subdomain to the next partition: no point of it is
  /// nearer than `bound` at this motion.
  void KeepLeaf(const double* slot, double bound, const PairNets& nets);
  /// Starts the search from the previous partition: the subdomains whose
  /// bound the drift has not used up are kept as they are, the rest placed
  /// at this motion and pushed (or kept, if their bound now prunes them).
  void SeedFromPartition(SlotPool* pool, const PairNets& nets, double level, std::vector<int>* heap);
};

void PairSearch::KeepLeaf(const double* slot, double bound, const PairNets& nets) {
  if (!Keeping()) return;
  std::vector<double>& out = reuse_->next->leaves;
  keptDepth_ = std::max(keptDepth_, slot[kDepth]);
  out.push_back(bound);
  out.push_back(reuse_->drift);
  // Each part's box: the hull of its placed nets' quotients NW_k / WW
  // (the control points of its map, whose hull holds it) about its centre.
  double lo[2][3], hi[2][3];
  for (int side = 0; side < 2; ++side) {
    const double* values = slot + kHeaderSize + (side == 0 ? 0 : nets.sideLength(0));
    const int n = nets.size(side);
    const double* w = values + (ambientDim_ + 1) * n;
    for (int k = 0; k < 3; ++k) {
      lo[side][k] = hi[side][k] = netCenter_[side][k];
      if (k >= ambientDim_) continue;
      const double* nw = values + (1 + k) * n;
      double least = kInf, most = -kInf;
      for (int i = 0; i < n; ++i) {
        const double q = nw[i] / w[i];
        least = std::min(least, q);
        most = std::max(most, q);
      }
      lo[side][k] += least;
      hi[side][k] += most;
    }
  }
  const std::size_t at = out.size();
  out.resize(at + kSubdomainPlaceSize);
  WriteSubdomainPlace(lo, hi, a_.motion, b_.motion, out.data() + at);
  out.insert(out.end(), slot, slot + kHeaderSize);
  const double* own = slot + ownOffset_;
  out.insert(out.end(), own, own + nets.sideLength(0) + nets.sideLength(1));
}

void PairSearch::SeedFromPartition(SlotPool* pool, const PairNets& nets, double level, std::vector<int>* heap) {
  const PairPartition& previous = *reuse_->previous;
  const double eps = std::numeric_limits<double>::epsilon();
  const double drift = reuse_->drift;
  const double levelDistance = std::sqrt(std::max(0.0, level - slack_));
  const int length = previous.leafLength;
  const int ownLength = nets.sideLength(0) + nets.sideLength(1);
  for (std::size_t at = 0; at + length <= previous.leaves.size(); at += length) {
    const double* leaf = previous.leaves.data() + at;
    const double bound = leaf[0], driftAt = leaf[1];
    // As PairBoundCache::Holds: the bound less the drift since, less the
    // subtraction's rounding; else the bound of how much nearer the two
    // parts can have come since (kernels/pair_motion_bound.h).
    bool holds = bound - (drift - driftAt) - 4.0 * eps * (bound + drift) >= levelDistance;
    if (!holds && bound > levelDistance) {
      const double now2 = bound * bound * (1.0 - 4.0 * eps) + SquaredDistanceChangeBound(leaf + kLeafPlace, a_.motion, b_.motion);
      holds = now2 > 0.0 && std::sqrt(now2) * (1.0 - 4.0 * eps) >= levelDistance;
    }
    if (holds) {
      if (Keeping()) reuse_->next->leaves.insert(reuse_->next->leaves.end(), leaf, leaf + length);
      continue;
    }
    const int c = pool->Allocate();
    double* slot = (*pool)[c];
    std::copy(leaf + kLeafHeader, leaf + kLeafHeader + kHeaderSize, slot);
    // Its KKT point was of the previous motion; a certificate is tried at once.
    slot[kHasSeed] = 0.0;
    slot[kRetryDepth] = slot[kDepth];
    std::copy(leaf + kLeafHeader + kHeaderSize, leaf + kLeafHeader + kHeaderSize + ownLength, slot + ownOffset_);
    double* sideA = slot + kHeaderSize;
    double* sideB = sideA + nets.sideLength(0);
    nets.Place(0, slot + ownOffset_, sideA);
    nets.Place(1, slot + ownOffset_ + nets.sideLength(0), sideB);
    slot[kLowerBound] = nets.LowerBound(sideA, sideB, &ws_->scratch);
    if (slot[kLowerBound] < level) {
      heap->push_back(c);
    } else {
      KeepLeaf(slot, Bound(slot[kLowerBound]), nets);
      pool->Free(c);
    }
  }
}

bool PairSearch::Admitted(const double* w) const {
  for (int side = 0; side < 2; ++side) {
    const TrimmedCell* trim = Trim(side);
    if (trim && !trim->Admits(w + layout_.offset(side))) return false;
  }
  return true;
}

void PairSearch::SideBox(double* slot, int side, double* lo, double* hi) const {
  const CellShape& shape = layout_.shape(side);
  for (int f = 0; f < shape.numFactors(); ++f) {
    lo[f] = Vertex(slot, side, f, 0)[0];
    hi[f] = Vertex(slot, side, f, 1)[0];
  }
}

bool PairSearch::MayHoldAdmittedKkt(double* slot, const PairNets& nets, double level2) {
  const double* sideA = slot + kHeaderSize;
  const double* sideB = sideA + nets.sideLength(0);
  const double levelLo = std::max(slot[kLowerBound] - slack_, 0.0);
  // The values a candidate can have here: from the subdomain's lower bound
  // up to the best so far or its own largest, whichever is less (the
  // narrower the band, the sooner one sign holds at both its ends).
  const double levelHi = std::min(level2, nets.UpperBound(sideA, sideB)) + slack_;
  double lo1[kMaxPairParams], hi1[kMaxPairParams], lo2[kMaxPairParams], hi2[kMaxPairParams];
  nets.GradientRanges(sideA, sideB, levelLo, lo1, hi1, &ws_->scratch);
  nets.GradientRanges(sideA, sideB, levelHi, lo2, hi2, &ws_->scratch);
  // Each coefficient of Q is off by up to the slack times WW's: a
  // derivative's, a difference times the degree, by twice that.
  const double noise = 2.0 * slack_ * nets.LargestWeight(sideA, sideB);
  // The part of each side's subdomain where KKT points may lie.
  double boxLo[2][3], boxHi[2][3];
  bool pinned[2] = {false, false};
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    if (Trim(side)) SideBox(slot, side, boxLo[side], boxHi[side]);
    for (int f = 0; f < shape.numFactors(); ++f) {
      if (shape.factor(f).dim != 1) continue;  // line factors only (a trimmed face's are)
      const int p = layout_.offset(side) + shape.factor(f).offset;
      // f = Q / WW has the sign of Q - f WW's derivative, affine in f:
      // one strict sign at both levels holds for every value between.
      const double lo = std::min(lo1[p], lo2[p]), hi = std::max(hi1[p], hi2[p]);
      const double margin =
          1e-12 * std::max(std::abs(lo), std::abs(hi)) + noise * nets.shape(side).factor(f).degree;
      if (!(lo > margin) && !(hi < -margin)) continue;
      // Rising: a KKT point needs the cell's lower face; falling: its upper.
      const double face = lo > margin ? 0.0 : 1.0;
      if (Vertex(slot, side, f, face == 0.0 ? 0 : 1)[0] != face) return false;
      if (Trim(side)) {
        boxLo[side][f] = boxHi[side][f] = face;
        pinned[side] = true;
      }
    }
  }
  for (int side = 0; side < 2; ++side) {
    if (pinned[side] && Trim(side)->ClassifySubdomain(boxLo[side], boxHi[side]) == TrimRegion::Side::Outside) {
      return false;
    }
  }
  return true;
}

void PairSearch::SetRoot(double* slot) {
  std::fill(slot, slot + kHeaderSize, 0.0);
  for (int side = 0; side < 2; ++side) {
    slot[kTrimSide + side] = static_cast<double>(Trim(side) ? TrimRegion::Side::Crossing : TrimRegion::Side::Inside);
  }
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      for (int v = 1; v <= shape.factor(f).dim; ++v) Vertex(slot, side, f, v)[v - 1] = 1.0;
    }
  }
}

bool PairSearch::Contains(double* slot, const double* w) const {
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    const double* ref = w + layout_.offset(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      const auto vertex = [&](int v) { return Vertex(slot, side, f, v); };
      if (!InSimplexSubdomain(fac.dim, ref + fac.offset, vertex)) return false;
    }
  }
  return true;
}

void PairSearch::Center(double* slot, double* w) const {
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      for (int i = 0; i < fac.dim; ++i) {
        double sum = 0.0;
        for (int v = 0; v <= fac.dim; ++v) sum += Vertex(slot, side, f, v)[i];
        w[layout_.offset(side) + fac.offset + i] = sum / (fac.dim + 1);
      }
    }
  }
}

bool PairSearch::CertifiedAround(double* slot, double pruneLevel) {
  if (best_.kkt.kkt && Contains(slot, best_.w) &&
      CertifyWith(slot, best_.w, best_.squaredDistance, best_.kkt, pruneLevel)) {
    return true;
  }
  if (slot[kHasSeed] == 0.0) return false;
  const double* w = slot + kSeedPoint;
  PairJet jet;
  EvaluatePair(a_, b_, layout_, w, JetOrder::Second, &jet);
  const PairKkt kkt = CheckPairKkt(layout_, jet, w, ambientDim_, options_.size);
  return kkt.kkt && CertifyWith(slot, w, slot[kSeedValue], kkt, pruneLevel);
}

bool PairSearch::CertifyWith(double* slot, const double* w, double value, const PairKkt& kkt, double pruneLevel) {
  // The certificate bounds f itself, with the rounding of its own Taylor
  // models: the nets' rounding slack, which the pruning level adds for the
  // nets' lower bounds, is not its to pay. Paid here it left nothing of the
  // tolerance (2 tau d) once d fell below slack / tau, and no minimum that
  // near the other cell could ever be closed.
  pruneLevel -= slack_;
  if (value < pruneLevel) {
    // Only the best point lies below the level, and then within rounding of it.
    value = std::max(value, 0.0);
  }
  const PairNets nets(a_, b_);
  const double* sideA = slot + kHeaderSize;
  const double* sideB = sideA + nets.sideLength(0);
  const int n = n_;
  double lo[kMaxPairParams * kMaxPairParams], hi[kMaxPairParams * kMaxPairParams];

  PairCertificateInput input;
  input.n = n;
  input.lo = lo;
  input.hi = hi;
  // The subdomain's local coordinates t: per factor, ref = V0 + E t with
  // E's columns the edges V_k - V0. Points go through E^-1, covectors
  // (normals, gradients) through E^T.
  Eigen::Matrix3d edges[2][kMaxFactors];
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      edges[side][f] = Eigen::Matrix3d::Identity();
      const double* v0 = Vertex(slot, side, f, 0);
      for (int k = 1; k <= fac.dim; ++k) {
        for (int i = 0; i < fac.dim; ++i) edges[side][f](i, k - 1) = Vertex(slot, side, f, k)[i] - v0[i];
      }
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      for (int i = 0; i < fac.dim; ++i) rhs[i] = w[layout_.offset(side) + fac.offset + i] - v0[i];
      const Eigen::Vector3d t = edges[side][f].partialPivLu().solve(rhs);
      for (int i = 0; i < fac.dim; ++i) input.point[layout_.offset(side) + fac.offset + i] = t[i];
    }
  }
  auto toLocal = [&](const double* covector, double* out) {
    for (int side = 0; side < 2; ++side) {
      const CellShape& shape = layout_.shape(side);
      for (int f = 0; f < shape.numFactors(); ++f) {
        const SimplexFactor& fac = shape.factor(f);
        const int first = layout_.offset(side) + fac.offset;
        for (int k = 0; k < fac.dim; ++k) {
          double sum = 0.0;
          for (int i = 0; i < fac.dim; ++i) sum += edges[side][f](i, k) * covector[first + i];
          out[first + k] = sum;
        }
      }
    }
  };
  // g = WW (f - value): at w its gradient is WW grad f = 2 WW grad F, F = |z|^2 / 2.
  const double weight = CellWeightAt(a_.cell, w) * CellWeightAt(b_.cell, w + layout_.offset(1));
  const double ww = weight * weight;
  double gradient[kMaxPairParams];
  for (int i = 0; i < n; ++i) gradient[i] = 2.0 * ww * kkt.gradient[i];
  double residual[kMaxPairParams];
  std::copy(gradient, gradient + n, residual);
  double normal[kMaxPairParams];
  input.numActive = kkt.numActive;
  for (int c = 0; c < kkt.numActive; ++c) {
    layout_.Normal(kkt.active[c], normal);
    const double mu = 2.0 * ww * kkt.multiplier[c];
    for (int i = 0; i < n; ++i) residual[i] -= mu * normal[i];
    toLocal(normal, input.normal[c]);
    input.multiplier[c] = mu;
  }
  toLocal(residual, input.residual);

  // S's vertices in its local coordinates: the products of every factor's
  // unit simplex vertices.
  double vertices[64 * kMaxPairParams];
  int count = 1;
  std::fill(vertices, vertices + n, 0.0);
  for (int side = 0; side < 2; ++side) {
    const CellShape& shape = layout_.shape(side);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      const int first = layout_.offset(side) + fac.offset;
      const int before = count;
      for (int v = 1; v <= fac.dim; ++v) {
        for (int c = 0; c < before; ++c) {
          double* copy = vertices + static_cast<size_t>(count) * n;
          std::copy(vertices + static_cast<size_t>(c) * n, vertices + static_cast<size_t>(c + 1) * n, copy);
          copy[first + v - 1] = 1.0;
          ++count;
        }
      }
    }
  }
  input.numVertices = count;
  input.vertices = vertices;
  input.allowed = std::max(0.0, value - pruneLevel) * nets.LeastWeight(sideA, sideB);

  // First the cheap test: f = |z|^2 itself, its Hessian bounded from each
  // side's own enclosures (kernels/pair_hessian_bounds.h) along the
  // eigenvectors of its Hessian at w (scaled to a unit diagonal), where a
  // direction in which f barely bends is kept apart from the steep ones.
  {
    PairJet jet;
    EvaluatePair(a_, b_, layout_, w, JetOrder::Second, &jet);
    Matrix local = Matrix::Zero(n, n);
    Matrix edgeMatrix = Matrix::Zero(n, n);
    for (int side = 0; side < 2; ++side) {
      const CellShape& shape = layout_.shape(side);
      for (int f = 0; f < shape.numFactors(); ++f) {
        const SimplexFactor& fac = shape.factor(f);
        const int first = layout_.offset(side) + fac.offset;
        edgeMatrix.block(first, first, fac.dim, fac.dim) = edges[side][f].topLeftCorner(fac.dim, fac.dim);
      }
    }
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        double v = 0.0;
        for (int k = 0; k < ambientDim_; ++k) v += jet.d1[k][r] * jet.d1[k][c] + jet.z[k] * jet.d2[k][r][c];
        local(r, c) = 2.0 * v;
      }
    }
    local = edgeMatrix.transpose() * local * edgeMatrix;
    double basis[kMaxPairParams * kMaxPairParams];
    PairCertificateInput ofF = input;
    ofF.lo = lo;
    ofF.hi = hi;
    ofF.basis = basis;
    ofF.allowed = std::max(0.0, value - pruneLevel);
    double residualF[kMaxPairParams];
    for (int i = 0; i < n; ++i) residualF[i] = 2.0 * kkt.gradient[i];
    for (int c = 0; c < kkt.numActive; ++c) {
      layout_.Normal(kkt.active[c], normal);
      ofF.multiplier[c] = 2.0 * kkt.multiplier[c];
      for (int i = 0; i < n; ++i) residualF[i] -= ofF.multiplier[c] * normal[i];
    }
    toLocal(residualF, ofF.residual);
    const PairTaylorBounds taylor(nets, sideA, sideB);
    if (ScaledEigenBasis(local, basis) && taylor.HessianBounds(basis, lo, hi) && ProvesPairBound(ofF)) {
      return true;
    }
  }
  // The joint nets' bounds cost their sizes' product and close the same
  // subdomain about one split earlier: worth it only where splits do not
  // help, along a valley of equal distances (the search has run long).
  if (examined_ <= kHardSearch) return false;

  nets.HessianRanges(sideA, sideB, value, true, lo, hi, &ws_->hessianScratch);
  if (ProvesPairBound(input)) return true;
  nets.HessianRanges(sideA, sideB, value, false, lo, hi, &ws_->hessianScratch);
  if (ProvesPairBound(input)) return true;
  // The bounds of the Hessian's entries lose what ties them together: along
  // a valley of equal distances (parallel cylinders) g does not change in
  // one direction anywhere, but its bound from the entries' separate ranges
  // bends both ways. Bounds of the directional second derivatives along the
  // eigenvectors of the bounds' midpoint (scaled to a unit diagonal) keep it.
  Matrix mid(n, n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      if (!std::isfinite(lo[r * n + c]) || !std::isfinite(hi[r * n + c])) return false;
      mid(r, c) = 0.5 * (lo[r * n + c] + hi[r * n + c]);
    }
  }
  double basis[kMaxPairParams * kMaxPairParams];
  if (!ScaledEigenBasis(mid, basis)) return false;
  nets.HessianRangesInBasis(sideA, sideB, value, basis, lo, hi, &ws_->hessianScratch);
  input.basis = basis;
  return ProvesPairBound(input);
}

void PairSearch::ChooseSplit(double* slot, int* side, int* factor, int* vi, int* vj) const {
  const PairEdge edge =
      LongestPairEdge(layout_, paramScale_, [slot](int s, int f, int v) { return Vertex(slot, s, f, v); });
  *side = edge.side;
  *factor = edge.factor;
  *vi = edge.vi;
  *vj = edge.vj;
}

void PairSearch::ChooseSplitByVariation(double* slot, int* side, int* factor, int* vi, int* vj) const {
  // Around a KKT point whose certificate failed, the bounds of the
  // Hessian were too wide: split where the Hessian changes most across the
  // subdomain (measured in its local coordinates, from the exact Hessians at
  // a quarter of each edge either side of the centre). Along a valley of
  // equal distances that is across the valley, never along it, where
  // splits by length would multiply the subdomains for nothing.
  const int n = n_;
  double center[kMaxPairParams];
  Center(slot, center);
  Matrix edges = Matrix::Zero(n, n);  // local coordinates into reference ones
  for (int s = 0; s < 2; ++s) {
    const CellShape& shape = layout_.shape(s);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      const int first = layout_.offset(s) + fac.offset;
      for (int k = 1; k <= fac.dim; ++k) {
        for (int i = 0; i < fac.dim; ++i) {
          edges(first + i, first + k - 1) = Vertex(slot, s, f, k)[i] - Vertex(slot, s, f, 0)[i];
        }
      }
    }
  }
  auto hessianAt = [&](const double* w) {
    PairJet jet;
    EvaluatePair(a_, b_, layout_, w, JetOrder::Second, &jet);
    Matrix h(n, n);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        double v = 0.0;
        for (int k = 0; k < ambientDim_; ++k) v += jet.d1[k][r] * jet.d1[k][c] + jet.z[k] * jet.d2[k][r][c];
        h(r, c) = v;
      }
    }
    return Matrix(edges.transpose() * h * edges);
  };
  // Judged with the Hessian scaled to a unit diagonal, as the certificate
  // judges it: what matters is the change relative to the curvature.
  const Matrix atCenter = hessianAt(center);
  double largest = 0.0;
  for (int r = 0; r < n; ++r) largest = std::max(largest, std::abs(atCenter(r, r)));
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPairParams, 1> unit(n);
  for (int r = 0; r < n; ++r) unit[r] = 1.0 / std::sqrt(std::max(std::abs(atCenter(r, r)), 1e-12 * largest + 1e-300));
  // The longest edge unless the Hessian changes along some edge: where it
  // changes along none (a parabola's vertex at the centre, where the
  // change is alike either way), the first edge would be split for ever.
  double most = 0.0;
  ChooseSplit(slot, side, factor, vi, vj);
  for (int s = 0; s < 2; ++s) {
    const CellShape& shape = layout_.shape(s);
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      for (int p = 0; p <= fac.dim; ++p) {
        for (int q = p + 1; q <= fac.dim; ++q) {
          double plus[kMaxPairParams], minus[kMaxPairParams];
          std::copy(center, center + n, plus);
          std::copy(center, center + n, minus);
          for (int i = 0; i < fac.dim; ++i) {
            const double quarter = 0.25 * (Vertex(slot, s, f, q)[i] - Vertex(slot, s, f, p)[i]);
            plus[layout_.offset(s) + fac.offset + i] += quarter;
            minus[layout_.offset(s) + fac.offset + i] -= quarter;
          }
          const double variation = (unit.asDiagonal() * (hessianAt(plus) - hessianAt(minus)) * unit.asDiagonal()).norm();
          if (variation > most) {
            most = variation;
            *side = s;
            *factor = f;
            *vi = p;
            *vj = q;
          }
        }
      }
    }
  }
  // Where the Hessian changes along one direction only (a segment against
  // a parabola: it depends on the parabola's parameter alone), the other
  // direction's length still enters the certificate through the residual
  // of the KKT conditions.
  KeepSplitsLong(slot, side, factor, vi, vj);
}

void PairSearch::ChooseSplitByBend(double* slot, const PairNets& nets, int* side, int* factor, int* vi,
                                   int* vj) const {
  const double* sideA = slot + kHeaderSize;
  const double* sideB = sideA + nets.sideLength(0);
  int argA = 0, argB = 0;
  nets.LowerBound(sideA, sideB, &ws_->scratch, &argA, &argB);
  if (!nets.MostBentEdgeAt(sideA, sideB, argA, argB, side, factor, vi, vj)) {
    ChooseSplit(slot, side, factor, vi, vj);
    return;
  }
  // The bend at one coefficient can miss a direction in which the net
  // still varies (a circle's arc seen from near its axis: the quotients
  // along it bend little, but their least stays far below the distance).
  // A direction far shorter than the longest is not split again: the
  // longest is.
  KeepSplitsLong(slot, side, factor, vi, vj);
}

void PairSearch::KeepSplitsLong(double* slot, int* side, int* factor, int* vi, int* vj) const {
  auto length2 = [&](int s, int f, int p, int q) {
    const SimplexFactor& fac = layout_.shape(s).factor(f);
    double l2 = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      const double e = (Vertex(slot, s, f, p)[i] - Vertex(slot, s, f, q)[i]) * paramScale_[layout_.offset(s) + fac.offset + i];
      l2 += e * e;
    }
    return l2;
  };
  int ls = 0, lf = 0, lp = 0, lq = 1;
  ChooseSplit(slot, &ls, &lf, &lp, &lq);
  if (length2(*side, *factor, *vi, *vj) * kBendSplitRatio2 < length2(ls, lf, lp, lq)) {
    *side = ls;
    *factor = lf;
    *vi = lp;
    *vj = lq;
  }
}

double PairSearch::RootLowerBound() {
  const PairNets nets(a_, b_);
  const int slotSize = kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
  if (ws_->slots.size() < static_cast<size_t>(slotSize)) ws_->slots.resize(slotSize);
  double* sideA = ws_->slots.data() + kHeaderSize;
  double* sideB = sideA + nets.sideLength(0);
  nets.BuildRoot(sideA, sideB);
  return nets.LowerBound(sideA, sideB, &ws_->scratch) - nets.RoundingSlack();
}

PairSolveResult PairSearch::Finish(const PairLocalResult& best, bool certified, double bound2) const {
  PairSolveResult result;
  const int pa = layout_.paramDim(0), pb = layout_.paramDim(1);
  std::copy(best.w, best.w + pa, result.refA);
  std::copy(best.w + pa, best.w + pa + pb, result.refB);
  std::copy(best.x, best.x + 3, result.pointA);
  std::copy(best.y, best.y + 3, result.pointB);
  result.distance = std::sqrt(best.squaredDistance);
  result.iterations = iterations_;
  result.subdomains = examined_;
  // Every subdomain the search closed lies at or beyond the exclusion
  // level of min(best, bound2), less the nets' rounding.
  const double closed = ExclusionLevel(std::min(best.squaredDistance, bound2), tau_, 0.0);
  double proved = certified ? closed : std::min(closed, open_);
  // A trimmed pair's search proves bounds for its admitted KKT points only.
  if (trimmed_) proved = std::min(proved, rootBound2_);
  result.lowerBound = std::sqrt(std::max(0.0, proved));
  if (!(best.squaredDistance < kInf)) {
    // No admitted point found: a trimmed pair whose nearest points lie on
    // its faces' boundaries (their edges' pairs answer) or beyond the bound.
    result.distance = kInf;
    result.status = certified ? PairStatus::Farther : PairStatus::NotCertified;
    if (!certified) result.openBound2 = std::max(open_, 0.0);
    return result;
  }
  if (!certified) {
    // Whatever its distance: some part of the pair may still hold a closer point.
    result.status = PairStatus::NotCertified;
    result.openBound2 = std::max(open_, 0.0);
  } else if (bound2 < kInf && best.squaredDistance >= bound2) {
    result.status = PairStatus::Farther;
  } else {
    result.status = best.onBoundary ? PairStatus::ProjectedToBoundary : PairStatus::Converged;
  }
  return result;
}

PairSolveResult PairSearch::Probe(double bound2) {
  if (!HaveNets() || (a_.affine && b_.affine)) return Solve(nullptr, nullptr, bound2);
  const PairNets nets(a_, b_);
  slack_ = nets.RoundingSlack();
  const int slotSize = kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
  if (ws_->slots.size() < static_cast<size_t>(slotSize)) ws_->slots.resize(slotSize);
  double* sideA = ws_->slots.data() + kHeaderSize;
  double* sideB = sideA + nets.sideLength(0);
  nets.BuildRoot(sideA, sideB);
  int argA = 0, argB = 0;
  const double lowerBound = nets.LowerBound(sideA, sideB, &ws_->scratch, &argA, &argB) - slack_;
  if (bound2 < kInf && lowerBound >= bound2) {
    PairSolveResult far;
    far.status = PairStatus::Farther;
    far.lowerBound = std::sqrt(lowerBound);
    return far;
  }
  double start[kMaxPairParams];
  ControlPointLocation(nets.shape(0), argA, start);
  ControlPointLocation(nets.shape(1), argB, start + layout_.offset(1));
  best_ = Local(start);
  if (!Admitted(best_.w)) Reject(&best_);
  rootBound2_ = lowerBound;
  if (best_.squaredDistance <= tau_ * tau_) return Finish(best_, true, bound2);
  open_ = lowerBound;
  return Finish(best_, false, bound2);
}

PairSolveResult PairSearch::Solve(const double* startA, const double* startB, double bound2) {
  const bool bounded = bound2 < kInf;
  double start[kMaxPairParams];
  bool reusing = false;
  if (HaveNets() && reuse_ && reuse_->previous && reuse_->previous->valid) {
    const PairNets nets(a_, b_);
    reusing = reuse_->previous->leafLength == kLeafHeader + kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
  }
  if (reusing) {
    // The previous partition replaces the whole pair's nets; its best point
    // starts the local solve.
    slack_ = PairNets(a_, b_).RoundingSlack();
    if (!startA) std::copy(reuse_->previous->start, reuse_->previous->start + n_, start);
  } else if (HaveNets()) {
    const PairNets nets(a_, b_);
    slack_ = nets.RoundingSlack();
    const int slotSize = kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
    SlotPool pool(&ws_->slots, &ws_->freeSlots, slotSize);
    const int root = pool.Allocate();
    SetRoot(pool[root]);
    double* sideA = pool[root] + kHeaderSize;
    double* sideB = sideA + nets.sideLength(0);
    nets.BuildRoot(sideA, sideB);
    int argA = 0, argB = 0;
    pool[root][kLowerBound] = nets.LowerBound(sideA, sideB, &ws_->scratch, &argA, &argB);
    rootBound2_ = pool[root][kLowerBound] - slack_;
    if (bounded && pool[root][kLowerBound] - slack_ >= bound2) {
      PairSolveResult far;
      far.status = PairStatus::Farther;
      far.lowerBound = std::sqrt(pool[root][kLowerBound] - slack_);
      return far;
    }
    if (!startA) {
      // Where the nets come closest: the lattice places of the least joint coefficient.
      ControlPointLocation(nets.shape(0), argA, start);
      ControlPointLocation(nets.shape(1), argB, start + layout_.offset(1));
    }
  } else if (!startA) {
    layout_.Center(start);
  }
  if (startA) {
    std::copy(startA, startA + layout_.paramDim(0), start);
    std::copy(startB, startB + layout_.paramDim(1), start + layout_.offset(1));
  }
  best_ = Local(start);
  if (!Admitted(best_.w)) {
    // Two affine maps: the KKT points are the convex distance's minima, a
    // convex set; one outside a region leaves the pair's nearest admitted
    // points on that region's boundary, which the face's edges answer.
    if (a_.affine && b_.affine && best_.kkt.kkt) {
      Reject(&best_);
      return Finish(best_, true, bound2);
    }
    Reject(&best_);
  }
  // Two affine maps make the squared distance a convex quadratic: a KKT
  // point is global. A distance within tau of zero cannot be beaten by more.
  if ((a_.affine && b_.affine && best_.kkt.kkt) || best_.squaredDistance <= tau_ * tau_) {
    return Finish(best_, true, bound2);
  }
  if (!HaveNets()) {
    open_ = 0.0;
    return Finish(best_, false, bound2);
  }
  // A trimmed side's local answer outside the region keeps nothing for the
  // search to prune with until it finds a point of the region.

  const PairNets nets(a_, b_);
  ownOffset_ = kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
  const int slotSize = ownOffset_ + (Keeping() ? nets.sideLength(0) + nets.sideLength(1) : 0);
  SlotPool pool(&ws_->slots, &ws_->freeSlots, slotSize);
  auto pruneLevel = [&] { return ExclusionLevel(std::min(best_.squaredDistance, bound2), tau_, slack_); };
  std::vector<int>& heap = ws_->heap;
  heap.clear();
  auto byLowerBound = [&](int x, int y) { return pool[x][kLowerBound] > pool[y][kLowerBound]; };
  if (reusing) {
    SeedFromPartition(&pool, nets, pruneLevel(), &heap);
    std::make_heap(heap.begin(), heap.end(), byLowerBound);
  } else {
    const int root = pool.Allocate();
    double* slot = pool[root];
    SetRoot(slot);
    double* sideA = slot + kHeaderSize;
    nets.BuildRoot(sideA, sideA + nets.sideLength(0));
    if (Keeping()) nets.BuildRootOwn(slot + ownOffset_, slot + ownOffset_ + nets.sideLength(0));
    slot[kLowerBound] = nets.LowerBound(sideA, sideA + nets.sideLength(0), &ws_->scratch);
    if (slot[kLowerBound] < pruneLevel()) {
      heap.push_back(root);
    } else {
      KeepLeaf(slot, Bound(slot[kLowerBound]), nets);
    }
  }

  bool certified = true;
  int examined = 0, hardSeeds = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), byLowerBound);
    const int s = heap.back();
    heap.pop_back();
    if (pool[s][kLowerBound] >= pruneLevel()) {
      // Every other subdomain is farther still.
      KeepLeaf(pool[s], Bound(pool[s][kLowerBound]), nets);
      for (int h : heap) KeepLeaf(pool[h], Bound(pool[h][kLowerBound]), nets);
      heap.clear();
      break;
    }
    examined_ = ++examined;
    if (examined > kMaxPairSubdomains) {
      // The heap's least bound holds for every part left open.
      certified = false;
      open_ = std::min(open_, pool[s][kLowerBound] - slack_);
      break;
    }
    if (trimmed_ && !MayHoldAdmittedKkt(pool[s], nets, std::min(best_.squaredDistance, bound2))) {
      pool.Free(s);
      continue;
    }
    const bool tryCertificate = pool[s][kDepth] >= pool[s][kRetryDepth];
    if (tryCertificate && CertifiedAround(pool[s], pruneLevel())) {
      // Closed around a KKT point that moves with the models: reopened next time.
      KeepLeaf(pool[s], 0.0, nets);
      pool.Free(s);
      continue;
    }
    double center[kMaxPairParams];
    Center(pool[s], center);
    PairJet jet;
    EvaluatePair(a_, b_, layout_, center, JetOrder::Value, &jet);
    const double fCenter = PairSquaredDistance(jet, ambientDim_);
    // As in the cell search: after kHardSearch subdomains every one also
    // seeds a local solve (a valley of equal distances, a near tie), which
    // finds the KKT points its centre's value cannot show.
    const bool seed = examined > kHardSearch && hardSeeds < kHardSeeds;
    hardSeeds += seed ? 1 : 0;
    // A trimmed pair seeds only from centres its regions admit (as the
    // cell search does): an admitted KKT point is the limit of the centres
    // of the subdomains that shrink onto it, and the stationary points
    // outside, which centres outside would find again and again, are no answers.
    const bool centerAdmitted = !trimmed_ || Admitted(center);
    if ((fCenter < best_.squaredDistance || seed) && centerAdmitted) {
      const PairLocalResult local = Local(center);
      const bool admitted = !trimmed_ || Admitted(local.w);
      if (admitted && local.squaredDistance < best_.squaredDistance) {
        best_ = local;
        if (best_.squaredDistance <= tau_ * tau_) {
          complete_ = false;  // what is left open has no proved bound
          break;
        }
      } else if (trimmed_ && fCenter < best_.squaredDistance) {
        // The centre is a point of the pair: it bounds the distance from
        // above and lets the search prune (it is never certified as a KKT point).
        PairLocalResult sample;
        std::copy(center, center + n_, sample.w);
        std::copy(jet.x, jet.x + 3, sample.x);
        std::copy(jet.y, jet.y + 3, sample.y);
        sample.squaredDistance = fCenter;
        best_ = sample;
      } else if (local.squaredDistance >= best_.squaredDistance && local.kkt.kkt && Contains(pool[s], local.w)) {
        pool[s][kHasSeed] = 1.0;
        pool[s][kSeedValue] = local.squaredDistance;
        std::copy(local.w, local.w + n_, pool[s] + kSeedPoint);
      }
      if (pool[s][kLowerBound] >= pruneLevel() || CertifiedAround(pool[s], pruneLevel())) {
        KeepLeaf(pool[s], pool[s][kLowerBound] >= pruneLevel() ? Bound(pool[s][kLowerBound]) : 0.0, nets);
        pool.Free(s);
        continue;
      }
    }
    if (pool[s][kDepth] >= kMaxDepth) {
      certified = false;
      open_ = std::min(open_, pool[s][kLowerBound] - slack_);
      pool.Free(s);
      continue;
    }
    if (tryCertificate && HoldsKktPoint(pool[s])) pool[s][kRetryDepth] = pool[s][kDepth] + retryStep_;
    int side = 0, factor = 0, vi = 0, vj = 1;
    const bool crossing = pool[s][kTrimSide] == static_cast<double>(TrimRegion::Side::Crossing) ||
                          pool[s][kTrimSide + 1] == static_cast<double>(TrimRegion::Side::Crossing);
    if (HoldsKktPoint(pool[s])) {
      ChooseSplitByVariation(pool[s], &side, &factor, &vi, &vj);
    } else if (crossing) {
      // Along a trimming curve, splits where the net bends most could make
      // slivers that no test closes: by length.
      ChooseSplit(pool[s], &side, &factor, &vi, &vj);
    } else {
      ChooseSplitByBend(pool[s], nets, &side, &factor, &vi, &vj);
    }
    for (int child = 0; child < 2; ++child) {
      const int keep = child == 0 ? vi : vj;
      const int move = child == 0 ? vj : vi;
      const int c = pool.Allocate();
      double* parent = pool[s];
      double* slot = pool[c];
      std::copy(parent, parent + kHeaderSize, slot);
      slot[kDepth] = parent[kDepth] + 1;
      double* moved = Vertex(slot, side, factor, move);
      const double* kept = Vertex(slot, side, factor, keep);
      for (int i = 0; i < 3; ++i) moved[i] = 0.5 * (moved[i] + kept[i]);
      if (slot[kHasSeed] != 0.0 && !Contains(slot, slot + kSeedPoint)) slot[kHasSeed] = 0.0;
      if (Trim(side) && slot[kTrimSide + side] != static_cast<double>(TrimRegion::Side::Inside)) {
        double lo[3], hi[3];
        SideBox(slot, side, lo, hi);
        const TrimRegion::Side where = Trim(side)->ClassifySubdomain(lo, hi);
        if (where == TrimRegion::Side::Outside) {
          pool.Free(c);
          continue;
        }
        slot[kTrimSide + side] = static_cast<double>(where);
      }
      const double* parentA = parent + kHeaderSize;
      const double* parentB = parentA + nets.sideLength(0);
      double* childA = slot + kHeaderSize;
      double* childB = childA + nets.sideLength(0);
      if (side == 0) {
        nets.Split(0, factor, keep, move, parentA, childA);
        std::copy(parentB, parentB + nets.sideLength(1), childB);
      } else {
        std::copy(parentA, parentA + nets.sideLength(0), childA);
        nets.Split(1, factor, keep, move, parentB, childB);
      }
      if (Keeping()) {
        const double* ownParent = parent + ownOffset_ + (side == 0 ? 0 : nets.sideLength(0));
        double* ownChild = slot + ownOffset_ + (side == 0 ? 0 : nets.sideLength(0));
        const double* ownOther = parent + ownOffset_ + (side == 0 ? nets.sideLength(0) : 0);
        double* ownOtherChild = slot + ownOffset_ + (side == 0 ? nets.sideLength(0) : 0);
        nets.Split(side, factor, keep, move, ownParent, ownChild);
        std::copy(ownOther, ownOther + nets.sideLength(1 - side), ownOtherChild);
      }
      slot[kLowerBound] = nets.LowerBound(childA, childB, &ws_->scratch);
      if (slot[kLowerBound] < pruneLevel()) {
        heap.push_back(c);
        std::push_heap(heap.begin(), heap.end(), byLowerBound);
      } else {
        KeepLeaf(slot, Bound(slot[kLowerBound]), nets);
        pool.Free(c);
      }
    }
    pool.Free(s);
  }
  if (Keeping() && certified && complete_ && best_.squaredDistance < kInf) {
    PairPartition& next = *reuse_->next;
    next.valid = true;
    next.leafLength = kLeafHeader + kHeaderSize + nets.sideLength(0) + nets.sideLength(1);
    std::copy(best_.w, best_.w + n_, next.start);
    const std::size_t count = next.leaves.size() / next.leafLength;
    next.wholeLeaves = reusing ? reuse_->previous->wholeLeaves : count;
    // Reopened subdomains near a minimum that moves are split again at
    // every motion: a partition grown so deep that its searches would reach
    // kMaxDepth is dropped too.
    if (count > kPartitionGrowth * next.wholeLeaves + 16 || keptDepth_ > kMaxDepth / 2) next.valid = false;
  }
  return Finish(best_, certified, bound2);
}

}  // namespace

bool IsAffineSimplexSide(const PairSide& side) {
  const CellType type = side.cell.shape.type();
  return side.affine && (type == CellType::Line || type == CellType::Tri) && side.cell.shape.factor(0).degree >= 1;
}

PairSolveResult SolveCellPair(const PairSide& a, const PairSide& b, const double* startA, const double* startB,
                              PairWorkspace* ws, double bound2, const PairReuse* reuse) {
  if (IsAffineSimplexSide(a) && IsAffineSimplexSide(b)) {
    double va[3][3], vb[3][3];
    SimplexVertices(a, va);
    SimplexVertices(b, vb);
    const double* pa[3] = {va[0], va[1], va[2]};
    const double* pb[3] = {vb[0], vb[1], vb[2]};
    PairSolveResult result;
    if (bound2 < kInf) {
      // Most nearby pairs of two meshes face each other across a gap that
      // one triangle's normal bounds; only the rest need the closed form.
      const double gap = SimplexPlaneGap(a.cell.shape.paramDim(), pa, b.cell.shape.paramDim(), pb, 3);
      if (gap * gap >= bound2) {
        result.distance = gap;
        result.lowerBound = gap;
        result.status = PairStatus::Farther;
        return result;
      }
    }
    const double d2 = ClosestPointsOfSimplices(a.cell.shape.paramDim(), pa, b.cell.shape.paramDim(), pb, 3,
                                               result.refA, result.refB, result.pointA, result.pointB);
    result.distance = std::sqrt(d2);
    result.lowerBound = result.distance;
    bool onBoundary = false;
    for (int side = 0; side < 2; ++side) {
      const double* ref = side == 0 ? result.refA : result.refB;
      const int pd = (side == 0 ? a : b).cell.shape.paramDim();
      double sum = 0.0;
      for (int i = 0; i < pd; ++i) {
        onBoundary = onBoundary || ref[i] <= 0.0;
        sum += ref[i];
      }
      onBoundary = onBoundary || sum >= 1.0;
    }
    result.status = bound2 < kInf && d2 >= bound2
                        ? PairStatus::Farther
                        : (onBoundary ? PairStatus::ProjectedToBoundary : PairStatus::Converged);
    return result;
  }
  PairSearch search(a, b, ws, reuse);
  const PairSolveResult result = search.Solve(startA, startB, bound2);
  if (result.status != PairStatus::NotCertified || !reuse || !reuse->previous || !reuse->previous->valid) {
    return result;
  }
  // The partition's boundaries were drawn around the minima of earlier
  // motions; a minimum now just outside a kept subdomain leaves that
  // subdomain's bound within rounding of the answer with no KKT point of
  // its own to certify it, and the search splits it to its depth limit.
  // Searched from the whole pair instead, as a fresh query would be.
  const PairReuse fromWhole{nullptr, reuse->next, reuse->drift};
  PairSearch again(a, b, ws, &fromWhole);
  return again.Solve(startA, startB, bound2);
}

PairSolveResult ProbeCellPair(const PairSide& a, const PairSide& b, PairWorkspace* ws, double bound2) {
  if (IsAffineSimplexSide(a) && IsAffineSimplexSide(b)) return SolveCellPair(a, b, nullptr, nullptr, ws, bound2);
  PairSearch search(a, b, ws);
  return search.Probe(bound2);
}

double PairNetLowerBound(const PairSide& a, const PairSide& b, PairWorkspace* ws) {
  if (!a.nets || !b.nets) return 0.0;
  PairSearch search(a, b, ws);
  return search.RootLowerBound();
}

}  // namespace invmap::kernels
