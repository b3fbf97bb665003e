// The finite-element and isogeometric readers of this target, made known to
// io's geometry readers (ReadGeometryFile, ReadGeometryWithFields).
#pragma once

namespace invmap::fem {

/// Registers .vtu (VTK), .exo and .e (Exodus II, Lagrange and Cubit's
/// Bezier extraction), .bext/.bxt (Cubit's LS-DYNA Bezier extraction) and
/// Cubit's Bezier extraction JSON. Idempotent and thread-safe; call once at
/// start (the command's main, the Python module's init).
void RegisterFemReaders();

}  // namespace invmap::fem
