#include "img/vtk_error_capture.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkObject.h>

namespace texsim::img {

VtkErrorCapture::VtkErrorCapture()
    : previous_display_(vtkObject::GetGlobalWarningDisplay()),
      callback_(vtkSmartPointer<vtkCallbackCommand>::New()) {
  vtkObject::GlobalWarningDisplayOff();
  callback_->SetCallback(&VtkErrorCapture::on_event);
  callback_->SetClientData(this);
}

VtkErrorCapture::~VtkErrorCapture() {
  for (auto& [object, tag] : observed_) {
    object->RemoveObserver(tag);
  }
  vtkObject::SetGlobalWarningDisplay(previous_display_);
}

void VtkErrorCapture::watch(vtkObject* object) {
  observed_.emplace_back(object, object->AddObserver(vtkCommand::ErrorEvent, callback_));
  observed_.emplace_back(object, object->AddObserver(vtkCommand::WarningEvent, callback_));
}

std::string VtkErrorCapture::errors() const {
  std::string joined;
  for (const auto& message : errors_) {
    joined += (joined.empty() ? "" : "; ") + message;
  }
  return joined;
}

void VtkErrorCapture::on_event(vtkObject*, unsigned long event, void* self, void* call_data) {
  if (event != vtkCommand::ErrorEvent || call_data == nullptr) {
    return;
  }
  // VTK formats messages as "ERROR: In <file>, line <n>\n<class> (<ptr>): <text>\n\n".
  std::string text(static_cast<const char*>(call_data));
  if (const auto colon = text.find("): "); colon != std::string::npos) {
    text = text.substr(colon + 3);
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
    text.pop_back();
  }
  static_cast<VtkErrorCapture*>(self)->errors_.push_back(text);
}

} // namespace texsim::img
