// The zero sets of a refined grid (docs/grids.md#outputs) as OBJ (every
// primitive, grouped by label) and PLY (the triangles, readable as a
// geometry). Writers go through AtomicOutput: the target is either the
// complete new file or untouched, and every failure is an InputError of
// Kind::Output naming the target.
#pragma once

#include <string>

#include "invmap/implicit.h"

namespace invmap::io {

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

}  // namespace invmap::io
