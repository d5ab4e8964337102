#pragma once
/// Keeps VTK quiet and collects its error messages, so VTK-based readers and writers can turn them
/// into exceptions instead of text on stderr.
#include <string>
#include <utility>
#include <vector>

#include <vtkSmartPointer.h>

class vtkObject;
class vtkCallbackCommand;

namespace texsim::img {

/// While alive: VTK's global warning display is off (nothing reaches stderr or vtkOutputWindow),
/// and the error and warning events of every watched object are recorded. Restores the previous
/// global setting on destruction. Not thread-safe (VTK's flag is process-wide): use it around
/// serial reader/writer calls only.
class VtkErrorCapture {
public:
  VtkErrorCapture();
  ~VtkErrorCapture();
  VtkErrorCapture(const VtkErrorCapture&) = delete;
  VtkErrorCapture& operator=(const VtkErrorCapture&) = delete;

  /// Records error and warning events raised by `object` (a reader, writer, or its executive).
  void watch(vtkObject* object);

  /// True once a watched object has raised an error event.
  bool has_errors() const { return !errors_.empty(); }
  /// The recorded error messages joined by "; ", with VTK's file/line prefixes stripped.
  std::string errors() const;

private:
  static void on_event(vtkObject* caller, unsigned long event, void* self, void* call_data);

  int previous_display_;
  vtkSmartPointer<vtkCallbackCommand> callback_;
  std::vector<std::pair<vtkSmartPointer<vtkObject>, unsigned long>> observed_;
  std::vector<std::string> errors_;
};

} // namespace texsim::img
