// The pickled form of a geometry: what a Manifold sends to another process
// (a Dask worker) so that it can rebuild without the original file.
#pragma once

#include <string>

#include "invmap/invmap.h"

namespace invmap::python {

/// Encodes every field of every patch, bit for bit (doubles are copied, never
/// printed), so a rebuilt manifold answers exactly as the original. Layout:
/// an 8-byte magic with the format version, a byte-order marker, the
/// dimension, then per patch its kind, cell type and each vector as a 64-bit
/// length followed by its elements in native byte order. Cost: one copy of
/// the geometry's arrays.
std::string SerializeGeometry(const Geometry& geometry);

/// Decodes SerializeGeometry's output. Throws std::invalid_argument on
/// anything else: another magic or version, another byte order, a truncated
/// or overlong buffer, or an out-of-range enum; it never reads out of bounds.
/// The result is not validated further: Manifold::Build does that.
Geometry DeserializeGeometry(const std::string& state);

}  // namespace invmap::python
