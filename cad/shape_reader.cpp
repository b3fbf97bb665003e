#include "cad/shape_reader.h"

#include "cad/exchange_file_check.h"

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <mutex>

namespace invmap::cad {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::size_t Count(const TopoDS_Shape& shape, TopAbs_ShapeEnum type) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, type, map);
  return static_cast<std::size_t>(map.Extent());
}

void CheckFile(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw ReadError{"cannot open: no such file", true};
  if (std::filesystem::is_directory(status)) throw ReadError{"is a directory, not a file", true};
  if (!std::ifstream(path).good()) throw ReadError{"cannot open: not readable", true};
  if (std::filesystem::file_size(path, ec) == 0) throw ReadError{"empty file", false};
}

/// The reason a file gave no shape: what its text tells (not of the
/// format, truncated), else `otherwise`.
ReadError NoShape(const std::string& path, const std::string& format, const std::string& otherwise) {
  const std::string broken = format == "BREP" ? "" : DescribeBrokenExchangeFile(path, format);
  return ReadError{broken.empty() ? otherwise : broken};
}

/// STEPControl_Reader or IGESControl_Reader: every root transferred.
template <class Reader>
TopoDS_Shape ReadExchangeFile(const std::string& path, const std::string& format) {
  Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) {
    throw NoShape(path, format,
                  "not a readable " + format + " file (OpenCascade's " + format + " reader rejected it)");
  }
  if (reader.NbRootsForTransfer() == 0) throw NoShape(path, format, "the " + format + " file holds no shape");
  // A file cut short may still give the shapes before the cut: a part of
  // the model, which would answer as if it were the whole.
  if (const std::string broken = DescribeBrokenExchangeFile(path, format); broken.rfind("a truncated", 0) == 0) {
    throw ReadError{broken};
  }
  reader.TransferRoots();
  return reader.OneShape();
}

TopoDS_Shape ReadBrep(const std::string& path) {
  TopoDS_Shape shape;
  BRep_Builder builder;
  if (!BRepTools::Read(shape, path.c_str(), builder)) {
    throw ReadError{"not an OpenCascade BREP file (BRepTools::Read rejected it)"};
  }
  return shape;
}

}  // namespace

void SilenceOpenCascade() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
    messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

bool HasCadExtension(const std::string& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep";
}

TopoDS_Shape ReadCadShape(const std::string& path, std::string* format) {
  SilenceOpenCascade();
  CheckFile(path);
  const std::string ext = LowerExtension(path);
  TopoDS_Shape shape;
  try {
    if (ext == ".step" || ext == ".stp") {
      *format = "STEP";
      shape = ReadExchangeFile<STEPControl_Reader>(path, *format);
    } else if (ext == ".iges" || ext == ".igs") {
      *format = "IGES";
      shape = ReadExchangeFile<IGESControl_Reader>(path, *format);
    } else if (ext == ".brep") {
      *format = "BREP";
      shape = ReadBrep(path);
    } else {
      throw ReadError{"not a CAD file extension (.step, .stp, .iges, .igs, .brep)"};
    }
  } catch (const Standard_Failure& e) {
    throw ReadError{std::string("OpenCascade failed to read it: ") + e.GetMessageString()};
  }
  if (shape.IsNull()) throw NoShape(path, *format, "the " + *format + " file holds no shape");
  const std::size_t faces = Count(shape, TopAbs_FACE);
  if (faces == 0) {
    throw ReadError{"no faces (" + std::to_string(Count(shape, TopAbs_EDGE)) + " edges, " +
                    std::to_string(Count(shape, TopAbs_VERTEX)) +
                    " vertices): invmap answers on a model's surfaces, and this one has none"};
  }
  return shape;
}

}  // namespace invmap::cad
