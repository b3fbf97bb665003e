// The SIMD lanes of curved cells (kernels/newton_lanes.h) and SolveLane on
// the cells they cover: every lane's certified answer against the
// independent brute-force reference of tests/support/reference_cell.h; the
// KKT points of the lanes against the reference's own map and derivatives;
// the same answer bit for bit whatever the instruction set and whichever
// points share a vector; the nets' lower bounds for all lanes against the
// scalar bound and against dense sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "kernels/bernstein_net.h"
#include "kernels/cell_solver.h"
#include "kernels/curvature_bounds.h"
#include "kernels/distance_net.h"
#include "kernels/newton_lanes.h"
#include "kernels/tangent_plane.h"
#include "tests/support/lane_output.h"
#include "tests/support/reference_cell.h"

namespace invmap::testing {
namespace {

using kernels::CellSolver;
using kernels::CellType;
using kernels::LaneIsa;
using kernels::LaneOutcome;
using kernels::NewtonLanes;
using kernels::PointStatus;
using kernels::QueryLane;
using kernels::ResultLane;
using kernels::SolveWorkspace;

/// Distances must match the reference to this times the cell size (as the
/// cell solver's own tests).
constexpr double kRelTol = 1e-9;

constexpr QueryKind kKinds[10] = {QueryKind::Inside, QueryKind::Inside, QueryKind::Near,     QueryKind::Near,
                                  QueryKind::Near,   QueryKind::Far,    QueryKind::Far,      QueryKind::Boundary,
                                  QueryKind::Boundary, QueryKind::Boundary};

/// The cells the lanes cover: curves in 2D and 3D, surfaces in 3D.
struct Combination {
  CellType type;
  int ambientDim;
  int degree;
  bool rational;
};

std::vector<Combination> CoveredCombinations() {
  std::vector<Combination> all;
  for (int degree : {1, 2, 3, 4}) {
    for (bool rational : {false, true}) {
      all.push_back({CellType::Line, 2, degree, rational});
      all.push_back({CellType::Line, 3, degree, rational});
      all.push_back({CellType::Quad, 3, degree, rational});
    }
  }
  return all;
}

std::string Name(const Combination& c) {
  std::ostringstream os;
  os << CellTypeName(c.type) << " " << c.ambientDim << "d degree " << c.degree
     << (c.rational ? " rational" : "");
  return os.str();
}

/// Query points of a cell as structure of arrays, and random starts.
struct LaneInput {
  std::vector<double> coord[3], start[3];
  int count() const { return static_cast<int>(coord[0].size()); }
};

LaneInput MakeInput(const RefCell& cell, int count, std::mt19937_64& rng) {
  LaneInput in;
  for (int l = 0; l < count; ++l) {
    const Query q = RandomQuery(cell, kKinds[l % 10], rng);
    const std::array<double, 3> s = RandomRefPoint(cell.type, rng);
    for (int k = 0; k < 3; ++k) {
      in.coord[k].push_back(q.point[k]);
      in.start[k].push_back(s[k]);
    }
  }
  return in;
}

/// The distance nets of `cell` around the centre of its control points' box
/// (as CellSolver builds them).
kernels::DistanceNets NetsAroundBoxCenter(const RefCell& cell) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, center[3] = {0, 0, 0};
  for (int p = 0; p < cell.numControlPoints(); ++p) {
    for (int k = 0; k < cell.ambientDim; ++k) {
      lo[k] = std::min(lo[k], cell.points[p * cell.ambientDim + k]);
      hi[k] = std::max(hi[k], cell.points[p * cell.ambientDim + k]);
    }
  }
  for (int k = 0; k < cell.ambientDim; ++k) center[k] = 0.5 * (lo[k] + hi[k]);
  kernels::DistanceNets nets;
  nets.Build(cell.view(), center);
  return nets;
}

/// The raw lane outputs of SolveNewtonLanes.
struct LaneRun {
  explicit LaneRun(int n) : squaredDistance(n), onBoundary(n), outcome(n), iterations(n) {
    for (int k = 0; k < 3; ++k) {
      ref[k].resize(n);
      closest[k].resize(n);
    }
  }
  std::vector<double> ref[3], closest[3], squaredDistance;
  std::vector<char> onBoundary;
  std::vector<LaneOutcome> outcome;
  std::vector<int> iterations;
};

/// Runs the lanes of `in` listed in `order` (in that order) with
/// instruction set `isa`; the outputs land at each lane's own index (the
/// others are left zero).
LaneRun RunLanes(const RefCell& cell, const LaneInput& in, const std::vector<int>& order, LaneIsa isa) {
  const int n = static_cast<int>(order.size());
  LaneInput gathered;
  for (int l : order) {
    for (int k = 0; k < 3; ++k) {
      gathered.coord[k].push_back(in.coord[k][l]);
      gathered.start[k].push_back(in.start[k][l]);
    }
  }
  LaneRun run(n);
  bool* onBoundaryData = reinterpret_cast<bool*>(run.onBoundary.data());
  NewtonLanes lanes;
  lanes.count = n;
  for (int k = 0; k < 3; ++k) {
    lanes.point[k] = gathered.coord[k].data();
    lanes.closest[k] = run.closest[k].data();
    run.ref[k] = gathered.start[k];
    lanes.ref[k] = run.ref[k].data();
  }
  lanes.squaredDistance = run.squaredDistance.data();
  lanes.onBoundary = onBoundaryData;
  lanes.outcome = run.outcome.data();
  lanes.iterations = run.iterations.data();
  kernels::SolveNewtonLanes(cell.view(), cell.size(), lanes, isa);
  // Back to the lanes' own indices.
  LaneRun scattered(in.count());
  for (int j = 0; j < n; ++j) {
    const int l = order[j];
    for (int k = 0; k < 3; ++k) {
      scattered.ref[k][l] = run.ref[k][j];
      scattered.closest[k][l] = run.closest[k][j];
    }
    scattered.squaredDistance[l] = run.squaredDistance[j];
    scattered.onBoundary[l] = run.onBoundary[j];
    scattered.outcome[l] = run.outcome[j];
    scattered.iterations[l] = run.iterations[j];
  }
  return scattered;
}

std::vector<int> Identity(int n) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  return order;
}

