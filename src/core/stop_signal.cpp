#include "core/stop_signal.hpp"

#include <csignal>
#include <cstring>

namespace texsim {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void record_stop_signal(int signal_number) {
  g_stop_signal = signal_number;
}

std::string signal_name(int signal_number) {
  switch (signal_number) {
  case SIGTERM:
    return "SIGTERM";
  case SIGUSR1:
    return "SIGUSR1";
  default:
    return "signal " + std::to_string(signal_number);
  }
}

} // namespace

void install_stop_signal_handlers() {
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = record_stop_signal;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: a signal arriving inside MPI or file I/O must not make that call fail with EINTR.
  action.sa_flags = SA_RESTART;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGUSR1, &action, nullptr);
}

int received_stop_signal() {
  return g_stop_signal;
}

CheckpointedStop::CheckpointedStop(int signal_number, const std::string& where)
    : std::runtime_error(signal_name(signal_number) + " received: checkpoint written " + where +
                         "; resubmit with --restart to continue") {}

} // namespace texsim
