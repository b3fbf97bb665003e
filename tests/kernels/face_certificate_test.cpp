// The face certificate of the cell search (kernels/face_certificate.h): when
// it accepts a net, the polynomial must really be at least its minimum over
// the face, and convex on that face. Checked by dense sampling with an
// evaluation written here from the Bernstein definition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/face_certificate.h"
#include "tests/support/tensor_net.h"

namespace {

using invmap::kernels::CellShape;
using invmap::kernels::CellType;
using invmap::kernels::IsMinimalOnFace;
using invmap::kernels::NetNoise;
using invmap::testing::ForGrid;
using invmap::testing::Net;

/// A net that is a sum of one term per direction (the Bernstein bases sum to
/// one in each direction, so coefficients a_0[i] + a_1[j] + .. give exactly
/// the polynomial a_0(t_0) + a_1(t_1) + ..), then perturbed coefficient by
/// coefficient so that some nets pass the certificate and some fail.
Net RandomSeparableNet(std::mt19937& rng, int dims, const int* side) {
  std::uniform_int_distribution<int> degree(2, dims == 2 ? 6 : 4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Net net{dims, {0, 0, 0}, {}};
  std::vector<double> term[3];
  for (int d = 0; d < dims; ++d) {
    net.deg[d] = degree(rng);
    double value = unit(rng);
    for (int i = 0; i <= net.deg[d]; ++i) {
      if (side[d] < 0) {
        // A convex parabola in the free direction.
        const double x = static_cast<double>(i) / net.deg[d] - unit(rng) * 0.2;
        term[d].push_back(x * x);
      } else {
        // Monotone away from the constrained face.
        value += (side[d] == 0 ? 1.0 : -1.0) * (0.05 + unit(rng));
        term[d].push_back(value);
      }
    }
  }
  std::normal_distribution<double> noise(0.0, 0.15);
  for (int k = 0; k < net.Size(2); ++k) {
    for (int j = 0; j < net.Size(1); ++j) {
      for (int i = 0; i < net.Size(0); ++i) {
        double v = term[0][i] + term[1][j] + (dims > 2 ? term[2][k] : 0.0);
        net.c.push_back(v + noise(rng));
      }
    }
  }
  return net;
}

TEST(FaceCertificate, AcceptedNetsAreAtLeastTheirMinimumOnTheFace) {
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> sideOf(-1, 1);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int dims = trial % 3 == 0 ? 3 : 2;
    int side[3] = {-1, -1, -1};
    for (int d = 0; d < dims; ++d) side[d] = sideOf(rng);
    const Net net = RandomSeparableNet(rng, dims, side);
    if (!IsMinimalOnFace(net.Shape(), net.c.data(), NetNoise{}, side)) {
      ++rejected;
      continue;
    }
    ++accepted;
    const int steps = dims == 2 ? 21 : 9;
    // The face where the constrained directions meet, sampled.
    double faceMin = 1e300;
    ForGrid(dims, steps, [&](const double* t) {
      for (int d = 0; d < dims; ++d) {
        if (side[d] >= 0 && t[d] != side[d]) return;
      }
      faceMin = std::min(faceMin, net(t));
    });
    ForGrid(dims, steps, [&](const double* t) { ASSERT_GE(net(t), faceMin - 1e-12) << "trial " << trial; });
    // Convex along the face's free directions: second differences of samples.
    for (int d = 0; d < dims; ++d) {
      if (side[d] >= 0) continue;
      ForGrid(dims, steps, [&](const double* t) {
        for (int e = 0; e < dims; ++e) {
          if (side[e] >= 0 && t[e] != side[e]) return;
        }
        if (t[d] > 1.0 - 2.5 / (steps - 1)) return;
        double a[3] = {t[0], t[1], t[2]}, b[3] = {t[0], t[1], t[2]};
        a[d] += 1.0 / (steps - 1);
        b[d] += 2.0 / (steps - 1);
        ASSERT_GE(net(b) - 2 * net(a) + net(t), -1e-12) << "trial " << trial;
      });
    }
  }
  // Both outcomes occur, so the checks above are not vacuous.
  EXPECT_GT(accepted, 300);
  EXPECT_GT(rejected, 300);
}

TEST(FaceCertificate, ParabolaOnAnEdgeIsCertified) {
  // f = t_0 + (t_1 - 1/2)^2, least at (0, 1/2). In Bernstein form t_0 has coefficients
  // (0, 1/2, 1) at degree 2, (t_1 - 1/2)^2 has (1/4, -1/4, 1/4).
  const double a[3] = {0.0, 0.5, 1.0}, b[3] = {0.25, -0.25, 0.25};
  std::vector<double> c;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) c.push_back(a[i] + b[j]);
  }
  const CellShape quad(CellType::Quad, {2, 2, 0});
  const int onEdge[3] = {0, -1, -1};
  EXPECT_TRUE(IsMinimalOnFace(quad, c.data(), NetNoise{}, onEdge));
  // The differences across the edge are 1/2: rounding of 1e-16 per unit
  // weight leaves them proved with light weights, not next to one of 1e16.
  std::vector<double> weights(c.size(), 1.0);
  EXPECT_TRUE(IsMinimalOnFace(quad, c.data(), NetNoise{weights.data(), 1e-16}, onEdge));
  weights[4] = 1e16;
  EXPECT_FALSE(IsMinimalOnFace(quad, c.data(), NetNoise{weights.data(), 1e-16}, onEdge));
  // Decreasing away from t_0 = 1: wrong side.
  const int wrongSide[3] = {1, -1, -1};
  EXPECT_FALSE(IsMinimalOnFace(quad, c.data(), NetNoise{}, wrongSide));
  // The corner (0, 0) is not where f is least along t_1.
  const int corner[3] = {0, 0, -1};
  EXPECT_FALSE(IsMinimalOnFace(quad, c.data(), NetNoise{}, corner));
  // Nothing constrained: the convexity certificate's job, not this one's.
  const int none[3] = {-1, -1, -1};
  EXPECT_FALSE(IsMinimalOnFace(quad, c.data(), NetNoise{}, none));
}

TEST(FaceCertificate, NonConvexFaceIsRejected) {
  // f = t_0 - (t_1 - 1/2)^2: monotone in t_0, concave along the face t_0 = 0.
  const double a[3] = {0.0, 0.5, 1.0}, b[3] = {-0.25, 0.25, -0.25};
  std::vector<double> c;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) c.push_back(a[i] + b[j]);
  }
  const int onEdge[3] = {0, -1, -1};
  EXPECT_FALSE(IsMinimalOnFace(CellShape(CellType::Quad, {2, 2, 0}), c.data(), NetNoise{}, onEdge));
}

}  // namespace
