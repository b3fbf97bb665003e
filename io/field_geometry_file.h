// Geometry input with the fields given at its nodes, for `invmap probe` and
// Manifold.probe (docs/fields.md).
#pragma once

#include <string>

#include "invmap/fields.h"
#include "io/geometry_source.h"
#include "io/reader_registry.h"

namespace invmap::io {

/// Reads any geometry file ReadGeometryFile reads, with its node fields:
/// gmsh .msh $NodeData (ReadGmshWithFields), and whatever a registered
/// reader gives (VTK .vtu point data, Exodus nodal variables at
/// options.timeStep). Other formats carry no fields. Throws InputError as
/// ReadGeometryFile does; the fields pass CheckFields. `source`, when not
/// null, receives what ReadGeometryFile records of the geometry's lines.
FieldGeometry ReadGeometryWithFields(const std::string& path, const FieldReadOptions& options = {},
                                     GeometrySource* source = nullptr);

}  // namespace invmap::io
