#include "tests/support/test_geometries.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

namespace invmap::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kHalfSqrt2 = std::sqrt(0.5);

/// Control polygon of the unit circle as 4 rational quadratic arcs.
constexpr double kCircle[9][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}};
double CircleWeight(int i) { return i % 2 ? kHalfSqrt2 : 1.0; }
/// Circle knots: double interior knots at arbitrary (non-uniform) values; the
/// values only reparametrize the arcs, not their shape.
std::vector<double> CircleKnots(double a, double b, double c) { return {0, 0, 0, a, a, b, b, c, c, 1, 1, 1}; }

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

void Push(std::vector<double>& v, const Vec3& x, int dim) { v.insert(v.end(), x.begin(), x.begin() + dim); }

/// A B-spline patch whose control point at Greville abscissae (a, b, c)
/// is f(a, b, c) plus uniform noise of amplitude `noise` per coordinate;
/// rational patches draw weights log-uniformly in [0.6, 1.6].
Patch GrevillePatch(int dim, const std::vector<int>& degrees, const std::vector<std::vector<double>>& knots,
                    const std::function<Vec3(double, double, double)>& f, double noise, bool rational,
                    std::mt19937_64& rng) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = degrees;
  patch.knots = knots;
  const int pd = static_cast<int>(degrees.size());
  int cnt[3] = {1, 1, 1};
  for (int d = 0; d < pd; ++d) {
    cnt[d] = static_cast<int>(knots[d].size()) - degrees[d] - 1;
    patch.counts.push_back(cnt[d]);
  }
  for (int k = 0; k < cnt[2]; ++k)
    for (int j = 0; j < cnt[1]; ++j)
      for (int i = 0; i < cnt[0]; ++i) {
        const double a = Greville(knots[0], degrees[0], i);
        const double b = pd > 1 ? Greville(knots[1], degrees[1], j) : 0.0;
        const double c = pd > 2 ? Greville(knots[2], degrees[2], k) : 0.0;
        Vec3 x = f(a, b, c);
        for (int e = 0; e < dim; ++e) x[e] += Uniform(rng, -noise, noise);
        Push(patch.points, x, dim);
        if (rational) patch.weights.push_back(std::exp(Uniform(rng, std::log(0.6), std::log(1.6))));
      }
  return patch;
}

/// A Bezier patch from a reference cell, moved so its control centroid is at `at`.
Patch BezierFrom(const RefCell& cell, CellType type, const Vec3& at) {
  Patch patch;
  patch.kind = Patch::Kind::Bezier;
  patch.cell = type;
  const int nf = type == CellType::Quad || type == CellType::Wedge ? 2 : type == CellType::Hex ? 3 : 1;
  for (int f = 0; f < nf; ++f) patch.degrees.push_back(cell.degrees[f]);
  const int dim = cell.ambientDim;
  const int n = static_cast<int>(cell.points.size()) / dim;
  double centroid[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) centroid[k] += cell.points[i * dim + k] / n;
  patch.points = cell.points;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) patch.points[i * dim + k] += at[k] - centroid[k];
  patch.weights = cell.weights;
  return patch;
}


}  // namespace

