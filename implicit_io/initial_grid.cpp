#include "implicit_io/initial_grid.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <utility>

#include "implicit/exact_predicates.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"

namespace invmap::io {

implicit::SimplexMesh ReadSimplexMeshMsh(const std::string& path) {
  const Geometry geometry = ReadGmsh(path);
  const int dim = geometry.dimension;
  const CellType wanted = dim == 3 ? CellType::Tet : CellType::Tri;
  const char* const wantedName = dim == 3 ? "linear tetrahedra" : "linear triangles (all z = 0)";
  static const char* const kCellNames[] = {"line", "triangle", "quadrangle", "tetrahedron", "hexahedron", "prism"};
  static const int kParamDim[] = {1, 2, 2, 3, 3, 3};

  implicit::SimplexMesh mesh;
  mesh.dimension = dim;
  const std::size_t per = static_cast<std::size_t>(dim + 1);

  // Exact coordinates -> vertex; +0.0 folds -0.0 into 0.0, which compare
  // equal but hash apart.
  struct KeyHash {
    std::size_t operator()(const implicit::Vec3& p) const {
      std::uint64_t h = 0x9E3779B97F4A7C15ull;
      for (const double x : p) {
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        h ^= bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<implicit::Vec3, std::uint32_t, KeyHash> vertexOf;

  std::size_t element = 0;  // Index over every element ReadGmsh returned, for messages.
  for (const Patch& patch : geometry.patches) {
    const std::size_t cells = patch.cellTypes.size();
    for (std::size_t c = 0; c < cells; ++c, ++element) {
      const CellType type = patch.cellTypes[c];
      const int degree = patch.cellDegrees[3 * c];
      const int typeIndex = static_cast<int>(type);
      if (type != wanted) {
        if (kParamDim[typeIndex] < dim) continue;  // A boundary tag.
        throw InputError(path, 0,
                         "element " + std::to_string(element + 1) + " (in file order) is a " + (degree > 1 ? "curved " : "") +
                             kCellNames[typeIndex] + ": an initial grid has " + wantedName + " only");
      }
      if (degree != 1 || patch.cellOffsets[c + 1] - patch.cellOffsets[c] != static_cast<std::int64_t>(per)) {
        throw InputError(path, 0,
                         "element " + std::to_string(element + 1) + " (in file order) is a " + kCellNames[typeIndex] + " of order " +
                             std::to_string(degree) + ": an initial grid has " + wantedName + " only");
      }
      for (std::size_t j = 0; j < per; ++j) {
        const double* q = patch.points.data() + (static_cast<std::size_t>(patch.cellOffsets[c]) + j) * dim;
        const implicit::Vec3 p = {q[0] + 0.0, q[1] + 0.0, dim == 3 ? q[2] + 0.0 : 0.0};
        const auto [it, inserted] = vertexOf.emplace(p, static_cast<std::uint32_t>(vertexOf.size()));
        if (inserted) {
          if (vertexOf.size() > std::numeric_limits<std::uint32_t>::max()) {
            throw InputError(path, 0, "more than 2^32 - 1 vertices");
          }
          mesh.vertices.insert(mesh.vertices.end(), p.begin(), p.end());
        }
        mesh.cells.push_back(it->second);
      }
    }
  }
  if (mesh.cells.empty()) throw InputError(path, 0, std::string("no cells: an initial grid has ") + wantedName);

  // Orientation by exact predicates: a nearly flat cell still gets its true sign.
  const double* v = mesh.vertices.data();
  for (std::size_t c = 0; c < mesh.numCells(); ++c) {
    std::uint32_t* cell = mesh.cells.data() + c * per;
    int sign = 0;
    if (dim == 3) {
      // Sign of det[v1 - v0, v2 - v0, v3 - v0].
      sign = implicit::Orient3d(v + 3 * cell[1], v + 3 * cell[2], v + 3 * cell[3], v + 3 * cell[0]);
    } else {
      const double a[2] = {v[3 * cell[0]], v[3 * cell[0] + 1]};
      const double b[2] = {v[3 * cell[1]], v[3 * cell[1] + 1]};
      const double d[2] = {v[3 * cell[2]], v[3 * cell[2] + 1]};
      sign = implicit::Orient2d(a, b, d);
    }
    if (sign == 0) {
      throw InputError(path, 0, "cell " + std::to_string(c) + " has zero " + (dim == 3 ? "volume" : "area") +
                                    " (its vertices are " + (dim == 3 ? "coplanar" : "collinear") + ")");
    }
    if (sign < 0) std::swap(cell[1], cell[2]);
  }
  return mesh;
}

}  // namespace invmap::io
