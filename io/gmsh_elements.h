// gmsh's Lagrange elements of orders 1 to 4 (MSH element type numbers, node
// orderings and, for the incomplete ones, their polynomial spaces), stated in
// invmap's reference coordinates (docs/formats.md section 1).
//
// Everything here was checked against gmsh 4.8 itself: the node positions
// against gmsh's reference elements (gmsh::model::mesh::getElementProperties)
// and, for prisms of order 3 and 4 (which that call cannot build), against
// the nodes of meshes gmsh generates; the incomplete spaces against gmsh's
// shape functions (getBasisFunctions). tests/io/gmsh_reader_test.cpp repeats
// the node check on meshes the gmsh binary generates.
#pragma once

#include <array>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::io {

/// One gmsh element type that invmap reads.
struct GmshElementType {
  int mshType = 0;  ///< gmsh's element type number (MSH_* in GmshDefines.h).
  CellType cell = CellType::Line;
  int order = 1;            ///< Polynomial order, 1..4; the Bezier cell gets this degree in every factor.
  bool incomplete = false;  ///< Serendipity-like: vertex and edge nodes only (gmsh's "incomplete" elements).
  int numNodes = 0;         ///< Nodes per element in the file.
  const char* name = "";    ///< gmsh's name, e.g. "10-node tetrahedron".
};

/// The element type with gmsh number `mshType`, or null when invmap does not
/// convert it (points, which a reader skips, pyramids and orders above 4).
const GmshElementType* FindGmshElementType(int mshType);

/// Every element type FindGmshElementType knows, in type-number order.
const std::vector<GmshElementType>& GmshElementTypes();

/// True for gmsh's 1-node point element (type 15), which carries no cell.
bool IsGmshPoint(int mshType);

/// True for gmsh's pyramids of any order (invmap has no pyramid cells).
bool IsGmshPyramid(int mshType);

/// Reference coordinates (invmap's, docs/formats.md section 1; unused entries 0)
/// of the nodes of `type`, in gmsh's node order: vertices, then the nodes of
/// each edge from its first to its second vertex (gmsh's edge order), then
/// face nodes (gmsh's face order, each face's nodes ordered like a smaller
/// element of the face's type spanned by the face's vertices), then interior
/// nodes (ordered like a smaller element of the same type; prisms: for each
/// interior triangle node, the interior line nodes). gmsh's own reference
/// cells differ only by the affine maps u_invmap = (u_gmsh + 1) / 2 on every
/// [-1, 1] coordinate (lines, quads, hexes, and the prism's third one).
std::vector<std::array<double, 3>> GmshReferenceNodes(const GmshElementType& type);

/// Exponents (a, b, c) of monomials s^a t^b r^c (invmap reference
/// coordinates) spanning the polynomial space of an incomplete element type;
/// empty for complete types (their space is the full Bernstein space of the
/// cell). gmsh's choices: triangles and tetrahedra take the exponents equal
/// to the node lattice points (order p: node at lattice (i, j, k) / p gives
/// s^i t^j r^k); quads and hexes take every exponent up to p with at most one
/// exponent above 1. Prisms: gmsh's 15-node prism is the triangle space of
/// order p times {1, r} plus {1, s, t} times {r^2 .. r^p}; gmsh 4.8 cannot
/// evaluate its own incomplete prisms of order 3 and 4, and invmap extends
/// the same rule to them (their faces then carry exactly the incomplete
/// triangle and quad spaces, so neighbours agree). These sets are closed under
/// lowering the exponents of the coordinates gmsh scales ([-1, 1] -> [0, 1]),
/// so they span the same space in gmsh's coordinates.
std::vector<std::array<int, 3>> GmshIncompleteMonomials(const GmshElementType& type);

}  // namespace invmap::io
