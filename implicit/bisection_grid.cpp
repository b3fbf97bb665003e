#include "implicit/bisection_grid.h"

#include <algorithm>

namespace invmap::implicit {

template <int N>
BisectionGrid<N>::BisectionGrid(const SimplexMesh& mesh)
    : coordinates_(mesh.vertices), cellsOfVertex_(mesh.numVertices()) {
  const std::size_t count = mesh.numCells();
  cells_.resize(count);
  versions_.assign(count, 0);
  for (std::size_t c = 0; c < count; ++c) {
    for (int i = 0; i <= N; ++i) {
      cells_[c][i] = mesh.cells[c * (N + 1) + i];
      cellsOfVertex_[cells_[c][i]].push_back(static_cast<std::uint32_t>(c));
    }
  }
}

template <int N>
int BisectionGrid<N>::LongestEdge(std::uint32_t c, double* length2) const {
  const Cell& cell = cells_[c];
  int longest = 0;
  double longest2 = -1;
  for (int e = 0; e < kEdges; ++e) {
    const double* p = point(cell[kEdgeVertex[e][0]]);
    const double* q = point(cell[kEdgeVertex[e][1]]);
    const double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    const double l2 = dx * dx + dy * dy + dz * dz;
    if (l2 > longest2) {
      longest2 = l2;
      longest = e;
    }
  }
  *length2 = longest2;
  return longest;
}

template <int N>
bool BisectionGrid<N>::Bisect(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>* children) {
  ring_.clear();
  for (std::uint32_t c : cellsOfVertex_[a]) {
    const Cell& cell = cells_[c];
    if (std::find(cell.begin(), cell.end(), b) != cell.end()) ring_.push_back(c);
  }
  if (ring_.empty()) return false;
  // The ring's order decides only the order children are reported in; sort it
  // so that it does not depend on the history of the incidence lists.
  std::sort(ring_.begin(), ring_.end());
  ring_.erase(std::unique(ring_.begin(), ring_.end()), ring_.end());

  const std::uint32_t m = static_cast<std::uint32_t>(numVertices());
  const double* pa = point(a);
  const double* pb = point(b);
  const double midpoint[3] = {(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2};
  coordinates_.insert(coordinates_.end(), midpoint, midpoint + 3);
  cellsOfVertex_.emplace_back();
  std::vector<std::uint32_t>& aroundM = cellsOfVertex_.back();

  for (std::uint32_t c : ring_) {
    const Cell parent = cells_[c];
    const int slotA = static_cast<int>(std::find(parent.begin(), parent.end(), a) - parent.begin());
    const int slotB = static_cast<int>(std::find(parent.begin(), parent.end(), b) - parent.begin());
    const std::uint32_t second = static_cast<std::uint32_t>(cells_.size());
    Cell first = parent;
    first[slotB] = m;
    Cell other = parent;
    other[slotA] = m;
    cells_[c] = first;
    ++versions_[c];
    cells_.push_back(other);
    versions_.push_back(0);
    // Incidence: a keeps c (the first child); b's c becomes the second child;
    // m gets both; the other vertices gain the second.
    std::vector<std::uint32_t>& aroundB = cellsOfVertex_[b];
    *std::find(aroundB.begin(), aroundB.end(), c) = second;
    aroundM.push_back(c);
    aroundM.push_back(second);
    for (int i = 0; i <= N; ++i)
      if (i != slotA && i != slotB) cellsOfVertex_[parent[i]].push_back(second);
    children->push_back(c);
    children->push_back(second);
  }
  return true;
}

template <int N>
SimplexMesh BisectionGrid<N>::ToMesh() const {
  SimplexMesh mesh;
  mesh.dimension = N;
  mesh.vertices = coordinates_;
  mesh.cells.reserve(cells_.size() * (N + 1));
  for (const Cell& cell : cells_) mesh.cells.insert(mesh.cells.end(), cell.begin(), cell.end());
  return mesh;
}

template class BisectionGrid<2>;
template class BisectionGrid<3>;

}  // namespace invmap::implicit
