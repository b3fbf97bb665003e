// A pair of random curved cells under random rigid motions, as the pair
// kernels see them (PairSide with its nets): the fixture of the tests of
// the pair search's bounds.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/distance_net.h"
#include "kernels/pair_problem.h"
#include "tests/support/reference_cell.h"

namespace invmap::kernels {

/// A random rotation (about z in 2D) and a translation within 1.5.
inline RigidMotion RandomMotion(std::mt19937_64& rng, int ambientDim) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  RigidMotion m;
  if (ambientDim == 2) {
    const double angle = 3.0 * u(rng);
    m.rotation[0][0] = std::cos(angle);
    m.rotation[0][1] = -std::sin(angle);
    m.rotation[1][0] = std::sin(angle);
    m.rotation[1][1] = std::cos(angle);
    m.translation[0] = u(rng);
    m.translation[1] = u(rng);
    return m;
  }
  const Eigen::Quaterniond q = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
  const Eigen::Matrix3d r = q.toRotationMatrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.rotation[i][j] = r(i, j);
    m.translation[i] = u(rng);
  }
  return m;
}

/// Two cells and their sides.
struct PairCase {
  testing::RefCell cell[2];
  DistanceNets nets[2];
  PairSide side[2];
};

/// The side of `cell` under `motion`, its nets built around its control box's centre.
inline void BuildSide(const testing::RefCell& cell, const RigidMotion& motion, DistanceNets* nets, PairSide* side) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, center[3] = {0, 0, 0};
  for (int c = 0; c < cell.numControlPoints(); ++c) {
    for (int k = 0; k < cell.ambientDim; ++k) {
      lo[k] = std::min(lo[k], cell.points[c * cell.ambientDim + k]);
      hi[k] = std::max(hi[k], cell.points[c * cell.ambientDim + k]);
    }
  }
  for (int k = 0; k < cell.ambientDim; ++k) center[k] = 0.5 * (lo[k] + hi[k]);
  nets->Build(cell.view(), center);
  side->cell = cell.view();
  side->motion = motion;
  side->size = cell.size();
  side->nets = nets;
}

/// Points of the cell under its motion at a lattice of reference coordinates.
inline std::vector<Eigen::Vector3d> Samples(const testing::RefCell& cell, const RigidMotion& motion, int perAxis) {
  std::vector<Eigen::Vector3d> points;
  const int pd = cell.paramDim();
  const bool simplex = cell.type == CellType::Tri;
  for (int i = 0; i <= perAxis; ++i) {
    for (int j = 0; j <= (pd > 1 ? perAxis : 0); ++j) {
      const double ref[3] = {static_cast<double>(i) / perAxis, static_cast<double>(j) / perAxis, 0.0};
      if (simplex && ref[0] + ref[1] > 1.0) continue;
      testing::RefJet jet;
      testing::RefEvaluateJet(cell, ref, 0, &jet);
      double world[3];
      const double local[3] = {jet.x[0], jet.x[1], cell.ambientDim > 2 ? jet.x[2] : 0.0};
      motion.Apply(local, world);
      points.emplace_back(world[0], world[1], world[2]);
    }
  }
  return points;
}

/// A motion a step from `m`: turned by up to `turn` about a random axis and moved by up to `move`.
inline RigidMotion StepMotion(const RigidMotion& m, std::mt19937_64& rng, double turn, double move) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(turn * u(rng), axis).toRotationMatrix();
  RigidMotion next;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      next.rotation[i][j] = 0.0;
      for (int k = 0; k < 3; ++k) next.rotation[i][j] += r(i, k) * m.rotation[k][j];
    }
    next.translation[i] = m.translation[i] + move * u(rng);
  }
  return next;
}

}  // namespace invmap::kernels
