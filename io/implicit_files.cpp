#include "io/implicit_files.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>

#include <nlohmann/json.hpp>

#include "implicit/csg_tree.h"
#include "implicit/exact_predicates.h"
#include "io/file_io.h"
#include "io/gmsh_reader.h"
#include "io/input_error.h"
#include "io/json_sax.h"

namespace invmap::io {
namespace {

using Json = nlohmann::json;

// ---------------------------------------------------------------------------
// JSON with line numbers. The function and tree files are small, so they are
// read into a tree of values that remember their line; nlohmann's SAX events
// carry no position, so the lexer reads through an iterator that publishes
// how far it has read (io/json_sax.h).

/// One JSON value and the line where it starts.
struct Value {
  enum class Type { Null, Boolean, Number, String, Array, Object };
  Type type = Type::Null;
  std::int64_t line = 0;
  bool boolean = false;
  double number = 0;                       ///< Number: its value (integers converted).
  bool integral = false;                   ///< Number: an exact integer in int64 range...
  std::int64_t integer = 0;                ///< ... with this value.
  std::string text;                        ///< String: the value; Number: the token as written.
  std::vector<Value> items;                ///< Array elements, or object field values.
  std::vector<std::string> keys;           ///< Object: keys[i] names items[i].
  std::vector<std::int64_t> keyLines;      ///< Object: line of each key.

  /// The field `key` of an object, null when absent.
  const Value* Find(std::string_view key) const {
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == key) return &items[i];
    }
    return nullptr;
  }
};

/// What a value is, for "expected X, found Y" messages.
std::string Describe(const Value& v) {
  switch (v.type) {
    case Value::Type::Null:
      return "null";
    case Value::Type::Boolean:
      return v.boolean ? "true" : "false";
    case Value::Type::Number:
      return v.text;
    case Value::Type::String: {
      constexpr std::size_t kShown = 40;
      return "the string \"" + v.text.substr(0, kShown) + (v.text.size() > kShown ? "...\"" : "\"");
    }
    case Value::Type::Array:
      return "a list";
    case Value::Type::Object:
      return "an object";
  }
  return "a value";
}

/// Builds the Value tree from nlohmann's SAX events.
class TreeBuilder {
 public:
  /// Nesting deeper than this is refused: the files are shallow, and the
  /// tree's destructor recurses.
  static constexpr std::size_t kMaxDepth = 64;

  TreeBuilder(const std::string& name, const char* begin, std::size_t size, const char** cursor)
      : name_(name), begin_(begin), size_(size), cursor_(cursor) {}

  bool null() {
    Add(Value::Type::Null);
    return true;
  }
  bool boolean(bool value) {
    Add(Value::Type::Boolean)->boolean = value;
    return true;
  }
  bool number_integer(std::int64_t value) {
    Value* v = Add(Value::Type::Number);
    v->number = static_cast<double>(value);
    v->integral = true;
    v->integer = value;
    v->text = std::to_string(value);
    return true;
  }
  bool number_unsigned(std::uint64_t value) {
    Value* v = Add(Value::Type::Number);
    v->number = static_cast<double>(value);
    v->integral = value <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
    v->integer = v->integral ? static_cast<std::int64_t>(value) : 0;
    v->text = std::to_string(value);
    return true;
  }
  bool number_float(double value, const std::string& token) {
    Value* v = Add(Value::Type::Number);
    v->number = value;
    // "2.0" counts as an integer (some writers print every number so).
    v->integral = std::floor(value) == value && std::fabs(value) < 9223372036854775808.0;
    v->integer = v->integral ? static_cast<std::int64_t>(value) : 0;
    v->text = token;
    return true;
  }
  bool string(std::string& value) {
    Add(Value::Type::String)->text = value;
    return true;
  }
  bool binary(Json::binary_t&) { return true; }  // JSON text has no binary values.
  bool start_object(std::size_t) {
    Open(Value::Type::Object);
    return true;
  }
  bool end_object() {
    open_.pop_back();
    return true;
  }
  bool start_array(std::size_t) {
    Open(Value::Type::Array);
    return true;
  }
  bool end_array() {
    open_.pop_back();
    return true;
  }
  bool key(std::string& name) {
    const Value& object = *open_.back();
    for (std::size_t i = 0; i < object.keys.size(); ++i) {
      if (object.keys[i] == name) {
        throw InputError(name_, LineHere(), "duplicate field \"" + name + "\" (first on line " +
                                                std::to_string(object.keyLines[i]) + ")");
      }
    }
    key_ = name;
    keyLine_ = LineHere();
    return true;
  }
  /// Invalid JSON at byte `position`: throws with nlohmann's reason.
  [[noreturn]] bool parse_error(std::size_t position, const std::string& /*lastToken*/,
                                const Json::exception& error) {
    throw InputError(name_, LineAt(position), DescribeJsonParseError(begin_, size_, position, error.what()));
  }

  /// The whole document (after a successful parse).
  Value& root() { return root_; }

