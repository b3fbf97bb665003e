#include "kernels/pair_motion_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::kernels {
namespace {

struct Interval {
  double lo, hi;
};

Interval Times(Interval a, Interval b) {
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}

double Magnitude(Interval a) { return std::max(std::abs(a.lo), std::abs(a.hi)); }

void WriteMotion(const RigidMotion& m, double* out) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out[3 * i + j] = m.rotation[i][j];
    out[9 + i] = m.translation[i];
  }
}

/// The motion of side s's points since `then` (9 rotation values, 3
/// translation values) over its box: per coordinate, an interval. `size`
/// receives the magnitude the rounding is relative to.
void Displacement(const double* lo, const double* hi, const double* then, const RigidMotion& now, Interval* d,
                  double* size) {
  // D = R_now R_then^T - I.
  double m[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k) v += now.rotation[i][k] * then[3 * j + k];
      m[i][j] = v - (i == j ? 1.0 : 0.0);
    }
  }
  Interval local[3];
  *size = 0.0;
  for (int c = 0; c < 3; ++c) {
    local[c] = {lo[c] - then[9 + c], hi[c] - then[9 + c]};
    *size += Magnitude(local[c]);
  }
  for (int r = 0; r < 3; ++r) {
    const double shift = now.translation[r] - then[9 + r];
    Interval sum{shift, shift};
    for (int c = 0; c < 3; ++c) {
      const Interval t = Times({m[r][c], m[r][c]}, local[c]);
      sum.lo += t.lo;
      sum.hi += t.hi;
    }
    d[r] = sum;
    *size += std::abs(shift);
  }
}

}  // namespace

void WriteSubdomainPlace(const double lo[2][3], const double hi[2][3], const RigidMotion& a, const RigidMotion& b,
                         double* place) {
  for (int s = 0; s < 2; ++s) {
    std::copy(lo[s], lo[s] + 3, place + 6 * s);
    std::copy(hi[s], hi[s] + 3, place + 6 * s + 3);
  }
  WriteMotion(a, place + 12);
  WriteMotion(b, place + 24);
}

double SquaredDistanceChangeBound(const double* place, const RigidMotion& a, const RigidMotion& b) {
  Interval da[3], db[3];
  double sizeA = 0.0, sizeB = 0.0;
  Displacement(place, place + 3, place + 12, a, da, &sizeA);
  Displacement(place + 6, place + 9, place + 24, b, db, &sizeB);
  double least = 0.0, scale = 0.0;
  for (int k = 0; k < 3; ++k) {
    // x - y over the boxes, and dx - dy.
    const Interval e{place[k] - place[9 + k], place[3 + k] - place[6 + k]};
    const Interval d{da[k].lo - db[k].hi, da[k].hi - db[k].lo};
    least += 2.0 * Times(e, d).lo;
    scale += Magnitude(e);
  }
  // The rounding: of D's entries (a few ulps each, against the boxes'
  // distances from the translations), of the sums and products, and of the
  // boxes themselves, relative to the magnitudes involved.
  const double eps = std::numeric_limits<double>::epsilon();
  return least - 64.0 * eps * scale * (sizeA + sizeB) - 64.0 * eps * scale * scale;
}

}  // namespace invmap::kernels
