// Helpers of the finite-element reader tests: evaluating a read cell and
// its fields at given parameters, and points of reference cells.
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <initializer_list>

#include "invmap/fields.h"
#include "invmap/invmap.h"
#include "io/input_error.h"

namespace invmap::testing {

/// Results that put one point in patch `patch`, cell `cell` at `params`.
inline Results OnePointAt(int patch, std::int64_t cell, const std::array<double, 3>& params) {
  Results r;
  r.status = {Status::Found};
  r.patch = {patch};
  r.cell = {cell};
  r.params = {params[0], params[1], params[2]};
  r.closest = {0, 0, 0};
  r.distance = {0};
  r.iterations = {0};
  return r;
}

/// The geometry's own points as a field: probing it evaluates the cells' map.
inline NodeField CoordinatesField(const Geometry& geometry) {
  NodeField field;
  field.name = "xyz";
  field.components = geometry.dimension;
  for (const Patch& patch : geometry.patches) field.patchValues.push_back(patch.points);
  return field;
}

/// Values of `field` (or, with null, the map) of cell `cell` of patch `patch` at `params`.
inline std::vector<double> EvaluateAt(const Geometry& geometry, const NodeField* field, int patch, std::int64_t cell,
                                      const std::array<double, 3>& params) {
  const NodeField coordinates = CoordinatesField(geometry);
  std::vector<double> values;
  std::string message;
  const Error e = ProbeFields(geometry, {field ? field : &coordinates}, OnePointAt(patch, cell, params), &values,
                              &message);
  if (e != Error::Ok) values.assign(1, std::nan(""));
  return values;
}

/// A random point of the reference domain of a cell type (docs/formats.md
/// section 1), kept `margin` inside it.
inline std::array<double, 3> RandomReferencePoint(CellType type, std::mt19937& rng, double margin = 0.0) {
  std::uniform_real_distribution<double> u(margin, 1.0 - margin);
  for (;;) {
    std::array<double, 3> x{u(rng), u(rng), u(rng)};
    switch (type) {
      case CellType::Line:
        return {x[0], 0, 0};
      case CellType::Quad:
        return {x[0], x[1], 0};
      case CellType::Hex:
        return x;
      case CellType::Tri:
        if (x[0] + x[1] <= 1.0 - margin) return {x[0], x[1], 0};
        break;
      case CellType::Tet:
        if (x[0] + x[1] + x[2] <= 1.0 - margin) return x;
        break;
      case CellType::Wedge:
        if (x[0] + x[1] <= 1.0 - margin) return x;
        break;
    }
  }
}

/// Expects `read()` to throw an io::InputError whose message contains each of `texts`.
template <typename Read>
void ExpectInputError(Read&& read, std::initializer_list<std::string> texts) {
  try {
    read();
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    for (const std::string& text : texts) EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

}  // namespace invmap::testing