 private:
  /// 1-based line of the last character read before byte `offset` (the
  /// lexer reads one character past a number, which this excludes).
  std::int64_t LineAt(std::size_t offset) const {
    const std::size_t end = std::min(offset, size_);
    const std::size_t last = end > 0 ? end - 1 : 0;
    return 1 + std::count(begin_, begin_ + last, '\n');
  }
  /// Line of the lexer's position.
  std::int64_t LineHere() const { return LineAt(static_cast<std::size_t>(*cursor_ - begin_)); }

  /// Appends a value of `type` where the parser is: the root, the next
  /// element of the open array or the value of the pending key. Pointers to
  /// the open containers stay valid: only the innermost one grows.
  Value* Add(Value::Type type) {
    Value* v = nullptr;
    if (open_.empty()) {
      v = &root_;
    } else {
      Value& parent = *open_.back();
      if (parent.type == Value::Type::Object) {
        parent.keys.push_back(key_);
        parent.keyLines.push_back(keyLine_);
      }
      parent.items.emplace_back();
      v = &parent.items.back();
    }
    v->type = type;
    v->line = LineHere();
    return v;
  }
  /// Appends a container and makes it the open one.
  void Open(Value::Type type) {
    if (open_.size() >= kMaxDepth) {
      throw InputError(name_, LineHere(), "lists and objects nested more than " + std::to_string(kMaxDepth) + " deep");
    }
    open_.push_back(Add(type));
  }

  const std::string& name_;
  const char* begin_;
  std::size_t size_;
  const char** cursor_;
  Value root_;
  std::vector<Value*> open_;  ///< Containers being read, outermost first.
  std::string key_;           ///< Pending object key.
  std::int64_t keyLine_ = 0;
};

/// Parses JSON `text` (named `path` in messages) into a Value tree; the top
/// level must be a non-empty list of `what`s ("function object").
Value ParseJsonList(const std::string& text, const std::string& path, const char* what) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(path, 1 + std::count(text.begin(), text.end(), '\n'),
                     std::string("empty file, expected a JSON list of ") + what + "s");
  }
  const char* cursor = text.data();
  TreeBuilder builder(path, text.data(), text.size(), &cursor);
  Json::sax_parse(TrackingIterator(&cursor), TrackingIterator(text.data() + text.size()), &builder);
  Value root = std::move(builder.root());
  if (root.type != Value::Type::Array) {
    throw InputError(path, root.line, "expected a JSON list of " + std::string(what) + "s, found " + Describe(root));
  }
  if (root.items.empty()) throw InputError(path, root.line, std::string("empty list, expected at least one ") + what);
  return root;
}

/// Checks of the fields of one object, with messages "where.field: ...".
class ObjectReader {
 public:
  /// `dimension`: how many numbers a point or vector has (function lists).
  ObjectReader(const std::string& file, const Value& object, std::string where, int dimension = 3)
      : file_(file), object_(object), where_(std::move(where)), dimension_(dimension) {}

  /// Throws InputError at `line`.
  [[noreturn]] void Fail(std::int64_t line, const std::string& message) const {
    throw InputError(file_, line, message);
  }
  /// Throws at the line of `v`, prefixing "where.field: ".
  [[noreturn]] void FailField(const Value& v, const std::string& field, const std::string& message) const {
    Fail(v.line, where_ + "." + field + ": " + message);
  }

