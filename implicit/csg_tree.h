// CSG trees of implicit regions (implicit.h, Mode::Csg): their validation
// and their value at a point. As in the reference implementation's tree
// files, operand i's region is {f_i <= 0}; a tree combines the regions with
// Intersection = max, Union = min and Negation = -, so the solid is
// {EvaluateCsg <= 0}.
#pragma once

#include <string>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::implicit {

/// Empty when `tree` is a usable CSG tree over `functionCount` functions,
/// else a message naming the first problem, e.g. "node 3: operand -7 names
/// function 7 but there are 5 functions". A usable tree is non-empty; every
/// operand is a node 1..tree.size() or a function -1..-functionCount (0 is
/// allowed only as the ignored `b` of a Negation); every node is reachable
/// from the root, node 1; and no node is its own operand or an operand of one
/// of its operands (no cycle). Nodes may be shared (the tree may be a DAG).
std::string ValidateCsgTree(const std::vector<CsgNode>& tree, int functionCount);

/// The CSG function at one point: Intersection = max(a, b), Union =
/// min(a, b), Negation = -a, where an operand -k is functionValues[k - 1]
/// and an operand k > 0 is the value of node k. Inside is <= 0.
/// Precondition: ValidateCsgTree(tree, n) is empty and functionValues holds
/// n values. Each node is evaluated once (shared nodes too); no recursion.
double EvaluateCsg(const std::vector<CsgNode>& tree, const double* functionValues);

}  // namespace invmap::implicit
