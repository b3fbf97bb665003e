// ExtractZeroSets (implicit.h): the zero sets of the piecewise-linear
// interpolant of Grid::values, cell by cell.
//
// In a cell every function is linear, so each zero set is a convex piece: a
// plane's polygon (3D) or a line's segment (2D) is sliced from the cell, then
// clipped or split by the other functions' planes (the material and CSG
// modes) or sliced again (curves and points). A piece's vertex is kept as the
// set of cell vertices it lies between (its support face) and the set of
// labels that vanish on it; its coordinates are solved from those alone, over
// the support sorted by global vertex id. Neighbouring cells therefore
// compute the same point bit for bit, and merging equal coordinates makes a
// closed surface a watertight triangle mesh.
//
// Zero is positive: a value exactly 0 counts as f >= 0 everywhere (in the
// material mode a tie f_i = f_j goes to the smaller index), like a perturbation
// of every value by +tiny. Triangles of zero area and segments of zero length
// are dropped.
//
// Orientation. A triangle's normal is (b - a) x (c - a); a 2D segment's normal
// is its direction turned clockwise, (dy, -dx), so a counter-clockwise loop
// has outward normals. Arrangement: the normal points toward increasing f_i.
// Material interface (i, j), i < j: from material i into material j (toward
// increasing f_j - f_i). CSG: out of the solid (toward decreasing CSG value),
// so the boundary is a consistently oriented closed surface. Curves of 3D
// complexes have no orientation.
//
// Labels. Arrangement and CSG: the functions that vanish, ascending: surface
// (i), curve (i, j), point (i, j, l). Material interface: the materials tied
// for the maximum, ascending: interface (i, j), junction (i, j, l), point
// (i, j, l, m). Unused entries are -1. In 2D, segments take the labels of 3D
// surfaces ((i), or (i, j) between materials) and points those of 3D curves.
//
// Output order: primitives in cell order, then by label as produced; vertices
// in order of first use. The cells run in fixed blocks through
// common/parallel.h and are merged in block order, so the output does not
// depend on the thread count. A curve segment or point that several cells
// produce (it lies on a shared face) is kept once.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "common/parallel.h"
#include "implicit/csg_tree.h"
#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

using Label = std::array<int, 4>;

/// Cells handled by one task; their primitives are merged in block order.
constexpr std::int64_t kCellsPerBlock = 4096;
/// Blocks extracted before their primitives are merged, which bounds the
/// memory held as unmerged coordinates.
constexpr std::int64_t kBlocksPerRound = 64;

/// Up to 4 function (or material) indices, ascending.
struct LabelSet {
  std::array<int, 4> items = {-1, -1, -1, -1};
  int size = 0;

  bool Contains(int label) const {
    for (int k = 0; k < size; ++k)
      if (items[k] == label) return true;
    return false;
  }
  void Insert(int label) {
    if (Contains(label) || size == 4) return;
    int k = size++;
    for (; k > 0 && items[k - 1] > label; --k) items[k] = items[k - 1];
    items[k] = label;
  }
  LabelSet Intersection(const LabelSet& other) const {
    LabelSet common;
    for (int k = 0; k < size; ++k)
      if (other.Contains(items[k])) common.Insert(items[k]);
    return common;
  }
};

/// A vertex of a piece, in barycentric coordinates of the cell.
struct Point {
  std::uint8_t support = 0;  ///< Bit v: the point may have weight on cell vertex v.
  LabelSet labels;           ///< Functions that vanish here (material: materials tied).
  double weight[4] = {0, 0, 0, 0};
};

/// A convex polygon (cyclic), a segment (2 points) or a point; empty when the
/// zero set misses the cell.
using Piece = std::vector<Point>;

/// Primitives of one block of cells, with coordinates; vertices are merged
/// when the blocks are joined.
struct BlockOutput {
  std::vector<double> triangleCorners;  // 9 per triangle
  std::vector<Label> triangleLabels;
  std::vector<double> segmentEnds;  // 6 per segment
  std::vector<Label> segmentLabels;
  std::vector<double> pointCoordinates;  // 3 per point
  std::vector<Label> pointLabels;
};

Label MakeLabel(std::initializer_list<int> labels) {
  Label label = {-1, -1, -1, -1};
  int k = 0;
  for (int l : labels) label[k++] = l;
  return label;
}

/// The zero-set geometry of one cell. Functionals: in the arrangement and CSG
/// modes label l means f_l (and `base` is unused, -1); in the material mode
/// label l means f_base - f_l, where `base` is the smaller material of the
/// interface being extracted.
class CellGeometry {
 public:
  CellGeometry(const Grid& grid, bool differences) : grid_(grid), differences_(differences) {
    dimension_ = grid.mesh.dimension;
    vertexCount_ = dimension_ + 1;
  }