  /// Rejects keys not in `allowed`; `what` names the object kind.
  void CheckKeys(const std::vector<const char*>& allowed, const std::string& what) const {
    for (std::size_t i = 0; i < object_.keys.size(); ++i) {
      const std::string& key = object_.keys[i];
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        Fail(object_.keyLines[i], where_ + ": unknown field \"" + key + "\" for " + what + " (fields: " + list + ")");
      }
    }
  }

  /// The field `key`; throws when it is missing.
  const Value& Required(const char* key, const std::string& what) const {
    const Value* v = object_.Find(key);
    if (v == nullptr) Fail(object_.line, where_ + ": missing field \"" + key + "\" (" + what + ")");
    return *v;
  }
  /// The field `key`, null when absent.
  const Value* Optional(const char* key) const { return object_.Find(key); }

  /// A finite number.
  double Number(const Value& v, const char* key) const {
    if (v.type != Value::Type::Number) FailField(v, key, "expected a number, found " + Describe(v));
    if (!std::isfinite(v.number)) FailField(v, key, v.text + " is not a finite number");
    return v.number;
  }
  /// The required field `key`, a finite number.
  double Number(const char* key) const { return Number(Required(key, "a number"), key); }
  /// A finite number > 0.
  double Positive(const char* key) const {
    const Value& v = Required(key, "a positive number");
    const double x = Number(v, key);
    if (!(x > 0)) FailField(v, key, v.text + ", expected a positive number");
    return x;
  }
  /// [x, y, z] in 3D or [x, y] (z = 0) in 2D, finite numbers.
  implicit::Vec3 Point(const Value& v, const char* key) const {
    const std::string expected = std::to_string(dimension_) + " numbers";
    if (v.type != Value::Type::Array) FailField(v, key, "expected a list of " + expected + ", found " + Describe(v));
    if (static_cast<int>(v.items.size()) != dimension_) {
      FailField(v, key,
                std::to_string(v.items.size()) + " numbers, expected " + expected + " (the grid is " +
                    std::to_string(dimension_) + "D)");
    }
    implicit::Vec3 p = {0, 0, 0};
    for (std::size_t i = 0; i < v.items.size(); ++i) {
      const Value& c = v.items[i];
      const std::string field = std::string(key) + "[" + std::to_string(i) + "]";
      if (c.type != Value::Type::Number) FailField(c, field, "expected a number, found " + Describe(c));
      if (!std::isfinite(c.number)) FailField(c, field, c.text + " is not a finite number");
      p[i] = c.number;
    }
    return p;
  }
  /// The required field `key`, a point.
  implicit::Vec3 Point(const char* key) const {
    return Point(Required(key, "a list of " + std::to_string(dimension_) + " numbers"), key);
  }
  /// A point that is a direction: non-zero, with a finite length.
  implicit::Vec3 Direction(const char* key) const {
    const Value& v = Required(key, "a non-zero vector of " + std::to_string(dimension_) + " numbers");
    const implicit::Vec3 d = Point(v, key);
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (length == 0) FailField(v, key, "zero vector, expected a direction");
    if (!std::isfinite(length)) FailField(v, key, "vector too long (its length overflows)");
    return d;
  }
  /// The optional field `key`, true or false; `fallback` when absent.
  bool Boolean(const char* key, bool fallback) const {
    const Value* v = Optional(key);
    if (v == nullptr) return fallback;
    if (v->type != Value::Type::Boolean) FailField(*v, key, "expected true or false, found " + Describe(*v));
    return v->boolean;
  }


 private:
  const std::string& file_;  ///< File name for messages.
  const Value& object_;      ///< The object read.
  std::string where_;        ///< Its path in messages: "functions[2]", "node 3".
  int dimension_;            ///< Numbers per point or vector.
};

/// The function types of the list file, with their fields ("type" and
/// "name" are allowed in every one).
struct FunctionType {
  const char* name;
  std::vector<const char*> fields;
};

/// Every function type, in the order messages list them.
const std::vector<FunctionType>& FunctionTypes() {
  static const std::vector<FunctionType> kTypes = {
      {"sphere", {"type", "name", "center", "radius", "squared"}},
      {"cylinder", {"type", "name", "axis_point", "axis_vector", "radius", "squared"}},
      {"plane", {"type", "name", "point", "normal"}},
      {"torus", {"type", "name", "center", "axis_vector", "major_radius", "minor_radius"}},
      {"cone", {"type", "name", "apex", "axis_vector", "apex_angle"}},
      {"quintic", {"type", "name", "center"}},
      {"gyroid", {"type", "name", "period"}},
  };
  return kTypes;
}

/// "sphere, cylinder, ...": the known types for messages.
std::string FunctionTypeList() {
  std::string list;
  for (const FunctionType& t : FunctionTypes()) list += (list.empty() ? "" : ", ") + std::string(t.name);
  return list;
}

/// Function `index` of the list, from its JSON object.
implicit::Function ReadFunction(const std::string& path, const Value& object, std::size_t index, int dimension) {
  const std::string where = "functions[" + std::to_string(index) + "]";
  if (object.type != Value::Type::Object) {
    throw InputError(path, object.line, where + ": expected a function object, found " + Describe(object));
  }
  const ObjectReader r(path, object, where, dimension);
  const Value& typeValue = r.Required("type", "one of " + FunctionTypeList());
  if (typeValue.type != Value::Type::String) {
    r.FailField(typeValue, "type", "expected a string (" + FunctionTypeList() + "), found " + Describe(typeValue));
  }
  const std::string& type = typeValue.text;
  const auto found = std::find_if(FunctionTypes().begin(), FunctionTypes().end(),
                                  [&](const FunctionType& t) { return type == t.name; });
  if (found == FunctionTypes().end()) {
    r.FailField(typeValue, "type", "unknown function type \"" + type + "\" (known: " + FunctionTypeList() + ")");
  }
  r.CheckKeys(found->fields, "a " + type);

  implicit::Function f;
  if (type == "sphere") {
    const implicit::Vec3 center = r.Point("center");
    f = implicit::Function::Sphere(center, r.Positive("radius"), r.Boolean("squared", false));
  } else if (type == "cylinder") {
    const implicit::Vec3 point = r.Point("axis_point");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    f = implicit::Function::Cylinder(point, axis, r.Positive("radius"), r.Boolean("squared", false));
  } else if (type == "plane") {
    const implicit::Vec3 point = r.Point("point");
    f = implicit::Function::Plane(point, r.Direction("normal"));
  } else if (type == "torus") {
    const implicit::Vec3 center = r.Point("center");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    const double major = r.Positive("major_radius");
    f = implicit::Function::Torus(center, axis, major, r.Positive("minor_radius"));
  } else if (type == "cone") {
    const implicit::Vec3 apex = r.Point("apex");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    const Value& angleValue = r.Required("apex_angle", "the half angle in radians");
    const double angle = r.Number(angleValue, "apex_angle");
    constexpr double kHalfPi = 1.57079632679489661923;
    if (!(angle > 0 && angle < kHalfPi)) {
      r.FailField(angleValue, "apex_angle", angleValue.text + ", expected a half angle in radians in (0, pi/2)");
    }
    f = implicit::Function::Cone(apex, axis, angle);
  } else if (type == "quintic") {
    const Value* center = r.Optional("center");
    f = implicit::Function::Quintic(center != nullptr ? r.Point(*center, "center") : implicit::Vec3{0, 0, 0});
  } else {  // gyroid
    f = implicit::Function::Gyroid(r.Positive("period"));
  }
  if (const Value* name = r.Optional("name")) {
    if (name->type != Value::Type::String) r.FailField(*name, "name", "expected a string, found " + Describe(*name));
    f.name = name->text;
  }
  return f;
}

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

