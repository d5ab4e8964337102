#pragma once
/// Running the texsim binary from a test as a user would: a shell command line, started with a
/// clean environment so that an `mpirun` inside it is a fresh job even when the test program
/// itself runs under mpirun.
#include <filesystem>
#include <string>

namespace texsim::test {

/// What a finished command left behind.
struct CommandOutcome {
  int exit_code = -1; ///< the shell's exit code; -1 if it did not exit normally
  std::string output; ///< stdout and stderr together, in order
};

/// Runs `command` with /bin/sh in `working_dir`. The environment holds only PATH, HOME and
/// OMP_NUM_THREADS=1: no OMPI_* or PMIX_* variable of an enclosing MPI job reaches the command.
/// Not collective: call it on one process (rank 0 of an MPI test).
CommandOutcome
run_command(const std::string& command,
            const std::filesystem::path& working_dir = std::filesystem::current_path());

/// "<mpiexec> --allow-run-as-root --oversubscribe [mpirun_options] -n <ranks> <texsim binary>":
/// the start of a command line running texsim on `ranks` processes.
std::string texsim_under_mpirun(int ranks, const std::string& mpirun_options = "");

/// A command started in the background (same clean environment as run_command), so a test can
/// watch its output and send it signals as a scheduler would. The shell execs the command, so
/// signals reach it (e.g. mpirun) directly; it leads a process group of its own (Open MPI's ranks
/// are not in it: each rank leads a group of its own). Not collective.
class BackgroundCommand {
public:
  explicit BackgroundCommand(const std::string& command, const std::filesystem::path& working_dir =
                                                             std::filesystem::current_path());
  ~BackgroundCommand(); ///< kills the command if it still runs
  BackgroundCommand(const BackgroundCommand&) = delete;
  BackgroundCommand& operator=(const BackgroundCommand&) = delete;

  /// Reads output until a line contains `text`; false if the command ended first.
  bool wait_for_output(const std::string& text);
  /// To the command alone (mpirun decides what its ranks get).
  void signal_command(int signal_number);
  /// To the command's child processes (mpirun's ranks, as Slurm and PBS signal a job's tasks).
  void signal_children(int signal_number);
  /// To the command's children (the ranks) and then its whole group, as a job's SIGKILL reaches
  /// every task: without the first, a killed mpirun's ranks run on until they notice it is gone.
  void signal_group(int signal_number);
  /// Reads the rest of the output and waits for the command to end.
  CommandOutcome finish();

private:
  int pid_ = -1;
  int output_fd_ = -1;
  CommandOutcome outcome_;
  std::size_t scanned_ = 0; ///< output already searched by wait_for_output
};

/// The texsim binary alone (a single process without mpirun).
std::string texsim_command();

} // namespace texsim::test
