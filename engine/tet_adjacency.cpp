#include "engine/tet_adjacency.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "common/parallel.h"

namespace invmap::engine {
namespace {

using FacePoints = std::array<const double*, 3>;

/// The corners of face `face` of a tetrahedron, in lexicographic order of
/// their coordinates, so that both cells of a face list them alike.
FacePoints SortedFace(const kernels::CellSolver& solver, int face) {
  FacePoints corners;
  int n = 0;
  for (int v = 0; v < 4; ++v) {
    if (v != face) corners[n++] = solver.CornerPoint(v);
  }
  std::sort(corners.begin(), corners.end(),
            [](const double* a, const double* b) { return std::lexicographical_compare(a, a + 3, b, b + 3); });
  return corners;
}

bool SameFace(const FacePoints& a, const FacePoints& b) {
  for (int i = 0; i < 3; ++i) {
    if (!std::equal(a[i], a[i] + 3, b[i])) return false;
  }
  return true;
}

/// A hash of the face's coordinates' bits (-0 counted as +0, since the
/// comparison treats them as equal).
std::uint64_t HashFace(const FacePoints& face) {
  std::uint64_t h = 1469598103934665603ull;
  for (const double* corner : face) {
    for (int k = 0; k < 3; ++k) {
      const double x = corner[k] == 0.0 ? 0.0 : corner[k];
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
  }
  return h;
}

struct FaceEntry {
  std::uint64_t hash;
  std::int64_t cellFace;  // cell * 4 + face
};

}  // namespace

void TetAdjacency::Build(const std::vector<kernels::CellSolver>& solvers, int maxThreads) {
  neighbors_.clear();
  const std::int64_t count = static_cast<std::int64_t>(solvers.size());
  std::int64_t tets = 0;
  for (const kernels::CellSolver& solver : solvers) tets += solver.isTetrahedron() ? 1 : 0;
  if (tets == 0) return;
  neighbors_.assign(static_cast<std::size_t>(count) * 4, -1);
  std::vector<FaceEntry> entries(static_cast<std::size_t>(count) * 4, FaceEntry{0, -1});
  ForEachBlock(
      ExecutionPolicy::Par, count, 1024,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c) {
          if (!solvers[c].isTetrahedron()) continue;
          for (int f = 0; f < 4; ++f) entries[c * 4 + f] = FaceEntry{HashFace(SortedFace(solvers[c], f)), c * 4 + f};
        }
      },
      maxThreads);
  entries.erase(std::remove_if(entries.begin(), entries.end(), [](const FaceEntry& e) { return e.cellFace < 0; }),
                entries.end());
  Sort(
      ExecutionPolicy::Par, entries.begin(), entries.end(),
      [](const FaceEntry& a, const FaceEntry& b) { return a.hash != b.hash ? a.hash < b.hash : a.cellFace < b.cellFace; },
      maxThreads);
  // Within a run of equal hashes, pair the faces whose corners agree; a face
  // met three or more times stays unpaired.
  for (std::size_t first = 0; first < entries.size();) {
    std::size_t last = first + 1;
    while (last < entries.size() && entries[last].hash == entries[first].hash) ++last;
    for (std::size_t i = first; i < last; ++i) {
      const std::int64_t a = entries[i].cellFace;
      const FacePoints faceA = SortedFace(solvers[a / 4], static_cast<int>(a % 4));
      std::int64_t match = -1;
      int matches = 0;
      for (std::size_t j = first; j < last; ++j) {
        const std::int64_t b = entries[j].cellFace;
        if (j == i || b / 4 == a / 4) continue;
        if (SameFace(faceA, SortedFace(solvers[b / 4], static_cast<int>(b % 4)))) {
          match = b;
          ++matches;
        }
      }
      if (matches == 1) neighbors_[a] = match / 4;
    }
    first = last;
  }
}

}  // namespace invmap::engine
