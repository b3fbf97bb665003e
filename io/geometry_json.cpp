#include "io/geometry_json.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <iterator>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/file_io.h"
#include "io/input_error.h"
#include "io/json_sax.h"
#include "kernels/cell_shape.h"

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
constexpr const char* kFieldNames[kNumFields] = {"kind",    "cell",     "degrees", "knots",
                                                 "counts",  "control_points", "weights", "vertices",
                                                 "cells",   "chart_control_points"};

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

/// Text of a number for messages: the shortest of 15 to 17 digits that reads
/// back as the same double, so 0.1 prints as 0.1 and no value is misquoted.
std::string FormatNumber(double x) {
  char text[32];
  for (int digits = 15; digits < 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x) return text;
  }
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

/// Row lengths of an array of arrays (points or cells), summarized while
/// streaming. JSON objects are unordered ("dimension" may follow "patches",
/// "cell" may follow "cells"), so the lengths are checked once the file is
/// read: row 0 against the expectation, then the first row that differs
/// from row 0. Offsets are byte positions of the rows, for the line.
struct RowShape {
  std::size_t rows = 0;
  std::size_t firstLength = 0;
  std::size_t firstOffset = 0;
  std::size_t oddRow = kNone;  ///< First row whose length differs from row 0's.
  std::size_t oddLength = 0;
  std::size_t oddOffset = 0;
  std::size_t openLength = 0;  ///< Length so far of the row being read.
  std::size_t openOffset = 0;

  /// A row starts at byte `offset`.
  void Open(std::size_t offset) {
    openLength = 0;
    openOffset = offset;
  }
  /// The open row ends.
  void Close() {
    if (rows == 0) {
      firstLength = openLength;
      firstOffset = openOffset;
    } else if (oddRow == kNone && openLength != firstLength) {
      oddRow = rows;
      oddLength = openLength;
      oddOffset = openOffset;
    }
    ++rows;
  }
};

/// Where the fields of the patch being read are in the file, and what is
/// checked when its object closes; the values themselves go straight into
/// the Patch.
struct PatchSource {
  std::size_t offset = 0;                ///< The patch object's opening brace.
  std::size_t fieldOffset[kNumFields];   ///< Of each field's name; kNone when absent.
  std::string kind;                      ///< As written (checked when the patch closes).
  std::string cell;                      ///< As written.
  std::vector<std::size_t> knotOffsets;  ///< One per knot vector.
  RowShape points;                       ///< control_points or vertices.
  RowShape chartPoints;                  ///< chart_control_points.
  RowShape cells;
  /// Extreme vertex indices of `cells` with their rows, checked against the
  /// vertex count when the patch closes ("vertices" may follow "cells").
  std::int64_t minIndex = std::numeric_limits<std::int64_t>::max();
  std::int64_t maxIndex = std::numeric_limits<std::int64_t>::min();
  std::size_t minRow = 0, minOffset = 0, maxRow = 0, maxOffset = 0;

  /// A patch with no field seen yet.
  PatchSource() { std::fill(std::begin(fieldOffset), std::end(fieldOffset), kNone); }
  /// Whether field f was present, and where.
  bool Has(Field f) const { return fieldOffset[static_cast<int>(f)] != kNone; }
  std::size_t At(Field f) const { return fieldOffset[static_cast<int>(f)]; }
};

/// The checks of one patch that need the dimension: coordinates per point
/// and cells that do not fit in 2D. They wait for the end of the file when
/// "dimension" follows "patches"; a small record keeps that wait cheap for
/// files of many patches.
struct DimensionCheck {
  std::size_t patch = 0;  ///< Index of the patch.
  Patch::Kind kind = Patch::Kind::Mesh;
  CellType cell = CellType::Line;  ///< Bezier and mesh patches.
  RowShape points;                 ///< control_points or vertices.
  std::size_t paramDim = 0;        ///< Parameters of the cells (bspline: of the patch).
  std::size_t paramDimOffset = 0;  ///< The field that fixes paramDim: "cell" or "degrees".
};

