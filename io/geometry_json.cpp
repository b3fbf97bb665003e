#include "io/geometry_json.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <istream>
#include <iterator>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/file_io.h"
#include "io/geometry_source.h"
#include "io/input_error.h"
#include "io/json_sax.h"

namespace invmap::io {
namespace {

using Json = nlohmann::json;

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

/// The fields a patch object may have (the union over all kinds).
enum class Field : int {
  Kind,
  Cell,
  Degrees,
  Knots,
  Counts,
  ControlPoints,
  Weights,
  Vertices,
  Cells,
  ChartControlPoints,
  None
};
constexpr int kNumFields = static_cast<int>(Field::None);
constexpr const char* kFieldNames[kNumFields] = {"kind",           "cell",    "degrees",  "knots", "counts",
                                                 "control_points", "weights", "vertices", "cells",
                                                 "chart_control_points"};

/// Each field as the engine's validation names it (GeometryError::field).
constexpr GeometryField kGeometryFields[kNumFields] = {
    GeometryField::Kind,          GeometryField::Cell,    GeometryField::Degrees,  GeometryField::Knots,
    GeometryField::Counts,        GeometryField::ControlPoints, GeometryField::Weights, GeometryField::Vertices,
    GeometryField::Cells,         GeometryField::ChartControlPoints};

/// The top-level fields; Other is any unknown one, which is skipped.
enum class RootKey { Format, Version, Dimension, Patches, Other };

/// One JSON scalar as the SAX events deliver it, so that every event funnels
/// into one dispatch.
struct Scalar {
  enum class Type { Null, Boolean, Integer, Unsigned, Float, String };
  Type type = Type::Null;
  bool boolean = false;               ///< Boolean value.
  std::int64_t integer = 0;           ///< Integer value (negative ones come as Integer).
  std::uint64_t unsignedInteger = 0;  ///< Unsigned value (non-negative integers).
  double number = 0.0;                ///< Float value.
  std::string_view text;              ///< String value, or the raw token of a float.

  /// True for the three number types.
  bool IsNumber() const { return type == Type::Integer || type == Type::Unsigned || type == Type::Float; }
  /// The value as a double (IsNumber() only).
  double AsDouble() const {
    switch (type) {
      case Type::Integer:
        return static_cast<double>(integer);
      case Type::Unsigned:
        return static_cast<double>(unsignedInteger);
      default:
        return number;
    }
  }
  /// True and `*value` when the number is an integer in int64 range; an
  /// integral float ("2.0", as some writers print every number) counts.
  bool AsInteger(std::int64_t* value) const {
    switch (type) {
      case Type::Integer:
        *value = integer;
        return true;
      case Type::Unsigned:
        if (unsignedInteger > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return false;
        *value = static_cast<std::int64_t>(unsignedInteger);
        return true;
      case Type::Float:
        // 2^63 is exactly representable; anything at or above it is out of range.
        if (!(std::floor(number) == number) || !(std::fabs(number) < 9223372036854775808.0)) return false;
        *value = static_cast<std::int64_t>(number);
        return true;
      default:
        return false;
    }
  }
};

/// "null", "true", "the string \"abc\"", "1.5": what was found instead of
/// what was expected.
std::string Describe(const Scalar& v) {
  switch (v.type) {
    case Scalar::Type::Null:
      return "null";
    case Scalar::Type::Boolean:
      return v.boolean ? "true" : "false";
    case Scalar::Type::Integer:
      return std::to_string(v.integer);
    case Scalar::Type::Unsigned:
      return std::to_string(v.unsignedInteger);
    case Scalar::Type::Float:
      return std::string(v.text);
    case Scalar::Type::String: {
      constexpr std::size_t kShown = 40;
      const std::string shown(v.text.substr(0, kShown));
      return "the string \"" + shown + (v.text.size() > kShown ? "...\"" : "\"");
    }
  }
  return "a value";
}

/// Row lengths of an array of arrays (points or cells), summarized while
/// streaming. JSON objects are unordered ("dimension" may follow "patches",
/// "cell" may follow "cells"), so the lengths are checked once the file is
/// read: row 0 against the expectation, then the first row that differs
/// from row 0. Lines are those of the rows, for messages.
struct RowShape {
  std::size_t rows = 0;
  std::size_t firstLength = 0;
  std::size_t firstLine = 0;
  std::size_t oddRow = kNone;  ///< First row whose length differs from row 0's.
  std::size_t oddLength = 0;
  std::size_t oddLine = 0;
  std::size_t openLength = 0;  ///< Length so far of the row being read.
  std::size_t openLine = 0;