std::vector<LaneIsa> AvailableIsas() {
  std::vector<LaneIsa> isas;
  for (LaneIsa isa : {LaneIsa::Sse2, LaneIsa::Avx2, LaneIsa::Avx512}) {
    if (kernels::LaneIsaAvailable(isa)) isas.push_back(isa);
  }
  return isas;
}

/// Bitwise equality of two doubles (NaN equal to the same NaN).
bool Same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(NewtonLanes, CoverCurvesAndSurfacesOfLineFactorsOnly) {
  std::mt19937_64 rng(3);
  EXPECT_TRUE(kernels::NewtonLanesCover(RandomCurvedCell(CellType::Quad, 3, false, 3, rng).view()));
  EXPECT_TRUE(kernels::NewtonLanesCover(RandomCurvedCell(CellType::Line, 2, true, 2, rng).view()));
  EXPECT_FALSE(kernels::NewtonLanesCover(RandomCurvedCell(CellType::Quad, 2, false, 2, rng).view()));  // a volume
  EXPECT_FALSE(kernels::NewtonLanesCover(RandomCurvedCell(CellType::Tri, 2, false, 3, rng).view()));
  EXPECT_FALSE(kernels::NewtonLanesCover(RandomCurvedCell(CellType::Hex, 2, false, 3, rng).view()));
}