/// Mesh patch of linear cells of `type` over a structured nx x ny x nz grid
/// of vertices f(i / nx, j / ny, k / nz) (tri and quad: nz = 0; line: ny =
/// nz = 0), FE vertex order; tets split each cube into 6 (Kuhn), wedges
/// each quad prism into 2.
Patch GridMesh(CellType type, int dim, int nx, int ny, int nz, const std::function<Vec3(double, double, double)>& f) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = type;
  const auto id = [&](int i, int j, int k) { return static_cast<std::int64_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Push(patch.points, f(static_cast<double>(i) / nx, ny ? static_cast<double>(j) / ny : 0.0,
                             nz ? static_cast<double>(k) / nz : 0.0),
             dim);
      }
  auto& c = patch.cells;
  for (int k = 0; k < std::max(nz, 1); ++k)
    for (int j = 0; j < std::max(ny, 1); ++j)
      for (int i = 0; i < nx; ++i) {
        switch (type) {
          case CellType::Line:
            c.insert(c.end(), {id(i, 0, 0), id(i + 1, 0, 0)});
            break;
          case CellType::Tri:
            c.insert(c.end(), {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0)});
            c.insert(c.end(), {id(i, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0)});
            break;
          case CellType::Quad:
            c.insert(c.end(), {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0)});
            break;
          case CellType::Hex:
            c.insert(c.end(), {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                               id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
            break;
          case CellType::Wedge:
            c.insert(c.end(), {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                               id(i + 1, j + 1, k + 1)});
            c.insert(c.end(), {id(i, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                               id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
            break;
          case CellType::Tet: {
            static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
            for (const auto& perm : kPerm) {
              int at[3] = {i, j, k};
              std::int64_t v[4];
              v[0] = id(at[0], at[1], at[2]);
              for (int s = 0; s < 3; ++s) {
                ++at[perm[s]];
                v[s + 1] = id(at[0], at[1], at[2]);
              }
              c.insert(c.end(), v, v + 4);
            }
            break;
          }
        }
      }
  return patch;
}

// ---------------------------------------------------------------------------
// Analytic shapes.

Geometry NurbsSphere(const Vec3& c, double r) {
  const double prof[5][2] = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}};  // (rho, z) of the meridian
  const double profW[5] = {1, kHalfSqrt2, 1, kHalfSqrt2, 1};
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2, 2};
  patch.counts = {9, 5};
  patch.knots = {CircleKnots(0.25, 0.5, 0.75), {0, 0, 0, 0.5, 0.5, 1, 1, 1}};
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 9; ++i) {
      patch.points.insert(patch.points.end(), {c[0] + r * prof[j][0] * kCircle[i][0],
                                               c[1] + r * prof[j][0] * kCircle[i][1], c[2] + r * prof[j][1]});
      patch.weights.push_back(CircleWeight(i) * profW[j]);
    }
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(std::move(patch));
  return g;
}

double SphereDistance(const Vec3& c, double r, const double* p) {
  const double d = std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2]));
  return std::fabs(d - r);
}

Geometry NurbsTorus(const Vec3& c, double big, double small) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2, 2};
  patch.counts = {9, 9};
  patch.knots = {CircleKnots(0.2, 0.45, 0.8), {0, 0, 0, 1, 1, 3, 3, 4, 4, 7, 7, 7}};
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) {
      const double rho = big + small * kCircle[j][0];
      patch.points.insert(patch.points.end(),
                          {c[0] + rho * kCircle[i][0], c[1] + rho * kCircle[i][1], c[2] + small * kCircle[j][1]});
      patch.weights.push_back(CircleWeight(i) * CircleWeight(j));
    }
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(std::move(patch));
  return g;
}

double TorusDistance(const Vec3& c, double big, double small, const double* p) {
  const double x = p[0] - c[0], y = p[1] - c[1], z = p[2] - c[2];
  const double rho = std::sqrt(x * x + y * y) - big;
  return std::fabs(std::sqrt(rho * rho + z * z) - small);
}

Frame TiltedFrame(const Vec3& origin) {
  // Rotation by Euler angles (0.3, 0.7, -0.4): its first two columns.
  const double a = 0.3, b = 0.7, g = -0.4;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cg = std::cos(g),
               sg = std::sin(g);
  Frame f;
  f.origin = origin;
  f.e1 = {ca * cb, sa * cb, -sb};
  f.e2 = {ca * sb * sg - sa * cg, sa * sb * sg + ca * cg, cb * sg};
  return f;
}

Geometry NurbsCircle(int dim, const Frame& frame, double r) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2};
  patch.counts = {9};
  patch.knots = {CircleKnots(0.3, 0.5, 0.65)};
  for (int i = 0; i < 9; ++i) {
    Vec3 x;
    for (int k = 0; k < 3; ++k) x[k] = frame.origin[k] + r * (kCircle[i][0] * frame.e1[k] + kCircle[i][1] * frame.e2[k]);
    Push(patch.points, x, dim);
    patch.weights.push_back(CircleWeight(i));
  }
  Geometry g;
  g.dimension = dim;
  g.patches.push_back(std::move(patch));
  return g;
}

