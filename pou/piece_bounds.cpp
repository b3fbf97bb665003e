#include "pou/piece_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pou/bump.h"
#include "pou/bump_bounds.h"
#include "pou/chart_maps.h"
#include "pou/shape_function.h"

namespace invmap::pou {
namespace {

/// Allowance for the rounding of the majorants' own arithmetic (sums and
/// products of positive numbers, a few dozen operations) and of the boxes'
/// trigonometry.
constexpr double kRoundingAllowance = 1.0 + 1e-9;

/// x (x - 1) .. (x - i + 1).
double Falling(double x, int i) {
  double f = 1.0;
  for (int k = 0; k < i; ++k) f *= x - k;
  return f;
}

/// sum over i + j = k of C(k, i) |(a)_i| |(b)_j|: the k-th derivative of
/// w^a conj(w)^b at |w| = 1 has at most this norm.
double WirtingerSum(double a, double b, int k) {
  double sum = 0.0, binomial = 1.0;
  for (int i = 0; i <= k; ++i) {
    sum += binomial * std::fabs(Falling(a, i)) * std::fabs(Falling(b, k - i));
    binomial = binomial * (k - i) / (i + 1);
  }
  return sum;
}

/// Majorant of w -> scale |w| e^(i alpha arg w), a rotation of it, or (alpha
/// = 0) scale |w|, where |w| >= least.
Majorant PolarPower(double alpha, double scale, double least) {
  const double a = 0.5 * (1.0 + alpha), b = 0.5 * (1.0 - alpha);
  return {{0.0, scale * WirtingerSum(a, b, 1), scale * WirtingerSum(a, b, 2) / least,
           scale * WirtingerSum(a, b, 3) / (least * least)}};
}

Majorant FromBump(const BumpDerivativeBounds& b) { return {{b.d[0], b.d[1], b.d[2], b.d[3]}}; }

/// x as a float no smaller than x.
float RoundUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, HUGE_VALF);
  return f;
}

/// Majorant of a shape function over a box of its chart: the partials'
/// ranges there, as norms (Frobenius for orders 1 and 2, sqrt(3 2^3) times
/// the largest third partial for order 3).
Majorant ShapeOverBox(const PouSurface& s, std::int64_t chart, const double lo[2], const double hi[2]) {
  const ShapeRanges r = RangeOverBox(s.net(chart), lo, hi);
  double n0 = 0.0, n1 = 0.0, n2 = 0.0;
  for (int c = 0; c < 3; ++c) {
    n0 += r.value[c].mag() * r.value[c].mag();
    n1 += r.grad[c][0].mag() * r.grad[c][0].mag() + r.grad[c][1].mag() * r.grad[c][1].mag();
    n2 += r.hess[c][0].mag() * r.hess[c][0].mag() + 2.0 * r.hess[c][1].mag() * r.hess[c][1].mag() +
          r.hess[c][2].mag() * r.hess[c][2].mag();
  }
  return {{std::sqrt(n0), std::sqrt(n1), std::sqrt(n2), std::sqrt(24.0) * r.third}};
}

/// The box of Cartesian coordinates that holds the annular sector r0 <= r
/// <= r1, a0 <= a <= a1: its corners and the points where it crosses an axis
/// direction.
void SectorBox(double r0, double r1, double a0, double a1, double lo[2], double hi[2]) {
  lo[0] = lo[1] = HUGE_VAL;
  hi[0] = hi[1] = -HUGE_VAL;
  const auto add = [&](double r, double a) {
    const double x = r * std::cos(a), y = r * std::sin(a);
    lo[0] = std::min(lo[0], x);
    hi[0] = std::max(hi[0], x);
    lo[1] = std::min(lo[1], y);
    hi[1] = std::max(hi[1], y);
  };
  for (double r : {r0, r1})
    for (double a : {a0, a1}) add(r, a);
  for (double axis = std::ceil(a0 / (kPi / 2)) * (kPi / 2); axis <= a1; axis += kPi / 2) add(r1, axis);
  const double pad = 1e-12 * r1;
  for (int i = 0; i < 2; ++i) {
    lo[i] -= pad;
    hi[i] += pad;
  }
}

