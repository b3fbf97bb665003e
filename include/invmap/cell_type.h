// The reference cell types and their names in geometry files
// (docs/formats.md, section 1): the one definition every layer uses.
#pragma once

#include <cstdint>
#include <string_view>

namespace invmap {

/// Reference cell types. Every type is a tensor product of one to three
/// simplices (line = 1-simplex, tri = 2-simplex, tet = 3-simplex): quad =
/// line x line, hex = line x line x line, wedge = tri x line.
enum class CellType : std::uint8_t { Line, Tri, Quad, Tet, Hex, Wedge };

/// What the formats say about a cell type.
struct CellTypeTraits {
  CellType type;
  const char* name;  ///< As written in geometry files: "line", "tri", ...
  int paramDim;      ///< Parameters of the reference cell: 1, 2 or 3.
  int vertices;      ///< Vertices of a linear (mesh) cell.
};

/// Every cell type, indexed by the enum's value.
inline constexpr CellTypeTraits kCellTypes[] = {
    {CellType::Line, "line", 1, 2}, {CellType::Tri, "tri", 2, 3}, {CellType::Quad, "quad", 2, 4},
    {CellType::Tet, "tet", 3, 4},   {CellType::Hex, "hex", 3, 8}, {CellType::Wedge, "wedge", 3, 6}};

/// The names of every type, for messages that list what is accepted.
inline constexpr const char* kCellTypeNames = "line, tri, quad, tet, hex or wedge";

/// The traits of `type` (a valid enum value).
constexpr const CellTypeTraits& TraitsOf(CellType type) { return kCellTypes[static_cast<int>(type)]; }

/// The name of `type` in geometry files.
constexpr const char* CellTypeName(CellType type) { return TraitsOf(type).name; }

/// The type called `name` in geometry files; false (and *type unchanged)
/// for any other name.
constexpr bool ParseCellType(std::string_view name, CellType* type) {
  for (const CellTypeTraits& traits : kCellTypes) {
    if (name == traits.name) {
      *type = traits.type;
      return true;
    }
  }
  return false;
}

}  // namespace invmap
