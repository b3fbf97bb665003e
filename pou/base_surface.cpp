#include "pou/base_surface.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "pou/loop_limit.h"

namespace invmap::pou {
namespace {

class FlatSurface : public BaseSurface {
 public:
  explicit FlatSurface(const ClosedMesh& mesh) : mesh_(mesh) {}
  void Evaluate(std::int64_t t, const double bary[3], double out[3]) const override {
    out[0] = out[1] = out[2] = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double* p = mesh_.position(mesh_.triangles()[3 * t + k]);
      for (int c = 0; c < 3; ++c) out[c] += bary[k] * p[c];
    }
  }

 private:
  const ClosedMesh& mesh_;
};

/// PN triangles: a cubic Bezier triangle per mesh triangle, 10 control
/// points each (b300, b030, b003 the corners; edge points pulled onto the
/// corners' tangent planes; b111 from them).
class PnSurface : public BaseSurface {
 public:
  explicit PnSurface(const ClosedMesh& mesh) {
    const std::int64_t nv = mesh.numVertices(), nt = mesh.numTriangles();
    std::vector<double> normal(3 * nv, 0.0);
    // Vertex normals: face normals weighted by the corner angles.
    for (std::int64_t t = 0; t < nt; ++t) {
      const std::int64_t* v = &mesh.triangles()[3 * t];
      double n[3];
      Cross(Sub(mesh.position(v[1]), mesh.position(v[0])).data(), Sub(mesh.position(v[2]), mesh.position(v[0])).data(), n);
      Normalize(n);
      for (int k = 0; k < 3; ++k) {
        auto a = Sub(mesh.position(v[(k + 1) % 3]), mesh.position(v[k]));
        auto b = Sub(mesh.position(v[(k + 2) % 3]), mesh.position(v[k]));
        Normalize(a.data());
        Normalize(b.data());
        const double angle = std::acos(std::max(-1.0, std::min(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2])));
        for (int c = 0; c < 3; ++c) normal[3 * v[k] + c] += angle * n[c];
      }
    }
    for (std::int64_t i = 0; i < nv; ++i) Normalize(&normal[3 * i]);
    nets_.resize(30 * nt);
    for (std::int64_t t = 0; t < nt; ++t) {
      const std::int64_t* v = &mesh.triangles()[3 * t];
      const double* p[3] = {mesh.position(v[0]), mesh.position(v[1]), mesh.position(v[2])};
      const double* n[3] = {&normal[3 * v[0]], &normal[3 * v[1]], &normal[3 * v[2]]};
      double* net = &nets_[30 * t];
      // Corners: 0, 1, 2. Edge point (i, j): 1/3 of the way from corner i to j,
      // pulled onto corner i's tangent plane: index 3 + 2 * i + (j == (i+1)%3 ? 0 : 1).
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) net[3 * i + c] = p[i][c];
      double edgeSum[3] = {0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        for (int s = 0; s < 2; ++s) {
          const int j = (i + 1 + s) % 3;
          const double w = (p[j][0] - p[i][0]) * n[i][0] + (p[j][1] - p[i][1]) * n[i][1] + (p[j][2] - p[i][2]) * n[i][2];
          for (int c = 0; c < 3; ++c) {
            const double e = (2.0 * p[i][c] + p[j][c] - w * n[i][c]) / 3.0;
            net[3 * (3 + 2 * i + s) + c] = e;
            edgeSum[c] += e;
          }
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double e = edgeSum[c] / 6.0, center = (p[0][c] + p[1][c] + p[2][c]) / 3.0;
        net[27 + c] = e + 0.5 * (e - center);
      }
    }
  }

  void Evaluate(std::int64_t t, const double bary[3], double out[3]) const override {
    const double* net = &nets_[30 * t];
    const double* l = bary;
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (int i = 0; i < 3; ++i) {
        sum += l[i] * l[i] * l[i] * net[3 * i + c];
        for (int s = 0; s < 2; ++s) {
          const int j = (i + 1 + s) % 3;
          sum += 3.0 * l[i] * l[i] * l[j] * net[3 * (3 + 2 * i + s) + c];
        }
      }
      sum += 6.0 * l[0] * l[1] * l[2] * net[27 + c];
      out[c] = sum;
    }
  }

 private:
  static std::array<double, 3> Sub(const double* a, const double* b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
  static void Cross(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  }
  static void Normalize(double* a) {
    const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (n > 0.0)
      for (int c = 0; c < 3; ++c) a[c] /= n;
  }

  std::vector<double> nets_;  // 10 control points per triangle
};

class LoopSurface : public BaseSurface {
 public:
  explicit LoopSurface(const ClosedMesh& mesh) : mesh_(mesh) {}
  void Evaluate(std::int64_t t, const double bary[3], double out[3]) const override {
    LoopLimitPoint(mesh_, t, bary, out);
  }

 private:
  const ClosedMesh& mesh_;
};

}  // namespace

std::unique_ptr<BaseSurface> MakeBaseSurface(BaseKind kind, const ClosedMesh& mesh) {
  switch (kind) {
    case BaseKind::Flat:
      return std::make_unique<FlatSurface>(mesh);
    case BaseKind::PnTriangles:
      return std::make_unique<PnSurface>(mesh);
    case BaseKind::Loop:
      return std::make_unique<LoopSurface>(mesh);
  }
  return nullptr;
}

}  // namespace invmap::pou
