// Face neighbours of volume cells (tetrahedra, hexahedra, wedges, mixed),
// used by the engine to walk from the previous point's cell toward the next
// point. Checked against a brute-force comparison of every pair of cells'
// faces, whose corners the test finds by evaluating each cell (its own
// evaluation, tests/support/reference_cell.h) at the corners of the
// reference faces as docs/formats.md and kernels/reference_faces.h number them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "engine/cell_store.h"
#include "invmap/invmap.h"
#include "kernels/reference_faces.h"
#include "tests/engine/built_cells.h"
#include "tests/support/reference_cell.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

using Corner = std::array<double, 3>;

/// The reference corners of face `face` of a cell type: a tetrahedron's face
/// k is opposite vertex k, a hexahedron's face 2i is u_i = 1 and 2i + 1 is
/// u_i = 0, a wedge's faces 0 to 2 are the quadrilaterals opposite the
/// triangle's vertices (0, 0), (1, 0), (0, 1), face 3 is w = 1 and 4 is w = 0.
std::vector<Corner> ReferenceFace(kernels::CellType type, int face) {
  std::vector<Corner> corners;
  switch (type) {
    case kernels::CellType::Tet: {
      const Corner v[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
      for (int k = 0; k < 4; ++k) {
        if (k != face) corners.push_back(v[k]);
      }
      break;
    }
    case kernels::CellType::Hex:
      for (int c = 0; c < 8; ++c) {
        const Corner x{double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)};
        if (x[face / 2] == (face % 2 == 0 ? 1.0 : 0.0)) corners.push_back(x);
      }
      break;
    case kernels::CellType::Wedge: {
      const double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      for (int t = 0; t < 3; ++t) {
        for (int w = 0; w < 2; ++w) {
          const bool on = face < 3 ? t != face : w == (face == 3 ? 1 : 0);
          if (on) corners.push_back({tri[t][0], tri[t][1], double(w)});
        }
      }
      break;
    }
    default:
      break;
  }
  return corners;
}

int FaceCount(kernels::CellType type) {
  return type == kernels::CellType::Tet ? 4 : type == kernels::CellType::Hex ? 6 : 5;
}

/// The cell of the store as the tests' own reference cell.
RefCell AsRefCell(const kernels::CellView& view) {
  RefCell cell;
  cell.type = view.shape.type();
  for (int f = 0; f < view.shape.numFactors(); ++f) cell.degrees[f] = view.shape.factor(f).degree;
  cell.ambientDim = view.ambientDim;
  cell.points.assign(view.points, view.points + view.shape.numControlPoints() * view.ambientDim);
  return cell;
}

/// The mapped corners of every face of every cell, each face's sorted.
std::vector<std::vector<std::vector<Corner>>> MappedFaces(const engine::CellStore& store) {
  std::vector<std::vector<std::vector<Corner>>> faces(static_cast<std::size_t>(store.size()));
  for (std::int64_t c = 0; c < store.size(); ++c) {
    const RefCell cell = AsRefCell(store.solver(c).cell());
    for (int f = 0; f < FaceCount(cell.type); ++f) {
      std::vector<Corner> mapped;
      for (const Corner& ref : ReferenceFace(cell.type, f)) {
        Corner x{0, 0, 0};
        RefEvaluate(cell, ref.data(), x.data());
        mapped.push_back(x);
      }
      std::sort(mapped.begin(), mapped.end());
      faces[c].push_back(mapped);
    }
  }
  return faces;
}

/// Every face's neighbour is the one other cell with the same mapped
/// corners (-1 for none); returns the number of boundary faces.
int ExpectBruteForceNeighbours(const Geometry& geometry) {
  const engine::CellStore store = BuildCells(geometry);
  const engine::FaceAdjacency& adjacency = store.faceAdjacency();
  EXPECT_FALSE(adjacency.empty());
  const auto faces = MappedFaces(store);
  int boundaryFaces = 0;
  for (std::int64_t a = 0; a < store.size(); ++a) {
    EXPECT_EQ(static_cast<int>(faces[a].size()), kernels::NumFaces(store.solver(a).cell().shape));
    for (std::size_t fa = 0; fa < faces[a].size(); ++fa) {
      std::int64_t expected = -1;
      for (std::int64_t b = 0; b < store.size(); ++b) {
        if (b == a) continue;
        for (const auto& face : faces[b]) {
          if (face == faces[a][fa]) expected = b;
        }
      }
      EXPECT_EQ(adjacency.Neighbor(a, static_cast<int>(fa)), expected) << "cell " << a << " face " << fa;
      boundaryFaces += expected < 0 ? 1 : 0;
    }
  }
  return boundaryFaces;
}

Vec3 Warp(double a, double b, double c) {
  return Vec3{a + 0.15 * b * b + 0.05 * c, b + 0.1 * std::sin(2 * a) + 0.05 * c * a, c + 0.1 * a * b};
}

TEST(FaceAdjacencyTest, QuadraticTetrahedra) {
  // A 4 x 4 x 3 block of cubes, two triangles per boundary square.
  EXPECT_EQ(ExpectBruteForceNeighbours(QuadraticMesh(false)), 2 * 2 * (4 * 4 + 4 * 3 + 4 * 3));
}

TEST(FaceAdjacencyTest, QuadraticHexahedraAcrossPatches) {
  // One Bezier patch per curved hexahedron, 6 x 5 x 4 of them.
  EXPECT_EQ(ExpectBruteForceNeighbours(QuadraticMesh(true)), 2 * (6 * 5 + 6 * 4 + 5 * 4));
}

TEST(FaceAdjacencyTest, Wedges) {
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(GridMesh(CellType::Wedge, 3, 4, 3, 2, Warp));
  // Two triangles per square of the top and bottom, one quadrilateral per
  // square of the sides.
  EXPECT_EQ(ExpectBruteForceNeighbours(g), 2 * 2 * 4 * 3 + 2 * (4 * 2 + 3 * 2));
}

TEST(FaceAdjacencyTest, MixedHexahedraWedgesAndTetrahedra) {
  EXPECT_GT(ExpectBruteForceNeighbours(MixedVolumeMesh()), 0);
}

TEST(FaceAdjacencyTest, SurfacesHaveNone) {
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(WavyHeightField(6, 3));
  const engine::CellStore surfaces = BuildCells(g);
  EXPECT_TRUE(surfaces.faceAdjacency().empty());
  EXPECT_EQ(surfaces.faceAdjacency().Neighbor(0, 0), -1);
}

}  // namespace
}  // namespace invmap::testing
