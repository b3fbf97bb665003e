#include "tests/support/pair_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "tests/support/closest_reference.h"
#include "tests/support/patch_reference.h"
#include "tests/support/reference_cell.h"

namespace invmap::testing {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using V3 = std::array<double, 3>;

V3 Sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double Dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 Cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 Lerp(const V3& a, const V3& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}
double Distance2(const V3& a, const V3& b) {
  const V3 d = Sub(a, b);
  return Dot(d, d);
}

/// Factor dimensions of a cell type, in the order of docs/formats.md.
std::vector<int> FactorDims(kernels::CellType type) {
  switch (type) {
    case kernels::CellType::Line: return {1};
    case kernels::CellType::Tri: return {2};
    case kernels::CellType::Quad: return {1, 1};
    case kernels::CellType::Tet: return {3};
    case kernels::CellType::Hex: return {1, 1, 1};
    case kernels::CellType::Wedge: return {2, 1};
  }
  return {};
}

/// The lattice of a simplex of dimension d with n divisions: a / n for the
/// multi-indices a of total degree at most n.
std::vector<V3> SimplexLattice(int d, int n) {
  std::vector<V3> out;
  for (int k = 0; k <= (d > 2 ? n : 0); ++k) {
    for (int j = 0; j <= (d > 1 ? n - k : 0); ++j) {
      for (int i = 0; i <= n - j - k; ++i) out.push_back({double(i) / n, double(j) / n, double(k) / n});
    }
  }
  return out;
}

/// The lattice of a cell type: the product of its factors' lattices.
std::vector<V3> CellLattice(kernels::CellType type, int n) {
  std::vector<V3> out{{0, 0, 0}};
  int offset = 0;
  for (const int d : FactorDims(type)) {
    const std::vector<V3> factor = SimplexLattice(d, n);
    std::vector<V3> next;
    for (const V3& p : out) {
      for (const V3& q : factor) {
        V3 r = p;
        for (int i = 0; i < d; ++i) r[offset + i] = q[i];
        next.push_back(r);
      }
    }
    out = std::move(next);
    offset += d;
  }
  return out;
}

/// Euclidean projection onto {x >= 0, sum x <= 1} in d dimensions.
void ProjectSimplex(int d, double* x) {
  double clamped[3], sum = 0.0;
  for (int i = 0; i < d; ++i) sum += (clamped[i] = std::max(x[i], 0.0));
  if (sum <= 1.0) {
    std::copy(clamped, clamped + d, x);
    return;
  }
  // Onto sum x = 1, x >= 0: x_i - theta clipped at 0 (sorting algorithm).
  double sorted[3];
  std::copy(x, x + d, sorted);
  for (int i = 1; i < d; ++i) {  // descending (d <= 3)
    for (int j = i; j > 0 && sorted[j - 1] < sorted[j]; --j) std::swap(sorted[j - 1], sorted[j]);
  }
  double cumulative = 0.0, theta = 0.0;
  for (int i = 0; i < d; ++i) {
    cumulative += sorted[i];
    const double t = (cumulative - 1.0) / (i + 1);
    if (sorted[i] - t > 0.0) theta = t;
  }
  for (int i = 0; i < d; ++i) x[i] = std::max(x[i] - theta, 0.0);
}

void ProjectDomain(kernels::CellType type, double* ref) {
  int offset = 0;
  for (const int d : FactorDims(type)) {
    if (d == 1) {
      ref[offset] = std::clamp(ref[offset], 0.0, 1.0);
    } else {
      ProjectSimplex(d, ref + offset);
    }
    offset += d;
  }
}

/// One cell placed by its pose, with its lattice.
struct PlacedCell {
  const PatchCell* source = nullptr;
  PoseRows pose{};
  V3 lo{}, hi{};
  std::vector<V3> refs;
  std::vector<V3> points;
  double spacing = 0.0;  ///< Estimated physical distance between lattice neighbours.
  int divisions = 1;     ///< Lattice divisions per parameter.
};

V3 PlacedPoint(const PlacedCell& cell, const double* ref) {
  double x[3] = {0, 0, 0}, y[3];
  RefEvaluate(cell.source->cell, ref, x);
  ApplyRows(cell.pose, x, y);
  return {y[0], y[1], y[2]};
}

std::vector<PlacedCell> PlaceCells(const std::vector<PatchCell>& cells, const PoseRows& pose,
                                   const PairReferenceOptions& options) {
  std::vector<PlacedCell> out(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    PlacedCell& placed = out[c];
    placed.source = &cells[c];
    placed.pose = pose;
    const RefCell& cell = cells[c].cell;
    placed.lo = {kInf, kInf, kInf};
    placed.hi = {-kInf, -kInf, -kInf};
    for (int p = 0; p < cell.numControlPoints(); ++p) {
      double x[3] = {0, 0, 0}, y[3];
      for (int k = 0; k < cell.ambientDim; ++k) x[k] = cell.points[p * cell.ambientDim + k];
      ApplyRows(pose, x, y);
      for (int k = 0; k < 3; ++k) {
        placed.lo[k] = std::min(placed.lo[k], y[k]);
        placed.hi[k] = std::max(placed.hi[k], y[k]);
      }
    }
    const int n = options.divisions[cell.paramDim() - 1];
    placed.refs = CellLattice(cell.type, n);
    for (const V3& r : placed.refs) placed.points.push_back(PlacedPoint(placed, r.data()));
    placed.spacing = std::sqrt(Distance2(placed.lo, placed.hi)) / n;
    placed.divisions = n;
  }
  return out;
}

double BoxDistance2(const PlacedCell& a, const PlacedCell& b) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({a.lo[k] - b.hi[k], 0.0, b.lo[k] - a.hi[k]});
    d2 += gap * gap;
  }
  return d2;
}

