#include "tests/support/closest_reference.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <queue>
#include <tuple>
#include <utility>

namespace invmap::testing {
namespace {

struct Box {
  double lo[3] = {0, 0, 0};
  double hi[3] = {0, 0, 0};
};

double BoxDistance2(const Box& b, const double* p) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({b.lo[k] - p[k], 0.0, p[k] - b.hi[k]});
    d2 += d * d;
  }
  return d2;
}

double Dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Bernstein coefficients on [a, b] of a degree-p polynomial from its
/// coefficients on [0, 1], as a (p + 1) x (p + 1) row-major matrix: row m is
/// the blossom at (a^(p-m), b^m), evaluated by de Casteljau's algorithm with
/// a different argument per level.
std::vector<double> SubintervalMatrix(int p, double a, double b) {
  const int n = p + 1;
  std::vector<double> m(n * n, 0.0);
  std::vector<double> c(n);
  for (int j = 0; j < n; ++j) {
    for (int row = 0; row < n; ++row) {
      std::fill(c.begin(), c.end(), 0.0);
      c[j] = 1.0;
      for (int r = 1; r <= p; ++r) {
        const double x = r <= p - row ? a : b;
        for (int i = 0; i + r <= p; ++i) c[i] = (1.0 - x) * c[i] + x * c[i + 1];
      }
      m[row * n + j] = c[0];
    }
  }
  return m;
}

/// Applies the n x n operator `op` along direction `dir` of a tensor net with
/// sizes[3] points per direction (first fastest) and h components per point.
void ApplyAlong(std::vector<double>& net, const int sizes[3], int h, int dir, const std::vector<double>& op) {
  const int n = sizes[dir];
  if (n == 1) return;
  std::vector<double> out(net.size(), 0.0);
  const int stride = dir == 0 ? 1 : dir == 1 ? sizes[0] : sizes[0] * sizes[1];
  for (int l = 0; l < sizes[2]; ++l)
    for (int k = 0; k < sizes[1]; ++k)
      for (int j = 0; j < sizes[0]; ++j) {
        const int idx[3] = {j, k, l};
        const int at = (l * sizes[1] + k) * sizes[0] + j;
        const int base = at - idx[dir] * stride;
        for (int m = 0; m < n; ++m) {
          const double f = op[idx[dir] * n + m];
          if (f == 0.0) continue;
          for (int c = 0; c < h; ++c) out[at * h + c] += f * net[(base + m * stride) * h + c];
        }
      }
  net.swap(out);
}

/// Control-point box of a cell (z = 0 in 2D).
Box ControlBox(const RefCell& cell) {
  Box b;
  const int dim = cell.ambientDim;
  const int n = static_cast<int>(cell.points.size()) / dim;
  for (int k = 0; k < dim; ++k) {
    b.lo[k] = std::numeric_limits<double>::infinity();
    b.hi[k] = -std::numeric_limits<double>::infinity();
  }
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) {
      b.lo[k] = std::min(b.lo[k], cell.points[i * dim + k]);
      b.hi[k] = std::max(b.hi[k], cell.points[i * dim + k]);
    }
  return b;
}

/// Boxes of the pieces of a tensor-product cell split `pieces` times per
/// direction, each the control-point box of the piece's subdivided net
/// (computed in homogeneous coordinates, so it holds the rational piece).
std::vector<Box> PieceBoxes(const RefCell& cell, int pieces) {
  const int dim = cell.ambientDim;
  const int pd = cell.paramDim();
  const int h = dim + 1;
  int sizes[3] = {1, 1, 1};
  for (int d = 0; d < pd; ++d) sizes[d] = cell.degrees[d] + 1;
  const int numPoints = sizes[0] * sizes[1] * sizes[2];
  std::vector<double> homogeneous(static_cast<std::size_t>(numPoints) * h);
  for (int i = 0; i < numPoints; ++i) {
    const double w = cell.weights.empty() ? 1.0 : cell.weights[i];
    for (int k = 0; k < dim; ++k) homogeneous[i * h + k] = w * cell.points[i * dim + k];
    homogeneous[i * h + dim] = w;
  }
  std::vector<std::vector<double>> ops[3];
  for (int d = 0; d < pd; ++d) {
    for (int m = 0; m < pieces; ++m) {
      ops[d].push_back(SubintervalMatrix(cell.degrees[d], static_cast<double>(m) / pieces,
                                         static_cast<double>(m + 1) / pieces));
    }
  }
  const int count[3] = {pieces, pd > 1 ? pieces : 1, pd > 2 ? pieces : 1};
  std::vector<Box> boxes;
  for (int c = 0; c < count[2]; ++c)
    for (int b = 0; b < count[1]; ++b)
      for (int a = 0; a < count[0]; ++a) {
        std::vector<double> net = homogeneous;
        const int which[3] = {a, b, c};
        for (int d = 0; d < pd; ++d) ApplyAlong(net, sizes, h, d, ops[d][which[d]]);
        Box box;
        for (int k = 0; k < dim; ++k) {
          box.lo[k] = std::numeric_limits<double>::infinity();
          box.hi[k] = -std::numeric_limits<double>::infinity();
        }
        for (int i = 0; i < numPoints; ++i)
          for (int k = 0; k < dim; ++k) {
            const double x = net[i * h + k] / net[i * h + dim];
            box.lo[k] = std::min(box.lo[k], x);
            box.hi[k] = std::max(box.hi[k], x);
          }
        boxes.push_back(box);
      }
  return boxes;
}

}  // namespace