/// A lane that ends Kkt has the map at its ref as closest point and is a
/// KKT point of the squared distance, both judged with the reference's own
/// evaluation: the slope along each free parameter small against |r| |J e_i|,
/// and on a held bound the descent pointing out of the domain.
TEST(NewtonLanes, KktLanesAreKktPointsOfTheReferenceMap) {
  std::mt19937_64 rng(17);
  for (const Combination& c : CoveredCombinations()) {
    SCOPED_TRACE(Name(c));
    const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
    const LaneInput in = MakeInput(cell, 200, rng);
    const LaneRun run = RunLanes(cell, in, Identity(in.count()), kernels::BestLaneIsa());
    const int pd = cell.paramDim(), ad = cell.ambientDim;
    const double size = cell.size();
    int kkt = 0;
    for (int l = 0; l < in.count(); ++l) {
      if (run.outcome[l] != LaneOutcome::Kkt) continue;
      ++kkt;
      double ref[3] = {run.ref[0][l], run.ref[1][l], 0.0};
      ASSERT_TRUE(InReferenceDomain(cell.type, ref, 0.0)) << "lane " << l;
      RefJet jet;
      RefEvaluateJet(cell, ref, 1, &jet);
      double r[3] = {0, 0, 0}, f = 0.0;
      for (int k = 0; k < ad; ++k) {
        r[k] = jet.x[k] - in.coord[k][l];
        f += r[k] * r[k];
        EXPECT_NEAR(run.closest[k][l], jet.x[k], 1e-12 * size) << "lane " << l;
      }
      EXPECT_NEAR(run.squaredDistance[l], f, 1e-12 * (f + size * size)) << "lane " << l;
      for (int i = 0; i < pd; ++i) {
        double slope = 0.0, column2 = 0.0;
        for (int k = 0; k < ad; ++k) {
          slope += r[k] * jet.d1[k][i];
          column2 += jet.d1[k][i] * jet.d1[k][i];
        }
        const double tolerance = 1e-6 * (std::sqrt(f) + size) * std::sqrt(column2) + 1e-12 * size * size;
        if (ref[i] == 0.0) {
          EXPECT_GE(slope, -tolerance) << "lane " << l << ": held at 0 but descends inward";
        } else if (ref[i] == 1.0) {
          EXPECT_LE(slope, tolerance) << "lane " << l << ": held at 1 but descends inward";
        } else {
          EXPECT_LE(std::abs(slope), tolerance) << "lane " << l << ": not stationary along parameter " << i;
        }
      }
    }
    // Most lanes stay in the lanes (a property of speed, not of correctness:
    // the rest is solved by the scalar path).
    EXPECT_GT(kkt, in.count() / 4);
  }
}

/// The same lanes on every instruction set, and in any grouping (alone, in
/// reverse, interleaved with others), give the same answer bit for bit.
TEST(NewtonLanes, SameBitsOnEveryInstructionSetAndInAnyGrouping) {
  std::mt19937_64 rng(29);
  const std::vector<LaneIsa> isas = AvailableIsas();
  for (const Combination& c : CoveredCombinations()) {
    SCOPED_TRACE(Name(c));
    const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
    const LaneInput in = MakeInput(cell, 37, rng);  // not a multiple of any width
    const LaneRun base = RunLanes(cell, in, Identity(in.count()), LaneIsa::Sse2);
    std::vector<int> reversed = Identity(in.count());
    std::reverse(reversed.begin(), reversed.end());
    std::vector<int> shuffled = Identity(in.count());
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    for (LaneIsa isa : isas) {
      for (const std::vector<int>* order : {&reversed, &shuffled}) {
        SCOPED_TRACE(kernels::LaneIsaName(isa));
        const LaneRun run = RunLanes(cell, in, *order, isa);
        for (int l = 0; l < in.count(); ++l) {
          EXPECT_EQ(run.outcome[l], base.outcome[l]) << "lane " << l;
          EXPECT_EQ(run.iterations[l], base.iterations[l]) << "lane " << l;
          for (int i = 0; i < cell.paramDim(); ++i) EXPECT_TRUE(Same(run.ref[i][l], base.ref[i][l])) << "lane " << l;
          if (base.outcome[l] != LaneOutcome::Kkt) continue;
          EXPECT_TRUE(Same(run.squaredDistance[l], base.squaredDistance[l])) << "lane " << l;
          for (int k = 0; k < cell.ambientDim; ++k) {
            EXPECT_TRUE(Same(run.closest[k][l], base.closest[k][l])) << "lane " << l;
          }
        }
      }
    }
    // One lane alone.
    for (int l : {0, 5, 36}) {
      const LaneRun alone = RunLanes(cell, in, {l}, kernels::BestLaneIsa());
      for (int i = 0; i < cell.paramDim(); ++i) EXPECT_TRUE(Same(alone.ref[i][l], base.ref[i][l])) << "lane " << l;
    }
  }
}