  /// A row starts at `line`.
  void Open(std::size_t line) {
    openLength = 0;
    openLine = line;
  }
  /// The open row ends.
  void Close() {
    if (rows == 0) {
      firstLength = openLength;
      firstLine = openLine;
    } else if (oddRow == kNone && openLength != firstLength) {
      oddRow = rows;
      oddLength = openLength;
      oddLine = openLine;
    }
    ++rows;
  }
};

/// Where the fields of the patch being read are in the file, and the rows'
/// shapes checked when its object closes; the values themselves go straight
/// into the Patch.
struct PatchSource {
  std::size_t line = 0;                  ///< Of the patch object's opening brace.
  std::size_t fieldLine[kNumFields];     ///< Of each field's name; kNone when absent.
  std::string kind;                      ///< As written (checked when the patch closes).
  std::string cell;                      ///< As written.
  RowShape points;                       ///< control_points or vertices.
  RowShape chartPoints;                  ///< chart_control_points.
  RowShape cells;

  /// A patch with no field seen yet.
  PatchSource() { std::fill(std::begin(fieldLine), std::end(fieldLine), kNone); }
  /// Whether field f was present, and where.
  bool Has(Field f) const { return fieldLine[static_cast<int>(f)] != kNone; }
  std::size_t At(Field f) const { return fieldLine[static_cast<int>(f)]; }
};

/// The check of one patch that needs the dimension: coordinates per point.
/// It waits for the end of the file when "dimension" follows "patches"; a
/// small record keeps that wait cheap for files of many patches.
struct DimensionCheck {
  std::size_t patch = 0;  ///< Index of the patch.
  Patch::Kind kind = Patch::Kind::Mesh;
  RowShape points;  ///< control_points or vertices.
  std::size_t kindLine = 0;  ///< Of "kind", for a pou_manifold outside dimension 3.
};

/// The SAX handler: checks each value's type and place as it arrives,
/// records its line and appends it to the patch being read, so a large file
/// is never held as a DOM. Depth 1 is the
/// root object, 2 the patches array, 3 a patch, 4 a field's array, 5 a row
/// of a nested field (a knot vector, a point, a cell). Every problem throws
/// InputError with the line of the offending value.
class GeometryHandler {
 public:
  /// `text` is what the lexer reads; it outlives the handler. `source`
  /// receives the line of every patch, field and element read.
  GeometryHandler(const std::string& name, JsonTextStream* text, GeometrySource* source)
      : name_(name), text_(text), source_(*source) {}

  // nlohmann's SAX events (nlohmann::json_sax): each returns true to go on;
  // a problem throws InputError instead of returning false, so the message
  // is ours.

  /// A scalar value: null, boolean, number or string.
  bool null() { return OnScalar(Scalar{}); }
  bool boolean(bool value) {
    Scalar v;
    v.type = Scalar::Type::Boolean;
    v.boolean = value;
    return OnScalar(v);
  }
  bool number_integer(std::int64_t value) {
    Scalar v;
    v.type = Scalar::Type::Integer;
    v.integer = value;
    return OnScalar(v);
  }
  bool number_unsigned(std::uint64_t value) {
    Scalar v;
    v.type = Scalar::Type::Unsigned;
    v.unsignedInteger = value;
    return OnScalar(v);
  }
  bool number_float(double value, const std::string& token) {
    Scalar v;
    v.type = Scalar::Type::Float;
    v.number = value;
    v.text = token;
    return OnScalar(v);
  }
  bool string(std::string& value) {
    Scalar v;
    v.type = Scalar::Type::String;
    v.text = value;
    return OnScalar(v);
  }
  bool binary(Json::binary_t&) { return true; }  // JSON text has no binary values.

