#include "support/run_command.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>

namespace texsim::test {
namespace {

/// A single-quoted shell word holding `text`.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text)
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string environment_value(const char* name, const char* fallback) {
  const char* value = std::getenv(name);
  return value ? value : fallback;
}

} // namespace

CommandOutcome run_command(const std::string& command, const std::filesystem::path& working_dir) {
  const std::string full =
      "cd " + shell_quoted(working_dir.string()) +
      " && env -i PATH=" + shell_quoted(environment_value("PATH", "/usr/bin:/bin")) +
      " HOME=" + shell_quoted(environment_value("HOME", "/tmp")) + " OMP_NUM_THREADS=1 sh -c " +
      shell_quoted(command) + " 2>&1";
  CommandOutcome outcome;
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe)
    return outcome;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), int(buffer.size()), pipe))
    outcome.output += buffer.data();
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

std::string texsim_under_mpirun(int ranks) {
  return std::string(TEXSIM_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " +
         std::to_string(ranks) + " " + texsim_command();
}

std::string texsim_command() {
  return TEXSIM_BINARY_PATH;
}

} // namespace texsim::test
