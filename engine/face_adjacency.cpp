#include "engine/face_adjacency.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <utility>

#include "common/parallel.h"
#include "kernels/reference_faces.h"

namespace invmap::engine {
namespace {

/// A face's corners, in lexicographic order of their coordinates so that
/// both cells of a face list them alike (unused entries null).
struct FacePoints {
  int count = 0;
  std::array<const double*, kernels::kMaxFaceCorners> corners{};
};

/// True for the cells that get neighbours: volumes in 3D whose every factor
/// has a degree (a degree-0 factor collapses the corners).
bool IsWalkable(const kernels::CellSolver& solver) {
  const kernels::CellView& cell = solver.cell();
  if (cell.ambientDim != 3 || cell.shape.paramDim() != 3) return false;
  for (int f = 0; f < cell.shape.numFactors(); ++f) {
    if (cell.shape.factor(f).degree < 1) return false;
  }
  return true;
}

/// The corner control points of every face of one cell shape
/// (kernels::FaceCornerControlPoints), worked out once per shape.
struct FaceTable {
  kernels::CellShape shape;
  int faces = 0;
  int count[kernels::kMaxFaces] = {};
  int corners[kernels::kMaxFaces][kernels::kMaxFaceCorners] = {};
};

bool SameShape(const kernels::CellShape& a, const kernels::CellShape& b) {
  if (a.type() != b.type()) return false;
  for (int f = 0; f < a.numFactors(); ++f) {
    if (a.factor(f).degree != b.factor(f).degree) return false;
  }
  return true;
}

/// The tables of the shapes of the walkable cells, and each cell's (-1 for
/// the others). A mesh has a handful of shapes.
std::vector<FaceTable> TablesOf(const std::vector<kernels::CellSolver>& solvers, std::vector<std::int16_t>* tableOf) {
  std::vector<FaceTable> tables;
  tableOf->assign(solvers.size(), -1);
  for (std::size_t c = 0; c < solvers.size(); ++c) {
    if (!IsWalkable(solvers[c])) continue;
    const kernels::CellShape& shape = solvers[c].cell().shape;
    std::size_t t = 0;
    while (t < tables.size() && !SameShape(tables[t].shape, shape)) ++t;
    if (t == tables.size()) {
      FaceTable table;
      table.shape = shape;
      table.faces = kernels::NumFaces(shape);
      for (int f = 0; f < table.faces; ++f) table.count[f] = kernels::FaceCornerControlPoints(shape, f, table.corners[f]);
      tables.push_back(table);
    }
    (*tableOf)[c] = static_cast<std::int16_t>(t);
  }
  return tables;
}

FacePoints SortedFace(const kernels::CellSolver& solver, const FaceTable& table, int face) {
  const double* points = solver.cell().points;
  FacePoints sorted;
  sorted.count = table.count[face];
  for (int i = 0; i < sorted.count; ++i) sorted.corners[i] = points + static_cast<std::size_t>(table.corners[face][i]) * 3;
  // Insertion sort of at most four corners.
  const auto less = [](const double* a, const double* b) { return std::lexicographical_compare(a, a + 3, b, b + 3); };
  for (int i = 1; i < sorted.count; ++i) {
    for (int j = i; j > 0 && less(sorted.corners[j], sorted.corners[j - 1]); --j) {
      std::swap(sorted.corners[j], sorted.corners[j - 1]);
    }
  }
  return sorted;
}

bool SameFace(const FacePoints& a, const FacePoints& b) {
  if (a.count != b.count) return false;
  for (int i = 0; i < a.count; ++i) {
    if (!std::equal(a.corners[i], a.corners[i] + 3, b.corners[i])) return false;
  }
  return true;
}

/// A hash of the face's coordinates' bits (-0 counted as +0, since the
/// comparison treats them as equal).
std::uint64_t HashFace(const FacePoints& face) {
  std::uint64_t h = 1469598103934665603ull;
  for (int i = 0; i < face.count; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double x = face.corners[i][k] == 0.0 ? 0.0 : face.corners[i][k];
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
  std::int64_t cellFace;  // cell * stride + face
};

}  // namespace

void FaceAdjacency::Build(const std::vector<kernels::CellSolver>& solvers, int maxThreads) {
  neighbors_.clear();
  startGrid_ = WalkStartGrid();
  frames_ = HexFrames();
  stride_ = 0;
  const std::int64_t count = static_cast<std::int64_t>(solvers.size());
  if (count > std::numeric_limits<std::int32_t>::max()) return;
  std::vector<std::int16_t> tableOf;
  const std::vector<FaceTable> tables = TablesOf(solvers, &tableOf);
  for (const FaceTable& table : tables) stride_ = std::max(stride_, table.faces);
  if (stride_ == 0) return;
  const int stride = stride_;
  const auto sortedFace = [&](std::int64_t cellFace) {
    const std::int64_t c = cellFace / stride;
    return SortedFace(solvers[c], tables[tableOf[c]], static_cast<int>(cellFace % stride));
  };
  neighbors_.assign(static_cast<std::size_t>(count) * stride, -1);
  std::vector<FaceEntry> entries(static_cast<std::size_t>(count) * stride, FaceEntry{0, -1});
  ForEachBlock(
      ExecutionPolicy::Par, count, 1024,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t c = begin; c < end; ++c) {
          if (tableOf[c] < 0) continue;
          for (int f = 0; f < tables[tableOf[c]].faces; ++f) {
            entries[c * stride + f] = FaceEntry{HashFace(sortedFace(c * stride + f)), c * stride + f};
          }
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
      const FacePoints faceA = sortedFace(a);
      std::int64_t match = -1;
      int matches = 0;
      for (std::size_t j = first; j < last; ++j) {
        const std::int64_t b = entries[j].cellFace;
        if (j == i || b / stride == a / stride) continue;
        if (SameFace(faceA, sortedFace(b))) {
          match = b;
          ++matches;
        }
      }
      if (matches == 1) neighbors_[a] = static_cast<std::int32_t>(match / stride);
    }
    first = last;
  }
  std::vector<bool> walkable(solvers.size());
  for (std::size_t c = 0; c < solvers.size(); ++c) walkable[c] = tableOf[c] >= 0;
  startGrid_.Build(solvers, walkable);
  frames_.Build(solvers, [&](std::int64_t cell, int face) { return face < stride ? Neighbor(cell, face) : -1; });
}

}  // namespace invmap::engine
