// The lane kernels of kernels/newton_lanes.h for one instruction set:
// included by newton_lanes_<isa>.cpp only, each compiled for its set.
// Everything is a template over the xsimd architecture A; nothing here may
// depend on how many lanes a vector holds beyond the loop over blocks.
#pragma once

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "kernels/newton_lanes.h"
#include "kernels/simplex_index.h"
#include "kernels/tolerances.h"

namespace invmap::kernels::lanes {

// The local solve's constants that tolerances.h does not hold yet (they are
// LocalSolve's, kernels/local_solver.cpp): the longest unchecked final
// Newton step, Armijo's fraction, the rounding of the map's coordinates per
// unit of their magnitude, and the KKT check's slope tolerances and face test.
constexpr double kLaneFinalStep = 1e-6;
constexpr double kLaneSufficientDecrease = 1e-4;
constexpr double kLaneMapRounding = 16.0 * std::numeric_limits<double>::epsilon();
constexpr double kLaneKktSlope = 1e-7;
constexpr double kLaneKktSlopeFloor = 1e-12;
constexpr double kLaneKktOnFace = 1e-12;
constexpr int kLaneMaxIterations = 100;
// CurvatureBounds::ProvesConvex's and IntervalMatrixIsPositive's margins.
constexpr double kBoundSumRoundingLanes = 1e-14;
constexpr double kPositivityMarginLanes = 1e-12;

template <class A>
using Batch = xsimd::batch<double, A>;
template <class A>
using Mask = xsimd::batch_bool<double, A>;

/// The lanes [first, first + W) of a call: loads that repeat the last lane
/// into a partial block's tail (which takes no part), stores of the lanes
/// that exist.
template <class A>
struct Block {
  static constexpr int W = static_cast<int>(Batch<A>::size);
  Block(int firstLane, int count) : first(firstLane), valid(std::min(W, count - firstLane)) {}

  Batch<A> Load(const double* data) {
    for (int l = 0; l < W; ++l) buffer[l] = data[first + std::min(l, valid - 1)];
    return Batch<A>::load_aligned(buffer);
  }
  /// The W values of `v` (valid until the next call).
  const double* Values(const Batch<A>& v) {
    v.store_aligned(buffer);
    return buffer;
  }
  void Store(const Batch<A>& v, double* to) {
    Values(v);
    for (int l = 0; l < valid; ++l) to[first + l] = buffer[l];
  }
  /// True in the lanes that exist.
  Mask<A> Existing() {
    for (int l = 0; l < W; ++l) buffer[l] = l < valid ? 1.0 : 0.0;
    return Batch<A>::load_aligned(buffer) != Batch<A>(0.0);
  }

  int first, valid;
  alignas(64) double buffer[W];
};

/// Bernstein polynomials of one line factor at t (a lane each) with their
/// first and second derivatives, by the recurrences of EvaluateFactorBasis.
/// FixedDegree > 0 makes every loop's length a constant.
template <class A, int FixedDegree>
struct LineBasisLanes {
  static constexpr int kCapacity = (FixedDegree > 0 ? FixedDegree : kMaxDegree) + 1;
  Batch<A> value[kCapacity], d1[kCapacity], d2[kCapacity];

  static void Raise(const Batch<A>* from, int n, Batch<A> u, Batch<A> t, Batch<A>* to) {
    to[n] = t * from[n - 1];
    for (int i = n - 1; i > 0; --i) to[i] = u * from[i] + t * from[i - 1];
    to[0] = u * from[0];
  }

  void Evaluate(int runtimeDegree, Batch<A> t) {
    const int degree = FixedDegree > 0 ? FixedDegree : runtimeDegree;
    const Batch<A> zero(0.0), one(1.0);
    const Batch<A> u = one - t;
    Batch<A> lower2[kCapacity], lower1[kCapacity];
    lower2[0] = one;
    for (int n = 1; n <= degree - 2; ++n) Raise(lower2, n, u, t, lower2);
    if (degree >= 2) {
      Raise(lower2, degree - 1, u, t, lower1);
    } else {
      lower1[0] = one;
    }
    if (degree >= 1) {
      Raise(lower1, degree, u, t, value);
    } else {
      value[0] = one;
    }
    const Batch<A> p(static_cast<double>(degree));
    for (int i = 0; i <= degree; ++i) {
      const Batch<A> left = i >= 1 ? lower1[i - 1] : zero;
      const Batch<A> right = i < degree ? lower1[i] : zero;
      d1[i] = degree >= 1 ? p * (left - right) : zero;
    }
    const Batch<A> pp(static_cast<double>(degree * (degree - 1)));
    for (int i = 0; i <= degree; ++i) {
      Batch<A> second = zero;
      if (degree >= 2) {
        const Batch<A> a = i >= 2 ? lower2[i - 2] : zero;
        const Batch<A> b = i >= 1 && i - 1 <= degree - 2 ? lower2[i - 1] : zero;
        const Batch<A> c = i <= degree - 2 ? lower2[i] : zero;
        second = pp * (a - Batch<A>(2.0) * b + c);
      }
      d2[i] = second;
    }
  }
};

/// The map of a cell at one reference point per lane: x_k, dx_k/du_i and
/// d2x_k/du_i du_j (second derivatives as the lower triangle, (i, j) with
/// j <= i at i (i + 1) / 2 + j).
template <class A, int PD, int AD>
struct JetLanes {
  static constexpr int kSecond = PD * (PD + 1) / 2;
  Batch<A> x[AD];
  Batch<A> d1[AD][PD];
  Batch<A> d2[AD][kSecond];
  Batch<A> logWeightSlope[PD];  ///< (dW/du_i) / W; 0 for a polynomial cell.