  void Load(std::int64_t cell) {
    const std::uint32_t* ids = grid_.mesh.cells.data() + cell * vertexCount_;
    for (int v = 0; v < vertexCount_; ++v) {
      id_[v] = ids[v];
      position_[v] = grid_.mesh.vertices.data() + 3 * static_cast<std::size_t>(ids[v]);
      values_[v] = grid_.values.data() + static_cast<std::size_t>(ids[v]) * grid_.functionCount;
      // byId_ lists the vertices by global id: the order in which every cell
      // sharing a face sums over it, so they get the same rounding.
      int k = v;
      for (; k > 0 && id_[byId_[k - 1]] > id_[v]; --k) byId_[k] = byId_[k - 1];
      byId_[k] = v;
    }
    orientation_ = SignedVolumeSign();
  }

  int Dimension() const { return dimension_; }
  int VertexCount() const { return vertexCount_; }
  const double* Values(int v) const { return values_[v]; }

  double VertexValue(int v, int base, int label) const {
    return differences_ ? values_[v][base] - values_[v][label] : values_[v][label];
  }

  /// Whether a functional value counts as inside the kept half (zero is
  /// positive; a material tie goes to the smaller index).
  bool Keeps(double value, int base, int label) const {
    return value > 0 || (value == 0 && (!differences_ || base < label));
  }

  double ValueAt(const Point& p, int base, int label) const {
    double sum = 0;
    for (int k = 0; k < vertexCount_; ++k) {
      const int v = byId_[k];
      if (p.support >> v & 1) sum += p.weight[v] * VertexValue(v, base, label);
    }
    return sum;
  }

  /// Interpolated values of every function at barycentric `weight`.
  void InterpolateAll(const double* weight, double* out) const {
    for (int i = 0; i < grid_.functionCount; ++i) {
      double sum = 0;
      for (int k = 0; k < vertexCount_; ++k) sum += weight[byId_[k]] * values_[byId_[k]][i];
      out[i] = sum;
    }
  }

  std::array<double, 3> Position(const Point& p) const {
    std::array<double, 3> x = {0, 0, 0};
    for (int k = 0; k < vertexCount_; ++k) {
      const int v = byId_[k];
      if (!(p.support >> v & 1)) continue;
      for (int c = 0; c < 3; ++c) x[c] += p.weight[v] * position_[v][c];
    }
    return x;
  }

  /// The zero set of functional `label` (with `base` in the material mode,
  /// base < label) in the cell: a polygon oriented toward increasing
  /// functional in 3D, a segment whose normal points that way in 2D.
  Piece Slice(int base, int label) const {
    bool kept[4];
    int keptCount = 0;
    for (int v = 0; v < vertexCount_; ++v) {
      kept[v] = Keeps(VertexValue(v, base, label), base, label);
      keptCount += kept[v];
    }
    if (keptCount == 0 || keptCount == vertexCount_) return {};
    auto edge = [&](int a, int b) { return Crossing(VertexPoint(a), VertexPoint(b), base, label); };
    if (keptCount == 2 && dimension_ == 3) {
      int in[2], out[2], nIn = 0, nOut = 0;
      for (int v = 0; v < 4; ++v) (kept[v] ? in[nIn++] : out[nOut++]) = v;
      const int a = in[0], b = in[1], c = out[0], d = out[1];
      // (ac, ad, bd, bc) faces c and d when (a, b, c, d) is positively oriented.
      if (Orientation({a, b, c, d}) > 0) return {edge(a, c), edge(b, c), edge(b, d), edge(a, d)};
      return {edge(a, c), edge(a, d), edge(b, d), edge(b, c)};
    }
    // One vertex `a` alone on its side: the piece cuts the edges from it.
    const bool aloneKept = keptCount == 1;
    int a = 0;
    while (kept[a] != aloneKept) ++a;
    int rest[3] = {-1, -1, -1}, n = 0;
    for (int v = 0; v < vertexCount_; ++v)
      if (v != a) rest[n++] = v;
    // With (a, rest...) positively oriented, (ab, ac[, ad]) faces away from a.
    const bool facesAwayFromA = Orientation({a, rest[0], rest[1], dimension_ == 3 ? rest[2] : -1}) > 0;
    Piece piece;
    for (int k = 0; k < n; ++k) piece.push_back(edge(a, rest[k]));
    if (facesAwayFromA == aloneKept) std::swap(piece[n - 2], piece[n - 1]);
    return piece;
  }