/// Projected Gauss-Newton (Levenberg-Marquardt damped) on the joint
/// parameters of two placed cells, from (ua, ub): the polish.
/// `b` without a source cell is the fixed point of its pose's translation.
double Polish(const PlacedCell& a, const PlacedCell& b, double* ua, double* ub) {
  const int pa = a.source->cell.paramDim(), pb = b.source ? b.source->cell.paramDim() : 0;
  const int n = pa + pb;
  auto evaluate = [&](const double* u, const double* v, V3* x, V3* y, double jac[3][6]) {
    RefJet ja, jb;
    RefEvaluateJet(a.source->cell, u, 1, &ja);
    if (b.source) RefEvaluateJet(b.source->cell, v, 1, &jb);
    double px[3], py[3];
    ApplyRows(a.pose, ja.x, px);
    ApplyRows(b.pose, jb.x, py);
    *x = {px[0], px[1], px[2]};
    *y = {py[0], py[1], py[2]};
    if (!jac) return;
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < pa; ++i) {
        double s = 0.0;
        for (int l = 0; l < 3; ++l) s += a.pose[4 * k + l] * ja.d1[l][i];
        jac[k][i] = s;
      }
      for (int i = 0; i < pb; ++i) {
        double s = 0.0;
        for (int l = 0; l < 3; ++l) s += b.pose[4 * k + l] * jb.d1[l][i];
        jac[k][pa + i] = -s;
      }
    }
  };
  ProjectDomain(a.source->cell.type, ua);
  if (b.source) ProjectDomain(b.source->cell.type, ub);
  V3 x, y;
  double jac[3][6] = {};
  evaluate(ua, ub, &x, &y, jac);
  double f = Distance2(x, y);
  // Trial point: the projection of (u, v) + t step onto the domains.
  auto trial = [&](const double* step, double t, double* tu, double* tv, V3* xt, V3* yt, double jt[3][6]) {
    for (int i = 0; i < 3; ++i) {
      tu[i] = ua[i] + (i < pa ? t * step[i] : 0.0);
      tv[i] = ub[i] + (i < pb ? t * step[pa + i] : 0.0);
    }
    ProjectDomain(a.source->cell.type, tu);
    if (b.source) ProjectDomain(b.source->cell.type, tv);
    evaluate(tu, tv, xt, yt, jt);
    return Distance2(*xt, *yt);
  };
  double mu = 1e-9;
  for (int iteration = 0; iteration < 400 && f > 0.0; ++iteration) {
    const V3 r = Sub(x, y);
    double g[6] = {}, h[6][6] = {};
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) g[i] += jac[k][i] * r[k];
      for (int j = 0; j < n; ++j) {
        for (int k = 0; k < 3; ++k) h[i][j] += jac[k][i] * jac[k][j];
      }
    }
    // Gauss-Newton (Levenberg-Marquardt damped) on the full step, then
    // projected; where that fails, the projected gradient with
    // backtracking along the projection arc (it always makes progress
    // toward a KKT point).
    double step[6] = {};
    double m[6][7];
    double diagonal = 0.0;
    for (int i = 0; i < n; ++i) diagonal = std::max(diagonal, h[i][i]);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) m[i][j] = h[i][j];
      m[i][i] += mu * (h[i][i] + 1e-12 * diagonal) + 1e-300;
      m[i][n] = -g[i];
    }
    bool singular = false;
    for (int col = 0; col < n && !singular; ++col) {
      int pivot = col;
      for (int row = col + 1; row < n; ++row) {
        if (std::abs(m[row][col]) > std::abs(m[pivot][col])) pivot = row;
      }
      if (!(std::abs(m[pivot][col]) > 0.0)) {
        singular = true;
        break;
      }
      for (int j = 0; j <= n; ++j) std::swap(m[col][j], m[pivot][j]);
      for (int row = 0; row < n; ++row) {
        if (row == col) continue;
        const double factor = m[row][col] / m[col][col];
        for (int j = col; j <= n; ++j) m[row][j] -= factor * m[col][j];
      }
    }
    double tu[3], tv[3], jt[3][6] = {};
    V3 xt, yt;
    double ft = f;
    bool accepted = false;
    if (!singular) {
      for (int i = 0; i < n; ++i) step[i] = m[i][n] / m[i][i];
      ft = trial(step, 1.0, tu, tv, &xt, &yt, jt);
      accepted = ft < f;
    }
    if (!accepted) {
      double gradient[6];
      for (int i = 0; i < n; ++i) gradient[i] = -g[i];
      double t = 1.0 / (diagonal + 1e-300);
      for (int halving = 0; halving < 60 && !accepted; ++halving, t *= 0.5) {
        ft = trial(gradient, t, tu, tv, &xt, &yt, jt);
        accepted = ft < f;
      }
      mu = std::min(mu * 8.0, 1e6);
    } else {
      mu = std::max(mu / 4.0, 1e-12);
    }
    if (!accepted) break;
    double moved = 0.0;
    for (int i = 0; i < pa; ++i) moved = std::max(moved, std::abs(tu[i] - ua[i]));
    for (int i = 0; i < pb; ++i) moved = std::max(moved, std::abs(tv[i] - ub[i]));
    std::copy(tu, tu + 3, ua);
    std::copy(tv, tv + 3, ub);
    x = xt;
    y = yt;
    std::copy(&jt[0][0], &jt[0][0] + 18, &jac[0][0]);
    f = ft;
    if (moved < 1e-16) break;
  }
  return std::sqrt(f);
}