/// The polar extent of a box: least and largest |p|, and, when it avoids
/// the centre, its angles relative to a direction.
struct PolarExtent {
  double rMin = 0.0, rMax = 0.0;
  double centreAngle = 0.0;
  double corner[4] = {0, 0, 0, 0};  ///< Corner angles minus centreAngle, in (-pi, pi).
};

PolarExtent ExtentOf(const ChartBox& box) {
  PolarExtent e;
  const double nx = std::clamp(0.0, box.lo[0], box.hi[0]), ny = std::clamp(0.0, box.lo[1], box.hi[1]);
  e.rMin = Length(nx, ny) * (1.0 - 1e-15);
  for (double x : {box.lo[0], box.hi[0]})
    for (double y : {box.lo[1], box.hi[1]}) e.rMax = std::max(e.rMax, Length(x, y));
  e.rMax *= 1.0 + 1e-15;
  if (e.rMin > 0.0) {
    e.centreAngle = std::atan2(0.5 * (box.lo[1] + box.hi[1]), 0.5 * (box.lo[0] + box.hi[0]));
    int i = 0;
    for (double x : {box.lo[0], box.hi[0]})
      for (double y : {box.lo[1], box.hi[1]}) {
        double d = std::atan2(y, x) - e.centreAngle;
        d -= 2.0 * kPi * std::round(d / (2.0 * kPi));
        e.corner[i++] = d;
      }
  }
  return e;
}

/// The canonical-frame range of a box that avoids the centre, for one edge:
/// radii rho and angles phi of W.
struct CanonicalSector {
  double rho0, rho1, phi0, phi1;
};

/// How a box lies relative to one edge's transition map.
enum class EdgeSide {
  Apart,   ///< No point of the box is within the edge's support angle: its bump is zero there.
  Within,  ///< The whole box is within FormulaAngle of the edge: the sector is the box's.
  Across,  ///< The box crosses FormulaAngle and meets the support angle: the
           ///< sector holds (only) the box's points within FormulaAngle.
};

/// The box's angles relative to the edge (pou/chart_maps.h: the formula
/// holds within FormulaAngle of the edge, the bump is zero beyond
/// SupportAngle) and its canonical sector.
EdgeSide SectorOfEdge(const PouSurface& s, std::int64_t chart, int edge, const PolarExtent& e, CanonicalSector* out) {
  const int n = s.valence(chart);
  double base = e.centreAngle - 2.0 * kPi * edge / n;
  base -= 2.0 * kPi * std::round(base / (2.0 * kPi));
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double d : e.corner) {
    lo = std::min(lo, base + d);
    hi = std::max(hi, base + d);
  }
  // Atan2's rounding, a few ulps of pi.
  lo -= 1e-14;
  hi += 1e-14;
  const double formula = FormulaAngle(n), support = SupportAngle(n) * (1.0 + 1e-12);
  const double k = kFrameRadius / s.radius(chart), alpha = n / 6.0;
  if (lo > -formula && hi < formula) {
    if (!(lo < support && hi > -support)) return EdgeSide::Apart;
    *out = {k * e.rMin, k * e.rMax, alpha * lo, alpha * hi};
    return EdgeSide::Within;
  }
  // The box's angles (lo and hi may pass a half turn) as they are, and a
  // turn either way: the parts within FormulaAngle that meet the support.
  double clipLo = HUGE_VAL, clipHi = -HUGE_VAL;
  for (double turn : {-2.0 * kPi, 0.0, 2.0 * kPi}) {
    const double a = std::max(lo + turn, -formula), b = std::min(hi + turn, formula);
    if (!(a <= b) || !(a < support && b > -support)) continue;
    clipLo = std::min(clipLo, a);
    clipHi = std::max(clipHi, b);
  }
  if (!(clipLo <= clipHi)) return EdgeSide::Apart;
  *out = {k * e.rMin, k * e.rMax, alpha * clipLo, alpha * clipHi};
  return EdgeSide::Across;
}

