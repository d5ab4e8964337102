#pragma once
/// Turns VTK's error reporting into data: the messages of watched readers, writers and filters are
/// recorded so callers can put them into exceptions, and nothing VTK reports reaches stderr.
#include <string>
#include <utility>
#include <vector>

#include <vtkLogger.h>
#include <vtkSmartPointer.h>

class vtkObject;
class vtkCallbackCommand;

namespace texsim::vtk {

/// While alive: the error events of every watched object are recorded (warnings are dropped), and
/// whatever else VTK reports (unwatched helper objects such as XML parsers) is silenced: VTK's
/// output window displays nothing and vtkLogger writes nothing to stderr. Both settings are
/// restored and the observers removed on destruction. Watched objects must outlive the capture.
/// Not thread-safe (VTK's output settings are process-wide): use it around serial reader/writer
/// calls only.
class ErrorCapture {
public:
  ErrorCapture();
  ~ErrorCapture();
  ErrorCapture(const ErrorCapture&) = delete;
  ErrorCapture& operator=(const ErrorCapture&) = delete;

  /// Records error events raised by `object` (a reader, writer, filter, or its executive).
  void watch(vtkObject* object);

  /// True once a watched object has raised an error event.
  bool has_errors() const { return !errors_.empty(); }
  /// The recorded error messages in order, each on one line without VTK's "ERROR: In <file>,
  /// line <n>" and "<class> (<address>): " prefixes.
  const std::vector<std::string>& error_messages() const { return errors_; }
  /// The recorded error messages joined by "; " (empty if there are none).
  std::string errors() const;

private:
  static void on_event(vtkObject* caller, unsigned long event, void* self, void* call_data);

  int previous_display_mode_;
  vtkLogger::Verbosity previous_stderr_verbosity_;
  vtkSmartPointer<vtkCallbackCommand> callback_;
  std::vector<std::pair<vtkSmartPointer<vtkObject>, unsigned long>> observed_;
  std::vector<std::string> errors_;
};

} // namespace texsim::vtk
