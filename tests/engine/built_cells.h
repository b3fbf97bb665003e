// The cells of a test geometry, built as Manifold::Build builds them.
#pragma once

#include <stdexcept>

#include "engine/cell_store.h"
#include "engine/geometry_validation.h"
#include "invmap/invmap.h"

namespace invmap::testing {

/// CellStore::Build of `geometry`, after the validation it presumes; an
/// invalid geometry (a mistake of the test) throws, which fails the test.
inline engine::CellStore BuildCells(const Geometry& geometry) {
  if (const GeometryError problem = engine::ValidateGeometry(geometry)) {
    throw std::invalid_argument("invalid test geometry: " + Describe(problem));
  }
  return engine::CellStore::Build(geometry, 1);
}

}  // namespace invmap::testing