/// SolveLane on covered cells: every lane's answer is the global minimum of
/// the brute-force reference, certified, and the same as when its point is
/// solved alone.
TEST(NewtonLanes, SolveLaneMatchesBruteForce) {
  std::mt19937_64 rng(41);
  for (const Combination& c : CoveredCombinations()) {
    SCOPED_TRACE(Name(c));
    for (int cellIndex = 0; cellIndex < 3; ++cellIndex) {
      const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
      const CellSolver solver(cell.view());
      BruteForceReference reference(cell);
      const LaneInput in = MakeInput(cell, 60, rng);
      for (bool warm : {false, true}) {
        QueryLane queries;
        queries.count = in.count();
        for (int k = 0; k < cell.ambientDim; ++k) queries.coord[k] = in.coord[k].data();
        if (warm) {
          for (int i = 0; i < cell.paramDim(); ++i) queries.initialRef[i] = in.start[i].data();
        }
        LaneOutput lanes(in.count());
        auto& [ref, closest, distance, status, iterations, results] = lanes;
        SolveWorkspace ws;
        solver.SolveLane(queries, results, &ws);
        for (int l = 0; l < in.count(); ++l) {
          const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
          const RefClosest expect = reference.Closest(p);
          SCOPED_TRACE("cell " + std::to_string(cellIndex) + " lane " + std::to_string(l) +
                       (warm ? " warm" : " cold") + "\n" + Describe(cell));
          EXPECT_TRUE(status[l] == PointStatus::Converged || status[l] == PointStatus::ProjectedToBoundary)
              << static_cast<int>(status[l]);
          EXPECT_NEAR(distance[l], expect.distance, kRelTol * cell.size());
          double r[3] = {ref[0][l], ref[1][l], 0.0}, x[3] = {0, 0, 0};
          EXPECT_TRUE(InReferenceDomain(cell.type, r, 1e-12));
          RefEvaluate(cell, r, x);
          double d2 = 0.0, off2 = 0.0;
          for (int k = 0; k < cell.ambientDim; ++k) {
            off2 += (x[k] - closest[k][l]) * (x[k] - closest[k][l]);
            d2 += (p[k] - closest[k][l]) * (p[k] - closest[k][l]);
          }
          EXPECT_LE(std::sqrt(off2), kRelTol * cell.size());
          EXPECT_NEAR(std::sqrt(d2), distance[l], kRelTol * cell.size());
          // The same point alone gives the same answer bit for bit.
          QueryLane one;
          one.count = 1;
          double coord[3][1] = {{p[0]}, {p[1]}, {p[2]}}, start[3][1] = {{in.start[0][l]}, {in.start[1][l]}, {0.0}};
          for (int k = 0; k < cell.ambientDim; ++k) one.coord[k] = coord[k];
          if (warm) {
            for (int i = 0; i < cell.paramDim(); ++i) one.initialRef[i] = start[i];
          }
          LaneOutput alone(1);
          solver.SolveLane(one, alone.out, &ws);
          EXPECT_TRUE(Same(alone.distance[0], distance[l]));
          for (int i = 0; i < cell.paramDim(); ++i) EXPECT_TRUE(Same(alone.ref[i][0], ref[i][l]));
        }
      }
    }
  }
}

