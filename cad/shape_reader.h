// Reading a CAD file into an OpenCascade shape with the default readers
// and settings (units: millimetres for STEP and IGES).
#pragma once

#include <TopoDS_Shape.hxx>

#include <string>

namespace invmap::cad {

/// A reading failure: why, and whether the file itself could not be opened.
struct ReadError {
  std::string reason;
  bool fileError = false;
};

/// Reads `path` by its extension: STEPControl_Reader (.step, .stp) or
/// IGESControl_Reader (.iges, .igs) with TransferRoots() and OneShape(), or
/// BRepTools::Read (.brep). Throws ReadError when the file cannot be
/// opened, is not of its format, or holds no face. `format` receives
/// "STEP", "IGES" or "BREP". OpenCascade's own messages are silenced.
TopoDS_Shape ReadCadShape(const std::string& path, std::string* format);

/// OpenCascade prints its readers' and writers' reports to stdout, which
/// belongs to the command's own output: its printers are removed (once per
/// process).
void SilenceOpenCascade();

/// True for the extensions ReadCadShape reads (case insensitive).
bool HasCadExtension(const std::string& path);

}  // namespace invmap::cad
