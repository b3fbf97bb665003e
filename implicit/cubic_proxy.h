// The cubic Bezier simplex proxy of section 3.1 of
// docs/grids.md, and what the
// refinement tests read from it.
//
// For a simplex with vertices p_0..p_N, values v_i and gradients g_i of one
// function, the proxy's control values are
//   vertices:        v_i
//   edge points:     v_i + g_i . (p_j - p_i) / 3   (the trisector of edge ij nearest p_i)
//   face centroids:  (1/4) sum of the face's 6 edge points - (1/6) sum of its 3 vertices
// (a tetrahedron has 4 + 12 + 4 = 20, a triangle 3 + 6 + 1 = 10). The tests
// also need the deviations of the proxy from the linear interpolant at the
// non-vertex control points, and the linear interpolant's gradient U / D
// (kept as the unnormalized U and the signed D = N! volume, so no test
// divides).
#pragma once

#include <algorithm>
#include <cmath>

namespace invmap::implicit {

template <int N>
struct SimplexCounts {
  static constexpr int kVertices = N + 1;
  static constexpr int kEdgePoints = (N + 1) * N;
  static constexpr int kFaces = N == 3 ? 4 : 1;
  static constexpr int kControl = kVertices + kEdgePoints + kFaces;
  static constexpr int kDeviations = kEdgePoints + kFaces;
};

/// The 3 vertices of each triangular face of a tetrahedron (the face
/// opposite vertex f), and of the triangle itself.
template <int N>
struct SimplexFaces;
template <>
struct SimplexFaces<3> {
  static constexpr int kVertex[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
};
template <>
struct SimplexFaces<2> {
  static constexpr int kVertex[1][3] = {{0, 1, 2}};
};

/// What every function's proxy on one simplex shares: the edge vectors, the
/// signed determinant D of the edge matrix and the cofactors that give the
/// linear interpolant's gradient.
template <int N>
struct SimplexFrame {
  double edge[N + 1][N + 1][N];  ///< edge[i][j] = p_j - p_i.
  double cofactor[N][N];         ///< U = sum_k (v_k - v_0) cofactor[k - 1].
  double determinant = 0;        ///< D = det[p_1 - p_0, ..., p_N - p_0].
  double longestEdge = 0;        ///< Length of the longest edge.

  /// `points[i]` is vertex i (3 coordinates; only the first N are read).
  void Set(const double* const points[N + 1]) {
    double longest2 = 0;
    for (int i = 0; i <= N; ++i) {
      for (int j = 0; j <= N; ++j) {
        double length2 = 0;
        for (int a = 0; a < N; ++a) {
          edge[i][j][a] = points[j][a] - points[i][a];
          length2 += edge[i][j][a] * edge[i][j][a];
        }
        longest2 = std::max(longest2, length2);
      }
    }
    longestEdge = std::sqrt(longest2);
    const double(&e)[N + 1][N] = edge[0];
    if constexpr (N == 3) {
      // cofactor[k] is the cross product of the other two edges from p_0, in
      // cyclic order, so that U . e_k = D (v_k - v_0).
      Cross(e[2], e[3], cofactor[0]);
      Cross(e[3], e[1], cofactor[1]);
      Cross(e[1], e[2], cofactor[2]);
      determinant = e[1][0] * cofactor[0][0] + e[1][1] * cofactor[0][1] + e[1][2] * cofactor[0][2];
    } else {
      // U = (v_1 - v_0) perp(e_2) - (v_2 - v_0) perp(e_1), perp(e) = (e_y, -e_x).
      cofactor[0][0] = e[2][1];
      cofactor[0][1] = -e[2][0];
      cofactor[1][0] = -e[1][1];
      cofactor[1][1] = e[1][0];
      determinant = e[1][0] * e[2][1] - e[1][1] * e[2][0];
    }
  }