/// SolveLane with a bound per lane (a neighbour that must beat the best so
/// far): just above the true minimum the answer comes back right; just below
/// it, Farther or a right answer; far below it, Farther (for most lanes at
/// once, by the nets' bounds or the tangent-plane exclusion in lanes).
TEST(NewtonLanes, BoundedLanesAreFartherOnlyWhenTheCellCannotBeatTheBound) {
  std::mt19937_64 rng(79);
  for (const Combination& c : CoveredCombinations()) {
    SCOPED_TRACE(Name(c));
    const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
    const CellSolver solver(cell.view());
    BruteForceReference reference(cell);
    const LaneInput in = MakeInput(cell, 60, rng);
    std::vector<double> expect(in.count());
    for (int l = 0; l < in.count(); ++l) {
      const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
      expect[l] = reference.Closest(p).distance;
    }
    const double size = cell.size();
    // Offsets of the bound from the true distance, in units of the size.
    for (double offset : {1e-6, -1e-6, -0.5}) {
      SCOPED_TRACE("bound offset " + std::to_string(offset));
      std::vector<double> bound2(in.count());
      for (int l = 0; l < in.count(); ++l) {
        const double b = std::max(0.0, expect[l] + offset * size);
        bound2[l] = b * b;
      }
      QueryLane queries;
      queries.count = in.count();
      for (int k = 0; k < cell.ambientDim; ++k) queries.coord[k] = in.coord[k].data();
      for (int i = 0; i < cell.paramDim(); ++i) queries.initialRef[i] = in.start[i].data();
      queries.bound2 = bound2.data();
      LaneOutput lanes(in.count());
      auto& [ref, closest, distance, status, iterations, results] = lanes;
      SolveWorkspace ws;
      solver.SolveLane(queries, results, &ws);
      for (int l = 0; l < in.count(); ++l) {
        SCOPED_TRACE("lane " + std::to_string(l) + "\n" + Describe(cell));
        if (offset > 0) {
          EXPECT_NE(status[l], PointStatus::Farther);
        } else if (expect[l] < 1e-4 * size) {
          continue;  // the bound is 0 or near it: either answer is right
        }
        if (status[l] == PointStatus::Farther) continue;
        EXPECT_TRUE(status[l] == PointStatus::Converged || status[l] == PointStatus::ProjectedToBoundary);
        EXPECT_NEAR(distance[l], expect[l], kRelTol * size);
      }
      if (offset == -0.5) {
        int farther = 0, eligible = 0;
        for (int l = 0; l < in.count(); ++l) {
          if (expect[l] + offset * size <= 0.0) continue;
          ++eligible;
          farther += status[l] == PointStatus::Farther ? 1 : 0;
        }
        EXPECT_EQ(farther, eligible);
      }
    }
  }
}

/// Cells at the ends of the supported range (coordinates near 1e100, a
/// cell 1e-95 across): the lanes answer as the scalar solve does (a lane
/// whose squares leave the normal range hands over to it).
TEST(NewtonLanes, ExtremeScalesAnswerAsTheScalarSolve) {
  std::mt19937_64 rng(89);
  for (double scale : {1e95, 1e-95}) {
    for (const Combination& c : CoveredCombinations()) {
      if (c.degree != 3) continue;
      SCOPED_TRACE(Name(c) + " scale " + std::to_string(scale));
      RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
      LaneInput in = MakeInput(cell, 24, rng);
      for (double& x : cell.points) x *= scale;
      for (auto& axis : in.coord) {
        for (double& x : axis) x *= scale;
      }
      const CellSolver solver(cell.view());
      QueryLane queries;
      queries.count = in.count();
      for (int k = 0; k < cell.ambientDim; ++k) queries.coord[k] = in.coord[k].data();
      LaneOutput lanes(in.count());
      SolveWorkspace ws;
      solver.SolveLane(queries, lanes.out, &ws);
      for (int l = 0; l < in.count(); ++l) {
        const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
        const kernels::CellSolveResult r = solver.Solve(p, nullptr, &ws);
        EXPECT_NEAR(lanes.distance[l], r.distance, kRelTol * solver.size()) << "lane " << l;
      }
    }
  }
}