namespace {
/// In-plane radius and out-of-plane distance of p in `frame`.
void PlaneCoordinates(int dim, const Frame& frame, const double* p, double* rho, double* height) {
  double q[3] = {0, 0, 0};
  for (int k = 0; k < dim; ++k) q[k] = p[k] - frame.origin[k];
  double a = 0, b = 0;
  for (int k = 0; k < 3; ++k) a += q[k] * frame.e1[k], b += q[k] * frame.e2[k];
  double h2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double off = q[k] - a * frame.e1[k] - b * frame.e2[k];
    h2 += off * off;
  }
  *rho = std::sqrt(a * a + b * b);
  *height = dim == 2 ? 0.0 : std::sqrt(h2);
}
}  // namespace

double CircleDistance(int dim, const Frame& frame, double r, const double* p) {
  double rho, h;
  PlaneCoordinates(dim, frame, p, &rho, &h);
  return std::sqrt((rho - r) * (rho - r) + h * h);
}

Geometry NurbsAnnulus(int dim, const Frame& frame, double r1, double r2) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {2, 1};
  patch.counts = {9, 2};
  patch.knots = {CircleKnots(0.25, 0.5, 0.75), {-1, -1, 2, 2}};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 9; ++i) {
      const double r = j ? r2 : r1;
      Vec3 x;
      for (int k = 0; k < 3; ++k)
        x[k] = frame.origin[k] + r * (kCircle[i][0] * frame.e1[k] + kCircle[i][1] * frame.e2[k]);
      Push(patch.points, x, dim);
      patch.weights.push_back(CircleWeight(i));
    }
  Geometry g;
  g.dimension = dim;
  g.patches.push_back(std::move(patch));
  return g;
}

double AnnulusDistance(int dim, const Frame& frame, double r1, double r2, const double* p) {
  double rho, h;
  PlaneCoordinates(dim, frame, p, &rho, &h);
  const double gap = std::max({0.0, r1 - rho, rho - r2});
  return std::sqrt(gap * gap + h * h);
}

// ---------------------------------------------------------------------------
// Brute-force geometries.

std::vector<double> RandomKnots(int p, int distinct, int repeatEvery, bool clamped, std::mt19937_64& rng) {
  std::vector<double> gaps(distinct + 1);
  double total = 0.0;
  for (double& g : gaps) total += (g = Uniform(rng, 0.3, 1.7));
  std::vector<double> knots;
  const double h = 1.0 / (distinct + 1);
  for (int e = 0; e <= p; ++e) knots.push_back(clamped ? 0.0 : -(p - e) * h);
  double t = 0.0;
  for (int i = 0; i < distinct; ++i) {
    t += gaps[i] / total;
    int mult = 1;
    if (p >= 2 && std::uniform_int_distribution<int>(0, repeatEvery - 1)(rng) == 0) {
      mult = std::uniform_int_distribution<int>(2, p)(rng);
    }
    for (int m = 0; m < mult; ++m) knots.push_back(t);
  }
  for (int e = 0; e <= p; ++e) knots.push_back(clamped ? 1.0 : 1.0 + e * h);
  return knots;
}

double Greville(const std::vector<double>& knots, int p, int i) {
  const int n = static_cast<int>(knots.size()) - p - 1;
  double sum = 0.0;
  for (int k = 1; k <= p; ++k) sum += knots[i + k];
  const double lo = knots[p], hi = knots[n];
  return (sum / p - lo) / (hi - lo);
}

Geometry WavySurfaces() {
  std::mt19937_64 rng(0x5eed0001);
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(GrevillePatch(
      3, {3, 3}, {RandomKnots(3, 22, 4, true, rng), RandomKnots(3, 16, 4, true, rng)},
      [](double a, double b, double) {
        return Vec3{a, 0.8 * b, 0.08 * std::sin(9 * a) * std::cos(7 * b) + 0.05 * std::sin(17 * a * b)};
      },
      0.01, false, rng));
  g.patches.push_back(GrevillePatch(
      3, {2, 3}, {RandomKnots(2, 14, 5, false, rng), RandomKnots(3, 9, 3, true, rng)},
      [](double a, double b, double) {
        return Vec3{0.1 + 0.8 * a, 0.1 + 0.6 * b, 0.2 + 0.1 * (a - 0.5) + 0.06 * std::sin(5 * a + 3 * b)};
      },
      0.01, true, rng));
  return g;
}