PairReferencePoint MakePoint(const PlacedCell& cell, const double* ref) {
  PairReferencePoint p;
  p.patch = cell.source->patch;
  p.cell = cell.source->index;
  p.ref = {ref[0], ref[1], ref[2]};
  p.point = PlacedPoint(cell, ref);
  return p;
}

/// The reference coordinates of `x` on `cell`, when the cell holds it.
bool RefOn(const PlacedCell& cell, const V3& x, double* ref) {
  bool inBox = true;
  for (int k = 0; k < 3; ++k) inBox = inBox && x[k] >= cell.lo[k] - 1e-9 && x[k] <= cell.hi[k] + 1e-9;
  if (!inBox) return false;
  PlacedCell target;
  target.pose = IdentityRows();
  target.pose[3] = x[0];
  target.pose[7] = x[1];
  target.pose[11] = x[2];
  std::size_t nearest = 0;
  for (std::size_t i = 0; i < cell.points.size(); ++i) {
    if (Distance2(cell.points[i], x) < Distance2(cell.points[nearest], x)) nearest = i;
  }
  for (int k = 0; k < 3; ++k) ref[k] = cell.refs[nearest][k];
  double none[3] = {0, 0, 0};
  return Polish(cell, target, ref, none) <= 1e-9;
}

/// True when some pair of cells holding the answer's two points polishes
/// from them to a pair closer than `d` (the answer sits on cells' edges
/// where the distance still falls across them).
bool CloserAcrossCells(const std::vector<PlacedCell>& placedA, const std::vector<PlacedCell>& placedB,
                       const PairReferenceAnswer& answer, double d) {
  for (const PlacedCell& ca : placedA) {
    double ua[3];
    if (!RefOn(ca, answer.a.point, ua)) continue;
    for (const PlacedCell& cb : placedB) {
      double ub[3];
      if (!RefOn(cb, answer.b.point, ub)) continue;
      double u[3] = {ua[0], ua[1], ua[2]}, v[3] = {ub[0], ub[1], ub[2]};
      if (Polish(ca, cb, u, v) < d - 1e-10) return true;
    }
  }
  return false;
}

}  // namespace

