#include "bench/peers/workloads.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include "bench/peers/peer.h"
#include "io/gmsh_reader.h"
#include "samples/sample_geometries.h"

namespace invmap::bench {
namespace {

/// Uniform double in [0, 1) from the top 53 bits: the same on every standard
/// library, unlike std::uniform_real_distribution.
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double Uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * Uniform(rng); }

/// Index of the knot span holding u (clamped knot vector, n control points).
int FindSpan(const std::vector<double>& knots, int p, int n, double u) {
  if (u >= knots[n]) {
    // The last non-empty span closes the domain on the right.
    int span = n - 1;
    while (span > p && knots[span] == knots[span + 1]) --span;
    return span;
  }
  if (u <= knots[p]) return p;
  const auto it = std::upper_bound(knots.begin() + p, knots.begin() + n + 1, u);
  return static_cast<int>(it - knots.begin()) - 1;
}

/// The p + 1 non-zero B-spline basis functions at u on `span` (The NURBS Book, A2.2).
void BasisFunctions(const std::vector<double>& knots, int p, int span, double u, double* basis) {
  double left[16], right[16];
  basis[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
}

/// Normal-direction derivative of a surface patch by central differences
/// (only used to place points near the surface, so the accuracy is ample).
std::array<double, 3> SurfaceNormal(const Patch& patch, double u, double v) {
  double lo[2], hi[2];
  PatchRange(patch, 0, &lo[0], &hi[0]);
  PatchRange(patch, 1, &lo[1], &hi[1]);
  const double h = 1e-6;
  double d[2][3];
  const double uv[2] = {u, v};
  for (int dir = 0; dir < 2; ++dir) {
    double a[2] = {uv[0], uv[1]}, b[2] = {uv[0], uv[1]};
    a[dir] = std::max(lo[dir], uv[dir] - h);
    b[dir] = std::min(hi[dir], uv[dir] + h);
    double pa[3], pb[3];
    EvaluatePatch(patch, 3, a, pa);
    EvaluatePatch(patch, 3, b, pb);
    for (int k = 0; k < 3; ++k) d[dir][k] = (pb[k] - pa[k]) / (b[dir] - a[dir]);
  }
  std::array<double, 3> n = {d[0][1] * d[1][2] - d[0][2] * d[1][1], d[0][2] * d[1][0] - d[0][0] * d[1][2],
                             d[0][0] * d[1][1] - d[0][1] * d[1][0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& x : n) x /= len;
  return n;
}

/// Near points of a surface patch: a uniform parameter, then an offset along
/// the normal of up to `offset` either way.
PointSet SurfaceNearPoints(const Patch& patch, std::int64_t count, double offset, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = "near";
  set.dim = 3;
  set.coords.reserve(3 * count);
  double lo[2], hi[2];
  PatchRange(patch, 0, &lo[0], &hi[0]);
  PatchRange(patch, 1, &lo[1], &hi[1]);
  for (std::int64_t i = 0; i < count; ++i) {
    const double uv[2] = {Uniform(rng, lo[0], hi[0]), Uniform(rng, lo[1], hi[1])};
    double x[3];
    EvaluatePatch(patch, 3, uv, x);
    const std::array<double, 3> n = SurfaceNormal(patch, uv[0], uv[1]);
    const double s = Uniform(rng, -offset, offset);
    for (int k = 0; k < 3; ++k) set.coords.push_back(x[k] + s * n[k]);
  }
  return set;
}

/// Points beyond the boundary of the wavy surface over [0, 1]^2: x and y in
/// [-0.5, 1.5]^2 outside the unit square, z over the surface's height and more.
PointSet SurfaceFarPoints(std::int64_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = "far";
  set.dim = 3;
  set.coords.reserve(3 * count);
  while (set.count() < count) {
    const double x = Uniform(rng, -0.5, 1.5), y = Uniform(rng, -0.5, 1.5), z = Uniform(rng, -0.5, 0.7);
    if (x >= 0.0 && x <= 1.0 && y >= 0.0 && y <= 1.0) continue;
    set.coords.insert(set.coords.end(), {x, y, z});
  }
  return set;
}

/// Points uniform in a box.
PointSet BoxPoints(const std::string& name, const double* lo, const double* hi, int dim, std::int64_t count,
                   std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = name;
  set.dim = dim;
  set.coords.reserve(dim * count);
  for (std::int64_t i = 0; i < count; ++i) {
    for (int k = 0; k < dim; ++k) set.coords.push_back(Uniform(rng, lo[k], hi[k]));
  }
  return set;
}

/// 2D points for the curve: 70% uniform in its box grown by a quarter on each
/// side, 30% within 1e-3 of the box diagonal of a point of its evolute (the
/// centers of curvature, where the closest point jumps and Newton solves from
/// a nearby seed converge to the wrong branch).
PointSet CurvePoints(const Patch& patch, std::int64_t count, std::uint64_t seed) {
  double t0, t1;
  PatchRange(patch, 0, &t0, &t1);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int i = 0; i <= 2000; ++i) {
    const double t = t0 + (t1 - t0) * i / 2000.0;
    double x[2];
    EvaluatePatch(patch, 2, &t, x);
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  }
  const double size = std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
  double boxLo[2], boxHi[2];
  for (int k = 0; k < 2; ++k) {
    const double grow = 0.25 * (hi[k] - lo[k]);
    boxLo[k] = lo[k] - grow;
    boxHi[k] = hi[k] + grow;
  }
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = "plane + evolute";
  set.dim = 2;
  set.coords.reserve(2 * count);
  const double h = 1e-4;
  while (set.count() < count) {
    if (Uniform(rng) < 0.7) {
      set.coords.push_back(Uniform(rng, boxLo[0], boxHi[0]));
      set.coords.push_back(Uniform(rng, boxLo[1], boxHi[1]));
      continue;
    }
    // Center of curvature by central differences (away from the ends).
    const double t = Uniform(rng, t0 + 2 * h, t1 - 2 * h);
    double a[2], b[2], c[2];
    const double ta = t - h, tc = t + h;
    EvaluatePatch(patch, 2, &ta, a);
    EvaluatePatch(patch, 2, &t, b);
    EvaluatePatch(patch, 2, &tc, c);
    const double d1[2] = {(c[0] - a[0]) / (2 * h), (c[1] - a[1]) / (2 * h)};
    const double d2[2] = {(c[0] - 2 * b[0] + a[0]) / (h * h), (c[1] - 2 * b[1] + a[1]) / (h * h)};
    const double cross = d1[0] * d2[1] - d1[1] * d2[0];
    if (std::abs(cross) < 1e-12) continue;
    const double scale = (d1[0] * d1[0] + d1[1] * d1[1]) / cross;
    const double e[2] = {b[0] - scale * d1[1], b[1] + scale * d1[0]};
    // Only evolute points inside the sampling box: far branches of the
    // evolute (nearly straight pieces) say little.
    if (e[0] < boxLo[0] || e[0] > boxHi[0] || e[1] < boxLo[1] || e[1] > boxHi[1]) continue;
    for (int k = 0; k < 2; ++k) set.coords.push_back(e[k] + Uniform(rng, -1e-3, 1e-3) * size);
  }
  return set;
}

/// Near points of a triangle mesh: a uniformly chosen triangle, a uniform
/// point on it, an offset along its normal of up to `offset` either way.
PointSet MeshNearPoints(const Patch& patch, std::int64_t count, double offset, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = "near";
  set.dim = 3;
  set.coords.reserve(3 * count);
  const std::int64_t numTris = static_cast<std::int64_t>(patch.cells.size() / 3);
  for (std::int64_t i = 0; i < count; ++i) {
    const std::int64_t t = std::min<std::int64_t>(numTris - 1, static_cast<std::int64_t>(Uniform(rng) * numTris));
    const double* v[3];
    for (int c = 0; c < 3; ++c) v[c] = &patch.points[3 * patch.cells[3 * t + c]];
    double a = Uniform(rng), b = Uniform(rng);
    if (a + b > 1.0) {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = v[1][k] - v[0][k];
      e2[k] = v[2][k] - v[0][k];
    }
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double s = Uniform(rng, -offset, offset) / len;
    for (int k = 0; k < 3; ++k) set.coords.push_back(v[0][k] + a * e1[k] + b * e2[k] + s * n[k]);
  }
  return set;
}

/// Points inside the unit ball used for the tet solid: half uniform in the
/// ball of radius 0.9, half in the shell 0.9 to 0.97, where the curved
/// boundary elements are (the mesh's boundary deviates from the sphere by far
/// less than 0.03, so every point is inside the mesh).
PointSet BallPoints(std::int64_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointSet set;
  set.name = "inside";
  set.dim = 3;
  set.coords.reserve(3 * count);
  while (set.count() < count) {
    const double x = Uniform(rng, -1, 1), y = Uniform(rng, -1, 1), z = Uniform(rng, -1, 1);
    const double r = std::sqrt(x * x + y * y + z * z);
    const bool shell = set.count() % 2 == 1;
    if (shell ? (r < 0.9 || r > 0.97) : r > 0.9) continue;
    set.coords.insert(set.coords.end(), {x, y, z});
  }
  return set;
}

#if !defined(INVMAP_PEER_GMSH) && defined(INVMAP_GMSH_EXECUTABLE)
bool FileExists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}
#endif

/// Writes the tet solid's .geo file and meshes it with gmsh (its API when
/// libgmsh was found, else the gmsh command). Returns false with a message
/// when neither is available or meshing fails.
bool MakeTetMesh(int order, double meshSize, const std::string& geoPath, const std::string& mshPath,
                 std::string* message) {
  {
    std::ofstream geo(geoPath);
    geo << TetSolidGeo(order, meshSize);
    if (!geo) {
      *message = "cannot write " + geoPath;
      return false;
    }
  }
#if defined(INVMAP_PEER_GMSH)
  return MeshWithGmshApi(geoPath, mshPath, message);
#elif defined(INVMAP_GMSH_EXECUTABLE)
  const std::string command =
      std::string(INVMAP_GMSH_EXECUTABLE) + " -v 0 -3 \"" + geoPath + "\" -o \"" + mshPath + "\" > /dev/null 2>&1";
  if (std::system(command.c_str()) != 0 || !FileExists(mshPath)) {
    *message = "'" + command + "' failed";
    return false;
  }
  return true;
#else
  (void)mshPath;
  *message = "neither libgmsh-dev nor the gmsh command was found at configure time";
  return false;
#endif
}

/// Non-empty knot spans of a knot vector.
int Spans(const std::vector<double>& knots) {
  std::vector<double> distinct = knots;
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  return static_cast<int>(distinct.size()) - 1;
}

}  // namespace

