#include "fem/vtk_messages.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

namespace invmap::fem {
namespace {

std::mutex& VtkReadMutex() {
  static std::mutex mutex;
  return mutex;
}

/// Keeps the first error (and warning) text instead of printing it.
class CollectingOutputWindow : public vtkOutputWindow {
 public:
  static CollectingOutputWindow* New();
  vtkTypeMacro(CollectingOutputWindow, vtkOutputWindow)

  void DisplayErrorText(const char* text) override {
    if (firstError.empty() && text != nullptr) firstError = text;
  }
  void DisplayWarningText(const char*) override {}
  void DisplayGenericWarningText(const char*) override {}
  void DisplayDebugText(const char*) override {}
  void DisplayText(const char*) override {}

  std::string firstError;
};
vtkStandardNewMacro(CollectingOutputWindow);

/// VTK's error text without its "ERROR: In file.cxx, line N\nvtkClass (0x..): "
/// prefix, on one line.
std::string Clean(std::string text) {
  const std::size_t colon = text.find("): ");
  if (text.rfind("ERROR:", 0) == 0 && colon != std::string::npos) text = text.substr(colon + 3);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  return text;
}

}  // namespace

struct ScopedVtkMessages::Impl {
  vtkSmartPointer<vtkOutputWindow> previous;
  vtkSmartPointer<CollectingOutputWindow> collector;
  vtkLogger::Verbosity previousVerbosity;
};

ScopedVtkMessages::ScopedVtkMessages() : lock_(VtkReadMutex()), impl_(std::make_unique<Impl>()) {
  impl_->previous = vtkOutputWindow::GetInstance();
  impl_->collector = vtkSmartPointer<CollectingOutputWindow>::New();
  vtkOutputWindow::SetInstance(impl_->collector);
  // VTK 9 also logs errors to stderr through its logger.
  impl_->previousVerbosity = vtkLogger::GetCurrentVerbosityCutoff();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

ScopedVtkMessages::~ScopedVtkMessages() {
  vtkLogger::SetStderrVerbosity(impl_->previousVerbosity);
  vtkOutputWindow::SetInstance(impl_->previous);
}

std::string ScopedVtkMessages::FirstError() const { return Clean(impl_->collector->firstError); }

}  // namespace invmap::fem
