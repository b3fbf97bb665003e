#include "implicit_io/csg_tree_file.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "implicit/csg_tree.h"
#include "implicit_io/json_values.h"
#include "io/file_io.h"
#include "io/input_error.h"

namespace invmap::io {
namespace {

using json::Describe;
using json::ObjectReader;
using json::ParseJsonList;
using json::Value;

/// The node types of a tree file, for messages.
const char* const kCsgTypes = "Intersection, Union or Negation";

/// Throws when the operands of `tree` form a cycle, naming one: a node
/// reached again while it is still being explored.
void CheckAcyclic(const std::string& path, const std::vector<implicit::CsgNode>& tree,
                  const std::vector<std::array<std::int64_t, 2>>& operandLines) {
  const std::size_t n = tree.size();
  enum : std::uint8_t { kNew, kOpen, kDone };
  std::vector<std::uint8_t> state(n, kNew);
  // Iterative depth-first search (a tree file may be a long chain): each
  // frame is a node and the operand to look at next.
  std::vector<std::pair<std::size_t, int>> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (state[start] != kNew) continue;
    stack.push_back({start, 0});
    state[start] = kOpen;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next == 2) {
        state[node] = kDone;
        stack.pop_back();
        continue;
      }
      const int operandIndex = next++;
      const implicit::CsgNode& c = tree[node];
      const int operand = operandIndex == 0 ? c.a : c.b;
      if (operand <= 0) continue;
      const std::size_t child = static_cast<std::size_t>(operand - 1);
      if (state[child] == kOpen) {
        std::string cycle;
        const auto from = std::find_if(stack.begin(), stack.end(), [&](const auto& frame) { return frame.first == child; });
        for (auto it = from; it != stack.end(); ++it) cycle += "node " + std::to_string(it->first + 1) + " -> ";
        cycle += "node " + std::to_string(child + 1);
        throw InputError(path, operandLines[node][static_cast<std::size_t>(operandIndex)],
                         "node " + std::to_string(node + 1) + ": the tree has a cycle: " + cycle);
      }
      if (state[child] == kNew) {
        state[child] = kOpen;
        stack.push_back({child, 0});  // Invalidates node and next, which are not used again.
      }
    }
  }
}

}  // namespace

std::vector<implicit::CsgNode> ReadCsgTree(const std::string& path, int functionCount) {
  return ParseCsgTree(ReadWholeFile(path, json::kMaxImplicitFileBytes), path, functionCount);
}

std::vector<implicit::CsgNode> ParseCsgTree(const std::string& text, const std::string& path, int functionCount) {
  const Value root = ParseJsonList(text, path, "CSG node");
  const std::size_t n = root.items.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InputError(path, root.line, "too many nodes (" + std::to_string(n) + ")");
  }
  std::vector<implicit::CsgNode> tree(n);
  std::vector<std::array<std::int64_t, 2>> operandLines(n);
  const std::string ranges = "nodes 1.." + std::to_string(n) + ", functions -1..-" + std::to_string(functionCount);
  for (std::size_t k = 0; k < n; ++k) {
    const Value& object = root.items[k];
    const std::string where = "node " + std::to_string(k + 1);
    if (object.type != Value::Type::Object) {
      throw InputError(path, object.line, where + ": expected an object {\"type\", \"elements\"}, found " +
                                              Describe(object));
    }
    const ObjectReader r(path, object, where);
    r.CheckKeys({"type", "elements"}, "a CSG node");
    const Value& typeValue = r.Required("type", std::string(kCsgTypes));
    if (typeValue.type != Value::Type::String) {
      r.FailField(typeValue, "type", std::string("expected a string (") + kCsgTypes + "), found " + Describe(typeValue));
    }
    implicit::CsgNode& node = tree[k];
    if (typeValue.text == "Intersection") {
      node.op = implicit::CsgNode::Op::Intersection;
    } else if (typeValue.text == "Union") {
      node.op = implicit::CsgNode::Op::Union;
    } else if (typeValue.text == "Negation") {
      node.op = implicit::CsgNode::Op::Negation;
    } else {
      r.FailField(typeValue, "type", "unknown node type \"" + typeValue.text + "\" (known: " + kCsgTypes + ")");
    }
    const bool negation = node.op == implicit::CsgNode::Op::Negation;
    const Value& elements = r.Required("elements", "a list of operands");
    if (elements.type != Value::Type::Array) {
      r.FailField(elements, "elements", "expected a list of operands, found " + Describe(elements));
    }
    const std::size_t count = elements.items.size();
    if (negation ? (count != 1 && count != 2) : count != 2) {
      r.FailField(elements, "elements",
                  std::to_string(count) + (count == 1 ? " operand, " : " operands, ") +
                      (negation ? "a Negation has one: [a] or [a, 0]" : typeValue.text + " takes two: [a, b]"));
    }
    int operands[2] = {0, 0};
    for (std::size_t i = 0; i < count; ++i) {
      const Value& e = elements.items[i];
      const std::string field = "elements[" + std::to_string(i) + "]";
      if (e.type != Value::Type::Number || !e.integral) {
        r.FailField(e, field, "expected an integer operand (" + ranges + "), found " + Describe(e));
      }
      operandLines[k][i] = e.line;
      if (negation && i == 1) {
        if (e.integer != 0) r.FailField(e, field, e.text + ": a Negation has one operand, the second must be 0");
        continue;
      }
      if (e.integer == 0) r.FailField(e, field, "operand 0 is neither a node nor a function (" + ranges + ")");
      if (e.integer > 0 && e.integer > static_cast<std::int64_t>(n)) {
        r.FailField(e, field, "node " + e.text + " out of range (the tree has " + std::to_string(n) + " nodes)");
      }
      if (e.integer < 0 && -e.integer > static_cast<std::int64_t>(functionCount)) {
        r.FailField(e, field, "function " + std::to_string(-e.integer) + " out of range (there are " +
                                  std::to_string(functionCount) + " functions: -1..-" + std::to_string(functionCount) +
                                  ")");
      }
      operands[i] = static_cast<int>(e.integer);
    }
    if (count == 1) operandLines[k][1] = operandLines[k][0];
    node.a = operands[0];
    node.b = operands[1];
  }
  CheckAcyclic(path, tree, operandLines);
  // Every node must contribute: an unreachable one is a mistake in the file.
  std::vector<bool> reached(n, false);
  std::vector<std::size_t> pending = {0};
  reached[0] = true;
  while (!pending.empty()) {
    const implicit::CsgNode& node = tree[pending.back()];
    pending.pop_back();
    for (const int operand : {node.a, node.b}) {
      if (operand > 0 && !reached[static_cast<std::size_t>(operand - 1)]) {
        reached[static_cast<std::size_t>(operand - 1)] = true;
        pending.push_back(static_cast<std::size_t>(operand - 1));
      }
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!reached[k]) {
      throw InputError(path, root.items[k].line,
                       "node " + std::to_string(k + 1) + " is not reachable from the root (node 1)");
    }
  }
  // The checks above give lines; the tree module's own validation is the
  // contract RefineGrid relies on, so it has the last word.
  if (const std::string problem = implicit::ValidateCsgTree(tree, functionCount); !problem.empty()) {
    throw InputError(path, 0, problem);
  }
  return tree;
}

}  // namespace invmap::io