double ControlBoxSize(const Patch& patch, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = k; i < patch.points.size(); i += dim) {
      lo = std::min(lo, patch.points[i]);
      hi = std::max(hi, patch.points[i]);
    }
    d2 += (hi - lo) * (hi - lo);
  }
  return std::sqrt(d2);
}

void PatchRange(const Patch& patch, int direction, double* lo, double* hi) {
  const std::vector<double>& knots = patch.knots[direction];
  const int p = patch.degrees[direction];
  const int n = patch.counts[direction];
  *lo = knots[p];
  *hi = knots[n];
}

void EvaluatePatch(const Patch& patch, int dim, const double* params, double* point) {
  const int numDirs = static_cast<int>(patch.degrees.size());
  int span[2] = {0, 0};
  double basis[2][16];
  for (int d = 0; d < numDirs; ++d) {
    const int p = patch.degrees[d];
    span[d] = FindSpan(patch.knots[d], p, patch.counts[d], params[d]);
    BasisFunctions(patch.knots[d], p, span[d], params[d], basis[d]);
  }
  const bool rational = !patch.weights.empty();
  double sum[3] = {0, 0, 0}, weightSum = 0.0;
  const int p = patch.degrees[0];
  const int q = numDirs > 1 ? patch.degrees[1] : 0;
  for (int b = 0; b <= q; ++b) {
    for (int a = 0; a <= p; ++a) {
      const int i = span[0] - p + a;
      const int j = numDirs > 1 ? span[1] - q + b : 0;
      const std::int64_t index = static_cast<std::int64_t>(j) * patch.counts[0] + i;
      const double w = (numDirs > 1 ? basis[1][b] : 1.0) * basis[0][a] * (rational ? patch.weights[index] : 1.0);
      for (int k = 0; k < dim; ++k) sum[k] += w * patch.points[index * dim + k];
      weightSum += w;
    }
  }
  for (int k = 0; k < dim; ++k) point[k] = sum[k] / weightSum;
}

