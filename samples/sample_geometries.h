// Sample geometries of `invmap generate`, shared by the demos, tests and benchmarks.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::samples {

/// A wavy bicubic B-spline surface over [0, 1]^2 with `spans` x `spans`
/// knot spans and a crease (a triple knot, C0) along u = 0.5. Dimension 3.
Geometry WavySurface(int spans);

/// A NURBS torus (biquadratic, rational, 9 x 9 control points) around the z
/// axis with major radius `major` and tube radius `minor`. Dimension 3.
Geometry NurbsTorus(double major, double minor);

/// A planar cubic NURBS curve with tight turns (high curvature), non-uniform
/// knots and varying weights. Dimension 2.
Geometry NurbsCurve2D();

/// A quadratic tetrahedral mesh of a curved solid (a bent, twisted beam):
/// `resolution`^3 cubes of 6 tets each, every node placed by a smooth curved
/// map, as Lagrange nodes in gmsh's 10-node order. Generated node by node
/// and tet by tet, so a writer can stream a mesh of any resolution.
class CurvedTetGrid {
 public:
  explicit CurvedTetGrid(int resolution);
  std::int64_t NumNodes() const;
  std::int64_t NumTets() const;
  /// Calls node(x, y, z) for every node, in index order.
  template <typename Fn>
  void ForEachNode(Fn&& node) const;
  /// Calls tet(const std::int64_t nodes[10]) for every tet (gmsh tet10
  /// order: vertices, then edges (0,1), (1,2), (0,2), (0,3), (2,3), (1,3)).
  template <typename Fn>
  void ForEachTet(Fn&& tet) const;

 private:
  int resolution_;
  int m_;  ///< Nodes per direction on the doubled grid.
};

/// The same mesh held in memory.
struct QuadraticTetMesh {
  std::vector<double> nodes;            ///< x, y, z per node.
  std::vector<std::int64_t> tets;       ///< 10 node indices per tet (gmsh tet10 order).
};
QuadraticTetMesh CurvedTetMesh(int resolution);

/// The same mesh as a BezierCells patch (Bernstein control points).
Geometry ToBezierGeometry(const QuadraticTetMesh& mesh);

/// A closed triangle mesh of a bumpy sphere with at least `minTriangles`
/// triangles: each face of an icosahedron cut into n^2 triangles (n = 2^k,
/// 20 * 4^k triangles), its vertices pushed onto the bumpy sphere.
/// Generated vertex by vertex and triangle by triangle, so a writer can
/// stream a mesh of any size: vertices are the 12 corners, then the inner
/// vertices of each of the 30 edges, then those of each face; triangles go
/// face by face, outward (counter-clockwise seen from outside).
class BumpySphereMesh {
 public:
  explicit BumpySphereMesh(std::int64_t minTriangles);
  std::int64_t NumVertices() const;
  std::int64_t NumTriangles() const;
  /// Calls vertex(x, y, z) for every vertex, in index order.
  template <typename Fn>
  void ForEachVertex(Fn&& vertex) const;
  /// Calls triangle(a, b, c) for every triangle, in index order.
  template <typename Fn>
  void ForEachTriangle(Fn&& triangle) const;

 private:
  /// The icosahedron's corner `c`.
  std::array<double, 3> Corner(int c) const;
  /// The vertex of face `f`'s grid with weights (n - i - j, i, j) on its
  /// corners (A, B, C).
  std::int64_t GridVertex(int f, std::int64_t i, std::int64_t j) const;
  /// Emits the point (a A + b B + c C) / n of corners A, B, C pushed onto
  /// the bumpy sphere.
  template <typename Fn>
  void Emit(int A, int B, int C, std::int64_t a, std::int64_t b, std::int64_t c, Fn&& vertex) const;

  std::int64_t n_ = 1;                 ///< Segments per icosahedron edge.
  int edgeOf_[12][12];                 ///< Index of the edge between two corners.
  std::array<std::array<int, 2>, 30> edges_;  ///< Corners of each edge, the lower first.
};

/// The same mesh held in memory (dimension 3, one tri mesh patch).
Geometry BumpySphere(std::int64_t minTriangles);

// ---------------------------------------------------------------- templates

