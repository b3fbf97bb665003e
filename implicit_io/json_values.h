// Small JSON files read with the line of every value, for messages that
// point into the file: the function lists and CSG trees of `invmap grid`.
// They are small, so they are read into a tree of values that remember their
// line; nlohmann's SAX events carry no position, so the lexer reads through
// an iterator that publishes how far it has read (io/json_sax.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "invmap/implicit.h"
#include "io/input_error.h"

namespace invmap::io::json {

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
std::string Describe(const Value& v);

/// The most bytes a function list or CSG tree file is read up to: they hold
/// kilobytes, so a larger file is none (and an endless one, /dev/zero under
/// a .json name, fails at once instead of filling the memory).
inline constexpr std::uint64_t kMaxImplicitFileBytes = std::uint64_t{64} << 20;

/// Parses JSON `text` (named `path` in messages) into a Value tree; the top
/// level must be a non-empty list of `what`s ("function object"). Throws
/// InputError at the line of invalid JSON, of an empty file or list, of a
/// duplicate key and of lists and objects nested too deep.
Value ParseJsonList(const std::string& text, const std::string& path, const char* what);

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

}  // namespace invmap::io::json
