// The Taylor-model bounds of the pair search (kernels/pair_taylor_bounds.h):
// for random pairs of curved cells (curves, triangles, quads; polynomial
// and rational; 2D and 3D) under random rigid motions, on random
// subdomains reached by the search's own splits, every Hessian entry along
// a random basis of f = |x - y|^2, computed at
// dense samples of the subdomains from the tests' own evaluator
// (tests/support/reference_cell.h), lies within the bounds; and the bounds
// shrink as the subdomains do (they are of use to the certificate).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <random>
#include <vector>

#include "kernels/pair_nets.h"
#include "kernels/pair_taylor_bounds.h"
#include "tests/distance/pair_case.h"
#include "tests/support/reference_cell.h"

namespace invmap::kernels {
namespace {

using testing::RandomCurvedCell;
using testing::RefCell;
using testing::RefEvaluateJet;
using testing::RefJet;

/// One side's subdomain as the search keeps it: the vertices of every
/// factor's sub-simplex in reference coordinates (the search's local
/// coordinates t map to ref = V0 + sum_k t_k (V_k - V0)).
struct Subdomain {
  double vertex[kMaxFactors][4][3] = {};
};

Subdomain Root(const CellShape& shape) {
  Subdomain s;
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int v = 1; v <= shape.factor(f).dim; ++v) s.vertex[f][v][v - 1] = 1.0;
  }
  return s;
}

/// Reference coordinates of local coordinates t, and the Jacobian E (d ref / d t).
void ToReference(const CellShape& shape, const Subdomain& s, const double* t, double* ref, Eigen::Matrix3d* e) {
  e->setZero();
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      double v = s.vertex[f][0][i];
      for (int k = 1; k <= fac.dim; ++k) {
        const double edge = s.vertex[f][k][i] - s.vertex[f][0][i];
        v += t[fac.offset + k - 1] * edge;
        (*e)(fac.offset + i, fac.offset + k - 1) = edge;
      }
      ref[fac.offset + i] = v;
    }
  }
}

/// Random local coordinates in the unit factors (boxes and simplices).
void RandomLocal(const CellShape& shape, std::mt19937_64& rng, double* t) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double sum = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      // Corners now and then: the bounds must hold on the boundary too.
      t[fac.offset + i] = u(rng) < 0.1 ? 0.0 : u(rng);
      sum += t[fac.offset + i];
    }
    if (sum > 1.0 && fac.dim > 1) {
      for (int i = 0; i < fac.dim; ++i) t[fac.offset + i] /= sum;
    }
  }
}

/// The exact Hessian of f in the local coordinates of both
/// subdomains at local coordinates (tA, tB), from the reference evaluator.
void ExactHessian(const PairCase& pair, const Subdomain* sub, const double* tA, const double* tB,
                  Eigen::MatrixXd* hessian) {
  const int pa = pair.cell[0].paramDim(), pb = pair.cell[1].paramDim(), n = pa + pb;
  const int ad = pair.cell[0].ambientDim;
  Eigen::Vector3d x[2];
  Eigen::MatrixXd jacobian[2];
  std::vector<Eigen::MatrixXd> second[2];
  for (int s = 0; s < 2; ++s) {
    const CellShape shape = pair.cell[s].shape();
    const int pd = shape.paramDim();
    double ref[3];
    Eigen::Matrix3d e;
    ToReference(shape, sub[s], s == 0 ? tA : tB, ref, &e);
    RefJet jet;
    RefEvaluateJet(pair.cell[s], ref, 2, &jet);
    Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r(i, j) = pair.side[s].motion.rotation[i][j];
    }
    const Eigen::Vector3d local(jet.x[0], jet.x[1], ad > 2 ? jet.x[2] : 0.0);
    x[s] = r * local + Eigen::Vector3d(pair.side[s].motion.translation);
    Eigen::MatrixXd j(3, pd);
    j.setZero();
    for (int k = 0; k < ad; ++k) {
      for (int p = 0; p < pd; ++p) j(k, p) = jet.d1[k][p];
    }
    const Eigen::MatrixXd ePart = e.topLeftCorner(pd, pd);
    jacobian[s] = r * j * ePart;
    second[s].assign(3, Eigen::MatrixXd::Zero(pd, pd));
    for (int k = 0; k < 3; ++k) {
      Eigen::MatrixXd h = Eigen::MatrixXd::Zero(pd, pd);
      for (int l = 0; l < ad; ++l) {
        Eigen::MatrixXd hl(pd, pd);
        for (int p = 0; p < pd; ++p) {
          for (int q = 0; q < pd; ++q) hl(p, q) = jet.d2[l][p][q];
        }
        h += r(k, l) * hl;
      }
      second[s][k] = ePart.transpose() * h * ePart;
    }
  }
  const Eigen::Vector3d z = x[0] - x[1];
  Eigen::MatrixXd j(3, n);
  j.leftCols(pa) = jacobian[0];
  j.rightCols(pb) = -jacobian[1];
  *hessian = 2.0 * j.transpose() * j;
  for (int k = 0; k < 3; ++k) {
    hessian->topLeftCorner(pa, pa) += 2.0 * z[k] * second[0][k];
    hessian->bottomRightCorner(pb, pb) -= 2.0 * z[k] * second[1][k];
  }
}