  /// The part of a polygon or segment where the functional is kept
  /// (`keepInside`) or not kept; polygon orientation is preserved.
  Piece Clip(const Piece& piece, int base, int label, bool keepInside) const {
    const int n = static_cast<int>(piece.size());
    if (n == 0) return {};
    std::vector<double> value(n);
    std::vector<char> in(n);
    int inCount = 0;
    for (int k = 0; k < n; ++k) {
      value[k] = ValueAt(piece[k], base, label);
      in[k] = Keeps(value[k], base, label) == keepInside;
      inCount += in[k];
    }
    if (inCount == n) return piece;
    if (inCount == 0) return {};
    Piece clipped;
    if (n == 2) {
      clipped.push_back(in[0] ? piece[0] : Crossing(piece[0], piece[1], base, label, value[0], value[1]));
      clipped.push_back(in[1] ? piece[1] : Crossing(piece[0], piece[1], base, label, value[0], value[1]));
      return clipped;
    }
    for (int k = 0; k < n; ++k) {
      const int next = (k + 1) % n;
      if (in[k]) clipped.push_back(piece[k]);
      if (in[k] != in[next]) clipped.push_back(Crossing(piece[k], piece[next], base, label, value[k], value[next]));
    }
    return clipped;
  }

  /// Where the functional changes side on a polygon (a segment, in the
  /// polygon's cyclic order) or on a segment (a point).
  Piece Cut(const Piece& piece, int base, int label) const {
    const int n = static_cast<int>(piece.size());
    if (n < 2) return {};
    std::vector<double> value(n);
    for (int k = 0; k < n; ++k) value[k] = ValueAt(piece[k], base, label);
    Piece cut;
    const int edges = n == 2 ? 1 : n;
    for (int k = 0; k < edges; ++k) {
      const int next = (k + 1) % n;
      if (Keeps(value[k], base, label) != Keeps(value[next], base, label))
        cut.push_back(Crossing(piece[k], piece[next], base, label, value[k], value[next]));
    }
    // A convex piece changes side at most twice; more means rounding noise
    // on a nearly degenerate piece, which has no meaningful answer.
    if (cut.size() != (n == 2 ? 1u : 2u)) return {};
    return cut;
  }

 private:
  Point VertexPoint(int v) const {
    Point p;
    p.support = static_cast<std::uint8_t>(1u << v);
    p.weight[v] = 1;
    return p;
  }

  Point Crossing(const Point& p, const Point& q, int base, int label) const {
    return Crossing(p, q, base, label, ValueAt(p, base, label), ValueAt(q, base, label));
  }

  /// The point of segment pq where the functional vanishes; p and q are on
  /// opposite sides, so valueP != valueQ.
  Point Crossing(const Point& p, const Point& q, int base, int label, double valueP, double valueQ) const {
    // An end where the value is exactly 0 is the crossing: a new point
    // solved there would differ from it by rounding and leave a sliver.
    if (valueP == 0) return p;
    if (valueQ == 0) return q;
    Point x;
    x.support = p.support | q.support;
    x.labels = p.labels.Intersection(q.labels);
    x.labels.Insert(label);
    if (differences_) x.labels.Insert(base);
    if (SolveWeights(x)) return x;
    // Nearly degenerate: interpolate along pq instead. A neighbouring cell
    // has the same p and q, so starting from the smaller end (by position)
    // gives it the same point.
    const bool swapEnds = Position(q) < Position(p);
    const Point& from = swapEnds ? q : p;
    const Point& to = swapEnds ? p : q;
    const double valueFrom = swapEnds ? valueQ : valueP, valueTo = swapEnds ? valueP : valueQ;
    const double t = valueFrom / (valueFrom - valueTo);
    for (int v = 0; v < 4; ++v) x.weight[v] = from.weight[v] + t * (to.weight[v] - from.weight[v]);
    return x;
  }

