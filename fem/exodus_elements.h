// Exodus II element types invmap reads, with their node positions in
// invmap's reference coordinates (docs/formats.md section 1) and, for the
// serendipity ones, their polynomial spaces. The node order is Exodus's
// (the PATRAN convention of the Exodus manual; the edge and face node
// lists of SEACAS's IOSS element topologies): vertices, edge nodes, then a
// hex27's volume centre and face centres.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::fem {

/// One Exodus element type: its topology and node count.
struct ExodusElementType {
  CellType cell = CellType::Line;
  int numNodes = 0;
  int degree = 1;            ///< Degree of the Bezier cell it becomes (every factor).
  bool serendipity = false;  ///< QUAD8, HEX20, WEDGE15: not a complete tensor space.
  const char* name = "";     ///< Canonical name, e.g. "HEX20".
};

/// The type of a block from its Exodus element type name (any case; the
/// base name alone or with the node count: "hex", "HEX27", "tetra10",
/// "shell4", "trishell", "bar3") and its nodes per element. False for the
/// types invmap does not read (pyramids, spheres, polygons, tri7, tet14, ...).
bool FindExodusElementType(const std::string& typeName, int nodesPerElement, ExodusElementType* type);

/// Reference coordinates of the nodes of `type` in Exodus order.
std::vector<std::array<double, 3>> ExodusReferenceNodes(const ExodusElementType& type);

/// Exponents (a, b, c) of the monomials s^a t^b r^c spanning a serendipity
/// type's space (empty for complete types): QUAD8 every exponent up to 2
/// with at most one of them 2; HEX20 likewise in three variables; WEDGE15
/// the quadratic triangle times {1, r} plus {1, s, t} times r^2. Converted
/// to Bezier form these become the biquadratic (triquadratic, quadratic
/// wedge) cell whose extra control points the space determines, so the map
/// and the fields are exactly the element's.
std::vector<std::array<int, 3>> ExodusSerendipityMonomials(const ExodusElementType& type);

}  // namespace invmap::fem
