// The files of `invmap grid` (FORMATS.md section 6): the function list and
// CSG tree JSON files of shared/benchmarks/implicit/README.md and an initial
// grid from gmsh in; the refined grid (gmsh MSH 4.1, VTK XML), its zero sets
// (OBJ, PLY) and its figures (stats.json) out.
//
// Readers throw InputError (Kind::Input) naming the file and, for JSON, the
// 1-based line of the offending value. Writers go through AtomicOutput: the
// target is either the complete new file or untouched, and every failure is
// an InputError of Kind::Output naming the target. Writers throw
// std::invalid_argument for inconsistent in-memory arguments (array sizes
// that disagree), which are programming errors, not user errors.
#pragma once

#include <string>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::io {

/// Reads a JSON list of function objects (at least one), in file order.
///
/// Objects, by "type" (fields in any order; numbers may be integers):
///  - "sphere":   center [3], radius > 0, optional squared (bool, default false)
///  - "cylinder": axis_point [3], axis_vector [3] (non-zero), radius > 0, optional squared
///  - "plane":    point [3], normal [3] (non-zero)
///  - "torus":    center [3], axis_vector [3] (non-zero), major_radius > 0, minor_radius > 0
///  - "cone":     apex [3], axis_vector [3] (non-zero), angle: the half angle in
///                radians, 0 < angle < pi/2
///  - "quintic":  optional center [3] (default the origin): x^5 + x^4 - 2y^2 of x - center
///  - "gyroid":   period > 0
/// Every object may also carry "name" (a string), which replaces the
/// function's default name (its type) in output labels. Points and vectors
/// have `dimension` numbers: 3, or 2 for a 2D grid (z is then 0). Every
/// number must be finite. Functions are built by the factories of implicit.h.
///
/// Throws InputError at the line of the offending value for: a missing or
/// unreadable file, invalid JSON, a top level that is not a non-empty list,
/// an element that is not an object, a missing or unknown "type" (the
/// message lists the known ones), a missing, unknown (the message lists the
/// allowed ones), duplicate or mistyped field, a wrong array length, a
/// non-finite number and the range violations above.
std::vector<implicit::Function> ReadFunctionList(const std::string& path, int dimension);

/// Reads a CSG tree file: a non-empty JSON list of nodes
/// {"type": "Intersection" | "Union" | "Negation", "elements": [a, b]}.
/// Node 1 (the first) is the root; an operand k > 0 is node k (1..nodes),
/// k < 0 is function -k (1..functionCount). A Negation has one operand:
/// "elements" is [a] or [a, 0]. Returns the nodes in file order.
///
/// Throws InputError at the line of the offending node or value for: a
/// missing or unreadable file, invalid JSON, a top level that is not a
/// non-empty list, a node that is not an object, missing, unknown,
/// duplicate or mistyped fields, an unknown type, a wrong operand count, an
/// operand out of range or 0, a cycle (a node that is its own operand,
/// directly or not; the message gives the cycle) and a node not reachable
/// from the root; finally implicit::ValidateCsgTree must accept the tree
/// (its message, without a line, otherwise).
std::vector<implicit::CsgNode> ReadCsgTree(const std::string& path, int functionCount);

/// Reads an initial grid from a gmsh MSH 4.1 file (io::ReadGmsh): linear
/// tetrahedra (3D), or linear triangles when every node has z == 0 (2D).
/// Lower-dimensional elements (lines; triangles in a tetrahedral mesh) are
/// boundary tags and are skipped; points are skipped by ReadGmsh. Vertices
/// with exactly equal coordinates are merged into one (ReadGmsh gives each
/// cell its own copies), in order of first use. Every cell is made
/// positively oriented (two vertices are swapped when its signed volume or
/// area is negative).
///
/// Throws InputError naming the file for everything ReadGmsh rejects, for an
/// element of another type or order (the message names it), for a file with
/// no tetrahedra or triangles, for more than 2^32 - 1 vertices, and for a
/// cell of zero volume (area), naming the cell's 0-based index among the
/// kept cells.
implicit::SimplexMesh ReadSimplexMeshMsh(const std::string& path);

/// ReadFunctionList and ReadCsgTree of JSON text held in memory, named
/// `name` in messages (the Python package's lists and dicts).
std::vector<implicit::Function> ParseFunctionList(const std::string& text, const std::string& name, int dimension);
std::vector<implicit::CsgNode> ParseCsgTree(const std::string& text, const std::string& name, int functionCount);

/// Writes the grid as gmsh MSH 4.1 ascii: one volume entity (surface in 2D)
/// holding every node (tags 1..N, in vertex order) and every cell (tags
/// 1..C, type 4 tetrahedra or type 2 triangles), then one $NodeData view per
/// function (string tag "f<i> <name>", time 0, 1 component) and an
/// $ElementData view "active" (0/1) when grid.active is not empty. Numbers
/// are the shortest text that reads back as the same double.
///
/// `functionNames`: one per function (grid.functionCount), or empty for
/// labels "f<i>" alone. Throws std::invalid_argument when the sizes of
/// grid.mesh, grid.values, grid.active or functionNames disagree.
void WriteGridMsh(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path);

/// Writes the grid as a VTK XML UnstructuredGrid (.vtu) with raw appended
/// binary data (little endian, UInt64 block headers): Float64 points,
/// Int64 connectivity and offsets, UInt8 types (10 tetra, 5 triangle), one
/// Float64 point array per function named like WriteGridMsh's views, and the
/// UInt8 cell array "active" when grid.active is not empty. Same arguments
/// and std::invalid_argument cases as WriteGridMsh.
void WriteGridVtu(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path);

/// Writes the zero sets as Wavefront OBJ: every vertex ("v x y z"), then one
/// group per distinct label, in increasing label order, named by its
/// function indices ("g f0", "g f0_f2", ...), holding that label's
/// triangles ("f a b c"), segments ("l a b") and points ("p a"), 1-based.
/// Throws std::invalid_argument when a primitive array's length is not a
/// multiple of its arity or disagrees with its labels.
void WriteZeroSetsObj(const implicit::ZeroSets& zeroSets, const std::string& path);

/// Writes the zero-set triangles alone as binary little-endian PLY, readable
/// by ReadPlyMesh (so the surfaces can be given to `invmap invert
/// --geometry`): element vertex (double x, y, z), only the vertices the
/// triangles use, renumbered in order of first use; element face (list
/// uchar uint vertex_indices, then int label0..label3: the triangle's
/// label, -1 unused). Same std::invalid_argument cases as WriteZeroSetsObj.
void WriteZeroSetsPly(const implicit::ZeroSets& zeroSets, const std::string& path);

/// Writes stats.json (FORMATS.md section 6): exactly the keys "cells",
/// "active_cells", "vertices" (integers), "min_radius_ratio",
/// "min_radius_ratio_active" and "seconds" (numbers), in this order.
/// (Whether --max-cells stopped the refinement is in the command's summary.)
void WriteGridStats(const implicit::GridStats& stats, const std::string& path);

}  // namespace invmap::io