  /// Weights of the point where every functional of x.labels vanishes on the
  /// face x.support, from the face's data in global vertex order only.
  /// False when the system is not square or (nearly) singular.
  bool SolveWeights(Point& x) const {
    int face[4], m = 0;
    for (int k = 0; k < vertexCount_; ++k)
      if (x.support >> byId_[k] & 1) face[m++] = byId_[k];
    const int base = differences_ ? x.labels.items[0] : -1;
    const int first = differences_ ? 1 : 0;
    const int d = x.labels.size - first;
    if (d < 1 || m != d + 1) return false;
    double g[3][4];
    for (int r = 0; r < d; ++r)
      for (int c = 0; c < m; ++c) g[r][c] = VertexValue(face[c], base, x.labels.items[first + r]);
    // The weights span the null space of g: its generalized cross product.
    double w[4];
    if (m == 2) {
      w[0] = g[0][1];
      w[1] = -g[0][0];
    } else if (m == 3) {
      w[0] = g[0][1] * g[1][2] - g[0][2] * g[1][1];
      w[1] = g[0][2] * g[1][0] - g[0][0] * g[1][2];
      w[2] = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    } else {
      for (int skip = 0; skip < 4; ++skip) {
        double minor[3][3];
        for (int r = 0; r < 3; ++r)
          for (int c = 0, cc = 0; c < 4; ++c)
            if (c != skip) minor[r][cc++] = g[r][c];
        const double det = minor[0][0] * (minor[1][1] * minor[2][2] - minor[1][2] * minor[2][1]) -
                           minor[0][1] * (minor[1][0] * minor[2][2] - minor[1][2] * minor[2][0]) +
                           minor[0][2] * (minor[1][0] * minor[2][1] - minor[1][1] * minor[2][0]);
        w[skip] = (skip % 2 == 0) ? det : -det;
      }
    }
    double sum = 0;
    for (int c = 0; c < m; ++c) sum += w[c];
    if (!(sum != 0) || !std::isfinite(sum)) return false;
    // The point lies on the clipped edge, inside the face; weights far
    // outside [0, 1] mean the system is too ill-conditioned to trust.
    constexpr double kSlack = 1e-9;
    double solved[4];
    for (int c = 0; c < m; ++c) {
      solved[c] = w[c] / sum;
      if (!(solved[c] >= -kSlack && solved[c] <= 1 + kSlack)) return false;
    }
    for (int v = 0; v < 4; ++v) x.weight[v] = 0;
    for (int c = 0; c < m; ++c) x.weight[face[c]] = solved[c];
    return true;
  }

  double SignedVolumeSign() const {
    double e[3][3];
    for (int k = 1; k < vertexCount_; ++k)
      for (int c = 0; c < 3; ++c) e[k - 1][c] = position_[k][c] - position_[0][c];
    const double volume = dimension_ == 3 ? e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                                                e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                                                e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])
                                          : e[0][0] * e[1][1] - e[0][1] * e[1][0];
    return volume < 0 ? -1 : 1;
  }

  /// Orientation of the cell with its vertices listed in `order` (-1 ends a
  /// 2D list): the cell's orientation times the permutation's parity.
  double Orientation(std::array<int, 4> order) const {
    int inversions = 0;
    for (int i = 0; i < vertexCount_; ++i)
      for (int j = i + 1; j < vertexCount_; ++j) inversions += order[i] > order[j];
    return inversions % 2 == 0 ? orientation_ : -orientation_;
  }

  const Grid& grid_;
  bool differences_;
  int dimension_ = 3;
  int vertexCount_ = 4;
  std::uint32_t id_[4] = {};
  const double* position_[4] = {};
  const double* values_[4] = {};
  int byId_[4] = {0, 1, 2, 3};  // local vertices sorted by global id
  double orientation_ = 1;
};

/// Writes pieces of one block of cells as coordinates.
class Emitter {
 public:
  Emitter(const CellGeometry& cell, BlockOutput& out) : cell_(cell), out_(out) {}

  /// A polygon as a fan of triangles (3D) or a segment (2D); `reverse` flips
  /// its orientation.
  void Surface(const Piece& piece, bool reverse, const Label& label) {
    if (cell_.Dimension() == 2) {
      if (piece.size() == 2) Segment(reverse ? Piece{piece[1], piece[0]} : piece, label);
      return;
    }
    const int n = static_cast<int>(piece.size());
    if (n < 3) return;
    std::vector<std::array<double, 3>> x(n);
    for (int k = 0; k < n; ++k) x[reverse ? n - 1 - k : k] = cell_.Position(piece[k]);
    for (int k = 1; k + 1 < n; ++k) {
      if (ZeroArea(x[0], x[k], x[k + 1])) continue;
      for (const auto* corner : {&x[0], &x[k], &x[k + 1]})
        out_.triangleCorners.insert(out_.triangleCorners.end(), corner->begin(), corner->end());
      out_.triangleLabels.push_back(label);
    }
  }

  void Segment(const Piece& piece, const Label& label) {
    if (piece.size() != 2) return;
    const auto a = cell_.Position(piece[0]);
    const auto b = cell_.Position(piece[1]);
    if (a == b) return;
    out_.segmentEnds.insert(out_.segmentEnds.end(), a.begin(), a.end());
    out_.segmentEnds.insert(out_.segmentEnds.end(), b.begin(), b.end());
    out_.segmentLabels.push_back(label);
  }

  void IsolatedPoint(const Piece& piece, const Label& label) {
    if (piece.size() != 1) return;
    const auto a = cell_.Position(piece[0]);
    out_.pointCoordinates.insert(out_.pointCoordinates.end(), a.begin(), a.end());
    out_.pointLabels.push_back(label);
  }

 private:
  static bool ZeroArea(const std::array<double, 3>& a, const std::array<double, 3>& b,
                       const std::array<double, 3>& c) {
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return n[0] == 0 && n[1] == 0 && n[2] == 0;
  }

