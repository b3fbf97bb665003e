#include "engine/pair_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::engine {

BoxPairBound::BoxPairBound(const kernels::RigidMotion& bIntoA) {
  identity_ = true;
  for (int k = 0; k < 3; ++k) {
    translation_[k] = bIntoA.translation[k];
    for (int l = 0; l < 3; ++l) {
      rotation_[k][l] = bIntoA.rotation[k][l];
      absRotation_[k][l] = std::abs(rotation_[k][l]);
      identity_ = identity_ && rotation_[k][l] == (k == l ? 1.0 : 0.0);
    }
  }
}

double BoxPairBound::LowerBound(const double* loA, const double* hiA, const double* loB, const double* hiB) const {
  double ca[3], ha[3], cb[3], hb[3], d[3];
  double magnitude = 0.0;
  for (int k = 0; k < 3; ++k) {
    ca[k] = 0.5 * (loA[k] + hiA[k]);
    ha[k] = 0.5 * (hiA[k] - loA[k]);
    hb[k] = 0.5 * (hiB[k] - loB[k]);
  }
  if (identity_) {
    // Both axis aligned in one frame: the exact box distance.
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double b = 0.5 * (loB[k] + hiB[k]) + translation_[k];
      const double gap = std::max({loA[k] - (b + hb[k]), 0.0, (b - hb[k]) - hiA[k]});
      d2 += gap * gap;
    }
    return std::sqrt(d2);
  }
  for (int k = 0; k < 3; ++k) {
    const double local = 0.5 * (loB[k] + hiB[k]);
    cb[k] = local;
  }
  for (int k = 0; k < 3; ++k) {
    double v = translation_[k];
    for (int l = 0; l < 3; ++l) v += rotation_[k][l] * cb[l];
    d[k] = v - ca[k];
    magnitude += std::abs(ca[k]) + std::abs(v) + ha[k] + hb[k];
  }
  double gap = 0.0;
  // A's axes.
  for (int k = 0; k < 3; ++k) {
    double rb = 0.0;
    for (int l = 0; l < 3; ++l) rb += absRotation_[k][l] * hb[l];
    gap = std::max(gap, std::abs(d[k]) - ha[k] - rb);
  }
  // B's axes (the rotation's columns).
  for (int l = 0; l < 3; ++l) {
    double s = 0.0, ra = 0.0;
    for (int k = 0; k < 3; ++k) {
      s += rotation_[k][l] * d[k];
      ra += absRotation_[k][l] * ha[k];
    }
    gap = std::max(gap, std::abs(s) - ra - hb[l]);
  }
  // The line through the centres.
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (length > 0.0) {
    double ra = 0.0, rb = 0.0;
    for (int k = 0; k < 3; ++k) ra += std::abs(d[k]) * ha[k];
    for (int l = 0; l < 3; ++l) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += rotation_[k][l] * d[k];
      rb += std::abs(s) * hb[l];
    }
    gap = std::max(gap, length - (ra + rb) / length);
  }
  // The bound's own rounding, so it never exceeds the true distance.
  return std::max(0.0, gap - 16.0 * std::numeric_limits<double>::epsilon() * magnitude);
}

kernels::RigidMotion RelativeMotion(const kernels::RigidMotion& motionA, const kernels::RigidMotion& motionB) {
  // A^-1 B: x -> Ra^T (Rb x + tb - ta).
  kernels::RigidMotion relative;
  for (int k = 0; k < 3; ++k) {
    double t = 0.0;
    for (int l = 0; l < 3; ++l) {
      double r = 0.0;
      for (int m = 0; m < 3; ++m) r += motionA.rotation[m][k] * motionB.rotation[m][l];
      relative.rotation[k][l] = r;
      t += motionA.rotation[l][k] * (motionB.translation[l] - motionA.translation[l]);
    }
    relative.translation[k] = t;
  }
  return relative;
}

}  // namespace invmap::engine
