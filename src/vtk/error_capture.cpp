#include "vtk/error_capture.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkObject.h>
#include <vtkOutputWindow.h>

#include <algorithm>
#include <cctype>

namespace texsim::vtk {

// texsim adds no vtkLogger files or callbacks, so the current verbosity cutoff is the stderr one.
ErrorCapture::ErrorCapture()
    : previous_display_mode_(vtkOutputWindow::GetInstance()->GetDisplayMode()),
      previous_stderr_verbosity_(vtkLogger::GetCurrentVerbosityCutoff()),
      callback_(vtkSmartPointer<vtkCallbackCommand>::New()) {
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  callback_->SetCallback(&ErrorCapture::on_event);
  callback_->SetClientData(this);
}

ErrorCapture::~ErrorCapture() {
  for (auto& [object, tag] : observed_) {
    object->RemoveObserver(tag);
  }
  vtkLogger::SetStderrVerbosity(previous_stderr_verbosity_);
  vtkOutputWindow::GetInstance()->SetDisplayMode(previous_display_mode_);
}

void ErrorCapture::watch(vtkObject* object) {
  observed_.emplace_back(object, object->AddObserver(vtkCommand::ErrorEvent, callback_));
  observed_.emplace_back(object, object->AddObserver(vtkCommand::WarningEvent, callback_));
}

std::string ErrorCapture::errors() const {
  std::string joined;
  for (const auto& message : errors_) {
    joined += (joined.empty() ? "" : "; ") + message;
  }
  return joined;
}

void ErrorCapture::on_event(vtkObject*, unsigned long event, void* self, void* call_data) {
  if (event != vtkCommand::ErrorEvent || call_data == nullptr) {
    return;
  }
  // VTK formats messages as "ERROR: In <file>, line <n>\n<class> (<address>): <text>\n\n".
  std::string message(static_cast<const char*>(call_data));
  if (const auto colon = message.find("): "); colon != std::string::npos) {
    message.erase(0, colon + 3);
  }
  std::replace(message.begin(), message.end(), '\n', ' ');
  while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) {
    message.pop_back();
  }
  static_cast<ErrorCapture*>(self)->errors_.push_back(message);
}

} // namespace texsim::vtk