PoseRows IdentityRows() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}; }

PoseRows RotationRows(const std::array<double, 3>& axis, double angle, const std::array<double, 3>& translation) {
  const double length = std::sqrt(Dot(axis, axis));
  const double x = axis[0] / length, y = axis[1] / length, z = axis[2] / length;
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  // Rodrigues' formula.
  return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y, translation[0],
          t * x * y + s * z, t * y * y + c,     t * y * z - s * x, translation[1],
          t * x * z - s * y, t * y * z + s * x, t * z * z + c,     translation[2]};
}

void ApplyRows(const PoseRows& pose, const double* x, double* out) {
  const double in[3] = {x[0], x[1], x[2]};
  for (int k = 0; k < 3; ++k) out[k] = pose[4 * k] * in[0] + pose[4 * k + 1] * in[1] + pose[4 * k + 2] * in[2] + pose[4 * k + 3];
}

PairReferenceAnswer BruteForcePairDistance(const Geometry& a, const PoseRows& poseA, const Geometry& b,
                                           const PoseRows& poseB, const PairReferenceOptions& options) {
  const std::vector<PatchCell> cellsA = GeometryCells(a), cellsB = GeometryCells(b);
  const std::vector<PlacedCell> placedA = PlaceCells(cellsA, poseA, options);
  const std::vector<PlacedCell> placedB = PlaceCells(cellsB, poseB, options);
  // An upper bound from every cell's first sample, then cell pairs by box distance.
  double upper2 = kInf;
  for (const PlacedCell& ca : placedA) {
    for (const PlacedCell& cb : placedB) upper2 = std::min(upper2, Distance2(ca.points[0], cb.points[0]));
  }
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> order;
  for (std::size_t i = 0; i < placedA.size(); ++i) {
    for (std::size_t j = 0; j < placedB.size(); ++j) {
      const double d2 = BoxDistance2(placedA[i], placedB[j]);
      if (d2 <= upper2) order.push_back({d2, {i, j}});
    }
  }
  std::sort(order.begin(), order.end());
  struct Sampled {
    double d2;
    std::size_t i, j, si, sj;
  };
  std::vector<Sampled> sampled;
  double best2 = upper2;
  for (const auto& [box2, pair] : order) {
    if (box2 > best2) break;
    const PlacedCell& ca = placedA[pair.first];
    const PlacedCell& cb = placedB[pair.second];
    Sampled s{kInf, pair.first, pair.second, 0, 0};
    for (std::size_t p = 0; p < ca.points.size(); ++p) {
      for (std::size_t q = 0; q < cb.points.size(); ++q) {
        const double d2 = Distance2(ca.points[p], cb.points[q]);
        if (d2 < s.d2) s = {d2, pair.first, pair.second, p, q};
      }
    }
    best2 = std::min(best2, s.d2);
    sampled.push_back(s);
  }
  PairReferenceAnswer best;
  best.distance = kInf;
  const double bestSampled = std::sqrt(best2);
  for (const Sampled& s : sampled) {
    const PlacedCell& ca = placedA[s.i];
    const PlacedCell& cb = placedB[s.j];
    if (std::sqrt(s.d2) > bestSampled + options.polishBand * (ca.spacing + cb.spacing)) continue;
    double ua[3] = {ca.refs[s.si][0], ca.refs[s.si][1], ca.refs[s.si][2]};
    double ub[3] = {cb.refs[s.sj][0], cb.refs[s.sj][1], cb.refs[s.sj][2]};
    const double d = Polish(ca, cb, ua, ub);
    if (d < best.distance) {
      best.distance = d;
      best.a = MakePoint(ca, ua);
      best.b = MakePoint(cb, ub);
    }
  }
  return best;
}

