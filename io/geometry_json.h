// Reader of the invmap geometry file (FORMATS.md section 2).
#pragma once

#include <iosfwd>
#include <string>

#include "invmap/invmap.h"

namespace invmap::io {

/// Reads the JSON geometry file at `path` ("format": "invmap-geometry",
/// "version": 1) into patches of kind BSpline, Bezier and Mesh, in file order.
/// The file is validated completely: the result has the right number of
/// coordinates per point, knots, control points, weights and cell indices for
/// every patch (Manifold::Build still checks what depends on the engine, such
/// as the highest supported degree). An empty "patches" list gives an empty
/// geometry. Unknown top-level fields are ignored; unknown patch fields are
/// errors, because a misspelt optional field ("weight") would otherwise change
/// the geometry silently.
/// Throws InputError with the file, the 1-based line and the JSON path of the
/// problem, e.g. "g.json:12: patches[3].knots[1]: decreasing at index 4 (0.5 > 0.25)".
/// Cost: one SAX pass over the text, about 2 s per 100 MB (nlohmann's lexer
/// is most of it); memory is the patches and a block of the file, never the
/// whole text nor a DOM, so a file of any size (or an endless one) is read
/// only as far as its first error.
Geometry ReadGeometryJson(const std::string& path);

/// Reads a geometry file from `in` (to its end); `nameForMessages` is the
/// file name the error messages give.
Geometry ReadGeometryJson(std::istream& in, const std::string& nameForMessages);

}  // namespace invmap::io