Geometry BSplineCurves(int dim) {
  std::mt19937_64 rng(0x5eed0002 + dim);
  Geometry g;
  g.dimension = dim;
  if (dim == 2) {
    g.patches.push_back(GrevillePatch(
        2, {3}, {RandomKnots(3, 149, 6, true, rng)},
        [](double t, double, double) {
          const double r = 0.15 + 0.85 * t, a = 5 * kPi * t;
          return Vec3{r * std::cos(a), r * std::sin(a), 0};
        },
        0.01, false, rng));
    g.patches.push_back(GrevillePatch(
        2, {2}, {RandomKnots(2, 59, 4, true, rng)},
        [](double t, double, double) { return Vec3{2 * t - 1, -1.2 + 0.15 * std::sin(20 * t), 0}; }, 0.01, true, rng));
  } else {
    g.patches.push_back(GrevillePatch(
        3, {4}, {RandomKnots(4, 119, 1000000, false, rng)},
        [](double t, double, double) {
          const double a = 6 * kPi * t;
          return Vec3{0.6 * std::cos(a), 0.6 * std::sin(a), 0.8 * t};
        },
        0.01, false, rng));
    g.patches.push_back(GrevillePatch(
        3, {1}, {RandomKnots(1, 49, 1000000, true, rng)},
        [](double t, double, double) { return Vec3{0.3 + 0.5 * std::sin(7 * t), -0.2 + 0.4 * t, 0.4 + 0.3 * std::cos(9 * t)}; },
        0.02, false, rng));
    g.patches.push_back(GrevillePatch(
        3, {5}, {RandomKnots(5, 20, 3, true, rng)},
        [](double t, double, double) { return Vec3{-1 + 2 * t, 0.9 * std::cos(4 * t), 0.4 * std::sin(6 * t)}; }, 0.02,
        true, rng));
  }
  return g;
}

Geometry BSplineVolumes() {
  std::mt19937_64 rng(0x5eed0003);
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(GrevillePatch(
      3, {2, 2, 3},
      {RandomKnots(2, 5, 3, true, rng), RandomKnots(2, 4, 2, true, rng), RandomKnots(3, 3, 2, true, rng)},
      [](double a, double b, double c) {
        const double angle = 1.2 * a, rho = 1 + 0.4 * b + 0.05 * std::sin(6 * c);
        return Vec3{rho * std::cos(angle), rho * std::sin(angle), 0.5 * c + 0.08 * std::sin(5 * a) + 0.1 * b * c};
      },
      0.005, false, rng));
  g.patches.push_back(GrevillePatch(
      3, {2, 2, 2}, {RandomKnots(2, 1, 1000000, true, rng), RandomKnots(2, 1, 1000000, true, rng), RandomKnots(2, 1, 1000000, true, rng)},
      [](double a, double b, double c) {
        return Vec3{-0.8 + 0.6 * a + 0.1 * b * b, 0.6 * b + 0.1 * std::sin(3 * c), 0.5 * c + 0.1 * a * b};
      },
      0.01, true, rng));
  return g;
}