std::vector<PairReferenceAnswer> BruteForcePairMinima(const Geometry& a, const PoseRows& poseA, const Geometry& b,
                                                      const PoseRows& poseB, double maxDistance,
                                                      double mergeTolerance, const PairReferenceOptions& options) {
  const std::vector<PatchCell> cellsA = GeometryCells(a), cellsB = GeometryCells(b);
  const std::vector<PlacedCell> placedA = PlaceCells(cellsA, poseA, options);
  const std::vector<PlacedCell> placedB = PlaceCells(cellsB, poseB, options);
  // Every sample of a model, with the samples one lattice step away
  // (within its cell, and across cells where two samples coincide).
  struct Sample {
    std::size_t cell, index;
    V3 point;
    std::vector<std::size_t> neighbours;
  };
  auto samplesOf = [](const std::vector<PlacedCell>& placed) {
    std::vector<Sample> samples;
    for (std::size_t c = 0; c < placed.size(); ++c) {
      for (std::size_t i = 0; i < placed[c].points.size(); ++i) samples.push_back({c, i, placed[c].points[i], {}});
    }
    // Neighbours: samples whose reference coordinates differ by one lattice
    // step in the same cell, or the same point in another cell (then the
    // other cell's neighbours of it are reached through it).
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const PlacedCell& cell = placed[samples[s].cell];
      const double step = 1.0 / cell.divisions;
      for (std::size_t t = 0; t < samples.size(); ++t) {
        if (t == s) continue;
        bool neighbour = false;
        if (samples[t].cell == samples[s].cell) {
          double most = 0.0;
          for (int k = 0; k < 3; ++k) {
            most = std::max(most, std::abs(cell.refs[samples[t].index][k] - cell.refs[samples[s].index][k]));
          }
          neighbour = most <= step * 1.0001;
        } else {
          neighbour = Distance2(samples[t].point, samples[s].point) <= 1e-24;
        }
        if (neighbour) samples[s].neighbours.push_back(t);
      }
    }
    return samples;
  };
  const std::vector<Sample> sa = samplesOf(placedA);
  const std::vector<Sample> sb = samplesOf(placedB);
  std::vector<PairReferenceAnswer> minima;
  for (std::size_t p = 0; p < sa.size(); ++p) {
    for (std::size_t q = 0; q < sb.size(); ++q) {
      const double d2 = Distance2(sa[p].point, sb[q].point);
      if (std::sqrt(d2) > maxDistance * 1.1 + 1e-12) continue;
      bool least = true;
      for (const std::size_t n : sa[p].neighbours) least = least && Distance2(sa[n].point, sb[q].point) >= d2;
      for (const std::size_t n : sb[q].neighbours) least = least && Distance2(sa[p].point, sb[n].point) >= d2;
      if (!least) continue;
      const PlacedCell& ca = placedA[sa[p].cell];
      const PlacedCell& cb = placedB[sb[q].cell];
      double ua[3] = {ca.refs[sa[p].index][0], ca.refs[sa[p].index][1], ca.refs[sa[p].index][2]};
      double ub[3] = {cb.refs[sb[q].index][0], cb.refs[sb[q].index][1], cb.refs[sb[q].index][2]};
      const double d = Polish(ca, cb, ua, ub);
      if (d > maxDistance) continue;
      PairReferenceAnswer answer;
      answer.distance = d;
      answer.a = MakePoint(ca, ua);
      answer.b = MakePoint(cb, ub);
      // Held on an edge of its cells: in every pair of cells that holds the
      // two points, a polish from there must not get closer.
      if (CloserAcrossCells(placedA, placedB, answer, d)) continue;
      bool known = false;
      for (const PairReferenceAnswer& m : minima) {
        known = known || (std::sqrt(Distance2(m.a.point, answer.a.point)) <= mergeTolerance &&
                          std::sqrt(Distance2(m.b.point, answer.b.point)) <= mergeTolerance);
      }
      if (!known) minima.push_back(answer);
    }
  }
  std::sort(minima.begin(), minima.end(),
            [](const PairReferenceAnswer& x, const PairReferenceAnswer& y) { return x.distance < y.distance; });
  return minima;
}