/// Cell types by their name in the file.
bool ParseCellType(const std::string& name, CellType* type) {
  static const std::pair<const char*, CellType> kNames[] = {{"line", CellType::Line}, {"tri", CellType::Tri},
                                                            {"quad", CellType::Quad}, {"tet", CellType::Tet},
                                                            {"hex", CellType::Hex},   {"wedge", CellType::Wedge}};
  for (const auto& [text, value] : kNames) {
    if (name == text) {
      *type = value;
      return true;
    }
  }
  return false;
}

/// Name of a cell type in the file.
const char* CellTypeName(CellType type) {
  static const char* const kNames[] = {"line", "tri", "quad", "tet", "hex", "wedge"};
  return kNames[static_cast<int>(type)];
}

/// Parametric dimension of a reference cell (FORMATS.md section 1).
int ParamDimOf(CellType type) {
  switch (type) {
    case CellType::Line:
      return 1;
    case CellType::Tri:
    case CellType::Quad:
      return 2;
    default:
      return 3;
  }
}

/// Vertices of a linear mesh cell.
std::size_t VerticesOf(CellType type) {
  static const std::size_t kVertices[] = {2, 3, 4, 4, 8, 6};
  return kVertices[static_cast<int>(type)];
}

/// Degrees a Bezier cell lists (one per simplex factor) and how they read.
int FactorsOf(CellType type, const char** form) {
  switch (type) {
    case CellType::Quad:
      *form = "[p, q]";
      return 2;
    case CellType::Hex:
      *form = "[p, q, r]";
      return 3;
    case CellType::Wedge:
      *form = "[p_tri, q_line]";
      return 2;
    default:
      *form = "[p]";
      return 1;
  }
}

/// Control points of a Bezier cell; double so that absurd degrees cannot
/// overflow (the count is only compared with the points actually present).
double BezierPointCount(CellType type, const std::vector<int>& degrees) {
  const double p = degrees[0];
  switch (type) {
    case CellType::Line:
      return p + 1;
    case CellType::Tri:
      return (p + 1) * (p + 2) / 2;
    case CellType::Quad:
      return (p + 1) * (degrees[1] + 1.0);
    case CellType::Tet:
      return (p + 1) * (p + 2) * (p + 3) / 6;
    case CellType::Hex:
      return (p + 1) * (degrees[1] + 1.0) * (degrees[2] + 1.0);
    case CellType::Wedge:
      return (p + 1) * (p + 2) / 2 * (degrees[1] + 1.0);
  }
  return 0;
}

/// The SAX handler: checks each value as it arrives and appends it to the
/// patch being read, so a large file is never held as a DOM. Depth 1 is the
/// root object, 2 the patches array, 3 a patch, 4 a field's array, 5 a row
/// of a nested field (a knot vector, a point, a cell). Every problem throws
/// InputError with the line of the offending value.
class GeometryHandler {
 public:
  /// `begin` is the buffer start and `*cursor` the lexer's reading position
  /// (see TrackingIterator); both outlive the handler.
  GeometryHandler(const std::string& name, const char* begin, std::size_t size, const char* const* cursor)
      : name_(name), begin_(begin), size_(size), cursor_(cursor) {}

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
  /// Checks the patch just closed (the last one) and hands its dimension
  /// checks to CheckDimension, now or at the end.
  void ValidatePatch();
  /// Coordinates per point and cells that need 3D, once the dimension is known.
  void CheckDimension(const DimensionCheck& check) const;

  /// Byte offset of the lexer: just past the current token (for a number,
  /// one character further, which LineAt excludes).
  std::size_t Here() const { return static_cast<std::size_t>(*cursor_ - begin_); }
  /// 1-based line of the last character read before byte `offset`.
  std::int64_t LineAt(std::size_t offset) const {
    const std::size_t end = std::min(offset, size_);
    const std::size_t last = end > 0 ? end - 1 : 0;
    return 1 + std::count(begin_, begin_ + last, '\n');
  }
  /// Throws InputError at the line of byte `offset`.
  [[noreturn]] void Fail(std::size_t offset, const std::string& message) const {
    throw InputError(name_, LineAt(offset), message);
  }

