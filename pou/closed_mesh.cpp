#include "pou/closed_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace invmap::pou {
namespace {

std::string Edge(std::int64_t a, std::int64_t b) {
  return "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
}

std::string Triangle(std::int64_t t, const std::int64_t* v) {
  return "triangle " + std::to_string(t) + " (vertices " + std::to_string(v[0]) + ", " + std::to_string(v[1]) +
         ", " + std::to_string(v[2]) + ")";
}

/// One corner of a triangle seen from its vertex: the triangle turns from
/// `from` to `to` around it.
struct Corner {
  std::int64_t from;
  std::int64_t to;
  std::int64_t triangle;
};

}  // namespace

int ClosedMesh::CornerOf(std::int64_t t, std::int64_t v) const {
  for (int k = 0; k < 3; ++k) {
    if (triangles_[3 * t + k] == v) return k;
  }
  return -1;
}

std::string ClosedMesh::Build(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                              std::int64_t numTriangles) {
  if (numTriangles <= 0) return "the mesh has no triangle";
  for (std::int64_t v = 0; v < numVertices; ++v) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(xyz[3 * v + k])) {
        return "vertex " + std::to_string(v) + ": coordinate " + std::to_string(k) + " is not finite (" +
               std::to_string(xyz[3 * v + k]) + ")";
      }
    }
  }
  for (std::int64_t t = 0; t < numTriangles; ++t) {
    const std::int64_t* v = triangles + 3 * t;
    for (int k = 0; k < 3; ++k) {
      if (v[k] < 0 || v[k] >= numVertices) {
        return "triangle " + std::to_string(t) + ": vertex index " + std::to_string(v[k]) + " out of range [0, " +
               std::to_string(numVertices) + ")";
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) return Triangle(t, v) + " repeats a vertex (degenerate)";
    // Zero area, judged against the longest edge so that it does not depend on the units.
    double e1[3], e2[3], e3[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = xyz[3 * v[1] + k] - xyz[3 * v[0] + k];
      e2[k] = xyz[3 * v[2] + k] - xyz[3 * v[0] + k];
      e3[k] = xyz[3 * v[2] + k] - xyz[3 * v[1] + k];
    }
    const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
    const double longest2 = std::max({e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2],
                                      e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2],
                                      e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2]});
    const double area2 = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    if (!(area2 > 1e-12 * longest2)) return Triangle(t, v) + " has zero area (degenerate)";
  }

  // Every undirected edge must be used by exactly two triangles, once in each direction.
  struct HalfEdge {
    std::int64_t lo, hi, triangle;
    bool forward;  // runs from lo to hi
  };
  std::vector<HalfEdge> halfEdges;
  halfEdges.reserve(3 * numTriangles);
  for (std::int64_t t = 0; t < numTriangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t a = triangles[3 * t + k], b = triangles[3 * t + (k + 1) % 3];
      halfEdges.push_back({std::min(a, b), std::max(a, b), t, a < b});
    }
  }
  std::sort(halfEdges.begin(), halfEdges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.triangle < y.triangle;
  });
  for (std::size_t i = 0; i < halfEdges.size();) {
    std::size_t j = i;
    while (j < halfEdges.size() && halfEdges[j].lo == halfEdges[i].lo && halfEdges[j].hi == halfEdges[i].hi) ++j;
    const std::string edge = Edge(halfEdges[i].lo, halfEdges[i].hi);
    if (j - i == 1) {
      return edge + " is on the boundary: only triangle " + std::to_string(halfEdges[i].triangle) +
             " uses it (the mesh must be closed)";
    }
    if (j - i > 2) {
      std::string list;
      for (std::size_t k = i; k < j && k < i + 4; ++k) list += (k > i ? ", " : "") + std::to_string(halfEdges[k].triangle);
      return edge + " is non-manifold: " + std::to_string(j - i) + " triangles use it (" + list +
             (j - i > 4 ? ", ..." : "") + ")";
    }
    if (halfEdges[i].forward == halfEdges[i + 1].forward) {
      return "triangles " + std::to_string(halfEdges[i].triangle) + " and " + std::to_string(halfEdges[i + 1].triangle) +
             " run along " + edge + " in the same direction (inconsistent orientation)";
    }
    i = j;
  }

  // Corners grouped by vertex, in triangle order.
  std::vector<std::int64_t> start(numVertices + 1, 0);
  for (std::int64_t i = 0; i < 3 * numTriangles; ++i) ++start[triangles[i] + 1];
  for (std::int64_t v = 0; v < numVertices; ++v) {
    if (start[v + 1] == 0) return "vertex " + std::to_string(v) + " belongs to no triangle (isolated)";
    start[v + 1] += start[v];
  }
  std::vector<Corner> corners(3 * numTriangles);
  std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
  for (std::int64_t t = 0; t < numTriangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = triangles[3 * t + k];
      corners[fill[v]++] = {triangles[3 * t + (k + 1) % 3], triangles[3 * t + (k + 2) % 3], t};
    }
  }

  xyz_.assign(xyz, xyz + 3 * numVertices);
  triangles_.assign(triangles, triangles + 3 * numTriangles);
  ringStart_ = start;
  ring_.assign(3 * numTriangles, 0);
  ringTriangle_.assign(3 * numTriangles, 0);
  for (std::int64_t v = 0; v < numVertices; ++v) {
    const Corner* first = &corners[start[v]];
    const std::int64_t count = start[v + 1] - start[v];
    // Walk the fan from the first triangle: each neighbour starts exactly one
    // corner (the edges are manifold and consistently oriented).
    std::int64_t current = first[0].from;
    for (std::int64_t i = 0; i < count; ++i) {
      const Corner* next = nullptr;
      for (std::int64_t k = 0; k < count; ++k) {
        if (first[k].from == current) next = &first[k];
      }
      if (i > 0 && current == first[0].from) {
        return "vertex " + std::to_string(v) + " is non-manifold: its triangles form more than one fan";
      }
      ring_[start[v] + i] = current;
      ringTriangle_[start[v] + i] = next->triangle;
      current = next->to;
    }
    if (count < 3) {
      return "vertex " + std::to_string(v) + " has valence " + std::to_string(count) + " (charts need 3 or more)";
    }
  }
  ringMate_.assign(ring_.size(), -1);
  for (std::int64_t v = 0; v < numVertices; ++v) {
    for (int i = 0; i < valence(v); ++i) {
      const std::int64_t u = neighbor(v, i);
      for (int j = 0; j < valence(u); ++j) {
        if (neighbor(u, j) == v) ringMate_[start[v] + i] = j;
      }
    }
  }
  return {};
}

}  // namespace invmap::pou