std::vector<PairReferencePoint> BruteForcePointMinima(const Geometry& geometry, const double* point, double maxDistance,
                                                      double mergeTolerance, int divisions) {
  const std::vector<PatchCell> cells = GeometryCells(geometry);
  PairReferenceOptions options;
  for (int& d : options.divisions) d = divisions;
  const std::vector<PlacedCell> placed = PlaceCells(cells, IdentityRows(), options);
  const V3 p{point[0], point[1], geometry.dimension > 2 ? point[2] : 0.0};
  struct Sample {
    std::size_t cell, index;
    double d2;
  };
  std::vector<Sample> samples;
  for (std::size_t c = 0; c < placed.size(); ++c) {
    // Cells beyond reach hold no minimum within maxDistance (their neighbours
    // within reach still see their samples as neighbours: a margin).
    double gap2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double gap = std::max({placed[c].lo[k] - p[k], 0.0, p[k] - placed[c].hi[k]});
      gap2 += gap * gap;
    }
    if (std::sqrt(gap2) > 1.5 * maxDistance + 1e-12) continue;
    for (std::size_t i = 0; i < placed[c].points.size(); ++i) samples.push_back({c, i, Distance2(placed[c].points[i], p)});
  }
  auto pointOf = [&](const Sample& s) { return placed[s.cell].points[s.index]; };
  // The polish's second side: the fixed point p.
  PlacedCell probe;
  probe.pose = IdentityRows();
  probe.pose[3] = p[0];
  probe.pose[7] = p[1];
  probe.pose[11] = p[2];
  double largestSpacing = 0.0;
  for (const PlacedCell& c : placed) largestSpacing = std::max(largestSpacing, c.spacing);
  // Lattice neighbours lie within a few spacings: a grid of that size
  // finds them without comparing every pair of samples.
  struct Grid {
    double cellSize;
    std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> buckets;
    std::array<std::int64_t, 3> Key(const V3& x) const {
      return {static_cast<std::int64_t>(std::floor(x[0] / cellSize)), static_cast<std::int64_t>(std::floor(x[1] / cellSize)),
              static_cast<std::int64_t>(std::floor(x[2] / cellSize))};
    }
    std::vector<std::size_t> Near(const V3& x) const {
      std::vector<std::size_t> out;
      const auto key = Key(x);
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          for (int k = -1; k <= 1; ++k) {
            const auto found = buckets.find({key[0] + i, key[1] + j, key[2] + k});
            if (found != buckets.end()) out.insert(out.end(), found->second.begin(), found->second.end());
          }
        }
      }
      return out;
    }
  } grid{4.0 * largestSpacing + 1e-300, {}};
  for (std::size_t s = 0; s < samples.size(); ++s) grid.buckets[grid.Key(pointOf(samples[s]))].push_back(s);
  std::vector<PairReferencePoint> minima;
  std::vector<double> minimaDistance;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const Sample& sample = samples[s];
    if (std::sqrt(sample.d2) > maxDistance * 1.1 + 1e-12) continue;
    const PlacedCell& cell = placed[sample.cell];
    const V3 at = pointOf(sample);
    const double step = 1.0 / cell.divisions;
    bool least = true;
    for (const std::size_t t : grid.Near(at)) {
      if (!least) break;
      if (t == s) continue;
      bool neighbour;
      if (samples[t].cell == sample.cell) {
        double most = 0.0;
        for (int k = 0; k < 3; ++k) most = std::max(most, std::abs(cell.refs[samples[t].index][k] - cell.refs[sample.index][k]));
        neighbour = most <= step * 1.0001;
      } else {
        neighbour = Distance2(pointOf(samples[t]), at) <= 1e-24;
      }
      if (neighbour && samples[t].d2 < sample.d2) least = false;
    }
    if (!least) continue;
    double u[3] = {cell.refs[sample.index][0], cell.refs[sample.index][1], cell.refs[sample.index][2]};
    double v[3] = {0, 0, 0};
    const double d = Polish(cell, probe, u, v);
    if (d > maxDistance) continue;
    const PairReferencePoint found = MakePoint(cell, u);
    // A point the polish held on its cell's edge is no minimum if the
    // distance still falls across that edge: a sample nearby is closer.
    bool beaten = false;
    for (const std::size_t t : grid.Near(found.point)) {
      const Sample& other = samples[t];
      if (Distance2(pointOf(other), found.point) <= 4.0 * largestSpacing * largestSpacing && std::sqrt(other.d2) < d - 1e-12) {
        beaten = true;
        break;
      }
    }
    if (beaten) continue;
    // Held on its cell's edge: in every other cell that holds the point, a
    // polish from there must not get closer (the distance must grow into
    // that cell too).
    for (std::size_t c2 = 0; c2 < placed.size() && !beaten; ++c2) {
      if (c2 == sample.cell) continue;
      const PlacedCell& other = placed[c2];
      bool inBox = true;
      for (int k = 0; k < 3; ++k) inBox = inBox && found.point[k] >= other.lo[k] - 1e-9 && found.point[k] <= other.hi[k] + 1e-9;
      if (!inBox) continue;
      PlacedCell target;
      target.pose = IdentityRows();
      target.pose[3] = found.point[0];
      target.pose[7] = found.point[1];
      target.pose[11] = found.point[2];
      std::size_t nearest = 0;
      for (std::size_t i = 0; i < other.points.size(); ++i) {
        if (Distance2(other.points[i], found.point) < Distance2(other.points[nearest], found.point)) nearest = i;
      }
      double w[3] = {other.refs[nearest][0], other.refs[nearest][1], other.refs[nearest][2]}, none[3] = {0, 0, 0};
      if (Polish(other, target, w, none) > 1e-9) continue;  // not on this cell
      beaten = Polish(other, probe, w, none) < d - 1e-10;
    }
    if (beaten) continue;
    bool known = false;
    for (const PairReferencePoint& m : minima) known = known || std::sqrt(Distance2(m.point, found.point)) <= mergeTolerance;
    if (!known) {
      minima.push_back(found);
      minimaDistance.push_back(d);
    }
  }
  // Nearest first.
  std::vector<std::size_t> order(minima.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return minimaDistance[x] < minimaDistance[y]; });
  std::vector<PairReferencePoint> sorted;
  for (const std::size_t i : order) sorted.push_back(minima[i]);
  return sorted;
}