  const CellGeometry& cell_;
  BlockOutput& out_;
};

/// The functions whose zero set crosses the cell: some vertex value < 0 and
/// some >= 0.
void CrossingFunctions(const CellGeometry& cell, int functionCount, std::vector<int>& crossing) {
  crossing.clear();
  for (int i = 0; i < functionCount; ++i) {
    bool negative = false, nonNegative = false;
    for (int v = 0; v < cell.VertexCount(); ++v) (cell.Values(v)[i] >= 0 ? nonNegative : negative) = true;
    if (negative && nonNegative) crossing.push_back(i);
  }
}

void ArrangementCell(const CellGeometry& cell, const std::vector<int>& crossing, Emitter& emit) {
  const int n = static_cast<int>(crossing.size());
  std::vector<Piece> slices(n);
  for (int a = 0; a < n; ++a) {
    slices[a] = cell.Slice(-1, crossing[a]);
    emit.Surface(slices[a], false, MakeLabel({crossing[a]}));
  }
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const Piece cut = cell.Cut(slices[a], -1, crossing[b]);
      if (cell.Dimension() == 2) {
        emit.IsolatedPoint(cut, MakeLabel({crossing[a], crossing[b]}));
        continue;
      }
      emit.Segment(cut, MakeLabel({crossing[a], crossing[b]}));
      for (int c = b + 1; c < n; ++c)
        emit.IsolatedPoint(cell.Cut(cut, -1, crossing[c]), MakeLabel({crossing[a], crossing[b], crossing[c]}));
    }
  }
}

/// Material mode: the materials that may be the largest somewhere in the
/// cell (for every other material, at least as large at some vertex), or
/// nothing when one material is the largest at every vertex.
void CandidateMaterials(const CellGeometry& cell, int materialCount, std::vector<int>& candidates) {
  candidates.clear();
  int firstWinner = -1;
  bool sameWinner = true;
  for (int v = 0; v < cell.VertexCount(); ++v) {
    const double* f = cell.Values(v);
    const int winner = static_cast<int>(std::max_element(f, f + materialCount) - f);  // ties: smallest index
    if (v == 0) firstWinner = winner;
    sameWinner = sameWinner && winner == firstWinner;
  }
  if (sameWinner) return;
  for (int l = 0; l < materialCount; ++l) {
    bool possible = true;
    for (int m = 0; m < materialCount && possible; ++m) {
      if (m == l) continue;
      bool somewhere = false;
      for (int v = 0; v < cell.VertexCount() && !somewhere; ++v) somewhere = cell.Values(v)[l] >= cell.Values(v)[m];
      possible = somewhere;
    }
    if (possible) candidates.push_back(l);
  }
}

/// Clips `piece` (on which material `base` is tied for the maximum) to where
/// `base` is at least every candidate outside `tied`.
Piece ClipToMaximum(const CellGeometry& cell, Piece piece, int base, const std::vector<int>& candidates,
                    std::initializer_list<int> tied) {
  for (int l : candidates) {
    if (piece.empty()) break;
    if (std::find(tied.begin(), tied.end(), l) != tied.end()) continue;
    piece = cell.Clip(piece, base, l, true);
  }
  return piece;
}

void MaterialCell(const CellGeometry& cell, const std::vector<int>& candidates, Emitter& emit) {
  const int n = static_cast<int>(candidates.size());
  for (int a = 0; a < n; ++a) {
    const int i = candidates[a];
    for (int b = a + 1; b < n; ++b) {
      const int j = candidates[b];
      const Piece interfacePlane = cell.Slice(i, j);
      if (interfacePlane.empty()) continue;
      // Slice faces increasing f_i - f_j (material i); the convention is toward j.
      emit.Surface(ClipToMaximum(cell, interfacePlane, i, candidates, {i, j}), true, MakeLabel({i, j}));
      for (int c = b + 1; c < n; ++c) {
        const int l = candidates[c];
        const Piece junction = cell.Cut(interfacePlane, i, l);
        if (junction.empty()) continue;
        if (cell.Dimension() == 2) {
          emit.IsolatedPoint(ClipToMaximum(cell, junction, i, candidates, {i, j, l}), MakeLabel({i, j, l}));
          continue;
        }
        emit.Segment(ClipToMaximum(cell, junction, i, candidates, {i, j, l}), MakeLabel({i, j, l}));
        for (int d = c + 1; d < n; ++d) {
          const int m = candidates[d];
          emit.IsolatedPoint(ClipToMaximum(cell, cell.Cut(junction, i, m), i, candidates, {i, j, l, m}),
                             MakeLabel({i, j, l, m}));
        }
      }
    }
  }
}

