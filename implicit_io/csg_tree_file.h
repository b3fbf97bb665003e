// The CSG tree file of `invmap grid` (docs/grids.md#csg-trees): how the
// functions of a list combine into a solid.
#pragma once

#include <string>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::io {

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

/// ReadCsgTree of JSON text held in memory, named `name` in messages (the
/// Python package's lists).
std::vector<implicit::CsgNode> ParseCsgTree(const std::string& text, const std::string& name, int functionCount);

}  // namespace invmap::io