bool VerifyLocalMinimum(const Geometry& geometry, const double* point, const double* x, double tolerance) {
  const std::vector<PatchCell> cells = GeometryCells(geometry);
  PairReferenceOptions options;
  for (int& d : options.divisions) d = 6;
  const std::vector<PlacedCell> placed = PlaceCells(cells, IdentityRows(), options);
  const V3 p{point[0], point[1], geometry.dimension > 2 ? point[2] : 0.0};
  const V3 at{x[0], x[1], geometry.dimension > 2 ? x[2] : 0.0};
  const double d = std::sqrt(Distance2(at, p));
  PlacedCell target;
  target.pose = IdentityRows();
  target.pose[3] = at[0];
  target.pose[7] = at[1];
  target.pose[11] = at[2];
  int holders = 0;
  for (const PlacedCell& cell : placed) {
    bool inBox = true;
    for (int k = 0; k < 3; ++k) inBox = inBox && at[k] >= cell.lo[k] - 1e-9 && at[k] <= cell.hi[k] + 1e-9;
    if (!inBox) continue;
    std::size_t nearest = 0;
    for (std::size_t i = 0; i < cell.points.size(); ++i) {
      if (Distance2(cell.points[i], at) < Distance2(cell.points[nearest], at)) nearest = i;
    }
    double u[3] = {cell.refs[nearest][0], cell.refs[nearest][1], cell.refs[nearest][2]}, none[3] = {0, 0, 0};
    if (Polish(cell, target, u, none) > 1e-9) continue;  // x is not on this cell
    ++holders;
    const int pd = cell.source->cell.paramDim();
    for (const double radius : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      const int directions = pd == 1 ? 2 : 16;
      for (int k = 0; k < directions; ++k) {
        double v[3] = {u[0], u[1], u[2]};
        if (pd == 1) {
          v[0] += k == 0 ? radius : -radius;
        } else {
          const double angle = 2.0 * 3.14159265358979323846 * k / directions;
          v[0] += radius * std::cos(angle);
          v[1] += radius * std::sin(angle);
          if (pd == 3) v[2] += radius * std::sin(3.0 * angle);
        }
        ProjectDomain(cell.source->cell.type, v);
        if (std::sqrt(Distance2(PlacedPoint(cell, v), p)) < d - tolerance) return false;
      }
    }
  }
  return holders > 0;
}

namespace {

/// Minimum over t in [0, 1] of the distance from p0 + t (p1 - p0) to
/// segment q: a convex function of t, minimized by golden sections to the
/// last bits (the reference's own method, unlike a closed form).
double SegmentSegmentDistance(const V3& p0, const V3& p1, const V3& q0, const V3& q1) {
  auto toSegment = [&](double t) {
    const V3 p = Lerp(p0, p1, t);
    const V3 d = Sub(q1, q0);
    const double len2 = Dot(d, d);
    const double s = len2 > 0.0 ? std::clamp(Dot(Sub(p, q0), d) / len2, 0.0, 1.0) : 0.0;
    return std::sqrt(Distance2(p, Lerp(q0, q1, s)));
  };
  double lo = 0.0, hi = 1.0;
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
  double f1 = toSegment(x1), f2 = toSegment(x2);
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-17; ++iteration) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - ratio * (hi - lo);
      f1 = toSegment(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + ratio * (hi - lo);
      f2 = toSegment(x2);
    }
  }
  return std::min({f1, f2, toSegment(0.0), toSegment(1.0)});
}

