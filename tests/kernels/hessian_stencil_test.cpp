// The convexity test of the cell search (HessianStencil::IsConvex in
// kernels/bernstein_net.h): a net it accepts must have a positive definite
// Hessian everywhere on the domain, checked by finite differences of an
// evaluation written from the Bernstein definition; and the nets whose
// diagonal second derivatives vary a lot along the cell, which the interval
// test alone rejects, are accepted.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/bernstein_net.h"
#include "kernels/simplex_index.h"
#include "tests/support/finite_differences.h"
#include "tests/support/tensor_net.h"

namespace {

using invmap::kernels::CellShape;
using invmap::kernels::CellType;
using invmap::kernels::HessianStencil;
using invmap::kernels::MostBentLine;
using invmap::kernels::NetNoise;
using invmap::kernels::SimplexIndex;
using invmap::kernels::SteepestDifferenceEdge;
using invmap::kernels::SteepestRatioEdge;
using invmap::testing::FiniteDifferenceHessian;
using invmap::testing::ForGrid;
using invmap::testing::Net;
using invmap::testing::SmallestEigenvalue;

/// Net with coefficient (i, j, k) = a[i] + b[j] + c[k] + cross (i / p)(j / q)
/// + cross02 (i / p)(k / r) + cross12 (j / q)(k / r): the polynomial a(t_0) +
/// b(t_1) + c(t_2) + cross t_0 t_1 + cross02 t_0 t_2 + cross12 t_1 t_2.
Net SeparablePlusCross(int dims, const std::vector<double>* terms, double cross, double cross02 = 0.0,
                       double cross12 = 0.0) {
  Net net{dims, {0, 0, 0}, {}};
  for (int d = 0; d < dims; ++d) net.deg[d] = static_cast<int>(terms[d].size()) - 1;
  for (int k = 0; k < net.Size(2); ++k) {
    for (int j = 0; j < net.Size(1); ++j) {
      for (int i = 0; i < net.Size(0); ++i) {
        double v = terms[0][i] + terms[1][j] + (dims > 2 ? terms[2][k] : 0.0);
        const double t[3] = {static_cast<double>(i) / net.deg[0], static_cast<double>(j) / net.deg[1],
                             dims > 2 ? static_cast<double>(k) / net.deg[2] : 0.0};
        v += cross * t[0] * t[1] + cross02 * t[0] * t[2] + cross12 * t[1] * t[2];
        net.c.push_back(v);
      }
    }
  }
  return net;
}

TEST(HessianStencil, VaryingDiagonalIsConvex) {
  // a(t_0) with second derivative 0.12 .. 9.72 along the cell, b = t_1^2
  // (second derivative 2) and a small mixed term: the intervals' midpoint
  // matrix diag(4.92, 2) is within their radius 4.8 of singular, but scaled
  // by the diagonal the mixed entry is far below one.
  const std::vector<double> terms[2] = {{0.0, 0.0, 0.01, 0.1, 1.0}, {0.0, 0.0, 1.0}};
  const Net net = SeparablePlusCross(2, terms, 0.1);
  EXPECT_TRUE(HessianStencil::Get(net.Shape()).IsConvex(net.c.data()));
  // A mixed term as large as the diagonal allows no proof (and the function
  // is not convex where a'' is small: 0.12 * 2 < 1.5^2).
  const Net saddle = SeparablePlusCross(2, terms, 1.5);
  EXPECT_FALSE(HessianStencil::Get(saddle.Shape()).IsConvex(saddle.c.data()));
}

TEST(HessianStencil, HugeIndefiniteHessianIsRejected) {
  // H = [[2 s, 10 s], [10 s, 2 s]] is indefinite for every s > 0; with s
  // large the product of the diagonal bounds overflows, which must not
  // make the mixed entry look small.
  for (const double scale : {1.0, 1e100, 1e155, 1e200}) {
    const std::vector<double> terms[2] = {{0.0, 0.0, scale}, {0.0, 0.0, scale}};
    const Net net = SeparablePlusCross(2, terms, 10.0 * scale);
    EXPECT_FALSE(HessianStencil::Get(net.Shape()).IsConvex(net.c.data())) << "scale " << scale;
  }
}

TEST(HessianStencil, ConcaveDirectionIsRejected) {
  const std::vector<double> terms[3] = {{0.0, 0.0, 1.0}, {0.0, 0.5, 0.0}, {0.0, 0.0, 1.0}};
  for (const int dims : {2, 3}) {
    const Net net = SeparablePlusCross(dims, terms, 0.0);
    EXPECT_FALSE(HessianStencil::Get(net.Shape()).IsConvex(net.c.data())) << dims << "D";
  }
}

TEST(HessianStencil, AcceptedNetsAreConvexEverywhere) {
  std::mt19937 rng(20261124);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int dims = trial % 3 == 0 ? 3 : 2;
    std::uniform_int_distribution<int> degree(2, dims == 2 ? 6 : 3);
    // Per direction a convex term whose curvature grows along the cell by a
    // random factor, plus noise and a random mixed term: some nets pass
    // either test, some only the scaled one, some neither.
    std::vector<double> terms[3];
    for (int d = 0; d < dims; ++d) {
      const int p = degree(rng);
      const double growth = 1.0 + 30.0 * unit(rng);
      double slope = -unit(rng), value = 0.0, step = 0.05 + unit(rng);
      for (int i = 0; i <= p; ++i) {
        terms[d].push_back(value + 0.05 * (unit(rng) - 0.5));
        value += slope;
        slope += step;
        step *= std::pow(growth, 1.0 / p);
      }
    }
    const Net net = SeparablePlusCross(dims, terms, 8.0 * (unit(rng) - 0.5), 8.0 * (unit(rng) - 0.5),
                                       8.0 * (unit(rng) - 0.5));
    if (!HessianStencil::Get(net.Shape()).IsConvex(net.c.data())) {
      ++rejected;
      continue;
    }
    ++accepted;
    const double h = 1e-3;
    ForGrid(dims, dims == 2 ? 11 : 5, [&](const double* grid) {
      double t[3] = {0, 0, 0};
      for (int d = 0; d < dims; ++d) t[d] = h + (1 - 2 * h) * grid[d];
      ASSERT_GT(SmallestEigenvalue(FiniteDifferenceHessian(net, net.dims, t, h)), -1e-5) << "trial " << trial;
    });
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 100);
}