Geometry QuadraticMesh(bool hexes) {
  Geometry g;
  g.dimension = 3;
  if (hexes) {
    const int n[3] = {6, 5, 4};
    const auto map = [](double a, double b, double c) {
      const double rho = 0.8 + 0.5 * b, angle = 1.4 * a;
      return Vec3{rho * std::cos(angle), rho * std::sin(angle), 0.6 * c + 0.1 * std::sin(3 * a) + 0.05 * b * b};
    };
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          Patch patch;
          patch.kind = Patch::Kind::Bezier;
          patch.cell = CellType::Hex;
          patch.degrees = {2, 2, 2};
          for (int c = 0; c < 3; ++c)
            for (int b = 0; b < 3; ++b)
              for (int a = 0; a < 3; ++a) {
                Push(patch.points, map((i + 0.5 * a) / n[0], (j + 0.5 * b) / n[1], (k + 0.5 * c) / n[2]), 3);
              }
          g.patches.push_back(std::move(patch));
        }
  } else {
    const int n[3] = {4, 4, 3};
    const auto map = [](double a, double b, double c) {
      const double angle = 0.8 * c, x = a - 0.5, y = b - 0.5;
      return Vec3{x * std::cos(angle) - y * std::sin(angle) + 0.1 * c * c,
                  x * std::sin(angle) + y * std::cos(angle), 1.2 * c + 0.1 * std::sin(3 * a)};
    };
    static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    Patch mesh;
    mesh.kind = Patch::Kind::BezierCells;
    mesh.cellOffsets.push_back(0);
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i)
          for (const auto& perm : kPerm) {
            // Kuhn simplex: walk from the cube's low corner along the axes in perm order.
            double v[4][3];
            int at[3] = {i, j, k};
            for (int s = 0; s < 4; ++s) {
              for (int e = 0; e < 3; ++e) v[s][e] = static_cast<double>(at[e]) / n[e];
              if (s < 3) ++at[perm[s]];
            }
            const double e1[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
            const double e2[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
            const double e3[3] = {v[3][0] - v[0][0], v[3][1] - v[0][1], v[3][2] - v[0][2]};
            const double det = e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0]) +
                               e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]);
            if (det < 0) std::swap(v[1], v[2]);  // positive orientation
            mesh.cellTypes.push_back(CellType::Tet);
            mesh.cellDegrees.insert(mesh.cellDegrees.end(), {2, 0, 0});
            for (int a3 = 0; a3 <= 2; ++a3)
              for (int a2 = 0; a2 + a3 <= 2; ++a2)
                for (int a1 = 0; a1 + a2 + a3 <= 2; ++a1) {
                  const int a0 = 2 - a1 - a2 - a3;
                  double x[3];
                  for (int e = 0; e < 3; ++e) x[e] = 0.5 * (a0 * v[0][e] + a1 * v[1][e] + a2 * v[2][e] + a3 * v[3][e]);
                  Push(mesh.points, map(x[0], x[1], x[2]), 3);
                }
            mesh.cellOffsets.push_back(static_cast<std::int64_t>(mesh.points.size() / 3));
          }
    g.patches.push_back(std::move(mesh));
  }
  return g;
}

Patch BumpySphereMesh(int nLon, int nLat, const Vec3& c, double r) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Tri;
  const auto vertex = [&](double theta, double phi) {
    const double rr = r * (1 + 0.04 * std::sin(8 * theta) * std::sin(6 * phi) + 0.02 * std::cos(13 * theta + phi));
    patch.points.insert(patch.points.end(), {c[0] + rr * std::sin(phi) * std::cos(theta),
                                             c[1] + rr * std::sin(phi) * std::sin(theta), c[2] + rr * std::cos(phi)});
  };
  vertex(0, 0);  // north pole: vertex 0
  for (int k = 1; k < nLat; ++k)
    for (int j = 0; j < nLon; ++j) vertex(2 * kPi * j / nLon, kPi * k / nLat);
  vertex(0, kPi);  // south pole
  const std::int64_t south = 1 + static_cast<std::int64_t>(nLat - 1) * nLon;
  const auto ring = [&](int k, int j) { return 1 + static_cast<std::int64_t>(k - 1) * nLon + (j % nLon); };
  for (int j = 0; j < nLon; ++j) patch.cells.insert(patch.cells.end(), {0, ring(1, j), ring(1, j + 1)});
  for (int k = 1; k + 1 < nLat; ++k)
    for (int j = 0; j < nLon; ++j) {
      patch.cells.insert(patch.cells.end(), {ring(k, j), ring(k + 1, j), ring(k + 1, j + 1)});
      patch.cells.insert(patch.cells.end(), {ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)});
    }
  for (int j = 0; j < nLon; ++j) patch.cells.insert(patch.cells.end(), {ring(nLat - 1, j), south, ring(nLat - 1, j + 1)});
  return patch;
}

