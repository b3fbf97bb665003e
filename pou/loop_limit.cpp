#include "pou/loop_limit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace invmap::pou {
namespace {

using Point = std::array<double, 3>;
using Face = std::array<int, 3>;

/// A piece of a (subdivided) mesh around the triangle being followed. A
/// vertex's position is known when everything it depends on was in the
/// piece; the valence is the vertex's true one, so its ring is complete in
/// the piece when as many faces hold it.
struct Piece {
  std::vector<Point> position;
  std::vector<char> known;
  std::vector<int> valence;
  std::vector<Face> faces;
};

/// The triangle followed through the levels, and the point in it.
struct Target {
  int corner[3];
  double bary[3];
};

double Beta(int n) {
  const double c = 0.375 + 0.25 * std::cos(2.0 * M_PI / n);
  return (0.625 - c * c) / n;
}

/// Neighbours of v counter-clockwise starting at `first` (or anywhere when
/// first < 0); empty when v's ring is not complete in the piece.
std::vector<int> Ring(const Piece& piece, int v, int first) {
  std::vector<std::pair<int, int>> turns;  // from -> to around v
  for (const Face& f : piece.faces) {
    for (int k = 0; k < 3; ++k) {
      if (f[k] == v) turns.push_back({f[(k + 1) % 3], f[(k + 2) % 3]});
    }
  }
  if (static_cast<int>(turns.size()) != piece.valence[v]) return {};
  std::vector<int> ring;
  int current = first >= 0 ? first : turns[0].first;
  for (std::size_t i = 0; i < turns.size(); ++i) {
    ring.push_back(current);
    int next = -1;
    for (const auto& t : turns) {
      if (t.first == current) next = t.second;
    }
    if (next < 0) return {};
    current = next;
  }
  return ring;
}

/// Loop's limit mask at v: (1 - n g) v + g (sum of neighbours), g = 1 / (n + 3 / (8 beta)).
bool LimitPosition(const Piece& piece, int v, Point* out) {
  const std::vector<int> ring = Ring(piece, v, -1);
  if (ring.empty() || !piece.known[v]) return false;
  const int n = static_cast<int>(ring.size());
  const double g = 1.0 / (n + 3.0 / (8.0 * Beta(n)));
  Point sum{0, 0, 0};
  for (int u : ring) {
    if (!piece.known[u]) return false;
    for (int c = 0; c < 3; ++c) sum[c] += piece.position[u][c];
  }
  for (int c = 0; c < 3; ++c) (*out)[c] = (1.0 - n * g) * piece.position[v][c] + g * sum[c];
  return true;
}

/// One Loop step of the piece; the target moves to the subtriangle holding
/// its point (the four children of a triangle share it on their borders, any
/// of them will do).
Piece Subdivide(const Piece& piece, Target* target) {
  const int n = static_cast<int>(piece.position.size());
  struct Edge {
    int lo, hi, opposite[2], count;
  };
  std::vector<Edge> edges;
  const auto edgeIndex = [&edges](int a, int b) {
    const int lo = std::min(a, b), hi = std::max(a, b);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (edges[e].lo == lo && edges[e].hi == hi) return static_cast<int>(e);
    }
    edges.push_back({lo, hi, {-1, -1}, 0});
    return static_cast<int>(edges.size() - 1);
  };
  std::vector<int> faceEdges(3 * piece.faces.size());
  for (std::size_t f = 0; f < piece.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int e = edgeIndex(piece.faces[f][k], piece.faces[f][(k + 1) % 3]);
      Edge& edge = edges[e];
      if (edge.count < 2) edge.opposite[edge.count] = piece.faces[f][(k + 2) % 3];
      ++edge.count;
      faceEdges[3 * f + k] = e;
    }
  }
  Piece next;
  next.position.assign(n + edges.size(), Point{0, 0, 0});
  next.known.assign(n + edges.size(), 0);
  next.valence.assign(n + edges.size(), 6);
  // Even vertices: (1 - n beta) v + beta (sum of neighbours), with the whole ring present.
  std::vector<int> incident(n, 0);
  std::vector<Point> neighbourSum(n, Point{0, 0, 0});
  std::vector<char> neighboursKnown(n, 1);
  for (const Face& f : piece.faces)
    for (int k = 0; k < 3; ++k) ++incident[f[k]];
  for (const Edge& e : edges) {
    const int ends[2] = {e.lo, e.hi};
    for (int s = 0; s < 2; ++s) {
      const int v = ends[s], u = ends[1 - s];
      if (!piece.known[u]) neighboursKnown[v] = 0;
      for (int c = 0; c < 3; ++c) neighbourSum[v][c] += piece.position[u][c];
    }
  }
  for (int v = 0; v < n; ++v) {
    next.valence[v] = piece.valence[v];
    if (!piece.known[v] || !neighboursKnown[v] || incident[v] != piece.valence[v]) continue;
    const double beta = Beta(piece.valence[v]);
    for (int c = 0; c < 3; ++c) {
      next.position[v][c] = (1.0 - piece.valence[v] * beta) * piece.position[v][c] + beta * neighbourSum[v][c];
    }
    next.known[v] = 1;
  }
  // Odd vertices: 3/8 of the edge's ends and 1/8 of the two opposite vertices.
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (e.count != 2 || !piece.known[e.lo] || !piece.known[e.hi] || !piece.known[e.opposite[0]] ||
        !piece.known[e.opposite[1]]) {
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      next.position[n + i][c] = 0.375 * (piece.position[e.lo][c] + piece.position[e.hi][c]) +
                                0.125 * (piece.position[e.opposite[0]][c] + piece.position[e.opposite[1]][c]);
    }
    next.known[n + i] = 1;
  }
  for (std::size_t f = 0; f < piece.faces.size(); ++f) {
    const Face& face = piece.faces[f];
    const int mab = n + faceEdges[3 * f], mbc = n + faceEdges[3 * f + 1], mca = n + faceEdges[3 * f + 2];
    next.faces.push_back({face[0], mab, mca});
    next.faces.push_back({face[1], mbc, mab});
    next.faces.push_back({face[2], mca, mbc});
    next.faces.push_back({mab, mbc, mca});
  }
  const int* c = target->corner;
  const double* l = target->bary;
  const int m01 = n + edgeIndex(c[0], c[1]), m12 = n + edgeIndex(c[1], c[2]), m20 = n + edgeIndex(c[2], c[0]);
  Target sub;
  if (l[0] >= 0.5) {
    sub = {{c[0], m01, m20}, {2 * l[0] - 1, 2 * l[1], 2 * l[2]}};
  } else if (l[1] >= 0.5) {
    sub = {{m01, c[1], m12}, {2 * l[0], 2 * l[1] - 1, 2 * l[2]}};
  } else if (l[2] >= 0.5) {
    sub = {{m20, m12, c[2]}, {2 * l[0], 2 * l[1], 2 * l[2] - 1}};
  } else {
    sub = {{m12, m20, m01}, {1 - 2 * l[0], 1 - 2 * l[1], 1 - 2 * l[2]}};
  }
  *target = sub;
  return next;
}