// ---------------------------------------------------------------------------
// Writers.

/// Writes the shortest text that reads back as `value`; at most 24 characters.
inline char* PutDouble(char* p, double value) { return std::to_chars(p, p + 32, value).ptr; }
inline char* PutInteger(char* p, std::int64_t value) { return std::to_chars(p, p + 24, value).ptr; }
inline char* PutText(char* p, std::string_view text) {
  std::memcpy(p, text.data(), text.size());
  return p + text.size();
}

/// Room for one line of numbers: a few of them and separators.
constexpr std::size_t kLineRoom = 256;

/// Throws std::invalid_argument when the grid's arrays or the names disagree in size.
void CheckGrid(const implicit::Grid& grid, const std::vector<std::string>& functionNames) {
  const implicit::SimplexMesh& mesh = grid.mesh;
  if (mesh.dimension != 2 && mesh.dimension != 3) {
    throw std::invalid_argument("grid dimension " + std::to_string(mesh.dimension) + ", expected 2 or 3");
  }
  if (mesh.vertices.size() % 3 != 0) throw std::invalid_argument("grid vertices: length not a multiple of 3");
  if (mesh.cells.size() % static_cast<std::size_t>(mesh.dimension + 1) != 0) {
    throw std::invalid_argument("grid cells: length not a multiple of dimension + 1");
  }
  if (grid.functionCount < 0 ||
      grid.values.size() != mesh.numVertices() * static_cast<std::size_t>(grid.functionCount)) {
    throw std::invalid_argument("grid values: " + std::to_string(grid.values.size()) + ", expected " +
                                std::to_string(grid.functionCount) + " per vertex");
  }
  if (!grid.active.empty() && grid.active.size() != mesh.numCells()) {
    throw std::invalid_argument("grid active: " + std::to_string(grid.active.size()) + " flags for " +
                                std::to_string(mesh.numCells()) + " cells");
  }
  if (!functionNames.empty() && functionNames.size() != static_cast<std::size_t>(grid.functionCount)) {
    throw std::invalid_argument(std::to_string(functionNames.size()) + " function names for " +
                                std::to_string(grid.functionCount) + " functions");
  }
}

/// "f<i> <name>" (or "f<i>"), the label of function i's data in the grid files.
std::string FunctionLabel(const std::vector<std::string>& functionNames, int i) {
  std::string label = "f" + std::to_string(i);
  if (!functionNames.empty() && !functionNames[static_cast<std::size_t>(i)].empty()) {
    label += " " + functionNames[static_cast<std::size_t>(i)];
  }
  return label;
}

/// `label` fit for a gmsh string tag: no quotes or line breaks.
std::string GmshString(const std::string& label) {
  std::string s = label;
  for (char& c : s) {
    if (c == '"') c = '\'';
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  }
  return "\"" + s + "\"";
}

