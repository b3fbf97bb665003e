// Where the parts of a geometry were read from: the line of each patch, of
// each of its fields and of their elements, so that a GeometryError of the
// engine's validation (Manifold::Build) names the file and the line of the
// value at fault, as the readers' own errors do.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "io/input_error.h"

namespace invmap::io {

/// Lines of the elements 0, 1, 2, ... of one field, stored as runs of
/// elements on one line or on consecutive lines: a file that writes a point
/// per line (or all of them on one line) costs a few runs, whatever its size.
class LineRuns {
 public:
  /// Element `element` (the next one, or later: skipped ones have no line)
  /// was read at `line` (1-based).
  void Add(std::int64_t element, std::int64_t line);
  /// The line of `element`, or 0 when it was not recorded.
  std::int64_t LineOf(std::int64_t element) const;

 private:
  struct Run {
    std::int64_t first;      ///< The run's first element.
    std::int64_t count;      ///< Elements in the run.
    std::int64_t firstLine;  ///< The first element's line.
    int step;                ///< Lines per element: 0 or 1 (-1 while the run has one element).
  };
  std::vector<Run> runs_;
};

/// The record of one file's geometry. Readers fill it as they read; the
/// lines of what they do not record fall back to the enclosing element,
/// field or patch, or to no line at all.
class GeometrySource {
 public:
  /// `file`: the name messages give (a path, or "<json>" for text).
  explicit GeometrySource(std::string file = {}) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }
  void set_file(std::string file) { file_ = std::move(file); }

  /// A new patch (the next index) starts at `line`.
  void BeginPatch(std::int64_t line);
  /// Field `field` of the last patch starts at `line`.
  void Field(GeometryField field, std::int64_t line);
  /// Element `element` of `field` of the last patch is at `line`; elements
  /// of a field come in increasing order.
  void Element(GeometryField field, std::int64_t element, std::int64_t line);
  /// The lines of every element of `field` of the last patch at once.
  void Elements(GeometryField field, LineRuns lines);
  /// Item `item` of that element is at `line`, another line than the
  /// element's (a row written over several lines).
  void Item(GeometryField field, std::int64_t element, std::int64_t item, std::int64_t line);

  /// The line of the place `error` names: its item's, else its element's,
  /// else its field's, else its patch's; 0 when none was recorded.
  std::int64_t LineOf(const GeometryError& error) const;

  /// `error` as the readers word their own errors: the file, the line
  /// (LineOf) and the place as a path into the geometry file,
  /// "g.json:12: patches[3].knots[1]: decreasing at index 4 (0.5 > 0.25)".
  InputError ToInputError(const GeometryError& error) const;

  /// Throws ToInputError(error) when `error` is one (the BuildResult::problem
  /// of the geometry read).
  void Check(const GeometryError& error) const {
    if (error) throw ToInputError(error);
  }

 private:
  static constexpr int kNumFields = static_cast<int>(GeometryField::ChartControlPoints) + 1;  // the last field
  struct ItemLine {
    GeometryField field;
    std::int64_t element, item, line;
  };
  struct PatchLines {
    std::int64_t line = 0;
    std::int64_t fieldLine[kNumFields] = {};
    LineRuns elements[kNumFields];
    std::vector<ItemLine> items;  ///< Only items off their element's line.
  };

  std::string file_;
  std::vector<PatchLines> patches_;
};

/// The place of `error` as a path into the geometry file: "patches[3].knots[1]",
/// "patches[0]", "dimension"; "" for the geometry as a whole.
std::string GeometryPath(const GeometryError& error);

}  // namespace invmap::io
