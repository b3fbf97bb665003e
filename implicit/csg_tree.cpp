// CSG tree validation and evaluation (csg_tree.h). Both walk the tree with
// an explicit stack: a file may hold a tree hundreds of nodes deep.
#include "implicit/csg_tree.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>

namespace invmap::implicit {
namespace {

int OperandCount(const CsgNode& node) { return node.op == CsgNode::Op::Negation ? 1 : 2; }

int Operand(const CsgNode& node, int which) { return which == 0 ? node.a : node.b; }

std::string CheckOperand(int nodeIndex, const CsgNode& node, int operand, int nodeCount, int functionCount) {
  std::ostringstream message;
  if (operand == 0) {
    message << "node " << nodeIndex << ": operand 0 names nothing ("
            << (node.op == CsgNode::Op::Negation ? "Negation needs its first operand"
                                                 : "Intersection and Union need two operands")
            << ")";
  } else if (operand > nodeCount) {
    message << "node " << nodeIndex << ": operand " << operand << " names node " << operand << " but there are "
            << nodeCount << " nodes";
  } else if (operand < 0 && -static_cast<long long>(operand) > functionCount) {
    message << "node " << nodeIndex << ": operand " << operand << " names function " << -static_cast<long long>(operand)
            << " but there are " << functionCount << " functions";
  }
  return message.str();
}

}  // namespace

std::string ValidateCsgTree(const std::vector<CsgNode>& tree, int functionCount) {
  if (tree.empty()) return "the CSG tree is empty (node 1 is its root)";
  if (tree.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) return "the CSG tree has too many nodes";
  const int nodeCount = static_cast<int>(tree.size());
  for (int n = 1; n <= nodeCount; ++n) {
    const CsgNode& node = tree[n - 1];
    for (int which = 0; which < OperandCount(node); ++which) {
      std::string problem = CheckOperand(n, node, Operand(node, which), nodeCount, functionCount);
      if (!problem.empty()) return problem;
    }
  }

  // Depth-first from the root: an operand that is still on the stack closes
  // a cycle; a node never reached is not part of the solid.
  enum : std::uint8_t { kUnseen, kOnStack, kDone };
  std::vector<std::uint8_t> state(nodeCount + 1, kUnseen);
  std::vector<std::pair<int, int>> stack = {{1, 0}};  // (node, next operand to visit)
  state[1] = kOnStack;
  while (!stack.empty()) {
    auto& [n, next] = stack.back();
    const CsgNode& node = tree[n - 1];
    if (next == OperandCount(node)) {
      state[n] = kDone;
      stack.pop_back();
      continue;
    }
    const int operand = Operand(node, next++);
    if (operand < 0) continue;
    if (state[operand] == kOnStack) {
      std::ostringstream message;
      message << "node " << n << ": operand " << operand << " makes a cycle (node " << operand
              << " is this node or one of its ancestors)";
      return message.str();
    }
    if (state[operand] == kUnseen) {
      state[operand] = kOnStack;
      stack.emplace_back(operand, 0);
    }
  }
  for (int n = 1; n <= nodeCount; ++n) {
    if (state[n] == kUnseen) {
      std::ostringstream message;
      message << "node " << n << " is not reachable from the root (node 1)";
      return message.str();
    }
  }
  return {};
}

double EvaluateCsg(const std::vector<CsgNode>& tree, const double* functionValues) {
  const std::size_t nodeCount = tree.size();
  std::vector<double> nodeValue(nodeCount + 1, 0);
  std::vector<std::uint8_t> expanded(nodeCount + 1, 0), done(nodeCount + 1, 0);
  auto valueOf = [&](int operand) { return operand < 0 ? functionValues[-operand - 1] : nodeValue[operand]; };
  // Post-order: a node is computed when it is on top of the stack the second
  // time, after every operand pushed above it has been computed.
  std::vector<int> stack = {1};
  while (!stack.empty()) {
    const int n = stack.back();
    const CsgNode& node = tree[n - 1];
    if (done[n]) {
      stack.pop_back();
    } else if (!expanded[n]) {
      expanded[n] = 1;
      for (int which = 0; which < OperandCount(node); ++which) {
        const int operand = Operand(node, which);
        if (operand > 0 && !done[operand]) stack.push_back(operand);
      }
    } else {
      switch (node.op) {
        case CsgNode::Op::Intersection: nodeValue[n] = std::max(valueOf(node.a), valueOf(node.b)); break;
        case CsgNode::Op::Union: nodeValue[n] = std::min(valueOf(node.a), valueOf(node.b)); break;
        case CsgNode::Op::Negation: nodeValue[n] = -valueOf(node.a); break;
      }
      done[n] = 1;
      stack.pop_back();
    }
  }
  return nodeValue[1];
}

}  // namespace invmap::implicit