/// `text` escaped for an XML attribute value.
std::string XmlAttribute(const std::string& text) {
  std::string s;
  for (const char c : text) {
    switch (c) {
      case '&':
        s += "&amp;";
        break;
      case '<':
        s += "&lt;";
        break;
      case '>':
        s += "&gt;";
        break;
      case '"':
        s += "&quot;";
        break;
      default:
        s += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return s;
}

/// Writes a gmsh $NodeData or $ElementData section: `count` values,
/// value(i) for tag i + 1.
template <class ValueAt>
void WriteGmshData(AtomicOutput& out, const char* section, const std::string& label, std::size_t count,
                   ValueAt valueAt) {
  out.Write(std::string("$") + section + "\n1\n" + GmshString(label) + "\n1\n0\n3\n0\n1\n" + std::to_string(count) +
            "\n");
  for (std::size_t i = 0; i < count; ++i) {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutInteger(start, static_cast<std::int64_t>(i + 1));
    *p++ = ' ';
    p = PutDouble(p, valueAt(i));
    *p++ = '\n';
    out.Advance(static_cast<std::size_t>(p - start));
  }
  out.Write(std::string("$End") + section + "\n");
}

/// Writes one appended VTK data block: its byte count (UInt64), then
/// `count` values of type T, value(i) each, little endian.
template <class T, class ValueAt>
void WriteVtkBlock(AtomicOutput& out, std::size_t count, ValueAt valueAt) {
  char header[8];
  StoreLittleEndian<std::uint64_t>(header, static_cast<std::uint64_t>(count) * sizeof(T));
  out.Write(header, sizeof header);
  constexpr std::size_t kChunk = std::size_t{1} << 14;
  for (std::size_t start = 0; start < count; start += kChunk) {
    const std::size_t m = std::min(kChunk, count - start);
    char* p = out.Reserve(m * sizeof(T));
    for (std::size_t i = 0; i < m; ++i) StoreLittleEndian<T>(p + i * sizeof(T), valueAt(start + i));
    out.Advance(m * sizeof(T));
  }
}

/// Checks a primitive list of the zero sets: a multiple of `arity` indices
/// below the vertex count, one label each.
void CheckPrimitives(const char* what, const std::vector<std::uint32_t>& indices,
                     const std::vector<std::array<int, 4>>& labels, std::size_t arity, std::size_t numVertices) {
  if (indices.size() % arity != 0 || indices.size() / arity != labels.size()) {
    throw std::invalid_argument(std::string("zero sets ") + what + ": " + std::to_string(indices.size()) +
                                " indices and " + std::to_string(labels.size()) + " labels");
  }
  for (const std::uint32_t v : indices) {
    if (v >= numVertices) {
      throw std::invalid_argument(std::string("zero sets ") + what + ": vertex index " + std::to_string(v) +
                                  " out of range (" + std::to_string(numVertices) + " vertices)");
    }
  }
}

/// Throws std::invalid_argument for inconsistent zero sets (see CheckPrimitives).
void CheckZeroSets(const implicit::ZeroSets& z) {
  if (z.vertices.size() % 3 != 0) throw std::invalid_argument("zero sets vertices: length not a multiple of 3");
  const std::size_t n = z.vertices.size() / 3;
  CheckPrimitives("triangles", z.triangles, z.triangleLabels, 3, n);
  CheckPrimitives("segments", z.segments, z.segmentLabels, 2, n);
  CheckPrimitives("points", z.points, z.pointLabels, 1, n);
}

/// OBJ group name of a label: "f0", "f0_f2", ...
std::string GroupName(const std::array<int, 4>& label) {
  std::string name;
  for (const int i : label) {
    if (i < 0) continue;
    name += (name.empty() ? "f" : "_f") + std::to_string(i);
  }
  return name.empty() ? "unlabeled" : name;
}

/// Indices 0..labels.size()-1 ordered by label (stable).
std::vector<std::size_t> OrderByLabel(const std::vector<std::array<int, 4>>& labels) {
  std::vector<std::size_t> order(labels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return labels[a] < labels[b]; });
  return order;
}

}  // namespace

// ---------------------------------------------------------------------------

std::vector<implicit::Function> ReadFunctionList(const std::string& path, int dimension) {
  return ParseFunctionList(ReadWholeFile(path), path, dimension);
}

std::vector<implicit::CsgNode> ReadCsgTree(const std::string& path, int functionCount) {
  return ParseCsgTree(ReadWholeFile(path), path, functionCount);
}

