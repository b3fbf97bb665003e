#include "tests/support/pou_meshes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace invmap::testing {
namespace {

/// Splits every triangle into 4; `place` moves each new midpoint.
template <typename Place>
TriangleMesh Split(const TriangleMesh& mesh, Place place) {
  TriangleMesh out;
  out.name = mesh.name;
  out.xyz = mesh.xyz;
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> midpoint;
  const auto mid = [&](std::int64_t a, std::int64_t b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    const auto found = midpoint.find(key);
    if (found != midpoint.end()) return found->second;
    double p[3];
    for (int c = 0; c < 3; ++c) p[c] = 0.5 * (mesh.xyz[3 * a + c] + mesh.xyz[3 * b + c]);
    place(p);
    const std::int64_t index = static_cast<std::int64_t>(out.xyz.size() / 3);
    out.xyz.insert(out.xyz.end(), p, p + 3);
    midpoint[key] = index;
    return index;
  };
  for (std::int64_t t = 0; t < mesh.numTriangles(); ++t) {
    const std::int64_t a = mesh.triangles[3 * t], b = mesh.triangles[3 * t + 1], c = mesh.triangles[3 * t + 2];
    const std::int64_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    for (std::int64_t v : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) out.triangles.push_back(v);
  }
  return out;
}

}  // namespace

double TriangleMesh::diagonal() const {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], xyz[i + c]);
      hi[c] = std::max(hi[c], xyz[i + c]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

TriangleMesh Bipyramid(int n) {
  TriangleMesh m;
  m.name = "bipyramid" + std::to_string(n);
  m.xyz = {0, 0, 1.1, 0, 0, -0.9};
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    m.xyz.insert(m.xyz.end(), {std::cos(a), std::sin(a), 0.1 * std::cos(3.0 * a)});
  }
  for (int i = 0; i < n; ++i) {
    const std::int64_t e0 = 2 + i, e1 = 2 + (i + 1) % n;
    m.triangles.insert(m.triangles.end(), {0, e0, e1});
    m.triangles.insert(m.triangles.end(), {1, e1, e0});
  }
  return m;
}

TriangleMesh Icosphere(int levels, double radius) {
  TriangleMesh m;
  m.name = "icosphere" + std::to_string(levels);
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  const auto project = [radius](double* p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int c = 0; c < 3; ++c) p[c] *= radius / n;
  };
  for (const auto& p : v) {
    double q[3] = {p[0], p[1], p[2]};
    project(q);
    m.xyz.insert(m.xyz.end(), q, q + 3);
  }
  for (const auto& tri : f) m.triangles.insert(m.triangles.end(), {tri[0], tri[1], tri[2]});
  for (int l = 0; l < levels; ++l) m = Split(m, project);
  return m;
}

TriangleMesh Torus(int around, int across, double big, double small) {
  TriangleMesh m;
  m.name = "torus" + std::to_string(around) + "x" + std::to_string(across);
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < across; ++j) {
      const double a = 2.0 * M_PI * i / around, b = 2.0 * M_PI * j / across;
      const double r = big + small * std::cos(b);
      m.xyz.insert(m.xyz.end(), {r * std::cos(a), r * std::sin(a), small * std::sin(b)});
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::int64_t>(((i + around) % around) * across + (j + across) % across); };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < across; ++j) {
      const std::int64_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
  }
  return m;
}

TriangleMesh Cylinder(int around, int rings) {
  TriangleMesh m;
  m.name = "cylinder" + std::to_string(around) + "x" + std::to_string(rings);
  for (int k = 0; k <= rings; ++k) {
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * M_PI * i / around;
      m.xyz.insert(m.xyz.end(), {std::cos(a), std::sin(a), 2.0 * k / rings});
    }
  }
  const std::int64_t bottom = m.numVertices(), top = bottom + 1;
  m.xyz.insert(m.xyz.end(), {0.0, 0.0, 0.0, 0.0, 0.0, 2.0});
  const auto id = [&](int k, int i) { return static_cast<std::int64_t>(k * around + (i % around)); };
  for (int k = 0; k < rings; ++k) {
    for (int i = 0; i < around; ++i) {
      m.triangles.insert(m.triangles.end(), {id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      m.triangles.insert(m.triangles.end(), {id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (int i = 0; i < around; ++i) {
    m.triangles.insert(m.triangles.end(), {bottom, id(0, i + 1), id(0, i)});
    m.triangles.insert(m.triangles.end(), {top, id(rings, i), id(rings, i + 1)});
  }
  return m;
}

TriangleMesh GenusTwo(int smoothing) {
  TriangleMesh m;
  m.name = "genus2";
  const auto present = [](int i, int j) {
    return i >= 0 && i < 5 && j >= 0 && j < 3 && !(j == 1 && (i == 1 || i == 3));
  };
  std::map<std::array<int, 3>, std::int64_t> index;
  const auto vertex = [&](std::array<int, 3> p) {
    const auto found = index.find(p);
    if (found != index.end()) return found->second;
    const std::int64_t id = static_cast<std::int64_t>(m.xyz.size() / 3);
    m.xyz.insert(m.xyz.end(), {double(p[0]), double(p[1]), double(p[2])});
    index[p] = id;
    return id;
  };
  // Outward faces: normal axis, sign, and tangents t1, t2 with t1 x t2 = normal.
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}, {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
  const int signs[6] = {1, -1, 1, -1, 1, -1};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!present(i, j)) continue;
      for (int f = 0; f < 6; ++f) {
        const int axis = axes[f][0], sign = signs[f];
        std::array<int, 3> cell{i, j, 0};
        std::array<int, 3> next = cell;
        next[axis] += sign;
        if (axis < 2 && present(next[0], next[1])) continue;
        std::array<int, 3> base = cell;
        if (sign > 0) base[axis] += 1;
        std::array<int, 3> p1 = base, p2 = base, p3 = base;
        p1[axes[f][1]] += 1;
        p2[axes[f][1]] += 1;
        p2[axes[f][2]] += 1;
        p3[axes[f][2]] += 1;
        const std::int64_t a = vertex(base), b = vertex(p1), c = vertex(p2), d = vertex(p3);
        m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
      }
    }
  }
  // Laplacian smoothing over the edges.
  for (int s = 0; s < smoothing; ++s) {
    std::vector<double> sum(m.xyz.size(), 0.0), count(m.xyz.size() / 3, 0.0);
    for (std::int64_t t = 0; t < m.numTriangles(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::int64_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
        for (int c = 0; c < 3; ++c) {
          sum[3 * a + c] += m.xyz[3 * b + c];
          sum[3 * b + c] += m.xyz[3 * a + c];
        }
        count[a] += 1;
        count[b] += 1;
      }
    }
    for (std::size_t v = 0; v < count.size(); ++v)
      for (int c = 0; c < 3; ++c) m.xyz[3 * v + c] += 0.5 * (sum[3 * v + c] / count[v] - m.xyz[3 * v + c]);
  }
  return m;
}

TriangleMesh Refine(const TriangleMesh& mesh) {
  return Split(mesh, [](double*) {});
}

}  // namespace invmap::testing
