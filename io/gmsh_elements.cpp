#include "io/gmsh_elements.h"

#include <algorithm>

namespace invmap::io {
namespace {

/// Node positions on the integer lattice {0..p}^d: reference coordinates
/// times the order (gmsh's [-1, 1] coordinates are 2 * lattice / p - 1).
using Lattice = std::vector<std::array<int, 3>>;

// gmsh's edges and faces (MTetrahedron::edges_tetra, MHexahedron::faces_hexa, ...):
// they fix the order of the edge and face nodes.
constexpr int kTriEdges[3][2] = {{0, 1}, {1, 2}, {2, 0}};
constexpr int kQuadEdges[4][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
constexpr int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {3, 1, 2}};
constexpr int kHexEdges[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                                  {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
constexpr int kHexFaces[6][4] = {{0, 3, 2, 1}, {0, 1, 5, 4}, {0, 4, 7, 3}, {1, 2, 6, 5}, {2, 3, 7, 6}, {4, 5, 6, 7}};
constexpr int kPrismEdges[9][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 4}, {2, 5}, {3, 4}, {3, 5}, {4, 5}};
constexpr int kPrismTriFaces[2][3] = {{0, 2, 1}, {3, 4, 5}};
constexpr int kPrismQuadFaces[3][4] = {{0, 1, 4, 3}, {0, 3, 5, 2}, {1, 2, 5, 4}};

/// The same lattice points shifted by `by` in their first `dims` coordinates:
/// a smaller element of order p - 2 (or p - 3, p - 4) placed strictly inside.
Lattice Shifted(Lattice points, int dims, int by) {
  for (auto& x : points) {
    for (int k = 0; k < dims; ++k) x[k] += by;
  }
  return points;
}

/// The p - 1 interior nodes of each edge, from its first vertex to its second.
template <std::size_t N>
void AddEdgeNodes(const Lattice& vertices, const int (&edges)[N][2], int p, Lattice* out) {
  for (const auto& edge : edges) {
    const auto& a = vertices[edge[0]];
    const auto& b = vertices[edge[1]];
    for (int k = 1; k < p; ++k) {
      out->push_back(
          {(a[0] * (p - k) + b[0] * k) / p, (a[1] * (p - k) + b[1] * k) / p, (a[2] * (p - k) + b[2] * k) / p});
    }
  }
}

/// The nodes of a face (f[0], f[1], .., f[last]): face-local lattice points
/// (u, v) of `local` (already strictly inside the face) go to
/// f0 + (u (f1 - f0) + v (f_last - f0)) / p, as gmsh places them.
void AddFaceNodes(const Lattice& vertices, const int* face, int faceSize, const Lattice& local, int p, Lattice* out) {
  const auto& f0 = vertices[face[0]];
  const auto& f1 = vertices[face[1]];
  const auto& fl = vertices[face[faceSize - 1]];
  for (const auto& uv : local) {
    std::array<int, 3> x{};
    for (int k = 0; k < 3; ++k) x[k] = f0[k] + (uv[0] * (f1[k] - f0[k]) + uv[1] * (fl[k] - f0[k])) / p;
    out->push_back(x);
  }
}

/// Line of order p: both ends, then the interior from 0 to p.
Lattice LineNodes(int p) {
  if (p < 0) return {};
  if (p == 0) return {{0, 0, 0}};
  Lattice out{{0, 0, 0}, {p, 0, 0}};
  for (int k = 1; k < p; ++k) out.push_back({k, 0, 0});
  return out;
}

/// Triangle of order p: vertices, edges, then the interior as a triangle of
/// order p - 3 (incomplete: no interior).
Lattice TriNodes(int p, bool incomplete) {
  if (p < 0) return {};
  if (p == 0) return {{0, 0, 0}};
  Lattice out{{0, 0, 0}, {p, 0, 0}, {0, p, 0}};
  const Lattice vertices = out;
  AddEdgeNodes(vertices, kTriEdges, p, &out);
  if (!incomplete) {
    const Lattice inner = Shifted(TriNodes(p - 3, false), 2, 1);
    out.insert(out.end(), inner.begin(), inner.end());
  }
  return out;
}

/// Quadrangle of order p: vertices, edges, then the interior as a
/// quadrangle of order p - 2.
Lattice QuadNodes(int p, bool incomplete) {
  if (p < 0) return {};
  if (p == 0) return {{0, 0, 0}};
  Lattice out{{0, 0, 0}, {p, 0, 0}, {p, p, 0}, {0, p, 0}};
  const Lattice vertices = out;
  AddEdgeNodes(vertices, kQuadEdges, p, &out);
  if (!incomplete) {
    const Lattice inner = Shifted(QuadNodes(p - 2, false), 2, 1);
    out.insert(out.end(), inner.begin(), inner.end());
  }
  return out;
}

/// Tetrahedron of order p: vertices, edges, faces, then the interior as a
/// tetrahedron of order p - 4.
Lattice TetNodes(int p, bool incomplete) {
  if (p < 0) return {};
  if (p == 0) return {{0, 0, 0}};
  Lattice out{{0, 0, 0}, {p, 0, 0}, {0, p, 0}, {0, 0, p}};
  const Lattice vertices = out;
  AddEdgeNodes(vertices, kTetEdges, p, &out);
  if (!incomplete) {
    const Lattice faceLocal = Shifted(TriNodes(p - 3, false), 2, 1);
    for (const auto& face : kTetFaces) AddFaceNodes(vertices, face, 3, faceLocal, p, &out);
    const Lattice inner = Shifted(TetNodes(p - 4, false), 3, 1);
    out.insert(out.end(), inner.begin(), inner.end());
  }
  return out;
}

/// Hexahedron of order p: vertices, edges, faces, then the interior as a
/// hexahedron of order p - 2.
Lattice HexNodes(int p, bool incomplete) {
  if (p < 0) return {};
  if (p == 0) return {{0, 0, 0}};
  Lattice out{{0, 0, 0}, {p, 0, 0}, {p, p, 0}, {0, p, 0}, {0, 0, p}, {p, 0, p}, {p, p, p}, {0, p, p}};
  const Lattice vertices = out;
  AddEdgeNodes(vertices, kHexEdges, p, &out);
  if (!incomplete) {
    const Lattice faceLocal = Shifted(QuadNodes(p - 2, false), 2, 1);
    for (const auto& face : kHexFaces) AddFaceNodes(vertices, face, 4, faceLocal, p, &out);
    const Lattice inner = Shifted(HexNodes(p - 2, false), 3, 1);
    out.insert(out.end(), inner.begin(), inner.end());
  }
  return out;
}

/// Prism of order p >= 1: vertices, edges, the two triangles, the three
/// quadrangles, then the interior (triangle nodes outer, line nodes inner).
Lattice PrismNodes(int p, bool incomplete) {
  Lattice out{{0, 0, 0}, {p, 0, 0}, {0, p, 0}, {0, 0, p}, {p, 0, p}, {0, p, p}};
  const Lattice vertices = out;
  AddEdgeNodes(vertices, kPrismEdges, p, &out);
  if (!incomplete) {
    const Lattice triLocal = Shifted(TriNodes(p - 3, false), 2, 1);
    for (const auto& face : kPrismTriFaces) AddFaceNodes(vertices, face, 3, triLocal, p, &out);
    const Lattice quadLocal = Shifted(QuadNodes(p - 2, false), 2, 1);
    for (const auto& face : kPrismQuadFaces) AddFaceNodes(vertices, face, 4, quadLocal, p, &out);
    const Lattice lineInner = Shifted(LineNodes(p - 2), 1, 1);
    for (const auto& st : triLocal) {
      for (const auto& r : lineInner) out.push_back({st[0], st[1], r[0]});
    }
  }
  return out;
}

/// Node lattice of an element type in gmsh's order.
Lattice NodeLattice(const GmshElementType& type) {
  switch (type.cell) {
    case CellType::Line:
      return LineNodes(type.order);
    case CellType::Tri:
      return TriNodes(type.order, type.incomplete);
    case CellType::Quad:
      return QuadNodes(type.order, type.incomplete);
    case CellType::Tet:
      return TetNodes(type.order, type.incomplete);
    case CellType::Hex:
      return HexNodes(type.order, type.incomplete);
    case CellType::Wedge:
      return PrismNodes(type.order, type.incomplete);
  }
  return {};
}

/// The table, sorted by type number (FindGmshElementType bisects it).
std::vector<GmshElementType> MakeTypes() {
  using C = CellType;
  return {
      {1, C::Line, 1, false, 2, "2-node line"},          {2, C::Tri, 1, false, 3, "3-node triangle"},
      {3, C::Quad, 1, false, 4, "4-node quadrangle"},    {4, C::Tet, 1, false, 4, "4-node tetrahedron"},
      {5, C::Hex, 1, false, 8, "8-node hexahedron"},     {6, C::Wedge, 1, false, 6, "6-node prism"},
      {8, C::Line, 2, false, 3, "3-node line"},          {9, C::Tri, 2, false, 6, "6-node triangle"},
      {10, C::Quad, 2, false, 9, "9-node quadrangle"},   {11, C::Tet, 2, false, 10, "10-node tetrahedron"},
      {12, C::Hex, 2, false, 27, "27-node hexahedron"},  {13, C::Wedge, 2, false, 18, "18-node prism"},
      {16, C::Quad, 2, true, 8, "8-node quadrangle"},    {17, C::Hex, 2, true, 20, "20-node hexahedron"},
      {18, C::Wedge, 2, true, 15, "15-node prism"},      {20, C::Tri, 3, true, 9, "9-node triangle"},
      {21, C::Tri, 3, false, 10, "10-node triangle"},    {22, C::Tri, 4, true, 12, "12-node triangle"},
      {23, C::Tri, 4, false, 15, "15-node triangle"},    {26, C::Line, 3, false, 4, "4-node line"},
      {27, C::Line, 4, false, 5, "5-node line"},         {29, C::Tet, 3, false, 20, "20-node tetrahedron"},
      {30, C::Tet, 4, false, 35, "35-node tetrahedron"}, {32, C::Tet, 4, true, 22, "22-node tetrahedron"},
      {36, C::Quad, 3, false, 16, "16-node quadrangle"}, {37, C::Quad, 4, false, 25, "25-node quadrangle"},
      {39, C::Quad, 3, true, 12, "12-node quadrangle"},  {40, C::Quad, 4, true, 16, "16-node incomplete quadrangle"},
      {90, C::Wedge, 3, false, 40, "40-node prism"},     {91, C::Wedge, 4, false, 75, "75-node prism"},
      {92, C::Hex, 3, false, 64, "64-node hexahedron"},  {93, C::Hex, 4, false, 125, "125-node hexahedron"},
      {99, C::Hex, 3, true, 32, "32-node hexahedron"},   {100, C::Hex, 4, true, 44, "44-node hexahedron"},
      {111, C::Wedge, 3, true, 24, "24-node prism"},     {112, C::Wedge, 4, true, 33, "33-node prism"},
      {137, C::Tet, 3, true, 16, "16-node tetrahedron"},
  };
}

}  // namespace

const std::vector<GmshElementType>& GmshElementTypes() {
  static const std::vector<GmshElementType> types = MakeTypes();
  return types;
}

const GmshElementType* FindGmshElementType(int mshType) {
  const auto& types = GmshElementTypes();
  const auto it = std::lower_bound(types.begin(), types.end(), mshType,
                                   [](const GmshElementType& t, int n) { return t.mshType < n; });
  return it != types.end() && it->mshType == mshType ? &*it : nullptr;
}

bool IsGmshPoint(int mshType) { return mshType == 15; }

bool IsGmshPyramid(int mshType) {
  // MSH_PYR_5, _14, _13, the complete orders 3..9 (118..124), the incomplete
  // ones (125..131) and the order-0 pyramid (132).
  return mshType == 7 || mshType == 14 || mshType == 19 || (mshType >= 118 && mshType <= 132);
}

std::vector<std::array<double, 3>> GmshReferenceNodes(const GmshElementType& type) {
  const Lattice lattice = NodeLattice(type);
  std::vector<std::array<double, 3>> nodes(lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    for (int k = 0; k < 3; ++k) nodes[i][k] = static_cast<double>(lattice[i][k]) / type.order;
  }
  return nodes;
}

std::vector<std::array<int, 3>> GmshIncompleteMonomials(const GmshElementType& type) {
  if (!type.incomplete) return {};
  const int p = type.order;
  switch (type.cell) {
    case CellType::Tri:
    case CellType::Tet:
      return NodeLattice(type);
    case CellType::Quad:
    case CellType::Hex: {
      const int dims = type.cell == CellType::Quad ? 2 : 3;
      std::vector<std::array<int, 3>> out;
      for (int c = 0; c <= (dims == 3 ? p : 0); ++c) {
        for (int b = 0; b <= p; ++b) {
          for (int a = 0; a <= p; ++a) {
            if ((a > 1) + (b > 1) + (c > 1) <= 1) out.push_back({a, b, c});
          }
        }
      }
      return out;
    }
    case CellType::Wedge: {
      std::vector<std::array<int, 3>> out;
      for (const auto& st : TriNodes(p, true)) {
        for (int c = 0; c <= 1; ++c) out.push_back({st[0], st[1], c});
      }
      for (int c = 2; c <= p; ++c) {
        for (const std::array<int, 3>& st : {std::array<int, 3>{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}) {
          out.push_back({st[0], st[1], c});
        }
      }
      return out;
    }
    case CellType::Line:
      break;
  }
  return {};
}

}  // namespace invmap::io
