// The lower bound a pair solve proves (PairSolveResult::lowerBound), which
// the trackers keep from one pose to the next: for random pairs of curved
// cells (curves, triangles, quads; polynomial and rational; 2D and 3D)
// under random rigid motions, solved and probed under bounds below, near
// and beyond their distance, it never exceeds the least distance of dense
// samples of both cells from the tests' own evaluator
// (tests/support/reference_cell.h), nor the certified distance of an
// unbounded solve; and under a bound below the distance it reaches that
// bound (it proves what the caller asked).
#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "kernels/pair_search.h"
#include "tests/distance/pair_case.h"
#include "tests/support/reference_cell.h"

namespace invmap::kernels {
namespace {

using testing::RandomCurvedCell;

TEST(PairLowerBound, NeverAboveTheDistanceOfTheCells) {
  const CellType types[] = {CellType::Line, CellType::Tri, CellType::Quad};
  PairWorkspace ws;
  int checked = 0, reached = 0, below = 0;
  for (const int ambientDim : {2, 3}) {
    for (const CellType ta : types) {
      for (const CellType tb : types) {
        for (const bool rational : {false, true}) {
          std::mt19937_64 rng(5 + 7 * ambientDim + 13 * static_cast<int>(ta) + 17 * static_cast<int>(tb) + rational);
          std::uniform_int_distribution<int> degree(1, 3);
          for (int trial = 0; trial < 3; ++trial) {
            PairCase pair;
            pair.cell[0] = RandomCurvedCell(ta, degree(rng), rational, ambientDim, rng);
            pair.cell[1] = RandomCurvedCell(tb, degree(rng), !rational, ambientDim, rng);
            for (int s = 0; s < 2; ++s) {
              BuildSide(pair.cell[s], RandomMotion(rng, ambientDim), &pair.nets[s], &pair.side[s]);
            }
            // The least distance of the samples: at least the cells' distance.
            const auto pa = Samples(pair.cell[0], pair.side[0].motion, 20);
            const auto pb = Samples(pair.cell[1], pair.side[1].motion, 20);
            double sampled = std::numeric_limits<double>::infinity();
            for (const auto& x : pa) {
              for (const auto& y : pb) sampled = std::min(sampled, (x - y).norm());
            }
            const PairSolveResult exact = SolveCellPair(pair.side[0], pair.side[1], nullptr, nullptr, &ws);
            const double size = pair.side[0].size + pair.side[1].size;
            const double slack = 1e-9 * size;
            EXPECT_LE(exact.lowerBound, sampled + slack);
            EXPECT_LE(exact.lowerBound, exact.distance + slack);
            for (const double factor : {0.0, 0.5, 0.9, 0.999, 1.001, 1.5, 4.0}) {
              const double bound = factor * exact.distance + (factor == 0.0 ? 0.0 : 1e-12);
              const double bound2 = bound * bound;
              const PairSolveResult solved = SolveCellPair(pair.side[0], pair.side[1], nullptr, nullptr, &ws, bound2);
              const PairSolveResult probed = ProbeCellPair(pair.side[0], pair.side[1], &ws, bound2);
              SCOPED_TRACE("bound factor " + std::to_string(factor));
              for (const PairSolveResult* r : {&solved, &probed}) {
                EXPECT_LE(r->lowerBound, sampled + slack);
                EXPECT_LE(r->lowerBound, exact.distance + slack);
                ++checked;
              }
              // A certified search that finds nothing nearer than the bound proves the bound.
              if (solved.status == PairStatus::Farther) {
                ++below;
                if (solved.lowerBound >= bound * (1.0 - 1e-6) - slack) ++reached;
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(below, 50);
  EXPECT_EQ(reached, below) << reached << " of " << below << " searches beyond their bound proved it";
}

}  // namespace
}  // namespace invmap::kernels
