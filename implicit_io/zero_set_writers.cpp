#include "implicit_io/zero_set_writers.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "implicit_io/text_output.h"
#include "io/file_io.h"

namespace invmap::io {
namespace {

/// Checks a primitive list of the zero sets: a multiple of `arity` indices
/// below the vertex count, one label each.
void CheckPrimitives(const char* what, const std::vector<std::uint32_t>& indices,
                     const std::vector<std::array<int, 4>>& labels, std::size_t arity, std::size_t numVertices) {
  if (indices.size() % arity != 0 || indices.size() / arity != labels.size()) {
    throw std::invalid_argument(std::string("zero sets ") + what + ": " + std::to_string(indices.size()) +
                                " indices and " + std::to_string(labels.size()) + " labels");
  }
  for (const std::uint32_t v : indices) {
    if (v >= numVertices) {
      throw std::invalid_argument(std::string("zero sets ") + what + ": vertex index " + std::to_string(v) +
                                  " out of range (" + std::to_string(numVertices) + " vertices)");
    }
  }
}

/// Throws std::invalid_argument for inconsistent zero sets (see CheckPrimitives).
void CheckZeroSets(const implicit::ZeroSets& z) {
  if (z.vertices.size() % 3 != 0) throw std::invalid_argument("zero sets vertices: length not a multiple of 3");
  const std::size_t n = z.vertices.size() / 3;
  CheckPrimitives("triangles", z.triangles, z.triangleLabels, 3, n);
  CheckPrimitives("segments", z.segments, z.segmentLabels, 2, n);
  CheckPrimitives("points", z.points, z.pointLabels, 1, n);
}

/// OBJ group name of a label: "f0", "f0_f2", ...
std::string GroupName(const std::array<int, 4>& label) {
  std::string name;
  for (const int i : label) {
    if (i < 0) continue;
    name += (name.empty() ? "f" : "_f") + std::to_string(i);
  }
  return name.empty() ? "unlabeled" : name;
}

/// Indices 0..labels.size()-1 ordered by label (stable).
std::vector<std::size_t> OrderByLabel(const std::vector<std::array<int, 4>>& labels) {
  std::vector<std::size_t> order(labels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return labels[a] < labels[b]; });
  return order;
}

}  // namespace

void WriteZeroSetsObj(const implicit::ZeroSets& zeroSets, const std::string& path) {
  CheckZeroSets(zeroSets);
  const implicit::ZeroSets& z = zeroSets;
  const std::size_t numVertices = z.vertices.size() / 3;
  const std::vector<std::size_t> triangles = OrderByLabel(z.triangleLabels);
  const std::vector<std::size_t> segments = OrderByLabel(z.segmentLabels);
  const std::vector<std::size_t> points = OrderByLabel(z.pointLabels);

  AtomicOutput out(path);
  out.Write("# invmap zero sets: " + std::to_string(numVertices) + " vertices, " + std::to_string(triangles.size()) +
            " triangles, " + std::to_string(segments.size()) + " segments, " + std::to_string(points.size()) +
            " points\n");
  for (std::size_t v = 0; v < numVertices; ++v) {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutText(start, "v ");
    p = PutDouble(p, z.vertices[3 * v]);
    *p++ = ' ';
    p = PutDouble(p, z.vertices[3 * v + 1]);
    *p++ = ' ';
    p = PutDouble(p, z.vertices[3 * v + 2]);
    *p++ = '\n';
    out.Advance(static_cast<std::size_t>(p - start));
  }

  // Walk the three label-sorted lists together, one group per label.
  std::size_t t = 0, s = 0, q = 0;
  const auto writeRun = [&](std::size_t* cursor, const std::vector<std::size_t>& order,
                            const std::vector<std::array<int, 4>>& labels, const std::array<int, 4>& label,
                            const std::vector<std::uint32_t>& indices, std::size_t arity, const char* prefix) {
    for (; *cursor < order.size() && labels[order[*cursor]] == label; ++*cursor) {
      const std::size_t e = order[*cursor];
      char* const start = out.Reserve(kLineRoom);
      char* p = PutText(start, prefix);
      for (std::size_t j = 0; j < arity; ++j) {
        *p++ = ' ';
        p = PutInteger(p, static_cast<std::int64_t>(indices[e * arity + j]) + 1);
      }
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
  };
  while (t < triangles.size() || s < segments.size() || q < points.size()) {
    std::array<int, 4> label = {std::numeric_limits<int>::max(), 0, 0, 0};
    bool any = false;
    const auto consider = [&](std::size_t cursor, const std::vector<std::size_t>& order,
                              const std::vector<std::array<int, 4>>& labels) {
      if (cursor < order.size() && (!any || labels[order[cursor]] < label)) {
        label = labels[order[cursor]];
        any = true;
      }
    };
    consider(t, triangles, z.triangleLabels);
    consider(s, segments, z.segmentLabels);
    consider(q, points, z.pointLabels);
    out.Write("g " + GroupName(label) + "\n");
    writeRun(&t, triangles, z.triangleLabels, label, z.triangles, 3, "f");
    writeRun(&s, segments, z.segmentLabels, label, z.segments, 2, "l");
    writeRun(&q, points, z.pointLabels, label, z.points, 1, "p");
  }
  out.Commit();
}

void WriteZeroSetsPly(const implicit::ZeroSets& zeroSets, const std::string& path) {
  CheckZeroSets(zeroSets);
  const implicit::ZeroSets& z = zeroSets;
  const std::size_t numTriangles = z.triangles.size() / 3;
  // Only the vertices the triangles use, in order of first use.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> old2New(z.vertices.size() / 3, kUnused);
  std::vector<std::uint32_t> new2Old;
  for (const std::uint32_t v : z.triangles) {
    if (old2New[v] == kUnused) {
      old2New[v] = static_cast<std::uint32_t>(new2Old.size());
      new2Old.push_back(v);
    }
  }

  AtomicOutput out(path);
  out.Write("ply\nformat binary_little_endian 1.0\ncomment invmap zero-set triangles\nelement vertex " +
            std::to_string(new2Old.size()) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(numTriangles) +
            "\nproperty list uchar uint vertex_indices\nproperty int label0\nproperty int label1\n"
            "property int label2\nproperty int label3\nend_header\n");
  constexpr std::size_t kVertexBytes = 24, kFaceBytes = 1 + 12 + 16;
  for (const std::uint32_t v : new2Old) {
    char* p = out.Reserve(kVertexBytes);
    for (int a = 0; a < 3; ++a) StoreLittleEndian<double>(p + 8 * a, z.vertices[3 * static_cast<std::size_t>(v) + a]);
    out.Advance(kVertexBytes);
  }
  for (std::size_t f = 0; f < numTriangles; ++f) {
    char* p = out.Reserve(kFaceBytes);
    p[0] = 3;
    for (int j = 0; j < 3; ++j) StoreLittleEndian<std::uint32_t>(p + 1 + 4 * j, old2New[z.triangles[3 * f + j]]);
    for (int j = 0; j < 4; ++j) StoreLittleEndian<std::int32_t>(p + 13 + 4 * j, z.triangleLabels[f][j]);
    out.Advance(kFaceBytes);
  }
  out.Commit();
}

}  // namespace invmap::io
