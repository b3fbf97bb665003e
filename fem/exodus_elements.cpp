#include "fem/exodus_elements.h"

#include <algorithm>
#include <cctype>

namespace invmap::fem {
namespace {

constexpr ExodusElementType kTypes[] = {
    {CellType::Line, 2, 1, false, "BAR2"},     {CellType::Line, 3, 2, false, "BAR3"},
    {CellType::Tri, 3, 1, false, "TRI3"},      {CellType::Tri, 6, 2, false, "TRI6"},
    {CellType::Quad, 4, 1, false, "QUAD4"},    {CellType::Quad, 8, 2, true, "QUAD8"},
    {CellType::Quad, 9, 2, false, "QUAD9"},    {CellType::Tet, 4, 1, false, "TET4"},
    {CellType::Tet, 10, 2, false, "TET10"},    {CellType::Hex, 8, 1, false, "HEX8"},
    {CellType::Hex, 20, 2, true, "HEX20"},     {CellType::Hex, 27, 2, false, "HEX27"},
    {CellType::Wedge, 6, 1, false, "WEDGE6"},  {CellType::Wedge, 15, 2, true, "WEDGE15"},
};

/// The topology an Exodus base name stands for.
bool TopologyOf(const std::string& base, CellType* cell) {
  static const std::pair<const char*, CellType> kNames[] = {
      {"BAR", CellType::Line},      {"BEAM", CellType::Line},     {"TRUSS", CellType::Line},
      {"EDGE", CellType::Line},     {"TRI", CellType::Tri},       {"TRIANGLE", CellType::Tri},
      {"TRISHELL", CellType::Tri},  {"QUAD", CellType::Quad},     {"SHELL", CellType::Quad},
      {"TET", CellType::Tet},       {"TETRA", CellType::Tet},     {"HEX", CellType::Hex},
      {"HEXAHEDRON", CellType::Hex}, {"WEDGE", CellType::Wedge},
  };
  for (const auto& [name, type] : kNames) {
    if (base == name) {
      *cell = type;
      return true;
    }
  }
  return false;
}

}  // namespace

bool FindExodusElementType(const std::string& typeName, int nodesPerElement, ExodusElementType* type) {
  std::string upper;
  for (const char c : typeName) {
    if (c != ' ' && c != '\0') upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  std::string base = upper;
  while (!base.empty() && std::isdigit(static_cast<unsigned char>(base.back()))) base.pop_back();
  const std::string digits = upper.substr(base.size());
  CellType cell;
  if (!TopologyOf(base, &cell)) return false;
  // A count in the name must agree with the block's.
  if (!digits.empty() && std::to_string(nodesPerElement) != digits) return false;
  for (const ExodusElementType& t : kTypes) {
    if (t.cell == cell && t.numNodes == nodesPerElement) {
      *type = t;
      return true;
    }
  }
  return false;
}

std::vector<std::array<double, 3>> ExodusReferenceNodes(const ExodusElementType& type) {
  const double h = 0.5;
  std::vector<std::array<double, 3>> all;
  switch (type.cell) {
    case CellType::Line:
      all = {{0, 0, 0}, {1, 0, 0}, {h, 0, 0}};
      break;
    case CellType::Tri:
      all = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {h, 0, 0}, {h, h, 0}, {0, h, 0}};
      break;
    case CellType::Quad:
      all = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {h, 0, 0}, {1, h, 0}, {h, 1, 0}, {0, h, 0}, {h, h, 0}};
      break;
    case CellType::Tet:
      all = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {h, 0, 0},
             {h, h, 0}, {0, h, 0}, {0, 0, h}, {h, 0, h}, {0, h, h}};
      break;
    case CellType::Hex:
      all = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1},
             {0, 1, 1},  // vertices
             {h, 0, 0}, {1, h, 0}, {h, 1, 0}, {0, h, 0},  // bottom edges
             {0, 0, h}, {1, 0, h}, {1, 1, h}, {0, 1, h},  // vertical edges
             {h, 0, 1}, {1, h, 1}, {h, 1, 1}, {0, h, 1},  // top edges
             {h, h, h},                                   // volume centre
             {h, h, 0}, {h, h, 1}, {0, h, h}, {1, h, h}, {h, 0, h}, {h, 1, h}};  // face centres
      break;
    case CellType::Wedge:
      all = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1},  // vertices
             {h, 0, 0}, {h, h, 0}, {0, h, 0},                                   // bottom edges
             {0, 0, h}, {1, 0, h}, {0, 1, h},                                   // vertical edges
             {h, 0, 1}, {h, h, 1}, {0, h, 1}};                                  // top edges
      break;
  }
  all.resize(static_cast<std::size_t>(type.numNodes));
  return all;
}

std::vector<std::array<int, 3>> ExodusSerendipityMonomials(const ExodusElementType& type) {
  std::vector<std::array<int, 3>> out;
  if (!type.serendipity) return out;
  if (type.cell == CellType::Wedge) {
    for (int c = 0; c <= 2; ++c) {
      const int triangleDegree = c < 2 ? 2 : 1;
      for (int b = 0; b <= triangleDegree; ++b) {
        for (int a = 0; a + b <= triangleDegree; ++a) out.push_back({a, b, c});
      }
    }
    return out;
  }
  const int last = type.cell == CellType::Hex ? 2 : 0;
  for (int c = 0; c <= last; ++c) {
    for (int b = 0; b <= 2; ++b) {
      for (int a = 0; a <= 2; ++a) {
        if ((a == 2) + (b == 2) + (c == 2) <= 1) out.push_back({a, b, c});
      }
    }
  }
  return out;
}

}  // namespace invmap::fem