  void SelectFrom(const Mask<A>& take, const JetLanes& other) {
    for (int i = 0; i < PD; ++i) logWeightSlope[i] = xsimd::select(take, other.logWeightSlope[i], logWeightSlope[i]);
    for (int k = 0; k < AD; ++k) {
      x[k] = xsimd::select(take, other.x[k], x[k]);
      for (int i = 0; i < PD; ++i) d1[k][i] = xsimd::select(take, other.d1[k][i], d1[k][i]);
      for (int e = 0; e < kSecond; ++e) d2[k][e] = xsimd::select(take, other.d2[k][e], d2[k][e]);
    }
  }
};

/// Evaluates cells of line factors (PD of them) whose homogeneous control
/// values are `h` (control point c's component k at h[c * Comps + k]: w x_k,
/// then w when rational), first factor fastest.
template <class A, int PD, int AD, bool Rational, int FixedDegree>
class LineCellLanes {
 public:
  static constexpr int kComps = AD + (Rational ? 1 : 0);

  LineCellLanes(const int* degrees, const double* homogeneous, const double* points)
      : h_(homogeneous), points_(points) {
    for (int f = 0; f < PD; ++f) degree_[f] = degrees[f];
  }

  /// The Greville parameters of the control point nearest to each lane's
  /// point (CellSolver::NearestControlPointStart's start for a curve or a
  /// surface: the first of equally near ones).
  void NearestControlPointStart(const Batch<A>* point, Batch<A>* ref) const {
    const int n0 = Degree(0) + 1;
    const int n = PD == 1 ? n0 : n0 * (Degree(PD - 1) + 1);
    Batch<A> nearest2(std::numeric_limits<double>::infinity()), nearest(0.0);
    for (int c = 0; c < n; ++c) {
      Batch<A> d2(0.0);
      for (int k = 0; k < AD; ++k) {
        const Batch<A> d = Batch<A>(points_[c * AD + k]) - point[k];
        d2 += d * d;
      }
      const Mask<A> nearer = d2 < nearest2;
      nearest2 = xsimd::select(nearer, d2, nearest2);
      nearest = xsimd::select(nearer, Batch<A>(static_cast<double>(c)), nearest);
    }
    // Control point (i, j) sits over (i / p, j / q); the indices are exact
    // small integers in double.
    const Batch<A> row = xsimd::floor(nearest / Batch<A>(static_cast<double>(n0)));
    ref[0] = (nearest - row * Batch<A>(static_cast<double>(n0))) / Batch<A>(static_cast<double>(Degree(0)));
    if constexpr (PD == 2) ref[1] = row / Batch<A>(static_cast<double>(Degree(1)));
  }
  /// Factor f's degree, a constant when FixedDegree is set.
  int Degree(int f) const { return FixedDegree > 0 ? FixedDegree : degree_[f]; }

  void Evaluate(const Batch<A>* ref, JetLanes<A, PD, AD>* out) const {
    LineBasisLanes<A, FixedDegree> basis[PD];
    for (int f = 0; f < PD; ++f) basis[f].Evaluate(Degree(f), ref[f]);
    // Homogeneous sums: s0 value, s1[i] first, s2[e] second derivatives.
    Batch<A> s0[kComps], s1[PD][kComps], s2[PD * (PD + 1) / 2][kComps];
    if constexpr (PD == 1) {
      for (int k = 0; k < kComps; ++k) s0[k] = s1[0][k] = s2[0][k] = Batch<A>(0.0);
      const LineBasisLanes<A, FixedDegree>& b = basis[0];
      for (int i = 0; i <= Degree(0); ++i) {
        for (int k = 0; k < kComps; ++k) {
          const Batch<A> c(h_[i * kComps + k]);
          s0[k] += b.value[i] * c;
          s1[0][k] += b.d1[i] * c;
          s2[0][k] += b.d2[i] * c;
        }
      }
    } else {
      for (int k = 0; k < kComps; ++k) {
        s0[k] = s1[0][k] = s1[1][k] = s2[0][k] = s2[1][k] = s2[2][k] = Batch<A>(0.0);
      }
      const LineBasisLanes<A, FixedDegree>& bu = basis[0];
      const LineBasisLanes<A, FixedDegree>& bv = basis[1];
      const int rowSize = Degree(0) + 1;
      for (int j = 0; j <= Degree(1); ++j) {
        // The row j contracted with the first factor's basis.
        Batch<A> r0[kComps], r1[kComps], r2[kComps];
        for (int k = 0; k < kComps; ++k) r0[k] = r1[k] = r2[k] = Batch<A>(0.0);
        const double* row = h_ + static_cast<std::size_t>(j) * rowSize * kComps;
        for (int i = 0; i < rowSize; ++i) {
          for (int k = 0; k < kComps; ++k) {
            const Batch<A> c(row[i * kComps + k]);
            r0[k] += bu.value[i] * c;
            r1[k] += bu.d1[i] * c;
            r2[k] += bu.d2[i] * c;
          }
        }
        for (int k = 0; k < kComps; ++k) {
          s0[k] += bv.value[j] * r0[k];
          s1[0][k] += bv.value[j] * r1[k];
          s1[1][k] += bv.d1[j] * r0[k];
          s2[0][k] += bv.value[j] * r2[k];  // (0, 0)
          s2[1][k] += bv.d1[j] * r1[k];     // (1, 0)
          s2[2][k] += bv.d2[j] * r0[k];     // (1, 1)
        }
      }
    }
    constexpr int kSecond = PD * (PD + 1) / 2;
    if constexpr (!Rational) {
      for (int i = 0; i < PD; ++i) out->logWeightSlope[i] = Batch<A>(0.0);
      for (int k = 0; k < AD; ++k) {
        out->x[k] = s0[k];
        for (int i = 0; i < PD; ++i) out->d1[k][i] = s1[i][k];
        for (int e = 0; e < kSecond; ++e) out->d2[k][e] = s2[e][k];
      }
    } else {
      // Quotient rule, as EvaluateMap's.
      const Batch<A> invW = Batch<A>(1.0) / s0[AD];
      for (int i = 0; i < PD; ++i) out->logWeightSlope[i] = s1[i][AD] * invW;
      for (int k = 0; k < AD; ++k) {
        out->x[k] = s0[k] * invW;
        for (int i = 0; i < PD; ++i) out->d1[k][i] = (s1[i][k] - out->x[k] * s1[i][AD]) * invW;
        for (int i = 0; i < PD; ++i) {
          for (int j = 0; j <= i; ++j) {
            const int ij = i * (i + 1) / 2 + j;
            out->d2[k][ij] = (s2[ij][k] - s1[i][AD] * out->d1[k][j] - s1[j][AD] * out->d1[k][i] -
                              out->x[k] * s2[ij][AD]) *
                             invW;
          }
        }
      }
    }
  }