Geometry MixedVolumeMesh() {
  const auto map = [](double x, double y, double z) {
    return Vec3{x + 0.15 * y * y + 0.05 * z, y + 0.1 * std::sin(2 * x) + 0.05 * z * x, z + 0.1 * x * y};
  };
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(GridMesh(CellType::Hex, 3, 3, 3, 2, map));
  g.patches.push_back(GridMesh(CellType::Wedge, 3, 3, 3, 2, [&](double a, double b, double c) { return map(1 + a, b, c); }));
  g.patches.push_back(GridMesh(CellType::Tet, 3, 3, 3, 2, [&](double a, double b, double c) { return map(1 + a, b, 1 + c); }));
  return g;
}

Patch WavyHeightField(int n, int dim) {
  return GridMesh(CellType::Tri, dim, n, n, 0, [](double a, double b, double) {
    return Vec3{a + 0.2 * b * b, b, 0.05 * std::sin(12 * a) * std::cos(9 * b) + 0.03 * std::sin(25 * a * b)};
  });
}

Geometry MixedGeometry3() {
  std::mt19937_64 rng(0x5eed0004);
  Geometry g;
  g.dimension = 3;
  // 0: rational B-spline surface.
  g.patches.push_back(GrevillePatch(
      3, {2, 3}, {RandomKnots(2, 9, 3, true, rng), RandomKnots(3, 7, 3, true, rng)},
      [](double a, double b, double) { return Vec3{a, b, 0.1 * std::sin(6 * a) * std::cos(5 * b)}; }, 0.01, true, rng));
  // 1-2: curved Bezier tri (rational, cubic) and quad [2, 3].
  g.patches.push_back(BezierFrom(RandomCurvedCell(kernels::CellType::Tri, 3, true, 3, rng), CellType::Tri, {0.5, 0.5, 0.5}));
  g.patches.push_back(
      BezierFrom(RandomCurvedCell(kernels::CellType::Quad, {{2, 3, 0}}, false, 3, rng), CellType::Quad, {1.6, 0.4, 0.3}));
  // 3: linear tri mesh, shifted.
  {
    Patch mesh = WavyHeightField(20, 3);
    for (std::size_t i = 0; i < mesh.points.size(); i += 3) mesh.points[i] += 1.3, mesh.points[i + 2] -= 0.5;
    g.patches.push_back(std::move(mesh));
  }
  // 4: cubic B-spline curve (a helix).
  g.patches.push_back(GrevillePatch(
      3, {3}, {RandomKnots(3, 29, 4, true, rng)},
      [](double t, double, double) {
        return Vec3{0.5 + 0.3 * std::cos(8 * t), 0.5 + 0.3 * std::sin(8 * t), 0.2 + 0.6 * t};
      },
      0.01, false, rng));
  // 5: bilinear (non-planar) quad mesh.
  g.patches.push_back(GridMesh(CellType::Quad, 3, 10, 10, 0, [&](double a, double b, double) {
    return Vec3{-1.2 + 0.8 * a, 0.8 * b, 0.2 * std::sin(7 * a * b) + Uniform(rng, -0.02, 0.02)};
  }));
  // 6: Bezier wedge [2, 1].
  g.patches.push_back(
      BezierFrom(RandomCurvedCell(kernels::CellType::Wedge, {{2, 1, 0}}, false, 3, rng), CellType::Wedge, {-0.6, 1.5, 0.3}));
  // 7-9: linear tet, hex and wedge meshes of perturbed grids.
  const auto wobble = [&](double ox) {
    return [&rng, ox](double a, double b, double c) {
      return Vec3{ox + 0.5 * a + Uniform(rng, -0.02, 0.02), 1.2 + 0.5 * b + Uniform(rng, -0.02, 0.02),
                  -0.6 + 0.4 * c + 0.1 * a * b};
    };
  };
  g.patches.push_back(GridMesh(CellType::Tet, 3, 3, 3, 2, wobble(0.0)));
  g.patches.push_back(GridMesh(CellType::Hex, 3, 3, 3, 2, wobble(0.7)));
  g.patches.push_back(GridMesh(CellType::Wedge, 3, 3, 3, 2, wobble(1.4)));
  // 10: rational Bezier line of degree 4; 11: rational quadratic Bezier tet;
  // 12: a polyline mesh; 13: Bezier hex [2, 2, 1].
  g.patches.push_back(BezierFrom(RandomCurvedCell(kernels::CellType::Line, 4, true, 3, rng), CellType::Line, {0.3, -0.6, 0.2}));
  g.patches.push_back(BezierFrom(RandomCurvedCell(kernels::CellType::Tet, 2, true, 3, rng), CellType::Tet, {1.2, -0.7, 0.0}));
  g.patches.push_back(GridMesh(CellType::Line, 3, 30, 0, 0, [](double t, double, double) {
    return Vec3{-1 + 2 * t, -1.0 + 0.2 * std::sin(9 * t), 0.8 + 0.2 * std::cos(5 * t)};
  }));
  g.patches.push_back(
      BezierFrom(RandomCurvedCell(kernels::CellType::Hex, {{2, 2, 1}}, false, 3, rng), CellType::Hex, {-0.8, -0.6, -0.2}));
  // 14: a BezierCells patch of mixed types and degrees (a high-order mesh);
  // the polynomial cells get unit weights since weights are per patch.
  {
    Patch mixed;
    mixed.kind = Patch::Kind::BezierCells;
    mixed.cellOffsets.push_back(0);
    const Patch parts[3] = {
        BezierFrom(RandomCurvedCell(kernels::CellType::Tri, 2, true, 3, rng), CellType::Tri, {2.3, 1.0, 0.0}),
        BezierFrom(RandomCurvedCell(kernels::CellType::Quad, {{3, 2, 0}}, false, 3, rng), CellType::Quad, {2.5, 0.0, 0.6}),
        BezierFrom(RandomCurvedCell(kernels::CellType::Wedge, {{1, 2, 0}}, true, 3, rng), CellType::Wedge, {2.3, -1.0, 0.0})};
    for (const Patch& part : parts) {
      mixed.cellTypes.push_back(part.cell);
      for (int f = 0; f < 3; ++f) mixed.cellDegrees.push_back(f < static_cast<int>(part.degrees.size()) ? part.degrees[f] : 0);
      mixed.points.insert(mixed.points.end(), part.points.begin(), part.points.end());
      const std::size_t n = part.points.size() / 3;
      if (part.weights.empty()) {
        mixed.weights.insert(mixed.weights.end(), n, 1.0);
      } else {
        mixed.weights.insert(mixed.weights.end(), part.weights.begin(), part.weights.end());
      }
      mixed.cellOffsets.push_back(static_cast<std::int64_t>(mixed.points.size() / 3));
    }
    g.patches.push_back(std::move(mixed));
  }
  return g;
}