/// The tangent-plane exclusion in lanes stops a lane only where the scalar
/// test (kernels/tangent_plane.h) at the same iterate holds too, and it does
/// stop lanes whose level is far below their distance.
TEST(NewtonLanes, TangentPlaneExclusionAgreesWithTheScalarTest) {
  std::mt19937_64 rng(83);
  int stopped = 0;
  for (const Combination& c : CoveredCombinations()) {
    if (c.type != CellType::Quad) continue;
    SCOPED_TRACE(Name(c));
    const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
    BruteForceReference reference(cell);
    const LaneInput in = MakeInput(cell, 40, rng);
    std::vector<double> level(in.count());
    for (int l = 0; l < in.count(); ++l) {
      const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
      const double below = std::max(0.0, reference.Closest(p).distance - 0.3 * cell.size());
      level[l] = below * below;
    }
    LaneRun run(in.count());
    NewtonLanes lanes;
    lanes.count = in.count();
    for (int k = 0; k < 3; ++k) {
      lanes.point[k] = in.coord[k].data();
      lanes.closest[k] = run.closest[k].data();
      run.ref[k] = in.start[k];
      lanes.ref[k] = run.ref[k].data();
    }
    lanes.squaredDistance = run.squaredDistance.data();
    lanes.onBoundary = reinterpret_cast<bool*>(run.onBoundary.data());
    lanes.outcome = run.outcome.data();
    lanes.iterations = run.iterations.data();
    lanes.exclusionLevel = level.data();
    kernels::SolveNewtonLanes(cell.view(), cell.size(), lanes);
    for (int l = 0; l < in.count(); ++l) {
      if (run.outcome[l] != LaneOutcome::AboveLevel) continue;
      ++stopped;
      const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
      const double ref[3] = {run.ref[0][l], run.ref[1][l], 0.0};
      kernels::MapJet jet;
      kernels::EvaluateMap(cell.view(), ref, kernels::JetOrder::First, &jet);
      EXPECT_GT(kernels::TangentPlaneLowerBound(cell.shape(), 3, jet, p, ref, level[l], cell.size()), 0.0)
          << "lane " << l;
    }
  }
  EXPECT_GT(stopped, 0);
}