 private:
  const double* h_;
  const double* points_;  ///< Cartesian control points.
  int degree_[PD];
};

/// |v| for lanes, and a mask of the lanes where the sum of squares left the
/// range in which LocalSolve's Norm takes it as it is (there the scalar solve,
/// which rescales, takes over).
template <class A>
Batch<A> PlainNorm(Batch<A> length2, Mask<A>* outOfRange) {
  *outOfRange = *outOfRange | !(length2 > Batch<A>(1e-300) && length2 < Batch<A>(1e300));
  return xsimd::sqrt(length2);
}

/// TangentPlaneLowerBound (kernels/tangent_plane.h) for lanes of a cell of
/// line factors: the least value over the unit box of the tangent plane of
/// W^2 (|x - p|^2 - level) at `ref`, less its rounding; -infinity where it
/// is not positive.
template <class A, int PD, int AD>
Batch<A> TangentPlaneLowerBoundLanes(const JetLanes<A, PD, AD>& jet, const Batch<A>* point, const Batch<A>* ref,
                                     const Batch<A>& level, double size) {
  using B = Batch<A>;
  const B zero(0.0), minusInfinity(-std::numeric_limits<double>::infinity());
  B r[AD], f = zero;
  for (int k = 0; k < AD; ++k) {
    r[k] = jet.x[k] - point[k];
    f += r[k] * r[k];
  }
  const B excess = f - level;
  B slope[PD];
  for (int i = 0; i < PD; ++i) {
    slope[i] = zero;
    for (int k = 0; k < AD; ++k) slope[i] += B(2.0) * jet.d1[k][i] * r[k];
    slope[i] += B(2.0) * jet.logWeightSlope[i] * excess;
  }
  // A linear function's least value over an interval is at an end.
  B least = excess;
  for (int i = 0; i < PD; ++i) {
    least -= slope[i] * ref[i];
    least += xsimd::min(zero, slope[i]);
  }
  B magnitude(size), columns = zero, weightSlope = zero;
  for (int k = 0; k < AD; ++k) {
    magnitude = xsimd::max(magnitude, xsimd::max(xsimd::abs(point[k]), xsimd::abs(jet.x[k]) + B(size)));
  }
  for (int i = 0; i < PD; ++i) {
    for (int k = 0; k < AD; ++k) columns += xsimd::abs(jet.d1[k][i]);
    weightSlope += B(2.0) * xsimd::abs(jet.logWeightSlope[i]);
  }
  const B delta = B(kLaneMapRounding) * magnitude;
  const B rounding = (B(2.0) * delta * (xsimd::sqrt(f) + columns) + delta * delta) * (B(1.0) + weightSlope);
  const B bound = least - rounding;
  return xsimd::select((excess > zero) & (least > zero) & xsimd::isfinite(bound), bound, minusInfinity);
}

/// The local solve of lanes [first, first + W) (see SolveNewtonLanes):
/// LocalSolve's fast path for line factors (LineFactorNewton) with the
/// general loop's step to a bound: a Newton step that leaves the domain is
/// cut where it does, and the constraint met is held, when the cut step
/// passes Armijo's test at once.
template <class A, int PD, int AD, bool Rational, int FixedDegree>
void SolveBlock(const LineCellLanes<A, PD, AD, Rational, FixedDegree>& cell, double size, const NewtonLanes& lanes,
                int first) {
  using B = Batch<A>;
  using M = Mask<A>;
  Block<A> block(first, lanes.count);
  B point[AD], ref[PD];
  for (int k = 0; k < AD; ++k) point[k] = block.Load(lanes.point[k]);
  if (lanes.startAtNearestControlPoint) {
    cell.NearestControlPointStart(point, ref);
  } else {
    for (int i = 0; i < PD; ++i) ref[i] = block.Load(lanes.ref[i]);
  }
  for (int i = 0; i < PD; ++i) ref[i] = xsimd::min(xsimd::max(ref[i], B(0.0)), B(1.0));
  const B zero(0.0), one(1.0);
  // Held constraints per parameter: at 0 (released toward +u) or at 1.
  M heldLo[PD], heldHi[PD];
  for (int i = 0; i < PD; ++i) {
    heldHi[i] = one - ref[i] <= B(kOnFaceTolerance);
    heldLo[i] = ref[i] <= B(kOnFaceTolerance);
    // ActiveSetAt keeps one coordinate of a factor free (lambda_0's face).
    heldHi[i] = heldHi[i] & !heldLo[i];
    ref[i] = xsimd::select(heldLo[i], zero, xsimd::select(heldHi[i], one, ref[i]));
  }
  JetLanes<A, PD, AD> jet, trialJet;
  cell.Evaluate(ref, &jet);
  const auto residual = [&](const JetLanes<A, PD, AD>& j, B* r) {
    B f = zero;
    for (int k = 0; k < AD; ++k) {
      r[k] = j.x[k] - point[k];
      f += r[k] * r[k];
    }
    return f;
  };
  const auto gradient = [&](const B* r, B* grad) {
    for (int i = 0; i < PD; ++i) {
      grad[i] = zero;
      for (int k = 0; k < AD; ++k) grad[i] += jet.d1[k][i] * r[k];
    }
  };
  {
    // A start on the boundary keeps only the constraints the descent presses
    // against (ReleaseInwardConstraints).
    B r[AD], grad[PD];
    residual(jet, r);
    gradient(r, grad);
    for (int i = 0; i < PD; ++i) {
      heldLo[i] = heldLo[i] & !(grad[i] < zero);
      heldHi[i] = heldHi[i] & !(-grad[i] < zero);
    }
  }
  M live(true), kkt(false), handover(false), jetStale(false), aboveLevel(false);
  M exclusionPending(false);
  B level(0.0);
  if (lanes.exclusionLevel) {
    level = block.Load(lanes.exclusionLevel);
    exclusionPending = level > B(-std::numeric_limits<double>::infinity());
  }
  live = block.Existing();  // lanes of the padded tail take no part
  B iterations = zero;
  const B perLengthSize(kGradientTolerance), floorLength(kThinDirection * size), sizeB(size);
  for (int iter = 0; iter < kLaneMaxIterations && xsimd::any(live); ++iter) {
    iterations = xsimd::select(live, iterations + one, iterations);
    if (xsimd::any(live & exclusionPending)) {
      // LocalSolve's exclusion: tried at each iterate until it first holds.
      const M above = live & exclusionPending & (TangentPlaneLowerBoundLanes(jet, point, ref, level, size) > zero);
      aboveLevel = aboveLevel | above;
      exclusionPending = exclusionPending & !above;
      live = live & !above;
      if (!xsimd::any(live)) break;
    }
    B r[AD], grad[PD];
    const B f = residual(jet, r);
    gradient(r, grad);
    const B perLength = perLengthSize * (sizeB + xsimd::sqrt(f));
    M extreme(false);
    B tolerance[PD];
    for (int i = 0; i < PD; ++i) {
      B column2 = zero;
      for (int k = 0; k < AD; ++k) column2 += jet.d1[k][i] * jet.d1[k][i];
      tolerance[i] = perLength * xsimd::max(PlainNorm(column2, &extreme), floorLength);
    }
    M stationary(true), noRelease(true);
    for (int i = 0; i < PD; ++i) {
      const M free = !(heldLo[i] | heldHi[i]);
      stationary = stationary & ((!free) | (xsimd::abs(grad[i]) <= tolerance[i]));
      noRelease = noRelease & !(heldLo[i] & (grad[i] < -tolerance[i])) & !(heldHi[i] & (-grad[i] < -tolerance[i]));
    }
    handover = handover | (live & extreme);
    live = live & !extreme;
    kkt = kkt | (live & stationary & noRelease);
    handover = handover | (live & stationary & !noRelease);
    live = live & !stationary;
    if (!xsimd::any(live)) break;

    // The rounding level of f (RoundingOfF).
    B magnitude = sizeB;
    for (int k = 0; k < AD; ++k) magnitude = xsimd::max(magnitude, xsimd::abs(point[k]) + xsimd::abs(r[k]));
    const B rError = B(kLaneMapRounding) * magnitude;
    const B fNoise = B(2.0) * xsimd::sqrt(f) * rError + rError * rError;

    // Newton step over the free parameters: a held one gets a unit row and
    // column and a zero gradient, so its step is 0.
    B h[PD][PD], g[PD];
    for (int a = 0; a < PD; ++a) {
      const M freeA = !(heldLo[a] | heldHi[a]);
      g[a] = xsimd::select(freeA, grad[a], zero);
      for (int b = 0; b <= a; ++b) {
        B v = zero;
        const int ab = a * (a + 1) / 2 + b;
        for (int k = 0; k < AD; ++k) v += jet.d1[k][a] * jet.d1[k][b] + r[k] * jet.d2[k][ab];
        const M freeB = !(heldLo[b] | heldHi[b]);
        h[a][b] = h[b][a] = xsimd::select(freeA & freeB, v, a == b ? one : zero);
      }
    }
    B step[PD], slopeHalf;
    M descends;
    if constexpr (PD == 1) {
      const M positive = h[0][0] > zero;
      step[0] = -g[0] / h[0][0];
      slopeHalf = step[0] * g[0];
      descends = positive;
    } else {
      // LDL^T of the 2 x 2 block (NewtonStepOf).
      const B d0 = h[0][0];
      const B l10 = h[1][0] / d0;
      const B d1 = h[1][1] - l10 * d0 * l10;
      const B y0 = -g[0];
      const B y1 = -g[1] - l10 * y0;
      step[1] = y1 / d1;
      step[0] = y0 / d0 - l10 * step[1];
      slopeHalf = step[1] * g[1] + step[0] * g[0];
      descends = (d0 > zero) & (d1 > zero);
    }
    descends = descends & xsimd::isfinite(slopeHalf) & (slopeHalf < zero);
    handover = handover | (live & !descends);
    live = live & descends;
    if (!xsimd::any(live)) break;

    B length2 = zero, slope = zero;
    for (int i = 0; i < PD; ++i) {
      length2 += step[i] * step[i];
      slope += B(2.0) * grad[i] * step[i];
    }
    const B length = xsimd::sqrt(length2);
    // The fraction of the step that stays in [0, 1]^PD, and the bound it meets.
    B alpha = one;
    M blockLo[PD], blockHi[PD];
    for (int i = 0; i < PD; ++i) {
      const B toLo = ref[i] / -step[i];
      const B toHi = (one - ref[i]) / step[i];
      blockLo[i] = (step[i] < zero) & (toLo < alpha);
      alpha = xsimd::select(blockLo[i], toLo, alpha);
      blockHi[i] = (step[i] > zero) & (toHi < alpha);
      alpha = xsimd::select(blockHi[i], toHi, alpha);
    }
    // Only the last bound that lowered alpha is the one met.
    M blocked(false);
    for (int i = PD - 1; i >= 0; --i) {
      blockHi[i] = blockHi[i] & !blocked;
      blocked = blocked | blockHi[i];
      blockLo[i] = blockLo[i] & !blocked;
      blocked = blocked | blockLo[i];
    }
    // Step limits (StepLimitsAt): shrunk where the map moves faster than size.
    B jac2 = zero;
    for (int k = 0; k < AD; ++k) {
      for (int i = 0; i < PD; ++i) jac2 += jet.d1[k][i] * jet.d1[k][i];
    }
    const B shrink = xsimd::select(jac2 > sizeB * sizeB, sizeB / xsimd::sqrt(jac2), one);
    const B negligible = B(kStepTolerance) * shrink;
    const B finalStep = B(kLaneFinalStep) * shrink;

    // Already on the bound the step meets (up to rounding): the general
    // loop holds it there and snaps onto it; the scalar solve does that.
    const M holdOnly = live & blocked & (alpha * length <= negligible);
    handover = handover | holdOnly;
    live = live & !holdOnly;
    M moving = live;
    // In the quadratic region: the step is taken unchecked.
    const M final = moving & !blocked & (-slope <= fNoise) & (length <= finalStep);
    for (int i = 0; i < PD; ++i) ref[i] = xsimd::select(final, ref[i] + step[i], ref[i]);
    kkt = kkt | (final & noRelease);
    handover = handover | (final & !noRelease);
    jetStale = jetStale | final;
    moving = moving & !final;
    // Too short to tell from rounding: the line search would give up here.
    const M negligibleStep = moving & ((alpha * length <= negligible) | (-alpha * slope <= fNoise));
    handover = handover | negligibleStep;
    moving = moving & !negligibleStep;
    live = live & !final & !negligibleStep;
    if (!xsimd::any(moving)) continue;

    B trial[PD];
    for (int i = 0; i < PD; ++i) {
      trial[i] = xsimd::select(moving, ref[i] + alpha * step[i], ref[i]);
      trial[i] = xsimd::select(blockLo[i], zero, xsimd::select(blockHi[i], one, trial[i]));
      trial[i] = xsimd::min(xsimd::max(trial[i], zero), one);
    }
    cell.Evaluate(trial, &trialJet);
    B rTrial[AD];
    const B fTrial = residual(trialJet, rTrial);
    const M accepted = moving & (fTrial <= f + B(kLaneSufficientDecrease) * alpha * slope) & (fTrial < f);
    // A step the line search would shorten: the scalar solve takes over.
    handover = handover | (moving & !accepted);
    live = live & !(moving & !accepted);
    for (int i = 0; i < PD; ++i) {
      ref[i] = xsimd::select(accepted, trial[i], ref[i]);
      heldLo[i] = heldLo[i] | (accepted & blockLo[i]);
      heldHi[i] = heldHi[i] | (accepted & blockHi[i]);
    }
    jet.SelectFrom(accepted, trialJet);
  }
  handover = handover | live;  // the iteration cap
  kkt = kkt & !handover;

  // The map at the answers whose last step was taken unchecked.
  if (xsimd::any(jetStale & kkt)) {
    cell.Evaluate(ref, &trialJet);
    jet.SelectFrom(jetStale, trialJet);
  }
  // The independent KKT check (IsKktOnUnitBox).
  B r[AD], grad[PD];
  const B f = residual(jet, r);
  gradient(r, grad);
  const B perLength = B(kLaneKktSlope) * xsimd::sqrt(f) + B(kLaneKktSlopeFloor) * sizeB;
  const B norm(1.0 / std::sqrt(2.0));
  M extreme = !xsimd::isfinite(perLength);
  M passes(true);
  for (int i = 0; i < PD; ++i) {
    B column2 = zero;
    for (int k = 0; k < AD; ++k) column2 += jet.d1[k][i] * jet.d1[k][i];
    const B length = PlainNorm(column2, &extreme);
    const B tolerance = perLength * xsimd::max(length, floorLength);
    const B tolerance2 = perLength * xsimd::max(norm * length, floorLength);
    const M atLo = (ref[i] <= B(kLaneKktOnFace)) & (ref[i] * length <= B(kLaneKktOnFace) * sizeB);
    const B fromHi = one - ref[i];
    const M atHi = (!atLo) & (fromHi <= B(kLaneKktOnFace)) & (fromHi * length <= B(kLaneKktOnFace) * sizeB);
    const M inside = (!atLo) & (!atHi);
    passes = passes & !(atLo & (grad[i] < -tolerance)) & !(atHi & (-grad[i] < -tolerance)) &
             !(inside & (xsimd::abs(-norm * grad[i]) > tolerance2));
  }
  kkt = kkt & passes & !extreme;

  for (int i = 0; i < PD; ++i) block.Store(ref[i], lanes.ref[i]);
  for (int k = 0; k < AD; ++k) block.Store(jet.x[k], lanes.closest[k]);
  block.Store(f, lanes.squaredDistance);
  const double* counted = block.Values(iterations);
  for (int l = 0; l < block.valid; ++l) lanes.iterations[first + l] = static_cast<int>(counted[l]);
  const double* outcome = block.Values(xsimd::select(kkt, one, xsimd::select(aboveLevel, B(2.0), zero)));
  for (int l = 0; l < block.valid; ++l) {
    lanes.outcome[first + l] = outcome[l] == 1.0   ? LaneOutcome::Kkt
                               : outcome[l] == 2.0 ? LaneOutcome::AboveLevel
                                                   : LaneOutcome::Handover;
  }
  M held(false);
  for (int i = 0; i < PD; ++i) held = held | heldLo[i] | heldHi[i];
  const double* onBoundary = block.Values(xsimd::select(held, one, zero));
  for (int l = 0; l < block.valid; ++l) lanes.onBoundary[first + l] = onBoundary[l] != 0.0;
}

template <class A, int PD, int AD, bool Rational, int FixedDegree>
void SolveTyped(const CellView& view, double size, const NewtonLanes& lanes) {
  constexpr int kComps = AD + (Rational ? 1 : 0);
  // Homogeneous control values, w x_k then w.
  double homogeneous[(kMaxDegree + 1) * (kMaxDegree + 1) * kComps];
  const int n = view.shape.numControlPoints();
  for (int c = 0; c < n; ++c) {
    const double w = Rational ? view.weights[c] : 1.0;
    for (int k = 0; k < AD; ++k) homogeneous[c * kComps + k] = Rational ? w * view.points[c * AD + k] : view.points[c * AD + k];
    if constexpr (Rational) homogeneous[c * kComps + AD] = w;
  }
  int degrees[PD];
  for (int f = 0; f < PD; ++f) degrees[f] = view.shape.factor(f).degree;
  const LineCellLanes<A, PD, AD, Rational, FixedDegree> cell(degrees, homogeneous, view.points);
  constexpr int W = static_cast<int>(Batch<A>::size);
  for (int first = 0; first < lanes.count; first += W) SolveBlock(cell, size, lanes, first);
}

template <class A, int PD, int AD, bool Rational>
void SolveForDegree(const CellView& view, double size, const NewtonLanes& lanes) {
  bool cubic = true;
  for (int f = 0; f < PD; ++f) cubic = cubic && view.shape.factor(f).degree == 3;
  if (cubic) return SolveTyped<A, PD, AD, Rational, 3>(view, size, lanes);
  SolveTyped<A, PD, AD, Rational, 0>(view, size, lanes);
}

template <class A, int PD, int AD>
void SolveForWeights(const CellView& view, double size, const NewtonLanes& lanes) {
  if (view.weights) return SolveForDegree<A, PD, AD, true>(view, size, lanes);
  SolveForDegree<A, PD, AD, false>(view, size, lanes);
}

/// SolveNewtonLanes for architecture A.
template <class A>
void SolveNewtonLanesFor(const CellView& view, double size, const NewtonLanes& lanes) {
  const int pd = view.shape.paramDim();
  if (pd == 2) return SolveForWeights<A, 2, 3>(view, size, lanes);
  if (view.ambientDim == 2) return SolveForWeights<A, 1, 2>(view, size, lanes);
  SolveForWeights<A, 1, 3>(view, size, lanes);
}

/// A polynomial tetrahedron's map and Jacobian at one point per lane, from
/// products of powers of the barycentric coordinates: the value from the
/// control points, each derivative from the degree p - 1 net of differences
/// p (P_{b + e_i} - P_{b + e_0}), both with their multinomials folded in.
template <class A, int FixedDegree>
class TetLanes {
 public:
  static constexpr int kMaxSize = SimplexBasisSize(3, FixedDegree > 0 ? FixedDegree : kMaxDegree);