/// |1 - rho e^(i phi)| over the sector: least where phi is nearest 0 and rho
/// nearest cos phi, largest at a corner (its square is convex in rho and
/// grows as phi leaves 0).
double SectorMin(const CanonicalSector& c) {
  const double phi = std::clamp(0.0, c.phi0, c.phi1);
  const double rho = std::clamp(std::cos(phi), c.rho0, c.rho1);
  return std::sqrt(std::max(0.0, 1.0 - 2.0 * rho * std::cos(phi) + rho * rho)) * (1.0 - 1e-12);
}
double SectorMax(const CanonicalSector& c) {
  double most = 0.0;
  for (double rho : {c.rho0, c.rho1})
    for (double phi : {c.phi0, c.phi1}) most = std::max(most, 1.0 - 2.0 * rho * std::cos(phi) + rho * rho);
  return std::sqrt(most) * (1.0 + 1e-12);
}

/// The range of arg(1 - rho e^(i phi)) over the sector (rho1 < 1). Along a
/// ray of fixed phi the argument is monotone; along an arc of radius rho it
/// is extreme where the ray from 0 touches that circle about 1: +-asin(rho)
/// at phi = -+acos(rho). So corners and those touching points hold the range.
void ArgumentRange(const CanonicalSector& c, double* lo, double* hi) {
  *lo = HUGE_VAL;
  *hi = -HUGE_VAL;
  const auto add = [&](double a) {
    *lo = std::min(*lo, a);
    *hi = std::max(*hi, a);
  };
  for (double rho : {c.rho0, c.rho1}) {
    for (double phi : {c.phi0, c.phi1}) add(std::atan2(-rho * std::sin(phi), 1.0 - rho * std::cos(phi)));
    const double touch = std::acos(std::min(rho, 1.0));
    if (c.phi0 <= -touch && -touch <= c.phi1) add(std::asin(std::min(rho, 1.0)));
    if (c.phi0 <= touch && touch <= c.phi1) add(-std::asin(std::min(rho, 1.0)));
  }
  *lo -= 1e-12;
  *hi += 1e-12;
}

}  // namespace

EvaluationSlack SlackOf(const PouSurface& surface, std::int64_t chart) {
  double largest = surface.shapeBounds(chart).value;
  for (int i = 0; i < surface.valence(chart); ++i) {
    largest = std::max(largest, surface.shapeBounds(surface.mesh().neighbor(chart, i)).value);
  }
  const double r = surface.radius(chart);
  const double ulps = largest * std::numeric_limits<double>::epsilon();
  return {0x1p10 * ulps, 0x1p14 * ulps / r, 0x1p18 * ulps / (r * r)};
}

namespace {

/// Norms of a scalar jet's value, gradient and Hessian, with an allowance.
void ScalarNorms(const Jet<double>& j, double allowance, double out[3]) {
  out[0] = std::fabs(j.v) + allowance;
  out[1] = Length(j.du, j.dv) + allowance;
  out[2] = std::sqrt(j.duu * j.duu + 2.0 * j.duv * j.duv + j.dvv * j.dvv) + allowance;
}

/// Norms of g_z = psi_z o phi_zv - psi_v for entry i of `parts`, with two
/// evaluations' rounding per coordinate.
std::array<double, 3> MismatchNorms(const BlendParts& parts, std::size_t i, const EvaluationSlack& slack) {
  double n0 = 0.0, n1 = 0.0, n2 = 0.0;
  for (int c = 0; c < 3; ++c) {
    const Jet<double> g = parts.shapes[3 * i + c] - parts.own[c];
    n0 += g.v * g.v;
    n1 += g.du * g.du + g.dv * g.dv;
    n2 += g.duu * g.duu + 2.0 * g.duv * g.duv + g.dvv * g.dvv;
  }
  return {std::sqrt(n0) + 4.0 * slack.value, std::sqrt(n1) + 4.0 * slack.first, std::sqrt(n2) + 4.0 * slack.second};
}

/// |w| = |1 - W| at a point of the chart for neighbour `edge`.
double CanonicalDistance(const PouSurface& s, std::int64_t chart, int edge, double u, double v) {
  const int n = s.valence(chart);
  double rel = std::atan2(v, u) - 2.0 * kPi * edge / n;
  rel -= 2.0 * kPi * std::round(rel / (2.0 * kPi));
  if (!(std::fabs(rel) < FormulaAngle(n))) return HUGE_VAL;  // beyond the formula: no bump
  const double rho = kFrameRadius / s.radius(chart) * Length(u, v), phi = n / 6.0 * rel;
  return Length(1.0 - rho * std::cos(phi), rho * std::sin(phi));
}

}  // namespace