std::string TetSolidGeo(int order, double meshSize) {
  // A unit sphere: every boundary element is curved (its high-order nodes lie
  // on the sphere), the interior ones are straight.
  std::ostringstream geo;
  geo << "// invmap peer benchmark: curved solid for the order-" << order << " tet workload.\n"
      << "SetFactory(\"OpenCASCADE\");\n"
      << "Sphere(1) = {0, 0, 0, 1};\n"
      << "Mesh.MeshSizeMin = " << meshSize << ";\n"
      << "Mesh.MeshSizeMax = " << meshSize << ";\n"
      << "Mesh.ElementOrder = " << order << ";\n"
      << "Mesh.MshFileVersion = 4.1;\n"
      << "General.NumThreads = 1;\n"
      << "Mesh.RandomSeed = 1;\n";
  return geo.str();
}

std::vector<GeometryCase> MakeCases(const WorkloadOptions& options) {
  std::vector<GeometryCase> cases;
  const std::int64_t n = options.points;
  auto wanted = [&](const std::string& name) {
    return options.only.empty() || name.find(options.only) != std::string::npos;
  };

  if (wanted("surface")) {
    GeometryCase c;
    c.name = "surface";
    c.kind = CaseKind::SplineSurface;
    c.geometry = samples::WavySurface(32);
    const Patch& patch = c.geometry.patches[0];
    c.description = "bicubic B-spline surface, " + std::to_string(Spans(patch.knots[0])) + " x " +
                    std::to_string(Spans(patch.knots[1])) + " spans with a C0 crease (samples::WavySurface(32))";
    c.pointSets.push_back(SurfaceNearPoints(patch, n, 0.05, 11));
    c.pointSets.push_back(SurfaceFarPoints(n, 12));
    cases.push_back(std::move(c));
  }
  if (wanted("torus")) {
    GeometryCase c;
    c.name = "torus";
    c.kind = CaseKind::SplineSurface;
    c.geometry = samples::NurbsTorus(2.0, 0.7);
    c.description = "rational biquadratic NURBS torus, R = 2, r = 0.7, 4 x 4 spans (samples::NurbsTorus)";
    const double lo[3] = {-3.4, -3.4, -1.4}, hi[3] = {3.4, 3.4, 1.4};
    c.pointSets.push_back(BoxPoints("everywhere", lo, hi, 3, n, 21));
    cases.push_back(std::move(c));
  }
  if (wanted("curve")) {
    GeometryCase c;
    c.name = "curve";
    c.kind = CaseKind::SplineCurve;
    c.geometry = samples::NurbsCurve2D();
    c.description = "planar rational cubic curve with tight turns, 7 spans (samples::NurbsCurve2D)";
    c.pointSets.push_back(CurvePoints(c.geometry.patches[0], n, 31));
    cases.push_back(std::move(c));
  }
  // The large mesh of the workload, and a small one (a robot's or
  // a haptic scene's size) whose tree stays in cache, where a search's
  // arithmetic counts more than its memory traffic.
  const struct {
    const char* name;
    int triangles, quickTriangles;
  } meshes[] = {{"trimesh", 1000000, 20000}, {"small trimesh", 20000, 2000}};
  for (const auto& mesh : meshes) {
    if (!wanted(mesh.name)) continue;
    GeometryCase c;
    c.name = mesh.name;
    c.kind = CaseKind::TriangleMesh;
    c.geometry = samples::BumpySphere(options.quick ? mesh.quickTriangles : mesh.triangles);
    const Patch& patch = c.geometry.patches[0];
    c.description = "bumpy sphere, " + std::to_string(patch.cells.size() / 3) + " triangles (samples::BumpySphere)";
    c.pointSets.push_back(MeshNearPoints(patch, n, 0.01, 41));
    const double lo[3] = {-1.3, -1.3, -1.3}, hi[3] = {1.3, 1.3, 1.3};
    c.pointSets.push_back(BoxPoints("uniform", lo, hi, 3, n, 42));
    cases.push_back(std::move(c));
  }
  for (int order : {2, 3}) {
    const std::string name = "tets order " + std::to_string(order);
    if (!wanted(name)) continue;
    GeometryCase c;
    c.name = name;
    c.kind = CaseKind::TetMesh;
    c.order = order;
    const double meshSize = options.quick ? 0.35 : 0.1;
    mkdir(options.workDir.c_str(), 0755);
    const std::string stem = options.workDir + "/sphere_order" + std::to_string(order);
    c.mshPath = stem + ".msh";
    std::string message;
    if (!MakeTetMesh(order, meshSize, stem + ".geo", c.mshPath, &message)) {
      std::fprintf(stderr, "invmap_bench_peers: skipping '%s': %s\n", name.c_str(), message.c_str());
      continue;
    }
    try {
      c.geometry = io::ReadGmsh(c.mshPath);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "invmap_bench_peers: skipping '%s': %s\n", name.c_str(), e.what());
      continue;
    }
    std::size_t cells = 0;
    for (const Patch& patch : c.geometry.patches) cells += patch.cellTypes.size();
    std::ostringstream d;
    d << "unit sphere meshed by gmsh, " << cells << " order-" << order << " tets, mesh size " << meshSize
      << " (" << c.mshPath << ")";
    c.description = d.str();
    c.pointSets.push_back(BallPoints(n, 50 + order));
    cases.push_back(std::move(c));
  }
#if defined(INVMAP_BENCH_CAD)
  AddCadCases(options, &cases);
#endif
  return cases;
}

}  // namespace invmap::bench