/// The nets' lower bounds for all lanes: the scalar bound's value bit for
/// bit, and never above the squared distance at any sample of the cell.
TEST(NewtonLanes, NetLowerBoundsOfAllLanes) {
  std::mt19937_64 rng(53);
  for (const Combination& c : CoveredCombinations()) {
    SCOPED_TRACE(Name(c));
    const RefCell cell = RandomCurvedCell(c.type, c.degree, c.rational, c.ambientDim, rng);
    const kernels::DistanceNets nets = NetsAroundBoxCenter(cell);
    kernels::NetLanes netLanes;
    netLanes.size = nets.size();
    netLanes.ambientDim = cell.ambientDim;
    netLanes.nn = nets.nn();
    for (int k = 0; k < cell.ambientDim; ++k) netLanes.nw[k] = nets.nw(k);
    netLanes.rational = nets.rational();
    netLanes.ww = nets.ww();
    netLanes.center = nets.center();
    const LaneInput in = MakeInput(cell, 45, rng);
    const double* points[3] = {in.coord[0].data(), in.coord[1].data(), in.coord[2].data()};
    for (LaneIsa isa : AvailableIsas()) {
      std::vector<double> bound(in.count());
      kernels::NetLowerBoundLanes(netLanes, in.count(), points, bound.data(), isa);
      std::vector<double> q(nets.size());
      for (int l = 0; l < in.count(); ++l) {
        const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
        nets.SquaredDistanceNumerator(p, q.data());
        const double scalar = kernels::NetLowerBound(nets.size(), q.data(), nets.rational() ? nets.ww() : nullptr);
        EXPECT_TRUE(Same(bound[l], scalar)) << kernels::LaneIsaName(isa) << " lane " << l;
        // A lower bound of the squared distance over a lattice of the cell
        // (less the nets' rounding).
        const double slack = nets.RoundingSlack(p);
        const int n = cell.paramDim() == 1 ? 64 : 16;
        for (int a = 0; a <= n; ++a) {
          for (int b = 0; b <= (cell.paramDim() == 1 ? 0 : n); ++b) {
            const double ref[2] = {static_cast<double>(a) / n, static_cast<double>(b) / n};
            double x[3] = {0, 0, 0}, d2 = 0.0;
            RefEvaluate(cell, ref, x);
            for (int k = 0; k < cell.ambientDim; ++k) d2 += (x[k] - p[k]) * (x[k] - p[k]);
            ASSERT_LE(bound[l] - slack, d2 * (1 + 1e-12)) << "lane " << l;
          }
        }
      }
    }
  }
}

/// The curvature bounds' certificate for all lanes: the scalar test's
/// answer lane by lane on every instruction set, at levels where it holds
/// and where it fails.
TEST(NewtonLanes, CurvatureCertificateOfAllLanesIsTheScalarOne) {
  std::mt19937_64 rng(67);
  int proved = 0, refused = 0;
  for (const Combination& c : CoveredCombinations()) {
    if (c.degree < 2) continue;
    SCOPED_TRACE(Name(c));
    for (double bend : {0.02, 0.2}) {
      // Mildly curved cells (a B-spline surface's spans) and strongly curved ones.
      RefCell cell = RandomCurvedCell(c.type, c.degree, false, c.ambientDim, rng);
      for (double& x : cell.points) x += bend * (std::uniform_real_distribution<double>(-1, 1)(rng));
      const kernels::DistanceNets nets = NetsAroundBoxCenter(cell);
      const kernels::CurvatureBounds bounds(nets, kernels::HessianStencil::Get(nets.shape()));
      const LaneInput in = MakeInput(cell, 41, rng);
      std::vector<double> level(in.count());
      for (double& v : level) v = std::uniform_real_distribution<double>(0.0, 0.05)(rng) * cell.size() * cell.size();
      const double* points[3] = {in.coord[0].data(), in.coord[1].data(), in.coord[2].data()};
      for (LaneIsa isa : AvailableIsas()) {
        std::vector<char> lanes(in.count());
        kernels::ProvesConvexLanes(bounds, in.count(), points, level.data(), reinterpret_cast<bool*>(lanes.data()),
                                   isa);
        for (int l = 0; l < in.count(); ++l) {
          const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
          const bool scalar = bounds.ProvesConvex(p, level[l]);
          EXPECT_EQ(lanes[l] != 0, scalar) << kernels::LaneIsaName(isa) << " lane " << l;
          (scalar ? proved : refused) += 1;
        }
      }
    }
  }
  // Both answers occur, so the comparison says something.
  EXPECT_GT(proved, 0);
  EXPECT_GT(refused, 0);
}