void SampleBox(const PouSurface& surface, std::int64_t chart, const ChartBox& box, const BlendParts& parts,
               const EvaluationSlack& slack, BlendParts* scratch, BoxSample* out) {
  // The bumps and weights are at most 1 in size: their rounding is a few
  // thousand ulps of 1 (derivatives through the transition maps' 1 / |p|).
  constexpr double kUnit = 1e-12;
  const std::size_t count = parts.edges.size();
  Jet<double> sum = parts.ownWeight;
  for (std::size_t i = 0; i < count; ++i) sum = sum + parts.weights[i];
  const Jet<double> inverse = JetReciprocal(sum);
  ScalarNorms(sum, kUnit, out->sum);
  out->sum[0] = sum.v;
  const double u = 0.5 * (box.lo[0] + box.hi[0]), v = 0.5 * (box.lo[1] + box.hi[1]);
  const double radius = 0.5 * Length(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1]) * (1.0 + 1e-15);
  out->defined.assign(parts.defined.begin(), parts.defined.end());
  out->weight.resize(count);
  out->mismatch.resize(count);
  out->reach.assign(count, radius);
  for (std::size_t i = 0; i < count; ++i) {
    if (!parts.active.empty() && !parts.active[i]) continue;
    ScalarNorms(parts.weights[i] * inverse, kUnit, out->weight[i].data());
    out->mismatch[i] = MismatchNorms(parts, i, slack);
    if (!parts.defined[i] || parts.weights[i].v > 0.0) continue;
    // Outside z's support: the rim point nearest it instead.
    double best = HUGE_VAL, bu = u, bv = v;
    for (int a = 0; a <= 2; ++a)
      for (int b = 0; b <= 2; ++b) {
        const double pu = box.lo[0] + 0.5 * a * (box.hi[0] - box.lo[0]), pv = box.lo[1] + 0.5 * b * (box.hi[1] - box.lo[1]);
        if ((a == 1 && b == 1) || (pu == 0.0 && pv == 0.0)) continue;
        const double w = CanonicalDistance(surface, chart, parts.edges[i], pu, pv);
        if (w < best) {
          best = w;
          bu = pu;
          bv = pv;
        }
      }
    if (!(best < kFrameRadius)) continue;
    scratch->edges.assign(1, parts.edges[i]);
    scratch->active.clear();
    surface.EvaluateParts(chart, bu, bv, scratch);
    if (!scratch->defined[0]) continue;
    out->mismatch[i] = MismatchNorms(*scratch, 0, slack);
    double farthest = 0.0;
    for (double cu : {box.lo[0], box.hi[0]})
      for (double cv : {box.lo[1], box.hi[1]}) farthest = std::max(farthest, Length(cu - bu, cv - bv));
    out->reach[i] = farthest * (1.0 + 1e-15);
  }
}

bool OutsideKites(const PouSurface& surface, std::int64_t chart, const ChartBox& box) {
  const PolarExtent extent = ExtentOf(box);
  if (!(extent.rMin > 0.0)) return false;
  for (int edge = 0; edge < surface.valence(chart); ++edge) {
    CanonicalSector c;
    if (SectorOfEdge(surface, chart, edge, extent, &c) != EdgeSide::Within) continue;
    const double widest = std::max(std::fabs(c.phi0), std::fabs(c.phi1));
    if (widest < kPi / 3 && c.rho0 * std::cos(widest) * (1.0 - 1e-12) > 0.5) return true;
  }
  return false;
}