  explicit TetLanes(const CellView& view) : degree_(FixedDegree > 0 ? FixedDegree : view.shape.factor(0).degree) {
    const SimplexIndex& index = SimplexIndex::Get(3, degree_);
    size_ = index.size();
    for (int a = 0; a < size_; ++a) {
      multi_[a] = index.multi(a);
      for (int k = 0; k < 3; ++k) value_[a][k] = index.multinomial(a) * view.points[a * 3 + k];
    }
    const SimplexIndex& lower = SimplexIndex::Get(3, degree_ - 1);
    lowerSize_ = lower.size();
    for (int b = 0; b < lowerSize_; ++b) {
      lowerMulti_[b] = lower.multi(b);
      std::array<int, 4> up0 = lower.multi(b);
      ++up0[0];
      const double* p0 = view.points + 3 * index.Position(up0);
      for (int i = 0; i < 3; ++i) {
        std::array<int, 4> up = lower.multi(b);
        ++up[i + 1];
        const double* pi = view.points + 3 * index.Position(up);
        for (int k = 0; k < 3; ++k) slope_[b][i][k] = degree_ * lower.multinomial(b) * (pi[k] - p0[k]);
      }
    }
  }

  /// x[k] and d1[k][i] at free coordinates s (lanes).
  void Evaluate(const Batch<A>* s, Batch<A>* x, Batch<A> (*d1)[3]) const {
    using B = Batch<A>;
    const int p = FixedDegree > 0 ? FixedDegree : degree_;
    B power[4][(FixedDegree > 0 ? FixedDegree : kMaxDegree) + 1];
    const B lambda[4] = {B(1.0) - s[0] - s[1] - s[2], s[0], s[1], s[2]};
    for (int k = 0; k < 4; ++k) {
      power[k][0] = B(1.0);
      for (int e = 1; e <= p; ++e) power[k][e] = power[k][e - 1] * lambda[k];
    }
    for (int k = 0; k < 3; ++k) {
      x[k] = B(0.0);
      for (int i = 0; i < 3; ++i) d1[k][i] = B(0.0);
    }
    for (int a = 0; a < size_; ++a) {
      const std::array<int, 4>& m = multi_[a];
      const B basis = power[0][m[0]] * power[1][m[1]] * power[2][m[2]] * power[3][m[3]];
      for (int k = 0; k < 3; ++k) x[k] += basis * B(value_[a][k]);
    }
    for (int b = 0; b < lowerSize_; ++b) {
      const std::array<int, 4>& m = lowerMulti_[b];
      const B basis = power[0][m[0]] * power[1][m[1]] * power[2][m[2]] * power[3][m[3]];
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) d1[k][i] += basis * B(slope_[b][i][k]);
      }
    }
  }

 private:
  int degree_;
  int size_ = 0, lowerSize_ = 0;
  std::array<int, 4> multi_[kMaxSize], lowerMulti_[kMaxSize];
  double value_[kMaxSize][3];
  double slope_[kMaxSize][3][3];
};