  /// Containers open and close; the size hint is -1 for text input.
  bool start_object(std::size_t);
  bool end_object();
  bool start_array(std::size_t);
  bool end_array();
  /// A field name of the object being read.
  bool key(std::string& name);
  /// Invalid JSON at byte `position` (1-based count of bytes read): throws.
  [[noreturn]] bool parse_error(std::size_t position, const std::string& lastToken, const Json::exception& error);

  /// Checks what needed the whole file (required top-level fields, the
  /// deferred dimension checks) and returns the geometry.
  Geometry Finish();

 private:
  /// Dispatches a scalar by depth to one of the four below.
  bool OnScalar(const Scalar& v);
  /// A top-level field's value.
  void RootScalar(const Scalar& v);
  /// A patch field's value (only kind and cell are scalars).
  void PatchScalar(const Scalar& v);
  /// An element of a field's array (degrees, counts, weights).
  void ListScalar(const Scalar& v);
  /// An element of a row (a knot, a coordinate, a vertex index).
  void RowScalar(const Scalar& v);
  /// Opens a new patch at the lexer's position.
  void BeginPatch();
  /// Checks the fields of the patch just closed (the last one): its kind,
  /// the fields that kind has, its cell type and its cells' rows; hands the
  /// check of its points' rows to CheckDimension, now or at the end. What
  /// the values mean (knots, counts, indices, weights) Manifold::Build checks.
  void CheckPatchFields();
  /// Coordinates per point, once the dimension is known.
  void CheckDimension(const DimensionCheck& check) const;

  /// The 1-based line of the current token (JsonTextStream::Line).
  std::size_t Here() const { return static_cast<std::size_t>(text_->Line()); }
  /// Here() as GeometrySource records lines.
  std::int64_t HereLine() const { return text_->Line(); }
  /// Throws InputError at `line`.
  [[noreturn]] void Fail(std::size_t line, const std::string& message) const {
    throw InputError(name_, static_cast<std::int64_t>(line), message);
  }

  /// JSON paths for messages: "patches[3]", "patches[3].knots",
  /// "patches[3].knots[1]", "patches[3].knots[1][4]".
  std::string PatchPath() const { return "patches[" + std::to_string(patches_.size() - 1) + "]"; }
  std::string FieldPath() const { return PatchPath() + "." + kFieldNames[static_cast<int>(field_)]; }
  std::string ElementPath() const { return FieldPath() + "[" + std::to_string(element_) + "]"; }
  std::string RowElementPath() const { return ElementPath() + "[" + std::to_string(rowElement_) + "]"; }
  /// What a patch field holds, for type errors.
  static std::string FieldExpectation(Field f);
  /// True for the fields that are arrays of arrays.
  bool NestedField() const {
    return field_ == Field::Knots || field_ == Field::ControlPoints || field_ == Field::Vertices ||
           field_ == Field::Cells || field_ == Field::ChartControlPoints;
  }

  const std::string& name_;    ///< File name for messages.
  JsonTextStream* text_;       ///< What the lexer reads, with its lines.
  GeometrySource& source_;     ///< Where each patch, field and element was read.
  bool started_ = false;       ///< A SAX event has come: the file is not empty.
  std::int64_t rowLine_ = 0;   ///< Line of the row being read (its opening bracket).

  int depth_ = 0;                     ///< Containers open (see the class comment).
  int skipDepth_ = 0;                 ///< > 0 while skipping the value of an unknown top-level field.
  RootKey rootKey_ = RootKey::Other;  ///< The top-level field being read.
  Field field_ = Field::None;         ///< The patch field being read.
  std::size_t element_ = 0;           ///< Index in the current field's array.
  std::size_t rowElement_ = 0;        ///< Index in the current row.