void BoundShapes(const PouSurface& surface, std::int64_t chart, const ChartBox& box, float own[3],
                 std::vector<ReachingShape>* reach) {
  const Majorant ownMajorant = ShapeOverBox(surface, chart, box.lo, box.hi);
  for (int k = 0; k < 3; ++k) own[k] = RoundUp(ownMajorant.d[k + 1]);
  const int n = surface.valence(chart);
  const PolarExtent extent = ExtentOf(box);
  const double k = kFrameRadius / surface.radius(chart);
  const double farthest = kFrameRadius * kShapeBoundExtension;
  for (int edge = 0; edge < n; ++edge) {
    // W's range: a sector (for a box across FormulaAngle, of its part within
    // it, where its sub-boxes can meet the bump), or for a box about the
    // centre the disk |W| <= rho1.
    CanonicalSector c{0.0, k * extent.rMax, -kPi, kPi};
    if (extent.rMin > 0.0 && SectorOfEdge(surface, chart, edge, extent, &c) == EdgeSide::Apart) continue;
    const double wMin = extent.rMin > 0.0 ? SectorMin(c) : std::max(0.0, 1.0 - c.rho1);
    if (!(wMin < kFrameRadius)) continue;
    const double wMax = std::min(farthest, extent.rMin > 0.0 ? SectorMax(c) : farthest);
    double argLo, argHi;
    if (extent.rMin > 0.0) {
      ArgumentRange(c, &argLo, &argHi);
    } else {
      argHi = c.rho1 < 1.0 ? std::asin(c.rho1) + 1e-12 : kPi / 2;
      argLo = -argHi;
    }
    // Where psi_z is evaluated: phi_zv of the box's points with |w| <= farthest,
    // a sector of z's chart about the direction of v (z's neighbour `mate`).
    const std::int64_t z = surface.mesh().neighbor(chart, edge);
    const int m = surface.valence(z);
    const double toOther = surface.radius(z) / kFrameRadius;
    const double toward = 2.0 * kPi * surface.mesh().mate(chart, edge) / m;
    double lo[2], hi[2];
    SectorBox(toOther * wMin, toOther * wMax, toward + 6.0 / m * argLo, toward + 6.0 / m * argHi, lo, hi);
    const Majorant other = ShapeOverBox(surface, z, lo, hi);
    ReachingShape shape;
    shape.edge = edge;
    for (int o = 0; o < 3; ++o) shape.norm[o] = RoundUp(other.d[o + 1]);
    reach->push_back(shape);
  }
}

void ReachingEdges(const PouSurface& surface, std::int64_t chart, const ChartBox& box, const ShapeMajorants& shapes,
                   BlendParts* parts) {
  const PolarExtent extent = ExtentOf(box);
  parts->edges.resize(shapes.count);
  parts->active.assign(shapes.count, 1);
  for (int i = 0; i < shapes.count; ++i) {
    parts->edges[i] = shapes.reach[i].edge;
    CanonicalSector c;
    if (extent.rMin > 0.0) {
      parts->active[i] = SectorOfEdge(surface, chart, shapes.reach[i].edge, extent, &c) != EdgeSide::Apart &&
                         SectorMin(c) < kFrameRadius;
    }
  }
}

