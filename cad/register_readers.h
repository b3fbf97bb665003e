// The CAD readers of this target, made known to io's geometry readers
// (ReadGeometryFile, ReadGeometryWithFields), so that every command reading
// a geometry (generate points, probe) reads CAD models too. invert, trim and
// info load the model itself (cad::Model), which also signs distances.
#pragma once

namespace invmap::cad {

/// Registers .step, .stp, .iges, .igs and .brep: the geometry of
/// cad::Model::Load, no fields. Idempotent and thread-safe; call once at
/// start (the command's main, the Python module's init).
void RegisterCadReaders();

}  // namespace invmap::cad
