// kernels::EvaluateMap against the reference's multinomial formula: value,
// first and second derivatives of every cell type, for uniform degrees (which
// cubic quads and hexes evaluate with loops of constant length)
// and mixed ones, polynomial and rational, in 2D and 3D, inside and outside
// the reference domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/cell_map.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellType;
using invmap::kernels::EvaluateMap;
using invmap::kernels::JetOrder;
using invmap::kernels::MapJet;
using invmap::testing::Describe;
using invmap::testing::ParamDimOf;
using invmap::testing::RandomCurvedCell;
using invmap::testing::RandomRefPoint;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluateJet;
using invmap::testing::RefJet;

constexpr CellType kAllTypes[] = {CellType::Line, CellType::Tri, CellType::Quad,
                                  CellType::Tet,  CellType::Hex, CellType::Wedge};

/// Degree combinations per factor (docs/formats.md order): every uniform degree
/// from 1 to 8 (the highest the formats allow), and mixed ones, which take
/// the general contraction.
std::vector<std::array<int, 3>> DegreeCases(CellType type) {
  std::vector<std::array<int, 3>> cases;
  for (int p = 1; p <= 8; ++p) cases.push_back({p, p, p});
  if (type == CellType::Quad || type == CellType::Hex || type == CellType::Wedge) {
    cases.push_back({3, 2, 3});
    cases.push_back({2, 3, 1});
    cases.push_back({8, 5, 7});
  }
  return cases;
}

/// Compares the jet of `cell` at `ref` to the reference's, up to `order`.
void ExpectJetMatches(const RefCell& cell, const double* ref, JetOrder order, int degree) {
  const int pd = ParamDimOf(cell.type);
  RefJet expected;
  RefEvaluateJet(cell, ref, 2, &expected);
  MapJet jet;
  EvaluateMap(cell.view(), ref, order, &jet);
  // Derivatives grow with the degree: each one brings a factor of about p.
  // Degrees 5 to 8 of rational cells reach values of 1e4 to 1e6 outside the
  // domain (near the weights' zeros), whose rounding is relative to them;
  // degrees 1 to 4 keep the tolerance of the cell's size alone.
  const auto tolerance = [&](double value) {
    const double scale = degree <= 4 ? cell.size() : std::max(cell.size(), std::abs(value));
    return 1e-12 * scale * (1 + degree) * (1 + degree);
  };
  for (int k = 0; k < cell.ambientDim; ++k) {
    EXPECT_NEAR(jet.x[k], expected.x[k], tolerance(expected.x[k])) << "x[" << k << "]";
    if (order == JetOrder::Value) continue;
    for (int i = 0; i < pd; ++i) {
      EXPECT_NEAR(jet.d1[k][i], expected.d1[k][i], tolerance(expected.d1[k][i])) << "d1[" << k << "][" << i << "]";
      if (order != JetOrder::Second) continue;
      for (int j = 0; j < pd; ++j) {
        EXPECT_NEAR(jet.d2[k][i][j], expected.d2[k][i][j], tolerance(expected.d2[k][i][j]))
            << "d2[" << k << "][" << i << "][" << j << "]";
      }
    }
  }
}

TEST(EvaluateMap, MatchesTheReferenceJetOfEveryCellTypeAndDegree) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> outward(-0.3, 0.3);
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (const std::array<int, 3>& degrees : DegreeCases(type)) {
      const int degree = *std::max_element(degrees.begin(), degrees.end());
      for (int ambient = std::max(2, pd); ambient <= 3; ++ambient) {
        for (bool rational : {false, true}) {
          const RefCell cell = RandomCurvedCell(type, degrees, rational, ambient, rng);
          SCOPED_TRACE(Describe(cell));
          for (int trial = 0; trial < 4; ++trial) {
            std::array<double, 3> ref = RandomRefPoint(type, rng);
            // Half the points outside the domain: the polynomial extension.
            if (trial % 2 == 1) {
              for (int i = 0; i < pd; ++i) ref[i] += outward(rng);
            }
            for (JetOrder order : {JetOrder::Value, JetOrder::First, JetOrder::Second}) {
              ExpectJetMatches(cell, ref.data(), order, degree);
            }
          }
        }
      }
    }
  }
}

}  // namespace
