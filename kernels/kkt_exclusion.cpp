#include "kernels/kkt_exclusion.h"

namespace invmap::kernels {
namespace {

/// Sign of every difference along `d` of q - level ww over the index box
/// [first, last] (inclusive per factor; along d the pairs (i, i + 1) with i
/// in [first[d], last[d] - 1]): +1 all above noise, -1 all below -noise, 0 otherwise.
int DifferenceSign(const int* count, const int* first, const int* last, int factors, int d, const double* q,
                   const double* ww, double level, double noise) {
  int stride[3] = {1, 1, 1};
  for (int f = 1; f < factors; ++f) stride[f] = stride[f - 1] * count[f - 1];
  bool up = true, down = true;
  int index[3] = {first[0], first[1], first[2]};
  const int stop = last[d] - 1;
  for (;;) {
    if (index[d] <= stop) {
      int at = 0;
      for (int f = 0; f < factors; ++f) at += index[f] * stride[f];
      const int next = at + stride[d];
      double diff, tolerance;
      if (ww) {
        diff = (q[next] - level * ww[next]) - (q[at] - level * ww[at]);
        tolerance = 2.0 * noise * (ww[at] + ww[next]);
      } else {
        diff = q[next] - q[at];
        tolerance = 2.0 * noise;
      }
      up = up && diff > tolerance;
      down = down && diff < -tolerance;
      if (!up && !down) return 0;
    }
    // Next multi-index of the box, first factor fastest (along d only up to stop).
    int f = 0;
    for (; f < factors; ++f) {
      const int end = f == d ? stop : last[f];
      if (++index[f] <= end) break;
      index[f] = first[f];
    }
    if (f == factors) break;
  }
  return up ? 1 : down ? -1 : 0;
}

}  // namespace

bool LocateKktPoints(const CellShape& shape, const double* q, const double* ww, double levelLo, double levelHi,
                     double noise, const bool* reachesLow, const bool* reachesHigh, int* face) {
  const int factors = shape.numFactors();
  int count[3] = {1, 1, 1}, first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
  for (int f = 0; f < factors; ++f) {
    count[f] = shape.factor(f).degree + 1;
    last[f] = count[f] - 1;
    face[f] = -1;
  }
  for (int f = factors; f < 3; ++f) face[f] = -1;
  // Each pass may pin one more direction to a face, on which the others are
  // judged again.
  for (bool changed = true; changed;) {
    changed = false;
    for (int d = 0; d < factors; ++d) {
      if (face[d] >= 0 || last[d] == first[d]) continue;
      int sign = DifferenceSign(count, first, last, factors, d, q, ww, levelLo, noise);
      if (sign != 0 && ww && levelHi != levelLo) {
        if (DifferenceSign(count, first, last, factors, d, q, ww, levelHi, noise) != sign) sign = 0;
      }
      if (sign == 0) continue;
      // Rising along d: only the lower face can take the slope; falling: the upper.
      if (sign > 0 ? !reachesLow[d] : !reachesHigh[d]) return false;
      face[d] = sign > 0 ? 0 : 1;
      first[d] = last[d] = sign > 0 ? 0 : count[d] - 1;
      changed = true;
    }
  }
  return true;
}

}  // namespace invmap::kernels