double PointTriangleDistance(const V3& p, const V3& a, const V3& b, const V3& c) {
  double s, t, x[3];
  ClosestOnTriangle(p.data(), a.data(), b.data(), c.data(), &s, &t, x);
  return std::sqrt(Distance2(p, {x[0], x[1], x[2]}));
}

/// Moller-Trumbore: does segment p0 p1 cross triangle (a, b, c)?
bool SegmentHitsTriangle(const V3& p0, const V3& p1, const V3& a, const V3& b, const V3& c) {
  const V3 dir = Sub(p1, p0), e1 = Sub(b, a), e2 = Sub(c, a);
  const V3 h = Cross(dir, e2);
  const double det = Dot(e1, h);
  if (std::abs(det) < 1e-300) return false;
  const double inv = 1.0 / det;
  const V3 s = Sub(p0, a);
  const double u = inv * Dot(s, h);
  if (u < 0.0 || u > 1.0) return false;
  const V3 q = Cross(s, e1);
  const double v = inv * Dot(dir, q);
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = inv * Dot(e2, q);
  return t >= 0.0 && t <= 1.0;
}

}  // namespace

double TriangleTriangleDistance(const double* a0, const double* a1, const double* a2, const double* b0,
                                const double* b1, const double* b2) {
  const V3 a[3] = {{a0[0], a0[1], a0[2]}, {a1[0], a1[1], a1[2]}, {a2[0], a2[1], a2[2]}};
  const V3 b[3] = {{b0[0], b0[1], b0[2]}, {b1[0], b1[1], b1[2]}, {b2[0], b2[1], b2[2]}};
  double best = kInf;
  for (int i = 0; i < 3; ++i) {
    best = std::min(best, PointTriangleDistance(a[i], b[0], b[1], b[2]));
    best = std::min(best, PointTriangleDistance(b[i], a[0], a[1], a[2]));
    for (int j = 0; j < 3; ++j) best = std::min(best, SegmentSegmentDistance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
    if (SegmentHitsTriangle(a[i], a[(i + 1) % 3], b[0], b[1], b[2]) ||
        SegmentHitsTriangle(b[i], b[(i + 1) % 3], a[0], a[1], a[2])) {
      best = 0.0;
    }
  }
  return best;
}

double AllPairsMeshDistance(const Patch& a, const PoseRows& poseA, const Patch& b, const PoseRows& poseB) {
  auto placed = [](const Patch& patch, const PoseRows& pose) {
    std::vector<double> out(patch.points.size());
    for (std::size_t v = 0; v < patch.points.size() / 3; ++v) ApplyRows(pose, &patch.points[3 * v], &out[3 * v]);
    return out;
  };
  const std::vector<double> va = placed(a, poseA), vb = placed(b, poseB);
  // Every pair of triangles, skipping those whose boxes are already
  // farther apart than the best distance.
  auto boxes = [](const Patch& patch, const std::vector<double>& v) {
    std::vector<std::array<double, 6>> out;
    for (std::size_t i = 0; i < patch.cells.size(); i += 3) {
      std::array<double, 6> box{kInf, kInf, kInf, -kInf, -kInf, -kInf};
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
          box[k] = std::min(box[k], v[3 * patch.cells[i + c] + k]);
          box[3 + k] = std::max(box[3 + k], v[3 * patch.cells[i + c] + k]);
        }
      }
      out.push_back(box);
    }
    return out;
  };
  const auto boxA = boxes(a, va), boxB = boxes(b, vb);
  double best = kInf;
  for (std::size_t i = 0; i < a.cells.size(); i += 3) {
    for (std::size_t j = 0; j < b.cells.size(); j += 3) {
      double gap2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double gap = std::max({boxA[i / 3][k] - boxB[j / 3][3 + k], 0.0, boxB[j / 3][k] - boxA[i / 3][3 + k]});
        gap2 += gap * gap;
      }
      if (std::sqrt(gap2) > best) continue;
      best = std::min(best, TriangleTriangleDistance(&va[3 * a.cells[i]], &va[3 * a.cells[i + 1]],
                                                     &va[3 * a.cells[i + 2]], &vb[3 * b.cells[j]],
                                                     &vb[3 * b.cells[j + 1]], &vb[3 * b.cells[j + 2]]));
    }
  }
  return best;
}

}  // namespace invmap::testing