namespace detail {
/// The bent, lifted beam: reference cube [0, 1]^3 to physical space.
std::array<double, 3> BeamMap(double a, double b, double c);
/// The icosahedron's 20 faces (corner indices, outward).
extern const int kIcosahedronFaces[20][3];
/// The bump of BumpySphere: a point of the unit sphere pushed to its radius.
std::array<double, 3> Bump(double x, double y, double z);
}  // namespace detail

template <typename Fn>
void CurvedTetGrid::ForEachNode(Fn&& node) const {
  for (int k = 0; k < m_; ++k) {
    for (int j = 0; j < m_; ++j) {
      for (int i = 0; i < m_; ++i) {
        const std::array<double, 3> x = detail::BeamMap(i / (m_ - 1.0), j / (m_ - 1.0), k / (m_ - 1.0));
        node(x[0], x[1], x[2]);
      }
    }
  }
}

template <typename Fn>
void CurvedTetGrid::ForEachTet(Fn&& tet) const {
  const auto nodeIndex = [this](int i, int j, int k) {
    return (static_cast<std::int64_t>(k) * m_ + j) * m_ + i;
  };
  // Kuhn split: one tet per ordering of the axes, from corner 000 to 111.
  static const int kAxesOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  static const int kEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  for (int k = 0; k < resolution_; ++k) {
    for (int j = 0; j < resolution_; ++j) {
      for (int i = 0; i < resolution_; ++i) {
        for (const auto& order : kAxesOrders) {
          std::array<std::array<int, 3>, 4> v;
          std::array<int, 3> corner{2 * i, 2 * j, 2 * k};
          v[0] = corner;
          for (int s = 0; s < 3; ++s) {
            corner[order[s]] += 2;
            v[s + 1] = corner;
          }
          std::int64_t nodes[10];
          for (int s = 0; s < 4; ++s) nodes[s] = nodeIndex(v[s][0], v[s][1], v[s][2]);
          for (int e = 0; e < 6; ++e) {
            const std::array<int, 3>& a = v[kEdges[e][0]];
            const std::array<int, 3>& b = v[kEdges[e][1]];
            nodes[4 + e] = nodeIndex((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
          }
          tet(static_cast<const std::int64_t*>(nodes));
        }
      }
    }
  }
}

template <typename Fn>
void BumpySphereMesh::Emit(int A, int B, int C, std::int64_t a, std::int64_t b, std::int64_t c, Fn&& vertex) const {
  const std::array<double, 3> pa = Corner(A), pb = Corner(B), pc = Corner(C);
  const double n = static_cast<double>(n_);
  double x[3];
  for (int k = 0; k < 3; ++k) x[k] = (a * pa[k] + b * pb[k] + c * pc[k]) / n;
  const double norm = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const std::array<double, 3> p = detail::Bump(x[0] / norm, x[1] / norm, x[2] / norm);
  vertex(p[0], p[1], p[2]);
}

template <typename Fn>
void BumpySphereMesh::ForEachVertex(Fn&& vertex) const {
  for (int c = 0; c < 12; ++c) Emit(c, c, c, n_, 0, 0, vertex);
  for (const auto& [P, Q] : edges_) {
    for (std::int64_t t = 1; t < n_; ++t) Emit(P, Q, Q, n_ - t, t, 0, vertex);
  }
  for (const auto& face : detail::kIcosahedronFaces) {
    for (std::int64_t j = 1; j <= n_ - 2; ++j) {
      for (std::int64_t i = 1; i <= n_ - 1 - j; ++i) Emit(face[0], face[1], face[2], n_ - i - j, i, j, vertex);
    }
  }
}

template <typename Fn>
void BumpySphereMesh::ForEachTriangle(Fn&& triangle) const {
  for (int f = 0; f < 20; ++f) {
    for (std::int64_t j = 0; j < n_; ++j) {
      for (std::int64_t i = 0; i + j < n_; ++i) {
        // The grid's triangles keep the face's orientation.
        triangle(GridVertex(f, i, j), GridVertex(f, i + 1, j), GridVertex(f, i, j + 1));
        if (i + j + 1 < n_) triangle(GridVertex(f, i + 1, j), GridVertex(f, i + 1, j + 1), GridVertex(f, i, j + 1));
      }
    }
  }
}

}  // namespace invmap::samples