  /// JSON paths for messages: "patches[3]", "patches[3].knots",
  /// "patches[3].knots[1]", "patches[3].knots[1][4]".
  std::string PatchPath() const { return "patches[" + std::to_string(patches_.size() - 1) + "]"; }
  std::string FieldPath() const { return PatchPath() + "." + kFieldNames[static_cast<int>(field_)]; }
  std::string ElementPath() const { return FieldPath() + "[" + std::to_string(element_) + "]"; }
  std::string RowElementPath() const { return ElementPath() + "[" + std::to_string(rowElement_) + "]"; }
  /// What a patch field holds, for type errors.
  static const char* FieldExpectation(Field f);
  /// True for the fields that are arrays of arrays.
  bool NestedField() const {
    return field_ == Field::Knots || field_ == Field::ControlPoints || field_ == Field::Vertices ||
           field_ == Field::Cells || field_ == Field::ChartControlPoints;
  }

  const std::string& name_;    ///< File name for messages.
  const char* begin_;          ///< The text.
  std::size_t size_;           ///< Its length.
  const char* const* cursor_;  ///< The lexer's reading position in it.

  int depth_ = 0;                     ///< Containers open (see the class comment).
  int skipDepth_ = 0;                 ///< > 0 while skipping the value of an unknown top-level field.
  RootKey rootKey_ = RootKey::Other;  ///< The top-level field being read.
  Field field_ = Field::None;         ///< The patch field being read.
  std::size_t element_ = 0;           ///< Index in the current field's array.
  std::size_t rowElement_ = 0;        ///< Index in the current row.

  std::size_t rootOffset_ = 0;  ///< The root object's opening brace.
  /// Where the top-level fields are; kNone until seen.
  std::size_t formatOffset_ = kNone, versionOffset_ = kNone, dimensionOffset_ = kNone, patchesOffset_ = kNone;
  int dimension_ = 0;                     ///< 0 until "dimension" is read.
  std::vector<Patch> patches_;            ///< The result, filled while reading.
  PatchSource source_;                    ///< Of the patch being read.
  std::vector<DimensionCheck> deferred_;  ///< Waiting for "dimension".
};