/// Determinant of the 3 x 3 matrix with columns a, b, c (kernels/cramer.h's).
template <class A>
Batch<A> Determinant3Lanes(const Batch<A>* a, const Batch<A>* b, const Batch<A>* c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// SolveInsideLanes for lanes [first, first + W).
template <class A, int FixedDegree>
void InsideBlock(const TetLanes<A, FixedDegree>& cell, double size, const InsideLanes& lanes, int first) {
  using B = Batch<A>;
  using M = Mask<A>;
  Block<A> block(first, lanes.count);
  const B zero(0.0), one(1.0), sizeB(size);
  B point[3], ref[3];
  for (int k = 0; k < 3; ++k) {
    point[k] = block.Load(lanes.point[k]);
    ref[k] = block.Load(lanes.ref[k]);
  }
  M live = block.Existing();
  M converged(false), handover(false), stale(false);
  B iterations = zero;
  B x[3], d1[3][3], xTrial[3], d1Trial[3][3];
  cell.Evaluate(ref, x, d1);
  const B cubeTolerance(kSingularTolerance * size * size * size);
  for (int iter = 0; iter < kLaneMaxIterations && xsimd::any(live); ++iter) {
    iterations = xsimd::select(live, iterations + one, iterations);
    B r[3], f = zero;
    for (int k = 0; k < 3; ++k) {
      r[k] = x[k] - point[k];
      f += r[k] * r[k];
    }
    // Full rank: stationary where r itself is as small as the tests ask.
    const B root = xsimd::sqrt(f);
    const M stationary = root <= B(kGradientTolerance) * (sizeB + root);
    converged = converged | (live & stationary);
    live = live & !stationary;
    if (!xsimd::any(live)) break;
    // -J^-1 r by Cramer's rule (FullRankStep).
    B column[3][3], minusR[3];
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) column[i][k] = d1[k][i];
    }
    for (int k = 0; k < 3; ++k) minusR[k] = -r[k];
    const B det = Determinant3Lanes<A>(column[0], column[1], column[2]);
    B step[3];
    step[0] = Determinant3Lanes<A>(minusR, column[1], column[2]) / det;
    step[1] = Determinant3Lanes<A>(column[0], minusR, column[2]) / det;
    step[2] = Determinant3Lanes<A>(column[0], column[1], minusR) / det;
    M ok = (xsimd::abs(det) > cubeTolerance) & xsimd::isfinite(step[0]) & xsimd::isfinite(step[1]) &
           xsimd::isfinite(step[2]);
    B slope = zero, length2 = zero, jac2 = zero;
    for (int i = 0; i < 3; ++i) {
      B grad = zero;
      for (int k = 0; k < 3; ++k) {
        grad += d1[k][i] * r[k];
        jac2 += d1[k][i] * d1[k][i];
      }
      slope += B(2.0) * grad * step[i];
      length2 += step[i] * step[i];
    }
    ok = ok & (slope < zero);
    // A step that leaves the tetrahedron: the scalar solve takes over.
    const B lambda0 = one - ref[0] - ref[1] - ref[2];
    const B trial0 = lambda0 - step[0] - step[1] - step[2];
    M inside = trial0 >= zero;
    for (int i = 0; i < 3; ++i) inside = inside & (ref[i] + step[i] >= zero);
    ok = ok & inside;
    handover = handover | (live & !ok);
    live = live & ok;
    if (!xsimd::any(live)) break;
    const B length = xsimd::sqrt(length2);
    const B shrink = xsimd::select(jac2 > sizeB * sizeB, sizeB / xsimd::sqrt(jac2), one);
    B magnitude = sizeB;
    for (int k = 0; k < 3; ++k) magnitude = xsimd::max(magnitude, xsimd::abs(point[k]) + xsimd::abs(r[k]));
    const B rError = B(kLaneMapRounding) * magnitude;
    const B fNoise = B(2.0) * root * rError + rError * rError;
    const M final = live & (-slope <= fNoise) & (length <= B(kLaneFinalStep) * shrink);
    for (int i = 0; i < 3; ++i) ref[i] = xsimd::select(final, ref[i] + step[i], ref[i]);
    converged = converged | final;
    stale = stale | final;
    live = live & !final;
    const M negligible = live & ((length <= B(kStepTolerance) * shrink) | (-slope <= fNoise));
    handover = handover | negligible;
    live = live & !negligible;
    if (!xsimd::any(live)) continue;
    B trial[3];
    for (int i = 0; i < 3; ++i) trial[i] = xsimd::select(live, ref[i] + step[i], ref[i]);
    cell.Evaluate(trial, xTrial, d1Trial);
    B fTrial = zero;
    for (int k = 0; k < 3; ++k) {
      const B d = xTrial[k] - point[k];
      fTrial += d * d;
    }
    const M accepted = live & (fTrial <= f + B(kLaneSufficientDecrease) * slope) & (fTrial < f);
    handover = handover | (live & !accepted);
    live = accepted;
    for (int i = 0; i < 3; ++i) ref[i] = xsimd::select(accepted, trial[i], ref[i]);
    for (int k = 0; k < 3; ++k) {
      x[k] = xsimd::select(accepted, xTrial[k], x[k]);
      for (int i = 0; i < 3; ++i) d1[k][i] = xsimd::select(accepted, d1Trial[k][i], d1[k][i]);
    }
  }
  handover = handover | live;
  converged = converged & !handover;
  if (xsimd::any(stale & converged)) {
    cell.Evaluate(ref, xTrial, d1Trial);
    for (int k = 0; k < 3; ++k) x[k] = xsimd::select(stale, xTrial[k], x[k]);
  }
  B f = zero;
  for (int k = 0; k < 3; ++k) {
    const B d = x[k] - point[k];
    f += d * d;
  }
  const B tau(kDistanceTolerance * size);
  const M inside = converged & (f <= tau * tau);
  for (int i = 0; i < 3; ++i) block.Store(ref[i], lanes.ref[i]);
  for (int k = 0; k < 3; ++k) block.Store(x[k], lanes.closest[k]);
  block.Store(f, lanes.squaredDistance);
  const double* counted = block.Values(iterations);
  for (int l = 0; l < block.valid; ++l) lanes.iterations[first + l] = static_cast<int>(counted[l]);
  const double* outcome = block.Values(xsimd::select(inside, B(2.0), xsimd::select(converged, one, zero)));
  for (int l = 0; l < block.valid; ++l) {
    lanes.outcome[first + l] = outcome[l] == 2.0   ? InsideOutcome::Inside
                               : outcome[l] == 1.0 ? InsideOutcome::NotInside
                                                   : InsideOutcome::Handover;
  }
}

