// Geometry readers that targets above io/ add at run time: finite-element
// and isogeometric formats whose libraries (VTK, Exodus, netCDF) the core
// does not link. The command and the Python module register them at start
// (fem/register_readers.h); ReadGeometryFile and ReadGeometryWithFields
// consult the registry before their own formats.
#pragma once

#include <cstdint>
#include <string>

#include "invmap/fields.h"

namespace invmap::io {

/// What a reader of fields needs to know beyond the path.
struct FieldReadOptions {
  /// Exodus: the time step whose nodal variables are read, 1-based as in
  /// the file; 0 means the last one.
  std::int64_t timeStep = 0;
};

/// One registered format.
struct RegisteredReader {
  /// Lower-case extension with its dot (".vtu").
  std::string extension;
  /// Optional: whether the file at the path is this reader's (formats that
  /// share an extension, such as Cubit's JSON and invmap's); null accepts
  /// every file with the extension. Must not throw.
  bool (*accepts)(const std::string& path) = nullptr;
  /// Reads the file; throws InputError naming the file and the element,
  /// record or line.
  FieldGeometry (*read)(const std::string& path, const FieldReadOptions& options) = nullptr;
};

/// Adds a reader (thread-safe). A second registration of the same extension
/// and read function is ignored, so registering twice is harmless.
void RegisterGeometryReader(const RegisteredReader& reader);

/// The first registered reader whose extension matches `path`'s and which
/// accepts the file, or null.
const RegisteredReader* FindRegisteredReader(const std::string& path);

/// The registered extensions, ", "-separated in registration order (empty
/// when none), for the messages that list the supported formats.
std::string RegisteredExtensions();

}  // namespace invmap::io