const char* GeometryHandler::FieldExpectation(Field f) {
  switch (f) {
    case Field::Kind:
      return "a string (bspline, bezier or mesh)";
    case Field::Cell:
      return "a string (line, tri, quad, tet, hex or wedge)";
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
  PatchSource& source = source_;
  if (field_ == Field::Kind || field_ == Field::Cell) {
    if (v.type != Scalar::Type::String)
      Fail(Here(), FieldPath() + ": expected " + FieldExpectation(field_) + ", found " + Describe(v));
    (field_ == Field::Kind ? source.kind : source.cell) = std::string(v.text);
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
  if (field_ == Field::Weights) {
    if (!v.IsNumber()) Fail(Here(), ElementPath() + ": expected a number, found " + Describe(v));
    const double w = v.AsDouble();
    if (!std::isfinite(w) || !(w > 0.0)) {
      Fail(Here(), ElementPath() + ": weight " + FormatNumber(w) + " is not positive");
    }
    if (w > kernels::kMaxWeight || w < 1.0 / kernels::kMaxWeight) {
      Fail(Here(), ElementPath() + ": weight " + FormatNumber(w) + " is outside [1e-50, 1e50] (the range invmap supports)");
    }
    patch.weights.push_back(w);
  } else {
    // degrees or counts: positive integers that fit in an int.
    std::int64_t integer = 0;
    if (!v.AsInteger(&integer)) Fail(Here(), ElementPath() + ": expected an integer, found " + Describe(v));
    if (integer < 1 || integer > std::numeric_limits<int>::max()) {
      Fail(Here(), ElementPath() + ": " + std::to_string(integer) + ", expected a positive integer");
    }
    // Checked here too (the engine checks it again) so that the message names the line.
    if (field_ == Field::Degrees && integer > kernels::kMaxDegree) {
      Fail(Here(), ElementPath() + ": " + std::to_string(integer) + ", expected 1 to " +
                       std::to_string(kernels::kMaxDegree) + " (the highest degree invmap supports)");
    }
    (field_ == Field::Degrees ? patch.degrees : patch.counts).push_back(static_cast<int>(integer));
  }
  ++element_;
}

void GeometryHandler::RowScalar(const Scalar& v) {
  Patch& patch = patches_.back();
  PatchSource& source = source_;
  if (field_ == Field::Cells) {
    std::int64_t index = 0;
    if (!v.AsInteger(&index))
      Fail(Here(), RowElementPath() + ": expected a vertex index (integer), found " + Describe(v));
    if (index < source.minIndex) {
      source.minIndex = index;
      source.minRow = element_;
      source.minOffset = Here();
    }
    if (index > source.maxIndex) {
      source.maxIndex = index;
      source.maxRow = element_;
      source.maxOffset = Here();
    }
    patch.cells.push_back(index);
    ++source.cells.openLength;
  } else {
    if (!v.IsNumber()) Fail(Here(), RowElementPath() + ": expected a number, found " + Describe(v));
    const double x = v.AsDouble();
    // The lexer rejects overflowing literals; this keeps the guarantee local.
    if (!std::isfinite(x)) Fail(Here(), RowElementPath() + ": " + Describe(v) + " is not a finite number");
    if (field_ == Field::Knots) {
      std::vector<double>& knots = patch.knots.back();
      if (!knots.empty() && knots.back() > x) {
        Fail(Here(), ElementPath() + ": decreasing at index " + std::to_string(knots.size()) + " (" +
                         FormatNumber(knots.back()) + " > " + FormatNumber(x) + ")");
      }
      knots.push_back(x);
    } else {
      // Checked here too (the engine checks it again) so that the message names the line.
      if (std::abs(x) > kernels::kMaxCoordinate) {
        Fail(Here(), RowElementPath() + ": coordinate " + FormatNumber(x) +
                         " is outside [-1e100, 1e100] (the range invmap supports)");
      }
      if (field_ == Field::ChartControlPoints) {
        patch.chartControlPoints.push_back(x);
        ++source.chartPoints.openLength;
      } else {
        patch.points.push_back(x);
        ++source.points.openLength;
      }
    }
  }
  ++rowElement_;
}

void GeometryHandler::BeginPatch() {
  patches_.emplace_back();
  source_ = PatchSource();
  source_.offset = Here();
  field_ = Field::None;
}

bool GeometryHandler::start_object(std::size_t) {
  if (skipDepth_ > 0) {
    ++skipDepth_;
    return true;
  }
  switch (depth_) {
    case 0:
      rootOffset_ = Here();
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
      if (field_ == Field::Knots) {
        patches_.back().knots.emplace_back();
        source_.knotOffsets.push_back(Here());
      } else {
        (field_ == Field::Cells                ? source_.cells
         : field_ == Field::ChartControlPoints ? source_.chartPoints
                                               : source_.points)
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
    if (field_ == Field::ControlPoints || field_ == Field::Vertices) source_.points.Close();
    if (field_ == Field::ChartControlPoints) source_.chartPoints.Close();
    if (field_ == Field::Cells) source_.cells.Close();
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
  if (depth_ == 2) ValidatePatch();
  return true;
}

bool GeometryHandler::key(std::string& name) {
  if (skipDepth_ > 0) return true;
  if (depth_ == 1) {
    static const std::pair<const char*, RootKey> kKeys[] = {{"format", RootKey::Format},
                                                            {"version", RootKey::Version},
                                                            {"dimension", RootKey::Dimension},
                                                            {"patches", RootKey::Patches}};
    std::size_t* offsets[] = {&formatOffset_, &versionOffset_, &dimensionOffset_, &patchesOffset_};
    rootKey_ = RootKey::Other;
    for (int k = 0; k < 4; ++k) {
      if (name == kKeys[k].first) {
        if (*offsets[k] != kNone) Fail(Here(), "duplicate field \"" + name + "\"");
        *offsets[k] = Here();
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
  PatchSource& source = source_;
  if (source.Has(field_)) Fail(Here(), PatchPath() + ": duplicate field \"" + name + "\"");
  source.fieldOffset[static_cast<int>(field_)] = Here();
  return true;
}

bool GeometryHandler::parse_error(std::size_t position, const std::string& /*lastToken*/,
                                  const Json::exception& error) {
  Fail(position, DescribeJsonParseError(begin_, size_, position, error.what()));
}

Geometry GeometryHandler::Finish() {
  if (formatOffset_ == kNone) Fail(rootOffset_, "missing field \"format\" (expected \"invmap-geometry\")");
  if (versionOffset_ == kNone) Fail(rootOffset_, "missing field \"version\" (expected 1)");
  if (dimensionOffset_ == kNone) Fail(rootOffset_, "missing field \"dimension\" (expected 2 or 3)");
  if (patchesOffset_ == kNone) Fail(rootOffset_, "missing field \"patches\" (an array, possibly empty)");
  for (const DimensionCheck& check : deferred_) CheckDimension(check);
  Geometry geometry;
  geometry.dimension = dimension_;
  geometry.patches = std::move(patches_);
  return geometry;
}

void GeometryHandler::ValidatePatch() {
  const std::size_t index = patches_.size() - 1;
  Patch& patch = patches_.back();
  const PatchSource& source = source_;
  const std::string where = "patches[" + std::to_string(index) + "]";

  // Kind, then which fields it allows and needs.
  if (!source.Has(Field::Kind)) {
    Fail(source.offset, where + ": missing field \"kind\" (bspline, bezier, mesh or pou_manifold)");
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
      Fail(source.fieldOffset[f],
           where + ": field \"" + kFieldNames[f] + "\" does not belong to a " + source.kind + " patch");
    }
  }
  for (int f = 0; f < kNumFields; ++f) {
    if ((required & (1u << f)) && !source.Has(static_cast<Field>(f))) {
      Fail(source.offset,
           where + ": missing field \"" + kFieldNames[f] + "\" (required for a " + source.kind + " patch)");
    }
  }
  if (source.Has(Field::Cell) && !ParseCellType(source.cell, &patch.cell)) {
    Fail(source.At(Field::Cell),
         where + ".cell: unknown cell type \"" + source.cell + "\" (expected line, tri, quad, tet, hex or wedge)");
  }

  DimensionCheck check;
  check.patch = index;
  check.kind = patch.kind;
  check.cell = patch.cell;
  check.points = source.points;
  if (patch.kind == Patch::Kind::BSpline) {
    if (patch.degrees.size() < 1 || patch.degrees.size() > 3) {
      Fail(source.At(Field::Degrees), where + ".degrees: " + std::to_string(patch.degrees.size()) +
                                          " values, expected 1 to 3 (one per parametric direction)");
    }
    check.paramDim = patch.degrees.size();
    check.paramDimOffset = source.At(Field::Degrees);
  } else {
    check.paramDim = static_cast<std::size_t>(ParamDimOf(patch.cell));
    check.paramDimOffset = source.At(Field::Cell);
    if (patch.kind == Patch::Kind::PouManifold) {
      check.paramDim = 3;  // a surface of R^3 only
      check.paramDimOffset = source.At(Field::Kind);
    }
  }
  if (dimension_ != 0) {
    CheckDimension(check);
  } else {
    deferred_.push_back(check);
  }

  const std::size_t numPoints = source.points.rows;
  const auto checkWeights = [&] {
    if (source.Has(Field::Weights) && patch.weights.size() != numPoints) {
      Fail(source.At(Field::Weights), where + ".weights: " + std::to_string(patch.weights.size()) +
                                          " values, expected one per control point (" + std::to_string(numPoints) +
                                          ")");
    }
  };

  switch (patch.kind) {
    case Patch::Kind::BSpline: {
      const std::size_t paramDim = patch.degrees.size();
      if (patch.counts.size() != paramDim) {
        Fail(source.At(Field::Counts), where + ".counts: " + std::to_string(patch.counts.size()) +
                                           " values, expected one per degree (" + std::to_string(paramDim) + ")");
      }
      if (patch.knots.size() != paramDim) {
        Fail(source.At(Field::Knots), where + ".knots: " + std::to_string(patch.knots.size()) +
                                          " knot vectors, expected one per degree (" + std::to_string(paramDim) + ")");
      }
      double expectedPoints = 1;
      std::string product;
      for (std::size_t d = 0; d < paramDim; ++d) {
        const std::string i = "[" + std::to_string(d) + "]";
        const std::int64_t p = patch.degrees[d], n = patch.counts[d];
        const std::vector<double>& knots = patch.knots[d];
        if (n < p + 1) {
          Fail(source.At(Field::Counts), where + ".counts" + i + ": " + std::to_string(n) +
                                             ", expected at least degrees" + i + " + 1 = " + std::to_string(p + 1));
        }
        if (static_cast<std::int64_t>(knots.size()) != n + p + 1) {
          Fail(source.knotOffsets[d], where + ".knots" + i + ": length " + std::to_string(knots.size()) +
                                          ", expected counts" + i + " + degrees" + i +
                                          " + 1 = " + std::to_string(n + p + 1));
        }
        // The spline lives on [t_p, t_n]; with no room there it has no cell.
        if (!(knots[p] < knots[n])) {
          Fail(source.knotOffsets[d], where + ".knots" + i + ": empty parameter domain [knots" + i + "[" +
                                          std::to_string(p) + "], knots" + i + "[" + std::to_string(n) + "]] = [" +
                                          FormatNumber(knots[p]) + ", " + FormatNumber(knots[n]) + "]");
        }
        expectedPoints *= static_cast<double>(n);
        product += (d > 0 ? " x " : "") + std::to_string(n);
      }
      if (static_cast<double>(numPoints) != expectedPoints) {
        Fail(source.At(Field::ControlPoints), where + ".control_points: " + std::to_string(numPoints) +
                                                  " points, expected " + FormatNumber(expectedPoints) + " (counts " +
                                                  product + ")");
      }
      checkWeights();
      break;
    }
    case Patch::Kind::Bezier: {
      const char* form = "";
      const int factors = FactorsOf(patch.cell, &form);
      if (patch.degrees.size() != static_cast<std::size_t>(factors)) {
        Fail(source.At(Field::Degrees), where + ".degrees: " + std::to_string(patch.degrees.size()) + " values, a " +
                                            CellTypeName(patch.cell) + " cell needs " + std::to_string(factors) + " " +
                                            form);
      }
      const double expected = BezierPointCount(patch.cell, patch.degrees);
      if (static_cast<double>(numPoints) != expected) {
        std::string degrees;
        for (std::size_t d = 0; d < patch.degrees.size(); ++d) {
          degrees += (d > 0 ? ", " : "") + std::to_string(patch.degrees[d]);
        }
        Fail(source.At(Field::ControlPoints), where + ".control_points: " + std::to_string(numPoints) +
                                                  " points, expected " + FormatNumber(expected) + " for a " +
                                                  CellTypeName(patch.cell) + " cell of degrees [" + degrees + "]");
      }
      checkWeights();
      break;
    }
    case Patch::Kind::PouManifold:
      if (source.chartPoints.rows > 0 && source.chartPoints.firstLength != 3) {
        Fail(source.chartPoints.firstOffset, where + ".chart_control_points[0]: " +
                                                 std::to_string(source.chartPoints.firstLength) +
                                                 " coordinates, expected 3");
      }
      if (source.chartPoints.oddRow != kNone) {
        Fail(source.chartPoints.oddOffset, where + ".chart_control_points[" + std::to_string(source.chartPoints.oddRow) +
                                               "]: " + std::to_string(source.chartPoints.oddLength) +
                                               " coordinates, expected 3");
      }
      if (patch.degrees.size() != numPoints) {
        Fail(source.At(Field::Degrees), where + ".degrees: " + std::to_string(patch.degrees.size()) +
                                            " values, expected one per vertex (" + std::to_string(numPoints) + ")");
      }
      {
        std::size_t expected = 0;
        for (int d : patch.degrees) expected += static_cast<std::size_t>(d + 1) * (d + 1);
        if (source.chartPoints.rows != expected) {
          Fail(source.At(Field::ChartControlPoints), where + ".chart_control_points: " +
                                                         std::to_string(source.chartPoints.rows) + " points, expected " +
                                                         std::to_string(expected) + " ((degree + 1)^2 per vertex)");
        }
      }
      [[fallthrough]];
    case Patch::Kind::Mesh: {
      const std::size_t perCell = VerticesOf(patch.cell);
      const RowShape& cells = source.cells;
      const auto cellCountMessage = [&](std::size_t row, std::size_t length) {
        return where + ".cells[" + std::to_string(row) + "]: " + std::to_string(length) + " vertex indices, a " +
               CellTypeName(patch.cell) + " cell has " + std::to_string(perCell);
      };
      if (cells.rows > 0 && cells.firstLength != perCell)
        Fail(cells.firstOffset, cellCountMessage(0, cells.firstLength));
      if (cells.oddRow != kNone) Fail(cells.oddOffset, cellCountMessage(cells.oddRow, cells.oddLength));
      if (cells.rows > 0) {
        const bool negative = source.minIndex < 0;
        const bool beyond = source.maxIndex >= static_cast<std::int64_t>(numPoints);
        // Of two bad indices, name the earlier one in the file.
        if (negative && (!beyond || source.minRow <= source.maxRow)) {
          Fail(source.minOffset, where + ".cells[" + std::to_string(source.minRow) + "]: vertex index " +
                                     std::to_string(source.minIndex) + " is negative (indices are 0-based)");
        }
        if (beyond) {
          Fail(source.maxOffset, where + ".cells[" + std::to_string(source.maxRow) + "]: vertex index " +
                                     std::to_string(source.maxIndex) + " out of range (the patch has " +
                                     std::to_string(numPoints) + " vertices)");
        }
      }
      break;
    }
    case Patch::Kind::BezierCells:
      break;  // Not a file kind: the kind names above are the only ones parsed.
  }
}

void GeometryHandler::CheckDimension(const DimensionCheck& check) const {
  const std::string where = "patches[" + std::to_string(check.patch) + "]";
  const std::size_t dim = static_cast<std::size_t>(dimension_);
  const char* pointsName =
      check.kind == Patch::Kind::Mesh || check.kind == Patch::Kind::PouManifold ? "vertices" : "control_points";
  const RowShape& points = check.points;
  if (points.rows > 0 && points.firstLength != dim) {
    Fail(points.firstOffset, where + "." + pointsName + "[0]: " + std::to_string(points.firstLength) +
                                 " coordinates, expected " + std::to_string(dim) + " (the dimension)");
  }
  if (points.oddRow != kNone) {
    Fail(points.oddOffset, where + "." + pointsName + "[" + std::to_string(points.oddRow) +
                               "]: " + std::to_string(points.oddLength) + " coordinates, expected " +
                               std::to_string(dim) + " (the dimension)");
  }
  if (check.paramDim > dim) {
    if (check.kind == Patch::Kind::PouManifold) Fail(check.paramDimOffset, where + ".kind: a pou_manifold needs dimension 3");
    if (check.kind == Patch::Kind::BSpline) {
      Fail(check.paramDimOffset,
           where + ".degrees: a " + std::to_string(check.paramDim) + "-parameter patch needs dimension 3");
    }
    Fail(check.paramDimOffset, where + ".cell: a " + CellTypeName(check.cell) +
                                   (check.kind == Patch::Kind::Mesh ? " mesh" : " cell") + " needs dimension 3");
  }
}

/// Parses a whole geometry file held in `text`, named `name` in messages.
Geometry ParseGeometryText(const std::string& text, const std::string& name) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(name, 1 + std::count(text.begin(), text.end(), '\n'), "empty file, expected a JSON object");
  }
  const char* cursor = text.data();
  GeometryHandler handler(name, text.data(), text.size(), &cursor);
  Json::sax_parse(TrackingIterator(&cursor), TrackingIterator(text.data() + text.size()), &handler);
  return handler.Finish();
}

}  // namespace

Geometry ReadGeometryJson(const std::string& path) { return ParseGeometryText(ReadWholeFile(path), path); }

Geometry ReadGeometryJson(std::istream& in, const std::string& nameForMessages) {
  return ParseGeometryText(ReadWholeStream(in, nameForMessages), nameForMessages);
}

}  // namespace invmap::io