void ClosestOnSegment(const double* p, const double* a, const double* b, double* s, double* x) {
  double ab[3], ap[3];
  for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ap[k] = p[k] - a[k];
  const double len2 = Dot3(ab, ab);
  double t = len2 > 0.0 ? Dot3(ap, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  *s = t;
  for (int k = 0; k < 3; ++k) x[k] = a[k] + t * ab[k];
}

void ClosestOnTriangle(const double* p, const double* a, const double* b, const double* c, double* s, double* t,
                       double* x) {
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
    bp[k] = p[k] - b[k];
    cp[k] = p[k] - c[k];
  }
  const double cross[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
  const auto set = [&](double v, double w) {
    *s = v;
    *t = w;
    for (int k = 0; k < 3; ++k) x[k] = a[k] + v * ab[k] + w * ac[k];
  };
  // A (nearly) degenerate triangle has no interior region worth solving:
  // its closest point is on one of its edges.
  if (Dot3(cross, cross) <= 1e-24 * Dot3(ab, ab) * Dot3(ac, ac)) {
    double best = std::numeric_limits<double>::infinity();
    double u, y[3];
    const auto tryEdge = [&](const double* e0, const double* e1, int which) {
      ClosestOnSegment(p, e0, e1, &u, y);
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) d2 += (y[k] - p[k]) * (y[k] - p[k]);
      if (d2 < best) {
        best = d2;
        if (which == 0) set(u, 0.0);
        if (which == 1) set(0.0, u);
        if (which == 2) set(1.0 - u, u);
      }
    };
    tryEdge(a, b, 0);
    tryEdge(a, c, 1);
    tryEdge(b, c, 2);
    return;
  }
  const double d1 = Dot3(ab, ap), d2 = Dot3(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return set(0.0, 0.0);
  const double d3 = Dot3(ab, bp), d4 = Dot3(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return set(1.0, 0.0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return set(d1 / (d1 - d3), 0.0);
  const double d5 = Dot3(ab, cp), d6 = Dot3(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return set(0.0, 1.0);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return set(0.0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return set(1.0 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  set(vb * denom, vc * denom);
}

struct ReferenceGeometry::Impl {
  ReferenceOptions options;
  int dim = 3;
  double size = 0.0;
  std::vector<PatchCell> cells;
  std::vector<std::unique_ptr<BruteForceReference>> brute;  // lazily built per cell
  // Leaves: one box per cell piece.
  std::vector<Box> leafBox;
  std::vector<std::int64_t> leafCell;
  // Tree: node n covers leaves order[first .. first + count) when count > 0,
  // else its children are left and left + 1.
  struct Node {
    Box box;
    int first = 0;
    int count = 0;
    int left = -1;
  };
  std::vector<Node> nodes;
  std::vector<int> order;
  std::vector<std::uint32_t> stamp;
  std::uint32_t now = 0;
  bool hasFullRank = false;
  std::vector<int> probeStack;

  Box Union(int first, int count) const {
    Box b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::numeric_limits<double>::infinity();
      b.hi[k] = -std::numeric_limits<double>::infinity();
    }
    for (int i = first; i < first + count; ++i) {
      const Box& l = leafBox[order[i]];
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(b.lo[k], l.lo[k]);
        b.hi[k] = std::max(b.hi[k], l.hi[k]);
      }
    }
    return b;
  }

  /// Median split on the longest axis of the leaf centres.
  void Build(int node, int first, int count) {
    nodes[node].box = Union(first, count);
    if (count <= 4) {
      nodes[node].first = first;
      nodes[node].count = count;
      return;
    }
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<double>::infinity(), hi[k] = -lo[k];
    for (int i = first; i < first + count; ++i) {
      const Box& l = leafBox[order[i]];
      for (int k = 0; k < 3; ++k) {
        const double c = 0.5 * (l.lo[k] + l.hi[k]);
        lo[k] = std::min(lo[k], c);
        hi[k] = std::max(hi[k], c);
      }
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    const int half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](int x, int y) {
                       return leafBox[x].lo[axis] + leafBox[x].hi[axis] < leafBox[y].lo[axis] + leafBox[y].hi[axis];
                     });
    const int left = static_cast<int>(nodes.size());
    nodes[node].left = left;
    nodes.emplace_back();
    nodes.emplace_back();
    Build(left, first, half);
    Build(left + 1, first + half, count - half);
  }

  /// The lattice search of cell c, built on first use.
  BruteForceReference& Brute(std::int64_t c) {
    if (!brute[c]) {
      BruteForceOptions bo;
      bo.divisions = options.divisions[cells[c].cell.paramDim() - 1];
      brute[c] = std::make_unique<BruteForceReference>(cells[c].cell, bo);
    }
    return *brute[c];
  }

  /// Reported answer of cell c for reference coordinates ref and point x.
  ReferenceAnswer Answer(std::int64_t c, const double* ref, const double* x, double distance) const {
    const PatchCell& pc = cells[c];
    ReferenceAnswer r;
    r.patch = pc.patch;
    r.cell = pc.index;
    r.distance = distance;
    for (int k = 0; k < dim; ++k) r.x[k] = x[k];
    for (int d = 0; d < pc.cell.paramDim(); ++d) r.params[d] = pc.paramLo[d] + pc.paramScale[d] * ref[d];
    return r;
  }

  /// Points inside a volume (full-rank) cell lie in many overlapping boxes;
  /// the lattice search of each costs far more than one local solve. So
  /// first try, for every full-rank cell whose box holds p, one local solve
  /// from the domain's centroid: a distance of 0 found that way is the
  /// global minimum (nothing is closer), otherwise the full search decides.
  bool ProbeInside(const double* p3, ReferenceAnswer* out) {
    if (!hasFullRank) return false;
    probeStack.clear();
    probeStack.push_back(0);
    while (!probeStack.empty()) {
      const Node& node = nodes[probeStack.back()];
      probeStack.pop_back();
      if (BoxDistance2(node.box, p3) > 0.0) continue;
      if (node.count == 0) {
        probeStack.push_back(node.left);
        probeStack.push_back(node.left + 1);
        continue;
      }
      for (int i = node.first; i < node.first + node.count; ++i) {
        const std::int64_t c = leafCell[order[i]];
        const RefCell& cell = cells[c].cell;
        if (cell.paramDim() != dim || BoxDistance2(leafBox[order[i]], p3) > 0.0) continue;
        const int pd = cell.paramDim();
        const bool simplex = cell.type == kernels::CellType::Tri || cell.type == kernels::CellType::Tet;
        double centroid[3] = {0, 0, 0};
        for (int d = 0; d < pd; ++d) centroid[d] = simplex ? 1.0 / (pd + 1) : 0.5;
        if (cell.type == kernels::CellType::Wedge) centroid[0] = centroid[1] = 1.0 / 3.0, centroid[2] = 0.5;
        const RefClosest rc = Brute(c).Polish(p3, centroid);
        if (rc.distance <= 1e-14 * size) {
          *out = Answer(c, rc.ref.data(), rc.x.data(), rc.distance);
          return true;
        }
      }
    }
    return false;
  }

  /// Exact (or lattice-searched) closest point on one cell.
  ReferenceAnswer SolveCell(std::int64_t c, const double* p3) {
    const PatchCell& pc = cells[c];
    const RefCell& cell = pc.cell;
    ReferenceAnswer r;
    r.patch = pc.patch;
    r.cell = pc.index;
    double ref[3] = {0, 0, 0};
    if (pc.linearSimplex) {
      double v[3][3] = {};
      for (int i = 0; i < cell.numControlPoints(); ++i)
        for (int k = 0; k < dim; ++k) v[i][k] = cell.points[i * dim + k];
      if (cell.type == kernels::CellType::Tri) {
        ClosestOnTriangle(p3, v[0], v[1], v[2], &ref[0], &ref[1], r.x.data());
      } else {
        ClosestOnSegment(p3, v[0], v[1], &ref[0], r.x.data());
      }
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) d2 += (r.x[k] - p3[k]) * (r.x[k] - p3[k]);
      r.distance = std::sqrt(d2);
    } else {
      const RefClosest rc = Brute(c).Closest(p3);
      r.distance = rc.distance;
      for (int k = 0; k < 3; ++k) ref[k] = rc.ref[k];
      for (int k = 0; k < dim; ++k) r.x[k] = rc.x[k];
    }
    const int pd = cell.paramDim();
    for (int d = 0; d < pd; ++d) r.params[d] = pc.paramLo[d] + pc.paramScale[d] * ref[d];
    return r;
  }
};

ReferenceGeometry::ReferenceGeometry(const Geometry& geometry, ReferenceOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  m.dim = geometry.dimension;
  m.size = GeometrySize(geometry);
  m.cells = GeometryCells(geometry);
  m.brute.resize(m.cells.size());
  m.stamp.assign(m.cells.size(), 0);
  // Rounding in the subdivision could shrink a box by a few ulps of the
  // coordinates; the pad keeps every box conservative.
  const double pad = 1e-12 * std::max(m.size, 1e-300);
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const RefCell& cell = m.cells[c].cell;
    m.hasFullRank = m.hasFullRank || cell.paramDim() == m.dim;
    const bool tensor = cell.type == kernels::CellType::Line || cell.type == kernels::CellType::Quad ||
                        cell.type == kernels::CellType::Hex;
    const int pieces = tensor ? options.subdivisions[cell.paramDim() - 1] : 1;
    std::vector<Box> boxes = pieces > 1 ? PieceBoxes(cell, pieces) : std::vector<Box>{ControlBox(cell)};
    for (Box& b : boxes) {
      for (int k = 0; k < m.dim; ++k) b.lo[k] -= pad, b.hi[k] += pad;
      m.leafBox.push_back(b);
      m.leafCell.push_back(static_cast<std::int64_t>(c));
    }
  }
  m.order.resize(m.leafBox.size());
  for (std::size_t i = 0; i < m.order.size(); ++i) m.order[i] = static_cast<int>(i);
  m.nodes.reserve(2 * m.leafBox.size() + 1);
  m.nodes.emplace_back();
  if (!m.leafBox.empty()) m.Build(0, 0, static_cast<int>(m.leafBox.size()));
}

ReferenceGeometry::~ReferenceGeometry() = default;
ReferenceGeometry::ReferenceGeometry(ReferenceGeometry&&) noexcept = default;
ReferenceGeometry& ReferenceGeometry::operator=(ReferenceGeometry&&) noexcept = default;

const std::vector<PatchCell>& ReferenceGeometry::cells() const { return impl_->cells; }
double ReferenceGeometry::size() const { return impl_->size; }

ReferenceAnswer ReferenceGeometry::Closest(const double* point) {
  Impl& m = *impl_;
  ReferenceAnswer best;
  if (m.leafBox.empty()) return best;
  if (++m.now == 0) {
    std::fill(m.stamp.begin(), m.stamp.end(), 0);
    m.now = 1;
  }
  double p[3] = {0, 0, 0};
  for (int k = 0; k < m.dim; ++k) p[k] = point[k];
  if (m.ProbeInside(p, &best)) return best;
  // Entries: (squared lower bound, tie-break, id); id >= 0 is a node, id < 0
  // the leaf -id - 1. Leaves with equal bounds (typically 0: the point is in
  // several boxes) go nearest box centre first, which usually is the cell
  // that holds the point, so the search ends after one solve.
  using Entry = std::tuple<double, double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  double best2 = std::numeric_limits<double>::infinity();
  heap.emplace(BoxDistance2(m.nodes[0].box, p), 0.0, 0);
  int solved = 0;
  while (!heap.empty()) {
    const auto [lb2, tie, id] = heap.top();
    heap.pop();
    if (lb2 >= best2) break;  // nothing left can be strictly closer
    if (id < 0) {
      const std::int64_t c = m.leafCell[-id - 1];
      if (m.stamp[c] == m.now) continue;
      m.stamp[c] = m.now;
      ++solved;
      const ReferenceAnswer r = m.SolveCell(c, p);
      if (r.distance * r.distance < best2) {
        best = r;
        best2 = r.distance * r.distance;
      }
      continue;
    }
    const Impl::Node& node = m.nodes[id];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int leaf = m.order[i];
        if (m.stamp[m.leafCell[leaf]] == m.now) continue;
        const Box& box = m.leafBox[leaf];
        const double d2 = BoxDistance2(box, p);
        if (d2 >= best2) continue;
        double centre2 = 0.0;
        for (int k = 0; k < 3; ++k) centre2 += (0.5 * (box.lo[k] + box.hi[k]) - p[k]) * (0.5 * (box.lo[k] + box.hi[k]) - p[k]);
        heap.emplace(d2, centre2, -static_cast<std::int64_t>(leaf) - 1);
      }
    } else {
      for (int child = node.left; child <= node.left + 1; ++child) {
        const double d2 = BoxDistance2(m.nodes[child].box, p);
        if (d2 < best2) heap.emplace(d2, 0.0, child);
      }
    }
  }
  best.cellsSolved = solved;
  return best;
}

}  // namespace invmap::testing