/// The faces around the target's corners (the support of the limit over the
/// target), renumbered.
Piece Neighbourhood(const Piece& piece, Target* target) {
  std::vector<int> index(piece.position.size(), -1);
  Piece out;
  const auto take = [&](int v) {
    if (index[v] < 0) {
      index[v] = static_cast<int>(out.position.size());
      out.position.push_back(piece.position[v]);
      out.known.push_back(piece.known[v]);
      out.valence.push_back(piece.valence[v]);
    }
    return index[v];
  };
  for (const Face& f : piece.faces) {
    bool touches = false;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) touches |= f[k] == target->corner[j];
    if (touches) out.faces.push_back({take(f[0]), take(f[1]), take(f[2])});
  }
  for (int& corner : target->corner) corner = index[corner];
  return out;
}

/// The 12 vertices around a regular triangle in a fixed order: its corners,
/// then each corner's ring, counter-clockwise from the next corner, skipping
/// vertices already listed. Empty unless all three corners have valence 6
/// and complete rings.
std::vector<int> RegularStencil(const Piece& piece, const Target& target) {
  std::vector<int> stencil(target.corner, target.corner + 3);
  for (int k = 0; k < 3; ++k) {
    const int v = target.corner[k];
    if (piece.valence[v] != 6) return {};
    const std::vector<int> ring = Ring(piece, v, target.corner[(k + 1) % 3]);
    if (ring.empty()) return {};
    for (int u : ring) {
      if (std::find(stencil.begin(), stencil.end(), u) == stencil.end()) stencil.push_back(u);
    }
  }
  if (stencil.size() != 12) return {};
  for (int v : stencil) {
    if (!piece.known[v]) return {};
  }
  return stencil;
}

