// The orthogonal barycentric basis of 7.3.1.1 and its tensor-product padding
// (7.3.1.2): orthonormal in barycentric space, spanning exactly the free
// face, so the residual norm is the norm of the projected gradient whatever
// the active set: continuous when a constraint is added or removed.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>

#include "kernels/active_set.h"

namespace {

using invmap::kernels::ActiveSet;
using invmap::kernels::BuildFaceBasis;
using invmap::kernels::CellShape;
using invmap::kernels::CellType;
using invmap::kernels::FaceBasis;
using invmap::kernels::SnapToDomain;

/// A basis column in full barycentric coordinates of every factor: for a
/// factor with free coordinates s, lambda_0 = -sum(ds), lambda_i = ds_i.
Eigen::VectorXd Barycentric(const CellShape& shape, const FaceBasis& basis, int column) {
  int size = 0;
  for (int f = 0; f < shape.numFactors(); ++f) size += shape.factor(f).dim + 1;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(size);
  int at = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const auto& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      v[at + 1 + i] = basis.t[fac.offset + i][column];
      v[at] -= basis.t[fac.offset + i][column];
    }
    at += fac.dim + 1;
  }
  return v;
}

/// Independent projector onto the face's tangent space in barycentric
/// coordinates: vectors with zero sum per factor and zero enforced entries.
Eigen::MatrixXd FaceProjector(const CellShape& shape, const ActiveSet& active) {
  int size = 0;
  for (int f = 0; f < shape.numFactors(); ++f) size += shape.factor(f).dim + 1;
  std::vector<Eigen::VectorXd> constraints;
  int at = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const int n = shape.factor(f).dim + 1;
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(size);
    sum.segment(at, n).setOnes();
    constraints.push_back(sum);
    for (int k = 0; k < n; ++k) {
      if (active.enforced[f] & (1u << k)) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(size);
        e[at + k] = 1.0;
        constraints.push_back(e);
      }
    }
    at += n;
  }
  Eigen::MatrixXd c(static_cast<int>(constraints.size()), size);
  for (std::size_t r = 0; r < constraints.size(); ++r) c.row(static_cast<int>(r)) = constraints[r].transpose();
  const Eigen::MatrixXd kernel = Eigen::FullPivLU<Eigen::MatrixXd>(c).kernel();
  if (kernel.cols() == 0 || (kernel.cols() == 1 && kernel.norm() == 0.0)) return Eigen::MatrixXd::Zero(size, size);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(kernel);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(size, kernel.cols());
  return q * q.transpose();
}

/// Every active set of a shape that leaves each factor at least one free coordinate.
std::vector<ActiveSet> AllActiveSets(const CellShape& shape) {
  std::vector<ActiveSet> sets(1);
  for (int f = 0; f < shape.numFactors(); ++f) {
    const unsigned all = (1u << (shape.factor(f).dim + 1)) - 1;
    std::vector<ActiveSet> next;
    for (const ActiveSet& s : sets) {
      for (unsigned mask = 0; mask < all; ++mask) {
        ActiveSet t = s;
        t.enforced[f] = mask;
        next.push_back(t);
      }
    }
    sets.swap(next);
  }
  return sets;
}

class FaceBasisTest : public ::testing::TestWithParam<CellType> {};

TEST_P(FaceBasisTest, OrthonormalAndSpanningTheFreeFace) {
  const CellShape shape(GetParam(), {2, 2, 2});
  for (const ActiveSet& active : AllActiveSets(shape)) {
    FaceBasis basis;
    BuildFaceBasis(shape, active, &basis);
    const Eigen::MatrixXd projector = FaceProjector(shape, active);
    const int rank = static_cast<int>(std::lround(projector.trace()));
    ASSERT_EQ(basis.columns, rank);
    for (int a = 0; a < basis.columns; ++a) {
      const Eigen::VectorXd va = Barycentric(shape, basis, a);
      // In the face: the projector leaves it unchanged.
      EXPECT_LT((projector * va - va).norm(), 1e-14);
      for (int b = 0; b < basis.columns; ++b) {
        EXPECT_NEAR(va.dot(Barycentric(shape, basis, b)), a == b ? 1.0 : 0.0, 1e-14);
      }
    }
  }
}