/// Inside solves of polynomial tetrahedra in lanes: a lane reported inside
/// is inside (the brute-force reference puts the point on the cell, and the
/// answer maps to it); the points made inside are found; the same bits on
/// every instruction set.
TEST(NewtonLanes, InsideSolvesOfTetrahedra) {
  std::mt19937_64 rng(71);
  for (int degree : {2, 3, 4}) {
    SCOPED_TRACE("tet degree " + std::to_string(degree));
    for (int cellIndex = 0; cellIndex < 3; ++cellIndex) {
      const RefCell cell = RandomCurvedCell(CellType::Tet, degree, false, 3, rng);
      ASSERT_TRUE(kernels::InsideLanesCover(cell.view()));
      const CellSolver solver(cell.view());
      BruteForceReference reference(cell);
      const LaneInput in = MakeInput(cell, 50, rng);
      QueryLane queries;
      queries.count = in.count();
      for (int k = 0; k < 3; ++k) queries.coord[k] = in.coord[k].data();
      LaneOutput lanes(in.count());
      auto& [ref, closest, distance, status, iterations, results] = lanes;
      std::vector<char> inside(in.count());
      solver.SolveInsideLane(queries, results, reinterpret_cast<bool*>(inside.data()));
      int made = 0, found = 0;
      for (int l = 0; l < in.count(); ++l) {
        const double p[3] = {in.coord[0][l], in.coord[1][l], in.coord[2][l]};
        SCOPED_TRACE("cell " + std::to_string(cellIndex) + " lane " + std::to_string(l) + "\n" + Describe(cell));
        if (kKinds[l % 10] == QueryKind::Inside) {
          ++made;
          found += inside[l] ? 1 : 0;
        }
        if (!inside[l]) continue;
        EXPECT_LE(reference.Closest(p).distance, kRelTol * cell.size());
        double r[3] = {ref[0][l], ref[1][l], ref[2][l]}, x[3];
        EXPECT_TRUE(InReferenceDomain(cell.type, r, 1e-12));
        RefEvaluate(cell, r, x);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], p[k], kRelTol * cell.size());
        EXPECT_LE(distance[l], 1e-11 * cell.size());
      }
      EXPECT_GE(found, made * 9 / 10) << "of the points made inside the cell";
    }
  }
}

TEST(NewtonLanes, InsideSolvesGiveTheSameBitsOnEveryInstructionSet) {
  std::mt19937_64 rng(73);
  for (int degree : {2, 3, 5}) {
    const RefCell cell = RandomCurvedCell(CellType::Tet, degree, false, 3, rng);
    const CellSolver solver(cell.view());
    const LaneInput in = MakeInput(cell, 37, rng);
    std::vector<std::vector<double>> runs;
    for (LaneIsa isa : AvailableIsas()) {
      std::vector<double> ref[3], closest[3], f(in.count());
      std::vector<kernels::InsideOutcome> outcome(in.count());
      std::vector<int> iterations(in.count());
      kernels::InsideLanes lanes;
      lanes.count = in.count();
      for (int k = 0; k < 3; ++k) {
        ref[k] = in.start[k];
        // Starts inside the domain, as SolveInsideLane gives them.
        for (double& v : ref[k]) v = 0.05 + 0.2 * v;
        closest[k].resize(in.count());
        lanes.point[k] = in.coord[k].data();
        lanes.ref[k] = ref[k].data();
        lanes.closest[k] = closest[k].data();
      }
      lanes.squaredDistance = f.data();
      lanes.outcome = outcome.data();
      lanes.iterations = iterations.data();
      kernels::SolveInsideLanes(cell.view(), cell.size(), lanes, isa);
      std::vector<double> flat;
      for (int l = 0; l < in.count(); ++l) {
        flat.push_back(static_cast<double>(outcome[l]));
        flat.push_back(iterations[l]);
        for (int k = 0; k < 3; ++k) flat.push_back(ref[k][l]);
        if (outcome[l] != kernels::InsideOutcome::Handover) flat.push_back(f[l]);
      }
      runs.push_back(flat);
    }
    for (std::size_t r = 1; r < runs.size(); ++r) {
      ASSERT_EQ(runs[r].size(), runs[0].size());
      for (std::size_t i = 0; i < runs[0].size(); ++i) EXPECT_TRUE(Same(runs[r][i], runs[0][i])) << i;
    }
  }
}

}  // namespace
}  // namespace invmap::testing