 private:
  static void Cross(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  }
};

/// One function's proxy on one simplex.
template <int N>
struct CubicProxy {
  using Counts = SimplexCounts<N>;
  double control[Counts::kControl];       ///< Vertices, edge points, face centroids.
  double deviation[Counts::kDeviations];  ///< Proxy minus linear interpolant at the non-vertex control points.
  double gradient[N];                     ///< U: D times the linear interpolant's gradient.
  double lo = 0, hi = 0;                  ///< Smallest and largest control value.

  /// `values[i]` and `gradients[i]` (3 entries, first N read) at vertex i.
  void Set(const SimplexFrame<N>& frame, const double values[N + 1], const double* const gradients[N + 1]) {
    // Multiplications by reciprocals, not divisions: this runs for millions
    // of cells and functions, and a division costs as much as the rest.
    constexpr double kThird = 1.0 / 3.0;
    for (int i = 0; i <= N; ++i) control[i] = values[i];
    // Edge point k of vertex i lies towards vertex (i + 1 + k) mod (N + 1).
    double edgePoint[N + 1][N + 1];
    int index = N + 1;
    for (int i = 0; i <= N; ++i) {
      for (int k = 0; k < N; ++k) {
        const int j = i + 1 + k <= N ? i + 1 + k : i + k - N;
        double slope = 0;
        for (int a = 0; a < N; ++a) slope += gradients[i][a] * frame.edge[i][j][a];
        edgePoint[i][j] = values[i] + slope * kThird;
        control[index] = edgePoint[i][j];
        deviation[index - (N + 1)] = edgePoint[i][j] - (2 * values[i] + values[j]) * kThird;
        ++index;
      }
    }
    for (int f = 0; f < Counts::kFaces; ++f) {
      const int* v = SimplexFaces<N>::kVertex[f];
      const double edges = edgePoint[v[0]][v[1]] + edgePoint[v[0]][v[2]] + edgePoint[v[1]][v[0]] +
                           edgePoint[v[1]][v[2]] + edgePoint[v[2]][v[0]] + edgePoint[v[2]][v[1]];
      const double vertices = values[v[0]] + values[v[1]] + values[v[2]];
      control[index] = edges * 0.25 - vertices * (1.0 / 6.0);
      deviation[index - (N + 1)] = control[index] - vertices * kThird;
      ++index;
    }
    lo = hi = control[0];
    for (int k = 1; k < Counts::kControl; ++k) {
      lo = std::min(lo, control[k]);
      hi = std::max(hi, control[k]);
    }
    for (int a = 0; a < N; ++a) {
      gradient[a] = 0;
      for (int k = 1; k <= N; ++k) gradient[a] += (values[k] - values[0]) * frame.cofactor[k - 1][a];
    }
  }

  /// The sign test (m = 1): some control value > 0 and some <= 0 (zero
  /// counts as negative, as in the reference implementation).
  bool Crosses() const { return hi > 0 && lo <= 0; }
};

/// True when function f certainly does not cross zero on the simplex, from
/// vertex data alone: every control value has its vertex's strict sign when
/// |v_i| > |g_i| L / 2 for all vertices (edge points move at most |g_i| L / 3
/// from v_i; a face centroid is the face's mean vertex value plus at most the
/// mean of |g_i| L / 2). The margin covers rounding, so the shortcut never
/// disagrees with CubicProxy::Crosses. values[i][f] and gradientNorms[i][f]
/// belong to vertex i. (An early exit beats a branch-free loop over all
/// functions here: most functions fail at the first vertex.)
template <int N>
bool CertainlyNoCrossing(const double* const values[N + 1], const double* const gradientNorms[N + 1], int f,
                         double longestEdge) {
  const double reach = 0.5 * (1 + 1e-9) * longestEdge;
  const bool positive = values[0][f] > 0;
  for (int i = 0; i <= N; ++i) {
    if ((values[i][f] > 0) != positive) return false;
    if (!(std::fabs(values[i][f]) > reach * gradientNorms[i][f] + 1e-300)) return false;
  }
  return true;
}

}  // namespace invmap::implicit