template <class A, int FixedDegree>
void SolveInsideTyped(const CellView& view, double size, const InsideLanes& lanes) {
  const TetLanes<A, FixedDegree> cell(view);
  constexpr int W = static_cast<int>(Batch<A>::size);
  for (int first = 0; first < lanes.count; first += W) InsideBlock(cell, size, lanes, first);
}

/// SolveInsideLanes for architecture A: quadratic and cubic tetrahedra
/// with loops of constant length.
template <class A>
void SolveInsideLanesFor(const CellView& view, double size, const InsideLanes& lanes) {
  switch (view.shape.factor(0).degree) {
    case 2:
      return SolveInsideTyped<A, 2>(view, size, lanes);
    case 3:
      return SolveInsideTyped<A, 3>(view, size, lanes);
    default:
      return SolveInsideTyped<A, 0>(view, size, lanes);
  }
}

/// NetLowerBoundLanes for architecture A: the coefficients' loop outside,
/// a block of lanes inside, so each coefficient is read once per block.
template <class A>
void NetLowerBoundLanesFor(const NetLanes& nets, int count, const double* const point[3], double* lowerBound) {
  using B = Batch<A>;
  for (int first = 0; first < count; first += Block<A>::W) {
    Block<A> block(first, count);
    B twoD[3], local2(0.0);
    for (int k = 0; k < nets.ambientDim; ++k) {
      const B d = block.Load(point[k]) - B(nets.center[k]);
      local2 += d * d;
      twoD[k] = B(2.0) * d;
    }
    B least(std::numeric_limits<double>::infinity());
    for (int i = 0; i < nets.size; ++i) {
      // The order of DistanceNets::SquaredDistanceNumerator.
      const B wwi(nets.ww[i]);
      B q = B(nets.nn[i]) + local2 * wwi;
      for (int k = 0; k < nets.ambientDim; ++k) q = q - twoD[k] * B(nets.nw[k][i]);
      least = xsimd::min(least, nets.rational ? q / wwi : q);
    }
    block.Store(least, lowerBound);
  }
}

