#include "io/geometry_source.h"

#include <algorithm>
#include <utility>

namespace invmap::io {

void LineRuns::Add(std::int64_t element, std::int64_t line) {
  if (!runs_.empty()) {
    Run& run = runs_.back();
    if (element == run.first + run.count) {
      if (run.step < 0 && (line == run.firstLine || line == run.firstLine + 1)) {
        run.step = static_cast<int>(line - run.firstLine);
        ++run.count;
        return;
      }
      if (run.step >= 0 && line == run.firstLine + run.step * run.count) {
        ++run.count;
        return;
      }
    }
  }
  runs_.push_back({element, 1, line, -1});
}

std::int64_t LineRuns::LineOf(std::int64_t element) const {
  // The last run that starts at or before the element.
  const auto after = std::upper_bound(runs_.begin(), runs_.end(), element,
                                      [](std::int64_t e, const Run& run) { return e < run.first; });
  if (after == runs_.begin()) return 0;
  const Run& run = *(after - 1);
  if (element >= run.first + run.count) return 0;
  return run.firstLine + std::max(run.step, 0) * (element - run.first);
}

void GeometrySource::BeginPatch(std::int64_t line) {
  patches_.emplace_back();
  patches_.back().line = line;
}

void GeometrySource::Field(GeometryField field, std::int64_t line) {
  patches_.back().fieldLine[static_cast<int>(field)] = line;
}

void GeometrySource::Element(GeometryField field, std::int64_t element, std::int64_t line) {
  patches_.back().elements[static_cast<int>(field)].Add(element, line);
}

void GeometrySource::Elements(GeometryField field, LineRuns lines) {
  patches_.back().elements[static_cast<int>(field)] = std::move(lines);
}

void GeometrySource::Item(GeometryField field, std::int64_t element, std::int64_t item, std::int64_t line) {
  patches_.back().items.push_back({field, element, item, line});
}

std::int64_t GeometrySource::LineOf(const GeometryError& error) const {
  if (error.patch < 0 || error.patch >= static_cast<std::int64_t>(patches_.size())) return 0;
  const PatchLines& patch = patches_[error.patch];
  const int field = static_cast<int>(error.field);
  if (error.element >= 0) {
    if (error.item >= 0) {
      for (const ItemLine& item : patch.items) {
        if (item.field == error.field && item.element == error.element && item.item == error.item) return item.line;
      }
    }
    if (const std::int64_t line = patch.elements[field].LineOf(error.element)) return line;
  }
  if (error.field != GeometryField::None && patch.fieldLine[field] > 0) return patch.fieldLine[field];
  return patch.line;
}

InputError GeometrySource::ToInputError(const GeometryError& error) const {
  const std::string path = GeometryPath(error);
  return InputError(file_, LineOf(error), path.empty() ? error.message : path + ": " + error.message);
}

std::string GeometryPath(const GeometryError& error) {
  std::string path;
  if (error.patch >= 0) path = "patches[" + std::to_string(error.patch) + "]";
  if (error.field != GeometryField::None) {
    if (!path.empty()) path += '.';
    path += GeometryFieldName(error.field);
    if (error.element >= 0) path += "[" + std::to_string(error.element) + "]";
  }
  return path;
}

}  // namespace invmap::io
