// Reader of the invmap geometry file (docs/formats.md section 2).
#pragma once

#include <iosfwd>
#include <string>

#include "invmap/invmap.h"
#include "io/geometry_source.h"

namespace invmap::io {

/// Reads the JSON geometry file at `path` ("format": "invmap-geometry",
/// "version": 1) into patches of kind BSpline, Bezier and Mesh, in file order.
/// The reader checks what it needs to fill the patches: the JSON itself,
/// the type of every value, the fields each kind has, the cell type's name,
/// and rows of the right length (coordinates per point, vertex indices per
/// cell). What the values mean (knots, counts, degrees, weights, vertex
/// indices, coordinate ranges) Manifold::Build validates; `source`, when
/// not null, receives where each patch, field and element was read, so that
/// its GeometryError names the file and line (GeometrySource::ToInputError).
/// An empty "patches" list gives an empty geometry. Unknown top-level fields
/// are ignored; unknown patch fields are errors, because a misspelt optional
/// field ("weight") would otherwise change the geometry silently.
/// Throws InputError with the file, the 1-based line and the JSON path of the
/// problem, e.g. "g.json:12: patches[3].knots: expected an array of knot
/// vectors (arrays of numbers), found 5".
/// Cost: one SAX pass over the text, about 2 s per 100 MB (nlohmann's lexer
/// is most of it); memory is the patches and a block of the file, never the
/// whole text nor a DOM, so a file of any size (or an endless one) is read
/// only as far as its first error.
Geometry ReadGeometryJson(const std::string& path, GeometrySource* source = nullptr);

/// Reads a geometry file from `in` (to its end); `nameForMessages` is the
/// file name the error messages give.
Geometry ReadGeometryJson(std::istream& in, const std::string& nameForMessages, GeometrySource* source = nullptr);

}  // namespace invmap::io