Geometry MixedGeometry2() {
  std::mt19937_64 rng(0x5eed0005);
  Geometry g;
  g.dimension = 2;
  // 0: a curved quadrilateral region (full rank in 2D).
  g.patches.push_back(GrevillePatch(
      2, {2, 2}, {RandomKnots(2, 7, 3, true, rng), RandomKnots(2, 5, 3, true, rng)},
      [](double a, double b, double) {
        const double angle = 2.0 * a, rho = 0.6 + 0.5 * b;
        return Vec3{rho * std::cos(angle), rho * std::sin(angle), 0};
      },
      0.01, false, rng));
  // 1: a planar linear triangle mesh.
  {
    Patch mesh = WavyHeightField(16, 2);
    for (std::size_t i = 0; i < mesh.points.size(); i += 2) mesh.points[i] += 1.3, mesh.points[i + 1] -= 1.2;
    g.patches.push_back(std::move(mesh));
  }
  // 2: a cubic B-spline curve through the scene.
  g.patches.push_back(GrevillePatch(
      2, {3}, {RandomKnots(3, 39, 4, true, rng)},
      [](double t, double, double) { return Vec3{-1.2 + 3 * t, 0.3 * std::sin(9 * t), 0}; }, 0.02, false, rng));
  // 3-5: a quadratic Bezier tri, a rational cubic Bezier line, a C-shaped quad.
  g.patches.push_back(BezierFrom(RandomCurvedCell(kernels::CellType::Tri, 2, false, 2, rng), CellType::Tri, {-1.0, -0.8, 0}));
  g.patches.push_back(BezierFrom(RandomCurvedCell(kernels::CellType::Line, 3, true, 2, rng), CellType::Line, {0.2, -1.3, 0}));
  g.patches.push_back(BezierFrom(CShapedQuad(4), CellType::Quad, {-1.8, 1.2, 0}));
  // 6-7: bilinear quad mesh and a polyline.
  g.patches.push_back(GridMesh(CellType::Quad, 2, 6, 6, 0, [&](double a, double b, double) {
    return Vec3{2.0 + 0.8 * a + Uniform(rng, -0.03, 0.03), 0.2 + 0.8 * b + 0.2 * a * a, 0};
  }));
  g.patches.push_back(GridMesh(CellType::Line, 2, 25, 0, 0, [](double t, double, double) {
    return Vec3{0.5 + 0.6 * std::cos(5 * t), 1.6 + 0.3 * std::sin(5 * t), 0};
  }));
  return g;
}