/// The 15 Bernstein coefficients (i, j, k with i + j + k = 4, in the order
/// of QuarticIndex) of a regular patch's limit as weights of its 12 stencil
/// vertices.
using QuarticMatrix = Eigen::Matrix<double, 15, 12>;

int QuarticIndex(int i, int j) {
  // (i, j) with k = 4 - i - j, listed i fastest within rows of j.
  int index = 0;
  for (int jj = 0; jj < j; ++jj) index += 5 - jj;
  return index + i;
}

double Factorial(int n) { return n <= 1 ? 1.0 : n * Factorial(n - 1); }

Point EvaluateBy(Piece piece, Target target, bool regularShortcut);

QuarticMatrix DeriveRegularPatch() {
  // A patch of the regular triangular lattice around the triangle
  // (p(0,0), p(1,0), p(0,1)), every vertex of valence 6.
  const int lo = -3, hi = 4, side = hi - lo + 1;
  Piece lattice;
  const auto id = [&](int i, int j) { return (i - lo) + side * (j - lo); };
  for (int j = lo; j <= hi; ++j) {
    for (int i = lo; i <= hi; ++i) {
      lattice.position.push_back({0, 0, 0});
      lattice.known.push_back(1);
      lattice.valence.push_back(6);
    }
  }
  for (int j = lo; j < hi; ++j) {
    for (int i = lo; i < hi; ++i) {
      lattice.faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
      lattice.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  Target central{{id(0, 0), id(1, 0), id(0, 1)}, {1, 0, 0}};
  const Piece piece = Neighbourhood(lattice, &central);
  const std::vector<int> stencil = RegularStencil(piece, central);
  if (stencil.size() != 12) throw std::logic_error("Loop: the regular stencil has no 12 vertices");
  // Limit values of each stencil vertex's basis function at the 15 lattice
  // points (i/4, j/4) of the triangle, three basis functions at a time.
  Eigen::Matrix<double, 15, 12> values;
  Eigen::Matrix<double, 15, 15> bernstein;
  for (int group = 0; group < 4; ++group) {
    Piece basis = piece;
    for (Point& p : basis.position) p = {0, 0, 0};
    for (int c = 0; c < 3; ++c) basis.position[stencil[3 * group + c]][c] = 1.0;
    for (int j = 0; j <= 4; ++j) {
      for (int i = 0; i + j <= 4; ++i) {
        Target at = central;
        at.bary[0] = (4 - i - j) / 4.0;
        at.bary[1] = i / 4.0;
        at.bary[2] = j / 4.0;
        const Point value = EvaluateBy(basis, at, false);
        for (int c = 0; c < 3; ++c) values(QuarticIndex(i, j), 3 * group + c) = value[c];
      }
    }
  }
  for (int j = 0; j <= 4; ++j) {
    for (int i = 0; i + j <= 4; ++i) {
      const double l1 = i / 4.0, l2 = j / 4.0, l0 = 1.0 - l1 - l2;
      for (int b = 0; b <= 4; ++b) {
        for (int a = 0; a + b <= 4; ++a) {
          bernstein(QuarticIndex(i, j), QuarticIndex(a, b)) =
              Factorial(4) / (Factorial(4 - a - b) * Factorial(a) * Factorial(b)) * std::pow(l0, 4 - a - b) *
              std::pow(l1, a) * std::pow(l2, b);
        }
      }
    }
  }
  return bernstein.fullPivLu().solve(values);
}

Point EvaluateRegular(const Piece& piece, const Target& target, const std::vector<int>& stencil) {
  static const QuarticMatrix kPatch = DeriveRegularPatch();
  const double l0 = target.bary[0], l1 = target.bary[1], l2 = target.bary[2];
  Point out{0, 0, 0};
  for (int b = 0; b <= 4; ++b) {
    for (int a = 0; a + b <= 4; ++a) {
      const double weight = Factorial(4) / (Factorial(4 - a - b) * Factorial(a) * Factorial(b)) *
                            std::pow(l0, 4 - a - b) * std::pow(l1, a) * std::pow(l2, b);
      for (int s = 0; s < 12; ++s) {
        const double w = weight * kPatch(QuarticIndex(a, b), s);
        for (int c = 0; c < 3; ++c) out[c] += w * piece.position[stencil[s]][c];
      }
    }
  }
  return out;
}

constexpr int kMaxLevels = 48;

Point EvaluateBy(Piece piece, Target target, bool regularShortcut) {
  piece = Neighbourhood(piece, &target);
  for (int level = 0;; ++level) {
    for (int k = 0; k < 3; ++k) {
      if (target.bary[k] == 1.0) {
        Point p;
        if (!LimitPosition(piece, target.corner[k], &p)) throw std::logic_error("Loop: incomplete ring at a corner");
        return p;
      }
    }
    if (regularShortcut) {
      const std::vector<int> stencil = RegularStencil(piece, target);
      if (!stencil.empty()) return EvaluateRegular(piece, target, stencil);
    }
    if (level == kMaxLevels) {
      Point corners[3];
      for (int k = 0; k < 3; ++k) {
        if (!LimitPosition(piece, target.corner[k], &corners[k])) {
          throw std::logic_error("Loop: incomplete ring at a corner");
        }
      }
      Point p{0, 0, 0};
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) p[c] += target.bary[k] * corners[k][c];
      return p;
    }
    piece = Subdivide(piece, &target);
    piece = Neighbourhood(piece, &target);
  }
}

/// The piece of `mesh` around triangle t: the triangles around its corners.
Piece MeshNeighbourhood(const ClosedMesh& mesh, std::int64_t t, Target* target) {
  std::vector<std::int64_t> vertices;
  Piece piece;
  const auto local = [&](std::int64_t v) {
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      if (vertices[i] == v) return static_cast<int>(i);
    }
    vertices.push_back(v);
    const double* p = mesh.position(v);
    piece.position.push_back({p[0], p[1], p[2]});
    piece.known.push_back(1);
    piece.valence.push_back(mesh.valence(v));
    return static_cast<int>(vertices.size() - 1);
  };
  std::vector<std::int64_t> triangles;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t v = mesh.triangles()[3 * t + k];
    target->corner[k] = local(v);
    for (int i = 0; i < mesh.valence(v); ++i) {
      const std::int64_t s = mesh.starTriangle(v, i);
      if (std::find(triangles.begin(), triangles.end(), s) == triangles.end()) triangles.push_back(s);
    }
  }
  for (std::int64_t s : triangles) {
    const std::int64_t* tri = &mesh.triangles()[3 * s];
    piece.faces.push_back({local(tri[0]), local(tri[1]), local(tri[2])});
  }
  return piece;
}

}  // namespace

void LoopLimitPoint(const ClosedMesh& mesh, std::int64_t t, const double bary[3], double out[3]) {
  Target target;
  Piece piece = MeshNeighbourhood(mesh, t, &target);
  for (int k = 0; k < 3; ++k) target.bary[k] = bary[k];
  const Point p = EvaluateBy(std::move(piece), target, true);
  for (int c = 0; c < 3; ++c) out[c] = p[c];
}

void LoopLimitVertex(const ClosedMesh& mesh, std::int64_t v, double out[3]) {
  const double bary[3] = {1, 0, 0};
  const std::int64_t t = mesh.starTriangle(v, 0);
  const int corner = mesh.CornerOf(t, v);
  double b[3] = {0, 0, 0};
  b[corner] = bary[0];
  LoopLimitPoint(mesh, t, b, out);
}

}  // namespace invmap::pou
