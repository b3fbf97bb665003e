// Reader of gmsh MSH 4.1 meshes (ascii and binary), linear and high order,
// into Bezier cells.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "invmap/fields.h"
#include "invmap/invmap.h"

namespace invmap::io {

/// Where one patch of a geometry read from a gmsh file comes from.
struct GmshPatchSource {
  /// True: a physical group; false: an elementary entity (a file without
  /// physical groups).
  bool physicalGroup = false;
  int dim = 0;       ///< Dimension of the group or entity (1, 2 or 3).
  int tag = 0;       ///< Physical tag or entity tag.
  std::string name;  ///< The group's name from $PhysicalNames; empty when it has none.
};

/// Reads a gmsh MSH 4.1 file, ascii or binary (either byte order, data size
/// 8). Sections $MeshFormat, $PhysicalNames, $Entities, $Nodes and $Elements
/// are read; other sections are skipped; $PartitionedEntities is an error.
///
/// Elements: lines, triangles, quadrangles, tetrahedra, hexahedra and prisms
/// of order 1 to 4, complete or incomplete (gmsh's serendipity-like types;
/// io/gmsh_elements.h lists them). Each becomes one Bezier cell of the same
/// order (complete space) by an exact change of basis from its Lagrange
/// nodes: the cell's map equals the element's at every reference point, with
/// reference coordinates in docs/formats.md's [0, 1] domains (gmsh's [-1, 1]
/// coordinates u map to (u + 1) / 2). Point elements are skipped; pyramids
/// and other element types are an error naming the element.
///
/// Patches, each of kind BezierCells with cells in file order:
///  - one per physical group, those of $PhysicalNames first in its order, then
///    the others in the order their entities appear in $Entities; a group gets
///    the elements of every entity tagged with it, of any dimension (a group
///    of boundary triangles in a volume mesh is a surface patch). A group
///    with no cells (points only) gets no patch.
///  - without physical groups: one per elementary entity of the mesh's
///    highest element dimension, in $Entities order, so a volume mesh's
///    boundary triangles do not duplicate its volume's faces.
/// The geometry's dimension is 2 when no element is a volume and every node
/// has z == 0, else 3.
///
/// Throws InputError naming the file and, in ascii files, the line, for a
/// missing or unreadable file, a version other than 4.1, truncated data,
/// counts that disagree with the data (or exceed what the rest of the file
/// can hold), tokens that are not numbers, undefined or duplicate node tags,
/// coordinates that are not finite, unsupported element types, and a file
/// with no cells. `sources`, when not null, receives one entry per patch.
Geometry ReadGmsh(const std::string& path, std::vector<GmshPatchSource>* sources = nullptr);

/// The same from a stream (read to its end), named `name` in messages.
Geometry ReadGmsh(std::istream& in, const std::string& name, std::vector<GmshPatchSource>* sources = nullptr);

/// One view of a file's $NodeData sections: the values of its highest time
/// step at every node.
struct GmshNodeView {
  std::string name;
  std::int64_t timeStep = -1;  ///< gmsh's time step index (from 0).
  int components = 1;          ///< 1 (scalar), 3 (vector) or 9 (tensor); gmsh allows 1 to 9.
  /// `components` values per node, in $Nodes order; NaN at nodes that no
  /// section of this step gives a value.
  std::vector<double> values;
};

/// ReadGmsh plus the file's $NodeData: one NodeField per view (its highest
/// time step; sections of that step from several partitions together), in
/// the order the views first appear, converted to each cell's Bernstein
/// coefficients by the cell's own change of basis, so a cell interpolates
/// the field exactly as gmsh's element does. A node without a value gives
/// NaN coefficients to the cells around it. $NodeData sections need 3
/// integer tags (time step, components, count) and refer to defined nodes,
/// else InputError. $ElementData and $ElementNodeData are skipped.
FieldGeometry ReadGmshWithFields(const std::string& path, std::vector<GmshPatchSource>* sources = nullptr);

/// The same from a stream, named `name` in messages.
FieldGeometry ReadGmshWithFields(std::istream& in, const std::string& name,
                                 std::vector<GmshPatchSource>* sources = nullptr);

}  // namespace invmap::io