TEST(HessianStencil, ConvexityWithinTheRoundingIsNotProved) {
  // A curve net (degree 4) whose second differences are 1e-3 (rows of
  // 12e-3 with the factor p (p - 1)), convex; its rounding is scale * weights:
  // a light coefficient next to heavy ones, as in a rational cell's WW net
  // spanning 1e14. Rows that gather more rounding than their value (24e14 *
  // 1e-16 here) prove nothing; with uniform light weights they do.
  std::vector<double> net;
  for (int i = 0; i <= 4; ++i) net.push_back(0.0005 * i * i);
  const HessianStencil& stencil = HessianStencil::Get(CellShape(CellType::Line, {4, 0, 0}));
  ASSERT_TRUE(stencil.IsConvex(net.data()));
  const std::vector<double> light(5, 1.0);
  EXPECT_TRUE(stencil.IsConvex(net.data(), NetNoise{light.data(), 1e-16}));
  const std::vector<double> unbalanced = {1.0, 1.0, 1e14, 1.0, 1.0};
  EXPECT_FALSE(stencil.IsConvex(net.data(), NetNoise{unbalanced.data(), 1e-16}));
}

TEST(SteepestRatioEdge, FindsTheDirectionWhereWeightsChangeMost) {
  // A quad net of degrees (2, 2): ratios of 3 along u, 100 along v.
  const CellShape quad(CellType::Quad, {2, 2, 0});
  std::vector<double> w;
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 2; ++i) w.push_back(std::pow(3.0, i) * std::pow(100.0, j));
  }
  int factor = -1, vi = -1, vj = -1;
  EXPECT_DOUBLE_EQ(SteepestRatioEdge(quad, w.data(), &factor, &vi, &vj), 100.0);
  EXPECT_EQ(factor, 1);
  EXPECT_EQ(vi, 0);
  EXPECT_EQ(vj, 1);
  // A quadratic triangle net, positions (a1, a2) = (0,0) (1,0) (2,0) (0,1)
  // (1,1) (0,2): only the coefficient at (1,1) is heavy; its neighbours
  // across edge (1, 2) of the simplex are (2,0) and (0,2), across (0, 1)
  // and (0, 2) the others; the largest jump decides.
  const CellShape tri(CellType::Tri, {2, 0, 0});
  const SimplexIndex& index = SimplexIndex::Get(2, 2);
  std::vector<double> tw(6, 1.0);
  tw[index.Position(1, 1)] = 50.0;
  tw[index.Position(2, 0)] = 0.5;  // vertex 1: the (1,1)-(2,0) jump, along edge (1, 2), is the largest
  EXPECT_DOUBLE_EQ(SteepestRatioEdge(tri, tw.data(), &factor, &vi, &vj), 100.0);
  EXPECT_EQ(factor, 0);
  EXPECT_EQ(vi, 1);
  EXPECT_EQ(vj, 2);
  // Constant weights: ratio 1.
  const std::vector<double> flat(9, 2.0);
  EXPECT_DOUBLE_EQ(SteepestRatioEdge(quad, flat.data(), &factor, &vi, &vj), 1.0);
  // Differences rather than ratios: steps of 5 along u beat the 1, 2 along v.
  std::vector<double> values;
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 2; ++i) values.push_back(5.0 * i + j * j);
  }
  EXPECT_DOUBLE_EQ(SteepestDifferenceEdge(quad, values.data(), &factor, &vi, &vj), 5.0);
  EXPECT_EQ(factor, 0);
  values[8] += 10.0;  // (2, 2): now 13 above (2, 1) along v, 15 above (1, 2) along u
  EXPECT_DOUBLE_EQ(SteepestDifferenceEdge(quad, values.data(), &factor, &vi, &vj), 15.0);
  EXPECT_EQ(factor, 0);
}


