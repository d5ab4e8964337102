#include "support/run_command.hpp"

#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

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

/// `command` run by sh in `working_dir` with a clean environment. The shells exec their
/// successor, so a single command (not a list) keeps the process id the caller started.
std::string clean_shell_line(const std::string& command, const std::filesystem::path& working_dir) {
  return "cd " + shell_quoted(working_dir.string()) +
         " && exec env -i PATH=" + shell_quoted(environment_value("PATH", "/usr/bin:/bin")) +
         " HOME=" + shell_quoted(environment_value("HOME", "/tmp")) + " OMP_NUM_THREADS=1 sh -c " +
         shell_quoted(command) + " 2>&1";
}

int exit_code_of(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

} // namespace

CommandOutcome run_command(const std::string& command, const std::filesystem::path& working_dir) {
  const std::string full = clean_shell_line(command, working_dir);
  CommandOutcome outcome;
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe)
    return outcome;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), int(buffer.size()), pipe))
    outcome.output += buffer.data();
  outcome.exit_code = exit_code_of(pclose(pipe));
  return outcome;
}

std::string texsim_under_mpirun(int ranks, const std::string& mpirun_options) {
  return std::string(TEXSIM_MPIEXEC) + " --allow-run-as-root --oversubscribe " + mpirun_options +
         " -n " + std::to_string(ranks) + " " + texsim_command();
}

BackgroundCommand::BackgroundCommand(const std::string& command,
                                     const std::filesystem::path& working_dir) {
  int fds[2];
  if (pipe(fds) != 0)
    return;
  const std::string line = clean_shell_line("exec " + command, working_dir);
  pid_ = fork();
  if (pid_ == 0) {
    setpgid(0, 0);
    dup2(fds[1], STDOUT_FILENO);
    close(fds[0]);
    close(fds[1]);
    execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid_, pid_); // as the child does: whichever runs first, the group exists before a signal
  close(fds[1]);
  output_fd_ = fds[0];
}

BackgroundCommand::~BackgroundCommand() {
  if (pid_ > 0 && outcome_.exit_code == -1 && waitpid(pid_, nullptr, WNOHANG) == 0) {
    kill(-pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  if (output_fd_ >= 0)
    close(output_fd_);
}

bool BackgroundCommand::wait_for_output(const std::string& text) {
  std::array<char, 4096> buffer{};
  for (;;) {
    const auto found = outcome_.output.find(text, scanned_);
    if (found != std::string::npos) {
      scanned_ = found + text.size();
      return true;
    }
    const ssize_t n = read(output_fd_, buffer.data(), buffer.size());
    if (n <= 0)
      return false;
    outcome_.output.append(buffer.data(), std::size_t(n));
  }
}

void BackgroundCommand::signal_command(int signal_number) {
  kill(pid_, signal_number);
}

void BackgroundCommand::signal_children(int signal_number) {
  // /proc/<pid>/stat: "pid (name) state ppid ..."; the name may hold spaces, so parse after ')'.
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    if (!std::getline(stat, line) || line.rfind(')') == std::string::npos)
      continue;
    std::istringstream rest(line.substr(line.rfind(')') + 1));
    char state = 0;
    int parent = 0;
    if (rest >> state >> parent && parent == pid_)
      kill(std::stoi(entry.path().filename().string()), signal_number);
  }
}

void BackgroundCommand::signal_group(int signal_number) {
  // Open MPI puts each rank in a process group of its own: signal the ranks by parentage first.
  signal_children(signal_number);
  kill(-pid_, signal_number);
}

CommandOutcome BackgroundCommand::finish() {
  std::array<char, 4096> buffer{};
  ssize_t n = 0;
  while ((n = read(output_fd_, buffer.data(), buffer.size())) > 0)
    outcome_.output.append(buffer.data(), std::size_t(n));
  int status = 0;
  waitpid(pid_, &status, 0);
  outcome_.exit_code = exit_code_of(status);
  return outcome_;
}

std::string texsim_command() {
  return TEXSIM_BINARY_PATH;
}

} // namespace texsim::test
