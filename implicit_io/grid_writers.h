// The refined grid of `invmap grid` (docs/grids.md#outputs) as gmsh MSH 4.1
// and VTK XML files, and its figures as stats.json. Writers go through
// AtomicOutput: the target is either the complete new file or untouched, and
// every failure is an InputError of Kind::Output naming the target. They
// throw std::invalid_argument for inconsistent in-memory arguments (array
// sizes that disagree), which are programming errors, not user errors.
#pragma once

#include <string>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::io {

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

/// Writes stats.json (docs/grids.md#outputs): exactly the keys "cells",
/// "active_cells", "vertices" (integers), "min_radius_ratio",
/// "min_radius_ratio_active" and "seconds" (numbers), in this order.
/// (Whether --max-cells stopped the refinement is in the command's summary.)
void WriteGridStats(const implicit::GridStats& stats, const std::string& path);

}  // namespace invmap::io