// ---------------------------------------------------------------------------
// Queries.

Vec3 RandomDirection(int dim, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (;;) {
    Vec3 v{{normal(rng), normal(rng), dim == 3 ? normal(rng) : 0.0}};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n < 1e-3) continue;
    for (double& x : v) x /= n;
    return v;
  }
}

int ScaledCount(int count) {
  static const double fraction = [] {
    const char* text = std::getenv("INVMAP_ENGINE_QUERY_FRACTION");
    const double f = text ? std::atof(text) : 1.0;
    return f > 0.0 && f <= 1.0 ? f : 1.0;
  }();
  return count > 0 ? std::max(1, static_cast<int>(std::lround(count * fraction))) : 0;
}

QuerySet MakeQueries(const std::vector<PatchCell>& cells, int dim, double size, const QueryMix& mix, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  QuerySet q;
  q.dim = dim;
  // Cells grouped by patch, so every patch is sampled equally often.
  std::vector<std::vector<std::size_t>> byPatch;
  std::vector<std::size_t> fullRank;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::size_t patch = static_cast<std::size_t>(cells[c].patch);
    if (byPatch.size() <= patch) byPatch.resize(patch + 1);
    byPatch[patch].push_back(c);
    if (cells[c].cell.paramDim() == dim) fullRank.push_back(c);
  }
  byPatch.erase(std::remove_if(byPatch.begin(), byPatch.end(), [](const auto& v) { return v.empty(); }), byPatch.end());
  const auto pick = [&](const std::vector<std::size_t>& from) {
    return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng)];
  };
  const auto sample = [&](std::size_t c) {
    const RefCell& cell = cells[c].cell;
    const std::array<double, 3> u = RandomRefPoint(cell.type, rng);
    Vec3 x{{0, 0, 0}};
    RefEvaluate(cell, u.data(), x.data());
    return x;
  };
  const auto add = [&](int count, double lo, double hi, const char* kind) {
    count = ScaledCount(count);
    for (int i = 0; i < count; ++i) {
      const std::vector<std::size_t>& patch = byPatch[std::uniform_int_distribution<std::size_t>(0, byPatch.size() - 1)(rng)];
      Vec3 x = sample(pick(patch));
      if (hi > 0) {
        const Vec3 dir = RandomDirection(dim, rng);
        const double t = Uniform(rng, lo, hi) * size;
        for (int k = 0; k < dim; ++k) x[k] += t * dir[k];
      }
      q.Add(x.data(), kind);
    }
  };
  add(mix.on, 0, 0, "on");
  add(mix.near, 0, mix.nearFraction, "near");
  add(mix.mid, 0.05, 0.5, "mid");
  add(mix.far, 1.5, 5.0, "far");
  for (int i = 0; i < ScaledCount(mix.inside) && !fullRank.empty(); ++i) {
    const Vec3 x = sample(pick(fullRank));
    q.Add(x.data(), "inside");
  }
  return q;
}

}  // namespace invmap::testing