TEST(PairTaylorBounds, HoldEveryHessianOfTheSubdomains) {
  const CellType types[] = {CellType::Line, CellType::Tri, CellType::Quad};
  int checked = 0, tight = 0, deep = 0;
  for (const int ambientDim : {2, 3}) {
    for (const CellType ta : types) {
      for (const CellType tb : types) {
        for (const bool rational : {false, true}) {
          std::mt19937_64 rng(11 + 7 * ambientDim + 13 * static_cast<int>(ta) + 17 * static_cast<int>(tb) + rational);
          std::uniform_int_distribution<int> degree(1, 3);
          PairCase pair;
          pair.cell[0] = RandomCurvedCell(ta, degree(rng), rational, ambientDim, rng);
          pair.cell[1] = RandomCurvedCell(tb, degree(rng), !rational, ambientDim, rng);
          for (int s = 0; s < 2; ++s) BuildSide(pair.cell[s], RandomMotion(rng, ambientDim), &pair.nets[s], &pair.side[s]);
          const PairNets nets(pair.side[0], pair.side[1]);
          const int n = pair.cell[0].paramDim() + pair.cell[1].paramDim();
          std::vector<double> a(nets.sideLength(0)), b(nets.sideLength(1));
          nets.BuildRoot(a.data(), b.data());
          Subdomain sub[2] = {Root(nets.shape(0)), Root(nets.shape(1))};
          double shallowWidth = 0.0;
          for (int depth = 0; depth <= 12; ++depth) {
            const PairTaylorBounds bounds(nets, a.data(), b.data());
            ASSERT_TRUE(bounds.valid());
            // A random orthonormal basis of the joint local coordinates.
            std::normal_distribution<double> normal(0.0, 1.0);
            Eigen::MatrixXd random(n, n);
            for (int r = 0; r < n; ++r) {
              for (int c = 0; c < n; ++c) random(r, c) = normal(rng);
            }
            const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(random).householderQ();
            std::vector<double> basis(n * n), lo(n * n), hi(n * n);
            for (int c = 0; c < n; ++c) {
              for (int r = 0; r < n; ++r) basis[c * n + r] = q(r, c);
            }
            ASSERT_TRUE(bounds.HessianBounds(basis.data(), lo.data(), hi.data()));
            double width = 0.0;
            for (int sample = 0; sample < 40; ++sample) {
              double tA[3] = {0, 0, 0}, tB[3] = {0, 0, 0};
              RandomLocal(nets.shape(0), rng, tA);
              RandomLocal(nets.shape(1), rng, tB);
              Eigen::MatrixXd hessian;
              ExactHessian(pair, sub, tA, tB, &hessian);
              const Eigen::MatrixXd inBasis = q.transpose() * hessian * q;
              const double magnitude = hessian.cwiseAbs().maxCoeff() + 1.0;
              const double slack = 1e-9 * magnitude;
              for (int r = 0; r < n; ++r) {
                for (int c = 0; c < n; ++c) {
                  EXPECT_GE(inBasis(r, c), lo[r * n + c] - slack) << "depth " << depth << " (" << r << ", " << c << ")";
                  EXPECT_LE(inBasis(r, c), hi[r * n + c] + slack) << "depth " << depth << " (" << r << ", " << c << ")";
                  ++checked;
                }
              }
            }
            for (int r = 0; r < n * n; ++r) width = std::max(width, hi[r] - lo[r]);
            if (depth == 2) shallowWidth = width;
            if (depth == 12) {
              ++deep;
              // Ten splits later (each side's parameters halved a few
              // times) the bounds are far tighter: they converge.
              if (width < 0.1 * shallowWidth) ++tight;
            }
            // Split as the search does: a random side, factor and edge.
            std::uniform_int_distribution<int> pick(0, 1);
            const int s = pick(rng);
            const CellShape& shape = nets.shape(s);
            const int f = std::uniform_int_distribution<int>(0, shape.numFactors() - 1)(rng);
            const int dim = shape.factor(f).dim;
            int vi = std::uniform_int_distribution<int>(0, dim)(rng), vj = std::uniform_int_distribution<int>(0, dim - 1)(rng);
            if (vj >= vi) ++vj;
            const bool keepFirst = pick(rng) == 0;
            const int keep = keepFirst ? vi : vj, move = keepFirst ? vj : vi;
            std::vector<double>& values = s == 0 ? a : b;
            std::vector<double> split(values.size());
            nets.Split(s, f, keep, move, values.data(), split.data());
            values.swap(split);
            for (int i = 0; i < 3; ++i) sub[s].vertex[f][move][i] = 0.5 * (sub[s].vertex[f][move][i] + sub[s].vertex[f][keep][i]);
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GE(tight, deep * 3 / 4) << tight << " of " << deep << " pairs' bounds shrank";
}

}  // namespace
}  // namespace invmap::kernels