  std::size_t rootLine_ = 0;  ///< The root object's opening brace.
  /// Where the top-level fields are; kNone until seen.
  std::size_t formatLine_ = kNone, versionLine_ = kNone, dimensionLine_ = kNone, patchesLine_ = kNone;
  int dimension_ = 0;                     ///< 0 until "dimension" is read.
  std::vector<Patch> patches_;            ///< The result, filled while reading.
  PatchSource patch_;                     ///< Of the patch being read.
  std::vector<DimensionCheck> deferred_;  ///< Waiting for "dimension".
};

std::string GeometryHandler::FieldExpectation(Field f) {
  switch (f) {
    case Field::Kind:
      return "a string (bspline, bezier, mesh or pou_manifold)";
    case Field::Cell:
      return std::string("a string (") + kCellTypeNames + ")";
    case Field::Degrees:
    case Field::Counts:
      return "an array of integers";
    case Field::Weights:
      return "an array of numbers";
    case Field::Knots:
      return "an array of knot vectors (arrays of numbers)";
    case Field::ControlPoints:
    case Field::Vertices:
    case Field::ChartControlPoints:
      return "an array of points (arrays of numbers)";
    case Field::Cells:
      return "an array of cells (arrays of vertex indices)";
    case Field::None:
      break;
  }
  return "a value";
}

bool GeometryHandler::OnScalar(const Scalar& v) {
  started_ = true;
  if (skipDepth_ > 0) return true;
  switch (depth_) {
    case 0:
      Fail(Here(), "expected a JSON object at the top level, found " + Describe(v));
    case 1:
      RootScalar(v);
      break;
    case 2:
      Fail(Here(), "patches[" + std::to_string(patches_.size()) + "]: expected a patch object, found " + Describe(v));
    case 3:
      PatchScalar(v);
      break;
    case 4:
      ListScalar(v);
      break;
    default:
      RowScalar(v);
      break;
  }
  return true;
}

void GeometryHandler::RootScalar(const Scalar& v) {
  std::int64_t integer = 0;
  switch (rootKey_) {
    case RootKey::Format:
      if (v.type != Scalar::Type::String || v.text != "invmap-geometry") {
        Fail(Here(), "format: " + Describe(v) + ", expected \"invmap-geometry\"");
      }
      break;
    case RootKey::Version:
      if (!v.AsInteger(&integer)) Fail(Here(), "version: expected an integer, found " + Describe(v));
      if (integer != 1) Fail(Here(), "version: " + std::to_string(integer) + ", this reader supports version 1");
      break;
    case RootKey::Dimension:
      if (!v.AsInteger(&integer)) Fail(Here(), "dimension: expected an integer, found " + Describe(v));
      if (integer != 2 && integer != 3) Fail(Here(), "dimension: " + std::to_string(integer) + ", expected 2 or 3");
      dimension_ = static_cast<int>(integer);
      break;
    case RootKey::Patches:
      Fail(Here(), "patches: expected an array of patch objects, found " + Describe(v));
    case RootKey::Other:
      break;
  }
}

void GeometryHandler::PatchScalar(const Scalar& v) {
  if (field_ == Field::Kind || field_ == Field::Cell) {
    if (v.type != Scalar::Type::String)
      Fail(Here(), FieldPath() + ": expected " + FieldExpectation(field_) + ", found " + Describe(v));
    (field_ == Field::Kind ? patch_.kind : patch_.cell) = std::string(v.text);
    return;
  }
  Fail(Here(), FieldPath() + ": expected " + FieldExpectation(field_) + ", found " + Describe(v));
}

void GeometryHandler::ListScalar(const Scalar& v) {
  Patch& patch = patches_.back();
  if (NestedField()) {
    const char* row = field_ == Field::Knots   ? "a knot vector (array of numbers)"
                      : field_ == Field::Cells ? "a cell (array of vertex indices)"
                                               : "a point (array of numbers)";
    Fail(Here(), ElementPath() + ": expected " + row + ", found " + Describe(v));
  }
  source_.Element(kGeometryFields[static_cast<int>(field_)], static_cast<std::int64_t>(element_), HereLine());
  if (field_ == Field::Weights) {
    if (!v.IsNumber()) Fail(Here(), ElementPath() + ": expected a number, found " + Describe(v));
    patch.weights.push_back(v.AsDouble());
  } else {
    // degrees or counts: integers that fit in an int.
    std::int64_t integer = 0;
    if (!v.AsInteger(&integer)) Fail(Here(), ElementPath() + ": expected an integer, found " + Describe(v));
    if (integer < std::numeric_limits<int>::min() || integer > std::numeric_limits<int>::max()) {
      Fail(Here(), ElementPath() + ": " + std::to_string(integer) + ", expected an integer within [" +
                       std::to_string(std::numeric_limits<int>::min()) + ", " +
                       std::to_string(std::numeric_limits<int>::max()) + "]");
    }
    (field_ == Field::Degrees ? patch.degrees : patch.counts).push_back(static_cast<int>(integer));
  }
  ++element_;
}

void GeometryHandler::RowScalar(const Scalar& v) {
  Patch& patch = patches_.back();
  // A row written over several lines: the lines of its values off the row's.
  if (const std::int64_t line = HereLine(); line != rowLine_) {
    source_.Item(kGeometryFields[static_cast<int>(field_)], static_cast<std::int64_t>(element_),
                 static_cast<std::int64_t>(rowElement_), line);
  }
  if (field_ == Field::Cells) {
    std::int64_t index = 0;
    if (!v.AsInteger(&index))
      Fail(Here(), RowElementPath() + ": expected a vertex index (integer), found " + Describe(v));
    patch.cells.push_back(index);
    ++patch_.cells.openLength;
  } else {
    if (!v.IsNumber()) Fail(Here(), RowElementPath() + ": expected a number, found " + Describe(v));
    const double x = v.AsDouble();
    // The lexer rejects overflowing literals; this keeps the guarantee local.
    if (!std::isfinite(x)) Fail(Here(), RowElementPath() + ": " + Describe(v) + " is not a finite number");
    if (field_ == Field::Knots) {
      patch.knots.back().push_back(x);
    } else if (field_ == Field::ChartControlPoints) {
      patch.chartControlPoints.push_back(x);
      ++patch_.chartPoints.openLength;
    } else {
      patch.points.push_back(x);
      ++patch_.points.openLength;
    }
  }
  ++rowElement_;
}

void GeometryHandler::BeginPatch() {
  patches_.emplace_back();
  patch_ = PatchSource();
  patch_.line = Here();
  source_.BeginPatch(HereLine());
  field_ = Field::None;
}

bool GeometryHandler::start_object(std::size_t) {
  started_ = true;
  if (skipDepth_ > 0) {
    ++skipDepth_;
    return true;
  }
  switch (depth_) {
    case 0:
      rootLine_ = Here();
      break;
    case 1:
      if (rootKey_ != RootKey::Other) {
        const char* names[] = {"format", "version", "dimension", "patches"};
        Fail(Here(), std::string(names[static_cast<int>(rootKey_)]) + ": unexpected object");
      }
      skipDepth_ = 1;
      return true;
    case 2:
      BeginPatch();
      break;
    case 3:
      Fail(Here(), FieldPath() + ": expected " + FieldExpectation(field_) + ", found an object");
    case 4:
      Fail(Here(), ElementPath() + ": expected " + (NestedField() ? "an array" : "a number") + ", found an object");
    default:
      Fail(Here(), RowElementPath() + ": expected a number, found an object");
  }
  ++depth_;
  return true;
}

bool GeometryHandler::start_array(std::size_t) {
  started_ = true;
  if (skipDepth_ > 0) {
    ++skipDepth_;
    return true;
  }
  switch (depth_) {
    case 0:
      Fail(Here(), "expected a JSON object at the top level, found an array");
    case 1:
      if (rootKey_ == RootKey::Other) {
        skipDepth_ = 1;
        return true;
      }
      if (rootKey_ != RootKey::Patches) {
        const char* names[] = {"format", "version", "dimension"};
        Fail(Here(), std::string(names[static_cast<int>(rootKey_)]) + ": unexpected array");
      }
      break;
    case 2:
      Fail(Here(), "patches[" + std::to_string(patches_.size()) + "]: expected a patch object, found an array");
    case 3:
      if (field_ == Field::Kind || field_ == Field::Cell) {
        Fail(Here(), FieldPath() + ": expected " + FieldExpectation(field_) + ", found an array");
      }
      element_ = 0;
      break;
    case 4:
      if (!NestedField()) {
        Fail(Here(), ElementPath() + ": expected " + (field_ == Field::Weights ? "a number" : "an integer") +
                         ", found an array");
      }
      rowElement_ = 0;
      rowLine_ = HereLine();
      source_.Element(kGeometryFields[static_cast<int>(field_)], static_cast<std::int64_t>(element_), rowLine_);
      if (field_ == Field::Knots) {
        patches_.back().knots.emplace_back();
      } else {
        (field_ == Field::Cells                ? patch_.cells
         : field_ == Field::ChartControlPoints ? patch_.chartPoints
                                               : patch_.points)
            .Open(Here());
      }
      break;
    default:
      Fail(Here(), RowElementPath() + ": expected a number, found an array");
  }
  ++depth_;
  return true;
}

bool GeometryHandler::end_array() {
  if (skipDepth_ > 0) {
    --skipDepth_;
    return true;
  }
  --depth_;
  if (depth_ == 4) {
    if (field_ == Field::ControlPoints || field_ == Field::Vertices) patch_.points.Close();
    if (field_ == Field::ChartControlPoints) patch_.chartPoints.Close();
    if (field_ == Field::Cells) patch_.cells.Close();
    ++element_;
  }
  return true;
}

bool GeometryHandler::end_object() {
  if (skipDepth_ > 0) {
    --skipDepth_;
    return true;
  }
  --depth_;
  if (depth_ == 2) CheckPatchFields();
  return true;
}

bool GeometryHandler::key(std::string& name) {
  if (skipDepth_ > 0) return true;
  if (depth_ == 1) {
    static const std::pair<const char*, RootKey> kKeys[] = {{"format", RootKey::Format},
                                                            {"version", RootKey::Version},
                                                            {"dimension", RootKey::Dimension},
                                                            {"patches", RootKey::Patches}};
    std::size_t* lines[] = {&formatLine_, &versionLine_, &dimensionLine_, &patchesLine_};
    rootKey_ = RootKey::Other;
    for (int k = 0; k < 4; ++k) {
      if (name == kKeys[k].first) {
        if (*lines[k] != kNone) Fail(Here(), "duplicate field \"" + name + "\"");
        *lines[k] = Here();
        rootKey_ = kKeys[k].second;
      }
    }
    return true;
  }
  // depth 3: objects elsewhere are rejected before their keys.
  field_ = Field::None;
  for (int f = 0; f < kNumFields; ++f) {
    if (name == kFieldNames[f]) field_ = static_cast<Field>(f);
  }
  if (field_ == Field::None) {
    Fail(Here(), PatchPath() + ": unknown field \"" + name +
                     "\" (patch fields: kind, cell, degrees, knots, counts, control_points, weights, vertices, cells, "
                     "chart_control_points)");
  }
  if (patch_.Has(field_)) Fail(Here(), PatchPath() + ": duplicate field \"" + name + "\"");
  patch_.fieldLine[static_cast<int>(field_)] = Here();
  source_.Field(kGeometryFields[static_cast<int>(field_)], HereLine());
  return true;
}

bool GeometryHandler::parse_error(std::size_t position, const std::string& /*lastToken*/,
                                  const Json::exception& error) {
  if (!started_ && text_->OnlyBlankRead()) {
    Fail(static_cast<std::size_t>(text_->LineBefore(text_->Offset() + 1)), "empty file, expected a JSON object");
  }
  const std::int64_t at = static_cast<std::int64_t>(position);
  const std::size_t inWindow = static_cast<std::size_t>(std::max<std::int64_t>(0, at - text_->windowOffset()));
  Fail(static_cast<std::size_t>(text_->LineBefore(at)),
       DescribeJsonParseError(text_->window(), text_->windowSize(), inWindow, error.what()));
}

Geometry GeometryHandler::Finish() {
  if (formatLine_ == kNone) Fail(rootLine_, "missing field \"format\" (expected \"invmap-geometry\")");
  if (versionLine_ == kNone) Fail(rootLine_, "missing field \"version\" (expected 1)");
  if (dimensionLine_ == kNone) Fail(rootLine_, "missing field \"dimension\" (expected 2 or 3)");
  if (patchesLine_ == kNone) Fail(rootLine_, "missing field \"patches\" (an array, possibly empty)");
  for (const DimensionCheck& check : deferred_) CheckDimension(check);
  Geometry geometry;
  geometry.dimension = dimension_;
  geometry.patches = std::move(patches_);
  return geometry;
}

void GeometryHandler::CheckPatchFields() {
  const std::size_t index = patches_.size() - 1;
  Patch& patch = patches_.back();
  const PatchSource& source = patch_;
  const std::string where = "patches[" + std::to_string(index) + "]";

  // Kind, then which fields it allows and needs.
  if (!source.Has(Field::Kind)) {
    Fail(source.line, where + ": missing field \"kind\" (bspline, bezier, mesh or pou_manifold)");
  }
  // Fields of each kind as bit sets over Field.
  const auto bit = [](Field f) { return 1u << static_cast<int>(f); };
  unsigned required = 0, optional = bit(Field::Kind);
  if (source.kind == "bspline") {
    patch.kind = Patch::Kind::BSpline;
    required = bit(Field::Degrees) | bit(Field::Knots) | bit(Field::Counts) | bit(Field::ControlPoints);
    optional |= bit(Field::Weights);
  } else if (source.kind == "bezier") {
    patch.kind = Patch::Kind::Bezier;
    required = bit(Field::Cell) | bit(Field::Degrees) | bit(Field::ControlPoints);
    optional |= bit(Field::Weights);
  } else if (source.kind == "mesh") {
    patch.kind = Patch::Kind::Mesh;
    required = bit(Field::Cell) | bit(Field::Vertices) | bit(Field::Cells);
  } else if (source.kind == "pou_manifold") {
    patch.kind = Patch::Kind::PouManifold;
    patch.cell = CellType::Tri;
    required = bit(Field::Vertices) | bit(Field::Cells) | bit(Field::Degrees) | bit(Field::ChartControlPoints);
  } else {
    Fail(source.At(Field::Kind), where + ".kind: unknown patch kind \"" + source.kind +
                                     "\" (expected bspline, bezier, mesh or pou_manifold)");
  }
  for (int f = 0; f < kNumFields; ++f) {
    if (source.Has(static_cast<Field>(f)) && !((required | optional) & (1u << f))) {
      Fail(source.fieldLine[f],
           where + ": field \"" + kFieldNames[f] + "\" does not belong to a " + source.kind + " patch");
    }
  }
  for (int f = 0; f < kNumFields; ++f) {
    if ((required & (1u << f)) && !source.Has(static_cast<Field>(f))) {
      Fail(source.line,
           where + ": missing field \"" + kFieldNames[f] + "\" (required for a " + source.kind + " patch)");
    }
  }
  if (source.Has(Field::Cell) && !ParseCellType(source.cell, &patch.cell)) {
    Fail(source.At(Field::Cell),
         where + ".cell: unknown cell type \"" + source.cell + "\" (expected " + kCellTypeNames + ")");
  }

  // Every cell a row of its type's vertex count: the indices go into one
  // array, where a row too long or too short would shift every later cell.
  if (patch.kind == Patch::Kind::Mesh || patch.kind == Patch::Kind::PouManifold) {
    const std::size_t perCell = static_cast<std::size_t>(TraitsOf(patch.cell).vertices);
    const RowShape& cells = source.cells;
    const auto cellCountMessage = [&](std::size_t row, std::size_t length) {
      return where + ".cells[" + std::to_string(row) + "]: " + std::to_string(length) + " vertex indices, a " +
             CellTypeName(patch.cell) + " cell has " + std::to_string(perCell);
    };
    if (cells.rows > 0 && cells.firstLength != perCell) Fail(cells.firstLine, cellCountMessage(0, cells.firstLength));
    if (cells.oddRow != kNone) Fail(cells.oddLine, cellCountMessage(cells.oddRow, cells.oddLength));
  }
  // A chart's control point is a point of R^3, whatever the dimension.
  if (patch.kind == Patch::Kind::PouManifold) {
    const RowShape& rows = source.chartPoints;
    const auto rowMessage = [&](std::size_t row, std::size_t length) {
      return where + ".chart_control_points[" + std::to_string(row) + "]: " + std::to_string(length) +
             " coordinates, expected 3";
    };
    if (rows.rows > 0 && rows.firstLength != 3) Fail(rows.firstLine, rowMessage(0, rows.firstLength));
    if (rows.oddRow != kNone) Fail(rows.oddLine, rowMessage(rows.oddRow, rows.oddLength));
  }

  DimensionCheck check;
  check.patch = index;
  check.kind = patch.kind;
  check.points = source.points;
  check.kindLine = source.At(Field::Kind);
  if (dimension_ != 0) {
    CheckDimension(check);
  } else {
    deferred_.push_back(check);
  }
}

void GeometryHandler::CheckDimension(const DimensionCheck& check) const {
  const std::string where = "patches[" + std::to_string(check.patch) + "]";
  const std::size_t dim = static_cast<std::size_t>(dimension_);
  if (check.kind == Patch::Kind::PouManifold && dim != 3) {
    Fail(check.kindLine, where + ".kind: a pou_manifold is a surface of R^3 (dimension 3), the file's dimension is " +
                             std::to_string(dim));
  }
  const char* pointsName =
      check.kind == Patch::Kind::Mesh || check.kind == Patch::Kind::PouManifold ? "vertices" : "control_points";
  const RowShape& points = check.points;
  if (points.rows > 0 && points.firstLength != dim) {
    Fail(points.firstLine, where + "." + pointsName + "[0]: " + std::to_string(points.firstLength) +
                                 " coordinates, expected " + std::to_string(dim) + " (the dimension)");
  }
  if (points.oddRow != kNone) {
    Fail(points.oddLine, where + "." + pointsName + "[" + std::to_string(points.oddRow) +
                               "]: " + std::to_string(points.oddLength) + " coordinates, expected " +
                               std::to_string(dim) + " (the dimension)");
  }
}

/// Parses a geometry file streamed from `in`, named `name` in messages,
/// recording where its parts are into `source` (when not null).
Geometry ParseGeometryStream(InputBuffer* in, const std::string& name, GeometrySource* source) {
  GeometrySource unused;
  if (!source) source = &unused;
  *source = GeometrySource(name);
  JsonTextStream text(in);
  GeometryHandler handler(name, &text, source);
  Json::sax_parse(text.begin(), text.end(), &handler);
  return handler.Finish();
}

}  // namespace

Geometry ReadGeometryJson(const std::string& path, GeometrySource* source) {
  InputBuffer in(path);
  return ParseGeometryStream(&in, path, source);
}

Geometry ReadGeometryJson(std::istream& in, const std::string& nameForMessages, GeometrySource* source) {
  // A stream of its own over the caller's buffer: reading advances `in`.
  InputBuffer buffer(std::make_unique<std::istream>(in.rdbuf()), nameForMessages);
  return ParseGeometryStream(&buffer, nameForMessages, source);
}

}  // namespace invmap::io
