#include "implicit_io/json_values.h"

#include <limits>

#include <nlohmann/json.hpp>

#include "io/json_sax.h"

namespace invmap::io::json {
namespace {

using Json = nlohmann::json;

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

}  // namespace

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

}  // namespace invmap::io::json