/// CSG mode: the inside/outside answers of the tree at one point.
class CsgProbe {
 public:
  CsgProbe(const std::vector<CsgNode>& tree, int functionCount) : tree_(tree), values_(functionCount) {}

  /// Interpolates every function at the piece's centroid.
  void MoveTo(const CellGeometry& cell, const Piece& piece) {
    double weight[4] = {0, 0, 0, 0};
    for (const Point& p : piece)
      for (int v = 0; v < 4; ++v) weight[v] += p.weight[v] / static_cast<double>(piece.size());
    cell.InterpolateAll(weight, values_.data());
  }

  /// Whether the solid is on the positive side of f_i here: 1 inside only
  /// for f_i > 0, -1 inside only for f_i < 0, 0 when f_i does not matter.
  int Side(int i) {
    const int outcome = Outcomes({i});
    const bool insideIfPositive = outcome & 1, insideIfNegative = outcome >> 1 & 1;
    return insideIfPositive == insideIfNegative ? 0 : (insideIfPositive ? 1 : -1);
  }

  /// Whether the answer depends on the sign of every one of `functions`.
  bool DependsOnEach(std::initializer_list<int> functions) {
    const int count = static_cast<int>(functions.size());
    const int outcome = Outcomes(functions);
    for (int k = 0; k < count; ++k) {
      bool matters = false;
      for (int signs = 0; signs < (1 << count) && !matters; ++signs)
        matters = (outcome >> signs & 1) != (outcome >> (signs ^ (1 << k)) & 1);
      if (!matters) return false;
    }
    return true;
  }

 private:
  /// Bit `signs` of the result: inside when function k of `functions` is
  /// set to +1 (bit k of signs clear) or -1 (set), the others as interpolated.
  int Outcomes(std::initializer_list<int> functions) {
    std::vector<double> saved;
    for (int f : functions) saved.push_back(values_[f]);
    const int count = static_cast<int>(functions.size());
    int outcome = 0;
    for (int signs = 0; signs < (1 << count); ++signs) {
      int k = 0;
      for (int f : functions) values_[f] = (signs >> k++ & 1) ? -1.0 : 1.0;
      if (EvaluateCsg(tree_, values_.data()) <= 0) outcome |= 1 << signs;
    }
    int k = 0;
    for (int f : functions) values_[f] = saved[k++];
    return outcome;
  }

  const std::vector<CsgNode>& tree_;
  std::vector<double> values_;
};

/// Splits `piece` by the zero sets of every crossing function but `skip`.
std::vector<Piece> SplitByOthers(const CellGeometry& cell, const Piece& piece, const std::vector<int>& crossing,
                                 std::initializer_list<int> skip) {
  std::vector<Piece> pieces = {piece}, next;
  for (int l : crossing) {
    if (std::find(skip.begin(), skip.end(), l) != skip.end()) continue;
    next.clear();
    for (const Piece& p : pieces) {
      for (bool side : {true, false}) {
        Piece part = cell.Clip(p, -1, l, side);
        if (!part.empty()) next.push_back(std::move(part));
      }
    }
    pieces.swap(next);
  }
  return pieces;
}

void CsgCell(const CellGeometry& cell, const std::vector<int>& crossing, CsgProbe& probe, Emitter& emit) {
  const int n = static_cast<int>(crossing.size());
  std::vector<Piece> slices(n);
  for (int a = 0; a < n; ++a) {
    const int i = crossing[a];
    slices[a] = cell.Slice(-1, i);
    if (slices[a].empty()) continue;
    for (const Piece& piece : SplitByOthers(cell, slices[a], crossing, {i})) {
      probe.MoveTo(cell, piece);
      const int side = probe.Side(i);
      // Slice faces increasing f_i; outward is toward decreasing f_i when
      // the solid is on the positive side.
      if (side != 0) emit.Surface(piece, side > 0, MakeLabel({i}));
    }
  }
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const int i = crossing[a], j = crossing[b];
      const Piece cut = cell.Cut(slices[a], -1, j);
      if (cut.empty()) continue;
      if (cell.Dimension() == 2) {
        probe.MoveTo(cell, cut);
        if (probe.DependsOnEach({i, j})) emit.IsolatedPoint(cut, MakeLabel({i, j}));
        continue;
      }
      for (const Piece& piece : SplitByOthers(cell, cut, crossing, {i, j})) {
        probe.MoveTo(cell, piece);
        if (probe.DependsOnEach({i, j})) emit.Segment(piece, MakeLabel({i, j}));
      }
      for (int c = b + 1; c < n; ++c) {
        const int l = crossing[c];
        const Piece point = cell.Cut(cut, -1, l);
        if (point.empty()) continue;
        probe.MoveTo(cell, point);
        if (probe.DependsOnEach({i, j, l})) emit.IsolatedPoint(point, MakeLabel({i, j, l}));
      }
    }
  }
}