TEST_P(FaceBasisTest, ResidualNormIsTheProjectedGradientNormForEveryActiveSet) {
  const CellShape shape(GetParam(), {2, 2, 2});
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    // A gradient with respect to the barycentric coordinates; the solver
    // sees its components along the free parameters.
    int size = 0;
    for (int f = 0; f < shape.numFactors(); ++f) size += shape.factor(f).dim + 1;
    Eigen::VectorXd gLambda(size);
    for (int i = 0; i < size; ++i) gLambda[i] = normal(rng);
    double gParam[3] = {0, 0, 0};
    int at = 0;
    for (int f = 0; f < shape.numFactors(); ++f) {
      const auto& fac = shape.factor(f);
      for (int i = 0; i < fac.dim; ++i) gParam[fac.offset + i] = gLambda[at + 1 + i] - gLambda[at];
      at += fac.dim + 1;
    }
    for (const ActiveSet& active : AllActiveSets(shape)) {
      FaceBasis basis;
      BuildFaceBasis(shape, active, &basis);
      double residual2 = 0.0;
      for (int c = 0; c < basis.columns; ++c) {
        double r = 0.0;
        for (int i = 0; i < shape.paramDim(); ++i) r += basis.t[i][c] * gParam[i];
        residual2 += r * r;
      }
      const double projected = (FaceProjector(shape, active) * gLambda).norm();
      // Basis-independent: adding a constraint removes exactly the component
      // along the dropped direction, so the norm changes continuously.
      EXPECT_NEAR(std::sqrt(residual2), projected, 1e-12 * (1.0 + projected));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllCellTypes, FaceBasisTest,
                         ::testing::Values(CellType::Line, CellType::Tri, CellType::Quad, CellType::Tet,
                                           CellType::Hex, CellType::Wedge));

/// x[0] + .. + x[n - 1] - 1 in quadruple precision: exact for the test's
/// coordinates (doubles in [1e-3, 1], whose sum needs at most 70 bits).
__float128 ExcessOverOne(const double* x, int n) {
  __float128 sum = -1;
  for (int i = 0; i < n; ++i) sum += x[i];
  return sum;
}

TEST(SnapToDomain, PutsPointsOfTheDomainUpToRoundingExactlyInIt) {
  // Points on a simplex factor's hypotenuse face, written as the solves
  // write them (each coordinate rounded on its own), often sum to 1 plus an
  // ulp; a coordinate of a point on another face comes out as -1e-17.
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(1e-3, 1.0);
  int overBefore = 0;
  for (const CellType type : {CellType::Tri, CellType::Tet, CellType::Wedge}) {
    const int dims[2] = {type == CellType::Tet ? 3 : 2, type == CellType::Wedge ? 1 : 0};
    for (int i = 0; i < 2000; ++i) {
      double ref[3] = {unit(rng), unit(rng), unit(rng)};
      double sum = 0.0;
      for (int k = 0; k < dims[0]; ++k) sum += ref[k];
      for (int k = 0; k < dims[0]; ++k) ref[k] /= sum;  // on the face, up to rounding
      if (dims[1] == 1) ref[2] = i % 2 ? -1e-17 : 1.0 + 2e-16;
      if (i % 7 == 0) ref[0] = -5.551115123125783e-17;
      const double before[3] = {ref[0], ref[1], ref[2]};
      overBefore += ExcessOverOne(ref, dims[0]) > 0;
      SnapToDomain(type, ref);
      for (int k = 0; k < dims[0] + dims[1]; ++k) {
        EXPECT_GE(ref[k], 0.0);
        EXPECT_LE(ref[k], 1.0);
        // Moved by rounding only.
        EXPECT_NEAR(ref[k], std::clamp(before[k], 0.0, 1.0), 4e-16);
      }
      EXPECT_LE(ExcessOverOne(ref, dims[0]), 0) << "type " << static_cast<int>(type) << ", point " << i;
    }
  }
  // The case the snap exists for did occur.
  EXPECT_GT(overBefore, 100);
}

}  // namespace