double ThirdDerivativeBound(const PouSurface& surface, std::int64_t chart, const ChartBox& box,
                            const ShapeMajorants& shapes, const BoxSample& sample) {
  const int n = surface.valence(chart);
  const double radius = surface.radius(chart);
  const PolarExtent extent = ExtentOf(box);
  const Majorant own{{0.0, shapes.own[0], shapes.own[1], shapes.own[2]}};
  double bound = own.d[3];
  if (extent.rMax < kOwnOnly * radius) return bound * kRoundingAllowance;  // theta_v = psi_v
  if (!(extent.rMin > 0.0)) return HUGE_VAL;
  const double boxRadius = 0.5 * Length(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1]) * (1.0 + 1e-15);
  // From the centre's values along segments of the box: order k at most its
  // value at the centre plus order k + 1's bound times the radius.
  const auto chain = [](const double* at, double distance, Majorant* m) {
    m->d[2] = std::min(m->d[2], at[2] + m->d[3] * distance);
    m->d[1] = std::min(m->d[1], at[1] + m->d[2] * distance);
    m->d[0] = std::min(m->d[0], at[0] + m->d[1] * distance);
  };
  const double k = kFrameRadius / radius, alpha = n / 6.0;
  // The sum of the bumps S, from the chart's own bump xi(|p| / R) (constant
  // inside R / 4) and each reaching neighbour's.
  Majorant sum;
  if (extent.rMax > 0.25 * radius) {
    const double from = std::max(extent.rMin, 0.25 * radius);
    sum = Compose(FromBump(BoundBump(from / radius, extent.rMax / radius)), PolarPower(0.0, 1.0 / radius, from));
  }
  double least = Bump(extent.rMax / radius).f;
  std::vector<int> active;
  std::vector<Majorant> bumps, mismatches;
  for (int i = 0; i < shapes.count; ++i) {
    CanonicalSector c;
    const EdgeSide side = SectorOfEdge(surface, chart, shapes.reach[i].edge, extent, &c);
    if (side == EdgeSide::Apart) continue;
    const double wMin = SectorMin(c), wMax = SectorMax(c);
    if (!(wMin < kFrameRadius)) continue;
    // The bump reaches a box that the formula does not cover whole.
    if (side == EdgeSide::Across) return HUGE_VAL;
    if (wMax > kFrameRadius * kShapeBoundExtension || !sample.defined[i]) return HUGE_VAL;
    const std::int64_t z = surface.mesh().neighbor(chart, shapes.reach[i].edge);
    // g_z: order 3 from the majorants of its two terms.
    const Majorant w = PolarPower(alpha, k, extent.rMin);
    const Majorant phi = Compose(PolarPower(6.0 / surface.valence(z), surface.radius(z) / kFrameRadius, wMin), w);
    const Majorant shape{{0.0, shapes.reach[i].norm[0], shapes.reach[i].norm[1], shapes.reach[i].norm[2]}};
    Majorant g = Compose(shape, phi) + own;
    g.d[0] = HUGE_VAL;
    chain(sample.mismatch[i].data(), sample.reach[i], &g);
    mismatches.push_back(g);
    // beta_z = xi(|w| / (sqrt(3)/2)), positive only where |p| >= 0.1547 R.
    const Majorant wOnSupport = PolarPower(alpha, k, std::max(extent.rMin, kOwnOnly * radius));
    const Majorant argument = Compose(PolarPower(0.0, 1.0 / kFrameRadius, wMin), wOnSupport);
    const Majorant beta = Compose(FromBump(BoundBump(wMin / kFrameRadius, wMax / kFrameRadius)), argument);
    bumps.push_back(beta);
    active.push_back(i);
    for (int o = 1; o <= 3; ++o) sum.d[o] += beta.d[o];
    least = std::max(least, Bump(wMax / kFrameRadius).f);
  }
  if (bumps.empty()) return bound * kRoundingAllowance;
  sum.d[0] = HUGE_VAL;
  chain(sample.sum, boxRadius, &sum);
  // S's least value: its value at the centre less its slope times the
  // radius, or each bump's least value (xi decreases).
  least = std::max(least, sample.sum[0] - sum.d[1] * boxRadius) * (1.0 - 1e-9);
  if (!(least > 0.0)) return HUGE_VAL;
  const Majorant reciprocal =
      Compose({{1.0 / least, 1.0 / (least * least), 2.0 / (least * least * least),
                6.0 / (least * least * least * least)}},
              sum);
  for (std::size_t a = 0; a < active.size(); ++a) {
    Majorant weight = Product(bumps[a], reciprocal);
    weight.d[0] = 1.0;  // beta_z <= S
    chain(sample.weight[active[a]].data(), boxRadius, &weight);
    bound += Product(weight, mismatches[a]).d[3];
  }
  return bound * kRoundingAllowance;
}

}  // namespace invmap::pou