std::vector<implicit::Function> ParseFunctionList(const std::string& text, const std::string& path, int dimension) {
  const Value root = ParseJsonList(text, path, "function object");
  std::vector<implicit::Function> functions;
  functions.reserve(root.items.size());
  for (std::size_t i = 0; i < root.items.size(); ++i) functions.push_back(ReadFunction(path, root.items[i], i, dimension));
  return functions;
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

implicit::SimplexMesh ReadSimplexMeshMsh(const std::string& path) {
  const Geometry geometry = ReadGmsh(path);
  const int dim = geometry.dimension;
  const CellType wanted = dim == 3 ? CellType::Tet : CellType::Tri;
  const char* const wantedName = dim == 3 ? "linear tetrahedra" : "linear triangles (all z = 0)";
  static const char* const kCellNames[] = {"line", "triangle", "quadrangle", "tetrahedron", "hexahedron", "prism"};
  static const int kParamDim[] = {1, 2, 2, 3, 3, 3};

  implicit::SimplexMesh mesh;
  mesh.dimension = dim;
  const std::size_t per = static_cast<std::size_t>(dim + 1);

  // Exact coordinates -> vertex; +0.0 folds -0.0 into 0.0, which compare
  // equal but hash apart.
  struct KeyHash {
    std::size_t operator()(const implicit::Vec3& p) const {
      std::uint64_t h = 0x9E3779B97F4A7C15ull;
      for (const double x : p) {
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        h ^= bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<implicit::Vec3, std::uint32_t, KeyHash> vertexOf;

  std::size_t element = 0;  // Index over every element ReadGmsh returned, for messages.
  for (const Patch& patch : geometry.patches) {
    const std::size_t cells = patch.cellTypes.size();
    for (std::size_t c = 0; c < cells; ++c, ++element) {
      const CellType type = patch.cellTypes[c];
      const int degree = patch.cellDegrees[3 * c];
      const int typeIndex = static_cast<int>(type);
      if (type != wanted) {
        if (kParamDim[typeIndex] < dim) continue;  // A boundary tag.
        throw InputError(path, 0,
                         "element " + std::to_string(element + 1) + " (in file order) is a " + (degree > 1 ? "curved " : "") +
                             kCellNames[typeIndex] + ": an initial grid has " + wantedName + " only");
      }
      if (degree != 1 || patch.cellOffsets[c + 1] - patch.cellOffsets[c] != static_cast<std::int64_t>(per)) {
        throw InputError(path, 0,
                         "element " + std::to_string(element + 1) + " (in file order) is a " + kCellNames[typeIndex] + " of order " +
                             std::to_string(degree) + ": an initial grid has " + wantedName + " only");
      }
      for (std::size_t j = 0; j < per; ++j) {
        const double* q = patch.points.data() + (static_cast<std::size_t>(patch.cellOffsets[c]) + j) * dim;
        const implicit::Vec3 p = {q[0] + 0.0, q[1] + 0.0, dim == 3 ? q[2] + 0.0 : 0.0};
        const auto [it, inserted] = vertexOf.emplace(p, static_cast<std::uint32_t>(vertexOf.size()));
        if (inserted) {
          if (vertexOf.size() > std::numeric_limits<std::uint32_t>::max()) {
            throw InputError(path, 0, "more than 2^32 - 1 vertices");
          }
          mesh.vertices.insert(mesh.vertices.end(), p.begin(), p.end());
        }
        mesh.cells.push_back(it->second);
      }
    }
  }
  if (mesh.cells.empty()) throw InputError(path, 0, std::string("no cells: an initial grid has ") + wantedName);

  // Orientation by exact predicates: a nearly flat cell still gets its true sign.
  const double* v = mesh.vertices.data();
  for (std::size_t c = 0; c < mesh.numCells(); ++c) {
    std::uint32_t* cell = mesh.cells.data() + c * per;
    int sign = 0;
    if (dim == 3) {
      // Sign of det[v1 - v0, v2 - v0, v3 - v0].
      sign = implicit::Orient3d(v + 3 * cell[1], v + 3 * cell[2], v + 3 * cell[3], v + 3 * cell[0]);
    } else {
      const double a[2] = {v[3 * cell[0]], v[3 * cell[0] + 1]};
      const double b[2] = {v[3 * cell[1]], v[3 * cell[1] + 1]};
      const double d[2] = {v[3 * cell[2]], v[3 * cell[2] + 1]};
      sign = implicit::Orient2d(a, b, d);
    }
    if (sign == 0) {
      throw InputError(path, 0, "cell " + std::to_string(c) + " has zero " + (dim == 3 ? "volume" : "area") +
                                    " (its vertices are " + (dim == 3 ? "coplanar" : "collinear") + ")");
    }
    if (sign < 0) std::swap(cell[1], cell[2]);
  }
  return mesh;
}

void WriteGridMsh(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path) {
  CheckGrid(grid, functionNames);
  const implicit::SimplexMesh& mesh = grid.mesh;
  const int dim = mesh.dimension;
  const std::size_t per = static_cast<std::size_t>(dim + 1);
  const std::size_t numVertices = mesh.numVertices(), numCells = mesh.numCells();
  const double* xyz = mesh.vertices.data();

  implicit::Vec3 lo = {0, 0, 0}, hi = {0, 0, 0};
  for (std::size_t v = 0; v < numVertices; ++v) {
    for (int a = 0; a < 3; ++a) {
      const double x = xyz[3 * v + a];
      lo[a] = v == 0 ? x : std::min(lo[a], x);
      hi[a] = v == 0 ? x : std::max(hi[a], x);
    }
  }

  AtomicOutput out(path);
  out.Write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n");
  out.Write(dim == 3 ? "0 0 0 1\n" : "0 0 1 0\n");
  {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutText(start, "1");
    for (const double x : {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]}) {
      *p++ = ' ';
      p = PutDouble(p, x);
    }
    p = PutText(p, " 0 0\n$EndEntities\n");
    out.Advance(static_cast<std::size_t>(p - start));
  }

  const std::string nv = std::to_string(numVertices), nc = std::to_string(numCells), d = std::to_string(dim);
  if (numVertices == 0) {
    out.Write("$Nodes\n0 0 0 0\n$EndNodes\n");
  } else {
    out.Write("$Nodes\n1 " + nv + " 1 " + nv + "\n" + d + " 1 0 " + nv + "\n");
    for (std::size_t v = 0; v < numVertices; ++v) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutInteger(start, static_cast<std::int64_t>(v + 1));
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    for (std::size_t v = 0; v < numVertices; ++v) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutDouble(start, xyz[3 * v]);
      *p++ = ' ';
      p = PutDouble(p, xyz[3 * v + 1]);
      *p++ = ' ';
      p = PutDouble(p, xyz[3 * v + 2]);
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    out.Write("$EndNodes\n");
  }

  if (numCells == 0) {
    out.Write("$Elements\n0 0 0 0\n$EndElements\n");
  } else {
    out.Write("$Elements\n1 " + nc + " 1 " + nc + "\n" + d + " 1 " + (dim == 3 ? "4 " : "2 ") + nc + "\n");
    const std::uint32_t* cells = mesh.cells.data();
    for (std::size_t c = 0; c < numCells; ++c) {
      char* const start = out.Reserve(kLineRoom);
      char* p = PutInteger(start, static_cast<std::int64_t>(c + 1));
      for (std::size_t j = 0; j < per; ++j) {
        *p++ = ' ';
        p = PutInteger(p, static_cast<std::int64_t>(cells[c * per + j]) + 1);
      }
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
    out.Write("$EndElements\n");
  }

  const std::size_t k = static_cast<std::size_t>(grid.functionCount);
  for (int i = 0; i < grid.functionCount; ++i) {
    const double* values = grid.values.data() + i;
    WriteGmshData(out, "NodeData", FunctionLabel(functionNames, i), numVertices,
                  [&](std::size_t v) { return values[v * k]; });
  }
  if (!grid.active.empty()) {
    WriteGmshData(out, "ElementData", "active", numCells, [&](std::size_t c) { return grid.active[c] ? 1.0 : 0.0; });
  }
  out.Commit();
}

void WriteGridVtu(const implicit::Grid& grid, const std::vector<std::string>& functionNames, const std::string& path) {
  CheckGrid(grid, functionNames);
  const implicit::SimplexMesh& mesh = grid.mesh;
  const std::size_t per = static_cast<std::size_t>(mesh.dimension + 1);
  const std::size_t numVertices = mesh.numVertices(), numCells = mesh.numCells();
  const std::size_t k = static_cast<std::size_t>(grid.functionCount);
  const bool hasActive = !grid.active.empty();

  // Offsets of the appended blocks, in writing order: functions, active,
  // points, connectivity, offsets, types; each is an 8-byte count then data.
  std::uint64_t offset = 0;
  const auto next = [&](std::uint64_t bytes) {
    const std::uint64_t at = offset;
    offset += 8 + bytes;
    return std::to_string(at);
  };
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(numVertices) + "\" NumberOfCells=\"" + std::to_string(numCells) + "\">\n";
  xml += "      <PointData>\n";
  for (std::size_t i = 0; i < k; ++i) {
    xml += "        <DataArray type=\"Float64\" Name=\"" +
           XmlAttribute(FunctionLabel(functionNames, static_cast<int>(i))) +
           "\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" + next(8 * numVertices) + "\"/>\n";
  }
  xml += "      </PointData>\n      <CellData>\n";
  if (hasActive) {
    xml += "        <DataArray type=\"UInt8\" Name=\"active\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" +
           next(numCells) + "\"/>\n";
  }
  xml += "      </CellData>\n      <Points>\n";
  xml += "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
         next(24 * numVertices) + "\"/>\n";
  xml += "      </Points>\n      <Cells>\n";
  xml += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"" +
         next(8 * per * numCells) + "\"/>\n";
  xml += "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" + next(8 * numCells) +
         "\"/>\n";
  xml += "        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" + next(numCells) + "\"/>\n";
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  AtomicOutput out(path);
  out.Write(xml);
  for (std::size_t i = 0; i < k; ++i) {
    const double* values = grid.values.data() + i;
    WriteVtkBlock<double>(out, numVertices, [&](std::size_t v) { return values[v * k]; });
  }
  if (hasActive) {
    WriteVtkBlock<std::uint8_t>(out, numCells,
                                [&](std::size_t c) { return static_cast<std::uint8_t>(grid.active[c] ? 1 : 0); });
  }
  WriteVtkBlock<double>(out, 3 * numVertices, [&](std::size_t i) { return mesh.vertices[i]; });
  WriteVtkBlock<std::int64_t>(out, per * numCells, [&](std::size_t i) { return std::int64_t{mesh.cells[i]}; });
  WriteVtkBlock<std::int64_t>(out, numCells,
                              [&](std::size_t c) { return static_cast<std::int64_t>((c + 1) * per); });
  const std::uint8_t cellType = mesh.dimension == 3 ? 10 : 5;  // VTK_TETRA, VTK_TRIANGLE.
  WriteVtkBlock<std::uint8_t>(out, numCells, [&](std::size_t) { return cellType; });
  out.Write("\n  </AppendedData>\n</VTKFile>\n");
  out.Commit();
}

void WriteZeroSetsObj(const implicit::ZeroSets& zeroSets, const std::string& path) {
  CheckZeroSets(zeroSets);
  const implicit::ZeroSets& z = zeroSets;
  const std::size_t numVertices = z.vertices.size() / 3;
  const std::vector<std::size_t> triangles = OrderByLabel(z.triangleLabels);
  const std::vector<std::size_t> segments = OrderByLabel(z.segmentLabels);
  const std::vector<std::size_t> points = OrderByLabel(z.pointLabels);

  AtomicOutput out(path);
  out.Write("# invmap zero sets: " + std::to_string(numVertices) + " vertices, " + std::to_string(triangles.size()) +
            " triangles, " + std::to_string(segments.size()) + " segments, " + std::to_string(points.size()) +
            " points\n");
  for (std::size_t v = 0; v < numVertices; ++v) {
    char* const start = out.Reserve(kLineRoom);
    char* p = PutText(start, "v ");
    p = PutDouble(p, z.vertices[3 * v]);
    *p++ = ' ';
    p = PutDouble(p, z.vertices[3 * v + 1]);
    *p++ = ' ';
    p = PutDouble(p, z.vertices[3 * v + 2]);
    *p++ = '\n';
    out.Advance(static_cast<std::size_t>(p - start));
  }

  // Walk the three label-sorted lists together, one group per label.
  std::size_t t = 0, s = 0, q = 0;
  const auto writeRun = [&](std::size_t* cursor, const std::vector<std::size_t>& order,
                            const std::vector<std::array<int, 4>>& labels, const std::array<int, 4>& label,
                            const std::vector<std::uint32_t>& indices, std::size_t arity, const char* prefix) {
    for (; *cursor < order.size() && labels[order[*cursor]] == label; ++*cursor) {
      const std::size_t e = order[*cursor];
      char* const start = out.Reserve(kLineRoom);
      char* p = PutText(start, prefix);
      for (std::size_t j = 0; j < arity; ++j) {
        *p++ = ' ';
        p = PutInteger(p, static_cast<std::int64_t>(indices[e * arity + j]) + 1);
      }
      *p++ = '\n';
      out.Advance(static_cast<std::size_t>(p - start));
    }
  };
  while (t < triangles.size() || s < segments.size() || q < points.size()) {
    std::array<int, 4> label = {std::numeric_limits<int>::max(), 0, 0, 0};
    bool any = false;
    const auto consider = [&](std::size_t cursor, const std::vector<std::size_t>& order,
                              const std::vector<std::array<int, 4>>& labels) {
      if (cursor < order.size() && (!any || labels[order[cursor]] < label)) {
        label = labels[order[cursor]];
        any = true;
      }
    };
    consider(t, triangles, z.triangleLabels);
    consider(s, segments, z.segmentLabels);
    consider(q, points, z.pointLabels);
    out.Write("g " + GroupName(label) + "\n");
    writeRun(&t, triangles, z.triangleLabels, label, z.triangles, 3, "f");
    writeRun(&s, segments, z.segmentLabels, label, z.segments, 2, "l");
    writeRun(&q, points, z.pointLabels, label, z.points, 1, "p");
  }
  out.Commit();
}

void WriteZeroSetsPly(const implicit::ZeroSets& zeroSets, const std::string& path) {
  CheckZeroSets(zeroSets);
  const implicit::ZeroSets& z = zeroSets;
  const std::size_t numTriangles = z.triangles.size() / 3;
  // Only the vertices the triangles use, in order of first use.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> old2New(z.vertices.size() / 3, kUnused);
  std::vector<std::uint32_t> new2Old;
  for (const std::uint32_t v : z.triangles) {
    if (old2New[v] == kUnused) {
      old2New[v] = static_cast<std::uint32_t>(new2Old.size());
      new2Old.push_back(v);
    }
  }

  AtomicOutput out(path);
  out.Write("ply\nformat binary_little_endian 1.0\ncomment invmap zero-set triangles\nelement vertex " +
            std::to_string(new2Old.size()) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(numTriangles) +
            "\nproperty list uchar uint vertex_indices\nproperty int label0\nproperty int label1\n"
            "property int label2\nproperty int label3\nend_header\n");
  constexpr std::size_t kVertexBytes = 24, kFaceBytes = 1 + 12 + 16;
  for (const std::uint32_t v : new2Old) {
    char* p = out.Reserve(kVertexBytes);
    for (int a = 0; a < 3; ++a) StoreLittleEndian<double>(p + 8 * a, z.vertices[3 * static_cast<std::size_t>(v) + a]);
    out.Advance(kVertexBytes);
  }
  for (std::size_t f = 0; f < numTriangles; ++f) {
    char* p = out.Reserve(kFaceBytes);
    p[0] = 3;
    for (int j = 0; j < 3; ++j) StoreLittleEndian<std::uint32_t>(p + 1 + 4 * j, old2New[z.triangles[3 * f + j]]);
    for (int j = 0; j < 4; ++j) StoreLittleEndian<std::int32_t>(p + 13 + 4 * j, z.triangleLabels[f][j]);
    out.Advance(kFaceBytes);
  }
  out.Commit();
}

void WriteGridStats(const implicit::GridStats& stats, const std::string& path) {
  nlohmann::ordered_json json;
  json["cells"] = stats.cells;
  json["active_cells"] = stats.activeCells;
  json["vertices"] = stats.vertices;
  json["min_radius_ratio"] = stats.minRadiusRatio;
  json["min_radius_ratio_active"] = stats.minRadiusRatioActive;
  json["seconds"] = stats.seconds;
  AtomicOutput out(path);
  out.Write(json.dump(2) + "\n");
  out.Commit();
}

}  // namespace invmap::io