/// IntervalMatrixIsPositive for lanes, dimension 1 or 2 (the same tests in
/// the same order of operations).
template <class A, int Dim>
Mask<A> IntervalMatrixIsPositiveLanes(const Batch<A> (&lo)[2][2], const Batch<A> (&hi)[2][2]) {
  using B = Batch<A>;
  const B zero(0.0), half(0.5);
  Mask<A> positive = lo[0][0] > zero;
  if constexpr (Dim == 1) {
    return positive;
  } else {
    positive = positive & (lo[1][1] > zero);
    B mid[2][2], radius2 = zero;
    for (int a = 0; a < 2; ++a) {
      for (int b = a; b < 2; ++b) {
        mid[a][b] = half * (lo[a][b] + hi[a][b]);
        const B r = half * (hi[a][b] - lo[a][b]);
        radius2 += B(a == b ? 1.0 : 2.0) * r * r;
      }
    }
    const B halfDifference = half * (mid[0][0] - mid[1][1]);
    const B lambdaMin =
        half * (mid[0][0] + mid[1][1]) - xsimd::sqrt(halfDifference * halfDifference + mid[0][1] * mid[0][1]);
    const B scale = xsimd::max(xsimd::max(xsimd::abs(mid[0][0]), xsimd::abs(mid[0][1])), xsimd::abs(mid[1][1]));
    const Mask<A> interval = lambdaMin > xsimd::sqrt(radius2) + B(kPositivityMarginLanes) * scale;
    const B largest = xsimd::max(xsimd::abs(lo[0][1]), xsimd::abs(hi[0][1]));
    const B beta = largest / (xsimd::sqrt(lo[0][0]) * xsimd::sqrt(lo[1][1]));
    const Mask<A> scaled = beta < B(1.0 - kPositivityMarginLanes);
    return positive & (interval | scaled);
  }
}

}  // namespace invmap::kernels::lanes