void ExtractBlock(const Grid& grid, const GridOptions& options, std::int64_t firstCell, std::int64_t endCell,
                  BlockOutput& out) {
  const bool material = options.mode == Mode::MaterialInterface;
  CellGeometry cell(grid, material);
  Emitter emit(cell, out);
  CsgProbe probe(options.tree, grid.functionCount);
  std::vector<int> active;
  for (std::int64_t c = firstCell; c < endCell; ++c) {
    cell.Load(c);
    if (material) {
      CandidateMaterials(cell, grid.functionCount, active);
      if (!active.empty()) MaterialCell(cell, active, emit);
      continue;
    }
    CrossingFunctions(cell, grid.functionCount, active);
    if (active.empty()) continue;
    if (options.mode == Mode::Csg)
      CsgCell(cell, active, probe, emit);
    else
      ArrangementCell(cell, active, emit);
  }
}

/// A cell of the welding lattice (integer coordinates).
struct LatticeKey {
  std::int64_t cell[3];
  bool operator==(const LatticeKey& o) const {
    return cell[0] == o.cell[0] && cell[1] == o.cell[1] && cell[2] == o.cell[2];
  }
};

struct LatticeKeyHash {
  std::size_t operator()(const LatticeKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::int64_t c : k.cell) h = (h ^ static_cast<std::uint64_t>(c)) * 0xff51afd7ed558ccdull, h ^= h >> 32;
    return static_cast<std::size_t>(h);
  }
};

/// Joins the blocks' primitives, giving one vertex to points within
/// `weldTolerance` of each other: neighbouring cells compute a shared vertex
/// from the same data, but where the complex is degenerate with respect to
/// the grid (a clipping line along a shared face) two cells can land a few
/// ulps apart. Primitives that collapse are dropped. Curves (3D) and points
/// that several cells produce are kept once; surface primitives never repeat
/// except where a zero set lies on a shared face with the same side on both
/// sides, where both copies belong.
class Merger {
 public:
  Merger(ZeroSets& out, double weldTolerance)
      : out_(out), tolerance_(weldTolerance), lattice_(4 * weldTolerance) {}

  void Add(const BlockOutput& block) {
    for (std::size_t t = 0; t < block.triangleLabels.size(); ++t) {
      const double* x = &block.triangleCorners[9 * t];
      const std::uint32_t a = Vertex(x), b = Vertex(x + 3), c = Vertex(x + 6);
      if (a == b || b == c || a == c) continue;
      out_.triangles.insert(out_.triangles.end(), {a, b, c});
      out_.triangleLabels.push_back(block.triangleLabels[t]);
    }
    for (std::size_t s = 0; s < block.segmentLabels.size(); ++s) {
      const double* x = &block.segmentEnds[6 * s];
      const std::uint32_t a = Vertex(x), b = Vertex(x + 3);
      if (a == b) continue;
      if (out_.dimension == 3 && !seenSegments_.insert(Key(std::min(a, b), std::max(a, b), block.segmentLabels[s])).second)
        continue;
      out_.segments.insert(out_.segments.end(), {a, b});
      out_.segmentLabels.push_back(block.segmentLabels[s]);
    }
    for (std::size_t p = 0; p < block.pointLabels.size(); ++p) {
      const std::uint32_t a = Vertex(&block.pointCoordinates[3 * p]);
      if (!seenPoints_.insert(Key(a, a, block.pointLabels[p])).second) continue;
      out_.points.push_back(a);
      out_.pointLabels.push_back(block.pointLabels[p]);
    }
  }

 private:
  struct PrimitiveKey {
    std::uint32_t a, b;
    Label label;
    bool operator==(const PrimitiveKey& o) const { return a == o.a && b == o.b && label == o.label; }
  };
  struct PrimitiveKeyHash {
    std::size_t operator()(const PrimitiveKey& k) const {
      std::uint64_t h = (static_cast<std::uint64_t>(k.a) << 32 | k.b) * 0x9e3779b97f4a7c15ull;
      for (int l : k.label) h = (h ^ static_cast<std::uint32_t>(l)) * 0xff51afd7ed558ccdull;
      return static_cast<std::size_t>(h ^ h >> 29);
    }
  };
  static PrimitiveKey Key(std::uint32_t a, std::uint32_t b, const Label& label) { return {a, b, label}; }