TEST(MostBentLine, FindsTheLineWhereTheNetBendsMost) {
  int factor = -1;
  // A quad net of degrees (2, 2), linear along u and 3 j^2 along v: second
  // differences 0 along u, 6 along v.
  const CellShape quad(CellType::Quad, {2, 2, 0});
  std::vector<double> q;
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 2; ++i) q.push_back(5.0 * i + 3.0 * j * j);
  }
  EXPECT_DOUBLE_EQ(MostBentLine(quad, q.data(), nullptr, 0.0, &factor), 6.0);
  EXPECT_EQ(factor, 1);
  // q - level ww: a net that is 7 ww plus a linear one bends nowhere at
  // level 7, though q and ww alone bend along u.
  std::vector<double> ww, shifted;
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 2; ++i) {
      ww.push_back(1.0 + i * i);
      shifted.push_back(7.0 * ww.back() + 2.0 * i - j);
    }
  }
  EXPECT_DOUBLE_EQ(MostBentLine(quad, shifted.data(), ww.data(), 7.0, &factor), 0.0);
  EXPECT_DOUBLE_EQ(MostBentLine(quad, shifted.data(), ww.data(), 0.0, &factor), 14.0);
  EXPECT_EQ(factor, 0);
  // A hex net of degrees (2, 2, 2): k^2 along the third line only.
  const CellShape hex(CellType::Hex, {2, 2, 2});
  std::vector<double> h;
  for (int k = 0; k <= 2; ++k) {
    for (int c = 0; c < 9; ++c) h.push_back(c + 4.0 * k * k);
  }
  EXPECT_DOUBLE_EQ(MostBentLine(hex, h.data(), nullptr, 0.0, &factor), 8.0);
  EXPECT_EQ(factor, 2);
  // A linear net bends nowhere: 0, and factor 0.
  const std::vector<double> plane = {0.0, 1.0, 2.0, 1.0, 2.0, 3.0, 2.0, 3.0, 4.0};
  EXPECT_DOUBLE_EQ(MostBentLine(quad, plane.data(), nullptr, 0.0, &factor), 0.0);
  EXPECT_EQ(factor, 0);
}

}  // namespace