namespace invmap::kernels {

template <class A>
void CurvatureLanes::Prove(const CurvatureBounds& bounds, int count, const double* const point[3],
                           const double* level, bool* proved) {
  using B = lanes::Batch<A>;
  using M = lanes::Mask<A>;
  const int pd = bounds.paramDim_;
  const int ad = bounds.ambientDim_;
  for (int first = 0; first < count; first += lanes::Block<A>::W) {
    lanes::Block<A> block(first, count);
    B d[3], distance2(0.0);
    for (int k = 0; k < ad; ++k) {
      d[k] = block.Load(point[k]) - B(bounds.center_[k]);
      distance2 += d[k] * d[k];
    }
    const B weightFactor = distance2 - block.Load(level);
    B lo[2][2], hi[2][2];
    for (int a = 0; a < pd; ++a) {
      for (int b = a; b < pd; ++b) {
        const int e = CurvatureBounds::Entry(a, b);
        B along(0.0), spread(0.0), size(0.0);
        for (int k = 0; k < ad; ++k) {
          along += d[k] * B(bounds.nw_[e][k].mid());
          spread += xsimd::abs(d[k]) * B(bounds.nw_[e][k].radius());
          size += xsimd::abs(d[k] * B(bounds.nw_[e][k].mid()));
        }
        B weightLo(0.0), weightHi(0.0);
        if (bounds.rational_) {
          const B atLo = weightFactor * B(bounds.ww_[e].lo), atHi = weightFactor * B(bounds.ww_[e].hi);
          weightLo = xsimd::min(atLo, atHi);
          weightHi = xsimd::max(atLo, atHi);
          size += xsimd::abs(weightLo) + xsimd::abs(weightHi);
        }
        const B rounding = B(lanes::kBoundSumRoundingLanes) * size;
        lo[a][b] = B(bounds.nn_[e].lo) - B(2.0) * (along + spread) + weightLo - rounding;
        hi[a][b] = B(bounds.nn_[e].hi) - B(2.0) * (along - spread) + weightHi + rounding;
      }
    }
    const M positive = pd == 1 ? lanes::IntervalMatrixIsPositiveLanes<A, 1>(lo, hi)
                               : lanes::IntervalMatrixIsPositiveLanes<A, 2>(lo, hi);
    const double* values = block.Values(xsimd::select(positive, B(1.0), B(0.0)));
    for (int l = 0; l < block.valid; ++l) proved[first + l] = values[l] != 0.0;
  }
}

}  // namespace invmap::kernels

/// Defines the entry points of one instruction set (newton_lanes_<isa>.cpp).
#define INVMAP_NEWTON_LANES_ISA(Suffix, Arch)                                                                     \
  namespace invmap::kernels::lanes {                                                                            \
  void SolveNewtonLanes##Suffix(const CellView& view, double size, const NewtonLanes& lanes) {                  \
    SolveNewtonLanesFor<Arch>(view, size, lanes);                                                               \
  }                                                                                                             \
  void NetLowerBoundLanes##Suffix(const NetLanes& nets, int count, const double* const point[3], double* lower) { \
    NetLowerBoundLanesFor<Arch>(nets, count, point, lower);                                                     \
  }                                                                                                             \
  void SolveInsideLanes##Suffix(const CellView& view, double size, const InsideLanes& lanes) {                  \
    SolveInsideLanesFor<Arch>(view, size, lanes);                                                               \
  }                                                                                                             \
  void ProvesConvexLanes##Suffix(const CurvatureBounds& bounds, int count, const double* const point[3],        \
                                 const double* level, bool* proved) {                                           \
    CurvatureLanes::Prove<Arch>(bounds, count, point, level, proved);                                           \
  }                                                                                                             \
  }