  /// The vertex at x: an earlier one within the tolerance (searched in the
  /// lattice cells of side 4 tolerance that the tolerance box around x
  /// touches: one cell, or a few near a cell's border), else a new one.
  std::uint32_t Vertex(const double* x) {
    std::int64_t lo[3], hi[3];
    LatticeKey own;
    for (int c = 0; c < 3; ++c) {
      own.cell[c] = static_cast<std::int64_t>(std::floor(x[c] / lattice_));
      lo[c] = static_cast<std::int64_t>(std::floor((x[c] - tolerance_) / lattice_));
      hi[c] = static_cast<std::int64_t>(std::floor((x[c] + tolerance_) / lattice_));
    }
    LatticeKey key;
    for (key.cell[0] = lo[0]; key.cell[0] <= hi[0]; ++key.cell[0])
      for (key.cell[1] = lo[1]; key.cell[1] <= hi[1]; ++key.cell[1])
        for (key.cell[2] = lo[2]; key.cell[2] <= hi[2]; ++key.cell[2]) {
          const auto found = firstInCell_.find(key);
          if (found == firstInCell_.end()) continue;
          for (std::uint32_t v = found->second; v != kNone; v = nextInCell_[v]) {
            const double* y = &out_.vertices[3 * static_cast<std::size_t>(v)];
            if (std::fabs(x[0] - y[0]) <= tolerance_ && std::fabs(x[1] - y[1]) <= tolerance_ &&
                std::fabs(x[2] - y[2]) <= tolerance_)
              return v;
          }
        }
    const std::uint32_t v = static_cast<std::uint32_t>(out_.vertices.size() / 3);
    out_.vertices.insert(out_.vertices.end(), x, x + 3);
    const auto [slot, inserted] = firstInCell_.emplace(own, v);
    nextInCell_.push_back(inserted ? kNone : slot->second);
    slot->second = v;
    return v;
  }

  static constexpr std::uint32_t kNone = 0xffffffffu;
  ZeroSets& out_;
  double tolerance_;
  double lattice_;
  std::unordered_map<LatticeKey, std::uint32_t, LatticeKeyHash> firstInCell_;  ///< Newest vertex per cell.
  std::vector<std::uint32_t> nextInCell_;  ///< Per vertex: the cell's previous one, or kNone.
  std::unordered_set<PrimitiveKey, PrimitiveKeyHash> seenSegments_, seenPoints_;
};

}  // namespace

ZeroSets ExtractZeroSets(const Grid& grid, const GridOptions& options) {
  ZeroSets zeroSets;
  zeroSets.dimension = grid.mesh.dimension;
  const int dimension = grid.mesh.dimension;
  if (dimension != 2 && dimension != 3) return zeroSets;
  if (grid.functionCount <= 0 ||
      grid.values.size() != grid.mesh.numVertices() * static_cast<std::size_t>(grid.functionCount))
    return zeroSets;
  if (options.mode == Mode::Csg && !ValidateCsgTree(options.tree, grid.functionCount).empty()) return zeroSets;
  const std::size_t vertexCount = grid.mesh.numVertices();
  for (std::uint32_t v : grid.mesh.cells)
    if (v >= vertexCount) return zeroSets;

  const std::int64_t cellCount = static_cast<std::int64_t>(grid.mesh.numCells());
  const std::int64_t blockCount = (cellCount + kCellsPerBlock - 1) / kCellsPerBlock;
  // Welding tolerance: far below any feature the grid resolves, far above
  // the rounding of coordinates computed in different cells.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (std::size_t v = 0; v < vertexCount; ++v)
    for (int c = 0; c < 3; ++c) {
      const double x = grid.mesh.vertices[3 * v + c];
      lo[c] = v == 0 ? x : std::min(lo[c], x);
      hi[c] = v == 0 ? x : std::max(hi[c], x);
    }
  const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  const double magnitude = std::max({std::fabs(lo[0]), std::fabs(lo[1]), std::fabs(lo[2]), std::fabs(hi[0]),
                                     std::fabs(hi[1]), std::fabs(hi[2])});
  Merger merger(zeroSets, 1e-12 * diagonal + 1e-15 * magnitude + std::numeric_limits<double>::min());
  std::vector<BlockOutput> blocks;
  for (std::int64_t roundStart = 0; roundStart < blockCount; roundStart += kBlocksPerRound) {
    const std::int64_t roundSize = std::min(kBlocksPerRound, blockCount - roundStart);
    blocks.assign(static_cast<std::size_t>(roundSize), BlockOutput());
    ForEachBlock(
        ExecutionPolicy::Par, roundSize, 1,
        [&](std::int64_t first, std::int64_t end) {
          for (std::int64_t b = first; b < end; ++b) {
            const std::int64_t firstCell = (roundStart + b) * kCellsPerBlock;
            ExtractBlock(grid, options, firstCell, std::min(cellCount, firstCell + kCellsPerBlock), blocks[b]);
          }
        },
        options.threads);
    for (const BlockOutput& block : blocks) merger.Add(block);
  }
  return zeroSets;
}

}  // namespace invmap::implicit
